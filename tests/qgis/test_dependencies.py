"""The dependency table and the checks derived from it, in real QGIS (offscreen).

The install itself (pip, the message bar, qgis_process in a fresh profile) is tested in
test_install_packages.py and test_install_from_zip.py.
"""
import ast
import re
import shlex
import sys
from pathlib import Path

import pytest
from qgis.core import QgsProcessingContext, QgsProcessingException, QgsProcessingFeedback

from easyidp_toolbox.easyidp_qgis import dependencies as deps
from easyidp_toolbox.easyidp_qgis.algorithms import ALGORITHMS

ROOT = Path(__file__).resolve().parents[2]
# QGIS's own modules need no row; pip is what install_packages.py runs (and checks for)
QGIS_OWN = {"qgis", "PyQt5", "osgeo", "processing", "pip"}


def _third_party_imports():
    """Top-level modules imported (absolutely) anywhere in core/ and easyidp_qgis/."""
    found = {}
    for path in sorted([*ROOT.glob("core/**/*.py"), *ROOT.glob("easyidp_qgis/**/*.py")]):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                names = [node.module]
            for name in names:
                top = name.split(".")[0]
                if top not in sys.stdlib_module_names and top not in QGIS_OWN:
                    found.setdefault(top, str(path.relative_to(ROOT)))
    return found


def test_every_imported_package_has_a_row():
    """The one place: a package imported by the plugin without a row in DEPENDENCIES fails."""
    rows = {d.module for d in deps.DEPENDENCIES}
    missing_rows = {m: p for m, p in _third_party_imports().items() if m not in rows}
    assert not missing_rows, f"add these to easyidp_qgis/dependencies.py: {missing_rows}"


def test_table_is_well_formed():
    names = {cls.NAME for cls in ALGORITHMS}
    modules = [d.module for d in deps.DEPENDENCIES]
    assert len(modules) == len(set(modules))
    qgis_txt = (ROOT / "requirements" / "qgis.txt").read_text()
    for dep in deps.DEPENDENCIES:
        assert dep.tools == deps.ALL or set(dep.tools) <= names, dep
        deps.version_satisfies("1.0", dep.specifier)  # every clause is one we can evaluate
        assert deps.canonical(dep.distribution) in deps.canonical(qgis_txt), \
            f"{dep.distribution} is not in requirements/qgis.txt (the test environment)"
    assert {"numpy", "gdal"} == set(deps.PROTECTED)
    from easyidp_toolbox.easyidp_qgis import install_packages
    assert deps.PROTECTED == install_packages.PROTECTED and deps.KEPT == install_packages.KEPT


def test_version_comparison_agrees_with_packaging():
    """Independent check: pip's own rules (packaging.specifiers) on release versions."""
    from packaging.specifiers import SpecifierSet
    versions = ["0.9", "1", "1.0", "1.0.0", "1.2", "1.24.2", "1.26.4", "2", "2.0.1", "10.1",
                "2023.7.10", "2026.3.3"]
    specs = [">=1.24", "<2", ">=1.24,<2", "==1.0", "!=1.0", ">1.0", "<=1.2", ">=2023.7.10",
             "", "==1.0.0"]
    for v in versions:
        for s in specs:
            assert deps.version_satisfies(v, s) == (v in SpecifierSet(s)), (v, s)
    assert deps.version_satisfies("3.6.2+dfsg", ">=3.4")
    with pytest.raises(ValueError):
        deps.version_satisfies("1.0", "~=1.0")


def test_requirement_parts():
    row = deps.Dependency("distributed", "dask[distributed]>=2024.1", deps.TOOLS)
    assert (row.distribution, row.specifier) == ("dask", ">=2024.1")
    assert deps.Dependency("shapefile", "pyshp>=2.3", ()).needed_by(None) is False
    assert deps.Dependency("numpy", "numpy", deps.ALL).needed_by("anything")


# The table before the tools declared REQUIRES (dependencies.py, 2026-12-03): which tools each
# row named. Frozen here as data, for the derived table to give the same answers.
_RASTER = ("croprasterbyrois", "roiheightsfromdsm", "camerafootprints", "pointcloudroistatistics",
           "createdemosurvey", "seasontraits", "backprojectrois", "forwardprojectpolygons",
           "orthorectifyrois", "photostatistics", "fitplotgrid", "exporttrainingset")
