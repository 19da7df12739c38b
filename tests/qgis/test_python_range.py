"""The Python range the plugin supports, 3.9 (QGIS 3.34–3.40 macOS installers) to 3.14 (Debian sid):
the engine and the plugin are written in Python 3.9's grammar, and the dependency table
(``easyidp_qgis/dependencies.py``) resolves to wheels for every Python of the range.

Truth kind: the reference implementations, not our code. Python's own parser with
``feature_version=(3, 9)`` for the syntax; pip's own resolver (``pip install --dry-run --report
--python-version X --only-binary=:all:``, what the installer runs, for another interpreter) for
the releases, against the package registry, with the numpy QGIS ships on that platform pinned as
the installer pins it. Older Pythons get older releases by their ``Requires-Python``
(tifffile, shapely, scikit-image, dask); no pin in the table may exclude them.
"""
import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest
from pip._vendor.packaging.specifiers import SpecifierSet

from easyidp_toolbox.easyidp_qgis import dependencies
from easyidp_toolbox.easyidp_qgis.dependencies import (DEPENDENCIES, PROTECTED, TESTED_PYTHONS,
                                                       canonical, pinned_requirement)

ROOT = Path(__file__).resolve().parents[2]
SUPPORTED = ((3, 9), (3, 14))
# the numpy each platform's QGIS ships with that Python (macOS 3.9 and OSGeo4W 3.12: 1.26;
# Debian 13: 2.2; sid and QGIS 4 on Windows: 2.4)
NUMPY = {(3, 9): "1.26.4", (3, 12): "1.26.4", (3, 13): "2.2.4", (3, 14): "2.4.6"}


def _sources():
    for folder in ("core", "easyidp_qgis", "scripts"):
        yield from sorted((ROOT / folder).rglob("*.py"))
    yield ROOT / "__init__.py"


def test_the_code_is_python_39_grammar():
    bad = []
    for path in _sources():
        try:
            ast.parse(path.read_text(encoding="utf-8"), str(path), feature_version=SUPPORTED[0])
        except SyntaxError as exc:
            bad.append(f"{path.relative_to(ROOT)}:{exc.lineno}: {exc.msg}")
    assert bad == []


def test_a_line_only_newer_pythons_parse_is_caught():
    """The check above can fail: a ``match`` statement (3.10) is refused with 3.9's grammar."""
    with pytest.raises(SyntaxError):
        ast.parse("match x:\n    case 1:\n        pass\n", feature_version=SUPPORTED[0])


@pytest.mark.parametrize("version", sorted(NUMPY), ids=lambda v: "python%d.%d" % v)
def test_the_dependency_table_resolves_to_wheels_for(version, tmp_path):
    # rows with releases for newer Pythons only (pyopf: 3.10) are left out of older ones
    rows = [d for d in DEPENDENCIES if not d.python or SpecifierSet(d.python).contains(
        "%d.%d" % version)]
    # what Install asks for on that Python: the tested pins, or a range below the next major
    reqs = [pinned_requirement(d, version) for d in rows
            if canonical(d.distribution) not in PROTECTED]
    (tmp_path / "pins.txt").write_text(f"numpy=={NUMPY[version]}\n")
    report = tmp_path / "report.json"
    proc = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--dry-run", "--quiet", "--ignore-installed",
         "--report", str(report), "--only-binary=:all:", "--target", str(tmp_path / "t"),
         "--python-version", "%d.%d" % version, "--platform", "manylinux2014_x86_64",
         "--platform", "manylinux_2_28_x86_64", "--constraint", str(tmp_path / "pins.txt"),
         f"numpy=={NUMPY[version]}", *reqs],
        capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    items = json.loads(report.read_text())["install"]
    got = {canonical(i["metadata"]["name"]): i["metadata"]["version"] for i in items}
    # every release chosen admits that Python (pip before 23.1 ignored Requires-Python here)
    refused = [f"{i['metadata']['name']} {i['metadata']['version']} ({i['metadata']['requires_python']})"
               for i in items if i["metadata"].get("requires_python") and
               not SpecifierSet(i["metadata"]["requires_python"]).contains("%d.%d" % version)]
    assert refused == []
    assert got["numpy"] == NUMPY[version]
    for dep in rows:
        assert canonical(dep.distribution) in got, (dep.requirement, version)
        pin = dependencies.tested_version(dep.distribution, version)
        if version in TESTED_PYTHONS and pin:
            assert got[canonical(dep.distribution)] == pin, (dep.distribution, version)
    print(f"\nPython {version[0]}.{version[1]}: " +
          ", ".join(f"{k} {v}" for k, v in sorted(got.items()) if k in
                    {canonical(d.distribution) for d in DEPENDENCIES}))


def test_the_range_is_the_one_the_readme_states():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "Python 3.9 to 3.14" in readme
    assert min(NUMPY) == SUPPORTED[0] and max(NUMPY) == SUPPORTED[1]
