"""Rolling shutter: the pose of a frame camera as a function of the image row.

A rolling-shutter sensor exposes its rows one after another while the camera moves. A camera's
motion across the readout is a :class:`RollingShutter`: a rotation vector ω (radians) and a
translation t (model units), both in the camera frame (x right, y down, z forward) and both for
the motion from the centre row to the last row. Row ``v`` (pixels, top edge 0) of an image of
height ``h`` is exposed at

    τ(v) = clamp((v − h/2) / (h/2), −1, 1)

(rows beyond the frame take the pose of the first or last row), and the camera sees a model
point X there at

    Xc(τ) = exp(τ[ω]×) · (R·(X − C) − τ·t),   i.e.   R(τ) = exp(τ[ω]×)·R,   C(τ) = C + τ·Rᵀ·t,

where (R, C) is the pose the project stores (the centre row's). The rotation turns at a constant
rate (axis-angle scaled by τ), the translation is linear. This is Agisoft Metashape's convention
for its per-camera ``<rolling_shutter>`` blocks, determined from Metashape's own marker
observations (ARCHITECTURE.md, "Rolling shutter").

The row is the *sensor* row: the distorted pixel row where the point lands. Projection solves
the row and the pose together (secant iteration on τ, to 1e-7 px); a pixel gives its pose
directly. With ``distortion=False`` (pixels of the photo with its lens distortion removed) the
pose is still that of the sensor row: the lens model gives it inside its valid radius, the
undistorted row beyond it (far outside the frame).
"""
from dataclasses import dataclass
from functools import lru_cache
from typing import Tuple

import numpy as np

from .frame_model import BEHIND, INSIDE, OUTSIDE, Calibration

TOL_PX = 1e-7        # convergence of the row: |row of the pixel − row of the pose|, pixels
MAX_ITER = 12        # secant steps; two or three are needed in practice
BLOCK_ELEMENTS = 1 << 17
"""Camera × point pairs projected at once: small enough that the many temporaries of the
iteration stay in the processor's cache (1.5× faster than 2^19 on goya_test)."""


@dataclass(frozen=True)
class RollingShutter:
    """Camera motion across the readout, from the centre row to the last row (camera frame).

    ``rotation`` (3,): rotation vector ω, radians (Xc turns by exp(τ[ω]×)); ``translation``
    (3,): t, model units (the camera centre moves by τ·t, in camera axes).
    """
    rotation: np.ndarray
    translation: np.ndarray

    def __post_init__(self):
        for name in ("rotation", "translation"):
            a = np.array(getattr(self, name), dtype=np.float64).reshape(3)   # a copy
            if not np.all(np.isfinite(a)):
                raise ValueError(f"rolling-shutter {name} is not finite: {a}")
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def is_zero(self) -> bool:
        return not (np.any(self.rotation) or np.any(self.translation))


def row_tau(v, height: int) -> np.ndarray:
    """τ of sensor rows ``v`` (pixels), clamped to [−1, 1]."""
    half = 0.5 * height
    return np.clip((np.asarray(v, dtype=np.float64) - half) / half, -1.0, 1.0)


def _axes(omega: np.ndarray):
    """Unit axes (m, 3) and angles (m,) of rotation vectors; axis 0 where the angle is 0."""
    theta = np.linalg.norm(omega, axis=-1)
    k = np.divide(omega, theta[..., None], out=np.zeros_like(omega), where=theta[..., None] > 0)
    return k, theta


def _sin_versin(a):
    """sin a and 1 − cos a; Taylor series (exact in double precision) for |a| ≤ 0.1 rad,
    where numpy's sin costs a hundred multiplications."""
    if a.size and np.max(np.abs(a)) > 0.1:
        h = np.sin(0.5 * a)
        return np.sin(a), 2.0 * h * h
    a2 = a * a
    s = a * (1.0 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 + a2 * (1.0 / 362880)))))
    c1 = a2 * (0.5 + a2 * (-1.0 / 24 + a2 * (1.0 / 720 + a2 * (-1.0 / 40320
                                                              + a2 * (1.0 / 3628800)))))
    return s, c1


def _rotate(kx, ky, kz, angle, px, py, pz):
    """Rodrigues: rotate (px, py, pz) by ``angle`` about unit axes (kx, ky, kz) (broadcast)."""
    s, c1 = _sin_versin(np.asarray(angle, dtype=np.float64))
    kp = c1 * (kx * px + ky * py + kz * pz)
    q = 1.0 - c1
    return (q * px + s * (ky * pz - kz * py) + kp * kx,
            q * py + s * (kz * px - kx * pz) + kp * ky,
            q * pz + s * (kx * py - ky * px) + kp * kz)


