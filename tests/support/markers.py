"""The test markers, applied from the conftest hooks by path and fixture (not written on tests).

- ``realdata``: the test, or a fixture it uses, needs the ``realdata`` fixture or reads
  ``REALDATA`` (the real test data: ``make realdata``, ``EASYIDP_REALDATA``);
- ``reference``: the test, or a fixture it uses, runs easyidp 2.0.4 (``REF_PYTHON``,
  ``require_reference``, ``reference_env`` of ``scripts/reference.py``: ``.venv-ref``);
- ``qgis``: every test of ``tests/qgis`` (real QGIS, qgis_process);
- ``desktop``: the QGIS desktop under Xvfb (``DESKTOP_MODULES``);
- ``unit``: a test of ``tests/core`` with none of the above, that does not generate the demo
  survey or season (``GENERATED_NAMES``: tens of seconds each) and is not in ``NOT_UNIT``: what
  ``make check`` runs, with no root, no QGIS, no real data and no reference environment. The
  others run in ``make test``.
"""

from pathlib import Path
from typing import Iterable, Set

MARKERS = {
    "unit": "tests/core without real data, easyidp 2.0.4 or the network (make check)",
    "realdata": "reads the real test data (make realdata; EASYIDP_REALDATA)",
    "reference": "runs easyidp 2.0.4 in its own environment (.venv-ref, make env-ref)",
    "qgis": "runs inside real QGIS or through qgis_process (tests/qgis)",
    "desktop": "runs the QGIS desktop under Xvfb",
}
REALDATA_NAMES = {"realdata", "REALDATA"}
REFERENCE_NAMES = {"REF_PYTHON", "require_reference", "reference_env"}
# a generated survey or season (tens of seconds each): not unit, run by make test
GENERATED_NAMES = {"make_demo_survey", "make_demo_season"}
DESKTOP_MODULES = {"test_desktop.py", "test_install_from_zip.py"}
# tests/core modules that are not unit tests, with the reason
NOT_UNIT = {
    "test_wheel.py": "builds the wheel and installs it into fresh venvs from the registry",
    "test_thermal_exiftool.py": "runs Debian's exiftool (libimage-exiftool-perl, make apt)",
}


def register(config) -> None:
    for name, text in MARKERS.items():
        config.addinivalue_line("markers", f"{name}: {text}")


def _code_names(code) -> Set[str]:
    """The names a code object reads, with its nested functions' and lambdas'."""
    names = set(code.co_names)
    for const in code.co_consts:
        if hasattr(const, "co_names"):
            names.update(const.co_names)
    return names


def _names_used(item) -> Set[str]:
    """Global names read by the test function and by every fixture it uses (their code only)."""
    names: Set[str] = set(item.fixturenames)
    funcs = [getattr(item, "function", None)]
    info = getattr(item, "_fixtureinfo", None)
    for defs in getattr(info, "name2fixturedefs", {}).values():
        funcs += [getattr(d, "func", None) for d in defs]
    for func in funcs:
        code = getattr(func, "__code__", None)
        if code is None:
            continue
        names.update(_code_names(code))
        # the functions it calls by name, one level down (a helper that runs the reference)
        for name in code.co_names:
            called = getattr(func, "__globals__", {}).get(name)
            if callable(called) and hasattr(called, "__code__"):
                names.update(_code_names(called.__code__))
    return names


def apply(items: Iterable, suite: str, folder: Path) -> None:
    """Mark the ``items`` under ``folder``, the tests of ``suite`` ("core" or "qgis")."""
    import pytest

    for item in items:
        path = Path(str(item.fspath))
        if folder not in path.parents:
            continue
        module = path.name
        used = _names_used(item)
        kinds = set()
        if used & REALDATA_NAMES:
            kinds.add("realdata")
        if used & REFERENCE_NAMES:
            kinds.add("reference")
        if suite == "qgis":
            kinds.add("qgis")
            if module in DESKTOP_MODULES:
                kinds.add("desktop")
        elif not kinds and module not in NOT_UNIT and not used & GENERATED_NAMES:
            kinds.add("unit")
        for kind in sorted(kinds):
            item.add_marker(getattr(pytest.mark, kind))
