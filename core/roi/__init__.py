"""Regions of interest (plots, trees, plants): the :class:`ROI` and :class:`ROISet` types and
readers for the files users have (see :func:`open_rois`)."""
from .geojson import read_geojson
from .model import ROI, ROISet, roi_from_coordinates

__all__ = ["ROI", "ROISet", "roi_from_coordinates", "read_geojson"]
