"""ROIs from CloudCompare point lists (a polyline picked on a point cloud, saved as text).

One ROI per file, named after the file: one vertex per line, ``x, y, z`` (commas, spaces,
semicolons or tabs), optionally after a label column (``Point #0, x, y, z``), as EasyIDP's
``read_cc_txt`` reads them. The ring is closed; z is kept as the vertex heights.
"""
import os
import re

import numpy as np

from ..errors import InputError
from .model import ROISet, roi_from_coordinates

_SPLIT = re.compile(r"[,;\s]+")


def read_cloudcompare(path, crs=None) -> ROISet:
    """The polyline in ``path`` as one ROI, in ``crs`` (the point cloud's CRS; required, as
    CloudCompare writes none)."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"ROI file not found: {path}")
    if crs is None:
        raise InputError(f"{path}: CloudCompare point lists carry no CRS. Give the CRS of the "
                         "point cloud they were picked on (crs='EPSG:…').")
    rows = []
    with open(path, encoding="utf-8", errors="replace") as fh:
        for n, line in enumerate(fh, 1):
            fields = [f for f in _SPLIT.split(line.strip()) if f]
            if not fields or line.lstrip().startswith(("//", "#")):
                continue
            nums = _numbers(fields)
            if nums is None or len(nums) < 2:
                raise InputError(f"{path}, line {n}: {line.strip()[:60]!r} is not 'x, y, z'.")
            rows.append(nums[-3:])
    if len({len(r) for r in rows}) > 1:
        raise InputError(f"{path}: some lines have a z and some do not.")
    if len(rows) < 3:
        raise InputError(f"{path}: {len(rows)} vertices; a polygon needs at least 3.")
    stem = os.path.splitext(os.path.basename(path))[0]
    return ROISet([roi_from_coordinates(stem, "Polygon", [np.array(rows).tolist()])], crs)


def _numbers(fields):
    """The trailing numeric fields of a line (a leading label such as 'Point #0' is skipped)."""
    out = []
    for f in reversed(fields):
        try:
            out.append(float(f))
        except ValueError:
            break
    return out[::-1] if len(out) >= 2 else None
