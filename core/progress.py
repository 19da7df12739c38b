"""Progress reporting and cancellation, passed into the core as plain callables.

The QGIS adapter passes ``feedback.setProgress`` and ``feedback.isCanceled``; a script user
passes nothing, or e.g. a tqdm update.
"""
from typing import Callable, Optional

from .errors import Cancelled


class Progress:
    """Wraps ``report(percent)`` and ``is_cancelled()``; both optional.

    ``sub(start, stop)`` gives a child that maps its own 0–100 onto ``start``–``stop``.
    """

    def __init__(self, report: Optional[Callable[[float], None]] = None,
                 is_cancelled: Optional[Callable[[], bool]] = None,
                 start: float = 0.0, stop: float = 100.0):
        self._report = report
        self._is_cancelled = is_cancelled
        self._start = start
        self._span = stop - start

    def set(self, percent: float) -> None:
        """Report progress in percent (0–100) of this stage."""
        if self._report is not None:
            self._report(self._start + self._span * min(max(percent, 0.0), 100.0) / 100.0)

    def cancelled(self) -> bool:
        return bool(self._is_cancelled is not None and self._is_cancelled())

    def check(self) -> None:
        """Raise :class:`Cancelled` if the caller asked to stop."""
        if self.cancelled():
            raise Cancelled("Cancelled by the user.")

    def sub(self, start: float, stop: float) -> "Progress":
        return Progress(self.set, self._is_cancelled, start, stop)


def as_progress(progress=None, is_cancelled=None) -> Progress:
    """Accept a :class:`Progress`, or a ``report(percent)`` callable plus ``is_cancelled``."""
    if isinstance(progress, Progress):
        return progress
    return Progress(progress, is_cancelled)
