"""The plugin object QGIS creates: registers the Processing provider (also under qgis_process).

Its Python packages come from a folder in the QGIS profile, put on ``sys.path`` first of all
(``dependencies.activate``). In the desktop, a missing package is offered for installation in the
message bar (``installer.DependencyBar``); under qgis_process nothing is ever installed.
"""
import os
import sys

from qgis.core import QgsApplication, QgsMessageLog
from qgis.PyQt.QtCore import QCoreApplication, QLocale, QSettings, QTranslator

from . import dependencies
from .compat import MessageLevel
from .resources import I18N_DIR


class EasyIDPPlugin:
    def __init__(self, iface):
        self.iface = iface  # None under qgis_process
        self.packages_dir = dependencies.activate()  # before any of the packages is imported
        self.provider = None  # keep a reference: a collected provider loses its algorithms
        self.load_error = ""  # why the provider could not load (a package every tool needs)
        self.dependency_bar = None
        self.viewer, self.viewer_action, self.toolbar = None, None, None
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
        if self.provider is not None:
            return
        try:
            from .provider import EasyIDPProvider
        except ImportError as exc:  # a package every tool needs is missing or broken
            required = [m for m in dependencies.missing() if m.dependency.scope == dependencies.ALL]
            self.load_error = "EasyIDP: the tools could not load. " + (
                f"{exc}. " + dependencies.tool_message("EasyIDP", required, headless=True)
                if required else dependencies.import_error_message(exc))
            if self.iface is None:  # qgis_process: stderr (stdout would corrupt --json output)
                sys.stderr.write(self.load_error + "\n")
            else:
                QgsMessageLog.logMessage(self.load_error, "EasyIDP", MessageLevel.Critical)
            return
        self.load_error = ""
        self.provider = EasyIDPProvider()
        QgsApplication.processingRegistry().addProvider(self.provider)

    def initGui(self):  # noqa: N802 (QGIS API)
        self.initProcessing()
        from .installer import DependencyBar
        self.dependency_bar = DependencyBar(self.iface, on_installed=self.initProcessing)
        self.dependency_bar.show_if_missing()
        self._add_viewer_action()

    def tr(self, text: str) -> str:
        return QCoreApplication.translate("EasyIDP", text)

    def _add_viewer_action(self) -> None:
        """The EasyIDP toolbar and the Plugins ▸ EasyIDP menu entry: the photo viewer."""
        try:
            from qgis.PyQt.QtGui import QAction                     # Qt6
        except ImportError:
            from qgis.PyQt.QtWidgets import QAction                 # Qt5
        from qgis.PyQt.QtGui import QIcon
        from .resources import ICON
        self.viewer_action = QAction(QIcon(ICON), self.tr("Photo viewer: which photos see this?"),
                                     self.iface.mainWindow())
        self.viewer_action.setObjectName("mActionEasyIDPPhotoViewer")
        self.viewer_action.triggered.connect(self.show_viewer)
        self.toolbar = self.iface.addToolBar("EasyIDP")
        self.toolbar.setObjectName("EasyIDPToolbar")
        self.toolbar.addAction(self.viewer_action)
        self.iface.addPluginToMenu("&EasyIDP", self.viewer_action)

    def show_viewer(self):
        """Open (once) and show the photo viewer dock; returns it."""
        if self.viewer is None:
            from qgis.PyQt.QtCore import Qt
            from .photo_viewer import PhotoViewer
            self.viewer = PhotoViewer(self.iface, self.iface.mainWindow())
            self.iface.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, self.viewer)
        self.viewer.show()
        self.viewer.raise_()
        return self.viewer

    def unload(self):
        if self.viewer_action is not None:
            self.iface.removePluginMenu("&EasyIDP", self.viewer_action)
            self.toolbar.removeAction(self.viewer_action)
            self.toolbar.deleteLater()
            self.viewer_action = self.toolbar = None
        if self.viewer is not None:
            self.viewer.close()
            self.iface.removeDockWidget(self.viewer)
            self.viewer.deleteLater()
            self.viewer = None
        if self.dependency_bar is not None:
            self.dependency_bar.unload()
            self.dependency_bar = None
        if self.provider is not None:
            QgsApplication.processingRegistry().removeProvider(self.provider)
            self.provider = None
        if self.translator is not None:
            QCoreApplication.removeTranslator(self.translator)
            self.translator = None
