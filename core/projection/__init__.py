"""Projection between the map and the raw photos of a photogrammetry project.

* The exact first hit of rays on a DSM (:func:`core.raster.first_hits` on a
  :class:`core.raster.DSM`'s ray surface) is shared by forward projection, occlusion,
  footprints and orthorectification; a DSM is given as a :class:`core.raster.DSM` (or a path).
* Camera footprints on a DSM or a constant height (:func:`camera_footprints`; each
  :class:`Footprint` has a :class:`FootprintStatus` and its message).
* Backward (map → photos, EasyIDP's ``back2raw``): :func:`back_project` finds every ROI in every
  photo that sees it (clipped to the frame, tested for occlusion, ranked); :func:`crop_photos`
  cuts the ROIs out of the photos, each photo decoded once.
* Training sets (:func:`export_training_set`): labelled map objects as COCO, YOLO and LabelMe
  datasets on the raw photos (whole or tiled).
* Plot statistics from the raw photos: :func:`photo_statistics` measures every ROI in every
  photo (bands, vegetation indices, cover; occluded pixels left out) in the same one-decode pass
  and gives one robust value per ROI across its views.
* Forward (photos → map): :func:`forward_project` brings shapes drawn or detected on a photo to
  the map by their rays' first hits on the DSM; :func:`merge_views` merges the same object seen
  in several photos (:func:`fuse_views`: one object per real object, with a confidence);
  :func:`orthorectify_rois` orthorectifies ROIs from the raw photos.

Pixels: origin at the top-left corner of the photo, x = column right, y = row down, centre of
the top-left pixel (0.5, 0.5).
"""
from .footprints import Footprint, FootprintStatus, camera_footprints
from .backward import back_project
from .ranking import score
from .forward import ForwardShape, forward_project
from .height_sources import ConstantHeight, GeometryZ, PerROIHeights, height_source
from .map_polygon import MapPolygon
from .merge import MERGE_MODES, merge_views
from .fuse import FusedObject, fuse_views
from .training_set import TrainingSet, export_training_set, point_discs
from .ortho import OrthoResult, orthorectify_rois
from .photo_crops import PhotoCropResult, crop_photos, draw_previews
from .photo_stats import PhotoStatistics, photo_statistics
from .roi_photo_stats import roi_photo_statistics
from ..photos import DecodedPhotos, read_photo, resolve_photos
from .forward_photos import PhotosToMap, forward_project_photos
from .photo_finder import POINT_SIDE, PhotoFinder
from ..geometry import FlatPolygons
from .result import PIXEL_CONVENTION, PIXEL_CRS_WKT, BackProjection, read_easyidp_json

__all__ = ["camera_footprints", "Footprint", "FootprintStatus",
           "back_project", "score", "BackProjection", "FlatPolygons", "PIXEL_CONVENTION", "PIXEL_CRS_WKT",
           "read_easyidp_json", "GeometryZ", "PerROIHeights", "ConstantHeight",
           "height_source", "crop_photos", "draw_previews", "PhotoCropResult", "read_photo",
           "resolve_photos", "DecodedPhotos", "photo_statistics", "PhotoStatistics",
           "roi_photo_statistics", "PhotoFinder", "POINT_SIDE",
           "ForwardShape", "forward_project", "MapPolygon",
           "merge_views", "MERGE_MODES", "fuse_views", "FusedObject", "export_training_set",
           "TrainingSet", "point_discs", "orthorectify_rois", "OrthoResult", "PhotosToMap",
           "forward_project_photos"]
