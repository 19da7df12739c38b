"""Feature sinks the tools write: the "ROI fields plus extra fields" layers, the index layer of
the tools that write one file per ROI, closing a sink before anything opens its file, and a
sink output written as a GeoPackage by the engine (:func:`geopackage_file`)."""
import os

from qgis.core import (QgsFeature, QgsField, QgsFields, QgsProcessingException,
                       QgsProcessingParameterFeatureSink, QgsProcessingUtils)

from .compat import FeatureSinkFlag, FieldType, ProcessingSourceType


def close_sink(sink) -> None:
    """Finish a sink of ``parameterAsSink`` and close its file now, before anything opens the
    output: QGIS >= 3.42 ``finalize()`` (it flushes and reports write errors), else
    ``flushBuffer()``; then the writer is destroyed here rather than whenever Python collects
    it. A GeoPackage opened while its writer is still open costs SQLite's lock wait ('database
    is locked', seconds per open) or reads as an empty file ('not recognized as a supported
    file format'). The sink must not be used afterwards."""
    from qgis.PyQt import sip
    finalize = getattr(sink, "finalize", None)
    if finalize is not None:
        finalize()
    else:
        sink.flushBuffer()
    if sip.ispyowned(sink):
        sip.delete(sink)


def fields_of(spec) -> QgsFields:
    """QgsFields from ``[(name, compat.FieldType member)]``."""
    fields = QgsFields()
    for name, kind in spec:
        fields.append(QgsField(name, kind))
    return fields


GPKG_TYPES = {FieldType.QString: "TEXT", FieldType.Int: "MEDIUMINT", FieldType.Double: "REAL",
              FieldType.Bool: "BOOLEAN", FieldType.LongLong: "INTEGER"}
"""The GeoPackage column type QGIS's writer (GDAL) gives each field type (``core.gpkg``)."""


def geopackage_file(alg, parameters, name: str, context):
    """The file of the sink output ``name`` when it is a new GeoPackage file (an absolute path
    ending in ``.gpkg``, not a layer added to an existing GeoPackage, not a temporary layer),
    which the engine writes (``core.gpkg.write_geopackage``: atomically, in one pass, without
    QgsFeatures) instead of a feature sink; QGIS is told to load it on completion as it would
    a sink's output (``parameterAsOutputLayer``). None otherwise: write a sink."""
    from .outputs import scratch_context
    dest = alg.parameterAsOutputLayer(parameters, name, scratch_context(context))
    if not (isinstance(dest, str) and dest.lower().endswith(".gpkg") and os.path.isabs(dest)
            and "|" not in dest):
        return None
    return alg.parameterAsOutputLayer(parameters, name, context)


def gpkg_fields(spec) -> list:
    """``[(name, GeoPackage type)]`` of ``[(name, compat.FieldType member)]`` (as QGIS's writer
    types them, :data:`GPKG_TYPES`)."""
    return [(n, GPKG_TYPES[kind]) for n, kind in spec]


BATCH = 10000
"""Features handed to a sink per ``addFeatures`` call (one call per feature cost more Python
overhead; the file writer already holds one transaction for the whole layer)."""


def write_features(alg, parameters, name: str, context, fields: QgsFields, wkb_type, crs, rows,
                   optional: bool = False):
    """Write the sink output ``name``: one feature per ``(attributes, geometry or None)`` of
    ``rows``. Returns the destination id; when the sink cannot be made, None if ``optional``,
    else QgsProcessingException."""
    sink, dest = alg.parameterAsSink(parameters, name, context, fields, wkb_type, crs)
    if sink is None:
        if optional:
            return None
        raise QgsProcessingException(alg.invalidSinkError(parameters, name))
    batch = []
    for attributes, geometry in rows:
        f = QgsFeature(fields)
        f.setAttributes(attributes if type(attributes) is list else list(attributes))
        if geometry is not None:
            f.setGeometry(geometry)
        batch.append(f)
        if len(batch) == BATCH:
            sink.addFeatures(batch, FeatureSinkFlag.FastInsert)
            batch = []
    if batch:
        sink.addFeatures(batch, FeatureSinkFlag.FastInsert)
    close_sink(sink)
    return dest


def write_roi_layer(alg, parameters, name: str, context, source, rows, extra, *,
                    replace: bool = False, wkb_type=None, optional: bool = False):
    """Write the sink output ``name`` as the ROI layer ``source`` plus the ``extra`` fields
    ``[(name, compat.FieldType member)]``: one feature per row ``(ROI feature, values[,
    geometry])``, with the ROI's attributes, then ``values``, and the ROI's geometry unless the
    row gives one. ``replace``: the ROI fields named like an extra field (any case) are left
    out, else QGIS renames the extra one (``combineFields``). ``wkb_type``: default the ROI
    layer's. Returns the destination id (``optional``: see :func:`write_features`)."""
    more = fields_of(extra)
    if replace:
        names = {n.lower() for n, _ in extra}
        kept = [i for i, f in enumerate(source.fields()) if f.name().lower() not in names]
        fields = QgsFields()
        for i in kept:
            fields.append(source.fields().at(i))
        for f in more:
            fields.append(f)
    else:
        kept = None
        fields = QgsProcessingUtils.combineFields(source.fields(), more)

    def features():
        for feat, values, *geometry in rows:
            attrs = feat.attributes()
            attrs = attrs if kept is None else [attrs[i] for i in kept]
            yield list(attrs) + list(values), (geometry[0] if geometry else feat.geometry())
    return write_features(alg, parameters, name, context, fields,
                          source.wkbType() if wkb_type is None else wkb_type,
                          source.sourceCrs(), features(), optional)


# ---- the index layer of a tool that writes one file per ROI ------------------------------------

def add_index_parameter(alg, description: str):
    """OUTPUT_INDEX (optional, made by default): the ROIs with the file written for each. Loading
    it is the user's choice of loading the files too (see presentation.load_project)."""
    alg.addParameter(QgsProcessingParameterFeatureSink(
        alg.OUTPUT_INDEX, description, ProcessingSourceType.VectorPolygon, optional=True,
        createByDefault=True))


def write_index(alg, parameters, context, source, rows, extra):
    """Write OUTPUT_INDEX when it is asked for (:func:`write_roi_layer`). Returns the
    destination id, or None when the output is skipped."""
    if parameters.get(alg.OUTPUT_INDEX) in (None, ""):
        return None
    return write_roi_layer(alg, parameters, alg.OUTPUT_INDEX, context, source, rows, extra,
                           optional=True)
