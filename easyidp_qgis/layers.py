"""Adapters from QGIS layers and parameters to the core's plain data."""
import os

from qgis.core import (QgsCoordinateReferenceSystem, QgsFeatureRequest, QgsProcessingException,
                       QgsWkbTypes)

from ..core.roi import ROISet, roi_from_coordinates


def crs_string(crs: QgsCoordinateReferenceSystem):
    """An EPSG code when QGIS knows one, else WKT; None for an invalid CRS."""
    if crs is None or not crs.isValid():
        return None
    if crs.authid().upper().startswith("EPSG:"):
        return crs.authid()
    return crs.toWkt(QgsCoordinateReferenceSystem.WKT_PREFERRED)


def geotiff_source(layer, label: str) -> str:
    """The GeoTIFF file behind a raster layer; refuses layers that are not a local GeoTIFF."""
    if layer is None:
        raise QgsProcessingException(f"{label}: no raster layer given, or it could not be loaded.")
    path = layer.source().split("|")[0]
    if layer.providerType() != "gdal" or not os.path.isfile(path):
        raise QgsProcessingException(
            f"{label}: layer '{layer.name()}' is not a local raster file ({layer.source()}). "
            "EasyIDP reads GeoTIFF files: save it as GeoTIFF first (Export ▸ Save As…).")
    driver = layer.dataProvider().metadata().get("driver") if hasattr(layer.dataProvider(), "metadata") else None
    with open(path, "rb") as fh:
        magic = fh.read(4)
    if magic not in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
        raise QgsProcessingException(
            f"{label}: {path} is not a GeoTIFF (it is read by GDAL as {driver or 'another format'}). "
            "Convert it to GeoTIFF first (Raster ▸ Conversion ▸ Translate).")
    return path


def rois_from_source(source, name_field: str, label: str, feedback=None):
    """ROIs from a feature source: (ROISet in the layer CRS, list of features in the same order).

    Names come from ``name_field``, else the feature id.
    """
    if source is None:
        raise QgsProcessingException(f"{label}: no ROI layer given, or it could not be loaded.")
    if QgsWkbTypes.geometryType(source.wkbType()) != QgsWkbTypes.PolygonGeometry:
        kind = QgsWkbTypes.geometryDisplayString(QgsWkbTypes.geometryType(source.wkbType()))
        raise QgsProcessingException(
            f"{label}: the ROI layer '{source.sourceName()}' has {kind} geometries; ROIs must be "
            "polygons. Buffer points or lines first (Vector geometry ▸ Buffer).")
    if name_field and source.fields().indexFromName(name_field) < 0:
        raise QgsProcessingException(f"{label}: the ROI layer has no field '{name_field}'.")
    rois, features = [], []
    total = max(source.featureCount(), 1)
    for k, feat in enumerate(source.getFeatures(QgsFeatureRequest())):
        if feedback is not None and feedback.isCanceled():
            break
        g = feat.geometry()
        name = feat[name_field] if name_field else feat.id()
        name = str(feat.id()) if name is None or str(name) == "NULL" else str(name)
        polys = []
        if not g.isNull() and not g.isEmpty():
            polys = g.asMultiPolygon() if g.isMultipart() else [g.asPolygon()]
        coords = [[[(p.x(), p.y()) for p in ring] for ring in poly] for poly in polys]
        rois.append(roi_from_coordinates(name, "MultiPolygon", coords))
        features.append(feat)
        if feedback is not None:
            feedback.setProgress(5.0 * k / total)
    return ROISet(rois, crs_string(source.sourceCrs())), features
