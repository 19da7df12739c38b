"""Rolling-shutter photos for the demo survey: the drone moves while the sensor is read out.

Opt-in (``make_demo_survey(..., rolling_shutter=True)``). Each shot gets a :class:`Motion`:
the drone flies at ``SPEED`` along its flight line and the camera turns at a random rate
(gimbal jitter, sd ``TURN_SD`` per axis). The sensor reads its rows from top to bottom in
``READOUT`` seconds, the centre row at the shot's pose; pixel row ``v`` (sensor rows, the
centre of row r at r + 0.5) is exposed at τ = (v − h/2)/(h/2) ∈ [−1, 1] half-readouts from it,
with the pose (local frame, as :mod:`.flight`)

    R(τ) = exp(τ[ω]×)·R,   C(τ) = C + τ·Δ,

ω = angular velocity × READOUT/2 (camera frame), Δ = velocity × READOUT/2 (local frame).

Everything true is computed from that definition here, independently of the core's projection
solver: photos are ray cast row by row with each row's pose, truth pixels are found by a
bracketed root search on the row, LabelMe vertices are cast from their own row's pose. The
Metashape project stores the motion as Metashape does (per-camera ``<rolling_shutter>``
blocks: camera-frame rotation and translation from the centre row to the last, chunk units;
see ``core/reconstruction/rolling_shutter.py``). Pix4D projects are not written for such surveys: our Pix4D reader has no
rolling-shutter model, so its pixels would be off by the motion.
"""
from dataclasses import dataclass, replace
from typing import List

import numpy as np

from ..reconstruction import BEHIND, INSIDE, OUTSIDE
from ..rotations import rotation_matrix
from .flight import CameraModel, Shot, project_still
from .render import intersect, render_rays

READOUT = 0.03        # s, top row to bottom row (DJI-class sensors: 20–40 ms)
SPEED = 8.0           # m/s along the flight line
TURN_SD = 0.4         # rad/s per axis, camera-frame angular velocity
BISECTIONS = 60       # at most, regula falsi steps (about ten are needed)
MARGIN = 200.0        # px: farther outside the frame (centre row's pose) is not solved


@dataclass(frozen=True)
class Motion:
    """One shot's motion across the readout, from the centre row to the last row: ``omega``
    (3,) rotation vector in the camera frame (rad), ``shift`` (3,) centre displacement in the
    local frame (m)."""
    omega: np.ndarray
    shift: np.ndarray


def add_motion(shots: List[Shot], rng) -> List[Shot]:
    """The shots with a :class:`Motion` each: velocity along the flight line (the direction
    from the shot to the next one on its line), random turn rates."""
    half = 0.5 * READOUT
    out = []
    for i, s in enumerate(shots):
        same = [o for o in shots if o.line == s.line]
        j = same.index(s)
        nxt, prv = same[min(j + 1, len(same) - 1)], same[max(j - 1, 0)]
        heading = nxt.C - prv.C
        heading[2] = 0.0
        v = SPEED * heading / np.linalg.norm(heading)
        w = rng.normal(0.0, TURN_SD, 3)
        out.append(replace(s, motion=Motion(omega=w * half, shift=v * half)))
    return out


def poses(shot: Shot, tau: np.ndarray):
    """(R (k, 3, 3), C (k, 3)) of ``shot`` at exposure times ``tau`` (k,)."""
    tau = np.asarray(tau, dtype=np.float64)
    return (rotation_matrix(tau[:, None] * shot.motion.omega) @ shot.R,
            shot.C + tau[:, None] * shot.motion.shift)


def at(shot: Shot, tau: float) -> Shot:
    """The shot as a global-shutter shot with its pose at ``tau``."""
    R, C = poses(shot, np.array([tau]))
    return replace(shot, R=R[0], C=C[0], motion=None)


def row_tau(v, height: int) -> np.ndarray:
    return np.clip((np.asarray(v, dtype=np.float64) - 0.5 * height) / (0.5 * height), -1.0, 1.0)


