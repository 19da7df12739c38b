"""COCO JSON (instances and detection datasets): polygon segmentations and boxes.

COCO pixel coordinates are continuous with (0, 0) at the top-left corner of the image (the
project's convention): no shift. A box ``[x, y, w, h]`` becomes a 4-vertex polygon; a
``segmentation`` list of ``[x1, y1, x2, y2, …]`` polygons becomes one shape per object (the
first polygon its outline, further polygons parts, kept as extra rings only if they lie
inside). RLE masks are refused with a message. The label is the category name; ``score``,
``id`` and ``category_id`` are kept.
"""
import json
import os
from typing import Dict, List

import numpy as np

from ..errors import InputError
from .model import POLYGON, PhotoAnnotations, PhotoShape, image_size


def _load(path: str, what: str):
    if not os.path.isfile(path):
        raise InputError(f"{what} not found: {path}")
    try:
        with open(path, "rb") as fh:
            return json.loads(fh.read().decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"{path} is not valid JSON ({exc}); is it a COCO file?") from None


def read_coco(path, dataset=None) -> List[PhotoAnnotations]:
    """One :class:`PhotoAnnotations` per image of a COCO JSON file (images without annotations
    included). Raises :class:`InputError` naming the file and the annotation at fault.

    ``path`` may also be a COCO *results* list (``image_id``, ``category_id``, ``bbox`` or
    ``segmentation``, ``score``, as detectors write): ``dataset`` is then the COCO file whose
    ``images`` and ``categories`` the ids refer to. An image with ``photo`` and ``photo_window``
    ([x0, y0, w, h], as :func:`core.projection.training_set.export_training_set` writes for
    tiles) is a window of that photo: its shapes are shifted into the photo's pixels and the
    image is reported as the photo, with no declared size."""
    path = os.fspath(path)
    doc = _load(path, "COCO file")
    if isinstance(doc, list):
        if dataset is None:
            raise InputError(f"{path} is a COCO *results* list (annotations without images). Give "
                             "the dataset file its image ids refer to (the COCO images file).")
        base = _load(os.fspath(dataset), "COCO dataset file")
        if not isinstance(base, dict) or not isinstance(base.get("images"), list):
            raise InputError(f"{dataset} is not a COCO dataset file: it has no 'images' list.")
        doc = {"images": base["images"], "categories": base.get("categories") or [],
               "annotations": doc}
    cats = {}
    for k, c in enumerate(doc.get("categories") or []):
        if isinstance(c, dict) and "id" in c:
            cats[c["id"]] = str(c.get("name", c["id"]))
    images: Dict[object, PhotoAnnotations] = {}
    offsets: Dict[object, object] = {}
    for k, im in enumerate(doc["images"]):
        where = f"{path}: images[{k}]"
        if not isinstance(im, dict) or "id" not in im or not im.get("file_name"):
            raise InputError(f"{where} has no 'id' or 'file_name'.")
        w, h = image_size(im, ("width", "height"), where)
        name, off = str(im["file_name"]), None
        if im.get("photo") and isinstance(im.get("photo_window"), list):
            win = _numbers(im["photo_window"], f"{where} photo_window")
            if len(win) != 4:
                raise InputError(f"{where}: photo_window must be [x0, y0, width, height].")
            name, off, w, h = str(im["photo"]), win[:2], None, None
        images[im["id"]] = PhotoAnnotations(path, name, w, h, [])
        offsets[im["id"]] = off
    for k, a in enumerate(doc.get("annotations") or []):
        where = f"{path}: annotations[{k}]"
        if not isinstance(a, dict):
            raise InputError(f"{where} is not an object.")
        if a.get("image_id") not in images:
            raise InputError(f"{where} (id {a.get('id')}) refers to image_id {a.get('image_id')!r}, "
                             "which is not in 'images'.")
        label = cats.get(a.get("category_id"), str(a.get("category_id", "")))
        rings, typ = _rings(a, where)
        if offsets[a["image_id"]] is not None:
            rings = [r + offsets[a["image_id"]] for r in rings]
        attrs = {"category_id": a.get("category_id")}
        score = a.get("score")
        if score is not None:
            try:
                score = float(score)
            except (TypeError, ValueError):
                raise InputError(f"{where}: score {score!r} is not a number.") from None
        images[a["image_id"]].shapes.append(
            PhotoShape(label, POLYGON, rings, typ, score, a.get("id"), attrs))
    return list(images.values())


def _rings(a: dict, where: str):
    seg = a.get("segmentation")
    if isinstance(seg, dict):
        raise InputError(f"{where}: the segmentation is an RLE mask; only polygons and boxes are "
                         "read. Export polygons (e.g. pycocotools/OpenCV contours) instead.")
    if seg:
        if not isinstance(seg, list) or not all(isinstance(p, list) for p in seg):
            raise InputError(f"{where}: 'segmentation' must be a list of [x1, y1, x2, y2, …] lists.")
        rings = []
        for j, p in enumerate(seg):
            pts = _numbers(p, f"{where} segmentation[{j}]")
            if len(pts) % 2 or len(pts) < 6:
                raise InputError(f"{where} segmentation[{j}]: {len(pts)} numbers; a polygon needs "
                                 "an even number, at least 6 (3 vertices).")
            rings.append(pts.reshape(-1, 2))
        return rings, "segmentation"
    box = a.get("bbox")
    if box is None:
        raise InputError(f"{where}: neither 'segmentation' nor 'bbox'.")
    b = _numbers(box, f"{where} bbox")
    if len(b) != 4 or b[2] <= 0 or b[3] <= 0:
        raise InputError(f"{where}: bbox must be [x, y, width, height] with a positive size, not {box}.")
    x, y, w, h = b
    return [np.array([[x, y], [x + w, y], [x + w, y + h], [x, y + h]])], "bbox"


def _numbers(values, where: str) -> np.ndarray:
    try:
        a = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError):
        raise InputError(f"{where}: not a list of numbers.") from None
    if not np.all(np.isfinite(a)):
        raise InputError(f"{where}: not finite numbers.")
    return a
