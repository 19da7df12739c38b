"""install_packages.py run by QGIS's own interpreter (Debian's /usr/bin/python3 with Debian's numpy
and GDAL, no tifffile or laspy: numpy 1.24 on Debian 12, 2.2 on Debian 13) with real pip against
the configured package index."""
import os
import subprocess
import sys
from pathlib import Path

import numpy

from easyidp_toolbox.easyidp_qgis import install_packages as ip

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "easyidp_qgis" / "install_packages.py"
QGIS_PYTHON = "/usr/bin/python3"
QGIS_NUMPY = subprocess.run([QGIS_PYTHON, "-c", "import numpy; print(numpy.__version__)"],
                            capture_output=True, text=True, check=True).stdout.strip()


def run(args, **env):
    clean = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    clean.update(env)
    return subprocess.run([QGIS_PYTHON, str(SCRIPT), *args], env=clean, capture_output=True,
                          text=True, timeout=600)


def test_constraints_pin_the_environment_but_not_the_request_or_the_folder(tmp_path):
    target = tmp_path / "packages"
    info = target / "fakepkg-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fakepkg\nVersion: 1.0\n")
    sys.path.insert(0, str(target))
    try:
        pins = ip.constraints(str(target), {"pytest", "numpy"})
    finally:
        sys.path.remove(str(target))
    assert f"numpy=={numpy.__version__}" in pins  # QGIS's numpy: pinned even when requested
    assert not any(p.startswith(("pytest==", "fakepkg==")) for p in pins)
    import pyproj
    assert f"pyproj=={pyproj.__version__}" in pins


def test_dry_run_resolves_around_qgis_numpy(tmp_path):
    target = tmp_path / "packages"
    proc = run(["--dry-run", "--target", str(target), "plyfile>=1.0", "laspy>=2.5"])
    assert proc.returncode == 0, proc.stdout + proc.stderr
    plan = next(line for line in proc.stdout.splitlines() if line.startswith("To install: "))
    names = [p.split()[0].lower() for p in plan[len("To install: "):].split(", ")]
    assert "plyfile" in names and "laspy" in names and "numpy" not in names
    assert "Requirement already satisfied: numpy" in proc.stdout and QGIS_NUMPY in proc.stdout
    assert "::progress" in proc.stdout and not target.exists()


def test_qgis_packages_are_never_installed(tmp_path):
    proc = run(["--target", str(tmp_path / "p"), "numpy>=2"])
    assert proc.returncode == 1
    assert "ERROR: QGIS's own packages are never installed here: numpy" in proc.stdout
    assert not (tmp_path / "p").exists()


def test_qgis_pyproj_and_pyqt_are_kept_even_when_asked_for(tmp_path):
    """pyproj and PyQt are QGIS's: pinned even when requested, so a newer one is refused by pip
    instead of shadowing QGIS's copy."""
    pins = ip.constraints(str(tmp_path / "p"), {"pyproj", "pyqt5"})
    import pyproj
    assert f"pyproj=={pyproj.__version__}" in pins
    assert [p for p in pins if p.lower().startswith("pyqt5==")]
    proc = run(["--target", str(tmp_path / "p"), "pyproj>=99"])
    assert proc.returncode == 1 and "ERROR: pip failed" in proc.stdout
    assert not (tmp_path / "p").exists()


def test_a_failed_install_leaves_the_folder_as_it_was(tmp_path):
    target = tmp_path / "packages"
    target.mkdir()
    (target / "keep.txt").write_text("x")
    empty = tmp_path / "empty"
    empty.mkdir()
    proc = run(["--target", str(target), "easyidp-no-such-package>=1"],
               PIP_NO_INDEX="1", PIP_FIND_LINKS=str(empty))
    assert proc.returncode == 1 and "ERROR: pip failed" in proc.stdout
    assert "easyidp-no-such-package" in proc.stdout
    assert sorted(os.listdir(tmp_path)) == ["empty", "packages"]  # no staging folder left
    assert os.listdir(target) == ["keep.txt"]


def test_an_upgrade_replaces_the_older_copy(tmp_path):
    target = tmp_path / "packages"
    assert run(["--target", str(target), "pyshp==2.3.1"]).returncode == 0
    assert [p.name for p in target.glob("*.dist-info")] == ["pyshp-2.3.1.dist-info"]
    again = run(["--target", str(target), "pyshp==2.3.1"])
    assert "Nothing to install" in again.stdout
    proc = run(["--target", str(target), "pyshp>=3"])
    assert proc.returncode == 0, proc.stdout
    infos = [p.name for p in target.glob("*.dist-info")]
    assert len(infos) == 1 and infos[0].startswith("pyshp-3.")
    version = subprocess.run([QGIS_PYTHON, "-c", "import shapefile; print(shapefile.__version__)"],
                             env={"PYTHONPATH": str(target), "PATH": os.environ["PATH"]},
                             capture_output=True, text=True).stdout.strip()
    assert version == infos[0][len("pyshp-"):-len(".dist-info")]
    assert not list(tmp_path.glob(".staging-*"))
