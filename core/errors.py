"""Exceptions raised by the core.

Every message names the input at fault and says what to do about it; the QGIS adapter turns
:class:`EasyIDPError` into ``QgsProcessingException`` unchanged.
"""


class EasyIDPError(Exception):
    """Base class: bad input or an operation that cannot be done."""


class InputError(EasyIDPError):
    """A missing, unreadable, truncated or unsupported input file."""


class ROIError(EasyIDPError):
    """An ROI that is empty, invalid, of the wrong geometry type or outside the data."""


class Cancelled(EasyIDPError):
    """The caller asked to stop; partial outputs have been removed."""
