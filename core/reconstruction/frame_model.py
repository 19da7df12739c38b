"""The frame camera model (pinhole + Brown, or equidistant fisheye), vectorised with numpy.

One model serves Metashape, Pix4D and OpenSfM/ODM (Metashape manual, Appendix C, frame camera):

    x = Xc/Zc, y = Yc/Zc, r² = x² + y²
    x' = x(1 + k1r² + k2r⁴ + k3r⁶ + k4r⁸) + (p1(r² + 2x²) + 2p2xy)(1 + p3r² + p4r⁴)
    y' = y(1 + k1r² + …)                + (p2(r² + 2y²) + 2p1xy)(1 + p3r² + p4r⁴)
    u  = cx + x'(f + b1) + y'b2,   v = cy + y'f

``model="fisheye"`` puts an equidistant projection before the same polynomial (the Metashape
fisheye and OpenCV ``cv2.fisheye`` models): θ = atan(r), (x, y) ← (x, y)·θ/r, so that with
p = 0 the radius becomes θ(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸). Only rays in front of the camera
(θ < 90°) are modelled.

Pixels follow the project convention: origin at the top-left *corner* of the image, x right,
y down, so the centre of the top-left pixel is (0.5, 0.5) and the frame is [0, w] × [0, h].
Here (cx, cy) is the principal point in that convention (Metashape: w/2 + cx_xml).
Pix4D's T1/T2 and OpenSfM's p1/p2 are OpenCV-ordered: their T1/p1 = p2 here, T2/p2 = p1 here.
"""
from dataclasses import dataclass, fields
from typing import Tuple

import numpy as np

INSIDE, BEHIND, OUTSIDE = 0, 1, 2
"""Status codes of a projected point: in the frame, behind the camera (Zc <= 0), outside."""
BROWN, FISHEYE = "brown", "fisheye"
MODELS = (BROWN, FISHEYE)
"""Lens models: pinhole + Brown polynomial, and equidistant fisheye + the same polynomial."""


