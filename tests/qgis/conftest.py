"""Fixtures for the tests inside real QGIS (offscreen, pytest-qgis) and through qgis_process.

The end of a run: pytest-qgis calls ``exitQgis()`` when the session's fixtures end, and a
garbage collection after it that frees a QGIS object crashes Python (QGIS 3.40: a segmentation
fault while pytest prints its summary, so the run's exit code said nothing about the tests).
So the project is cleared and garbage collected before QGIS exits, the collector is off after
it, and once pytest has reported everything the process exits with the run's status
(``os._exit``: nothing of QGIS is torn down again at interpreter exit).
"""
import gc
import os
import sys
from pathlib import Path

import pytest

from easyidp_toolbox.tests.support import markers

ROOT = Path(__file__).resolve().parents[2]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))


@pytest.fixture(scope="session")
def realdata() -> Path:
    if not REALDATA.is_dir():
        pytest.fail(f"real test data not found at {REALDATA}: run make realdata (or set "
                    "EASYIDP_REALDATA to a folder that holds it)")
    return REALDATA


def pytest_configure(config):
    markers.register(config)


def pytest_collection_modifyitems(config, items):
    """qgis, desktop, realdata, reference: by path and fixtures (tests/support/markers.py)."""
    markers.apply(items, "qgis", Path(__file__).resolve().parent)


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


@pytest.fixture
def load_results(monkeypatch, qgis_processing):
    """QGIS's own loader of results, as the toolbox, batch and model dialogs call it after a run
    (``processing.gui.Postprocessing.handleAlgorithmResults``): the parameters by keyword (QGIS
    3.22 has a ``showResults`` argument before them, 3.40 not), and no layer tree view
    (pytest-qgis's iface is a mock, which the C++ loader of QGIS 3.44 refuses), so QGIS adds the
    layers as it does headless."""
    from processing.gui import Postprocessing
    monkeypatch.setattr(Postprocessing, "iface", None, raising=False)   # 3.22: none there

    def load(alg, context, feedback, parameters):
        return Postprocessing.handleAlgorithmResults(alg, context, feedback,
                                                     parameters=parameters)
    return load


@pytest.fixture(scope="session")
def qp_env(tmp_path_factory):
    """Environment for qgis_process.bin with the plugin enabled in an isolated profile."""
    from easyidp_toolbox.scripts.qgis_process import qgis_process_env
    return qgis_process_env(str(tmp_path_factory.mktemp("qgis-profile")))


@pytest.fixture(scope="session", autouse=True)
def _collect_before_qgis_exits(qgis_app):
    """Set up after pytest-qgis's ``qgis_app``, so torn down before its ``exitQgis()``."""
    yield
    from qgis.core import QgsProject
    QgsProject.instance().clear()
    gc.collect()
    gc.disable()


_SESSION = []


def pytest_sessionstart(session):
    _SESSION.append(session)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    """After everything is reported: exit now with the run's status (see the module's doc)."""
    if _SESSION:
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(int(_SESSION[0].exitstatus))
