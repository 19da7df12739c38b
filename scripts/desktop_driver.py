"""Run inside the QGIS desktop (``qgis --code``) by ``qgis_desktop.run_desktop``: looks at what the
EasyIDP plugin shows at start-up and clicks its buttons, as a user would.

The spec comes in ``EASYIDP_DRIVER`` (JSON): ``out`` (result file), ``screenshot`` (PNG of the
message bar, optional), ``steps`` (optional list of ``{"action": "install" | "cancel",
"env": {name: value or null}}``: the environment pip sees during that step; *Install* is clicked,
and for "cancel" *Cancel* once pip runs), ``session`` (optional: a user's session with the tools,
see ``desktop_session.py``; its findings go to ``session``). QGIS quits when done; errors go to
``driver_error``; ``probe`` plants a dialog, a hang, a photo-pixel layer in the map (its red
"No transform available") or a crash at exit (the driver's own test).

QGIS ends as a user ends it, by Project ▸ Exit QGIS (``iface.actionExit()``; the project marked
saved first, so no question is asked); the exit status is the caller's to check (QGIS's crash
handler aborts a crash with code 134). Every message-bar error the main window shows (level
Critical, or QGIS's "Python error") is kept in ``bar_errors`` (title, text), from start-up to the
exit. ``probe``: one name or a list.

Nothing waits for a click that never comes: every modal dialog (a question, QGIS's Python error
dialog; not the tool dialogs a session opens) is closed as soon as it shows, its title and text kept in ``modal``; every message-log
entry tagged "Python error" is kept in ``python_errors``. ``deadline`` (seconds, from the spec)
ends the run: the findings so far are written, with a ``driver_error`` that says what was being
done and quotes those dialogs and errors, and QGIS exits. What is known is also kept in
``<out>.partial`` while the run goes on, for when the desktop has to be killed.
"""
import faulthandler
import json
import os
import sys
import threading
import time
import traceback

from qgis.core import Qgis, QgsApplication, QgsProject
from qgis.gui import (QgsMessageBarItem, QgsModelDesignerDialog,
                      QgsProcessingAlgorithmDialogBase)
from qgis.PyQt import sip
from qgis.PyQt.QtCore import QMetaObject, QPoint, QRect, Qt, QTimer
from qgis.PyQt.QtWidgets import (QApplication, QDialog, QLabel, QMessageBox, QPushButton,
                                 QTextEdit)
from qgis.utils import iface, plugins

SPEC = json.loads(os.environ["EASYIDP_DRIVER"])
PROBES = [SPEC["probe"]] if isinstance(SPEC.get("probe"), str) else SPEC.get("probe", [])
STARTED = time.time()
faulthandler.enable(all_threads=True)   # a crash of QGIS shows the Python stacks on stderr
FOUND = {"steps": [], "modal": [], "python_errors": [], "bar_errors": [], "doing": "starting"}
# the dialogs a session opens itself
OWN_DIALOGS = (QgsProcessingAlgorithmDialogBase, QgsModelDesignerDialog)


def _write(path: str) -> None:
    with open(path + ".tmp", "w", encoding="utf-8") as fh:
        json.dump(FOUND, fh, indent=1, default=str)
    os.replace(path + ".tmp", path)


def doing(what: str) -> None:
    """Say what the run is doing now (named by a time-out); kept in ``<out>.partial``."""
    FOUND["doing"] = what
    _write(SPEC["out"] + ".partial")


def _dialog_text(w) -> str:
    """Title and text of a dialog: a message box's texts, else its labels and text views."""
    parts = [w.windowTitle()]
    if isinstance(w, QMessageBox):
        parts += [w.text(), w.informativeText(), w.detailedText()]
    else:
        parts += [label.text() for label in w.findChildren(QLabel)]
        parts += [view.toPlainText() for view in w.findChildren(QTextEdit)]
    return "\n".join(p.strip() for p in parts if p and p.strip())


def _own(w) -> bool:
    """A dialog the session opened, or one of its parts (QGIS 3.22 shows a tool's progress in a
    modal dialog of the tool's dialog while a model runs)."""
    while w is not None:
        if isinstance(w, OWN_DIALOGS):
            return True
        w = w.parentWidget()
    return False


