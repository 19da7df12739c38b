"""Raw photos in physical units: the one place where a photo's pixels become values in stated
units (:class:`PhotoValues`), with a note of what was applied.

:func:`read_photo_values` is the entry: ``values="stored"`` (the pixels as the file stores
them), ``"temperature"`` (°C: FLIR radiometric JPEGs by the Planck curve, temperature TIFFs by a
stated scale and offset; DJI R-JPEGs are refused with what to do) or ``"reflectance"``
(MicaSense and DJI multispectral band files, :func:`reflectance_values`, from the irradiance
sensor or a calibration panel; band files of one capture grouped by :func:`group_captures`).
:func:`read_photo` decodes a photo as stored (the one decoder of raw photos);
:func:`photo_decoder` is what every tool reading photo pixels decodes with, and
:func:`tiff_extratags` how the float32 files they write state the unit.
"""
import dataclasses
import functools
import os
from typing import Optional

import numpy as np

from ..errors import EasyIDPError
from ..photos import read_band_tags as read_photo_tags  # the band tags, by their old name
from ..photos import read_photo
from .acquisition import acquisition_time
from .flir import FlirPhoto, read_flir
from .planck import KELVIN, OBJECT_PARAMETERS, ThermalParameters, celsius_to_raw, raw_to_celsius
from .thermal import DJI_RJPEG, TEMPERATURE_PRESETS, scale_offset, temperature_values
from .values import PhotoValues

from .output_tags import NODATA_TEXT, gdal_metadata, tiff_extratags
from .multispectral import (SUPPORTED_CAMERAS, Capture, ReflectanceOptions, band_key,
                            capture_key, group_captures, reflectance_values)

VALUES = ("stored", "temperature", "reflectance")
UNITS = {"stored": "stored", "temperature": "degC", "reflectance": "reflectance"}


def read_photo_values(path, *, values: str = "stored", options: Optional[dict] = None) -> PhotoValues:
    """The photo at ``path`` in physical units.

    Parameters
    ----------
    path : str or os.PathLike
        The photo file.
    values : {"stored", "temperature", "reflectance"}
        ``stored``: the pixels as stored, as float32, every pixel valid; ``temperature``: °C
        (one band, ``temp_c``); ``reflectance``: reflectance 0–1 per band.
    options : dict, optional
        Overrides of what the photo says: for temperature, the object parameters
        (:data:`OBJECT_PARAMETERS`: ``emissivity``, ``object_distance`` in m,
        ``reflected_temperature``, ``atmospheric_temperature``, ``ir_window_temperature`` in °C,
        ``relative_humidity`` 0–1, ``ir_window_transmission``) and, for temperature TIFFs,
        ``temperature_preset`` (:data:`TEMPERATURE_PRESETS`) or ``temperature_scale`` and
        ``temperature_offset`` (°C = stored × scale + offset).

    Returns
    -------
    PhotoValues
        float32 values, the valid mask (saturated or unreadable pixels False), the unit, the
        band names and a note of what was applied.

    Raises
    ------
    InputError
        The photo cannot be read, or holds no values of the kind asked for (the message names
        the photo and says what to do).
    """
    if values == "stored":
        arr = read_photo(os.fspath(path))
        n = 1 if arr.ndim == 2 else arr.shape[2]
        return PhotoValues(arr.astype(np.float32), np.ones(arr.shape[:2], bool), "stored",
                           tuple(f"b{k + 1}" for k in range(n)), "as stored")
    if values == "temperature":
        return temperature_values(path, options=options)
    if values == "reflectance":
        return reflectance_values(path, options=_reflectance_options(options))
    raise EasyIDPError(f"Unknown values {values!r}: choose from {', '.join(VALUES)}.")


def photo_decoder(values: str = "stored", options: Optional[dict] = None):
    """The decoder of the tools that read photo pixels: None for ``values="stored"`` (they
    decode with :func:`read_photo`, the pixels and data type as stored), else path →
    :class:`PhotoValues` (:func:`read_photo_values` with ``options``).

    Raises
    ------
    EasyIDPError
        ``values`` is not one of :data:`VALUES`.
    """
    if values not in VALUES:
        raise EasyIDPError(f"Unknown values {values!r}: choose from {', '.join(VALUES)}.")
    if values == "stored":
        return None
    return functools.partial(read_photo_values, values=values, options=options)


def _reflectance_options(options) -> Optional[ReflectanceOptions]:
    """``options`` as :class:`ReflectanceOptions`: one already, or a dict of its fields (the
    temperature keys of a shared dict are left out), or None."""
    if options is None or isinstance(options, ReflectanceOptions):
        return options
    names = {f.name for f in dataclasses.fields(ReflectanceOptions)}
    return ReflectanceOptions(**{k: v for k, v in dict(options).items() if k in names})


__all__ = ["PhotoValues", "read_photo_values", "read_photo", "VALUES", "UNITS",
           "ThermalParameters", "OBJECT_PARAMETERS", "KELVIN", "raw_to_celsius", "celsius_to_raw",
           "FlirPhoto", "read_flir", "temperature_values", "TEMPERATURE_PRESETS",
           "scale_offset", "DJI_RJPEG", "acquisition_time", "reflectance_values",
           "ReflectanceOptions", "Capture", "group_captures", "band_key", "capture_key",
           "read_photo_tags", "SUPPORTED_CAMERAS", "photo_decoder", "gdal_metadata",
           "tiff_extratags", "NODATA_TEXT"]
