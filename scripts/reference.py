"""easyidp 2.0.4, the reference: its interpreter and the environment to run it in.

It lives in its own environment (``make env-ref``: ``.venv-ref``, or ``EASYIDP_REF_PYTHON``, which
the Makefile sets for the Debian roots) and is never imported: tests, the demo and the benchmarks
run it in a child process.
"""
import os
from pathlib import Path
from typing import Optional

ROOT = Path(__file__).resolve().parents[1]
REF_PYTHON = Path(os.environ.get("EASYIDP_REF_PYTHON") or ROOT / ".venv-ref" / "bin" / "python")


def require_reference() -> str:
    """The reference interpreter's path; RuntimeError naming ``make env-ref`` when it is missing."""
    if not REF_PYTHON.exists():
        raise RuntimeError(f"easyidp 2.0.4's environment not found at {REF_PYTHON}: run `make env-ref`")
    return str(REF_PYTHON)


def reference_env(env: Optional[dict] = None) -> dict:
    """The environment for easyidp 2.0.4's interpreter: without PROJ_DATA / PROJ_LIB, which
    point its wheels' own PROJ at Debian's data and slow it several times."""
    return {k: v for k, v in (env or os.environ).items() if k not in ("PROJ_DATA", "PROJ_LIB")}