def _close_modal() -> None:
    w = QApplication.activeModalWidget()
    if w is None or (_own(w) and not isinstance(w, QMessageBox)):    # a question is never own
        return
    if FOUND["doing"].startswith("exiting") and isinstance(w, QMessageBox):
        _answer_exit_question(w)
        return
    FOUND["modal"].append(f"{type(w).__name__} while {FOUND['doing']}: {_dialog_text(w)}")
    _write(SPEC["out"] + ".partial")
    if isinstance(w, QMessageBox) and w.escapeButton() is not None:
        w.escapeButton().click()
    elif isinstance(w, QDialog):
        w.reject()
    else:
        w.close()


def _answer_exit_question(box) -> None:
    """While QGIS quits, its questions (e.g. "temporary layers … will be lost") are answered as a
    user quitting answers them: yes, discard."""
    FOUND.setdefault("exit_questions", []).append(_dialog_text(box))
    _write(SPEC["out"] + ".partial")
    role = QMessageBox.ButtonRole        # scoped: Qt5 and Qt6
    roles = (role.YesRole, role.AcceptRole, role.DestructiveRole)
    for button in box.buttons():
        if box.buttonRole(button) in roles:
            button.click()
            return
    box.reject()


def _log(message, tag, level) -> None:
    if tag == "Python error":
        FOUND["python_errors"].append(message)
        _write(SPEC["out"] + ".partial")


def _bar_item(widget) -> None:
    """A message-bar item as it is pushed: an error (level Critical, or QGIS's "Python error") is
    kept in ``bar_errors``."""
    item = sip.cast(widget, QgsMessageBarItem)      # the signal hands a QWidget to Python
    if item.level() == Qgis.MessageLevel.Critical or item.title().startswith("Python error"):
        python = "".join(traceback.format_stack(limit=6)[:-1])   # what Python code ran then
        FOUND["bar_errors"].append(f"{item.title()}: {item.text()} (while {FOUND['doing']})\n"
                                   f"{python}")
        _write(SPEC["out"] + ".partial")


def _deadline() -> None:
    """A thread's timer: it fires even while the main thread is stuck (in a nested event loop,
    or in Python that never returns to Qt)."""
    quoted = "\n".join(FOUND["modal"] + FOUND["python_errors"]) or "no dialog, no Python error"
    FOUND["driver_error"] = (f"time limit of {SPEC['deadline']:.0f} s reached while "
                             f"{FOUND['doing']}; seen:\n{quoted}")
    for _ in range(10):                  # the main thread may be changing FOUND meanwhile
        try:
            _write(SPEC["out"])
            break
        except RuntimeError:
            time.sleep(0.05)
    os._exit(3)


def _probe(kind: str) -> None:
    """What the driver's own test plants (spec ``probe``): a question and a Python error
    raised in a slot (``dialog``), or a run that never ends (``hang``)."""
    if kind == "dialog":
        QTimer.singleShot(0, lambda: 1 / 0)              # QGIS's Python error dialog
        QMessageBox.question(None, "Planted question", "Replace the planted file?")
    elif kind == "hang":
        while True:
            time.sleep(0.1)
    elif kind == "pixels_on_map":
        _pixels_on_map()


