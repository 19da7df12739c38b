"""Memory layers for the QGIS tests (imports QGIS: the QGIS suite only)."""
from qgis.core import QgsFeature, QgsGeometry, QgsVectorLayer


def memory_layer(crs, wkts, name="rois", kind="Polygon"):
    """A memory layer of ``kind`` in ``crs`` with a string field ``name`` and one feature per
    ``(name, WKT)`` of ``wkts``."""
    layer = QgsVectorLayer(f"{kind}?crs={crs}&field=name:string", name, "memory")
    feats = []
    for n, w in wkts:
        f = QgsFeature(layer.fields())
        f.setAttributes([n])
        f.setGeometry(QgsGeometry.fromWkt(w))
        feats.append(f)
    layer.dataProvider().addFeatures(feats)
    return layer
