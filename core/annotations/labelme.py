"""LabelMe JSON files (labelme 3.x–5.x): polygons, rectangles, circles, lines, points.

LabelMe stores Qt scene coordinates, where pixel (0, 0) covers [0, 1)², i.e. the project's own
pixel convention: no shift is applied. A rectangle (two opposite corners) becomes a 4-vertex
polygon; a circle (centre, a point on the circle) a polygon of ``CIRCLE_VERTICES`` vertices;
``line``/``linestrip`` a polyline; ``point`` a point. Masks (labelme 5 ``mask``) are refused
with a message.
"""
import os
from typing import List

import numpy as np

from ..errors import InputError, reads_file
from ..files import load_json
from .model import LINE, POINT, POLYGON, PhotoAnnotations, PhotoShape, image_size

CIRCLE_VERTICES = 64


@reads_file("Open and save it again in LabelMe.")
def read_labelme(path) -> PhotoAnnotations:
    """Read a LabelMe JSON file. Raises :class:`InputError` naming the file and the shape."""
    path = os.fspath(path)
    doc = load_json(path, "LabelMe JSON")
    if not isinstance(doc, dict) or not isinstance(doc.get("shapes"), list):
        raise InputError(f"{path} is not a LabelMe file: it has no 'shapes' list.")
    width, height = image_size(doc, ("imageWidth", "imageHeight"), path)
    shapes = [_shape(s, k, path) for k, s in enumerate(doc["shapes"])]
    return PhotoAnnotations(path, str(doc.get("imagePath") or ""), width, height, shapes)


def _shape(s, k: int, path: str) -> PhotoShape:
    if not isinstance(s, dict):
        raise InputError(f"{path}: shape {k} is not an object.")
    label = str(s.get("label", ""))
    typ = str(s.get("shape_type") or "polygon")
    where = f"{path}: shape {k} ({label!r}, {typ})"
    try:
        pts = np.asarray(s.get("points") or [], dtype=np.float64).reshape(-1, 2)
    except (TypeError, ValueError):
        raise InputError(f"{where}: its points are not (x, y) pixel pairs.") from None
    if not np.all(np.isfinite(pts)):
        raise InputError(f"{where}: its points are not finite numbers.")
    need = {"polygon": 3, "rectangle": 2, "circle": 2, "line": 2, "linestrip": 2, "point": 1}
    if typ not in need:
        raise InputError(f"{where}: shape type {typ!r} is not supported (polygon, rectangle, "
                         "circle, line, linestrip, point). Convert it to a polygon in LabelMe.")
    if len(pts) < need[typ]:
        raise InputError(f"{where}: {len(pts)} point(s), a {typ} needs at least {need[typ]}.")
    kind, rings = _geometry(typ, pts)
    attrs = {key: s[key] for key in ("flags", "description") if s.get(key) not in (None, {}, "")}
    return PhotoShape(label, kind, rings, typ, s.get("score"), s.get("group_id"), attrs)


def _geometry(typ: str, pts: np.ndarray):
    if typ == "polygon":
        return POLYGON, [pts]
    if typ == "rectangle":
        (x0, y0), (x1, y1) = pts[0], pts[1]
        return POLYGON, [np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])]
    if typ == "circle":
        r = float(np.hypot(*(pts[1] - pts[0])))
        t = np.linspace(0.0, 2 * np.pi, CIRCLE_VERTICES, endpoint=False)
        return POLYGON, [pts[0] + r * np.column_stack([np.cos(t), np.sin(t)])]
    if typ in ("line", "linestrip"):
        return LINE, [pts]
    return POINT, [pts[:1]]


def polygons(doc: PhotoAnnotations) -> List[PhotoShape]:
    """The polygon shapes of ``doc`` (rectangles and circles included)."""
    return [s for s in doc.shapes if s.kind == POLYGON]
