"""Multispectral band files as reflectance: the vendors' radiometric models, panels, captures.

:func:`reflectance_values` turns one band file of a MicaSense (:mod:`.micasense`) or DJI
(:mod:`.dji_multispectral`) camera into reflectance, a :class:`.values.PhotoValues`. The light is
taken from the photo's own irradiance sensor (MicaSense DLS, DJI sunlight sensor), or, when
:class:`ReflectanceOptions` gives calibration-panel photos, from the panel: the mean signal over
the panel's active area and its albedo per band give the factor ``albedo / mean`` by which the
band's signal becomes reflectance (MicaSense tutorial 1; for DJI the same ratio on the guide's
camera value). Bands are known by the photo's band tag (``Camera:BandName``), never by file name.

Saturated pixels (the top code of the 12-bit sensors, left-justified in 16 bits: ≥ 65520) are
``valid = False`` in the result, so that statistics leave them out.

:func:`group_captures` groups band files into captures, the one view a multi-camera rig takes at a
time: MicaSense by ``CaptureId``, DJI by ``drone-dji:CaptureUUID`` or, lacking it, by the capture
time to the sub-second.
"""
import functools
import os
from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from ..errors import InputError
from .dji_multispectral import dji_irradiance, dji_signal, is_dji_multispectral
from .micasense import is_micasense, micasense_irradiance, micasense_radiance, sub_seconds
from ..photos import BandTags, read_band_tags, read_raw_band
from .values import PhotoValues

__all__ = ["ReflectanceOptions", "reflectance_values", "Capture", "group_captures", "band_key",
           "capture_key", "SUPPORTED_CAMERAS", "MICASENSE_LWIR"]

SUPPORTED_CAMERAS = ("MicaSense RedEdge-3/M/MX/P, Altum, Altum-PT (DLS 1, DLS 2)",
                     "DJI P4 Multispectral, Mavic 3M (sunlight sensor)")
SATURATED_DN = 65520          # 4095 × 16: a 12-bit sensor's top code, left-justified in 16 bits
_BANDS = {"blue": "blue", "green": "green", "red": "red", "nir": "nir", "near infrared": "nir",
          "rededge": "red_edge", "red edge": "red_edge", "re": "red_edge", "red_edge": "red_edge",
          "panchro": "panchro", "panchromatic": "panchro", "lwir": "lwir"}


def band_key(name: str) -> str:
    """The vendor-neutral key of a band name (``"Red edge"``, ``"RedEdge"`` → ``"red_edge"``)."""
    text = str(name).strip().lower()
    return _BANDS.get(text, _BANDS.get(text.replace("-", " "), text.replace(" ", "_")))


@dataclass(frozen=True)
class ReflectanceOptions:
    """How the light is known.

    Parameters
    ----------
    panel_photos : sequence of str
        band files of a capture of a calibration panel (one per band); empty: the photo's own
        irradiance sensor is used.
    panel_albedo : mapping of str to float, optional
        the panel's reflectance (0–1) per band name (any vendor spelling: ``"NIR"``,
        ``"Red edge"``); a band missing here takes the photo's ``Camera:Albedo`` tag.
    panel_region : (col0, row0, col1, row1), optional
        the panel's active area in the panel photos, pixels (corner convention, end exclusive),
        for photos that carry no ``Camera:ReflectArea`` tag.
    """

    panel_photos: Tuple[str, ...] = ()
    panel_albedo: Optional[Mapping[str, float]] = None
    panel_region: Optional[Tuple[int, int, int, int]] = None

    def key(self):
        albedo = tuple(sorted((band_key(k), float(v)) for k, v in (self.panel_albedo or {}).items()))
        photos = tuple((os.fspath(p), os.stat(p).st_mtime_ns if os.path.exists(p) else 0)
                       for p in self.panel_photos)
        return (photos, albedo,
                tuple(self.panel_region) if self.panel_region else None)


