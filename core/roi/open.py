"""``open_rois``: ROIs from whatever a user has, with its CRS."""
import json
import os
from typing import Optional

from ..deprecation import renamed_parameters
from ..errors import InputError
from .cloudcompare import read_cloudcompare
from .geo_interface import rois_from_geo_interface
from .geojson import read_geojson
from .geopackage import read_geopackage
from .labelme_on_raster import read_labelme_rois
from .model import ROISet
from .shapefile import read_shapefile


@renamed_parameters(crs="source_crs")
def open_rois(source, name_field: Optional[str] = None, source_crs=None, raster=None,
              layer: Optional[str] = None) -> ROISet:
    """ROIs from a file or an object, with their CRS.

    Parameters
    ----------
    source : str, path or object
        * ``.shp`` / ``.zip``: ESRI shapefile (CRS from ``.prj``, encoding from ``.cpg``);
        * ``.gpkg``: a polygon layer of a GeoPackage;
        * ``.geojson`` / ``.json``: GeoJSON, or a LabelMe file (recognised by its ``shapes``),
          whose pixel polygons are placed on the georeferenced ``raster`` they were drawn on;
        * ``.txt`` / ``.csv``: a CloudCompare point list (one polygon; ``source_crs``
          required);
        * any object with ``__geo_interface__`` (shapely, geopandas) or a GeoJSON-like dict.
    name_field : str, optional
        The attribute that names each ROI (default: the feature id or index).
    source_crs : CRS, optional
        Overrides (or, where the source has none, supplies) the CRS.
    raster : GeoTiff or path, optional
        LabelMe only: the georeferenced raster the polygons were drawn on, opened
        (``core.raster.open_geotiff``); ``easyidp_toolbox.core.open_rois`` also takes its path.
    layer : str, optional
        GeoPackage only: the layer's name, when it has several.

    Returns
    -------
    ROISet
        The ROIs with their CRS.
    """
    if not isinstance(source, (str, os.PathLike)):
        return rois_from_geo_interface(source, source_crs, name_field)
    path = os.fspath(source)
    ext = os.path.splitext(path)[1].lower()
    if not os.path.isfile(path):
        raise InputError.of("roi_file_not_found", path=path)
    if ext in (".shp", ".zip"):
        return read_shapefile(path, name_field, source_crs)
    if ext == ".gpkg":
        return read_geopackage(path, name_field, source_crs, layer)
    if ext in (".geojson", ".json"):
        if _is_labelme(path):
            if name_field is not None:
                raise InputError(f"{path} is a LabelMe file: its ROIs are named by their labels; "
                                 "do not give a name field.")
            return read_labelme_rois(path, raster, source_crs)
        return read_geojson(path, name_field, source_crs)
    if ext in (".txt", ".csv", ".xyz"):
        return read_cloudcompare(path, source_crs)
    raise InputError(f"{path}: {ext or 'no extension'} is not an ROI format I read. Use a "
                     "shapefile (.shp), GeoPackage (.gpkg), GeoJSON (.geojson), LabelMe (.json) "
                     "or a CloudCompare point list (.txt), or load the layer in QGIS and use the "
                     "Processing tools.")


def _is_labelme(path: str) -> bool:
    try:
        with open(path, "rb") as fh:
            doc = json.loads(fh.read().decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError):
        return False   # read_geojson reports the syntax error
    return isinstance(doc, dict) and isinstance(doc.get("shapes"), list) and "type" not in doc
