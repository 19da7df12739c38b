"""Shared fixtures for the core tests (no QGIS). Real files are read from ../shared/realdata."""
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))


@pytest.fixture(scope="session")
def realdata() -> Path:
    if not REALDATA.is_dir():
        pytest.fail(f"real test data not found at {REALDATA} (set EASYIDP_REALDATA)")
    return REALDATA