@dataclass(frozen=True)
class Calibration:
    """Frame-camera intrinsics. f, cx, cy, b1, b2 in pixels; k*, p* on normalised coordinates
    (on the equidistant coordinates θ·(x, y)/r for ``model="fisheye"``)."""
    f: float
    cx: float
    cy: float
    b1: float = 0.0
    b2: float = 0.0
    k1: float = 0.0
    k2: float = 0.0
    k3: float = 0.0
    k4: float = 0.0
    p1: float = 0.0
    p2: float = 0.0
    p3: float = 0.0
    p4: float = 0.0
    model: str = BROWN

    def __post_init__(self):
        if self.model not in MODELS:
            raise ValueError(f"lens model {self.model!r} is not one of {', '.join(MODELS)}")
        for fld in fields(self):
            if fld.name != "model" and not np.isfinite(getattr(self, fld.name)):
                raise ValueError(f"calibration parameter {fld.name} is not a finite number")
        if not self.f > 0:
            raise ValueError(f"focal length f={self.f} px must be positive")

    @property
    def has_distortion(self) -> bool:
        """True when pixels are not a pinhole projection (always for a fisheye)."""
        return self.model == FISHEYE or any(getattr(self, n) != 0.0 for n in
                                            ("k1", "k2", "k3", "k4", "p1", "p2"))

    # --- normalised (x, y) <-> distorted normalised (x', y') ---------------------------------
    def distort_normalised(self, x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(x, y) = (Xc/Zc, Yc/Zc) → distorted (x', y'), same shapes."""
        if self.model == FISHEYE:
            x, y = _equidistant(x, y)
        return self._polynomial(x, y)

    def _polynomial(self, x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """The radial + tangential polynomial of the module docstring."""
        r2 = x * x + y * y
        rad = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * (self.k3 + r2 * self.k4)))
        xy2 = 2.0 * x * y
        tx = self.p1 * (r2 + 2.0 * x * x) + self.p2 * xy2
        ty = self.p2 * (r2 + 2.0 * y * y) + self.p1 * xy2
        if self.p3 or self.p4:
            tf = 1.0 + r2 * (self.p3 + r2 * self.p4)
            tx, ty = tx * tf, ty * tf
        return x * rad + tx, y * rad + ty

    def _jacobian(self, x, y):
        r2 = x * x + y * y
        rad = 1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * (self.k3 + r2 * self.k4)))
        drad = self.k1 + r2 * (2 * self.k2 + r2 * (3 * self.k3 + r2 * 4 * self.k4))  # d rad / d r²
        tx = self.p1 * (r2 + 2 * x * x) + 2 * self.p2 * x * y
        ty = self.p2 * (r2 + 2 * y * y) + 2 * self.p1 * x * y
        tf = 1.0 + r2 * (self.p3 + r2 * self.p4)
        dtf = self.p3 + 2 * self.p4 * r2
        a = rad + 2 * x * x * drad + (6 * self.p1 * x + 2 * self.p2 * y) * tf + tx * dtf * 2 * x
        b = 2 * x * y * drad + (2 * self.p1 * y + 2 * self.p2 * x) * tf + tx * dtf * 2 * y
        c = 2 * x * y * drad + (2 * self.p2 * x + 2 * self.p1 * y) * tf + ty * dtf * 2 * x
        d = rad + 2 * y * y * drad + (6 * self.p2 * y + 2 * self.p1 * x) * tf + ty * dtf * 2 * y
        return a, b, c, d

    def undistort_normalised(self, xd: np.ndarray, yd: np.ndarray, tol_px: float = 1e-6,
                             max_iter: int = 30) -> Tuple[np.ndarray, np.ndarray]:
        """Invert :meth:`distort_normalised`: the polynomial by Newton iteration (to ``tol_px``
        pixels), the fisheye projection in closed form (NaN beyond 90° from the axis)."""
        xd = np.asarray(xd, dtype=np.float64)
        yd = np.asarray(yd, dtype=np.float64)
        x, y = xd.copy(), yd.copy()
        if not self.has_distortion:
            return x, y
        tol = tol_px / self.f
        for _ in range(max_iter):
            fx, fy = self._polynomial(x, y)
            ex, ey = fx - xd, fy - yd
            if np.all(np.abs(ex) < tol) and np.all(np.abs(ey) < tol):
                break
            a, b, c, d = self._jacobian(x, y)
            det = a * d - b * c
            x = x - (d * ex - b * ey) / det
            y = y - (a * ey - c * ex) / det
        if self.model == FISHEYE:
            return _inverse_equidistant(x, y)
        return x, y

    # --- normalised <-> pixels ------------------------------------------------------------------
    def to_pixels(self, xd, yd) -> Tuple[np.ndarray, np.ndarray]:
        """Distorted normalised → pixels (project convention)."""
        return self.cx + xd * (self.f + self.b1) + yd * self.b2, self.cy + yd * self.f

    def from_pixels(self, u, v) -> Tuple[np.ndarray, np.ndarray]:
        """Pixels → distorted normalised coordinates (inverse of :meth:`to_pixels`)."""
        yd = (np.asarray(v, dtype=np.float64) - self.cy) / self.f
        xd = (np.asarray(u, dtype=np.float64) - self.cx - yd * self.b2) / (self.f + self.b1)
        return xd, yd

    def project_normalised(self, x, y, distortion: bool = True):
        """Normalised camera coordinates → pixels."""
        if distortion and self.has_distortion:
            x, y = self.distort_normalised(x, y)
        return self.to_pixels(x, y)

    def pixel_to_normalised(self, u, v, distortion: bool = True):
        """Pixels → undistorted normalised coordinates (Xc/Zc, Yc/Zc)."""
        xd, yd = self.from_pixels(u, v)
        if distortion and self.has_distortion:
            return self.undistort_normalised(xd, yd)
        return xd, yd

    # --- interoperability -----------------------------------------------------------------------
    def to_opencv(self) -> Tuple[np.ndarray, np.ndarray]:
        """OpenCV camera matrix and distortion coefficients.

        Brown: distCoeffs (k1, k2, p1, p2, k3) for ``cv2.projectPoints``; k4, p3, p4 have no
        equivalent in that 5-term model and must be zero. Fisheye: D = (k1, k2, k3, k4) for
        ``cv2.fisheye.projectPoints`` (whose skew is ``alpha = K[0, 1] / K[0, 0]``); p1..p4
        must be zero. OpenCV puts pixel centres at integers: c_cv = c − 0.5. Its tangential
        order is swapped (OpenCV p1 = p2 here). fx = f + b1, skew = b2. ValueError when a
        term has no OpenCV equivalent.
        """
        K = np.array([[self.f + self.b1, self.b2, self.cx - 0.5],
                      [0.0, self.f, self.cy - 0.5],
                      [0.0, 0.0, 1.0]])
        if self.model == FISHEYE:
            if self.p1 or self.p2 or self.p3 or self.p4:
                raise ValueError("p1..p4 have no equivalent in OpenCV's fisheye model")
            return K, np.array([self.k1, self.k2, self.k3, self.k4])
        if self.k4 or self.p3 or self.p4:
            raise ValueError("k4, p3, p4 have no equivalent in OpenCV's 5-coefficient model")
        return K, np.array([self.k1, self.k2, self.p2, self.p1, self.k3])

    def valid_radius2(self, width: int, height: int, margin: float = 1.5) -> float:
        """Largest r² (normalised) where the lens model is trusted.

        ``margin`` × the radius of the image corners, shortened to where the radial mapping
        r ↦ r·(1 + k1r² + …) stops increasing (beyond it, far-away points fold back into the
        frame). Points beyond it are reported outside the frame. A fisheye is bounded in angle
        instead: ``margin`` × the corners' angle θ from the axis, at most 89.9° and where
        θ ↦ θ(1 + k1θ² + …) stops increasing; returned as tan² of that angle.
        """
        if self.model == FISHEYE:
            return self._fisheye_valid_radius2(width, height, margin)
        u = np.array([0.0, width, 0.0, width, width / 2, width / 2, 0.0, width])
        v = np.array([0.0, 0.0, height, height, 0.0, height, height / 2, height / 2])
        x, y = self.pixel_to_normalised(u, v)
        rc = float(np.sqrt(np.max(x * x + y * y)))
        rmax = margin * rc
        if self.has_distortion:
            r = np.linspace(0.0, rmax, 2001)
            r2 = r * r
            g = r * (1.0 + r2 * (self.k1 + r2 * (self.k2 + r2 * (self.k3 + r2 * self.k4))))
            bad = np.nonzero(np.diff(g) <= 0)[0]
            if bad.size:
                rmax = max(float(r[bad[0]]), rc * 1.0001)
        return rmax * rmax

    def _fisheye_valid_radius2(self, width: int, height: int, margin: float) -> float:
        u = np.array([0.0, width, 0.0, width, width / 2, width / 2, 0.0, width])
        v = np.array([0.0, 0.0, height, height, 0.0, height, height / 2, height / 2])
        x, y = self.pixel_to_normalised(u, v)
        theta_c = np.arctan(np.sqrt(x * x + y * y))
        theta_c = float(np.max(np.where(np.isfinite(theta_c), theta_c, np.pi / 2)))
        tmax = min(margin * theta_c, np.radians(89.9))
        t = np.linspace(0.0, tmax, 2001)
        t2 = t * t
        g = t * (1.0 + t2 * (self.k1 + t2 * (self.k2 + t2 * (self.k3 + t2 * self.k4))))
        bad = np.nonzero(np.diff(g) <= 0)[0]
        if bad.size:
            tmax = max(float(t[bad[0]]), min(theta_c * 1.0001, np.radians(89.9)))
        return float(np.tan(tmax) ** 2)


def _equidistant(x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(Xc/Zc, Yc/Zc) → (x, y)·θ/r with θ = atan(r): the equidistant fisheye projection."""
    r = np.sqrt(x * x + y * y)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(r > 1e-12, np.arctan(r) / r, 1.0)
    return x * s, y * s


def _inverse_equidistant(x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`_equidistant`; NaN where θ = |(x, y)| reaches 90°."""
    t = np.sqrt(x * x + y * y)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(t > 1e-12, np.tan(t) / t, 1.0)
    s = np.where(t < np.pi / 2, s, np.nan)
    return x * s, y * s


def border_pixels(width: int, height: int, per_edge: int = 16) -> np.ndarray:
    """(4·per_edge, 2) points along the frame [0, w] × [0, h], clockwise from the top-left corner."""
    s = np.linspace(0.0, 1.0, per_edge, endpoint=False)
    top = np.column_stack([s * width, np.zeros_like(s)])
    right = np.column_stack([np.full_like(s, width), s * height])
    bottom = np.column_stack([(1 - s) * width, np.full_like(s, height)])
    left = np.column_stack([np.zeros_like(s), (1 - s) * height])
    return np.vstack([top, right, bottom, left])


def project_block(xyz: np.ndarray, R: np.ndarray, C: np.ndarray, cal: Calibration,
                  width: int, height: int, r2_limit: float, distortion: bool = True
                  ) -> Tuple[np.ndarray, np.ndarray]:
    """Project points into several cameras of one sensor.

    xyz (n, 3) in the model frame; R (m, 3, 3) model → camera rotations (Xc = R(X − C));
    C (m, 3) camera centres. Returns pixels (m, n, 2) (NaN where behind the camera or beyond
    the lens model's valid radius) and status (m, n) uint8: INSIDE, BEHIND (Zc <= 0, tested
    first) or OUTSIDE (beyond the frame [0, w] × [0, h] or the valid radius).
    """
    m = len(R)
    xc = (R.reshape(3 * m, 3) @ xyz.T).reshape(m, 3, -1)   # one BLAS call for all cameras
    xc -= np.einsum("mij,mj->mi", R, C)[:, :, None]         # − R·C
    zc = xc[:, 2]
    behind = zc <= 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        iz = 1.0 / np.where(behind, np.nan, zc)
        x = xc[:, 0] * iz
        y = xc[:, 1] * iz
        near = (x * x + y * y) <= r2_limit if distortion else ~behind
    # the lens model is evaluated only where it is valid (and in front of the camera)
    u = np.full(zc.shape, np.nan)
    v = np.full(zc.shape, np.nan)
    u[near], v[near] = cal.project_normalised(x[near], y[near], distortion)
    inside = near & (u >= 0.0) & (u <= width) & (v >= 0.0) & (v <= height)
    status = np.full(zc.shape, OUTSIDE, dtype=np.uint8)
    status[inside] = INSIDE
    status[behind] = BEHIND
    return np.stack([u, v], axis=-1), status
