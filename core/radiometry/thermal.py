"""Temperatures (°C) of a thermal photo: FLIR radiometric JPEGs (:mod:`.flir`, :mod:`.planck`),
temperature TIFFs with a stated scale and offset, and DJI R-JPEGs refused with what to do.

**Temperature TIFFs** (converters' output: DJI Thermal SDK, FLIR Thermal Studio, ...): °C =
stored × ``temperature_scale`` + ``temperature_offset``, or one of :data:`TEMPERATURE_PRESETS`
(``temperature_preset``). Pixels that are not finite, the TIFF's GDAL nodata value, or the
extremes of an integer type are invalid.
"""
import os
from typing import Dict, Optional, Tuple

import numpy as np

from ..errors import EasyIDPError, InputError
from ..photos import jpeg_facts, read_photo
from .flir import FLIR_MAGIC, read_flir
from .planck import raw_to_celsius
from .values import PhotoValues

# name: (scale, offset, what the file stores): °C = stored × scale + offset
TEMPERATURE_PRESETS: Dict[str, Tuple[float, float, str]] = {
    "degC": (1.0, 0.0, "°C"),
    "K": (1.0, -273.15, "kelvin"),
    "ddegC": (0.1, 0.0, "°C × 10 (DJI Thermal SDK int16)"),
    "mdegC": (0.001, 0.0, "°C × 1000"),
    "cK": (0.01, -273.15, "centi-kelvin (K × 100)"),
}

DJI_RJPEG = ("{name}: DJI thermal R-JPEG (M2EA, H20T, M30T, M3T, H30T): its temperatures need "
             "DJI's Thermal SDK. Convert the photos to temperature TIFFs with DJI's dji_irp "
             "(-a measure --measurefmt float32), keep their file names, and give that folder "
             "as the photos (temperature preset degC).")


def scale_offset(options: Optional[dict]) -> Tuple[float, float, str]:
    """(scale, offset, what) of a temperature TIFF from ``options``: ``temperature_scale`` /
    ``temperature_offset`` when given, else ``temperature_preset`` (default ``degC``)."""
    opts = options or {}
    preset = opts.get("temperature_preset") or "degC"
    if preset not in TEMPERATURE_PRESETS:
        raise EasyIDPError(f"Unknown temperature preset {preset!r}: choose from "
                           f"{', '.join(TEMPERATURE_PRESETS)}, or give a scale and offset.")
    scale, offset, what = TEMPERATURE_PRESETS[preset]
    if opts.get("temperature_scale") is not None or opts.get("temperature_offset") is not None:
        try:
            scale = float(opts["temperature_scale"]) if opts.get("temperature_scale") is not None else 1.0
            offset = float(opts["temperature_offset"]) if opts.get("temperature_offset") is not None else 0.0
        except (TypeError, ValueError):
            raise EasyIDPError("The temperature scale and offset must be numbers.") from None
        if not np.isfinite(scale) or scale == 0 or not np.isfinite(offset):
            raise EasyIDPError(f"Temperature scale {scale:g} / offset {offset:g}: the scale must "
                               "be a finite number other than 0.")
        what = f"stored × {scale:g} + {offset:g}"
    return scale, offset, what


def _tiff_nodata(path) -> Optional[float]:
    import tifffile
    try:
        with tifffile.TiffFile(path) as tif:
            tag = tif.pages.first.tags.get(42113)
            return float(str(tag.value).strip("\x00 ")) if tag is not None else None
    except (OSError, ValueError, Exception):
        return None


def temperature_values(path, *, options: Optional[dict] = None) -> PhotoValues:
    """Temperatures in °C (band ``temp_c``) of the thermal photo at ``path``; ``options``: the
    object parameters of :data:`.planck.OBJECT_PARAMETERS` (FLIR photos; None: the photo's),
    ``temperature_preset`` or ``temperature_scale``/``temperature_offset`` (temperature TIFFs).
    :class:`InputError` naming the photo, with what to do, for photos that hold no
    temperatures this can read."""
    path = os.fspath(path)
    name = os.path.basename(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read()
    except OSError as exc:
        raise InputError(f"The thermal photo {path} cannot be read ({exc.strerror}).") from None
    if data[:2] == b"\xff\xd8":
        if FLIR_MAGIC in data[:1 << 20] and b"FFF\x00" in data[:1 << 20]:
            flir = read_flir(path, data)
            p = flir.parameters.overridden(options, name)
            t = raw_to_celsius(flir.raw, p)
            lo, hi = flir.raw_range
            valid = np.isfinite(t) & (flir.raw > max(lo, 0)) & (flir.raw < min(hi, 65535))
            note = (f"{flir.model or 'FLIR camera'} raw ({flir.encoding}) to °C by Planck (R1 "
                    f"{p.r1:g}, R2 {p.r2:g}, B {p.b:g}, F {p.f:g}, O {p.o:g}), emissivity "
                    f"{p.emissivity:g}, distance {p.object_distance:g} m, reflected "
                    f"{p.reflected_temperature:.2f} °C, air {p.atmospheric_temperature:.2f} °C, "
                    f"humidity {p.relative_humidity:.2f}, window "
                    f"{p.ir_window_transmission:g} at {p.ir_window_temperature:.2f} °C")
            return PhotoValues(t.astype(np.float32), valid, "degC", ("temp_c",), note)
        if jpeg_facts(path).get("thermal"):
            raise InputError(DJI_RJPEG.format(name=path))
        raise InputError(f"The photo {path} holds no temperatures (a JPEG without FLIR "
                         "radiometric records): give the camera's radiometric JPEGs or "
                         "temperature TIFFs.")
    if data[:4] not in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
        raise InputError(f"The photo {path} is neither a FLIR radiometric JPEG nor a TIFF: "
                         "give the camera's radiometric JPEGs or temperature TIFFs.")
    arr = read_photo(path)
    if arr.ndim != 2:
        raise InputError(f"The temperature TIFF {path} has {arr.shape[2]} bands; a temperature "
                         "TIFF has one.")
    scale, offset, what = scale_offset(options)
    valid = np.isfinite(arr) if arr.dtype.kind == "f" else np.ones(arr.shape, bool)
    if arr.dtype.kind in "iu":
        info = np.iinfo(arr.dtype)
        valid &= (arr > info.min) & (arr < info.max)
    nodata = _tiff_nodata(path)
    if nodata is not None:
        valid &= arr != nodata
    t = arr.astype(np.float64) * scale + offset
    t[~valid] = np.nan
    return PhotoValues(t.astype(np.float32), valid, "degC", ("temp_c",),
                       f"temperature TIFF: °C = {what}")
