"""Progress of a tool, one way: the core's ``Progress`` on the Processing feedback, a stage of
it mapped onto a share of the bar with ``Progress.sub``."""


def feedback_progress(feedback, start: float = 0.0, stop: float = 100.0):
    """A core ``Progress`` that reports its 0–100 as ``start``–``stop`` percent of ``feedback``
    and polls its cancellation; pass it (or its ``set``) as a core call's ``progress``."""
    from ..core.progress import Progress
    return Progress(feedback.setProgress, feedback.isCanceled).sub(start, stop)
