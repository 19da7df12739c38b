"""The EasyIDP Processing provider (id ``easyidp``)."""
from qgis.core import QgsProcessingProvider
from qgis.PyQt.QtCore import QCoreApplication
from qgis.PyQt.QtGui import QIcon

from .algorithms import ALGORITHMS
from .resources import ICON



class EasyIDPProvider(QgsProcessingProvider):
    def id(self):
        return "easyidp"

    def name(self):
        return "EasyIDP"

    def longName(self):  # noqa: N802 (QGIS API)
        return QCoreApplication.translate("EasyIDP", "EasyIDP: drone photogrammetry ROIs")

    def icon(self):
        return QIcon(ICON)

    def svgIconPath(self):  # noqa: N802 (QGIS API)
        return ICON

    def loadAlgorithms(self):  # noqa: N802 (QGIS API)
        for cls in ALGORITHMS:
            self.addAlgorithm(cls())
