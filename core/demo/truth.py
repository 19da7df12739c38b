"""Ground truth: where known ground points are in every photo, which photos see each plot whole.

Everything is computed with the true poses in the local frame and the camera model of
``core.reconstruction.frame_model`` (pixels: origin at the top-left image corner, centre of the
top-left pixel at (0.5, 0.5)), so the pixels written here agree with the core by construction.
truth.json therefore also states the camera (``camera``, in the Metashape manual's terms) and
every photo's pose (``rotation``, ``centre``), from which ``tests/support/independent_camera.py``
recomputes the pixels with OpenCV and no ``core`` code: the checks compare with those. A point is *seen* by a photo when it is in front of the camera,
inside the frame [0, w] × [0, h] and the segment from the point to the camera centre does not
pass under the surface (the DSM, bilinear between pixel centres).
"""
import json
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

from ..files import write_bytes
from .field import plot_corners
from ..reconstruction import INSIDE
from . import readout_motion
from .flight import CameraModel, Shot, project_still
from .scene import Scene

N_RANDOM_POINTS = 1500
OCCLUSION_STEP = 0.005     # m, horizontal sampling of the point → camera segment
OCCLUSION_START = 0.015    # m from the point before the surface may hide it
PLOT_GRID = 0.1            # m, spacing of the outline samples that must be in the frame ("whole")
TRUTH_FORMAT = "easyidp-demo-survey-truth"


@dataclass
class Truth:
    """Truth in map coordinates (EPSG:32654, ellipsoidal heights) and photo pixels.

    ``points``: (n, 3); ``point_ids``/``point_kinds``; ``obs_point``/``obs_shot``/``obs_pixel``:
    every (point, photo) pair where the photo sees the point, with its exact pixel;
    ``hidden_point``/``hidden_shot``: pairs in front and inside the frame but hidden by the
    surface; ``plots``: per plot id, photos that see it whole and photos that see its 4 corners,
    its crop height and (added by the survey) its colour truth ``exg`` and ``cover``
    (:mod:`.plot_colour`).
    """
    points: np.ndarray
    point_ids: List[str]
    point_kinds: List[str]
    obs_point: np.ndarray
    obs_shot: np.ndarray
    obs_pixel: np.ndarray
    hidden_point: np.ndarray
    hidden_shot: np.ndarray
    plots: Dict[str, dict]
    labelme: Dict[str, dict] = field(default_factory=dict)


def project(camera: CameraModel, shots: List[Shot], xyz_local: np.ndarray):
    """Pixels (m, n, 2) and status (m, n) of local points in the shots (true poses)."""
    if any(s.motion is not None for s in shots):
        return readout_motion.project(camera, shots, xyz_local)
    return project_still(camera, shots, xyz_local)