def _project_at(camera: CameraModel, R, C, xyz: np.ndarray, tau: np.ndarray, omega, r2: float):
    """Pixels (k, 2), valid and in-front flags of points ``xyz`` (k, 3) seen by poses (R, C)
    (k, 3, 3), (k, 3) moved to their own τ (k,) by rotation vectors ``omega`` (k, 3)."""
    xc = np.einsum("kij,kj->ki", rotation_matrix(tau[:, None] * omega) @ R, xyz - C)
    front = xc[:, 2] > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        x, y = xc[:, 0] / xc[:, 2], xc[:, 1] / xc[:, 2]
        valid = front & (x * x + y * y <= r2)
    uv = np.full((len(xyz), 2), np.nan)
    uv[valid] = np.column_stack(camera.calibration.project_normalised(x[valid], y[valid]))
    return uv, valid, front


def project(camera: CameraModel, shots: List[Shot], xyz_local: np.ndarray):
    """Pixels (m, n, 2) and status (m, n) of local points in moving shots: each point's
    exposure time is the root of τ ↦ τ(row of its pixel at the pose of τ) − τ (decreasing), by
    bracketed regula falsi on [−1, 1], then the frame test at that pose (as
    ``flight.project_still``). Pairs more than ``MARGIN`` px outside the frame at the centre row's
    pose are only classified (OUTSIDE, or BEHIND), with NaN pixels: the motion moves a ground
    point by a few pixels."""
    cal = camera.calibration
    r2 = cal.valid_radius2(camera.width, camera.height)
    xyz = np.asarray(xyz_local, np.float64)
    h, w = camera.height, camera.width
    pixels, status = project_still(camera, shots, xyz)
    u0, v0 = pixels[..., 0], pixels[..., 1]
    with np.errstate(invalid="ignore"):
        near = (u0 > -MARGIN) & (u0 < w + MARGIN) & (v0 > -MARGIN) & (v0 < h + MARGIN)
    pixels[~near] = np.nan
    status[~near & (status == INSIDE)] = OUTSIDE
    si, pi = np.nonzero(near)
    R = np.array([s.R for s in shots])[si]
    C = np.array([s.C for s in shots])[si]
    moves = np.array([s.motion for s in shots], dtype=object)[si]
    omega = np.array([m.omega for m in moves]).reshape(-1, 3)
    shift = np.array([m.shift for m in moves]).reshape(-1, 3)
    X = xyz[pi]

    def F(t, k):                                         # pairs k at t; decreasing in t
        uv, _, _ = _project_at(camera, R[k], C[k] + t[:, None] * shift[k], X[k], t, omega[k], r2)
        return row_tau(uv[:, 1], h) - t

    tau = _illinois(F, len(si), 1e-9 / (0.5 * h))
    uv, valid, front = _project_at(camera, R, C + tau[:, None] * shift, X, tau, omega, r2)
    inside = valid & (uv[:, 0] >= 0) & (uv[:, 0] <= w) & (uv[:, 1] >= 0) & (uv[:, 1] <= h)
    pixels[si, pi] = uv
    status[si, pi] = np.where(inside, INSIDE, np.where(front, OUTSIDE, BEHIND))
    return pixels, status


