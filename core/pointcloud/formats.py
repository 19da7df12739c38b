"""Format dispatch: read and write .las, .laz and .ply by file suffix (case-insensitive)."""
from pathlib import Path
from typing import Optional

import numpy as np

from ..deprecation import renamed_parameters
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


@renamed_parameters(crs="source_crs")
def read_point_cloud(path, source_crs=None) -> PointCloud:
    """Read a .las, .laz or .ply point cloud.

    Parameters
    ----------
    path : str or path
        The file; its suffix (any case) gives the format.
    source_crs : CRS, optional
        The cloud's CRS (EPSG code, WKT, pyproj CRS): required for PLY to be used with
        georeferenced ROIs; overrides the CRS stored in a LAS file.

    Returns
    -------
    PointCloud
        Coordinates as float64 (x, y, z), every per-point attribute kept.
    """
    fmt = format_of(path)
    return read_ply(path, source_crs) if fmt == "ply" else read_las(path, source_crs)


def write_point_cloud(cloud: PointCloud, path, index: Optional[np.ndarray] = None,
                      ply_text: Optional[bool] = None) -> Path:
    """Write ``cloud`` (or its points at ``index``) in the format given by the suffix of ``path``.

    Parameters
    ----------
    cloud : PointCloud
        The points.
    path : str or path
        The file to write (.las, .laz or .ply), atomically.
    index : ndarray, optional
        The indices of the points to write (default: all).
    ply_text : bool, optional
        PLY only: ASCII instead of binary (default: the source's encoding).

    Returns
    -------
    Path
        The file written.
    """
    fmt = format_of(path)
    if fmt == "ply":
        return write_ply(cloud, path, text=ply_text, index=index)
    return write_las(cloud, path, compress=(fmt == "laz"), index=index)
