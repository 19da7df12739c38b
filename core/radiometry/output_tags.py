"""Physical values in the files written from photos (crops, orthorectified ROIs, training
images): how a float32 TIFF states what its pixels are.

The unit goes where GDAL (and so QGIS) reads it: GDAL's metadata, TIFF tag 42112, with each
band's unit type (``UNITTYPE``, e.g. ``degC``) and description (the band name, e.g.
``temp_c``), and the dataset items ``EASYIDP_VALUES`` (temperature or reflectance),
``EASYIDP_UNIT`` and ``EASYIDP_VALUES_NOTE`` (what was applied: :attr:`PhotoValues.note`).
Pixels without a value (invalid: saturated, unreadable; or outside what the file shows) are
NaN, which GDAL's nodata tag (42113) states.
"""
from html import escape
from typing import List, Sequence, Tuple

from .values import PhotoValues

TIFF_TAG_GDAL_METADATA = 42112
TIFF_TAG_GDAL_NODATA = 42113
NODATA_TEXT = "nan"


def gdal_metadata(values: str, photo_values: PhotoValues, extra_bands: Sequence[str] = ()) -> str:
    """GDAL's metadata XML for a file of ``photo_values`` (``values``: the kind asked for):
    the dataset items and each band's unit and description; ``extra_bands``: names of bands
    written after the values (e.g. ``alpha``), without a unit."""
    items: List[Tuple[str, str, str]] = [
        ("EASYIDP_VALUES", values, ""), ("EASYIDP_UNIT", photo_values.unit, ""),
        ("EASYIDP_VALUES_NOTE", photo_values.note, "")]
    for k, band in enumerate(photo_values.bands):
        items.append(("DESCRIPTION", band, f' sample="{k}" role="description"'))
        items.append(("UNITTYPE", photo_values.unit, f' sample="{k}" role="unittype"'))
    for k, band in enumerate(extra_bands, start=len(photo_values.bands)):
        items.append(("DESCRIPTION", band, f' sample="{k}" role="description"'))
    # html.escape: &, <, > and both quotes, which is XML's escaping of text and attribute values
    body = "".join(f'<Item name="{escape(n)}"{attrs}>{escape(v)}</Item>' for n, v, attrs in items)
    # TIFF text is 7-bit ASCII: "°C" as a character reference (XML readers and GDAL decode it)
    return f"<GDALMetadata>{body}</GDALMetadata>".encode("ascii", "xmlcharrefreplace").decode()


def tiff_extratags(values: str, photo_values: PhotoValues, extra_bands: Sequence[str] = ()):
    """tifffile ``extratags`` writing :func:`gdal_metadata` and the NaN nodata."""
    return [(TIFF_TAG_GDAL_METADATA, "s", 0, gdal_metadata(values, photo_values, extra_bands), True),
            (TIFF_TAG_GDAL_NODATA, "s", 0, NODATA_TEXT, True)]