_CLOUD = ("croppointcloudbyrois", "pointcloudroistatistics", "createdemosurvey", "seasontraits")
OLD_TOOLS = {
    "numpy": deps.ALL, "pyproj": deps.ALL, "tifffile": _RASTER, "imagecodecs": _RASTER,
    "laspy": _CLOUD, "lazrs": _CLOUD, "plyfile": _CLOUD, "shapefile": (),
    "scipy": ("orthorectifyrois",), "shapely": ("forwardprojectpolygons",),
    "skimage": ("seasontraits", "photostatistics", "forwardprojectpolygons"),
    # Pillow: the photo tools since core.photos reads headers with it (issue 39)
    "PIL": ("photostatistics", "backprojectrois", "camerafootprints", "exporttrainingset",
            "forwardprojectpolygons", "orthorectifyrois"),
    "matplotlib": ("seasontraits",), "dask": (), "pyopf": (),
}


def test_the_derived_table_answers_as_the_old_one(monkeypatch):
    """[consistency only: the old table, frozen above] For every tool and every row, whether the
    tool needs the package, and what ``missing`` reports for it when every package is too old,
    are as before."""
    assert {d.module for d in deps.DEPENDENCIES} == set(OLD_TOOLS)
    for dep in deps.DEPENDENCIES:
        old = OLD_TOOLS[dep.module]
        assert dep.needed_by(None) == (old == deps.ALL or bool(old)), dep.module
        if old == deps.ALL or old == ():
            assert dep.tools == old, dep.module
        else:
            assert set(dep.tools) == set(old), dep.module
        for cls in ALGORITHMS:
            assert dep.needed_by(cls.NAME) == (old == deps.ALL or cls.NAME in old), \
                (dep.module, cls.NAME)
            assert dep.needed_by(cls.NAME) == (dep.module in cls.REQUIRES
                                               or dep.scope == deps.ALL), (dep.module, cls.NAME)
    rows = tuple(deps.Dependency(d.module, f"{d.distribution}>=9999", d.scope, d.needs_shipped,
                                 d.python) for d in deps.DEPENDENCIES)
    monkeypatch.setattr(deps, "DEPENDENCIES", rows)
    for tool in [cls.NAME for cls in ALGORITHMS] + [None]:
        expected = [d.module for d in rows if d.fits_here() and (
            OLD_TOOLS[d.module] == deps.ALL or (tool in OLD_TOOLS[d.module] if tool
                                                 else bool(OLD_TOOLS[d.module])))]
        assert [m.dependency.module for m in deps.missing(tool)] == expected, tool


def test_every_tool_declares_its_packages_and_each_has_a_row():
    """[consistency only] Each algorithm class sets its own REQUIRES (a tuple of import names),
    every name has a TOOLS row, and every TOOLS row is required by some tool."""
    rows = {d.module: d for d in deps.DEPENDENCIES}
    for cls in ALGORITHMS:
        assert "REQUIRES" in vars(cls), f"{cls.__name__} does not declare REQUIRES"
        assert isinstance(cls.REQUIRES, tuple) and len(set(cls.REQUIRES)) == len(cls.REQUIRES)
        for module in cls.REQUIRES:
            assert module in rows and rows[module].scope == deps.TOOLS, (cls.NAME, module)
    for dep in deps.DEPENDENCIES:
        assert (dep.scope == deps.TOOLS) == bool(deps.tools_requiring(dep.module)), dep.module
    with pytest.raises(ValueError, match="REQUIRES"):
        deps.Dependency("laspy", "laspy>=2", ("croppointcloudbyrois",))


def test_the_plugin_start_checks_without_importing_the_tools():
    """The desktop's start (the message bar: ``missing()``) and the provider's load failure
    (ALL rows) never need the algorithms, which may be what failed to import."""
    code = ("import sys; from easyidp_toolbox.easyidp_qgis import dependencies as d; "
            "d.missing(); d.missing(include_extras=True); d.install_hint(); "
            "print(any(m.startswith('easyidp_toolbox.easyidp_qgis.algorithms') "
            "for m in sys.modules))")
    import subprocess
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT.parent, check=True)
    assert out.stdout.strip() == "False", out.stderr


def test_nothing_missing_in_the_test_environment():
    assert deps.missing() == [] and deps.missing(include_extras=True) == []


