"""Base class of the EasyIDP algorithms: naming, help, icon, dependency check, and core error
translation."""
import os
import threading
from typing import Callable, NamedTuple, Tuple

from qgis.core import QgsProcessingAlgorithm, QgsProcessingException, QgsProcessingParameterBoolean
from qgis.PyQt.QtCore import QCoreApplication
from qgis.PyQt.QtGui import QIcon

from .. import dependencies
from ..compat import ProcessingParameterFlag
from ..layer_files import unreadable_inputs_message
from ..messages import error_message
from ..outputs import check_values, claim_outputs
from ..parameters import translatable  # noqa: F401 (the tools import it from here)
from ..resources import ICON, help_url


def __getattr__(name):
    """``INSTALL_HINT``: how to install the plugin's packages, made from the dependency table
    when read (it names QGIS's interpreter and the profile's package folder)."""
    if name == "INSTALL_HINT":
        return dependencies.install_hint()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


_PROJ_CONTEXTS = {}
"""pyproj's owner of each task thread's PROJ context, kept alive (see :func:`keep_proj_context`)."""


def keep_proj_context() -> None:
    """Keep this thread's pyproj context alive, on pyproj 3.7.0 and 3.7.1 (Debian 13's).

    Those keep a thread's PROJ context in two places: a pointer in the thread's own storage, and
    its owner in a ``threading.local``, which Python clears when a call from a thread it did not
    create (a QGIS task thread) returns. The next run in that pooled thread then used the freed
    context and crashed QGIS (pyproj#1509, fixed in 3.7.2). One context per thread is kept."""
    import pyproj
    if not pyproj.__version__.startswith(("3.7.0", "3.7.1")):
        return
    from pyproj._context import get_context_manager
    manager = get_context_manager()
    if manager is not None:
        _PROJ_CONTEXTS[threading.get_ident()] = manager


class CoreStep(NamedTuple):
    """A tool's pure step, parameters → the core call: the core ``function``, its keyword
    arguments ``kwargs``, and ``inputs``, what the tool's outputs need besides the result (the
    ROI layer and its features, a layer's name), which the core is not given."""
    function: Callable
    kwargs: dict
    inputs: dict


class EasyIDPAlgorithm(QgsProcessingAlgorithm):
    """Subclasses set NAME, REQUIRES, DISPLAY, GROUP, GROUP_ID, HELP and implement ``core_step``
    (the parameters → the core call, testable without running it, as the GDAL provider's
    ``getConsoleCommands``) and ``write_outputs`` (the result → the outputs); ``run_tool``
    chains the two (all 14 tools are split so)."""

    NAME = ""
    REQUIRES: Tuple[str, ...] = ()
    """The import names of the packages of ``dependencies.DEPENDENCIES`` the tool needs beyond the
    plugin's own (numpy, pyproj); the table's tools are derived from them."""
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

    def helpUrl(self):  # noqa: N802 (QGIS API: the dialog's Help button)
        return help_url(f"easyidp-{self.NAME}")

    def icon(self):
        return QIcon(ICON)

    @staticmethod
    def decimals(parameter, places: int):
        """Show a number parameter with ``places`` decimals in every dialog (QGIS shows 6:
        a percentile of 95 read 95.000000); returns the parameter."""
        meta = dict(parameter.metadata())
        meta["widget_wrapper"] = {**dict(meta.get("widget_wrapper") or {}), "decimals": places}
        parameter.setMetadata(meta)
        return parameter

    def canExecute(self):  # noqa: N802 (QGIS API; the desktop's dialogs ask it)
        items = dependencies.missing(self.NAME)
        if items:
            return False, dependencies.tool_message(self.displayName(), items)
        return True, ""

    FILE_OR_FOLDER = ("PROJECT",)
    """File parameters that also take a folder (a Pix4D or OpenDroneMap project folder)."""

    def checkParameterValues(self, parameters, context):  # noqa: N802 (QGIS API)
        """QGIS's check, with the ranges and choices named, and a folder accepted where
        :attr:`FILE_OR_FOLDER` says so (QGIS's file parameter refuses folders)."""
        ok, message = check_values(self, parameters, context)
        if not ok:
            return ok, message
        folders = {n: v for n, v in parameters.items() if n in self.FILE_OR_FOLDER and
                   isinstance(v, str) and os.path.isdir(v)}
        if folders:    # QGIS checks the rest; the folder itself is the reader's to judge
            parameters = {**parameters, **{n: os.path.abspath(__file__) for n in folders}}
        ok, message = super().checkParameterValues(parameters, context)
        if not ok:              # QGIS says '… not found' for a file it cannot read
            message = unreadable_inputs_message(self, parameters, context) or message
        return ok, message

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802 (QGIS API)
        items = dependencies.missing(self.NAME)  # the packages the table says this tool needs
        if items:
            raise QgsProcessingException(
                dependencies.tool_message(self.displayName(), items, headless=True))
        try:
            from ...core.errors import EasyIDPError
        except ImportError as exc:
            raise QgsProcessingException(dependencies.import_error_message(exc)) from None
        ok, message = check_values(self, parameters, context)   # also where QGIS did not ask
        if not ok:
            raise QgsProcessingException(message)
        try:
            with claim_outputs(self, parameters, context, self.overwrite(parameters, context),
                               feedback):
                return self.run_tool(parameters, context, feedback)
        except EasyIDPError as exc:
            raise QgsProcessingException(error_message(exc)) from None
        except ImportError as exc:  # a package the table does not list for this tool
            raise QgsProcessingException(dependencies.import_error_message(exc)) from None
        finally:
            keep_proj_context()

    def postProcessAlgorithm(self, context, feedback):  # noqa: N802 (QGIS API: main thread)
        """The layers in photo pixels a run held off the map go into the project, for the photo
        viewer (``presentation.load_off_map``)."""
        from ..presentation import load_off_map
        load_off_map(self, context, feedback)
        return {}

    OVERWRITE = "OVERWRITE"

    def add_overwrite_parameter(self) -> None:
        """The advanced OVERWRITE option (default off): replace files that already exist."""
        p = QgsProcessingParameterBoolean(self.OVERWRITE, self.tr("Overwrite existing files"), False)
        p.setHelp(self.tr("Otherwise the tool stops before writing anything when an output "
                          "already exists"))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)

    def overwrite(self, parameters, context) -> bool:
        """OVERWRITE when the tool has it (every tool that writes files does)."""
        return self.parameterDefinition(self.OVERWRITE) is not None and \
            self.parameterAsBool(parameters, self.OVERWRITE, context)

    def core_step(self, parameters, context, feedback) -> CoreStep:
        """Parameters → :class:`CoreStep`; QgsProcessingException naming the input for a bad
        parameter. Reads the QGIS inputs (layers, features) but runs nothing of the core's work."""
        raise NotImplementedError

    def step(self, parameters, context, feedback) -> CoreStep:
        """:meth:`core_step` with a core error about the parameters (a file the season table
        names given as an output…) raised as QgsProcessingException, as a run does."""
        from ...core.errors import EasyIDPError
        try:
            return self.core_step(parameters, context, feedback)
        except EasyIDPError as exc:
            raise QgsProcessingException(error_message(exc)) from None

    def write_outputs(self, parameters, context, feedback, step: CoreStep, result) -> dict:
        """The core's ``result`` → the tool's outputs (sinks, map layers, log)."""
        raise NotImplementedError

    def run_tool(self, parameters, context, feedback) -> dict:
        step = self.core_step(parameters, context, feedback)
        return self.write_outputs(parameters, context, feedback, step,
                                  step.function(**step.kwargs))
