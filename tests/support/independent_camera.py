"""An independent projection truth for the demo survey: map point → photo pixel, written without
``easyidp_toolbox.core``.

The demo generator renders its photos and computes its truth pixels with the production camera
model (``core.reconstruction``), so a check against *those* pixels proves consistency only. The
pixels here are computed again from the camera as ``truth.json`` states it (its ``camera``
member, each photo's ``rotation``, ``centre`` and, for a rolling-shutter survey, its
``rolling_shutter`` motion), by other code:

* the Brown lens distortion (k1, k2, k3, p1, p2) by OpenCV's ``cv2.projectPoints``; Metashape's
  tangential terms are OpenCV's swapped (Metashape p1 multiplies r² + 2x², OpenCV's p2 does);
* Metashape's affinity and skew (b1, b2) and the pixel offset, written out here from the
  Metashape manual (appendix C, frame cameras): u = w/2 + cx + x'f + x'b1 + y'b2,
  v = h/2 + cy + y'f (see ``/work/shared/DESIGN.md``, "Metashape camera model");
* the rolling shutter, written out here from the truth's own definition: row v is exposed at
  τ = clamp((v − h/2)/(h/2), −1, 1) with the pose R(τ) = exp(τ[ω]×)·R, C(τ) = C + τ·shift;
  each point's τ is the fixed point of τ ↦ τ(row of its pixel at the pose of τ), found by
  iteration (the motion moves a pixel by a few rows, so it contracts by about 1 %).

Pixels: origin at the image's top-left corner, x right, y down, the centre of the top-left
pixel at (0.5, 0.5). A point is *in the frame* when it is in front of the camera (Zc > 0), its
undistorted normalised radius is within 1.5 × that of the frame's corners (a pinhole estimate;
beyond it the lens polynomial folds back) and its pixel is in [0, w] × [0, h]. Occlusion is not
modelled here: which pairs are seen stays the generator's (its own ray marching over the DSM).

This module imports numpy and OpenCV only (``tests/core/test_independent_camera.py`` fails if it
imports ``easyidp_toolbox.core``). OpenCV is a test requirement, never a plugin dependency.
"""
import json

import cv2
import numpy as np

MAX_ITER = 50          # rolling-shutter fixed-point iterations (about five are needed)
TOL_TAU = 1e-13        # their convergence, in half-readouts (1e-10 px on a 600-row photo)
RADIUS_MARGIN = 1.5    # × the corners' pinhole radius: beyond it a point is not in the frame


def load(truth) -> dict:
    """The truth document from a path or a dict (unchanged)."""
    if isinstance(truth, dict):
        return truth
    with open(truth) as fh:
        return json.load(fh)


