"""Running ``qgis_process`` headless with this plugin loaded (used by the demo and the tests).

Debian's ``/usr/bin/qgis_process`` wrapper is broken, so ``qgis_process.bin`` is called. The
plugin is found through ``QGIS_PLUGINPATH`` (``.plugins/easyidp_toolbox`` links to this tree),
enabled in an isolated profile (``QGIS_CUSTOM_CONFIG_PATH``), and sees the project's Python
packages through ``PYTHONPATH``.
"""
import json
import os
import shutil
import subprocess
import sysconfig
import tempfile
from typing import Dict, List, Optional

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLUGINS = os.path.join(ROOT, ".plugins")
EXE = shutil.which("qgis_process.bin") or "/usr/bin/qgis_process.bin"


def qgis_process_env(profile_dir: Optional[str] = None) -> Dict[str, str]:
    """Environment for qgis_process with the plugin enabled in a fresh profile."""
    env = dict(os.environ)
    env.update(QT_QPA_PLATFORM="offscreen", QGIS_PLUGINPATH=PLUGINS,
               QGIS_CUSTOM_CONFIG_PATH=profile_dir or tempfile.mkdtemp(prefix="easyidp-qgis-"),
               PROJ_DATA=env.get("PROJ_DATA", "/usr/share/proj"),
               PYTHONPATH=os.pathsep.join(filter(None, [sysconfig.get_paths()["purelib"],
                                                        env.get("PYTHONPATH")])))
    if not os.path.isdir(os.path.join(PLUGINS, "easyidp_toolbox")):
        os.makedirs(PLUGINS, exist_ok=True)
        os.symlink(ROOT, os.path.join(PLUGINS, "easyidp_toolbox"))
    subprocess.run([EXE, "plugins", "enable", "easyidp_toolbox"], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return env


def run(args: List[str], env: Dict[str, str], timeout: float = 600) -> subprocess.CompletedProcess:
    """``qgis_process.bin ARGS`` with captured text output."""
    return subprocess.run([EXE, *args], env=env, capture_output=True, text=True, timeout=timeout)


def run_algorithm(alg: str, params: Dict[str, object], env: Dict[str, str]) -> dict:
    """Run one algorithm with ``--json``; returns its results, raises RuntimeError with stderr."""
    args = ["--json", "run", alg, "--"] + [f"{k}={v}" for k, v in params.items()]
    proc = run(args, env)
    if proc.returncode != 0:
        raise RuntimeError(f"qgis_process {alg} failed ({proc.returncode}):\n{proc.stderr.strip()}")
    return json.loads(proc.stdout)["results"]
