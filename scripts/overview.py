"""Render an overview PNG of demo results with QGIS itself (offscreen map rendering).

Usage: python -m easyidp_toolbox.scripts.overview OUT.png RASTER [VECTOR ...]
The first layer is the background raster; vectors are drawn as outlines in distinct colours.
"""
import os
import sys
from typing import Sequence

COLOURS = ["#ffdd00", "#ff3b30", "#00c2ff", "#ff00ff"]


def render_overview(png: str, raster: str, vectors: Sequence[str], width: int = 1600) -> str:
    """Draw ``raster`` with ``vectors`` on top (outlines) into ``png``; returns the path.

    Starts (and exits) a QgsApplication when none is running.
    """
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from qgis.core import QgsApplication

    app = QgsApplication.instance()
    if app is not None:
        return _render(png, raster, vectors, width)
    app = QgsApplication([], False)
    app.initQgis()
    try:
        return _render(png, raster, vectors, width)  # its layers are gone before exitQgis
    finally:
        app.exitQgis()


def _render(png: str, raster: str, vectors: Sequence[str], width: int) -> str:
    from qgis.core import (QgsFillSymbol, QgsMapRendererParallelJob, QgsMapSettings,
                           QgsRasterLayer, QgsRectangle, QgsVectorLayer)
    from qgis.PyQt.QtCore import QSize
    from qgis.PyQt.QtGui import QColor

    layers = []
    for k, path in enumerate(vectors):
        v = QgsVectorLayer(path, os.path.splitext(os.path.basename(path))[0], "ogr")
        if not v.isValid():
            raise RuntimeError(f"cannot open {path} for the overview")
        v.renderer().setSymbol(QgsFillSymbol.createSimple({
            "color": "0,0,0,0", "outline_color": COLOURS[k % len(COLOURS)],
            "outline_width": "0.5" if k == 0 else "0.3"}))
        layers.append(v)
    r = QgsRasterLayer(raster, "background")
    if not r.isValid():
        raise RuntimeError(f"cannot open {raster} for the overview")
    extent = QgsRectangle(r.extent())
    settings = QgsMapSettings()
    settings.setLayers(layers[::-1] + [r])   # the first vector on top
    settings.setDestinationCrs(r.crs())
    for v in layers:
        extent.combineExtentWith(settings.layerExtentToOutputExtent(v, v.extent()))
    extent.scale(1.05)
    settings.setBackgroundColor(QColor("white"))
    height = int(width * extent.height() / max(extent.width(), 1e-9))
    settings.setOutputSize(QSize(width, max(height, 1)))
    settings.setExtent(extent)
    job = QgsMapRendererParallelJob(settings)
    job.start()
    job.waitForFinished()
    if not job.renderedImage().save(png, "PNG"):
        raise RuntimeError(f"cannot write {png}")
    return png


if __name__ == "__main__":
    print(render_overview(sys.argv[1], sys.argv[2], sys.argv[3:]))
