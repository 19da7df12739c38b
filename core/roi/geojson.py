"""Reading ROIs from GeoJSON (RFC 7946 and the older GDAL/QGIS flavour with a ``crs`` member)."""
import json
import os
from typing import Optional

from ..errors import InputError
from .model import ROISet, roi_from_coordinates


def read_geojson(path: str, name_field: Optional[str] = None) -> ROISet:
    """ROIs from a GeoJSON file: a FeatureCollection, a single Feature or a bare geometry.

    The CRS is the legacy ``crs`` member when present, else OGC:CRS84 (lon/lat) as RFC 7946 says.
    Names come from ``name_field``, else the feature ``id``, else the 0-based feature index.
    """
    if not os.path.isfile(path):
        raise InputError(f"ROI file not found: {path}")
    try:
        with open(path, "rb") as fh:
            doc = json.loads(fh.read().decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"ROI file {path} is not valid GeoJSON ({exc}).") from None
    crs = "OGC:CRS84"
    if isinstance(doc, dict) and isinstance(doc.get("crs"), dict):
        crs = doc["crs"].get("properties", {}).get("name", crs)
    if doc.get("type") == "FeatureCollection":
        features = doc.get("features") or []
    elif doc.get("type") == "Feature":
        features = [doc]
    else:
        features = [{"type": "Feature", "geometry": doc, "properties": {}}]
    rois = []
    for i, feat in enumerate(features):
        props = feat.get("properties") or {}
        if name_field is not None:
            if name_field not in props:
                raise InputError(f"ROI file {path}: feature {i} has no field {name_field!r}; "
                                 f"fields are {sorted(props)}.")
            name = props[name_field]
        else:
            name = feat.get("id", i)
        geom = feat.get("geometry") or {}
        rois.append(roi_from_coordinates(str(name), geom.get("type", "empty"),
                                         geom.get("coordinates"), props))
    return ROISet(rois, crs)
