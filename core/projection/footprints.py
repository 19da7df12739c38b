"""Camera ground footprints.

The ground is a constant height (in the project CRS's vertical reference) or a DSM
(:class:`core.raster.DSM`). Each footprint is the image border (densified) cast as rays from
the camera: on a DSM, their exact first hits on its ray surface (:func:`core.raster.first_hits`);
on a constant height, the exact point of the ray at that height (Newton's method on the
project CRS height, to 1e-6 m).
"""
from dataclasses import dataclass
from enum import Enum
from typing import List, Optional, Sequence, Union

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError
from ..geometry import ring_area
from ..progress import as_progress
from ..raster import DSM, first_hits
from ..reconstruction import Reconstruction, border_pixels

Ground = Union[float, DSM]   # a height, or a DSM


class FootprintStatus(Enum):
    """What is unusual about a camera's footprint; ``message`` says it in words."""
    OK = ""
    BELOW_GROUND = "the camera is at or below the ground: no footprint"
    GROUND_FROM_FOOTPRINT = ("no DSM under the camera: height above the DSM where its photo "
                             "sees the ground")
    GROUND_FROM_OTHERS = ("no DSM under the camera nor in its view: height above the median "
                          "ground under the other cameras")

    @property
    def message(self) -> str:
        return self.value


