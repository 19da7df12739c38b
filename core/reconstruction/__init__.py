"""Solved photogrammetry projects (Metashape, Pix4D, OpenDroneMap/OpenSfM, OPF) and one camera model.

``open_reconstruction(path, chunk=None)`` recognises a Metashape ``.psx``/``.psz``/cameras
``.xml``, a Pix4D ``.p4d``, project folder or ``1_initial/params`` folder, an ODM project
folder, an OpenSfM dataset folder or ``reconstruction.json``, an Open Photogrammetry Format
``project.opf`` (PIX4Dmatic) or its folder, or a folder of photos (or a list of photo paths)
whose EXIF and XMP tags give rough cameras (:func:`open_photos`), and returns a
:class:`Reconstruction`. Pixels: top-left corner origin, centre of the top-left pixel at
(0.5, 0.5). Map coordinates always (x, y) = (easting, northing) / (lon, lat).
"""
from pathlib import Path

from ..deprecation import renamed_parameters
from ..errors import InputError
from .frame_model import BEHIND, INSIDE, OUTSIDE, Calibration, border_pixels, project_block
from .geodesy import enu_rotation
from .metashape import list_chunks, open_metashape
from .odm import is_opensfm_input, list_reconstructions, open_opensfm
from .model import (Camera, Marker, Projection, Reconstruction, Sensor, VisiblePoints,
                    fit_sensors_to_photos)
from .opf import find_project_opf, open_opf
from .photo_folder import is_photo_input, open_photos
from .pix4d import open_pix4d

__all__ = ["open_reconstruction", "Reconstruction", "Sensor", "Camera", "Marker", "Calibration",
           "Projection", "VisiblePoints", "INSIDE", "BEHIND", "OUTSIDE", "border_pixels",
           "project_block", "enu_rotation", "list_chunks", "open_metashape", "open_pix4d",
           "open_opensfm", "list_reconstructions", "open_opf", "open_photos"]


PIX4D_PARAM_FILES = ("_pmatrix.txt", "_offset.xyz", "_calibrated_camera_parameters.txt",
                     "_calibrated_internal_camera_parameters.cam", "_wkt.prj")


@renamed_parameters(crs="source_crs")
def open_reconstruction(path, chunk=None, source_crs=None, *, camera_heights: str = "absolute",
                        takeoff_height=None) -> Reconstruction:
    """Open a Metashape, Pix4D, OpenDroneMap/OpenSfM or OPF project, or a folder of photos.

    Parameters
    ----------
    path : str or path or list of paths
        Metashape: a ``.psx``, ``.psz`` or cameras ``.xml``. Pix4D: a ``.p4d``, the project or
        params folder, or any file of the params folder such as ``*_pmatrix.txt``.
        ODM/OpenSfM: the ODM project folder, the OpenSfM dataset folder or a
        ``reconstruction.json``. OPF: the ``.opf`` file or the folder that holds it (needs
        pyopf). Photos: a folder of JPEG/TIFF photos with no project file in it, or a list of
        photo paths: one rough camera per photo from its EXIF and XMP tags
        (:func:`open_photos`).
    chunk : str or int, optional
        Metashape: the chunk id or label (required when the project has several). OpenSfM: the
        reconstruction index (default the largest).
    source_crs : CRS, optional
        The project's CRS where it has none usable: Pix4D, the output CRS when the project has
        no ``*_wkt.prj`` (or one PROJ cannot use); OpenSfM, the map CRS when ODM did not
        georeference the project; OPF, the CRS when the scene reference frame's is not usable;
        Metashape, the chunk CRS when its ``<reference>`` is neither usable nor an EPSG CRS;
        photos, the map CRS (default the photos' UTM zone). A CRS that contradicts the
        project's is refused.
    camera_heights : {"absolute", "relative"}, optional
        Photos only: where the camera heights come from, as :func:`open_photos` says.
    takeoff_height : float, optional
        Photos only: the take-off height (m) added to relative altitudes.

    Returns
    -------
    Reconstruction
        The sensors, the cameras and the project CRS.
    """
    photo_kw = dict(camera_heights=camera_heights, takeoff_height=takeoff_height)
    if isinstance(path, (list, tuple)):
        return open_photos(path, source_crs, **photo_kw)
    p = Path(path)
    suffix = p.suffix.lower()
    recon = None
    if suffix in (".psx", ".psz", ".xml"):
        recon = open_metashape(p, chunk, source_crs)
    elif is_opensfm_input(p):
        recon = open_opensfm(p, chunk, source_crs)
    elif suffix == ".opf" or (p.is_dir() and find_project_opf(p) is not None):
        recon = open_opf(p, source_crs)
    elif is_photo_input(p):
        return open_photos(p, source_crs, **photo_kw)
    elif suffix == ".p4d" or p.is_dir():
        recon = open_pix4d(p, source_crs)
    elif p.is_file() and p.name.endswith(PIX4D_PARAM_FILES):  # a file of a params folder
        recon = open_pix4d(p.parent, source_crs)
    if recon is not None and (camera_heights != "absolute" or takeoff_height is not None):
        raise InputError(f"{p}: camera heights from the photos' tags (camera_heights, "
                         "takeoff_height) apply to a folder of photos, not to a solved project.")
    if recon is not None:
        return fit_sensors_to_photos(recon)
    if not p.exists():
        raise InputError.of("project_not_found", path=p)
    if suffix == ".csv":
        raise InputError(f"{p}: a table of camera positions and angles (Orthority's or Metashape's "
                         "reference CSV) is not read yet; give the folder of photos instead: "
                         "their EXIF and XMP tags give the cameras.")
    raise InputError(f"{p}: not a photogrammetry project I can read. Give a Metashape .psx, "
                     ".psz or cameras .xml, a Pix4D .p4d, project folder or params folder, an "
                     "OpenDroneMap project folder or OpenSfM reconstruction.json, an OPF "
                     "project.opf (PIX4Dmatic), or a folder of drone photos.")
