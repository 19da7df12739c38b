"""The photo viewer's helpers off the GUI and on the map: photos decoded in a background task
(QgsTask), and the map tool that picks a point (``photo_viewer.PhotoViewer`` uses both)."""
from qgis.core import QgsTask
from qgis.gui import QgsMapToolEmitPoint
from qgis.PyQt.QtCore import QSize, pyqtSignal
from qgis.PyQt.QtGui import QImage, QImageReader

from .compat import TaskFlag


def read_image(path: str, longest: int = 0) -> QImage:
    """The photo at ``path`` as a QImage (null when it cannot be read), decoded at most
    ``longest`` pixels on its longer side (0: full resolution; JPEG decodes at a reduced scale,
    which is what makes thumbnails fast)."""
    reader = QImageReader(path)
    reader.setAutoTransform(False)           # pixels as the camera model counts them
    size = reader.size()
    if longest and size.isValid() and max(size.width(), size.height()) > longest:
        scale = longest / max(size.width(), size.height())
        reader.setScaledSize(QSize(max(1, round(size.width() * scale)),
                                   max(1, round(size.height() * scale))))
    image = reader.read()
    return image if not image.isNull() else QImage()


class DecodeTask(QgsTask):
    """Decodes ``paths`` in the background, in order, each at most ``longest`` pixels (0: full
    size); ``decoded(key, index, QImage)`` is emitted for each (a null image for a photo that
    cannot be read). Cancelled (a new query): it stops before the next photo. ``key`` tells
    the receiver which query the images belong to."""

    decoded = pyqtSignal(int, int, QImage)

    def __init__(self, description: str, key: int, paths, longest: int = 0):
        super().__init__(description, TaskFlag.CanCancel)
        self.key, self.paths, self.longest = key, list(paths), int(longest)

    def run(self):  # noqa: D102 (QgsTask API, a worker thread)
        for k, path in enumerate(self.paths):
            if self.isCanceled():
                return False
            self.decoded.emit(self.key, k, read_image(path, self.longest) if path else QImage())
            self.setProgress(100.0 * (k + 1) / max(len(self.paths), 1))
        return True


class PointTool(QgsMapToolEmitPoint):
    """A map tool that emits ``picked(QgsPointXY)`` (map canvas CRS) on a left click."""

    picked = pyqtSignal(object)

    def __init__(self, canvas):
        super().__init__(canvas)
        self.canvasClicked.connect(lambda point, button: self.picked.emit(point))
