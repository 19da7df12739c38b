"""ROI layers as the core's ROISet: the ROIS / NAME_FIELD parameters the tools share."""
from qgis.core import (QgsCoordinateTransform, QgsCsException, QgsFeatureRequest, QgsGeometry,
                       QgsProcessingException, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProject, QgsWkbTypes)

from ..core.roi import roi_from_coordinates, rois_from_wkb
from .compat import GeometryType, ProcessingSourceType, WkbType
from .crs import crs_string, has_crs
from .geometries import polygon_coordinates
from .progress import feedback_progress
from .values import is_null

PLAIN_POLYGONS = (WkbType.Polygon, WkbType.MultiPolygon)
"""The flat geometry types read from their WKB in one pass by the core (curves: by QGIS)."""


def add_roi_parameters(alg, name_field: bool = True):
    """ROIS (a polygon layer) and, with ``name_field``, NAME_FIELD (names files and records)."""
    alg.addParameter(QgsProcessingParameterFeatureSource(
        alg.ROIS, alg.tr("ROIs (polygons)"), [ProcessingSourceType.VectorPolygon]))
    if name_field:
        alg.addParameter(QgsProcessingParameterField(
            alg.NAME_FIELD, alg.tr("Name field (default: feature id)"),
            parentLayerParameterName=alg.ROIS, optional=True))


def rois_from_source(source, name_field: str, label: str, feedback=None, crs=None, context=None):
    """ROIs from a feature source: (ROISet, list of the features, untouched, in the same order).

    Names come from ``name_field``, else the feature id. With ``crs`` (a
    QgsCoordinateReferenceSystem) the ROIs are transformed by QGIS into it, with the transform
    context of ``context`` (the project's datum transformation choices, as QGIS's own tools
    and ``QgsFeatureRequest.setDestinationCrs`` do); otherwise they stay in the layer's CRS. A Z
    coordinate is kept as the ROI's vertex heights.
    """
    if source is None:
        raise QgsProcessingException(f"{label}: no ROI layer given, or it could not be loaded.")
    if QgsWkbTypes.geometryType(source.wkbType()) != GeometryType.Polygon:
        kind = QgsWkbTypes.geometryDisplayString(QgsWkbTypes.geometryType(source.wkbType()))
        raise QgsProcessingException(
            f"{label}: the ROI layer '{source.sourceName()}' has {kind} geometries; ROIs must be "
            "polygons. Buffer points or lines first (Vector geometry ▸ Buffer).")
    if name_field and source.fields().indexFromName(name_field) < 0:
        raise QgsProcessingException(f"{label}: the ROI layer has no field '{name_field}'.")
    transform, out_crs = None, source.sourceCrs()
    if crs is not None and crs.isValid() and crs != source.sourceCrs():
        if not has_crs(source.sourceCrs()):
            raise QgsProcessingException(
                f"{label}: the ROI layer '{source.sourceName()}' has no CRS"
                f"{_undefined(source.sourceCrs())}, so it cannot be "
                f"placed on {crs.authid() or crs.description()}. Set the layer's CRS (Layer "
                "Properties ▸ Source, or Vector general ▸ Assign projection) and run again.")
        # QGIS's own transformation, with the project's datum transformation choices
        transform = QgsCoordinateTransform(source.sourceCrs(), crs, context.transformContext()
                                           if context is not None else
                                           QgsProject.instance().transformContext())
        out_crs = crs
    names, blobs, others, features = [], [], {}, []
    flat_type = QgsWkbTypes.flatType
    total = max(source.featureCount(), 1)
    progress = feedback_progress(feedback, 0, 5) if feedback is not None else None
    for k, feat in enumerate(source.getFeatures(QgsFeatureRequest())):
        if feedback is not None and feedback.isCanceled():
            break
        if name_field:
            name = feat[name_field]
            name = str(feat.id()) if is_null(name) else str(name)
        else:
            name = str(feat.id())
        geom = feat.geometry()
        if transform is not None and not geom.isNull():
            geom = QgsGeometry(geom)
            try:
                geom.transform(transform)
            except QgsCsException as exc:
                raise QgsProcessingException(
                    f"{label}: ROI '{name}' of the layer '{source.sourceName()}' cannot be "
                    f"transformed from {source.sourceCrs().authid() or source.sourceCrs().description()}"
                    f" to {crs.authid() or crs.description()} ({exc}). Check that the layer's CRS "
                    "is set correctly.") from None
        names.append(name)
        if geom.isNull():
            blobs.append(None)
        elif flat_type(geom.wkbType()) in PLAIN_POLYGONS:        # all at once, below
            blobs.append(bytes(geom.asWkb()))
        else:                                           # curves: QGIS's own vertices
            blobs.append(None)
            others[k] = roi_from_coordinates(name, "MultiPolygon", polygon_coordinates(geom))
        features.append(feat)
        if feedback is not None and k % 1000 == 0:
            progress.set(100.0 * k / total)
    rois = rois_from_wkb(names, blobs, crs_string(out_crs))
    for k, roi in others.items():
        rois.rois[k] = roi
    return rois, features



def _undefined(crs) -> str:
    """' (its GeoPackage says "Undefined geographic SRS")' when the CRS is one of those."""
    return f" (its GeoPackage says \"{crs.description()}\")" if crs.isValid() else ""


def rois_parameter(alg, parameters, context, feedback, crs=None):
    """The ROIs of a tool's ``ROIS`` parameter, named by its ``NAME_FIELD`` when the tool has
    one: (source, ROISet, features), as :func:`rois_from_source`; with ``crs`` they are
    transformed into it with the project's transform context."""
    source = alg.parameterAsSource(parameters, alg.ROIS, context)
    name_field = alg.parameterAsString(parameters, alg.NAME_FIELD, context) \
        if hasattr(alg, "NAME_FIELD") else ""
    rois, features = rois_from_source(source, name_field, alg.tr("ROIs"), feedback, crs, context)
    return source, rois, features