def _vendor(tags: BandTags) -> str:
    if is_micasense(tags):
        return "micasense"
    if is_dji_multispectral(tags):
        return "dji"
    raise InputError(f"{tags.path}: not a band file of a supported multispectral camera (no "
                     f"MicaSense or DJI calibration tags); supported: {'; '.join(SUPPORTED_CAMERAS)}. "
                     f"For another camera, convert its photos to reflectance with the maker's "
                     f"software and measure them as stored")


def _band_name(tags: BandTags) -> str:
    name = tags.xmp.get("Camera:BandName")
    if not name or isinstance(name, list):
        raise InputError(f"{tags.path}: no band name tag (XMP Camera:BandName); bands are matched "
                         f"by that tag, so use the camera's original band files")
    return str(name)


MICASENSE_LWIR = ("{path}: the LWIR band of a MicaSense Altum or Altum-PT is its thermal camera: it "
                  "stores temperatures in centi-kelvin, not light, so it has no reflectance; measure "
                  "it with the values 'temperature' and the temperature-TIFF preset centi-kelvin "
                  "(K × 100)")


def _signal(path) -> Tuple[BandTags, np.ndarray, np.ndarray, str]:
    """(tags, signal, saturated, note): the vendor's radiance-like signal of one band file."""
    tags = read_band_tags(path)
    if band_key(tags.xmp.get("Camera:BandName") or "") == "lwir":
        raise InputError(MICASENSE_LWIR.format(path=tags.path))
    vendor = _vendor(tags)
    _band_name(tags)
    raw = read_raw_band(path)
    saturated = raw >= SATURATED_DN
    if vendor == "micasense":
        signal, note = micasense_radiance(raw, tags)
    else:
        signal, note = dji_signal(raw, tags)
    return tags, signal, saturated, note


def _panel_mask(tags: BandTags, shape, region) -> np.ndarray:
    rows, cols = shape
    if region is not None:
        c0, r0, c1, r1 = (int(v) for v in region)
        mask = np.zeros(shape, bool)
        mask[max(r0, 0):min(r1, rows), max(c0, 0):min(c1, cols)] = True
        return mask
    corners = tags.numbers("Camera:ReflectArea")
    if not corners or len(corners) < 8:
        raise InputError(f"{tags.path}: a panel photo without a panel: it has no panel area "
                         f"(XMP Camera:ReflectArea, written when the camera detects the panel); "
                         f"give the panel's area in pixels (panel_region) or another panel capture")
    quad = np.asarray(corners[:8], float).reshape(4, 2)
    x, y = quad[:, 0], quad[:, 1]
    orientation = np.sign(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))   # shoelace sign
    yy, xx = np.mgrid[0:rows, 0:cols]
    px, py = xx + 0.5, yy + 0.5                      # pixel centres (corner convention)
    inside = np.ones(shape, bool)
    for (x0, y0), (x1, y1) in zip(quad, np.roll(quad, -1, axis=0)):
        inside &= ((x1 - x0) * (py - y0) - (y1 - y0) * (px - x0)) * orientation >= 0
    return inside


@functools.lru_cache(maxsize=8)
def _panel_factors(key) -> Dict[str, Tuple[float, str]]:
    """{band key: (factor, note)}: reflectance = factor · signal, from a panel capture."""
    paths, albedo, region = key
    albedo = dict(albedo)
    factors: Dict[str, Tuple[float, str]] = {}
    for path, _mtime in paths:
        tags, signal, saturated, _ = _signal(path)
        band = band_key(_band_name(tags))
        mask = _panel_mask(tags, signal.shape, region) & ~saturated
        if mask.sum() < 16:
            raise InputError(f"{path}: a panel photo without a panel: fewer than 16 unsaturated "
                             f"pixels in the panel area; take the panel capture again, not in "
                             f"direct glare, or give the panel's area (panel_region)")
        rho = albedo.get(band, tags.number("Camera:Albedo"))
        if rho is None:
            raise InputError(f"{path}: no albedo for band {_band_name(tags)!r} (neither given in "
                             f"panel_albedo nor in the photo's Camera:Albedo tag); give the panel's "
                             f"reflectance per band, from its calibration sheet")
        mean = float(signal[mask].mean())
        if not mean > 0:
            raise InputError(f"{path}: the panel area is black (mean signal {mean:g}); a panel "
                             f"photo without a panel: give the panel's area (panel_region)")
        factors[band] = (rho / mean, f"calibration panel {os.path.basename(path)} "
                                     f"(albedo {rho:g}, {int(mask.sum())} pixels)")
    return factors


