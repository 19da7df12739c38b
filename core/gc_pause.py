"""Python's cyclic garbage collector paused while many small objects are built at once.

Building 100,000 ROIs, placed ROIs or features allocates far more objects than it frees, so
the collector runs a full generation again and again over everything alive (half the time of
reading 100,000 plots). None of these objects form cycles that must be freed during the build;
the collector runs again, as before, when the block ends.
"""
import gc
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def paused_gc() -> Iterator[None]:
    """Disable the cyclic collector inside the block (re-enabled after it, if it was on)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()
