"""Install like a user: the zip into a fresh QGIS profile, QGIS's own Python only (Debian's numpy,
GDAL and pyproj: numpy 1.24 and GDAL 3.6 on Debian 12, numpy 2.2 and GDAL 3.10 on Debian 13; no
tifffile, imagecodecs, laspy, lazrs, plyfile), the real QGIS desktop under Xvfb and qgis_process.

In order: qgis_process refuses a tool and installs nothing; the desktop shows the message bar
with *Install*; the button is clicked three times: cancelled while pip waits on an index that
never answers, failed with no index at all, then installed from the configured package index;
qgis_process then creates the demo survey and crops it; a second desktop start shows no message.
"""
import json
import os
import shlex
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from easyidp_toolbox.easyidp_qgis import dependencies
from easyidp_toolbox.scripts.package import build
from easyidp_toolbox.scripts.qgis_desktop import (install_zip, profile_dir, run_desktop,
                                                  run_headless)


def _missing_on_debian(extras: bool):
    """Distributions of the dependency table (table order) that Debian's own Python lacks: what a
    fresh profile on this machine misses. ``extras``: include the script-only extras. Rows that
    do not fit this QGIS (``fits_here``: pyopf beside Debian 12's Pillow) are never installed."""
    rows = [d for d in dependencies.DEPENDENCIES
            if d.tools != dependencies.ALL and (d.tools or extras) and d.fits_here()]
    code = ("import importlib.util, sys\n"
            "print(' '.join(m for m in sys.argv[1:] if importlib.util.find_spec(m) is None))")
    out = subprocess.run(["/usr/bin/python3", "-c", code, *[d.module for d in rows]],
                         capture_output=True, text=True, check=True).stdout.split()
    return [d.distribution for d in rows if d.module in out]


NEEDED = _missing_on_debian(extras=False)      # tifffile, imagecodecs, laspy, lazrs, plyfile, …
# QGIS's interpreter (the one its Python is: Debian's python3.X) and the numpy it has
QGIS_PYTHON = "/usr/bin/python{}.{}".format(*sys.version_info[:2])
QGIS_NUMPY = subprocess.run(["/usr/bin/python3", "-c", "import numpy; print(numpy.__version__)"],
                            capture_output=True, text=True, check=True).stdout.strip()


@pytest.fixture(scope="module")
def profile(tmp_path_factory):
    """A fresh QGIS profile root with the plugin installed from its zip, and its package folder."""
    tmp = tmp_path_factory.mktemp("fresh")
    zip_path, _ = build(str(tmp / "dist"))
    root = tmp / "qgis"
    install_zip(zip_path, str(root))
    folder = dependencies.packages_dir(profile_dir(str(root)))
    return root, Path(folder)


