"""Solved photogrammetry projects (Metashape, Pix4D, OpenDroneMap/OpenSfM, OPF) and one camera model.

``open_reconstruction(path, chunk=None)`` recognises a Metashape ``.psx``/``.psz``/cameras
``.xml``, a Pix4D ``.p4d``, project folder or ``1_initial/params`` folder, an ODM project
folder, an OpenSfM dataset folder or ``reconstruction.json``, an Open Photogrammetry Format
``project.opf`` (PIX4Dmatic) or its folder, or a folder of photos (or a list of photo paths)
whose EXIF and XMP tags give rough cameras (:func:`open_photos`), and returns a
:class:`Reconstruction`. Pixels: top-left corner origin, centre of the top-left pixel at
(0.5, 0.5). Map coordinates always (x, y) = (easting, northing) / (lon, lat).
"""
from .frame_model import BEHIND, INSIDE, OUTSIDE, Calibration, border_pixels, project_block
from .geodesy import enu_rotation
from .metashape import list_chunks, open_metashape
from .odm import list_reconstructions, open_opensfm
from .model import Camera, Marker, Projection, Reconstruction, Sensor, VisiblePoints
from .opf import open_opf
from .photo_folder import open_photos
from .pix4d import open_pix4d
from .readers import open_reconstruction

__all__ = ["open_reconstruction", "Reconstruction", "Sensor", "Camera", "Marker", "Calibration",
           "Projection", "VisiblePoints", "INSIDE", "BEHIND", "OUTSIDE", "border_pixels",
           "project_block", "enu_rotation", "list_chunks", "open_metashape", "open_pix4d",
           "open_opensfm", "list_reconstructions", "open_opf", "open_photos"]
