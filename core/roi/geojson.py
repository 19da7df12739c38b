"""Reading ROIs from GeoJSON (RFC 7946, and the older GDAL/QGIS flavour with a ``crs`` member)."""
import os
from typing import Optional

from ..errors import InputError, reads_file
from ..files import load_json
from .features import rois_from_features
from .model import ROISet


@reads_file("Export the layer again (QGIS: Export ▸ Save Features As… GeoJSON).")
def read_geojson(path, name_field: Optional[str] = None, crs=None) -> ROISet:
    """ROIs from a GeoJSON file: a FeatureCollection, a single Feature or a bare geometry.

    The CRS is ``crs`` when given, else the legacy ``crs`` member, else OGC:CRS84 (lon/lat) as
    RFC 7946 says. Names come from ``name_field``, else the feature ``id``, else the 0-based
    feature index. Z coordinates are kept as vertex heights.
    """
    path = os.fspath(path)
    doc = load_json(path, "GeoJSON")
    if not isinstance(doc, dict) or "type" not in doc:
        raise InputError(f"ROI file {path} is not GeoJSON: it has no 'type' member.")
    if crs is None:
        crs = "OGC:CRS84"
        if isinstance(doc.get("crs"), dict):
            crs = (doc["crs"].get("properties") or {}).get("name", crs)
    if doc["type"] == "FeatureCollection":
        features = doc.get("features") or []
    elif doc["type"] == "Feature":
        features = [doc]
    else:
        features = [{"type": "Feature", "geometry": doc, "properties": {}}]
    return rois_from_features(features, crs, name_field, f"ROI file {path}")