def ray_poses(R: np.ndarray, C: np.ndarray, rs: RollingShutter, tau: np.ndarray,
              x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Rays of normalised camera coordinates (x, y) seen at rows τ: origins C(τ) (n, 3) and
    (not normalised) directions R(τ)ᵀ·(x, y, 1) (n, 3), in the model frame."""
    k, theta = _axes(rs.rotation)
    dx, dy, dz = _rotate(k[0], k[1], k[2], -tau * theta, x, y, np.ones_like(x))
    d = np.column_stack([dx, dy, dz]) @ R                    # Rᵀ·E(−τ)·(x, y, 1)
    origins = C[None, :] + tau[:, None] * (rs.translation @ R)[None, :]
    return origins, d


def sensor_rows(cal: Calibration, x, y, v, r2_limit: float, distortion: bool) -> np.ndarray:
    """Sensor rows of normalised points whose output rows are ``v``: ``v`` itself with
    distortion; without it the lens model's row inside its valid radius, ``v`` beyond."""
    if distortion:
        return v
    rows = np.array(v, dtype=np.float64, copy=True)
    ok = (x * x + y * y) <= r2_limit
    rows[ok] = cal.project_normalised(x[ok], y[ok], True)[1]
    return rows


def frame_box(cal: Calibration, width: int, height: int, distortion: bool) -> Tuple[float, ...]:
    """(xmin, xmax, ymin, ymax): normalised coordinates that hold every pixel of the frame
    (cached per calibration when it is hashable)."""
    try:
        return _frame_box_cached(cal, width, height, distortion)
    except TypeError:                                   # an unhashable calibration
        return _frame_box(cal, width, height, distortion)


def _frame_box(cal: Calibration, width: int, height: int, distortion: bool) -> Tuple[float, ...]:
    s = np.linspace(0.0, 1.0, 257)
    u = np.concatenate([s * width, np.full_like(s, width), s * width, np.zeros_like(s)])
    v = np.concatenate([np.zeros_like(s), s * height, np.full_like(s, height), s * height])
    x, y = cal.pixel_to_normalised(u, v, distortion)
    pad = 1e-3 * (1.0 + float(np.max(np.hypot(x, y))))   # between border samples
    return (float(x.min()) - pad, float(x.max()) + pad, float(y.min()) - pad, float(y.max()) + pad)


_frame_box_cached = lru_cache(maxsize=32)(_frame_box)


def project_block_rs(xyz: np.ndarray, R: np.ndarray, C: np.ndarray, omega: np.ndarray,
                     shift: np.ndarray, cal: Calibration, width: int, height: int,
                     r2_limit: float, distortion: bool = True, inside_only: bool = False
                     ) -> Tuple[np.ndarray, np.ndarray]:
    """:func:`~.frame_model.project_block` for rolling-shutter cameras of one sensor.

    ``omega``/``shift`` (m, 3): each camera's :class:`RollingShutter` rotation and translation.
    Each point's row and pose are solved together. Status is taken at the final pose: BEHIND
    (Zc ≤ 0), OUTSIDE (beyond the frame or, with distortion, the lens model's valid radius) or
    INSIDE. Pairs that no pose of the readout can bring into the lens model's valid cone (or,
    with ``inside_only``, into the frame) are settled from conservative bounds without
    iterating; with ``inside_only`` only the INSIDE pairs are exact, the others are OUTSIDE.
    """
    m, n = len(R), len(xyz)
    xc = (R.reshape(3 * m, 3) @ xyz.T).reshape(m, 3, -1)
    xc -= np.einsum("mij,mj->mi", R, C)[:, :, None]
    X, Y, Z = xc[:, 0], xc[:, 1], xc[:, 2]
    k, theta = _axes(omega)
    tnorm = np.linalg.norm(shift, axis=1)
    # ε bounds the angle between a point's direction at τ = 0 and at any τ in [−1, 1]: θ for
    # the rotation, asin(s) for the translation, s = |t|/|Xc| ≤ |t|/max(|X|, |Y|, |Zc|), with
    # asin s ≤ 1.0017·s for s ≤ 0.1 and ≤ (π/2)·s for s ≤ 1; T ≥ tan ε (tan x ≤ 1.0034·x for
    # x ≤ 0.1, ≤ tan(1)·x for x ≤ 1). No square roots or sines: each costs as much as the
    # whole projection.
    with np.errstate(divide="ignore", invalid="ignore"):
        sn = tnorm[:, None] / np.maximum(np.maximum(np.abs(X), np.abs(Y)), np.abs(Z))
        eps = theta[:, None] + np.where(sn <= 0.1, 1.0017 * sn,
                                        np.where(sn <= 1.0, 0.5 * np.pi * sn, np.inf))
        T = np.where(eps <= 0.1, 1.0034 * eps, np.where(eps <= 1.0, 1.5575 * eps, np.inf))
        rho2 = X * X + Y * Y                            # squared distance from the axis
        Z2 = Z * Z
        behind = (Z < 0) & (Z2 >= rho2 * (T * T))       # behind the camera at every pose
    settled = behind.copy()
    if inside_only:                                     # nowhere near the frame at any pose
        # a pose that brings a point into the frame sees it within ε of a direction of the
        # frame box, where the normalised radius is at most rb; along an arc of ε from there
        # the radius stays below rp and normalised coordinates move at most (1 + rp²)·ε
        x0, x1, y0, y1 = frame_box(cal, width, height, distortion)
        rb = np.sqrt(max(x0 * x0, x1 * x1) + max(y0 * y0, y1 * y1))
        with np.errstate(divide="ignore", invalid="ignore"):
            rp = (rb + T) / (1.0 - rb * T)
            delta = np.where(rb * T < 1.0, (1.0 + rp * rp) * T, np.inf)
            away = (Z > 0) & ((X < Z * (x0 - delta)) | (X > Z * (x1 + delta)) |
                              (Y < Z * (y0 - delta)) | (Y > Z * (y1 + delta)))
        settled |= away
    elif distortion:                                    # beyond the valid cone at every pose
        rl = np.sqrt(r2_limit)
        with np.errstate(invalid="ignore"):
            a = 1.0 - rl * T
            far = (Z > 0) & (a > 0) & (rho2 * (T * T) < Z2) & \
                (rho2 * (a * a) > Z2 * ((rl + T) * (rl + T)))
        settled |= far
    uv = np.full((m, n, 2), np.nan)
    status = np.full((m, n), OUTSIDE, dtype=np.uint8)
    status[behind] = BEHIND
    work = np.flatnonzero(~settled)
    if work.size:
        cam = work // n
        base = cam * (3 * n) + (work - cam * n)        # flat index of X in xc (m, 3, n)
        flat = xc.reshape(-1)
        u, v, st = _solve(
            (np.take(flat, base), np.take(flat, base + n), np.take(flat, base + 2 * n)),
            tuple(np.take(a, cam) for a in (k[:, 0], k[:, 1], k[:, 2], theta, shift[:, 0],
                                             shift[:, 1], shift[:, 2])),
            cal, width, height, r2_limit, distortion)
        uvf = uv.reshape(-1, 2)
        uvf[work, 0], uvf[work, 1] = u, v
        status.reshape(-1)[work] = st
    return uv, status


def _evaluate(a, cam, tau, cal, r2_limit, distortion):
    """Output pixels (u, v), sensor rows, valid (in front, within the lens model's radius when
    distorting) and in-front flags of camera coordinates ``a`` = (X, Y, Z) at τ (None: τ = 0),
    for cameras ``cam`` = (kx, ky, kz, θ, tx, ty, tz) (one per element)."""
    ax, ay, az = a
    kx, ky, kz, th, tx, ty, tz = cam
    if tau is None:                                     # τ = 0: the stored pose
        X, Y, Z = ax, ay, az
    else:
        X, Y, Z = _rotate(kx, ky, kz, tau * th, ax - tau * tx, ay - tau * ty, az - tau * tz)
    front = Z > 0.0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        iz = 1.0 / np.where(front, Z, np.nan)
        x, y = X * iz, Y * iz
        r2 = x * x + y * y
        if distortion:
            valid = r2 <= r2_limit
            u, v = cal.project_normalised(x, y, True)
            return u, v, v, valid, front
        u, v = cal.project_normalised(x, y, False)
        rows = np.where(r2 <= r2_limit, cal.project_normalised(x, y, True)[1], v)
    return u, v, rows, front, front


def _solve(a, cam, cal, width, height, r2_limit, distortion):
    """Row and pose of each (camera, point) pair. Returns u, v, status.

    Root of F(τ) = τ(row at the pose of τ) − τ: from τ = 0 (the stored pose) a first step on
    the pinhole rate of the row, then secant steps. Pairs leave when their row is consistent
    with their pose to ``TOL_PX`` (or when they leave the lens model's valid region: status
    taken there). Once three poses are known, the pixel at the next secant root is
    interpolated between the last two when the curvature of the pixel track bounds the
    interpolation error below TOL_PX / 4; that saves the last projection of most pairs."""
    n = len(a[0])
    half = 0.5 * height
    out_u, out_v = np.full(n, np.nan), np.full(n, np.nan)
    out_s = np.full(n, OUTSIDE, dtype=np.uint8)
    idx = np.arange(n)
    u, v, rows, valid, _ = _evaluate(a, cam, None, cal, r2_limit, distortion)
    g = (rows - half) / half
    ok0 = np.isfinite(g)                                # else: settled at τ = 0 below
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = _pinhole_row_rate(a, cam, cal.f) / half  # dτ(row)/dτ at τ = 0, about ±0.03
        rate = np.where(np.abs(rate) < 0.5, rate, 0.0)
        tau = np.where(ok0, np.clip(g / (1.0 - rate), -1.0, 1.0), 0.0)
    prev = (np.zeros(n), np.where(ok0, g, 0.0), u, v, rows, valid)   # τ, F, u, v, row, valid
    older = None
    active = np.ones(n, dtype=bool)

    def record(sel, uu, vv, ok, front):
        d = idx[sel]
        inside = ok & (uu >= 0.0) & (uu <= width) & (vv >= 0.0) & (vv <= height)
        st = np.where(inside, INSIDE, OUTSIDE).astype(np.uint8)
        st[~front] = BEHIND
        out_s[d] = st
        out_u[d], out_v[d] = np.where(ok, uu, np.nan), np.where(ok, vv, np.nan)

    for it in range(MAX_ITER + 1):
        u, v, rows, valid, front = _evaluate(a, cam, tau, cal, r2_limit, distortion)
        g = (rows - half) / half
        f = g - tau
        with np.errstate(invalid="ignore"):
            step = np.clip(g, -1.0, 1.0) - tau
            done = active & (~valid | (np.abs(step) * half < TOL_PX) | (it == MAX_ITER))
        if done.any():
            record(done, u[done], v[done], valid[done], front[done])
        tp, fp, up, vp, rp, okp = prev
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = tau - tp
            nxt = tau - f * dt / (f - fp)               # secant
            nxt = np.clip(np.where(np.isfinite(nxt), nxt, g), -1.0, 1.0)
            nxt = np.where(np.isfinite(nxt), nxt, tau)
            if older is not None:                       # interpolate when it is exact enough
                to, uo, vo, ro = older
                dto = tp - to
                span = np.abs(nxt - tp) * np.abs(nxt - tau) / np.abs(tau - to)
                curve = np.maximum.reduce([np.abs((q - qp) / dt - (qp - qo) / dto) for q, qp, qo
                                           in ((u, up, uo), (v, vp, vo), (rows, rp, ro))])
                w = (nxt - tau) / dt
                ui, vi = u + w * (u - up), v + w * (v - vp)
                take = active & ~done & valid & okp & (curve * span < 0.25 * TOL_PX) & \
                    np.isfinite(ui) & np.isfinite(vi)
                if take.any():
                    record(take, ui[take], vi[take], valid[take], front[take])
                    done |= take
        older = (tp, up, vp, rp)
        prev = (tau, f, u, v, rows, valid)
        tau = nxt
        active &= ~done
        left = int(np.count_nonzero(active))
        if left == 0:
            break
        if left < 0.8 * len(idx):                       # drop the settled pairs
            keep = np.flatnonzero(active)
            a, cam, prev, older = (tuple(x.take(keep) for x in group)
                                   for group in (a, cam, prev, older))
            idx, tau = idx.take(keep), tau.take(keep)
            active = np.ones(len(idx), dtype=bool)
    return out_u, out_v, out_s


def _pinhole_row_rate(a, cam, f: float):
    """d(row)/dτ at τ = 0 for a pinhole (distortion ignored): the first step's slope."""
    ax, ay, az = a
    kx, ky, kz, th, tx, ty, tz = cam
    dy = th * (kz * ax - kx * az) - ty                   # d(Xc)/dτ = ω × Xc − t
    dz = th * (kx * ay - ky * ax) - tz
    return f * (dy - (ay / az) * dz) / az


__all__ = ["RollingShutter", "row_tau", "ray_poses", "sensor_rows",
           "project_block_rs", "frame_box", "TOL_PX"]
