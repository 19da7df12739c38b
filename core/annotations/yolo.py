"""YOLO text labels: one ``<image stem>.txt`` per photo, one object per line.

A line is ``class cx cy w h`` (a box) or ``class x1 y1 x2 y2 … xn yn`` (a segmentation
polygon, n ≥ 3), all normalised to the image size, optionally followed by a confidence (as
``save_conf`` writes). Normalised coordinates times the photo size (from the project) give
pixels in the project's convention (origin at the top-left corner; no shift). Class names
come from a ``classes.txt`` (one per line) or the ``names:`` of a ``data.yaml`` beside the
labels or up to two folders above them, else the class number is the label.
"""
import os
from typing import Dict, List, Optional

import numpy as np

from ..errors import InputError
from .model import POLYGON, PhotoAnnotations, PhotoShape


def read_yolo(path, size: Optional[tuple] = None, names: Optional[Dict[int, str]] = None,
              image: Optional[str] = None) -> PhotoAnnotations:
    """Read one YOLO label file. ``size`` = (width, height) of the photo in pixels (from the
    project); without it the shapes stay normalised (0–1) and ``width``/``height`` are None.
    ``image``: the photo name (default: the file's stem). Malformed lines raise
    :class:`InputError` naming the file and the line."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"YOLO label file not found: {path}")
    if names is None:
        names = class_names(os.path.dirname(path))
    w, h = size if size is not None else (1.0, 1.0)
    shapes = []
    with open(path, "r", encoding="utf-8-sig", errors="replace") as fh:
        for n, line in enumerate(fh, 1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            where = f"{path}, line {n}"
            parts = text.split()
            try:
                cls = int(float(parts[0]))
                vals = np.array([float(v) for v in parts[1:]])
            except ValueError:
                raise InputError(f"{where}: {text[:60]!r} is not 'class x y …' numbers.") from None
            if not np.all(np.isfinite(vals)):
                raise InputError(f"{where}: coordinates are not finite numbers.")
            score = None
            if len(vals) == 5 or (len(vals) >= 7 and len(vals) % 2 == 1):
                score, vals = float(vals[-1]), vals[:-1]
            if len(vals) == 4:
                cx, cy, bw, bh = vals
                if bw <= 0 or bh <= 0:
                    raise InputError(f"{where}: a box with width {bw} and height {bh}.")
                ring = np.array([[cx - bw / 2, cy - bh / 2], [cx + bw / 2, cy - bh / 2],
                                 [cx + bw / 2, cy + bh / 2], [cx - bw / 2, cy + bh / 2]])
                typ = "bbox"
            elif len(vals) >= 6:
                ring, typ = vals.reshape(-1, 2), "segmentation"
            else:
                raise InputError(f"{where}: {len(vals)} numbers after the class; a box has 4 "
                                 "(cx cy w h), a polygon at least 6.")
            if ring.min() < -0.01 or ring.max() > 1.01:
                raise InputError(f"{where}: coordinates outside 0–1; YOLO labels are normalised "
                                 "to the image size.")
            ring = ring * np.array([w, h])
            shapes.append(PhotoShape(names.get(cls, str(cls)), POLYGON, [ring], typ, score, None,
                                     {"class": cls}))
    stem = image or os.path.splitext(os.path.basename(path))[0]
    return PhotoAnnotations(path, stem, size[0] if size else None, size[1] if size else None,
                            shapes)


def class_names(folder: str) -> Dict[int, str]:
    """Class names from ``classes.txt`` or ``data.yaml`` (``names:`` list or mapping) in
    ``folder``, its parent or the parent's parent (Ultralytics' ``labels/train`` layout);
    empty when there is none."""
    parent = os.path.dirname(os.path.abspath(folder))
    for base in (folder, parent, os.path.dirname(parent)):
        p = os.path.join(base, "classes.txt")
        if os.path.isfile(p):
            with open(p, encoding="utf-8-sig") as fh:
                return {k: s.strip() for k, s in enumerate(fh) if s.strip()}
        p = os.path.join(base, "data.yaml")
        if os.path.isfile(p):
            return _yaml_names(p)
    return {}


def _yaml_names(path: str) -> Dict[int, str]:
    """The ``names`` of an Ultralytics data.yaml: ``names: [a, b]`` or a ``names:`` block of
    ``0: a`` lines or ``- a`` items (the two forms Ultralytics writes)."""
    lines = open(path, encoding="utf-8-sig").read().splitlines()
    out: Dict[int, str] = {}
    for k, line in enumerate(lines):
        if not line.strip().startswith("names:"):
            continue
        rest = line.split(":", 1)[1].strip()
        if rest.startswith("["):
            items = [s.strip().strip("'\"") for s in rest.strip("[]").split(",") if s.strip()]
            return dict(enumerate(items))
        for item in lines[k + 1:]:
            s = item.strip()
            if not item.startswith((" ", "\t")) or not s:
                break
            if s.startswith("- "):
                out[len(out)] = s[2:].strip().strip("'\"")
            elif ":" in s:
                key, val = s.split(":", 1)
                try:
                    out[int(key)] = val.strip().strip("'\"")
                except ValueError:
                    break
        return out
    return out


def read_yolo_folder(folder, sizes=None) -> List[PhotoAnnotations]:
    """Every ``*.txt`` label file of ``folder`` (``classes.txt`` excluded); ``sizes``: a
    callable ``stem -> (width, height)`` giving each photo's size."""
    folder = os.fspath(folder)
    names = class_names(folder)
    out = []
    for name in sorted(os.listdir(folder)):
        if not name.lower().endswith(".txt") or name.lower() == "classes.txt":
            continue
        stem = os.path.splitext(name)[0]
        out.append(read_yolo(os.path.join(folder, name), sizes(stem) if sizes else None, names))
    return out
