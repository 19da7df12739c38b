"""Reading ROIs from GeoJSON (RFC 7946, and the older GDAL/QGIS flavour with a ``crs`` member)."""
import os
from typing import Optional

from ..deprecation import renamed_parameters
from ..errors import InputError, reads_file
from ..files import load_json
from .features import rois_from_features
from .model import ROISet


@renamed_parameters(crs="source_crs")
@reads_file("Export the layer again (QGIS: Export ▸ Save Features As… GeoJSON).")
def read_geojson(path, name_field: Optional[str] = None, source_crs=None) -> ROISet:
    """ROIs from a GeoJSON file: a FeatureCollection, a single Feature or a bare geometry.

    Z coordinates are kept as vertex heights.

    Parameters
    ----------
    path : str or path
        The GeoJSON file.
    name_field : str, optional
        The property that names each ROI; default the feature ``id``, else the 0-based feature
        index.
    source_crs : CRS, optional
        The CRS of the coordinates; default the legacy ``crs`` member, else OGC:CRS84
        (lon/lat) as RFC 7946 says.

    Returns
    -------
    ROISet
        The ROIs, in the file's order.
    """
    path = os.fspath(path)
    doc = load_json(path, "GeoJSON")
    if not isinstance(doc, dict) or "type" not in doc:
        raise InputError(f"ROI file {path} is not GeoJSON: it has no 'type' member.")
    crs = source_crs
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