def _illinois(F, n: int, tol: float) -> np.ndarray:
    """Roots in [−1, 1] of n decreasing functions (``F(t, k)``: functions k at t), by regula
    falsi with the Illinois modification on the bracket [−1, 1]; an end where F has the root's
    sign is the answer (rows beyond the frame take the first or last row's pose)."""
    lo, hi, every = np.full(n, -1.0), np.full(n, 1.0), np.arange(n)
    flo, fhi = F(lo, every), F(hi, every)
    tau = np.where(flo <= 0, -1.0, np.where(fhi >= 0, 1.0, np.nan))
    todo = np.flatnonzero(np.isnan(tau))
    lo, hi, flo, fhi = lo[todo], hi[todo], flo[todo], fhi[todo]
    side = np.zeros(len(todo), np.int8)
    for _ in range(BISECTIONS):
        if not todo.size:
            break
        t = (lo * fhi - hi * flo) / (fhi - flo)
        ft = F(t, todo)
        done = (np.abs(ft) < tol) | (hi - lo < tol) | ~np.isfinite(ft)
        tau[todo[done]] = t[done]
        right = ft > 0                                   # the root is above t
        flo = np.where(right, ft, np.where(side == -1, 0.5 * flo, flo))
        fhi = np.where(right, np.where(side == 1, 0.5 * fhi, fhi), ft)
        lo, hi = np.where(right, t, lo), np.where(right, hi, t)
        side = np.where(right, 1, -1).astype(np.int8)
        keep = ~done
        todo, lo, hi, flo, fhi, side = (a[keep] for a in (todo, lo, hi, flo, fhi, side))
    tau[todo] = 0.5 * (lo + hi)
    return np.where(np.isnan(tau), 0.0, tau)


def centres(shots: List[Shot], shot_index: np.ndarray, uv: np.ndarray, height: int) -> np.ndarray:
    """Camera centres (k, 3) at the rows of pixels ``uv`` (k, 2) of shots ``shot_index``."""
    out = np.empty((len(shot_index), 3))
    for i in np.unique(shot_index):
        sel = shot_index == i
        out[sel] = poses(shots[i], row_tau(uv[sel, 1], height))[1]
    return out


def pixel_ground(scene, camera: CameraModel, shot: Shot, uv: np.ndarray) -> np.ndarray:
    """Local points where the rays of pixels ``uv`` (k, 2), each from its row's pose, meet the
    surface."""
    x, y = camera.calibration.pixel_to_normalised(uv[:, 0], uv[:, 1])
    R, C = poses(shot, row_tau(uv[:, 1], camera.height))
    d = np.einsum("kji,kj->ki", R, np.column_stack([x, y, np.ones_like(x)]))   # Rᵀ·(x, y, 1)
    t = np.array([intersect(scene, C[k], d[k:k + 1])[0] for k in range(len(uv))])
    return C + t[:, None] * d


def render_photo(scene, camera: CameraModel, shot: Shot, rays: np.ndarray,
                 level_img: np.ndarray, level: int) -> np.ndarray:
    """The photo (h, w, 3) uint8 ray cast row by row, each row from its own pose (``rays``,
    ``level_img``, ``level`` as for ``render.render_photo``)."""
    f32 = np.float32
    h, w = camera.height, camera.width
    R, C = poses(shot, row_tau(np.arange(h) + 0.5, h))
    d = np.einsum("rwk,rkj->rwj", rays.reshape(h, w, 3), R.astype(f32)).reshape(-1, 3)
    return render_rays(scene, camera, np.repeat(C, w, axis=0), d, level_img, level)


def metashape_block(fit_pose, shot: Shot, chunk_scale: float):
    """(rotation 3×3, translation (3,)) of the shot's Metashape ``<rolling_shutter>`` block:
    the motion from the centre row to the last one, camera frame, chunk units. ``fit_pose(shot)``
    returns the shot's (R, C) in the project's metric frame (the writer's fitted ENU pose)."""
    R0, C0 = fit_pose(at(shot, 0.0))
    R1, C1 = fit_pose(at(shot, 1.0))
    return R1 @ R0.T, R0 @ (C1 - C0) / chunk_scale


def describe(shot: Shot) -> dict:
    """The motion of a shot for truth.json."""
    return {"readout_s": READOUT, "rotation_vector_rad": shot.motion.omega.tolist(),
            "shift_m": shot.motion.shift.tolist(),
            "rows": "row v (pixels) is exposed at tau = (v - h/2)/(h/2) in [-1, 1]; pose "
                    "R(tau) = exp(tau [rotation_vector]x) R, C(tau) = C + tau shift"}


__all__ = ["Motion", "add_motion", "poses", "at", "project", "centres", "pixel_ground",
           "render_photo", "metashape_block", "describe", "READOUT", "SPEED", "TURN_SD"]