def _pixels_on_map() -> None:
    """The error users met (issue 37): a layer in photo pixels (GeoPackage, undefined Cartesian
    CRS) drawn in a map canvas in a projected CRS; QGIS shows "No transform available" in red."""
    from qgis.core import (QgsCoordinateReferenceSystem, QgsFeature, QgsGeometry,
                           QgsVectorFileWriter, QgsVectorLayer)
    memory = QgsVectorLayer("Polygon", "pixels", "memory")
    feature = QgsFeature()
    feature.setGeometry(QgsGeometry.fromWkt("POLYGON((10 -10, 90 -10, 90 -60, 10 -60, 10 -10))"))
    memory.dataProvider().addFeatures([feature])
    path = SPEC["out"] + ".pixels.gpkg"
    options = QgsVectorFileWriter.SaveVectorOptions()
    options.driverName = "GPKG"
    QgsVectorFileWriter.writeAsVectorFormatV2(
        memory, path, QgsProject.instance().transformContext(), options)
    from easyidp_toolbox.core.projection import PIXEL_CRS_WKT
    layer = QgsVectorLayer(path, "ROIs in photo pixels", "ogr")
    layer.setCrs(QgsCoordinateReferenceSystem.fromWkt(PIXEL_CRS_WKT))
    QgsProject.instance().setCrs(QgsCoordinateReferenceSystem("EPSG:32654"))
    QgsProject.instance().addMapLayer(layer)
    canvas = iface.mapCanvas()
    canvas.setExtent(canvas.mapSettings().layerExtentToOutputExtent(layer, layer.extent()))
    canvas.refresh()
    _wait(lambda: bool(FOUND["bar_errors"]), 10)


WATCHDOG = QTimer()
WATCHDOG.timeout.connect(_close_modal)
WATCHDOG.start(300)
QgsApplication.messageLog().messageReceived.connect(_log)
iface.messageBar().widgetAdded.connect(_bar_item)
if SPEC.get("deadline"):
    DEADLINE = threading.Timer(SPEC["deadline"], _deadline)
    DEADLINE.daemon = True               # QGIS's exit does not wait for it
    DEADLINE.start()


def _pump(seconds: float) -> None:
    end = time.time() + seconds
    while time.time() < end:
        QgsApplication.processEvents()
        time.sleep(0.02)


def _wait(condition, timeout: float) -> bool:
    end = time.time() + timeout
    while time.time() < end:
        QgsApplication.processEvents()
        if condition():
            return True
        time.sleep(0.05)
    return False


def _button(name: str):
    """The visible button of that name in the message bar (popped items linger, hidden)."""
    shown = [b for b in iface.messageBar().findChildren(QPushButton, name) if b.isVisible()]
    return shown[-1] if shown else None


def _bar_texts():
    return [f"{item.title()}: {item.text()}"
            for item in iface.messageBar().findChildren(QgsMessageBarItem) if item.isVisible()]


def _listing(folder: str):
    return sorted(os.listdir(folder)) if os.path.isdir(folder) else None


def _current():
    item = iface.messageBar().currentItem()
    return f"{item.title()}: {item.text()}" if item is not None else None


def _screenshot(path: str) -> None:
    window = iface.mainWindow()
    window.resize(1280, 760)
    _pump(0.5)
    bar = iface.messageBar()
    bottom = bar.mapTo(window, QPoint(0, bar.height())).y()
    window.grab(QRect(0, 0, window.width(), min(window.height(), bottom + 120))).save(path)


def _step(plugin, step: dict) -> dict:
    from easyidp_toolbox.easyidp_qgis import dependencies
    bar = plugin.dependency_bar
    saved = {k: os.environ.get(k) for k in step.get("env", {})}
    for key, value in step.get("env", {}).items():
        if value is None:
            os.environ.pop(key, None)
        else:
            os.environ[key] = value
    try:
        if not _wait(lambda: _button(bar.INSTALL_BUTTON) is not None, 2):
            bar.show_if_missing()  # the bar as at start-up, after the previous step's result
            _wait(lambda: _button(bar.INSTALL_BUTTON) is not None, 5)
        install = _button(bar.INSTALL_BUTTON)
        found = {"action": step["action"], "install_button": install is not None}
        bar.result = ""
        install.click()  # the button itself: its clicked signal runs the slot
        task = bar.task
        found["progress_bar_shown"] = _wait(lambda: _button(bar.CANCEL_BUTTON) is not None, 10)
        if step["action"] == "cancel":
            _wait(lambda: task.pid is not None and any(l.startswith("$ ") for l in task.output),
                  60)
            _pump(1.0)
            found["pid"] = task.pid
            _button(bar.CANCEL_BUTTON).click()
        started = time.time()
        found["finished"] = _wait(lambda: bar.result != "", SPEC.get("timeout", 600))
        found["seconds"] = round(time.time() - started, 1)
        found.update(result=bar.result, message=bar.message, output=task.output[-40:],
                     command=bar.command, bar=_bar_texts(), current=_current())
        if found.get("pid"):
            try:
                os.killpg(found["pid"], 0)
                found["process_group_alive"] = True
            except ProcessLookupError:
                found["process_group_alive"] = False
        found["missing_after"] = [m.dependency.distribution
                                  for m in dependencies.missing(include_extras=True)]
        found["folder"] = _listing(dependencies.packages_dir())
        return found
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value


