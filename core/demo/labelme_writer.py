"""LabelMe annotations on a few photos: polygons around plots, as a user would click them.

Each polygon has six vertices: the plot's four corners (on the surface) and the middles of its
long sides, where they appear in the photo, each moved by a hand's imprecision (normal, 0.8 px,
at most 2 px). LabelMe point coordinates use our pixel convention (origin at the image's
top-left corner; LabelMe stores Qt scene coordinates, where pixel (0, 0) covers [0, 1)²), so no
shift is applied. The truth of each vertex is where its pixel's ray meets the surface.
"""
import os
from typing import Dict, List

import numpy as np

from ..files import write_json
from .field import plot_corners
from .flight import CameraModel, Shot
from .readout_motion import pixel_ground
from .render import intersect
from .scene import Scene
from .truth import project

LABELME_VERSION = "4.5.6"
PHOTOS = (4, 16, 19, 31)     # indices of the annotated photos (one or two per flight line)
MAX_PLOTS = 5                # polygons per photo
JITTER, JITTER_MAX = 0.8, 2.0


def _outline(p: dict) -> np.ndarray:
    """(6, 2) map points: corners and long-side middles, in drawing order."""
    c = plot_corners(p)                                  # ll, lr, ur, ul (long side first)
    return np.array([c[0], 0.5 * (c[0] + c[1]), c[1], c[2], 0.5 * (c[2] + c[3]), c[3]])


def write_labelme(folder: str, photo_dir: str, scene: Scene, camera: CameraModel,
                  shots: List[Shot], plots_whole: Dict[str, List[str]], rng) -> Dict[str, dict]:
    """Write ``folder/<photo>.json`` for the photos in PHOTOS; return their truth
    {json path relative to the survey folder: {image, photo, shapes: [{label, pixels, map}]}}."""
    os.makedirs(folder, exist_ok=True)
    by_id = {p["plot_id"]: p for p in scene.plots}
    truth = {}
    for i in PHOTOS:
        shot = shots[i]
        labels = sorted(pid for pid, names in plots_whole.items() if shot.label in names)[:MAX_PLOTS]
        shapes, shapes_truth = [], []
        for pid in labels:
            xy = _outline(by_id[pid]) - scene.offset[:2]
            pts = np.column_stack([xy, scene.surface_local(xy[:, 0], xy[:, 1])])
            uv = project(camera, [shot], pts)[0][0]
            uv = uv + np.clip(rng.normal(0.0, JITTER, uv.shape), -JITTER_MAX, JITTER_MAX)
            if shot.motion is not None:                   # each vertex from its row's pose
                ground = pixel_ground(scene, camera, shot, uv) + scene.offset
            else:
                x, y = camera.calibration.pixel_to_normalised(uv[:, 0], uv[:, 1])
                d = np.column_stack([x, y, np.ones_like(x)]) @ shot.R
                t = intersect(scene, shot.C, d)
                ground = shot.C + t[:, None] * d + scene.offset
            shapes.append({"label": pid, "points": uv.tolist(), "group_id": None,
                           "shape_type": "polygon", "flags": {}})
            shapes_truth.append({"label": pid, "pixels": uv.tolist(), "map": ground.tolist()})
        name = shot.label + ".json"
        image = os.path.relpath(os.path.join(photo_dir, shot.filename), folder).replace(os.sep, "/")
        doc = {"version": LABELME_VERSION, "flags": {}, "shapes": shapes, "imagePath": image,
               "imageData": None, "imageHeight": camera.height, "imageWidth": camera.width}
        write_json(os.path.join(folder, name), doc, indent=2)
        truth[f"{os.path.basename(folder)}/{name}"] = {
            "image": f"photos/{shot.filename}", "photo": shot.label, "shapes": shapes_truth}
    return truth
