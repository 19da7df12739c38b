"""The desktop's offer to install missing Python packages: message bar, *Install*, progress, result.

Only the desktop shows it (``initGui``); ``qgis_process`` never installs anything. *Install* runs
``install_packages.py`` with QGIS's own Python in a ``QgsTask`` (progress in the bar and in the
task manager, cancellable from either); nothing is downloaded before the click. The packages go
in at the releases the tests ran with (``dependencies.pinned_requirement``); once pip has
resolved them, the bar lists everything that will be installed, what comes with them included.
The result stays in the bar until it is closed.
"""
import os
import queue
import signal
import subprocess
import sys
import threading
from typing import Callable, List, Optional

from qgis.core import QgsApplication, QgsMessageLog, QgsTask
from qgis.PyQt.QtCore import QCoreApplication
from qgis.PyQt.QtWidgets import QProgressBar, QPushButton

from . import dependencies
from .compat import MessageLevel, TaskFlag

LOG_TAG = "EasyIDP"


class InstallTask(QgsTask):
    """Runs the install command in the background, reporting ``::progress`` lines; cancellable.

    ``done(task)`` is called in the main thread at the end; ``ok``, ``cancelled``, ``output`` and
    ``error`` say how it went; ``plan`` is what pip resolved (``"name version, …"``), once known.
    """

    def __init__(self, argv: List[str], description: str, done: Callable[["InstallTask"], None]):
        super().__init__(description, TaskFlag.CanCancel)
        self.argv = list(argv)
        self.done = done
        self.output: List[str] = []
        self.error = ""
        self.plan = ""
        self.ok = False
        self.cancelled = False
        self.returncode: Optional[int] = None
        self.pid: Optional[int] = None  # of the installer process (its process group on POSIX)

    def run(self) -> bool:  # worker thread
        try:
            problem = dependencies.check_python(self.argv[0])
            if problem:
                self.error = problem
                return False
            self.ok = self._run_command()
            return self.ok
        except Exception as exc:  # reported in finished(); a task must not raise
            self.error = f"{type(exc).__name__}: {exc}"
            return False

    def _run_command(self) -> bool:
        env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONIOENCODING="utf-8")
        if os.name == "nt":
            group = {"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP |
                     subprocess.CREATE_NO_WINDOW}
        else:
            group = {"start_new_session": True}  # its own process group: cancel stops pip too
        proc = subprocess.Popen(self.argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,  # nosec B603 -- QGIS's Python and the plugin's installer, no shell
                                stdin=subprocess.DEVNULL, text=True, encoding="utf-8",
                                errors="replace", bufsize=1, env=env, **group)
        self.pid = proc.pid
        lines: "queue.Queue[Optional[str]]" = queue.Queue()
        reader = threading.Thread(target=_read_lines, args=(proc.stdout, lines), daemon=True)
        reader.start()
        try:
            self._follow(proc, lines)
            proc.wait()
            reader.join(timeout=5)
        finally:
            proc.stdout.close()  # the pipe is ours to close (no ResourceWarning)
        self.returncode = proc.returncode
        return proc.returncode == 0 and not self.cancelled

    def _follow(self, proc: subprocess.Popen, lines: "queue.Queue[Optional[str]]") -> None:
        """Read the installer's lines until it ends or the task is cancelled."""
        while True:
            if self.isCanceled():
                self.cancelled = True
                _stop(proc)
                break
            try:
                line = lines.get(timeout=0.1)
            except queue.Empty:
                continue
            if line is None:
                break
            line = line.rstrip()
            if line.startswith("::progress "):
                self.setProgress(float(line.split()[1]))
            else:
                self.output.append(line)
                if line.startswith("ERROR:"):
                    self.error = line[len("ERROR:"):].strip()
                elif line.startswith("To install: "):
                    self.plan = line[len("To install: "):].strip()
                    self.setProgress(self.progress())  # the bar shows the plan (main thread)

    def finished(self, result: bool) -> None:  # main thread
        self.cancelled = self.cancelled or self.isCanceled()  # also when cancelled before run()
        self.done(self)


def _read_lines(stream, lines: "queue.Queue[Optional[str]]") -> None:
    for line in stream:
        lines.put(line)
    lines.put(None)


def _loaded_elsewhere(installed: str) -> bool:
    """Whether a package just installed (``"name version, …"``) was already imported from
    another folder: the new copy is used only after a restart."""
    names = {dependencies.canonical(p.split()[0]) for p in installed.split(", ") if p.strip()}
    folder = os.path.normcase(dependencies.packages_dir())
    for dep in dependencies.DEPENDENCIES:
        module = sys.modules.get(dep.module)
        path = os.path.normcase(getattr(module, "__file__", None) or "")
        if dependencies.canonical(dep.distribution) in names and path \
                and not path.startswith(folder):
            return True
    return False


def _stop(proc: subprocess.Popen) -> None:
    """Stop the installer and the pip it runs (its whole process group or tree)."""
    if proc.poll() is not None:
        return
    if os.name == "nt":
        taskkill = os.path.join(os.environ.get("SystemRoot", r"C:\Windows"), "System32",
                                "taskkill.exe")
        subprocess.run([taskkill, "/F", "/T", "/PID", str(proc.pid)], capture_output=True,  # nosec B603 -- Windows's taskkill, no shell
                       creationflags=subprocess.CREATE_NO_WINDOW)
    else:
        try:
            os.killpg(proc.pid, signal.SIGTERM)
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


