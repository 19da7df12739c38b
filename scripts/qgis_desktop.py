"""The real QGIS desktop (under Xvfb), driven as a user would:

- the plugin as a user installs it: its zip unpacked into a fresh QGIS profile, run by the
  desktop and by ``qgis_process`` with QGIS's own Python only (none of this repository's
  environments): ``tests/qgis/test_install_from_zip.py`` and the README's screenshot of the
  message bar (``--screenshot docs/install_message_bar.png``);
- a user's session with the tools of this checkout (``run_session``, ``desktop_session.py``):
  ``tests/qgis/test_desktop.py`` and ``make screenshots`` (``--screenshots docs``).

    python -m easyidp_toolbox.scripts.qgis_desktop --screenshot docs/install_message_bar.png
    python -m easyidp_toolbox.scripts.qgis_desktop --screenshots docs

The desktop runs ``desktop_driver.py`` (``qgis --code``), which does what ``spec`` asks and writes
what it saw to a JSON file.
"""
import argparse
import configparser
import json
import os
import shutil
import signal
import subprocess
import sys
import sysconfig
import tempfile
import zipfile
from typing import Dict, List, Optional

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DRIVER = os.path.join(HERE, "desktop_driver.py")
MODEL = os.path.join(ROOT, "tests", "qgis", "data", "heights_then_crop.model3")
QGIS = shutil.which("qgis") or "/usr/bin/qgis"
QGIS_PROCESS = shutil.which("qgis_process.bin") or "/usr/bin/qgis_process.bin"
PLUGIN_ID = "easyidp_toolbox"


def profile_dir(root: str) -> str:
    return os.path.join(root, "profiles", "default")


def install_zip(zip_path: str, root: str) -> str:
    """Unpack the plugin zip into the profile's plugin folder and enable it (as *Install from
    ZIP* does); returns the plugin folder."""
    plugins = os.path.join(profile_dir(root), "python", "plugins")
    os.makedirs(plugins, exist_ok=True)
    with zipfile.ZipFile(zip_path) as zf:
        zf.extractall(plugins)
    enable_plugin(root)
    return os.path.join(plugins, PLUGIN_ID)


def enable_plugin(root: str) -> None:
    """Mark the plugin enabled in the profile's settings (as the Plugin Manager does)."""
    ini = os.path.join(profile_dir(root), "QGIS", "QGIS3.ini")
    os.makedirs(os.path.dirname(ini), exist_ok=True)
    cfg = configparser.ConfigParser()
    cfg.optionxform = str
    cfg.read(ini)
    if not cfg.has_section("PythonPlugins"):
        cfg.add_section("PythonPlugins")
    cfg.set("PythonPlugins", PLUGIN_ID, "true")
    with open(ini, "w") as fh:
        cfg.write(fh, space_around_delimiters=False)