@dataclass
class Footprint:
    """One camera. ``centre`` (3,) and ``ring`` (k, 3) in the output CRS (ring open, image
    border order: top edge left→right, right edge, bottom, left); ``height_above_ground`` in
    metres (NaN if no ground under the camera); ``view_angle`` of the optical axis from the
    nadir, degrees; ``area`` of the ring on the local horizontal plane (m², local units for a
    local CRS); ``complete`` False when some border rays miss the ground (ring partial) or
    land where the ground has no data (there the ring continues on a plane at the ground
    height under the camera). ``status``: what is unusual about this camera
    (:class:`FootprintStatus`: below the ground, so no footprint, or the ground height taken
    elsewhere than under it); ``message`` says it in words (empty when nothing is).
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
    status: FootprintStatus = FootprintStatus.OK

    @property
    def message(self) -> str:
        return self.status.message

    @property
    def below_ground(self) -> bool:
        return bool(self.height_above_ground <= 0)


@renamed_parameters(crs="output_crs")
def camera_footprints(recon: Reconstruction, ground: Ground, *, output_crs=None,
                      cameras: Optional[Sequence] = None, per_edge: int = 16,
                      progress=None, is_cancelled=None) -> List[Footprint]:
    """Footprints of the aligned, enabled cameras (or ``cameras``) on ``ground``.

    On a DSM, border rays that leave it, miss it or enter nodata continue on the plane at the
    DSM height under the camera (``complete`` is then False).

    Parameters
    ----------
    recon : Reconstruction
        The opened project.
    ground : float or DSM
        A constant height in the project CRS, or a :class:`~core.raster.DSM` (any CRS the
        project can convert to).
    output_crs : CRS, optional
        The CRS of the output coordinates (default: the project CRS).
    cameras : sequence of str, optional
        The labels of the cameras to take (default: every aligned, enabled camera).
    per_edge : int
        Rays cast along each edge of the photo frame.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    list of Footprint
        One per camera, each with its :class:`FootprintStatus`.
    """
    prog = as_progress(progress, is_cancelled)
    cams = recon.select_cameras(cameras)
    if not cams:
        return []
    C = np.array([c.C for c in cams])
    up = recon.frame.up(C)
    on_dsm = isinstance(ground, DSM)
    if on_dsm:       # height above ground: the camera's vertical ray on the DSM
        surface = ground.ray_surface()
        below = first_hits(surface, recon.frame, C, -up)
        hag = np.where(below.hit, below.distance, np.nan)
    else:
        h0 = float(ground)
        hag = recon.from_model(C)[:, 2] - h0
    ref_h = np.where(np.isfinite(hag) & (hag > 0), hag, np.nan)
    if np.all(np.isnan(ref_h)):
        raise EasyIDPError("No camera is above the given ground (or the ground has no data under "
                           "any camera): check the ground height or DSM and its vertical reference.")
    ground_z = recon.from_model(C)[:, 2] - ref_h             # ground under each camera, map CRS
    ref_h = np.where(np.isnan(ref_h), np.nanmedian(ref_h), ref_h)
    out = []
    for i, cam in enumerate(cams):
        prog.check()
        centre = recon.from_model(C[i:i + 1], output_crs)[0]
        axis = cam.R[2]                                            # optical axis in the model frame
        angle = float(np.degrees(np.arccos(np.clip(-(axis @ up[i]), -1.0, 1.0))))
        if np.isfinite(hag[i]) and hag[i] <= 0:
            out.append(Footprint(cam.label, cam.photo_path, cam.enabled, centre, None,
                                 float(hag[i]), angle, float("nan"), False,
                                 FootprintStatus.BELOW_GROUND))
            continue
        s = recon.sensors[cam.sensor_id]
        origin, d = recon.pixel_to_ray(cam, border_pixels(s.width, s.height, per_edge))
        origin = np.broadcast_to(origin, d.shape)          # one per ray (rolling shutter)
        cos_t = -(d @ up[i])
        t = np.full(len(d), np.nan)
        complete = True
        h_i, status = float(hag[i]), FootprintStatus.OK
        if on_dsm:
            hits = first_hits(surface, recon.frame, origin, d)
            t = np.where(hits.hit, hits.distance, np.nan)
            complete = bool(hits.hit.all())
            rest = ~hits.hit & (cos_t > 1e-6)            # on the plane under the camera
            t[rest] = ref_h[i] / cos_t[rest]
            if not np.isfinite(h_i):                     # no DSM right under the camera
                cz = recon.from_model(C[i:i + 1])[0, 2]
                if hits.hit.any():
                    h_i = float(cz - np.median(recon.from_model(
                        origin[hits.hit] + hits.distance[hits.hit, None] * d[hits.hit])[:, 2]))
                    status = FootprintStatus.GROUND_FROM_FOOTPRINT
                else:
                    h_i = float(cz - np.nanmedian(ground_z))
                    status = FootprintStatus.GROUND_FROM_OTHERS
        else:
            down = cos_t > 1e-6
            t[down] = _at_height(recon, origin[down], d[down], h0, ref_h[i] / cos_t[down])
            complete = bool(down.all())
        hit = np.isfinite(t)
        pts_model = origin[hit] + t[hit, None] * d[hit]
        ring = recon.from_model(pts_model, output_crs) if hit.sum() >= 3 else None
        area = abs(ring_area(pts_model @ _horizontal_basis(up[i]))) if ring is not None \
            else float("nan")
        out.append(Footprint(cam.label, cam.photo_path, cam.enabled, centre, ring, h_i, angle,
                             area, complete and bool(hit.all()), status))
        prog.set(100.0 * (i + 1) / len(cams))
    return out


def _at_height(recon: Reconstruction, origin, d, h0: float, t) -> np.ndarray:
    """Ray parameters where rays ``origin + t·d`` reach the project-CRS height ``h0``
    (Newton's method from ``t``; the height is nearly linear along a ray)."""
    t = np.array(t, np.float64)
    for _ in range(20):
        p = origin + t[:, None] * d
        h = recon.from_model(p)[:, 2]
        dh = recon.from_model(p + d)[:, 2] - h              # height change per unit of t
        step = (h - h0) / dh
        t -= step
        if np.all(np.abs(step) < 1e-7):
            break
    return t


def _horizontal_basis(up: np.ndarray) -> np.ndarray:
    """(3, 2) orthonormal basis of the plane normal to ``up``."""
    a = np.array([1.0, 0.0, 0.0]) if abs(up[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = a - (a @ up) * up
    e1 /= np.linalg.norm(e1)
    return np.column_stack([e1, np.cross(up, e1)])
