"""make package: the zip's tree, metadata.txt against the plugin repository's checks, and the
repository's scan (Bandit, detect-secrets, qgis-plugin-analyzer) on the zip and on planted
findings. Truth kind: the scanners themselves (independent code) on code written here."""
import shutil
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
        "changelog": "0.1.0 first", "hasProcessingProvider": "yes", "icon": "icons/i.svg",
        "supportsQt6": "True"}


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
    ({"supportsQt6": ""}, "supportsQt6=True is needed"),
    ({"supportsQt6": "False"}, "supportsQt6=True is needed"),
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


def test_the_plugin_declares_qt6():
    meta = package.read_metadata((ROOT / "metadata.txt").read_text())
    assert meta["supportsQt6"] == "True"


def _tree_copy(dest: Path) -> Path:
    """The files make package takes, and CHANGELOG.md, copied into ``dest`` (not a git
    checkout: every file there is taken)."""
    for name in package.plugin_files(str(ROOT)) + ["CHANGELOG.md"]:
        (dest / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, dest / name)
    return dest


PLANTED_B314 = ("import xml.etree.ElementTree as ET\n\n\ndef read(data):\n"
                "    return ET.fromstring(data)\n")


def test_make_package_fails_on_a_planted_b314(tmp_path):
    """The command make package runs, on a copy of the tree with XML parsed by ElementTree:
    refused (B314, and its import B405), and no zip written."""
    tree = _tree_copy(tmp_path / "tree")
    (tree / "core" / "planted.py").write_text(PLANTED_B314)
    out = tmp_path / "dist"
    run = subprocess.run([sys.executable, "-m", "easyidp_toolbox.scripts.package", "--root",
                          str(tree), "--output", str(out)], capture_output=True, text=True,
                         cwd=ROOT)
    assert run.returncode == 1, run.stdout + run.stderr
    assert "scan would refuse the zip" in run.stderr
    assert "Bandit: core/planted.py:5 B314 (MEDIUM)" in run.stderr
    assert "Bandit: core/planted.py:1 B405 (LOW)" in run.stderr
    assert not out.exists() or not list(out.iterdir())


def test_the_plugin_passes_the_repository_scan(built):
    """The zip itself: no Bandit finding of the repository's rules at any severity, every
    # nosec with its reason, no secret, and the analyzer's repository checks pass; the only
    notes are the placeholder addresses the analyzer cannot reach."""
    path, _, _ = built
    errors, warnings = package.security_scan(str(path))
    assert errors == []
    assert all("example.org" in w for w in warnings), warnings


@pytest.mark.parametrize("source, rule", [
    (PLANTED_B314, "B314"),
    ("def login(user, password=\"hunter22\"):\n    return user, password\n", "B107"),
    ("TOKEN = 1\npassword = \"hunter22\"\n", "B105"),
    ("import subprocess\n\n\ndef run(name):\n"
     "    return subprocess.call(\"ls \" + name, shell=True)\n", "B602"),
])
def test_bandit_refuses_findings_of_every_severity(tmp_path, source, rule):
    """LOW findings block as MEDIUM and HIGH ones do (B105–B107 are LOW in Bandit)."""
    (tmp_path / "planted.py").write_text(source)
    found = package._bandit(str(tmp_path))
    assert any(f.startswith("Bandit: planted.py:") and f" {rule} " in f for f in found), found


def test_a_nosec_needs_its_rule_and_a_reason(tmp_path):
    code = PLANTED_B314.replace("    return ET.fromstring(data)", "    return ET.fromstring(data)  {}")
    (tmp_path / "bare.py").write_text(code.format("# nosec"))
    (tmp_path / "no_reason.py").write_text(code.format("# nosec B314"))
    (tmp_path / "reasoned.py").write_text(
        code.format("# nosec B314 -- the data is written by this module"))
    bad = package._unjustified_nosec(str(tmp_path))
    assert sorted(b.split(":")[0] for b in bad) == ["bare.py", "no_reason.py"]
    # Bandit honours the reasoned form: only the import (B405) is left in that file
    found = [f for f in package._bandit(str(tmp_path)) if "reasoned.py" in f]
    assert [f.split()[2] for f in found] == ["B405"], found


def test_detect_secrets_refuses_a_key(tmp_path):
    key = "AKIA" + "IOSFODNN7" + "QWERTYZ"              # an AWS access key id's shape
    (tmp_path / "settings.py").write_text(f"ACCESS = \"{key}\"\n")
    found = package._detect_secrets(str(tmp_path))
    assert found and found[0].startswith("detect-secrets: settings.py:1 AWS Access Key"), found


def test_metadata_out_of_step_is_refused(tmp_path):
    tree = _tree_copy(tmp_path / "tree")
    changelog = (tree / "CHANGELOG.md").read_text()
    (tree / "CHANGELOG.md").write_text(changelog.replace("- Create demo survey\n",
                                                         "- Create demo survey\n- more\n"))
    with pytest.raises(ValueError, match="out of step with core.__version__ and CHANGELOG.md"):
        package.build(str(tmp_path / "dist"), root=str(tree))


def test_make_package_command_runs(tmp_path):
    """The command `make package` runs (as the Makefile spells it) and writes only the zip."""
    assert "-m easyidp_toolbox.scripts.package --output" in (ROOT / "Makefile").read_text()
    run = subprocess.run([sys.executable, "-m", "easyidp_toolbox.scripts.package", "--output",
                          str(tmp_path)], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    version = package.read_metadata((ROOT / "metadata.txt").read_text())["version"]
    assert [p.name for p in tmp_path.iterdir()] == [f"easyidp_toolbox-{version}.zip"]
