"""Writers of training sets: COCO instances, YOLO (detect and segment) labels, LabelMe files.

Shapes come in the project pixel convention (origin at the image's top-left corner, x =
column right, y = row down; the centre of the top-left pixel is (0.5, 0.5)), which is also the
convention of COCO, YOLO (times the image size) and LabelMe: nothing is shifted. Every file is
written atomically (:mod:`..files`). COCO and YOLO polygons carry exterior rings only (neither
format has holes); a shape of several parts gives several polygons in COCO's
``segmentation`` and one YOLO segment line per part.
"""
import json
import os
from dataclasses import dataclass, field
from typing import Dict, List, Sequence

import numpy as np

from ..files import write_bytes, write_json
from ..geometry import polygons_area

COCO_DECIMALS = 4      # pixels: 1e-4 px
YOLO_DECIMALS = 7      # normalised: 1e-7 of the image size


@dataclass
class LabelledShape:
    """One object on one training image. ``polygons``: [[exterior, hole, ...], ...] open
    (n, 2) pixel rings, exteriors first; ``instance``: the object's name (unique over the set);
    ``attributes``: extra numbers kept in COCO and LabelMe (e.g. visible_fraction)."""
    label: str
    instance: str
    polygons: List[List[np.ndarray]]
    attributes: dict = field(default_factory=dict)

    def bbox(self):
        """(x0, y0, x1, y1) of the exteriors, pixels."""
        xy = np.vstack([p[0] for p in self.polygons])
        return float(xy[:, 0].min()), float(xy[:, 1].min()), float(xy[:, 0].max()), float(xy[:, 1].max())


@dataclass
class LabelledImage:
    """One training image: its file name (as written), size in pixels and shapes."""
    file_name: str
    width: int
    height: int
    shapes: List[LabelledShape] = field(default_factory=list)
    attributes: dict = field(default_factory=dict)


def coco_document(images: Sequence[LabelledImage], categories: Sequence[str],
                  description: str = "") -> dict:
    """A COCO instances document: ``images`` (ids from 1), ``categories`` (ids from 1, in the
    order given), ``annotations`` with ``segmentation`` (exterior rings, flat x, y lists),
    ``bbox`` [x, y, w, h], ``area`` (pixels², holes subtracted), ``iscrowd`` 0 and
    ``attributes`` (instance name and the shape's own numbers)."""
    cat_id = {c: k + 1 for k, c in enumerate(categories)}
    doc = {"info": {"description": description, "version": "1.0"},
           "licenses": [], "images": [], "annotations": [],
           "categories": [{"id": cat_id[c], "name": c, "supercategory": ""} for c in categories]}
    ann_id = 0
    for k, im in enumerate(images, 1):
        doc["images"].append({"id": k, "file_name": im.file_name, "width": int(im.width),
                              "height": int(im.height), **im.attributes})
        for s in im.shapes:
            ann_id += 1
            x0, y0, x1, y1 = s.bbox()
            seg = [np.round(p[0], COCO_DECIMALS).ravel().tolist() for p in s.polygons]
            doc["annotations"].append({
                "id": ann_id, "image_id": k, "category_id": cat_id[s.label],
                "segmentation": seg, "area": round(polygons_area(s.polygons), COCO_DECIMALS),
                "bbox": [round(x0, COCO_DECIMALS), round(y0, COCO_DECIMALS),
                         round(x1 - x0, COCO_DECIMALS), round(y1 - y0, COCO_DECIMALS)],
                "iscrowd": 0, "attributes": {"instance": s.instance, **s.attributes}})
    return doc


def write_coco(path, images: Sequence[LabelledImage], categories: Sequence[str],
               description: str = "") -> str:
    """Write :func:`coco_document` to ``path`` (atomically)."""
    write_json(path, coco_document(images, categories, description), separators=(",", ":"))
    return os.fspath(path)


def _fmt(v: float) -> str:
    s = f"{v:.{YOLO_DECIMALS}f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def yolo_lines(im: LabelledImage, class_index: Dict[str, int], segment: bool) -> List[str]:
    """YOLO label lines of one image: ``class cx cy w h`` (detect) or ``class x1 y1 … xn yn``
    (segment, one line per part), normalised to the image size."""
    w, h = float(im.width), float(im.height)
    out = []
    for s in im.shapes:
        c = class_index[s.label]
        if segment:
            for p in s.polygons:
                xy = p[0] / np.array([w, h])
                out.append(" ".join([str(c)] + [_fmt(v) for v in xy.ravel()]))
        else:
            x0, y0, x1, y1 = s.bbox()
            out.append(" ".join([str(c)] + [_fmt(v) for v in
                                            ((x0 + x1) / 2 / w, (y0 + y1) / 2 / h,
                                             (x1 - x0) / w, (y1 - y0) / h)]))
    return out


def write_yolo_labels(path, im: LabelledImage, class_index: Dict[str, int], segment: bool) -> str:
    """One image's YOLO label file (atomically; empty for an image without shapes)."""
    lines = yolo_lines(im, class_index, segment)
    write_bytes(path, ("\n".join(lines) + ("\n" if lines else "")).encode())
    return os.fspath(path)


def yolo_data_yaml(categories: Sequence[str], splits: Sequence[str], task: str) -> str:
    """An Ultralytics ``data.yaml`` for a dataset rooted at the yaml's folder (no ``path:``,
    so Ultralytics takes the yaml's folder): ``train``/``val`` image folders and ``names``."""
    names = "\n".join(f"  {k}: {_yaml_str(c)}" for k, c in enumerate(categories))
    rows = [f"# YOLO {task} dataset written by EasyIDP for QGIS", *
            (f"{s}: images/{s}" for s in splits), f"nc: {len(categories)}", "names:", names]
    return "\n".join(rows) + "\n"


def _yaml_str(s: str) -> str:
    return json.dumps(str(s), ensure_ascii=False)


def labelme_document(im: LabelledImage, image_path: str) -> dict:
    """A LabelMe 5 document of one image: one polygon per part (holes are not kept: LabelMe has
    none), ``group_id`` the object's number on the image, ``description`` its instance name."""
    shapes = []
    for k, s in enumerate(im.shapes):
        for p in s.polygons:
            shapes.append({"label": s.label, "points": np.round(p[0], COCO_DECIMALS).tolist(),
                           "group_id": k, "description": s.instance, "shape_type": "polygon",
                           "flags": {}})
    return {"version": "5.2.1", "flags": {}, "shapes": shapes, "imagePath": image_path,
            "imageData": None, "imageHeight": int(im.height), "imageWidth": int(im.width)}


def write_labelme(path, im: LabelledImage, image_path: str) -> str:
    write_json(path, labelme_document(im, image_path), separators=(",", ":"))
    return os.fspath(path)


__all__ = ["LabelledShape", "LabelledImage", "coco_document", "write_coco", "yolo_lines",
           "write_yolo_labels", "yolo_data_yaml", "labelme_document", "write_labelme"]
