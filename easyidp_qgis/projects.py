"""Photogrammetry projects: the PROJECT / CHUNK / PROJECT_CRS parameters the tools share."""
from qgis.core import (QgsProcessingException, QgsProcessingParameterCrs,
                       QgsProcessingParameterFile, QgsProcessingParameterString)

from .compat import ProcessingFileParameterBehavior, ProcessingParameterFlag
from .crs import crs_string

PROJECT_HELP = ("Metashape .psx/.psz or cameras .xml; Pix4D .p4d, project folder or any file of "
                "its 1_initial/params folder; OpenDroneMap project folder or its "
                "opensfm/reconstruction.json; OPF project.opf (PIX4Dmatic); or a folder of drone "
                "photos (cameras from their EXIF and XMP tags)")


def add_project_parameters(alg):
    """PROJECT (a file or a folder: no file filter, so folders are accepted too; a folder of
    photos gives cameras from their tags), CHUNK and PROJECT_CRS (advanced)."""
    alg.addParameter(QgsProcessingParameterFile(
        alg.PROJECT, alg.tr("Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d, "
                            "project or params folder; OpenDroneMap folder or reconstruction.json) "
                            "or a folder of drone photos"),
        behavior=ProcessingFileParameterBehavior.File))
    alg.addParameter(QgsProcessingParameterString(
        alg.CHUNK, alg.tr("Chunk: Metashape chunk (label or index) or OpenSfM reconstruction index "
                          "(needed when there are several)"), optional=True))
    p = QgsProcessingParameterCrs(
        alg.PROJECT_CRS, alg.tr("Project CRS (Pix4D without a *_wkt.prj file; OpenSfM without "
                                "OpenDroneMap; Metashape chunk CRS that PROJ cannot use; photos: "
                                "default their UTM zone)"),
        optional=True)
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
    recon = open_reconstruction(path, chunk, crs_string(pcrs) if pcrs.isValid() else None)
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
