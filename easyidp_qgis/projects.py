"""Photogrammetry projects: the PROJECT / CHUNK / PROJECT_CRS parameters the tools share."""
from qgis.core import (QgsProcessingException, QgsProcessingParameterCrs,
                       QgsProcessingParameterEnum, QgsProcessingParameterFile,
                       QgsProcessingParameterNumber, QgsProcessingParameterString)

from .compat import (ProcessingFileParameterBehavior, ProcessingNumberParameterType,
                     ProcessingParameterFlag)
from .crs import crs_string
from .parameters import with_help
from .rasters import dsm_parameter

CAMERA_HEIGHTS = "CAMERA_HEIGHTS"
TAKEOFF_HEIGHT = "TAKEOFF_HEIGHT"
"""CAMERA_HEIGHTS choices (a folder of photos): 0 the tags' altitude, 1 relative altitude +
TAKEOFF_HEIGHT, 2 relative altitude + the DSM under the first photo."""

PROJECT_HELP = ("Metashape .psx/.psz or cameras .xml; Pix4D .p4d, project folder or any file of "
                "its 1_initial/params folder; OpenDroneMap project folder or its "
                "opensfm/reconstruction.json; OPF project.opf (PIX4Dmatic); or a folder of drone "
                "photos (cameras from their EXIF and XMP tags)")


def add_project_parameters(alg):
    """PROJECT (a file or a folder: no file filter, so folders are accepted too; a folder of
    photos gives cameras from their tags), CHUNK and PROJECT_CRS (advanced)."""
    alg.addParameter(with_help(QgsProcessingParameterFile(
        alg.PROJECT, alg.tr("Photogrammetry project or folder of photos"),
        behavior=ProcessingFileParameterBehavior.File),
        alg.tr("Metashape .psx/.psz/.xml; Pix4D .p4d, project or params folder; OpenDroneMap "
               "folder or reconstruction.json; OPF project.opf; or a folder of drone photos "
               "(cameras from their EXIF/XMP tags: rough, see the log's uncertainty)")))
    alg.addParameter(with_help(QgsProcessingParameterString(
        alg.CHUNK, alg.tr("Chunk or reconstruction"), optional=True),
        alg.tr("Metashape chunk (label or index) or OpenSfM reconstruction index: needed when "
               "the project has several")))
    p = with_help(QgsProcessingParameterCrs(
        alg.PROJECT_CRS, alg.tr("Project CRS (override)"), optional=True),
        alg.tr("For Pix4D without a *_wkt.prj file, OpenSfM without OpenDroneMap, or a Metashape "
               "chunk CRS that PROJ cannot use; for a folder of photos, default: their UTM zone"))
    p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
    alg.addParameter(p)
    p = QgsProcessingParameterEnum(
        CAMERA_HEIGHTS, alg.tr("Camera heights (a folder of photos)"),
        [alg.tr("Altitude in the tags (GNSS; RTK: ellipsoidal)"),
         alg.tr("Relative altitude + the take-off height below"),
         alg.tr("Relative altitude + the DSM under the first photo")], defaultValue=0,
        optional=True)          # optional: models saved before it stay valid
    p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
    alg.addParameter(p)
    p = QgsProcessingParameterNumber(
        TAKEOFF_HEIGHT, alg.tr("Take-off height (m; a folder of photos)"),
        ProcessingNumberParameterType.Double, optional=True)
    p.setHelp(alg.tr("In the DSM's vertical reference: added to the photos' relative altitude"))
    p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
    alg.addParameter(p)


def open_project_parameter(alg, parameters, context, feedback, need_crs: bool = True):
    """The Reconstruction of PROJECT/CHUNK/PROJECT_CRS, its summary and notes in the log, and
    its unaligned cameras named. ``need_crs``: refuse a project whose CRS is unknown."""
    from ..core.reconstruction import open_reconstruction

    path = alg.parameterAsFile(parameters, alg.PROJECT, context)
    if not path:
        raise QgsProcessingException(alg.tr("Photogrammetry project: none given ({what}).").format(
            what=PROJECT_HELP))
    chunk = alg.parameterAsString(parameters, alg.CHUNK, context) or None
    pcrs = alg.parameterAsCrs(parameters, alg.PROJECT_CRS, context)
    recon = open_reconstruction(path, chunk, crs_string(pcrs) if pcrs.isValid() else None,
                                **_camera_heights(alg, parameters, context))
    feedback.pushInfo(recon.summary())
    for note in recon.notes:
        feedback.pushWarning(note)
    if need_crs and recon.crs is None:
        raise QgsProcessingException(alg.tr(
            "{path}: the project's CRS is unknown (a Pix4D project without *_wkt.prj, or an "
            "OpenSfM dataset without GPS): set 'Project CRS'.").format(path=path))
    if recon.unaligned_cameras:
        names = [c.label for c in recon.unaligned_cameras]
        feedback.pushWarning(alg.tr("{n} camera(s) are not aligned and have no pose: {names}").format(
            n=len(names), names=", ".join(names[:20]) + (" …" if len(names) > 20 else "")))
    return recon


def _camera_heights(alg, parameters, context) -> dict:
    """CAMERA_HEIGHTS / TAKEOFF_HEIGHT as ``open_reconstruction``'s keywords (none when the
    tags' altitude is chosen, so solved projects are opened as before)."""
    choice = alg.parameterAsEnum(parameters, CAMERA_HEIGHTS, context) \
        if alg.parameterDefinition(CAMERA_HEIGHTS) is not None else 0
    if choice == 0:
        return {}
    if choice == 1:
        if parameters.get(TAKEOFF_HEIGHT) is None:
            raise QgsProcessingException(alg.tr(
                "Camera heights from the relative altitude need the take-off height: set "
                "'Take-off height'."))
        return dict(camera_heights="relative",
                    takeoff_height=alg.parameterAsDouble(parameters, TAKEOFF_HEIGHT, context))
    dsm = dsm_parameter(alg, parameters, context) if alg.parameterDefinition("DSM") else None
    if dsm is None:
        raise QgsProcessingException(alg.tr(
            "Camera heights from the DSM under the first photo need a DSM: set 'DSM', or give "
            "the take-off height."))
    return dict(camera_heights="relative", takeoff_height=dsm)
