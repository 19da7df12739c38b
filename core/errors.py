"""Exceptions raised by the core.

Every message names the input at fault and says what to do about it; the QGIS adapter turns
:class:`EasyIDPError` into ``QgsProcessingException`` unchanged.
"""
import functools
import struct
import zlib
from typing import Optional


# The messages users meet most (a missing input, no CRS, nothing to do), each with an id: the
# error keeps the id and its fields, and the QGIS plugin shows the message in the user's language
# (easyidp_qgis/messages.py holds the same texts, translated in i18n/). The other messages are
# English only.
MESSAGES = {
    "roi_file_not_found": "ROI file not found: {path}",
    "project_not_found": "{path}: file not found.",
    "rois_no_crs": "The ROIs have no CRS: set one on the layer before using it.",
    "rois_no_features": "The ROI layer has no features.",
    "rois_miss_raster": (
        "None of the {count} ROIs overlaps the raster {raster}. Raster extent {raster_extent}, "
        "ROI extent {roi_extent} (both in {crs}). Check that the ROI layer and the raster cover "
        "the same area and that the ROI layer's CRS is set correctly."),
    "no_roi_seen": ("No ROI is seen by any photo: check that the ROIs lie in the surveyed area "
                    "and in the right CRS."),
    "nothing_to_write": "Nothing to write: give a crops folder, a previews folder or both.",
}


class EasyIDPError(Exception):
    """Base class: bad input or an operation that cannot be done.

    ``key`` and ``fields``: the message's id in :data:`MESSAGES` and its arguments, for the
    plugin to translate (None for a message in English only); ``str(error)`` is the English text.
    """

    def __init__(self, *args, key: Optional[str] = None, **fields):
        super().__init__(*args)
        self.key = key
        self.fields = fields

    @classmethod
    def of(cls, key: str, **fields) -> "EasyIDPError":
        """The error of the message ``key`` of :data:`MESSAGES` with its ``fields``."""
        return cls(MESSAGES[key].format(**fields), key=key, **fields)


class InputError(EasyIDPError):
    """A missing, unreadable, truncated or unsupported input file."""


class ROIError(EasyIDPError):
    """An ROI that is empty, invalid, of the wrong geometry type or outside the data."""


class Cancelled(EasyIDPError):
    """The caller asked to stop; partial outputs have been removed."""


def reads_file(advice: str):
    """Decorate a reader ``fn(path, …)``: whatever a damaged file makes the parsing raise
    (ValueError, KeyError, struct.error, zlib.error, …) becomes an :class:`InputError` that names
    the file and gives ``advice``; the reader's own, more precise errors pass through.

    ``TypeError`` and ``AttributeError`` are not caught: they are bugs of the reader (or a
    structure it failed to check), and must surface as such, not as "damaged file"."""
    parse_errors = (ValueError, KeyError, IndexError, LookupError, ArithmeticError, EOFError,
                    struct.error, zlib.error, OSError)

    def deco(fn):
        @functools.wraps(fn)
        def wrapper(path, *args, **kwargs):
            try:
                return fn(path, *args, **kwargs)
            except EasyIDPError:
                raise
            except parse_errors as exc:
                raise InputError(f"{path}: the file is damaged and cannot be read "
                                 f"({type(exc).__name__}: {exc}). {advice}") from None
        return wrapper
    return deco