def hidden(scene: Scene, C: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """True where the segment from each local point (k, 3) to its camera centre C (k, 3)
    passes under the surface (beyond the first ``OCCLUSION_START`` m)."""
    d = C - pts
    a, bx, by = scene.ground_plane
    # the segment can only meet the surface while it is below the top of the surface band
    climb = d[:, 2] - bx * d[:, 0] - by * d[:, 1]          # height gain over the ground plane
    above = pts[:, 2] - scene.ground_local(pts[:, 0], pts[:, 1])
    s_top = np.clip((scene.rel_max + 0.01 - above) / np.maximum(climb, 1e-9), 0.0, 1.0)
    length = np.linalg.norm(d, axis=1)
    horiz = np.hypot(d[:, 0], d[:, 1]) * s_top
    s0 = np.minimum(OCCLUSION_START / length, s_top)
    n = np.maximum(np.ceil(horiz / OCCLUSION_STEP).astype(int), 1) + 1
    out = np.zeros(len(pts), bool)
    for k in range(int(n.max()) + 1):
        s = s0 + (s_top - s0) * np.minimum(k / (n - 1), 1.0)
        q = pts + s[:, None] * d
        out |= scene.surface_local(q[:, 0], q[:, 1]) > q[:, 2] + 1e-4
    return out


def truth_points(scene: Scene, rng):
    """Local (n, 3) points on the surface with ids and kinds: random points where the DSM has
    data, plot corners (on the surface) and the ground control target centres."""
    lay, off = scene.layout, scene.offset
    x0, y0 = lay.origin[0] - off[0], lay.origin[1] - off[1]
    xy = np.column_stack([rng.uniform(x0, x0 + lay.size[0], 3 * N_RANDOM_POINTS),
                          rng.uniform(y0 - lay.size[1], y0, 3 * N_RANDOM_POINTS)])
    xy = xy[scene.dsm_valid(xy[:, 0], xy[:, 1], margin=0.05)][:N_RANDOM_POINTS]
    ids = [f"P{i + 1:04d}" for i in range(len(xy))]
    kinds = ["surface"] * len(xy)
    corners = []
    for p in scene.plots:
        for k, c in enumerate(plot_corners(p)):
            corners.append(c - off[:2])
            ids.append(f"{p['plot_id']}_c{k + 1}")
            kinds.append("plot_corner")
    gcp = scene.gcps[:, :2] - off[:2]
    ids += scene.gcp_labels
    kinds += ["gcp"] * len(gcp)
    xy = np.vstack([xy, np.array(corners), gcp])
    z = scene.surface_local(xy[:, 0], xy[:, 1])
    return np.column_stack([xy, z]), ids, kinds


def observations(scene: Scene, camera: CameraModel, shots: List[Shot], pts: np.ndarray):
    """(seen point, seen shot, pixel, hidden point, hidden shot) for local points."""
    uv, st = project(camera, shots, pts)
    mi, pi = np.nonzero(st == INSIDE)
    C = np.array([s.C for s in shots])[mi]
    if any(s.motion is not None for s in shots):      # the centre when the point's row was read
        C = readout_motion.centres(shots, mi, uv[mi, pi], camera.height)
    hid = hidden(scene, C, pts[pi])
    order = np.lexsort((mi[~hid], pi[~hid]))
    seen_p, seen_m = pi[~hid][order], mi[~hid][order]
    return seen_p, seen_m, uv[seen_m, seen_p], pi[hid], mi[hid]


def plot_visibility(scene: Scene, camera: CameraModel, shots: List[Shot]) -> Dict[str, dict]:
    """Per plot: photos that see it whole (every sample of its outline, every ``PLOT_GRID`` m on
    the surface, is in the frame: the outline of a ROI, as back-projection draws it; the crop
    inside, up to 0.7 m tall, may reach beyond the frame) and photos whose frame holds its four
    corners on the surface (the vertex rule of back-projection tools)."""
    out = {}
    names = [s.label for s in shots]
    for p in scene.plots:
        w, h = p["size"]
        u = np.linspace(-w / 2, w / 2, int(round(w / PLOT_GRID)) + 1)
        v = np.linspace(-h / 2, h / 2, int(round(h / PLOT_GRID)) + 1)
        uu = np.concatenate([u, u, np.full(len(v), -w / 2), np.full(len(v), w / 2)])
        vv = np.concatenate([np.full(len(u), -h / 2), np.full(len(u), h / 2), v, v])
        ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
        x = p["centre"][0] - scene.offset[0] + uu * ca - vv * sa
        y = p["centre"][1] - scene.offset[1] + uu * sa + vv * ca
        grid = np.column_stack([x, y, scene.surface_local(x, y)])
        c = plot_corners(p) - scene.offset[:2]
        corners = np.column_stack([c, scene.surface_local(c[:, 0], c[:, 1])])
        _, st = project(camera, shots, np.vstack([grid, corners]))
        inside = st == INSIDE
        whole = inside[:, :len(grid)].all(axis=1)
        four = inside[:, len(grid):].all(axis=1)
        out[p["plot_id"]] = {"photos_whole": [names[i] for i in np.flatnonzero(whole)],
                             "photos_corners": [names[i] for i in np.flatnonzero(four)],
                             "corners": (corners + scene.offset).tolist(),
                             "crop_height": p["height"]}
    return out


def camera_doc(camera: CameraModel) -> dict:
    """The camera as truth.json states it, in the Metashape manual's frame-camera terms, so that
    code other than ``core.reconstruction`` can compute the truth pixels from it."""
    c = camera.calibration
    return {
        "model": "Metashape frame camera (manual, appendix C): Xc = rotation * (X - centre) with X "
                 "and centre in map coordinates (x right, y down, z forward); x = Xc/Zc, y = Yc/Zc; "
                 "r2 = x^2 + y^2; x' = x(1 + k1 r2 + k2 r2^2 + k3 r2^3 + k4 r2^4) + p1(r2 + 2x^2) "
                 "+ 2 p2 x y; y' = y(1 + ...) + p2(r2 + 2y^2) + 2 p1 x y; u = width/2 + cx + x' f "
                 "+ x' b1 + y' b2; v = height/2 + cy + y' f (pixels as 'pixels' says)",
        "width": camera.width, "height": camera.height,
        **{k: float(getattr(c, k)) for k in ("f", "b1", "b2", "k1", "k2", "k3", "k4", "p1", "p2")},
        "cx": float(c.cx - camera.width / 2), "cy": float(c.cy - camera.height / 2)}


def write_truth(path: str, truth: Truth, scene: Scene, camera: CameraModel, shots: List[Shot],
                meta: dict) -> str:
    """The truth as JSON (see the module docstring for the conventions it states)."""
    doc = {
        "format": TRUTH_FORMAT, "version": 1, **meta,
        "crs": f"EPSG:{scene.layout.epsg}",
        "heights": "ellipsoidal (WGS 84), metres; points lie on the DSM surface (bilinear between "
                   "pixel centres)",
        "pixels": "origin at the top-left corner of the image, x right, y down; the centre of the "
                  "top-left pixel is (0.5, 0.5)",
        "seen": "in front of the camera, inside the frame [0, width] x [0, height], and the "
                "segment to the camera centre does not pass under the DSM surface",
        "image_size": [camera.width, camera.height],
        "camera": camera_doc(camera),
        "photos": {s.label: {"file": f"photos/{s.filename}", "line": s.line,
                             "centre": (s.C + scene.offset).tolist(),
                             "rotation": s.R.tolist(),
                             **({"rolling_shutter": readout_motion.describe(s)}
                                if s.motion is not None else {})}
                   for s in shots},
        "points": {"id": truth.point_ids, "kind": truth.point_kinds,
                   "xyz": truth.points.tolist()},
        "observations": {"point": truth.obs_point.tolist(),
                         "photo": [shots[i].label for i in truth.obs_shot],
                         "pixel": truth.obs_pixel.tolist()},
        "hidden": {"point": truth.hidden_point.tolist(),
                   "photo": [shots[i].label for i in truth.hidden_shot]},
        "plot_colour": "exg: mean ExG (2G-R-B)/(R+G+B) of the plot rectangle's texture; cover: "
                       "share of the rectangle that is mostly leaf (crop height >= 2.5 cm); both "
                       "from the generator's noise-free colour model on a 5 mm grid",
        "plots": truth.plots,
        "labelme": truth.labelme,
    }
    # one line per top-level member, values compact
    write_bytes(path, ("{\n" + ",\n".join(f"{json.dumps(k)}: {json.dumps(v, separators=(',', ':'))}"
                                         for k, v in doc.items()) + "\n}\n").encode())
    return path
