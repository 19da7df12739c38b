"""make package: the zip's tree, and metadata.txt against the plugin repository's checks."""
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from easyidp_toolbox.scripts import package

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    path, warnings = package.build(str(out))
    unpacked = out / "unpacked"
    with zipfile.ZipFile(path) as zf:
        zf.extractall(unpacked)
    return Path(path), warnings, unpacked / "easyidp_toolbox"


def _tracked(pattern):
    out = subprocess.run(["git", "-C", str(ROOT), "ls-files", "--cached", "--others",
                          "--exclude-standard", pattern], capture_output=True, text=True).stdout
    return {p for p in out.split() if (ROOT / p).is_file()}


def test_zip_name_and_tree(built):
    path, _, plugin = built
    meta = package.read_metadata((ROOT / "metadata.txt").read_text())
    assert path.name == f"easyidp_toolbox-{meta['version']}.zip"
    files = {p.relative_to(plugin).as_posix() for p in plugin.rglob("*") if p.is_file()}
    expected = _tracked("core/*.py") | _tracked("easyidp_qgis/*.py") | _tracked("icons/*") | \
        {p[:-3] + ".qm" for p in _tracked("i18n/*.ts")} | {"__init__.py", "metadata.txt", "LICENSE"}
    assert files == expected
    assert "easyidp_qgis/install_packages.py" in files and "easyidp_qgis/dependencies.py" in files
    for part in ("tests/", "bench/", "scripts/", "docs/", "requirements/", ".ci/", "README",
                 "Makefile", ".ts", "__pycache__", ".pyc", ".venv", "demo_output"):
        assert not [f for f in files if part in f], part
    for py in plugin.rglob("*.py"):
        compile(py.read_text(encoding="utf-8"), str(py), "exec")
    assert (plugin / "metadata.txt").read_bytes() == (ROOT / "metadata.txt").read_bytes()
    licence = (plugin / "LICENSE").read_text()
    assert "MIT License" in licence and "Copyright (c) 2026 EasyIDP for QGIS contributors" in licence


def test_zip_passes_the_repository_checks(built):
    path, _, _ = built
    assert package.check_zip(str(path)) == []
    with zipfile.ZipFile(path) as zf:
        assert zf.namelist()[0] == "easyidp_toolbox/"


def test_placeholders_are_reported_not_passed(built, tmp_path):
    _, warnings, _ = built
    for key in ("email", "repository", "tracker", "homepage"):
        assert any(w.startswith(f"metadata.txt: {key} ") and "placeholder" in w
                   for w in warnings), key
    with pytest.raises(ValueError, match="placeholder"):
        package.build(str(tmp_path), strict=True)
    assert not list(tmp_path.iterdir())


GOOD = {"name": "X", "description": "d", "about": "a", "version": "0.1.0",
        "qgisMinimumVersion": "3.22", "qgisMaximumVersion": "4.99", "author": "A B",
        "email": "a@b.org",
        "tracker": "https://github.com/o/r/issues", "repository": "https://github.com/o/r",
        "changelog": "0.1.0 first", "hasProcessingProvider": "yes", "icon": "icons/i.svg"}


@pytest.mark.parametrize("change, message", [
    ({"tracker": ""}, "tracker is required"),
    ({"version": "0.1.0-beta"}, "dotted numbers"),
    ({"version": "1.0.2000"}, "dotted numbers"),
    ({"changelog": "0.0.9 older"}, "no entry for version 0.1.0"),
    ({"qgisMinimumVersion": "3"}, "QGIS 3 version"),
    ({"qgisMaximumVersion": ""}, "qgisMaximumVersion (missing) must be a QGIS 4 version, 4.99"),
    ({"qgisMaximumVersion": "3.99"}, "hide the plugin from QGIS 4 users"),
    ({"repository": "http://repo"}, "not a valid http(s) address"),
    ({"homepage": "github.com/o/r"}, "not a valid http(s) address"),
    ({"author": "A/B"}, "slash"),
    ({"email": "nobody"}, "not an address"),
    ({"experimental": "maybe"}, "True or False"),
    ({"hasProcessingProvider": "no"}, "hasProcessingProvider"),
])
def test_bad_metadata_is_refused(change, message):
    errors, _ = package.check_metadata(dict(GOOD, **change), ["icons/i.svg", "LICENSE"])
    assert any(message in e for e in errors), errors


def test_good_metadata_and_missing_files():
    assert package.check_metadata(GOOD, ["icons/i.svg", "LICENSE"]) == ([], [])
    errors, _ = package.check_metadata(GOOD, ["__init__.py"])
    assert any("icon icons/i.svg" in e for e in errors) and any("LICENSE" in e for e in errors)
    _, warnings = package.check_metadata(dict(GOOD, homepage="https://www.example.com/x"), [])
    assert warnings and "homepage" in warnings[0]



def test_the_plugin_declares_qgis_4():
    meta = package.read_metadata((ROOT / "metadata.txt").read_text())
    assert meta["qgisMaximumVersion"] == "4.99"


def test_bandit_refuses_a_high_severity_finding(tmp_path):
    """The security scan is real: a planted shell command built from input is refused."""
    planted = tmp_path / "planted.zip"
    with zipfile.ZipFile(planted, "w") as zf:
        zf.writestr("easyidp_toolbox/run.py", "import subprocess\n\n\ndef run(name):\n"
                    "    return subprocess.call('ls ' + name, shell=True)\n")
    found = package.security_scan(str(planted))
    assert len(found) == 1 and found[0].startswith("easyidp_toolbox/run.py:5 B602: ")
    built_zip = package.build(str(tmp_path / "dist"))[0]
    assert package.security_scan(built_zip) == []        # the plugin itself: nothing high


def test_make_package_command_runs(tmp_path):
    """The command `make package` runs (as the Makefile spells it) and writes only the zip."""
    assert "-m easyidp_toolbox.scripts.package --output" in (ROOT / "Makefile").read_text()
    run = subprocess.run([sys.executable, "-m", "easyidp_toolbox.scripts.package", "--output",
                          str(tmp_path)], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    version = package.read_metadata((ROOT / "metadata.txt").read_text())["version"]
    assert [p.name for p in tmp_path.iterdir()] == [f"easyidp_toolbox-{version}.zip"]