def reflectance_values(path, *, options: Optional[ReflectanceOptions] = None) -> PhotoValues:
    """One multispectral band file as reflectance (a fraction; 1 = white Lambertian surface).

    Parameters
    ----------
    path : str or os.PathLike
        a MicaSense or DJI multispectral band file (16-bit TIFF with the maker's tags).
    options : ReflectanceOptions, optional
        calibration-panel photos and albedos; without them the photo's irradiance sensor is used.

    Returns
    -------
    PhotoValues
        float32 (rows, cols) reflectance, ``valid`` False on saturated pixels, one band named by
        the photo's band tag, and a note of the model, the irradiance source and the mask.

    Raises
    ------
    InputError
        naming the photo: not a supported camera, calibration tags missing, no irradiance (no
        sensor reading and no panel), or a panel photo without a panel.
    """
    path = os.fspath(path)
    options = options or ReflectanceOptions()
    tags, signal, saturated, note = _signal(path)
    band = _band_name(tags)
    vendor = _vendor(tags)
    if options.panel_photos:
        factors = _panel_factors(options.key())
        if band_key(band) not in factors:
            raise InputError(f"{path}: no panel photo for band {band!r} among the panel photos "
                             f"({', '.join(sorted(factors))}); give the panel capture's file of "
                             f"every band")
        factor, light = factors[band_key(band)]
    else:
        irradiance, light = (micasense_irradiance(tags) if vendor == "micasense"
                             else dji_irradiance(tags))
        if irradiance is None or not irradiance > 0:
            raise InputError(f"{path}: {light}, and no calibration panel was given, so the light "
                             f"is unknown; give panel photos with their albedo, or use photos "
                             f"taken with the irradiance sensor connected")
        factor = np.pi / irradiance if vendor == "micasense" else 1.0 / irradiance
    values = (signal * factor).astype(np.float32)
    valid = ~saturated
    masked = int(saturated.sum())
    note = f"{os.path.basename(path)} [{band}]: {note}; reflectance from {light}"
    if masked:
        note += f"; {masked} saturated pixels masked"
    return PhotoValues(values, valid, "reflectance", (band,), note)


@dataclass
class Capture:
    """The band files of one capture: ``bands`` maps the band name (as tagged) to its file."""

    key: str
    bands: Dict[str, str] = field(default_factory=dict)


def capture_key(tags: BandTags) -> str:
    """The capture a band file belongs to: its capture id (MicaSense ``CaptureId``, DJI
    ``CaptureUUID``), else its capture time to the sub-second."""
    for k in ("MicaCamera:CaptureId", "Camera:CaptureId", "drone-dji:CaptureUUID"):
        value = tags.xmp.get(k)
        if value and not isinstance(value, list):
            return str(value)
    stamp = str(tags.tiff.get("DateTimeOriginal", "")).strip("\x00 ")
    if not stamp:
        raise InputError(f"{tags.path}: no capture id (CaptureId, CaptureUUID) and no capture time "
                         f"(EXIF DateTimeOriginal), so its capture's other bands cannot be found")
    sub = sub_seconds(tags)
    return f"{stamp}.{sub}" if sub else stamp


def group_captures(paths: Sequence) -> List[Capture]:
    """Band files grouped into captures by the vendors' tags, in the order of first appearance.
    :class:`InputError` naming both files when a capture has the same band twice."""
    captures: Dict[str, Capture] = {}
    for path in paths:
        path = os.fspath(path)
        tags = read_band_tags(path)
        key = capture_key(tags)
        band = _band_name(tags)
        capture = captures.setdefault(key, Capture(key))
        if band in capture.bands:
            raise InputError(f"{path}: band {band!r} of capture {key} is also in "
                             f"{capture.bands[band]}; give each capture's band files once")
        capture.bands[band] = path
    return list(captures.values())
