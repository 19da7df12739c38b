"""pip install for the engine: the wheel pyproject.toml builds, and `pip install .`, in a fresh
venv without QGIS (packages from the registry), then a crop and a back-projection through the
public API of the installed package.

Truth kinds: the crops are checked against the orthomosaic read by tifffile in the venv (an
independent reader, pixel for pixel); the back-projection's whole-plot photo sets against the demo
survey's truth (the generator's own record of which photos hold each plot). Not a unit test
(conftest.py leaves it out of make check): it downloads packages and takes about a minute.
"""

import json
import os
import re
import subprocess
import sys
import textwrap
import venv
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

# Run inside the fresh venv: prints a JSON summary.
CHECK = textwrap.dedent("""
    import json, sys
    import numpy as np
    import tifffile
    try:
        import qgis  # noqa: F401
        sys.exit("qgis is importable in the fresh venv")
    except ImportError:
        pass
    import easyidp_toolbox
    from easyidp_toolbox import core
    from easyidp_toolbox.core import open_reconstruction, open_rois
    from easyidp_toolbox.core.projection import back_project
    from easyidp_toolbox.core.raster import DSM, crop_raster_by_rois

    ortho, plots, dsm, psx, out = sys.argv[1:6]
    rois = open_rois(plots, name_field="plot_id")
    crop = crop_raster_by_rois(ortho, rois, out)

    def origin(tif):
        page = tif.pages[0]
        tie = page.tags["ModelTiepointTag"].value
        scale = page.tags["ModelPixelScaleTag"].value
        return tie[3], tie[4], scale[0], scale[1]

    with tifffile.TiffFile(ortho) as tif:
        big = tif.asarray()
        x0, y0, sx, sy = origin(tif)
    worst = 0
    for path in crop.files:
        with tifffile.TiffFile(path) as tif:
            small = tif.asarray()
            cx, cy, _, _ = origin(tif)
        col, row = int(round((cx - x0) / sx)), int(round((y0 - cy) / sy))
        window = big[row:row + small.shape[0], col:col + small.shape[1]]
        inside = small[..., -1] > 0              # alpha: pixels whose centre is in the plot
        worst = max(worst, int(np.abs(small[..., :3][inside].astype(int)
                                      - window[..., :3][inside].astype(int)).max()))
    recon = open_reconstruction(psx)
    res = back_project(rois, recon, heights=DSM(dsm), clip=False, min_visible=0)
    whole = {name: sorted({p.rsplit("/", 1)[-1].rsplit(".", 1)[0]
                           for p in res.photo[res.records_of(name)]}) for name in rois.names}
    print(json.dumps({"version": core.__version__, "file": easyidp_toolbox.__file__,
                      "crops": len(crop.files), "rois": len(rois), "worst": worst,
                      "whole": whole}))
""")


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("wheel")
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "-q",
            "--disable-pip-version-check",
            "-w",
            str(out),
            str(ROOT),
        ],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    (path,) = out.glob("easyidp_toolbox-*.whl")
    return path


def _core_version():
    text = (ROOT / "core" / "__init__.py").read_text(encoding="utf-8")
    return re.search(r'^__version__ = "([^"]+)"$', text, re.MULTILINE).group(1)


def test_the_wheel_holds_the_engine_only(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    version = _core_version()
    assert wheel.name == f"easyidp_toolbox-{version}-py3-none-any.whl"
    tops = {n.split("/")[0] for n in names}
    assert tops == {"easyidp_toolbox", f"easyidp_toolbox-{version}.dist-info"}
    inside = {n.split("/")[1] for n in names if n.startswith("easyidp_toolbox/")}
    assert inside == {"__init__.py", "core"}  # no easyidp_qgis, scripts, tests, bench
    assert not [n for n in names if "__pycache__" in n or n.endswith(".pyc")]
    tracked = subprocess.run(
        ["git", "-C", str(ROOT), "ls-files", "core/*.py"], capture_output=True, text=True
    ).stdout.split()
    if tracked:  # a git checkout: every core module
        assert {f"easyidp_toolbox/{p}" for p in tracked} <= set(names)
    meta = zipfile.ZipFile(wheel).read(f"easyidp_toolbox-{version}.dist-info/METADATA").decode()
    requires = re.findall(r"^Requires-Dist: (.+)$", meta, re.MULTILINE)
    base = sorted(r.split(">")[0].split("=")[0] for r in requires if "extra ==" not in r)
    assert base == ["imagecodecs", "numpy", "pillow", "pyproj", "pyshp", "tifffile"]
    extras = set(re.findall(r"^Provides-Extra: (.+)$", meta, re.MULTILINE))
    assert extras == {"cloud", "photos", "dask", "opf", "all"}


def _fresh_venv(folder: Path) -> Path:
    venv.EnvBuilder(with_pip=True, system_site_packages=False, clear=True).create(folder)
    return folder / ("Scripts" if os.name == "nt" else "bin") / "python"


def _pip(python: Path, *args):
    run = subprocess.run(
        [str(python), "-m", "pip", "-q", "--disable-pip-version-check", *args],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr[-3000:]


def _run_check(python: Path, survey, out: Path) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PROJ_DATA", "PROJ_LIB")}
    run = subprocess.run(
        [
            str(python),
            "-c",
            CHECK,
            survey.orthomosaic,
            survey.plots_geojson,
            survey.dsm,
            survey.metashape_project,
            str(out),
        ],
        capture_output=True,
        text=True,
        cwd=str(out.parent),
        env=env,
    )
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


def _check_result(got: dict, survey, venv_dir: Path):
    assert got["version"] == _core_version()
    assert Path(got["file"]).resolve().is_relative_to(venv_dir.resolve())  # not the checkout
    assert got["crops"] == got["rois"] > 0
    assert got["worst"] == 0  # the crops are the ortho's own pixels
    plots = survey.truth_doc["plots"]
    assert got["whole"] == {name: sorted(plots[name]["photos_whole"]) for name in got["whole"]}


def test_wheel_and_pip_install_dot_in_a_fresh_venv(wheel, demo, tmp_path):
    """The wheel, then `pip install .` over it, into one fresh venv (dependencies from the
    registry; pip's cache may be warm). ``demo``: the small demo survey (conftest.py)."""
    python = _fresh_venv(tmp_path / "venv")
    _pip(python, "install", str(wheel))
    _check_result(_run_check(python, demo, tmp_path / "crops_wheel"), demo, tmp_path / "venv")
    _pip(python, "uninstall", "-y", "easyidp-toolbox")
    _pip(python, "install", str(ROOT))
    _check_result(_run_check(python, demo, tmp_path / "crops_dot"), demo, tmp_path / "venv")
