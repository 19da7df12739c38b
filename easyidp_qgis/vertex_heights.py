"""The heights of the ROI vertices in the backward-projection tools: the HEIGHT_SOURCE, DSM,
HEIGHT_FIELD and GROUND_HEIGHT parameters, and the core height source they choose."""
from qgis.core import (QgsProcessingException, QgsProcessingParameterEnum,
                       QgsProcessingParameterField, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer)

from .compat import ProcessingFieldParameterDataType, ProcessingNumberParameterType
from .parameters import optional_number

HEIGHT_Z, HEIGHT_DSM, HEIGHT_FIELD, HEIGHT_CONSTANT = range(4)


def add_height_parameters(alg):
    """HEIGHT_SOURCE, DSM (vertex heights and the occlusion test), HEIGHT_FIELD, GROUND_HEIGHT."""
    alg.addParameter(QgsProcessingParameterEnum(
        alg.HEIGHT_SOURCE, alg.tr("Heights of the ROI vertices"),
        [alg.tr("Geometry Z (3-D polygons)"), alg.tr("DSM, sampled at every vertex"),
         alg.tr("Attribute (one height per ROI)"), alg.tr("Constant ground height")],
        defaultValue=HEIGHT_DSM))
    alg.addParameter(QgsProcessingParameterRasterLayer(
        alg.DSM, alg.tr("DSM (GeoTIFF): vertex heights and occlusion test"), optional=True))
    alg.addParameter(QgsProcessingParameterField(
        alg.HEIGHT_FIELD, alg.tr("Height attribute"), parentLayerParameterName=alg.ROIS,
        type=ProcessingFieldParameterDataType.Numeric, optional=True))
    alg.addParameter(alg.decimals(QgsProcessingParameterNumber(
        alg.GROUND_HEIGHT, alg.tr("Constant ground height (project vertical reference)"),
        ProcessingNumberParameterType.Double, optional=True), 3))


def height_source_parameter(alg, parameters, context, features, dsm):
    """The core height source chosen by HEIGHT_SOURCE (``features``: the ROI features, for an
    attribute; ``dsm``: from :func:`dsm_parameter`)."""
    from ..core.projection import ConstantHeight, GeometryZ, PerROIHeights
    kind = alg.parameterAsEnum(parameters, alg.HEIGHT_SOURCE, context)
    if kind == HEIGHT_Z:
        return GeometryZ()
    if kind == HEIGHT_DSM:
        if dsm is None:
            raise QgsProcessingException(alg.tr(
                "Heights from the DSM: choose the DSM raster, or another height source."))
        return dsm
    if kind == HEIGHT_FIELD:
        field = alg.parameterAsString(parameters, alg.HEIGHT_FIELD, context)
        if not field:
            raise QgsProcessingException(alg.tr(
                "Heights from an attribute: choose the height attribute of the ROI layer."))
        return PerROIHeights([f[field] for f in features])
    h = optional_number(alg, parameters, alg.GROUND_HEIGHT, context)
    if h is None:
        raise QgsProcessingException(alg.tr(
            "Constant ground height: give the height, or choose another height source."))
    return ConstantHeight(h)
