"""ESRI shapefiles with pyshp: polygons (shape types 5, 15, 25), CRS from ``.prj``, encoding
from ``.cpg``; a zipped shapefile (``.zip``) is read in place.

Rings are grouped as the shapefile specification says: clockwise rings are exteriors,
counter-clockwise rings are holes of the exterior that contains them. PolygonZ heights are kept.
"""
import os
import warnings
import zipfile
from typing import List, Optional

import numpy as np
from pyproj import CRS

from .. import geometry
from ..errors import InputError
from .features import rois_from_features
from .model import ROISet

POLYGON_TYPES = {5: "Polygon", 15: "PolygonZ", 25: "PolygonM"}
SHAPE_NAMES = {0: "Null", 1: "Point", 3: "PolyLine", 8: "MultiPoint", 11: "PointZ", 13: "PolyLineZ",
               18: "MultiPointZ", 21: "PointM", 23: "PolyLineM", 28: "MultiPointM", 31: "MultiPatch"}


def read_shapefile(path, name_field: Optional[str] = None, crs=None, encoding: Optional[str] = None
                   ) -> ROISet:
    """ROIs from a polygon shapefile (``.shp`` with its ``.dbf``/``.shx``, or a ``.zip``).

    The CRS is ``crs`` when given, else the ``.prj`` (ESRI or OGC WKT). Names come from
    ``name_field``, else the 0-based record index. ``encoding`` overrides the ``.cpg``.
    """
    import shapefile  # pyshp

    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"ROI file not found: {path}")
    kw = {"encoding": encoding} if encoding else {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # pyshp's warnings on damage: reported as errors
        try:
            reader = shapefile.Reader(path, **kw)
        except (shapefile.ShapefileException, OSError, ValueError, zipfile.BadZipFile) as exc:
            raise InputError(f"{path} cannot be read as a shapefile ({exc}). A shapefile needs "
                             "its .shp, .shx and .dbf files side by side.") from None
        return _read(reader, path, name_field, crs)


def _read(reader, path: str, name_field: Optional[str], crs) -> ROISet:
    """The ROIs of an open pyshp reader (closed on return)."""
    with reader:
        if reader.shapeType not in POLYGON_TYPES:
            kind = SHAPE_NAMES.get(reader.shapeType, f"type {reader.shapeType}")
            raise InputError(f"{path} holds {kind} shapes, not polygons: ROIs must be polygons "
                             "(buffer points or lines first).")
        prj = crs if crs is not None else _prj(path)
        if prj is None:
            raise InputError(f"{path} has no .prj file, so its CRS is unknown. Give the CRS "
                             "(crs='EPSG:…'), or save the layer with its CRS (QGIS: Export ▸ Save "
                             "Features As…).")
        try:
            features = []
            for i, sr in enumerate(reader.iterShapeRecords()):
                features.append({"id": i, "properties": sr.record.as_dict(),
                                 "geometry": _geometry(sr.shape)})
        except Exception as exc:  # pyshp raises struct.error, IndexError, … on damaged files
            raise InputError(f"{path} is damaged or truncated ({type(exc).__name__}: {exc}); "
                             "re-export it.") from None
    return rois_from_features(features, prj, name_field, f"ROI file {path}")


def _prj(path: str) -> Optional[CRS]:
    """The CRS of the ``.prj`` beside the ``.shp`` (or inside the ``.zip``), None if absent."""
    text = None
    if path.lower().endswith(".zip"):
        with zipfile.ZipFile(path) as z:
            names = [n for n in z.namelist() if n.lower().endswith(".prj")]
            text = z.read(names[0]).decode("utf-8", "replace") if names else None
    else:
        for ext in (".prj", ".PRJ"):
            p = os.path.splitext(path)[0] + ext
            if os.path.isfile(p):
                with open(p, "rb") as fh:
                    text = fh.read().decode("utf-8", "replace")
                break
    if text is None:
        return None
    try:
        return CRS.from_user_input(text.strip())
    except Exception as exc:
        raise InputError(f"The .prj of {path} is not a CRS that PROJ can read ({exc}). Give the CRS "
                         "(crs='EPSG:…') or fix the .prj.") from None


def _geometry(shape) -> Optional[dict]:
    """A GeoJSON-like geometry of one polygon record (None for a Null record)."""
    if shape.shapeType == 0 or not len(shape.points):
        return None
    xy = np.asarray(shape.points, dtype=np.float64)
    z = np.asarray(getattr(shape, "z", None) or [], dtype=np.float64)
    xyz = np.column_stack([xy, z]) if len(z) == len(xy) and shape.shapeType == 15 else xy
    bounds = list(shape.parts) + [len(xy)]
    rings = [xyz[bounds[k]:bounds[k + 1]] for k in range(len(shape.parts))]
    rings = [r for r in rings if len(r)]
    return {"type": "MultiPolygon", "coordinates": [[r.tolist() for r in p] for p in _group(rings)]}


def _group(rings: List[np.ndarray]) -> List[List[np.ndarray]]:
    """Polygons [exterior, holes…]: clockwise rings are exteriors, the others holes of the first
    exterior containing them. When no ring is clockwise, every ring is its own polygon."""
    area = [geometry.ring_area(r[:, :2]) for r in rings]
    ext = [k for k, a in enumerate(area) if a < 0]
    if not ext:
        return [[r] for r in rings]
    polys = {k: [rings[k]] for k in ext}
    for k, r in enumerate(rings):
        if k in polys:
            continue
        owner = next((e for e in ext if geometry.points_in_rings(r[:1, 0], r[:1, 1],
                                                                 [rings[e][:, :2]])[0]), None)
        if owner is None:
            polys[k] = [r]          # a lone counter-clockwise ring: its own polygon
        else:
            polys[owner].append(r)
    return [polys[k] for k in sorted(polys)]
