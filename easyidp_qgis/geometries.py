"""The one bridge between core geometry and QGIS: the core's WKB (``core.wkb``) →
``QgsGeometry.fromWkb``, and QGIS polygons → the core's plain rings.

The core is imported at module level: a function-level import runs QGIS's import hook
(``qgis.utils._import``) at every call, 0.13 s for 47,477 back-projection features."""
import numpy as np
from qgis.core import QgsGeometry, QgsWkbTypes

from ..core.wkb import flat_multipolygons_wkb, multipolygon_wkb, polygon_wkb


def from_wkb(wkb: bytes) -> QgsGeometry:
    """A QgsGeometry from WKB bytes (ISO, as ``core.wkb`` writes them)."""
    g = QgsGeometry()
    g.fromWkb(wkb)
    return g


def multipolygon(polygons, z: bool = False, min_vertices: int = 0, close: bool = True,
                 flip_y: bool = False) -> QgsGeometry:
    """A MultiPolygon(Z) QgsGeometry of the core's polygons ``[[exterior, hole, …], …]`` (open
    rings unless ``close=False``); rings shorter than ``min_vertices`` are dropped, so the
    geometry may be empty (``isEmpty()``). See ``core.wkb.multipolygon_wkb``."""
    return from_wkb(multipolygon_wkb(polygons, z=z, min_vertices=min_vertices, close=close,
                                     flip_y=flip_y))


def polygon(rings, z: bool = False) -> QgsGeometry:
    """A Polygon(Z) QgsGeometry of one core polygon ``[exterior, hole, …]`` (open rings)."""
    return from_wkb(polygon_wkb(rings, z=z))


def pixel_geometry(polys) -> QgsGeometry:
    """Photo-pixel polygons (x = column, y = row) → a MultiPolygon with x = column, y = −row
    (how QGIS places a photo opened without georeference)."""
    return multipolygon(polys, flip_y=True)


def pixel_geometries(flat) -> list:
    """:func:`pixel_geometry` of every record of a ``core.geometry.FlatPolygons`` (a
    back-projection's ``polygons``), the WKB built in one pass (``core.wkb``)."""
    return [from_wkb(w) for w in flat_multipolygons_wkb(flat, flip_y=True)]


def polygon_coordinates(g) -> list:
    """MultiPolygon coordinates [[[(x, y[, z]), …] ring …] polygon …] of a QgsGeometry (rings
    closed, as QGIS stores them)."""
    if g is None or g.isNull() or g.isEmpty():
        return []
    geom = g.constGet()
    polys = [geom.geometryN(i) for i in range(geom.numGeometries())] if g.isMultipart() else [geom]
    has_z = QgsWkbTypes.hasZ(geom.wkbType())

    def ring(r):
        return [(p.x(), p.y(), p.z()) if has_z else (p.x(), p.y()) for p in r.points()]
    return [[ring(p.exteriorRing())] + [ring(p.interiorRing(k)) for k in range(p.numInteriorRings())]
            for p in polys if p is not None and p.exteriorRing() is not None]


def pixel_polygons(geom) -> list:
    """Photo-pixel polygons [[exterior, hole, …], …] (x = column, y = row; open rings) of a
    geometry of the photo-pixel layer (x = column, y = −row): the inverse of
    :func:`pixel_geometry`."""
    out = []
    for poly in polygon_coordinates(geom):
        rings = []
        for ring in poly:
            a = np.array([p[:2] for p in ring], np.float64) * [1.0, -1.0]
            if len(a) > 1 and np.all(a[0] == a[-1]):
                a = a[:-1]
            rings.append(a)
        out.append(rings)
    return out
