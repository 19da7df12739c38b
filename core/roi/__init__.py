"""Regions of interest (plots, trees, plants): the :class:`ROI` and :class:`ROISet` types and
readers for the files users have.

``open_rois(source, name_field=None, source_crs=None, raster=None, layer=None)`` reads ESRI shapefiles
(pyshp), GeoPackage polygon layers, GeoJSON, LabelMe polygons drawn on a georeferenced raster
(opened by the caller), CloudCompare point lists, and any
object with ``__geo_interface__`` (shapely, geopandas).
"""
from .cloudcompare import read_cloudcompare
from .geo_interface import rois_from_geo_interface
from .geojson import read_geojson
from .from_wkb import rois_from_wkb, wkb_with_height
from .geopackage import read_geopackage
from .labelme_on_raster import read_labelme_rois
from .model import ROI, ROISet, roi_from_coordinates
from .open import open_rois
from .shapefile import read_shapefile

__all__ = ["ROI", "ROISet", "roi_from_coordinates", "rois_from_wkb", "wkb_with_height", "open_rois", "read_geojson",
           "read_shapefile", "read_geopackage", "rois_from_geo_interface", "read_labelme_rois",
           "read_cloudcompare"]
