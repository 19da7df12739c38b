"""Camera centres and ground footprints.

The ground is either a constant height or a callable ``ground(x, y) -> z`` taking 1-D arrays
of project-CRS coordinates and returning heights in the project CRS's vertical reference (NaN
where there is no data), e.g. a DSM sampler. Each footprint is the image border (densified)
cast as rays from the camera and intersected with the ground by ray marching, then refined by
bisection to ``tol`` metres.
"""
from dataclasses import dataclass
from typing import Callable, List, Optional, Sequence, Union

import numpy as np

from ..errors import EasyIDPError
from ..progress import as_progress
from .model import Reconstruction

Ground = Union[float, Callable[[np.ndarray, np.ndarray], np.ndarray]]


@dataclass
class Footprint:
    """One camera. ``centre`` (3,) and ``ring`` (k, 3) in the output CRS (ring open, image
    border order: top edge left→right, right edge, bottom, left); ``height_above_ground`` in
    metres (NaN if no ground under the camera); ``view_angle`` of the optical axis from the
    nadir, degrees; ``area`` of the ring on the local horizontal plane (m², local units for a
    local CRS); ``complete`` False when some border rays miss the ground (ring partial) or
    land where the ground has no data (there the ring continues on a plane at the ground
    height under the camera).
    """
    label: str
    photo_path: Optional[str]
    enabled: bool
    centre: np.ndarray
    ring: Optional[np.ndarray]
    height_above_ground: float
    view_angle: float
    area: float
    complete: bool


def border_pixels(width: int, height: int, per_edge: int = 16) -> np.ndarray:
    """(4·per_edge, 2) points along the frame [0, w] × [0, h], clockwise from the top-left corner."""
    s = np.linspace(0.0, 1.0, per_edge, endpoint=False)
    top = np.column_stack([s * width, np.zeros_like(s)])
    right = np.column_stack([np.full_like(s, width), s * height])
    bottom = np.column_stack([(1 - s) * width, np.full_like(s, height)])
    left = np.column_stack([np.zeros_like(s), (1 - s) * height])
    return np.vstack([top, right, bottom, left])


def _ground_fn(ground: Ground) -> Callable:
    if callable(ground):
        def fn(x, y):
            z = np.asarray(ground(x, y), dtype=np.float64)
            if z.shape != np.shape(x):
                raise EasyIDPError(f"ground(x, y) returned shape {z.shape}, expected {np.shape(x)}.")
            return z
        return fn
    h = float(ground)
    return lambda x, y: np.full(np.shape(x), h)


def _shoelace(xy: np.ndarray) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def camera_footprints(recon: Reconstruction, ground: Ground, *, crs=None,
                      cameras: Optional[Sequence] = None, per_edge: int = 16,
                      samples: int = 128, max_range: float = 20.0, tol: float = 1e-3,
                      progress=None, is_cancelled=None) -> List[Footprint]:
    """Footprints of the aligned, enabled cameras (or ``cameras``) on ``ground``.

    ``ground``: constant height or ``ground(x, y) -> z`` in the project CRS. Rays are marched
    in ``samples`` steps out to ``max_range`` × the camera's height above the ground at its
    nadir (for rays tilted by θ from the nadir: that / cos θ, capped at ``max_range``).
    Output coordinates are in ``crs`` (default: the project CRS).
    """
    prog = as_progress(progress, is_cancelled)
    cams = recon._select(cameras)
    gfn = _ground_fn(ground)
    if not cams:
        return []
    C = np.array([c.C for c in cams])
    cmap = recon.from_model(C)                                  # project CRS
    up = recon.frame.up(C)
    hag = cmap[:, 2] - gfn(cmap[:, 0], cmap[:, 1])
    ref_h = np.where(np.isfinite(hag) & (hag > 0), hag, np.nan)
    if np.all(np.isnan(ref_h)):
        raise EasyIDPError("No camera is above the given ground (or the ground has no data under "
                           "any camera): check the ground height or DSM and its vertical reference.")
    ref_h = np.where(np.isnan(ref_h), np.nanmedian(ref_h), ref_h)
    out = []
    for i, cam in enumerate(cams):
        prog.check()
        s = recon.sensors[cam.sensor_id]
        origin, d = recon.pixel_to_ray(cam, border_pixels(s.width, s.height, per_edge))
        origin = np.broadcast_to(origin, d.shape)          # one per ray (rolling shutter)
        cos_t = np.clip(-(d @ up[i]), 1e-6, None)
        tmax = np.minimum(ref_h[i] / cos_t * 1.5, max_range * ref_h[i])
        t = tmax[:, None] * np.linspace(0.0, 1.0, samples + 1)[None, 1:]      # (k, samples)

        g_fallback = cmap[i, 2] - ref_h[i]   # the ground under the camera

        def ground_at(m):
            """Ground heights at map points, the fallback plane where the ground has no data."""
            z = gfn(m[:, 0], m[:, 1])
            return np.where(np.isfinite(z), z, g_fallback), np.isfinite(z)

        def above(tt):
            p = origin[:, None, :] + tt[..., None] * d[:, None, :] if tt.ndim == 2 \
                else origin + tt[:, None] * d
            m = recon.from_model(p.reshape(-1, 3))
            return (m[:, 2] - ground_at(m)[0]).reshape(tt.shape)

        f = above(t)
        below = f <= 0
        below &= np.isfinite(f)
        hit = below.any(axis=1)
        j = np.argmax(below, axis=1)
        lo = np.where(j > 0, t[np.arange(len(t)), np.maximum(j - 1, 0)], 0.0)
        hi = t[np.arange(len(t)), j]
        for _ in range(60):
            if np.all((hi - lo)[hit] < tol):
                break
            mid = 0.5 * (lo + hi)
            fm = above(mid)
            go_hi = fm <= 0
            hi = np.where(go_hi, mid, hi)
            lo = np.where(go_hi, lo, mid)
        pts_model = origin[hit] + hi[hit, None] * d[hit]
        on_data = ground_at(recon.from_model(pts_model))[1] if hit.any() else np.array([False])
        ring = recon.from_model(pts_model, crs) if hit.sum() >= 3 else None
        area = _shoelace(pts_model @ _horizontal_basis(up[i])) if ring is not None else float("nan")
        axis = cam.R[2]                                            # optical axis in the model frame
        angle = float(np.degrees(np.arccos(np.clip(-(axis @ up[i]), -1.0, 1.0))))
        out.append(Footprint(cam.label, cam.photo_path, cam.enabled,
                             recon.from_model(C[i:i + 1], crs)[0], ring, float(hag[i]), angle,
                             area, bool(hit.all() and on_data.all())))
        prog.set(100.0 * (i + 1) / len(cams))
    return out


def _horizontal_basis(up: np.ndarray) -> np.ndarray:
    """(3, 2) orthonormal basis of the plane normal to ``up``."""
    a = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = a - (a @ up) * up
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(up, e1)])
