"""Fixtures for the tests inside real QGIS (offscreen, pytest-qgis) and through qgis_process."""
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))
sys.path.insert(0, str(ROOT / "tests" / "core"))  # the synthetic raster writer


@pytest.fixture(scope="session")
def realdata() -> Path:
    if not REALDATA.is_dir():
        pytest.fail(f"real test data not found at {REALDATA}")
    return REALDATA


@pytest.fixture(scope="session")
def plugin(qgis_processing):
    """The plugin as QGIS loads it (classFactory, initProcessing); unload is checked at the end."""
    from qgis.core import QgsApplication
    import easyidp_toolbox
    plug = easyidp_toolbox.classFactory(None)
    plug.initProcessing()
    yield plug
    plug.unload()
    assert QgsApplication.processingRegistry().providerById("easyidp") is None


@pytest.fixture(scope="session")
def provider(plugin):
    """The registered EasyIDP provider."""
    return plugin.provider


@pytest.fixture(scope="session")
def qp_env(tmp_path_factory):
    """Environment for qgis_process.bin with the plugin enabled in an isolated profile."""
    from easyidp_toolbox.scripts.qgis_process import qgis_process_env
    return qgis_process_env(str(tmp_path_factory.mktemp("qgis-profile")))
