"""Shared fixtures for the core tests (no QGIS). Real files are read from ../shared/realdata."""
import os
from pathlib import Path

import pytest

from easyidp_toolbox.tests.support import markers

ROOT = Path(__file__).resolve().parents[2]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))


def pytest_configure(config):
    # make test deselects (-m) what an environment does not have; a selected test never skips
    config.addinivalue_line("markers", "gdal: compares with GDAL's Python bindings (QGIS "
                            "environment only)")
    config.addinivalue_line("markers", "geopandas: uses geopandas (current-stack environment only)")
    markers.register(config)


def pytest_collection_modifyitems(config, items):
    """unit, realdata, reference: from each test's fixtures and names (tests/support/markers.py)."""
    markers.apply(items, "core", Path(__file__).resolve().parent)


@pytest.fixture(scope="session")
def realdata() -> Path:
    if not REALDATA.is_dir():
        pytest.fail(f"real test data not found at {REALDATA}: run make realdata (or set "
                    "EASYIDP_REALDATA to a folder that holds it); make check runs without it")
    return REALDATA


@pytest.fixture(scope="session")
def demo(tmp_path_factory):
    """The small demo survey (seed 0) and its truth, for the projection tests: the tidy field
    (``NO_MESS``). The messy default field (issue 32) is checked in test_demo_survey.py; moving
    these tests onto it needs truths that hold there (the nadir colour truth against oblique
    views of tall rows, grazing occlusion at row walls)."""
    import json
    from easyidp_toolbox.core.demo import NO_MESS, make_demo_survey
    s = make_demo_survey(str(tmp_path_factory.mktemp("projection_demo")), seed=0, size="small",
                         field_mess=NO_MESS)
    with open(s.truth) as fh:
        s.truth_doc = json.load(fh)
    return s
