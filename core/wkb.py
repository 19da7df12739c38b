"""Well-Known Binary (ISO WKB, little-endian) of the core's polygons, written with numpy.

The one form in which core geometry reaches a GIS: the QGIS plugin turns it into features with
``QgsGeometry.fromWkb``. Polygons are ``[exterior, hole, …]``, each ring an (n, 2) or (n, 3)
array of open vertices (the first vertex is not repeated): the encoder closes every ring by
repeating its first vertex (``close=False``: the rings are already closed, as QGIS stores
them). With Z, every ring of the geometry must have three columns. Coordinates in the units of
the geometry's CRS (photo pixels for the photo-pixel layers).
"""
import struct
from typing import Sequence

import numpy as np

__all__ = ["multipolygon_wkb", "polygon_wkb"]

_POLYGON, _MULTIPOLYGON, _Z = 3, 6, 1000


def _rings(rings, z: bool, close: bool, flip_y: bool) -> list:
    out = [struct.pack("<I", len(rings))]
    width = 3 if z else 2
    for r in rings:
        r = np.asarray(r, np.float64)
        n = len(r)
        a = np.empty((n + 1 if close else n, width), "<f8")
        a[:n] = r[:, :width]
        if close:
            a[n] = a[0]
        if flip_y:
            a[:, 1] *= -1.0
        out.append(struct.pack("<I", len(a)))
        out.append(a.tobytes())
    return out


def polygon_wkb(rings: Sequence, z: bool = False, close: bool = True) -> bytes:
    """The WKB Polygon (PolygonZ with ``z``) of one polygon ``[exterior, hole, …]``."""
    return b"".join([struct.pack("<BI", 1, _POLYGON + (_Z if z else 0)),
                     *_rings(rings, z, close, False)])


def multipolygon_wkb(polygons: Sequence, z: bool = False, min_vertices: int = 0,
                     close: bool = True, flip_y: bool = False) -> bytes:
    """The WKB MultiPolygon (MultiPolygonZ with ``z``) of ``polygons`` ``[[exterior, hole, …],
    …]``. Rings of fewer than ``min_vertices`` vertices are left out, and polygons left with no
    ring; the result may then have no polygon. ``flip_y``: y written as −y (photo pixels, y =
    row down, as QGIS places a photo opened without georeference: y = −row)."""
    kept = []
    for p in polygons:
        rings = [r for r in p if len(r) >= min_vertices] if min_vertices else list(p)
        if rings:
            kept.append(rings)
    ptype = struct.pack("<BI", 1, _POLYGON + (_Z if z else 0))
    out = [struct.pack("<BII", 1, _MULTIPOLYGON + (_Z if z else 0), len(kept))]
    for rings in kept:
        out.append(ptype)
        out += _rings(rings, z, close, flip_y)
    return b"".join(out)

