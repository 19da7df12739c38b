"""Format dispatch: read and write .las, .laz and .ply by file suffix (case-insensitive)."""
from pathlib import Path
from typing import Optional

import numpy as np

from ..errors import InputError
from .cloud import PointCloud
from .las_io import read_las, write_las
from .ply_io import read_ply, write_ply

SUFFIXES = {".las": "las", ".laz": "laz", ".ply": "ply"}


def format_of(path) -> str:
    """'las', 'laz' or 'ply' from the suffix of ``path``; InputError otherwise."""
    fmt = SUFFIXES.get(Path(path).suffix.lower())
    if fmt is None:
        raise InputError(f"Point cloud {Path(path).name!r}: unsupported file type "
                         f"{Path(path).suffix or '(no suffix)'!r}; use .las, .laz or .ply.")
    return fmt


def read_point_cloud(path, crs=None) -> PointCloud:
    """Read a .las/.laz/.ply point cloud. ``crs`` (EPSG code, WKT, pyproj CRS) is required for
    PLY to be used with georeferenced ROIs and overrides the CRS stored in a LAS file."""
    fmt = format_of(path)
    return read_ply(path, crs) if fmt == "ply" else read_las(path, crs)


def write_point_cloud(cloud: PointCloud, path, index: Optional[np.ndarray] = None,
                      ply_text: Optional[bool] = None) -> Path:
    """Write ``cloud`` (or its points at ``index``) in the format given by the suffix of ``path``."""
    fmt = format_of(path)
    if fmt == "ply":
        return write_ply(cloud, path, text=ply_text, index=index)
    return write_las(cloud, path, compress=(fmt == "laz"), index=index)