def test_missing_and_too_old_are_reported(monkeypatch):
    rows = (deps.Dependency("easyidp_no_such_module", "easyidp-no-such-package>=1", deps.ALL),
            deps.Dependency("numpy", "numpy>=99", deps.ALL),
            deps.Dependency("laspy", "laspy>=99", deps.TOOLS))
    monkeypatch.setattr(deps, "DEPENDENCIES", rows)
    found = deps.missing()
    assert [m.dependency.module for m in found] == ["easyidp_no_such_module", "numpy", "laspy"]
    import numpy
    assert found[1].installed == numpy.__version__ and found[1].protected
    assert [m.dependency.module for m in deps.missing("croprasterbyrois")] == \
        ["easyidp_no_such_module", "numpy"]
    text = deps.tool_message("Some tool", found, headless=True)
    assert f"numpy {numpy.__version__} (needs >=99)" in text and "Nothing was installed" in text
    assert "use a newer QGIS" in text
    argv = deps.install_argv(found)
    assert "numpy>=99" not in argv  # QGIS's numpy is never installed
    assert argv[-2:] == ["easyidp-no-such-package>=1", "laspy>=99"]
    assert deps.format_command(argv) in text


def test_a_row_that_does_not_fit_this_qgis_is_left_out(monkeypatch):
    """pyopf asks for Pillow >= 10 (metadata only); where QGIS ships an older Pillow (Debian 12)
    installing it beside QGIS would fail the whole install, so the row is not offered there."""
    import PIL
    row = next(d for d in deps.DEPENDENCIES if d.module == "pyopf")
    assert row.needs_shipped == ("pillow", ">=10") and row.tools == () and row.python == ">=3.10"
    assert row.fits_here() == (deps.version_satisfies(PIL.__version__, ">=10")
                               and sys.version_info >= (3, 10))
    rows = (deps.Dependency("easyidp_no_such_module", "easyidp-no-such-package>=1", (),
                            ("pillow", ">=9999")),
            deps.Dependency("easyidp_no_such_other", "easyidp-no-such-other>=1", (),
                            ("pillow", ">=1")),
            deps.Dependency("easyidp_no_such_third", "easyidp-no-such-third>=1", (),
                            ("easyidp-not-shipped", ">=1")),
            deps.Dependency("easyidp_no_such_fourth", "easyidp-no-such-fourth>=1", (), (),
                            ">=99.0"))
    monkeypatch.setattr(deps, "DEPENDENCIES", rows)
    assert [m.dependency.module for m in deps.missing(include_extras=True)] == \
        ["easyidp_no_such_other", "easyidp_no_such_third"]


def test_a_tool_refuses_to_run_and_names_the_package(plugin, realdata, tmp_path, monkeypatch):
    rows = tuple(deps.Dependency(d.module, "tifffile>=9999", d.scope) if d.module == "tifffile"
                 else d for d in deps.DEPENDENCIES)
    monkeypatch.setattr(deps, "DEPENDENCIES", rows)
    import processing
    alg = plugin.provider.algorithm("croprasterbyrois")
    ok, message = alg.canExecute()
    assert not ok and "tifffile" in message and "Nothing was installed" not in message
    with pytest.raises(QgsProcessingException) as err:
        processing.run("easyidp:croprasterbyrois", {
            "INPUT": str(realdata / "d2spy/dsm.tif"),
            "ROIS": str(realdata / "d2spy/feature_in_dsm.geojson"),
            "OUTPUT_FOLDER": str(tmp_path / "crops")},
            context=QgsProcessingContext(), feedback=QgsProcessingFeedback())
    text = str(err.value)
    assert "(needs >=9999)" in text and "Nothing was installed" in text
    assert "install_packages.py" in text and "--target" in text and deps.packages_dir() in text
    assert not (tmp_path / "crops").exists()
    # tools that do not need tifffile still run
    assert plugin.provider.algorithm("croppointcloudbyrois").canExecute()[0]


def test_import_error_message_and_install_hint():
    err = ModuleNotFoundError("No module named 'laspy'", name="laspy")
    text = deps.import_error_message(err)
    laspy = deps.dependency_for_module("laspy")
    assert deps.pinned_requirement(laspy) in text and "install_packages.py" in text
    unknown = deps.import_error_message(ModuleNotFoundError("x", name="somethingelse"))
    assert "somethingelse" not in deps.install_hint() and "QGIS's Python" in unknown
    from easyidp_toolbox.easyidp_qgis.algorithms.base import INSTALL_HINT
    for dep in deps.DEPENDENCIES:
        assert (deps.pinned_requirement(dep) in INSTALL_HINT) == (dep.distribution != "numpy")


