"""GeoJSON-like features → :class:`ROISet`: the one path every vector reader ends in."""
from typing import Iterable, Mapping, Optional

from ..crs import as_crs
from ..errors import InputError
from .model import ROISet, roi_from_coordinates


def rois_from_features(features: Iterable[Mapping], crs, name_field: Optional[str],
                       where: str) -> ROISet:
    """ROIs from GeoJSON-like features (``{"geometry": {...}, "properties": {...}, "id": ...}``).

    Names come from ``name_field``, else the feature ``id``, else the 0-based feature index.
    ``where`` names the source in messages. Raises :class:`InputError` for an empty source, a
    missing name field, a feature without geometry; :class:`ROIError` for a non-polygon.
    """
    rois = []
    for i, feat in enumerate(features):
        if not isinstance(feat, Mapping):
            raise InputError(f"{where}: feature {i} is not a GeoJSON-like feature object.")
        props = feat.get("properties") or {}
        if not isinstance(props, Mapping):
            raise InputError(f"{where}: feature {i} has properties that are not an object "
                             f"({type(props).__name__}). Export the layer again.")
        props = dict(props)
        if name_field is not None:
            if name_field not in props:
                raise InputError(f"{where}: feature {i} has no field {name_field!r}; its fields "
                                 f"are {sorted(props) or 'none'}.")
            name = props[name_field]
        else:
            name = feat.get("id", i)
        name = i if name is None else name
        geom = feat.get("geometry")
        if not isinstance(geom, Mapping) or geom.get("type") is None:
            raise InputError(f"{where}: feature {i} ({name!r}) has no geometry. Remove it or draw "
                             "its polygon.")
        rois.append(roi_from_coordinates(str(name), geom["type"], geom.get("coordinates"), props))
    if not rois:
        raise InputError(f"{where} holds no features: it is empty.")
    return ROISet(rois, as_crs(crs, f"CRS of {where}"))
