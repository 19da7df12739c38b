"""The plugin object QGIS creates: registers the Processing provider (also under qgis_process)."""
import os

from qgis.core import QgsApplication
from qgis.PyQt.QtCore import QCoreApplication, QLocale, QSettings, QTranslator

from .provider import EasyIDPProvider
from .resources import I18N_DIR


class EasyIDPPlugin:
    def __init__(self, iface):
        self.iface = iface  # None under qgis_process
        self.provider = None  # keep a reference: a collected provider loses its algorithms
        self.translator = None
        self._install_translator()

    def _install_translator(self) -> None:
        locale = str(QSettings().value("locale/userLocale", QLocale().name()) or "")
        for name in (locale, locale.split("_")[0]):
            path = os.path.join(I18N_DIR, f"easyidp_{name}.qm")
            if name and os.path.exists(path):
                self.translator = QTranslator()
                if self.translator.load(path):
                    QCoreApplication.installTranslator(self.translator)
                return

    def initProcessing(self):  # noqa: N802 (QGIS API)
        if self.provider is None:
            self.provider = EasyIDPProvider()
            QgsApplication.processingRegistry().addProvider(self.provider)

    def initGui(self):  # noqa: N802 (QGIS API)
        self.initProcessing()

    def unload(self):
        if self.provider is not None:
            QgsApplication.processingRegistry().removeProvider(self.provider)
            self.provider = None
        if self.translator is not None:
            QCoreApplication.removeTranslator(self.translator)
            self.translator = None