class DependencyBar:
    """The message bar item and what its buttons do. ``on_installed()`` runs after a success."""

    INSTALL_BUTTON = "easyidpInstallButton"
    CANCEL_BUTTON = "easyidpCancelButton"

    def __init__(self, iface, on_installed: Optional[Callable[[], None]] = None):
        self.iface = iface
        self.on_installed = on_installed
        self.item = None
        self.task: Optional[InstallTask] = None
        self.missing: List[dependencies.Missing] = []
        self.command = ""
        self.result = ""  # "", "installed", "failed" or "cancelled"
        self.message = ""  # the text of the last message shown
        self.unloaded = False
        self.extras = False

    def tr(self, text: str) -> str:
        return QCoreApplication.translate("EasyIDP", text)

    @property
    def bar(self):
        return self.iface.messageBar()

    def show_if_missing(self) -> bool:
        """Show the warning with *Install* when a package a tool needs is missing or too old."""
        self.missing = dependencies.missing()
        if not self.missing:
            return False
        text = self.tr("Some tools need Python packages that QGIS's Python lacks: {packages}."
                       ).format(packages=dependencies.describe(self.missing))
        note = dependencies.protected_message(self.missing)
        if note:
            text += " " + note
        widget = self.bar.createMessage(self.tr("EasyIDP"), text)
        if dependencies.installable(self.missing):
            button = QPushButton(self.tr("Install"), widget)
            button.setObjectName(self.INSTALL_BUTTON)
            button.setToolTip(self.tr("Download them with pip into your QGIS profile; QGIS's own "
                                      "packages are not changed."))
            button.clicked.connect(self.install)
            widget.layout().addWidget(button)
        self._show(widget, MessageLevel.Warning, text)
        return True

    def install(self, extras: bool = False) -> None:
        """The *Install* button: run the installer for every missing package the tools need
        (``extras``: the script-only extras too, Dask and OPF), in a task."""
        if self.task is not None:
            return
        self.extras = extras
        items = dependencies.installable(dependencies.missing(include_extras=extras))
        if not items:
            self._report(MessageLevel.Success, self.tr("Every Python package EasyIDP needs is installed."))
            return
        argv = dependencies.install_argv(items)
        self.command = dependencies.format_command(argv)
        names = ", ".join(m.dependency.distribution for m in items)
        QgsMessageLog.logMessage(f"Installing {names}: {self.command}", LOG_TAG, MessageLevel.Info)
        self.task = InstallTask(argv, self.tr("Installing Python packages for EasyIDP"),
                                self._finished)
        text = self.tr("Installing {packages} …").format(packages=names)
        widget = self.bar.createMessage(self.tr("EasyIDP"), text)
        progress = QProgressBar(widget)
        progress.setRange(0, 100)
        progress.setMinimumWidth(160)
        widget.layout().addWidget(progress)
        cancel = QPushButton(self.tr("Cancel"), widget)
        cancel.setObjectName(self.CANCEL_BUTTON)
        cancel.clicked.connect(self.cancel)
        widget.layout().addWidget(cancel)
        task = self.task

        def advanced(value):
            progress.setValue(int(value))
            planned = self.tr("Installing {packages} …").format(packages=task.plan)
            if task.plan and widget.text() != planned:
                widget.setText(planned)          # what pip resolved, dependencies included
                self.message = planned
        self.task.progressChanged.connect(advanced)
        self._show(widget, MessageLevel.Info, text)
        QgsApplication.taskManager().addTask(self.task)

    def cancel(self) -> None:
        if self.task is not None:
            self.task.cancel()

    def unload(self) -> None:
        """The plugin is unloaded: stop a running install, report nothing more."""
        self.on_installed = None
        self.unloaded = True
        self.cancel()
        self._pop()

    def _finished(self, task: InstallTask) -> None:
        self.task = None
        if self.unloaded:
            return
        QgsMessageLog.logMessage("\n".join(task.output), LOG_TAG,
                                 MessageLevel.Info if task.ok else MessageLevel.Warning)
        if task.cancelled:
            self.result = "cancelled"
            self._report(MessageLevel.Info, self.tr("Installation cancelled; nothing was changed. To "
                                            "install later, run:\n{command}").format(
                command=self.command))
            return
        still = dependencies.missing(include_extras=self.extras) if task.ok else []
        if not task.ok or still:
            self.result = "failed"
            reason = task.error or (self.tr("still missing after pip: {packages}").format(
                packages=dependencies.describe(still)) if still else
                self.tr("exit status {code}").format(code=task.returncode))
            self._report(MessageLevel.Critical, self.tr(
                "Installing the Python packages failed: {reason}. Run this command in a "
                "terminal to see why:\n{command}").format(reason=reason, command=self.command),
                details="\n".join(task.output))
            return
        self.result = "installed"
        installed = next((line.split(": ", 1)[1] for line in reversed(task.output)
                          if line.startswith("Installed into ")), "")
        text = self.tr("Python packages installed: {packages}.").format(
            packages=installed or self.tr("nothing was missing"))
        if _loaded_elsewhere(installed):
            text += " " + self.tr("Restart QGIS to use them: an older copy is already loaded.")
        self._report(MessageLevel.Success, text)  # stays until closed
        if self.on_installed is not None:
            self.on_installed()

    def _report(self, level, text: str, details: str = "", duration: int = 0) -> None:
        """A result message; ``duration`` 0 (every result) keeps it until it is closed."""
        self._pop()
        self.message = text
        if details:
            self.bar.pushMessage(self.tr("EasyIDP"), text, details, level, duration)
        else:
            self.bar.pushMessage(self.tr("EasyIDP"), text, level, duration)
        self.item = self.bar.currentItem()

    def _show(self, widget, level, text: str) -> None:
        self._pop()
        self.message = text
        self.item = self.bar.pushWidget(widget, level)

    def _pop(self) -> None:
        if self.item is not None:
            try:
                self.bar.popWidget(self.item)
            except RuntimeError:  # already closed by the user (the C++ object is gone)
                pass
            self.item = None
