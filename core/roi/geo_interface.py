"""ROIs from any object with ``__geo_interface__``: shapely geometries, a geopandas GeoDataFrame
or GeoSeries, a GeoJSON-like dict, or a list of any of these — no file needed."""
from typing import Optional

from ..errors import InputError
from .features import rois_from_features
from .model import ROISet


def rois_from_geo_interface(obj, crs=None, name_field: Optional[str] = None) -> ROISet:
    """ROIs from ``obj`` (see the module docstring) in ``crs``.

    ``crs`` defaults to the object's own ``.crs`` (geopandas); without either, an error says to
    give one. Names come from ``name_field``, else the feature ``id`` (a GeoDataFrame's index),
    else the 0-based position.
    """
    where = f"the {type(obj).__name__} given"
    if crs is None:
        crs = getattr(obj, "crs", None)
    if crs is None:
        raise InputError(f"ROIs from {where}: its CRS is unknown. Give it: "
                         "rois_from_geo_interface(obj, crs='EPSG:…').")
    return rois_from_features(_features(obj, where), crs, name_field, f"ROIs from {where}")


def _features(obj, where: str) -> list:
    if isinstance(obj, (list, tuple)):
        out = []
        for item in obj:
            out.extend(_features(item, where))
        return out
    gi = getattr(obj, "__geo_interface__", obj)
    if not isinstance(gi, dict) or "type" not in gi:
        raise InputError(f"ROIs from {where}: it has no __geo_interface__ (a shapely geometry, a "
                         "GeoDataFrame or a GeoJSON-like dict is expected).")
    if gi["type"] == "FeatureCollection":
        return list(gi.get("features") or [])
    if gi["type"] == "Feature":
        return [gi]
    if gi["type"] == "GeometryCollection":
        return [{"geometry": g, "properties": {}} for g in gi.get("geometries") or []]
    return [{"geometry": gi, "properties": {}}]
