"""Base class of the EasyIDP algorithms: naming, help, icon, and core error translation."""
from qgis.core import (QgsProcessingAlgorithm, QgsProcessingException, QgsProcessingParameterBoolean,
                       QgsProcessingParameterDefinition)
from qgis.PyQt.QtCore import QCoreApplication
from qgis.PyQt.QtGui import QIcon

from ..resources import ICON

INSTALL_HINT = ("Install the plugin's Python dependencies for the Python that QGIS uses: "
                "pip install numpy pyproj tifffile imagecodecs laspy lazrs plyfile "
                "(see the plugin README).")


class EasyIDPAlgorithm(QgsProcessingAlgorithm):
    """Subclasses set NAME, DISPLAY, GROUP, GROUP_ID, HELP and implement ``run_tool``."""

    NAME = ""
    DISPLAY = ""
    GROUP = ""
    GROUP_ID = ""
    HELP = ""

    def tr(self, text: str) -> str:
        return QCoreApplication.translate("EasyIDP", text)

    def createInstance(self):  # noqa: N802 (QGIS API)
        return self.__class__()

    def name(self):
        return self.NAME

    def displayName(self):  # noqa: N802 (QGIS API)
        return self.tr(self.DISPLAY)

    def group(self):
        return self.tr(self.GROUP)

    def groupId(self):  # noqa: N802 (QGIS API)
        return self.GROUP_ID

    def shortHelpString(self):  # noqa: N802 (QGIS API)
        return self.tr(self.HELP)

    def icon(self):
        return QIcon(ICON)

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802 (QGIS API)
        try:
            from ...core.errors import EasyIDPError
        except ImportError as exc:
            raise QgsProcessingException(f"{exc}. {INSTALL_HINT}") from None
        try:
            return self.run_tool(parameters, context, feedback)
        except EasyIDPError as exc:
            raise QgsProcessingException(str(exc)) from None
        except ImportError as exc:
            raise QgsProcessingException(f"{exc}. {INSTALL_HINT}") from None

    OVERWRITE = "OVERWRITE"

    def add_overwrite_parameter(self) -> None:
        """The advanced OVERWRITE option (default off): replace files that already exist."""
        p = QgsProcessingParameterBoolean(
            self.OVERWRITE, self.tr("Overwrite existing files (otherwise the tool stops before "
                                    "writing anything when an output already exists)"), False)
        p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(p)

    def overwrite(self, parameters, context) -> bool:
        return self.parameterAsBool(parameters, self.OVERWRITE, context)

    def run_tool(self, parameters, context, feedback) -> dict:
        raise NotImplementedError
