"""The plugin as a user installs it: its zip unpacked into a fresh QGIS profile, run by the real QGIS
desktop (under Xvfb) and by ``qgis_process``, with QGIS's own Python only (none of this
repository's environments). Used by ``tests/qgis/test_install_from_zip.py`` and to make the
README's screenshot:

    python -m easyidp_toolbox.scripts.qgis_desktop --screenshot docs/install_message_bar.png

The desktop runs ``desktop_driver.py`` (``qgis --code``), which does what ``spec`` asks and writes
what it saw to a JSON file.
"""
import argparse
import configparser
import json
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from typing import Dict, List, Optional

HERE = os.path.dirname(os.path.abspath(__file__))
DRIVER = os.path.join(HERE, "desktop_driver.py")
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
    return os.path.join(plugins, PLUGIN_ID)


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


def run_desktop(root: str, spec: dict, timeout: float = 600) -> dict:
    """Start the QGIS desktop on the profile under Xvfb; the driver follows ``spec`` (see
    desktop_driver.py) and its findings are returned."""
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        raise RuntimeError("xvfb-run is missing: apt-get install xvfb xauth (make env does)")
    fd, out = tempfile.mkstemp(prefix="easyidp-desktop-", suffix=".json")
    os.close(fd)
    os.remove(out)
    spec = dict(spec, out=out)
    env = clean_env({"EASYIDP_DRIVER": json.dumps(spec)})
    cmd = [xvfb, "-a", "-s", "-screen 0 1280x800x24", QGIS, "--noversioncheck", "--nologo",
           "--profiles-path", root, "--code", DRIVER]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    if not os.path.exists(out):
        raise RuntimeError(f"the QGIS desktop wrote no result (exit {proc.returncode}):\n"
                           f"{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    with open(out, encoding="utf-8") as fh:
        found = json.load(fh)
    os.remove(out)
    if found.get("driver_error"):
        raise RuntimeError("the desktop driver failed:\n" + found["driver_error"])
    return found


def run_headless(root: str, args: List[str], timeout: float = 600) -> subprocess.CompletedProcess:
    """``qgis_process.bin ARGS`` on the profile, with QGIS's own Python only."""
    env = clean_env({"QT_QPA_PLATFORM": "offscreen", "QGIS_CUSTOM_CONFIG_PATH": root})
    return subprocess.run([QGIS_PROCESS, *args], env=env, capture_output=True, text=True,
                          timeout=timeout)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--screenshot", required=True, help="PNG of the message bar to write")
    args = parser.parse_args(argv)
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