@pytest.fixture(scope="module")
def silent_index():
    """A package index that accepts connections and never answers (pip waits on it)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(16)
    yield f"http://127.0.0.1:{server.getsockname()[1]}/simple"
    server.close()


@pytest.fixture(scope="module")
def first_start(profile, silent_index, tmp_path_factory):
    root, _ = profile
    empty = tmp_path_factory.mktemp("no-links")
    steps = [
        {"action": "cancel", "env": {"PIP_INDEX_URL": silent_index, "PIP_RETRIES": "0"}},
        {"action": "install", "env": {"PIP_NO_INDEX": "1", "PIP_FIND_LINKS": str(empty)}},
        {"action": "install"},
    ]
    # the second step's failure is shown in red, as it should be
    return run_desktop(str(root), {"steps": steps,
                                   "expected_bar_errors": ["Installing the Python packages failed"]})


def test_headless_with_packages_missing_installs_nothing(profile, realdata, tmp_path):
    root, folder = profile
    proc = run_headless(str(root), [
        "run", "easyidp:croprasterbyrois", "--", f"INPUT={realdata / 'd2spy/dsm.tif'}",
        f"ROIS={realdata / 'd2spy/feature_in_dsm.geojson'}", f"OUTPUT_FOLDER={tmp_path / 'c'}"])
    text = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert ("Crop raster by ROIs needs Python packages that QGIS's Python does not have: "
            "tifffile, imagecodecs.") in text
    assert "Nothing was installed" in text
    plugin_dir = Path(profile_dir(str(root))) / "python" / "plugins" / "easyidp_toolbox"
    tifffile = dependencies.pinned_requirement(dependencies.dependency_for_module("tifffile"))
    command = (f"{QGIS_PYTHON} {plugin_dir}/easyidp_qgis/install_packages.py --target "
               f"{folder} {shlex.quote(tifffile)}")    # the release the tests ran with
    assert command in text
    assert not folder.parent.exists() and not (tmp_path / "c").exists()


def test_desktop_shows_the_missing_packages_with_install(first_start, profile):
    _, folder = profile
    assert first_start["plugin_loaded"] and first_start["provider"]
    assert first_start["python"] == QGIS_PYTHON  # not sys.executable (a PATH lookup)
    assert first_start["packages_dir"] == str(folder) and first_start["packages_dir_first"]
    assert first_start["missing"] == NEEDED
    assert first_start["install_button"] and first_start["folder"] is None
    assert NEEDED[:5] == ["tifffile", "imagecodecs", "laspy", "lazrs", "plyfile"]
    assert first_start["bar"] == ["EasyIDP: Some tools need Python packages that QGIS's Python "
                                  f"lacks: {', '.join(NEEDED)}."]


def test_install_cancelled_while_pip_runs(first_start):
    step = first_start["steps"][0]
    assert step["install_button"] and step["progress_bar_shown"] and step["finished"]
    assert step["result"] == "cancelled" and step["seconds"] < 30
    assert step["process_group_alive"] is False  # the installer and its pip are gone
    assert "nothing was changed" in step["message"] and step["command"] in step["message"]
    assert step["folder"] is None or not [f for f in step["folder"] if "dist-info" in f]


def test_install_failure_says_the_command(first_start):
    step = first_start["steps"][1]
    assert step["result"] == "failed"
    assert "Run this command in a terminal to see why" in step["message"]
    assert step["command"] in step["message"] and "install_packages.py" in step["command"]
    assert any("No matching distribution" in line for line in step["output"])
    assert step["missing_after"] == _missing_on_debian(extras=True)
    assert step["current"] and "failed" in step["current"]


def test_install_from_the_package_index(first_start, profile):
    """Exactly the tools' packages, at the releases the tests ran with on this Python (the
    pinned table), and what pip resolved for them; the extras (Dask, OPF, pyshp) not asked for."""
    _, folder = profile
    step = first_start["steps"][2]
    assert step["result"] == "installed", json.dumps(step, indent=1)
    extras = [d for d in _missing_on_debian(extras=True) if d not in NEEDED]
    assert step["missing_after"] == extras
    installed = {}                                  # {distribution: version} in the folder
    for entry in step["folder"]:
        if entry.endswith(".dist-info"):
            name, version = entry[:-len(".dist-info")].rsplit("-", 1)
            installed[dependencies.canonical(name)] = version
    python = sys.version_info[:2]
    for name in NEEDED:
        assert dependencies.canonical(name) in installed, name
        pin = dependencies.tested_version(name, python)
        if python in dependencies.TESTED_PYTHONS and pin:
            assert installed[dependencies.canonical(name)] == pin, name
            assert f"{name} {pin}" in step["message"], name    # the bar said what it installed
    assert not {dependencies.canonical(n) for n in extras} & set(installed)
    listed = step["message"].split(": ", 1)[1].rstrip(".").split(", ")
    assert len(listed) > len(NEEDED)                  # what came with them is listed too
    assert not [f for f in step["folder"] if f.lower().startswith(("numpy", "gdal"))]
    for module, path in first_start["imported"].items():
        assert path.startswith(str(folder)), module  # usable at once, without a restart
    version, path = first_start["numpy"]
    assert version == QGIS_NUMPY and path.startswith("/usr/lib/python3/")   # QGIS's own


def test_headless_after_install_creates_and_crops_the_demo(first_start, profile, tmp_path):
    root, _ = profile
    assert first_start["steps"][2]["result"] == "installed"
    proc = run_headless(str(root), ["--json", "run", "easyidp:createdemosurvey", "--",
                                    f"OUTPUT_FOLDER={tmp_path / 'survey'}"])
    assert proc.returncode == 0, proc.stderr
    survey = json.loads(proc.stdout)["results"]
    proc = run_headless(str(root), [
        "--json", "run", "easyidp:croprasterbyrois", "--", f"INPUT={survey['ORTHOMOSAIC']}",
        f"ROIS={survey['PLOTS']}", "NAME_FIELD=plot_id", f"OUTPUT_FOLDER={tmp_path / 'crops'}"])
    assert proc.returncode == 0, proc.stderr
    results = json.loads(proc.stdout)["results"]
    assert results["CROPPED"] == 40 and len(list((tmp_path / "crops").glob("*.tif"))) == 40
    proc = run_headless(str(root), [
        "--json", "run", "easyidp:croppointcloudbyrois", "--", f"INPUT={survey['POINT_CLOUD']}",
        f"ROIS={survey['PLOTS']}", "NAME_FIELD=plot_id", f"OUTPUT_FOLDER={tmp_path / 'clouds'}"])
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["results"]["CROPPED"] == 40


def test_second_start_finds_everything_and_shows_nothing(first_start, profile):
    root, _ = profile
    assert first_start["steps"][2]["result"] == "installed"
    again = run_desktop(str(root), {})
    assert again["missing"] == [] and again["message"] == ""
    assert not again["install_button"]
    assert not [t for t in again["bar"] if t.startswith("EasyIDP")]
    assert again["provider"] and os.path.isdir(again["packages_dir"])


def test_headless_without_a_package_every_tool_needs(tmp_path, realdata):
    """A broken pyproj (importable, then failing) in the package folder: the provider cannot
    load; qgis_process says why on stderr, with the install command, and the run fails."""
    zip_path, _ = build(str(tmp_path / "dist"))
    root = tmp_path / "qgis"
    install_zip(zip_path, str(root))
    fake = Path(dependencies.packages_dir(profile_dir(str(root)))) / "pyproj"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text(
        "raise ModuleNotFoundError(\"No module named 'pyproj._core'\", name='pyproj._core')\n")
    proc = run_headless(str(root), [
        "run", "easyidp:croprasterbyrois", "--", f"INPUT={realdata / 'd2spy/dsm.tif'}",
        f"ROIS={realdata / 'd2spy/feature_in_dsm.geojson'}", f"OUTPUT_FOLDER={tmp_path / 'c'}"])
    assert proc.returncode != 0 and not (tmp_path / "c").exists()
    assert "EasyIDP: the tools could not load. No module named 'pyproj._core'" in proc.stderr
    assert "'pyproj>=3.4'" in proc.stderr and "install_packages.py" in proc.stderr
