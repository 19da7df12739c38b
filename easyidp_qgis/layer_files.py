"""The file behind a layer or an output, found one way: ``QgsProviderRegistry.decodeUri``."""
from qgis.core import QgsProviderRegistry


def uri_file(source: str, provider: str = "ogr") -> str:
    """The file path of a layer source of ``provider`` ('x.gpkg|layername=a', a delimited-text
    'file:///…?delimiter=,' URI, a plain path), or of a Processing output URI
    ('ogr:dbname=…'); '' when there is none (a memory layer)."""
    s = str(source or "")
    if s.startswith("ogr:"):            # a Processing output: 'ogr:dbname='x.gpkg' table=…'
        for part in s[4:].split():
            if part.startswith("dbname="):
                return part[7:].strip("'\"")
        return ""
    return QgsProviderRegistry.instance().decodeUri(provider, s).get("path") or ""


def layer_file(layer) -> str:
    """The file behind a map layer ('' when there is none)."""
    return uri_file(layer.source(), layer.providerType()) if layer is not None else ""


def unreadable_why(alg, path: str) -> str:
    """Why the existing file ``path`` cannot be read as a layer, in words for the user ('' when
    nothing is found wrong): empty, not readable, not JSON (a truncated GeoJSON), not a TIFF,
    or GDAL's own complaint. QGIS says only '… not found' for all of these."""
    import os
    if not os.path.isfile(path):
        return ""
    if not os.access(path, os.R_OK):
        return alg.tr("you may not read it (permissions)")
    if os.path.getsize(path) == 0:
        return alg.tr("it is empty (0 bytes)")
    ext = os.path.splitext(path)[1].lower()
    with open(path, "rb") as fh:
        head = fh.read(4)
    if ext in (".geojson", ".json"):
        import json
        try:
            with open(path, "rb") as fh:
                doc = json.loads(fh.read().decode("utf-8-sig"))
        except UnicodeDecodeError:
            return alg.tr("it is not UTF-8 text, so not GeoJSON")
        except ValueError as exc:
            return alg.tr("it is not valid JSON ({error}); it may be cut short").format(error=exc)
        if not isinstance(doc, dict) or doc.get("type") not in (
                "FeatureCollection", "Feature", "Polygon", "MultiPolygon", "Point", "MultiPoint",
                "LineString", "MultiLineString", "GeometryCollection"):
            return alg.tr("it is JSON but not GeoJSON (no FeatureCollection)")
    if ext in (".tif", ".tiff") and head not in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
        return alg.tr("it is not a TIFF file (it starts with {head!r})").format(head=head)
    from osgeo import gdal
    gdal.PushErrorHandler("CPLQuietErrorHandler")
    try:
        gdal.ErrorReset()
        try:                         # GDAL raises instead of returning None where another
            ds = gdal.OpenEx(path, gdal.OF_VECTOR | gdal.OF_RASTER | gdal.OF_READONLY)
            error = gdal.GetLastErrorMsg()
        except RuntimeError as exc:  # module in this process called UseExceptions
            ds, error = None, str(exc)
    finally:
        gdal.PopErrorHandler()
    if ds is None:
        return alg.tr("GDAL cannot open it ({error})").format(
            error=error or alg.tr("not a format it knows"))
    return ""


def unreadable_inputs_message(alg, parameters, context) -> str:
    """The message for the first input layer given as a file that exists but cannot be read
    ('' when there is none): QGIS's own check says '… not found' for such a file."""
    import os
    for p in alg.parameterDefinitions():
        value = parameters.get(p.name())
        if p.isDestination() or not isinstance(value, str) or not value or \
                p.type() not in ("source", "vector", "raster", "layer", "mesh", "pointcloud"):
            continue
        path = uri_file(value) or value
        if not os.path.isfile(path):
            continue
        why = unreadable_why(alg, path)
        if why:
            return alg.tr("{name}: {path} exists but cannot be read as a layer: {why}. Check "
                          "the file, or save it again from the program that made it.").format(
                              name=p.description(), path=path, why=why)
    return ""
