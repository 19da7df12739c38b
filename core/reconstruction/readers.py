"""The project readers ``open_reconstruction`` asks, in order, and the function itself.

Each reader module says whether a path is its (``READER.recognises``); the first reader of
:data:`READERS` that does opens it. The order is the precedence where two could match:

* OpenDroneMap before OPF, photos and Pix4D: an ODM project folder may also hold an ``.opf``,
  photos or anything else; its ``opensfm/`` and ``odm_*`` folders decide.
* OPF before photos: a folder with a ``project.opf`` and the photos beside it is the project.
* Photos before Pix4D: a folder of photos with a stray Pix4D file (``*_offset.xyz``) is the
  photos'; the photo reader itself leaves a folder holding a project file (``.p4d``, ``.psx``,
  ``.psz``, ``.opf``), a ``1_initial`` folder or a ``*_pmatrix.txt`` to the project readers.

Metashape claims only ``.psx``, ``.psz`` and ``.xml`` paths, which no other reader claims.
Adding a reader: a module with its ``READER`` (:class:`~.project_reader.ProjectReader`) and
its line here.
"""
from pathlib import Path
from typing import Tuple

from ..deprecation import renamed_parameters
from ..errors import InputError
from . import metashape, odm, opf, photo_folder, pix4d
from .model import Reconstruction, fit_sensors_to_photos
from .project_reader import OpenOptions, ProjectReader

READERS: Tuple[ProjectReader, ...] = (
    metashape.READER,
    odm.READER,
    opf.READER,
    photo_folder.READER,
    pix4d.READER,
)


def reader_for(path) -> ProjectReader:
    """The first reader of :data:`READERS` that claims ``path`` (a path, or a list of photo
    paths); :class:`~..errors.InputError` naming the path and the kinds accepted if none does."""
    target = path if isinstance(path, (list, tuple)) else Path(path)
    for reader in READERS:
        if reader.claims(target):
            return reader
    raise unrecognised(target)


def unrecognised(p: Path) -> InputError:
    """Why ``p`` is refused: not found, a camera table (not read yet), or no reader's, with what
    each reader accepts."""
    if not p.exists():
        return InputError.of("project_not_found", path=p)
    if p.suffix.lower() == ".csv":
        return InputError(f"{p}: a table of camera positions and angles (Orthority's or "
                          "Metashape's reference CSV) is not read yet; give the folder of photos "
                          "instead: their EXIF and XMP tags give the cameras.")
    kinds = "".join(f"\n- {r.name}: {r.expects}" for r in READERS)
    return InputError(f"{p}: not a photogrammetry project I can read. Give one of these:{kinds}")


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
        (:func:`open_photos`). The readers are asked in the order of
        ``core.reconstruction.readers.READERS``; a path none of them recognises is refused
        with the list of what each accepts.
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
    reader = reader_for(path)
    target = path if isinstance(path, (list, tuple)) else Path(path)
    recon = reader.open(target, OpenOptions(chunk, source_crs, camera_heights, takeoff_height))
    if reader.photo_tags:
        return recon
    if camera_heights != "absolute" or takeoff_height is not None:
        raise InputError(f"{target}: camera heights from the photos' tags (camera_heights, "
                         "takeoff_height) apply to a folder of photos, not to a solved project.")
    return fit_sensors_to_photos(recon)