def _rodrigues(v: np.ndarray) -> np.ndarray:
    """Rotation matrices (k, 3, 3) of rotation vectors (k, 3), Rodrigues' formula written out
    (``cv2.Rodrigues`` takes one vector at a time; it checks this in the tests)."""
    a = np.linalg.norm(v, axis=1)
    k = v / np.where(a > 0, a, 1.0)[:, None]
    K = np.zeros((len(v), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -k[:, 2], k[:, 1], -k[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = k[:, 2], -k[:, 1], k[:, 0]
    s, c = np.sin(a)[:, None, None], np.cos(a)[:, None, None]
    return np.eye(3)[None] + s * K + (1.0 - c) * K @ K


class Camera:
    """The demo camera of a truth document: ``camera_pixels`` maps camera-frame points to pixels."""

    def __init__(self, cam: dict):
        if any(cam.get(k, 0.0) for k in ("k4", "p3", "p4")):
            raise ValueError("the independent truth has no k4/p3/p4 (OpenCV's Brown model has "
                             "no r^8 term); the demo camera uses none")
        self.w, self.h = int(cam["width"]), int(cam["height"])
        self.f, self.cx, self.cy = float(cam["f"]), float(cam["cx"]), float(cam["cy"])
        self.b1, self.b2 = float(cam["b1"]), float(cam["b2"])
        # OpenCV's order (k1, k2, p1, p2, k3) with Metashape's p1/p2 swapped (see the docstring)
        self.dist = np.array([cam["k1"], cam["k2"], cam["p2"], cam["p1"], cam["k3"]], np.float64)
        corners = np.array([[0, 0], [self.w, 0], [0, self.h], [self.w, self.h]], float)
        centre = np.array([self.w / 2 + self.cx, self.h / 2 + self.cy])
        self.r2_max = (RADIUS_MARGIN * np.max(np.hypot(*(corners - centre).T)) / self.f) ** 2

    def camera_pixels(self, xc: np.ndarray):
        """(pixels (k, 2), in the frame (k,)) of camera-frame points (k, 3)."""
        xc = np.asarray(xc, np.float64)
        front = xc[:, 2] > 0
        uv = np.full((len(xc), 2), np.nan)
        if front.any():
            p = xc[front]
            # identity camera matrix: OpenCV returns the distorted normalised x', y'
            xd, _ = cv2.projectPoints(p.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), np.eye(3),
                                      self.dist)
            xd = xd.reshape(-1, 2)
            uv[front, 0] = self.w / 2 + self.cx + xd[:, 0] * (self.f + self.b1) + xd[:, 1] * self.b2
            uv[front, 1] = self.h / 2 + self.cy + xd[:, 1] * self.f
        with np.errstate(invalid="ignore", divide="ignore"):
            r2 = (xc[:, 0] ** 2 + xc[:, 1] ** 2) / xc[:, 2] ** 2
            inside = front & (r2 <= self.r2_max) & (uv[:, 0] >= 0) & (uv[:, 0] <= self.w) \
                & (uv[:, 1] >= 0) & (uv[:, 1] <= self.h)
        return uv, inside


def photo_pixels(truth, photo: str, xyz) -> tuple:
    """(pixels (n, 2), in the frame (n,)) of map points ``xyz`` (n, 3) (the truth's CRS) in one
    photo (its label, e.g. ``DJI_0007``)."""
    doc = load(truth)
    cam = Camera(doc["camera"])
    ph = doc["photos"][photo]
    R, C = np.asarray(ph["rotation"], float), np.asarray(ph["centre"], float)
    X = np.asarray(xyz, np.float64).reshape(-1, 3) - C     # differences: no large coordinates
    motion = ph.get("rolling_shutter")
    if motion is None:
        return cam.camera_pixels(X @ R.T)
    omega = np.asarray(motion["rotation_vector_rad"], float)
    shift = np.asarray(motion["shift_m"], float)
    half = cam.h / 2
    uv, inside = cam.camera_pixels(X @ R.T)                 # the centre row's pose first
    tau = np.zeros(len(X))
    for _ in range(MAX_ITER):
        new = np.clip((np.nan_to_num(uv[:, 1], nan=half) - half) / half, -1.0, 1.0)
        done = np.max(np.abs(new - tau)) < TOL_TAU
        tau = new
        Rt = _rodrigues(tau[:, None] * omega) @ R
        uv, inside = cam.camera_pixels(np.einsum("kij,kj->ki", Rt, X - tau[:, None] * shift))
        if done:
            break
    return uv, inside


def observation_pixels(truth) -> np.ndarray:
    """Independent pixels (k, 2) of the truth's observations (``observations``: the pairs the
    generator says are seen), in their order."""
    doc = load(truth)
    xyz = np.asarray(doc["points"]["xyz"], float)
    obs = doc["observations"]
    point, photo = np.asarray(obs["point"]), np.asarray(obs["photo"])
    out = np.full((len(point), 2), np.nan)
    for name in sorted(set(obs["photo"])):
        sel = photo == name
        out[sel] = photo_pixels(doc, name, xyz[point[sel]])[0]
    return out


def observation_lookup(truth) -> dict:
    """{(point id, photo label): independent pixel (2,)} of the truth's observations."""
    doc = load(truth)
    ids, obs = doc["points"]["id"], doc["observations"]
    return {(ids[p], ph): uv for p, ph, uv in zip(obs["point"], obs["photo"],
                                                   observation_pixels(doc))}


__all__ = ["Camera", "load", "photo_pixels", "observation_pixels", "observation_lookup"]
