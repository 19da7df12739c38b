"""Solved photogrammetry projects (Metashape, Pix4D) and one frame camera model.

``open_reconstruction(path, chunk=None)`` recognises a Metashape ``.psx``/``.psz``/cameras
``.xml``, a Pix4D ``.p4d``, project folder or ``1_initial/params`` folder, and returns a
:class:`Reconstruction`. Pixels: top-left corner origin, centre of the top-left pixel at
(0.5, 0.5). Map coordinates always (x, y) = (easting, northing) / (lon, lat).
"""
from pathlib import Path

from ..errors import InputError
from .footprints import Footprint, camera_footprints
from .frame_model import BEHIND, INSIDE, OUTSIDE, Calibration
from .metashape import list_chunks, open_metashape
from .model import Camera, Marker, Projection, Reconstruction, Sensor, VisiblePoints
from .pix4d import open_pix4d

__all__ = ["open_reconstruction", "Reconstruction", "Sensor", "Camera", "Marker", "Calibration",
           "Projection", "VisiblePoints", "INSIDE", "BEHIND", "OUTSIDE", "Footprint",
           "camera_footprints", "list_chunks", "open_metashape", "open_pix4d"]


PIX4D_PARAM_FILES = ("_pmatrix.txt", "_offset.xyz", "_calibrated_camera_parameters.txt",
                     "_calibrated_internal_camera_parameters.cam", "_wkt.prj")


def open_reconstruction(path, chunk=None, crs=None) -> Reconstruction:
    """Open a Metashape or Pix4D project (a .p4d, the project or params folder, or any file of
    the params folder such as ``*_pmatrix.txt``).

    ``chunk``: Metashape chunk id or label (required when the project has several).
    ``crs``: Pix4D only, the output CRS when the project has no ``*_wkt.prj``.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in (".psx", ".psz", ".xml"):
        if crs is not None:
            raise InputError(f"{p}: a Metashape chunk carries its own CRS; do not pass crs=.")
        return open_metashape(p, chunk)
    if suffix == ".p4d" or p.is_dir():
        return open_pix4d(p, crs)
    if p.is_file() and p.name.endswith(PIX4D_PARAM_FILES):  # a file of a params folder
        return open_pix4d(p.parent, crs)
    if not p.exists():
        raise InputError(f"{p}: file not found.")
    raise InputError(f"{p}: not a photogrammetry project I can read. Give a Metashape .psx, "
                     ".psz or cameras .xml, or a Pix4D .p4d, project folder or params folder.")
