"""Photo-pixel layers (x = column, y = −row), e.g. the OUTPUT of *Back-project ROIs*, read back
as the core's back-projection or photo annotations."""
from qgis.core import QgsProcessingException, QgsWkbTypes

from .compat import GeometryType
from .geometries import pixel_polygons
from .values import is_null


def backprojection_from_layer(layer, label: str, roi_names, recon, feedback=None):
    """A core ``BackProjection`` from the photo-pixel layer of *Back-project ROIs* (its OUTPUT):
    fields ``roi`` and ``photo`` (and its others when present); photo sizes and paths from the
    layer, else from the project ``recon``."""
    from ..core.projection import BackProjection
    names = layer.fields().names()
    for need in ("roi", "photo"):
        if need not in names:
            raise QgsProcessingException(
                f"{label}: the layer '{layer.sourceName()}' has no field '{need}'. Give the "
                "photo-pixel layer (OUTPUT) of Back-project ROIs.")
    records, photos = [], {}
    for feat in layer.getFeatures():
        if feedback is not None and feedback.isCanceled():
            break
        rec = {k: None if is_null(feat[k]) else feat[k] for k in names}
        rec["roi"], rec["photo"] = str(rec["roi"]), str(rec["photo"])
        rec["polygons"] = pixel_polygons(feat.geometry())
        if not rec["polygons"]:
            continue
        records.append(rec)
        if rec["photo"] not in photos:
            try:
                cam = recon.camera(rec["photo"])
            except Exception:
                raise QgsProcessingException(
                    f"{label}: photo '{rec['photo']}' is not a camera of the project "
                    f"{recon.source}: give the project the back-projection was made with.") from None
            sensor = recon.sensors[cam.sensor_id]
            cal = sensor.calibration
            photos[rec["photo"]] = {
                "path": rec.get("photo_path") or cam.photo_path,
                "width": int(rec.get("photo_width") or sensor.width),
                "height": int(rec.get("photo_height") or sensor.height),
                "principal_point": (cal.cx, cal.cy) if cal is not None else None}
    return BackProjection.from_records(list(roi_names), records, photos)


def photo_layer_annotations(source, feedback=None):
    """PhotoAnnotations per photo from a photo-pixel layer (x = column, y = −row), e.g. the one
    *Back-project ROIs* writes: fields ``photo`` (required), ``roi`` or ``label``, ``score``."""
    from ..core.annotations import POLYGON, PhotoAnnotations, PhotoShape
    names = source.fields().names()
    if "photo" not in names:
        raise QgsProcessingException(
            f"Photo-pixel layer '{source.sourceName()}': it has no 'photo' field naming the photo "
            "of each polygon (as Back-project ROIs writes).")
    if QgsWkbTypes.geometryType(source.wkbType()) != GeometryType.Polygon:
        raise QgsProcessingException(
            f"Photo-pixel layer '{source.sourceName()}': polygons are needed.")
    label_field = "roi" if "roi" in names else ("label" if "label" in names else None)
    by_photo = {}
    for feat in source.getFeatures():
        if feedback is not None and feedback.isCanceled():
            break
        g = feat.geometry()
        if g is None or g.isEmpty():
            continue
        label = str(feat[label_field]) if label_field else str(feat.id())
        score = feat["score"] if "score" in names else None
        try:
            score = None if is_null(score) else float(score)
        except (TypeError, ValueError):
            score = None
        for px in pixel_polygons(g):
            photo = str(feat["photo"])
            ann = by_photo.setdefault(photo, PhotoAnnotations(source.sourceName(), photo, None,
                                                              None, []))
            ann.shapes.append(PhotoShape(label, POLYGON, px, "layer", score, feat.id()))
    return list(by_photo.values())