def clean_env(extra: Optional[Dict[str, str]] = None) -> Dict[str, str]:
    """The environment of a user's QGIS: no PYTHONPATH, virtualenv or plugin path of this
    repository, and no ``python3`` of a virtualenv first on PATH."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "QGIS_PLUGINPATH",
                        "QGIS_CUSTOM_CONFIG_PATH", "QT_QPA_PLATFORM", "PYTHONDONTWRITEBYTECODE")}
    venv_bin = os.path.join(sys.prefix, "bin")
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                  if os.path.abspath(p) != os.path.abspath(venv_bin))
    env.setdefault("PROJ_DATA", "/usr/share/proj")
    env.update(extra or {})
    return env


def checkout_env() -> Dict[str, str]:
    """What the desktop needs to load this checkout's plugin with this environment's packages
    (as ``qgis_process.qgis_process_env`` does for qgis_process)."""
    from .qgis_process import PLUGINS
    if not os.path.isdir(os.path.join(PLUGINS, PLUGIN_ID)):
        os.makedirs(PLUGINS, exist_ok=True)
        os.symlink(ROOT, os.path.join(PLUGINS, PLUGIN_ID))
    return {"QGIS_PLUGINPATH": PLUGINS, "PYTHONPATH": sysconfig.get_paths()["purelib"],
            "PYTHONDONTWRITEBYTECODE": "1"}


def run_session(work: str, shots: Optional[str] = None, timeout: float = 900) -> dict:
    """A user's session (``desktop_session.py``) in a fresh profile, with this checkout's
    plugin: the demo survey and the tools in ``work``; PNGs in ``shots`` when given.
    Returns what the session saw (layers, groups, styles, the message log, steps)."""
    root = os.path.join(work, "qgis-profile")
    enable_plugin(root)
    found = run_desktop(root, {"session": {"work": work, "shots": shots, "model": MODEL}},
                        timeout=timeout, extra_env=checkout_env())
    if found.get("session", {}).get("session_error"):
        raise RuntimeError("the desktop session failed:\n" + found["session"]["session_error"])
    return found


def run_desktop(root: str, spec: dict, timeout: float = 600,
                extra_env: Optional[Dict[str, str]] = None) -> dict:
    """Start the QGIS desktop on the profile under Xvfb; the driver follows ``spec`` (see
    desktop_driver.py) and its findings are returned. ``extra_env``: added to a user's
    environment (e.g. :func:`checkout_env`). Within ``timeout`` seconds, or RuntimeError saying
    what the desktop was doing and quoting the dialogs it closed and the Python errors logged
    (the driver stops itself 30 s before; QGIS is killed at ``timeout``). :class:`DesktopFailed`
    (a RuntimeError) when QGIS, quit by Project ▸ Exit QGIS, ends with a non-zero status (a crash:
    134) or showed an error in its message bar (but those containing one of the texts in
    ``spec["expected_bar_errors"]``)."""
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        raise RuntimeError("xvfb-run is missing: apt-get install xvfb xauth (make env does)")
    fd, out = tempfile.mkstemp(prefix="easyidp-desktop-", suffix=".json")
    os.close(fd)
    os.remove(out)
    spec = dict(spec, out=out, deadline=max(timeout - 30, timeout / 2))
    env = clean_env({"EASYIDP_DRIVER": json.dumps(spec), **(extra_env or {})})
    cmd = [xvfb, "-a", "-s", "-screen 0 1280x800x24", QGIS, "--noversioncheck", "--nologo",
           "--profiles-path", root, "--code", DRIVER]
    with subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True, start_new_session=True) as proc:   # its own process group
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
            exit_text = f"exit {proc.returncode}"
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)                        # Xvfb and QGIS too
            stdout, stderr = proc.communicate()
            exit_text = f"killed after {timeout:.0f} s"
    output = f"{stdout[-3000:]}\n{stderr[-8000:]}"     # room for the Python stacks of a crash
    found = _read_json(out) or {}
    partial = _read_json(out + ".partial") or {}
    if not found:
        quoted = "\n".join(partial.get("modal", []) + partial.get("python_errors", []))
        raise RuntimeError(f"the QGIS desktop wrote no result ({exit_text}) while "
                           f"{partial.get('doing', 'starting')}; dialogs and Python errors: "
                           f"{quoted or 'none'}\n{output}")
    if found.get("driver_error"):
        raise RuntimeError("the desktop driver failed:\n" + found["driver_error"])
    problems = []
    if proc.returncode != 0:
        crash = " (a crash: QGIS's crash handler aborted)" if proc.returncode in (134, -6) else ""
        problems.append(f"QGIS ended with exit status {proc.returncode}{crash} after Project ▸ "
                        f"Exit QGIS\n{output}")
    expected = spec.get("expected_bar_errors", [])
    bar_errors = [e for e in found.get("bar_errors", []) if not any(x in e for x in expected)]
    if bar_errors:
        problems.append("errors in the message bar:\n" + "\n".join(bar_errors))
    if problems:
        raise DesktopFailed("\n\n".join(problems), found)
    return found


class DesktopFailed(RuntimeError):
    """The desktop did what was asked but crashed or failed at its exit, or showed an error in
    its message bar: the message says which; ``found``: what it saw."""

    def __init__(self, message: str, found: dict):
        super().__init__(message)
        self.found = found


def _read_json(path: str) -> Optional[dict]:
    """The JSON object in ``path`` (then removed), or None when there is none."""
    if not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as fh:
        found = json.load(fh)
    os.remove(path)
    return found



def run_headless(root: str, args: List[str], timeout: float = 600) -> subprocess.CompletedProcess:
    """``qgis_process.bin ARGS`` on the profile, with QGIS's own Python only."""
    env = clean_env({"QT_QPA_PLATFORM": "offscreen", "QGIS_CUSTOM_CONFIG_PATH": root})
    return subprocess.run([QGIS_PROCESS, *args], env=env, capture_output=True, text=True,
                          timeout=timeout)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--screenshot", help="PNG of the message bar after installing the zip")
    what.add_argument("--screenshots", help="folder for the PNGs of a session with the tools")
    args = parser.parse_args(argv)
    if args.screenshots:
        shots = os.path.abspath(args.screenshots)
        with tempfile.TemporaryDirectory(prefix="easyidp-session-") as work:
            found = run_session(work, shots)
        for path in found["session"]["shots"]:
            print(path)
        return 0
    from .package import build
    with tempfile.TemporaryDirectory(prefix="easyidp-shot-") as tmp:
        zip_path, _ = build(os.path.join(tmp, "dist"))
        root = os.path.join(tmp, "qgis")
        install_zip(zip_path, root)
        found = run_desktop(root, {"screenshot": os.path.abspath(args.screenshot)})
    print(f"{args.screenshot}: the message bar said: {found['message']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
