"""Projection between the map and the raw photos of a photogrammetry project.

* The exact first hit of rays on a DSM (:mod:`.ray_surface`: :func:`first_hits`), shared by
  forward projection, occlusion and orthorectification.
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
  :mod:`.ortho` orthorectifies ROIs from the raw photos.

Pixels: origin at the top-left corner of the photo, x = column right, y = row down, centre of
the top-left pixel (0.5, 0.5).
"""
from .ray_surface import HIT, LEFT, MISS, NODATA, DSMSurface, RayHits, first_hits
from .backward import back_project, score
from .forward import ForwardShape, densify_ring, forward_project
from .heights import ConstantHeight, DSMHeights, GeometryZ, PerROIHeights, height_source
from .merge import MERGE_MODES, MapPolygon, merge_views
from .fuse import FusedObject, fuse_views
from .training_set import TrainingSet, export_training_set
from .photo_crops import PhotoCropResult, crop_photos, draw_previews
from .photo_stats import PhotoStatistics, photo_statistics
from .photos import DecodedPhotos, read_photo, resolve_photos
from .result import PIXEL_CONVENTION, PIXEL_CRS_WKT, BackProjection, FlatPolygons, read_easyidp_json

from .forward_photos import PhotosToMap, forward_project_photos
from .ortho import orthorectify_rois
from .training_set import point_discs
__all__ = ["DSMSurface", "RayHits", "first_hits", "HIT", "MISS", "LEFT", "NODATA",
           "back_project", "score", "BackProjection", "FlatPolygons", "PIXEL_CONVENTION", "PIXEL_CRS_WKT",
           "read_easyidp_json", "GeometryZ", "DSMHeights", "PerROIHeights", "ConstantHeight",
           "height_source", "crop_photos", "draw_previews", "PhotoCropResult", "read_photo",
           "resolve_photos", "DecodedPhotos", "photo_statistics", "PhotoStatistics",
           "ForwardShape", "forward_project", "densify_ring", "MapPolygon",
           "merge_views", "MERGE_MODES", "fuse_views", "FusedObject", "export_training_set",
           "TrainingSet"]
__all__ += ["PhotosToMap", "forward_project_photos", "orthorectify_rois", "point_discs"]
