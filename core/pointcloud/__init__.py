"""Point clouds: LAS/LAZ/PLY input and output, crop by many ROIs in one pass, ROI heights.

Coordinates are float64 (x, y, z) in the cloud's CRS; every per-point attribute of the source is
kept (see :mod:`.cloud`). Outputs are written atomically and never over an input.
"""
from .cloud import PlyHeader, PointCloud
from ..deprecation import moved_names
from .crop import CloudCropResult, CropItem, crop_indices, crop_point_cloud
from .formats import read_point_cloud, write_point_cloud
from .las_io import read_las, write_las
from .ply_io import read_ply, write_ply
from .stats import canopy_summary, cloud_roi_heights

__all__ = [
    "PointCloud", "PlyHeader", "CropItem", "CloudCropResult", "crop_indices", "crop_point_cloud",
    "read_point_cloud", "write_point_cloud", "read_las", "write_las", "read_ply", "write_ply",
    "canopy_summary", "cloud_roi_heights",
]

# the names before the glossary's renames, for one release (core.deprecation)
__getattr__ = moved_names(__name__, globals(), CropResult="CloudCropResult",
                          roi_heights="cloud_roi_heights")
