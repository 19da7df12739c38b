"""Attribute values of QGIS features as plain Python: NULL as None, dates as ISO text."""
from qgis.core import NULL
from qgis.PyQt.QtCore import QDate, QDateTime, QVariant

from .compat import DateFormat


def is_null(value) -> bool:
    """Whether an attribute value is empty: None, ``qgis.core.NULL`` or a null QVariant."""
    return value is None or value == NULL or (isinstance(value, QVariant) and value.isNull())


def plain_value(value):
    """None for NULL, ISO text for a date, else the value."""
    if is_null(value):
        return None
    if isinstance(value, (QDate, QDateTime)):
        return value.toString(DateFormat.ISODate)
    return value


def value_text(value) -> str:
    """The text of an attribute value: '' for NULL, ISO for a date."""
    v = plain_value(value)
    return "" if v is None else str(v)
