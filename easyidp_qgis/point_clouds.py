"""Point-cloud files: the INPUT / INPUT_CRS parameters the point-cloud tools share."""
import os

from qgis.core import QgsProcessingException, QgsProcessingParameterCrs, QgsProcessingParameterFile

from .compat import ProcessingFileParameterBehavior
from .crs import crs_string
from .parameters import with_help

POINT_CLOUD_FILTER = "Point clouds (*.las *.laz *.ply *.LAS *.LAZ *.PLY);;All files (*.*)"


def add_point_cloud_parameters(alg):
    """INPUT (a .las/.laz/.ply file: no point cloud layers on QGIS without PDAL) and INPUT_CRS."""
    alg.addParameter(QgsProcessingParameterFile(
        alg.INPUT, alg.tr("Point cloud (.las, .laz or .ply)"),
        behavior=ProcessingFileParameterBehavior.File, fileFilter=POINT_CLOUD_FILTER))
    alg.addParameter(with_help(QgsProcessingParameterCrs(
        alg.INPUT_CRS, alg.tr("Point cloud CRS"), optional=True),
        alg.tr("Needed for PLY, and for LAS/LAZ without a CRS; otherwise read from the file (a "
               "CRS given here replaces the file's)")))


def read_point_cloud_parameter(alg, parameters, context, feedback):
    """The INPUT point cloud, read with INPUT_CRS when given (it replaces a LAS file's own CRS)."""
    from ..core.crs import same_crs
    from ..core.pointcloud import read_point_cloud

    path = alg.parameterAsFile(parameters, alg.INPUT, context)
    if not path:
        raise QgsProcessingException("Point cloud: no file given.")
    qcrs = alg.parameterAsCrs(parameters, alg.INPUT_CRS, context)
    cloud = read_point_cloud(path, crs_string(qcrs))
    name = os.path.basename(path)
    if qcrs.isValid() and cloud.file_crs is not None and not same_crs(cloud.file_crs, cloud.crs):
        feedback.pushWarning(f"The point cloud CRS given ({qcrs.authid() or qcrs.description()}) "
                             f"replaces the CRS stored in {name} ({cloud.file_crs.name}).")
    for note in cloud.notes:
        feedback.pushWarning(note)
    crs = cloud.crs.name if cloud.crs is not None else "no CRS"
    feedback.pushInfo(f"{name}: {len(cloud):,} points ({cloud.fmt.upper()}), {crs}.")
    return cloud