def test_interpreter_and_folder():
    python = deps.python_executable()
    assert deps.check_python(python) is None
    folder = deps.activate("/tmp/easyidp-profile")
    assert sys.path[0] == folder and deps.activate("/tmp/easyidp-profile") == folder
    assert sys.path.count(folder) == 1
    sys.path.remove(folder)
    assert folder.endswith("python/easyidp_toolbox_packages/python{}.{}".format(*sys.version_info))
    argv = deps.install_argv([deps.Missing(deps.DEPENDENCIES[2], None)], target=folder)
    assert shlex.split(deps.format_command(argv)) == argv
    assert Path(argv[1]).name == "install_packages.py" and Path(argv[1]).is_file()
    win = deps.format_command([r"C:\Program Files\QGIS 3.34\apps\Python312\python.exe",
                               "x.py", "--target", r"C:\Users\a\p", "tifffile>=2023.7.10"],
                              windows=True)
    assert win == (r'"C:\Program Files\QGIS 3.34\apps\Python312\python.exe" x.py --target '
                   r'C:\Users\a\p "tifffile>=2023.7.10"')


def test_qgis_pyproj_is_never_replaced_but_installed_where_missing(monkeypatch):
    """QGIS's pyproj too old: reported as QGIS's, never shadowed by a copy in the package folder;
    no pyproj at all: installed like the others."""
    row = deps.Dependency("pyproj", "pyproj>=99", deps.ALL)
    monkeypatch.setattr(deps, "DEPENDENCIES", (row,))
    [old] = deps.missing()
    assert old.installed and old.protected and deps.installable([old]) == []
    assert "use a newer QGIS" in deps.install_instructions([old])
    absent = deps.Missing(row, None)
    assert not absent.protected and "'pyproj>=99'" in deps.install_instructions([absent])


def _qgis_txt_pins(python):
    """{distribution: version} that requirements/qgis.txt pins (==) for ``python`` (major,
    minor), its markers evaluated by pip's own packaging (the truth: not our parser)."""
    from pip._vendor.packaging.requirements import Requirement
    pins = {}
    qgis_txt = (ROOT / "requirements" / "qgis.txt").read_text()
    for line in qgis_txt.splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        req = Requirement(line)
        env = {"python_version": "%d.%d" % python, "python_full_version": "%d.%d.0" % python}
        if req.marker is None or req.marker.evaluate(env):
            for spec in req.specifier:
                if spec.operator == "==":
                    pins[deps.canonical(req.name)] = spec.version
    if python < (3, 12):   # the Makefile installs qgis.txt's pyopf there too, with --no-deps
        pins["pyopf"] = re.search(r"^pyopf==([0-9.]+)", qgis_txt, re.MULTILINE).group(1)
    return pins


@pytest.mark.parametrize("python", deps.TESTED_PYTHONS)
def test_the_pinned_table_is_what_the_tests_ran_with(python):
    pins = _qgis_txt_pins(python)
    rows = {deps.canonical(d.distribution): d for d in deps.DEPENDENCIES}
    for name in deps.TESTED:
        assert name in rows, name
        assert deps.tested_version(name, python) == pins[name], name
        assert deps.pinned_requirement(rows[name], python).endswith(f"=={pins[name]}")
        assert deps.version_satisfies(pins[name], rows[name].specifier), name
    # every pinned table package of requirements/qgis.txt is in TESTED (numpy is QGIS's own)
    table = set(rows) - set(deps.PROTECTED)
    assert {n for n in pins if n in table} == set(deps.TESTED)


def test_untested_pythons_get_a_range_below_the_next_major():
    rows = {d.distribution: d for d in deps.DEPENDENCIES}
    assert deps.pinned_requirement(rows["tifffile"], (3, 9)) == "tifffile>=2023.7.10,<2027"
    assert deps.pinned_requirement(rows["scikit-image"], (3, 12)) == "scikit-image>=0.22,<1"
    assert deps.pinned_requirement(rows["dask"], (3, 10)) == "dask[distributed]>=2024.1,<2027"
    assert deps.pinned_requirement(rows["dask"], (3, 11)) == "dask[distributed]==2026.8.0"
    assert deps.pinned_requirement(rows["plyfile"], (3, 11)) == "plyfile==1.0.3"
    assert deps.pinned_requirement(rows["plyfile"], (3, 14)) == "plyfile==1.1.3"
    assert deps.pinned_requirement(rows["scipy"], (3, 12)) == "scipy>=1.10"   # QGIS's own
    # what a fresh profile's Install runs: the pins of this Python
    argv = deps.install_argv([deps.Missing(rows["laspy"], None)], python="py", target="t")
    assert argv[-1] == deps.pinned_requirement(rows["laspy"])
