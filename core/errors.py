"""Exceptions raised by the core.

Every message names the input at fault and says what to do about it; the QGIS adapter turns
:class:`EasyIDPError` into ``QgsProcessingException`` unchanged.
"""
import functools
import struct
import zlib


class EasyIDPError(Exception):
    """Base class: bad input or an operation that cannot be done."""


class InputError(EasyIDPError):
    """A missing, unreadable, truncated or unsupported input file."""


class ROIError(EasyIDPError):
    """An ROI that is empty, invalid, of the wrong geometry type or outside the data."""


class Cancelled(EasyIDPError):
    """The caller asked to stop; partial outputs have been removed."""


def reads_file(advice: str):
    """Decorate a reader ``fn(path, …)``: whatever a damaged file makes the parsing raise
    (ValueError, KeyError, struct.error, zlib.error, …) becomes an :class:`InputError` that names
    the file and gives ``advice``; the reader's own, more precise errors pass through."""
    parse_errors = (ValueError, TypeError, KeyError, IndexError, LookupError, AttributeError,
                    ArithmeticError, EOFError, struct.error, zlib.error, OSError)

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