def _close_qgis_notices() -> list:
    """Remove QGIS's own start-up messages from the bar (as a user closes them; e.g. QGIS 3.40's
    failed download of a font without network, which hides the plugin's message), returning
    their texts."""
    bar = iface.messageBar()
    notices = [i for i in bar.items() if i.title() != "EasyIDP"]
    for item in notices:
        bar.popWidget(item)
    return [f"{i.title()}: {i.text()}" for i in notices]


def run() -> None:
    found = FOUND
    try:
        plugin = plugins.get("easyidp_toolbox")
        found["plugin_loaded"] = plugin is not None
        from easyidp_toolbox.easyidp_qgis import dependencies
        bar = plugin.dependency_bar
        _pump(0.5)
        found["qgis_notices"] = _close_qgis_notices()
        found.update(
            plugin_file=sys.modules[type(plugin).__module__].__file__,
            python=dependencies.python_executable(), packages_dir=dependencies.packages_dir(),
            packages_dir_first=sys.path[0] == dependencies.packages_dir(),
            missing=[m.dependency.distribution for m in bar.missing], message=bar.message,
            install_button=_button(bar.INSTALL_BUTTON) is not None, bar=_bar_texts(),
            current=_current(),
            provider=QgsApplication.processingRegistry().providerById("easyidp") is not None,
            folder=_listing(dependencies.packages_dir()))
        for probe in PROBES:
            doing(f"the planted {probe}")
            _probe(probe)
        if SPEC.get("screenshot"):
            doing("taking the screenshot")
            _screenshot(SPEC["screenshot"])
        if SPEC.get("session"):
            from easyidp_toolbox.scripts.desktop_session import run_session
            found["session"] = run_session(SPEC["session"], found["modal"], doing)
        for step in SPEC.get("steps", []):
            doing(f"clicking {step['action']} in the message bar")
            found["steps"].append(_step(plugin, step))
        if found["steps"] and found["steps"][-1]["result"] == "installed":
            import importlib
            found["imported"] = {name: importlib.import_module(name).__file__
                                 for name in ("tifffile", "imagecodecs", "laspy", "plyfile")}
            import numpy
            found["numpy"] = [numpy.__version__, numpy.__file__]
    except Exception:
        found["driver_error"] = traceback.format_exc()
    doing("exiting through Project ▸ Exit QGIS")
    _write(SPEC["out"])
    _exit()


def _exit() -> None:
    """Project ▸ Exit QGIS, as a user quits (QGIS asks nothing: the project is marked saved); a
    planted crash (probe ``crash``) signals 11 on the way out. QGIS not gone 20 s later: a
    ``driver_error`` and exit status 4."""
    _wait(lambda: QgsApplication.taskManager().countActiveTasks() == 0, 60)   # as a user waits
    QgsProject.instance().setDirty(False)
    if "crash" in PROBES:
        import signal
        QgsApplication.instance().aboutToQuit.connect(lambda: os.kill(os.getpid(), signal.SIGSEGV))
    QTimer.singleShot(20000, _not_gone)
    # from the event loop, no Python on the stack: QGIS may wait there for a Python task thread,
    # which needs the interpreter lock a Python caller would hold
    QMetaObject.invokeMethod(iface.actionExit(), "trigger", Qt.ConnectionType.QueuedConnection)


def _not_gone() -> None:
    FOUND["driver_error"] = ("QGIS did not exit within 20 s of Project ▸ Exit QGIS; seen:\n"
                             + "\n".join(FOUND["modal"] + FOUND["python_errors"]))
    _write(SPEC["out"])
    os._exit(4)


QTimer.singleShot(500, run)
