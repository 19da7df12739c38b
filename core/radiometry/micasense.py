"""MicaSense (RedEdge-3/M/MX/P, Altum, Altum-PT): digital numbers → radiance → irradiance.

The model of MicaSense's image processing tutorial 1 and its ``micasense`` package
(``github.com/micasense/imageprocessing``: ``utils.raw_image_to_radiance``, ``image.py``,
``dls.py``), per band file:

* dark level ``pBL``: the mean of the EXIF ``BlackLevel`` values;
* vignetting: ``r = hypot(x − cx, y − cy)`` from ``Camera:VignettingCenter`` (``x`` the column,
  ``y`` the row index), ``V = 1 / (1 + k0·r + k1·r² + … + k5·r⁶)`` from
  ``Camera:VignettingPolynomial``;
* row gradient: ``R = 1 / (1 + a2·y/tₑ − a3·y)`` with ``a1, a2, a3`` = ``Camera:RadiometricCalibration``;
* radiance ``L = V·R·max(p − pBL, 0) / (g·tₑ) · a1 / 2^N`` in W/m²/sr/nm, with ``tₑ`` the EXIF
  ``ExposureTime`` (s), ``g`` = EXIF ``ISOSpeed`` / 100 and ``N`` the EXIF ``BitsPerSample``.

Irradiance (W/m²/nm) from the downwelling light sensor, as ``image.py`` takes it:

* DLS 2 with ``DLS:HorizontalIrradiance`` (firmware that computes it right): that value;
* DLS 2 with direct and scattered parts: ``E = E_dir·sin(elevation) + E_scat``
  (``DLS:SolarElevation``);
* DLS 1 (``DLS:SpectralIrradiance`` only): the sun–sensor angle θ from the sun's position (GPS,
  UTC time) and the DLS pose (``DLS:Yaw``, ``Pitch``, ``Roll``), the diffuser's Fresnel
  transmission T(θ) (air → polycarbonate → PTFE), a clear-sky direct/diffuse ratio of 6:
  ``E_dir = E_sensor / T(θ) / (1/6 + cos θ)``, ``E = E_dir·(sin(elevation) + 1/6)``.

The irradiance tags are scaled by ``IrradianceScaleToSIUnits`` (0.01 for DLS 2 without it, 1 for
DLS 1). Reflectance is ``π·L / E``.
"""
import math
from datetime import datetime, timedelta, timezone
from typing import Optional, Tuple

import numpy as np

from ..errors import InputError
from ..sun import sun_position
from ..photos import BandTags

__all__ = ["is_micasense", "micasense_radiance", "micasense_irradiance", "sub_seconds", "capture_time",
           "gps_position", "fresnel_transmission"]

REQUIRED = ("Camera:RadiometricCalibration", "Camera:VignettingCenter", "Camera:VignettingPolynomial")
# Firmware from which the camera's own horizontal irradiance is right (micasense metadata.py)
GOOD_HORIZONTAL = {"Altum": (1, 2, 3), "RedEdge": (5, 1, 7), "RedEdge-M": (5, 1, 7)}
DIFFUSE_SHARE = 1.0 / 6.0         # clear-sky diffuse/direct ratio the DLS 1 model assumes
DIFFUSER = (1.000277, 1.6, 1.38)  # refractive indices: air, polycarbonate, PTFE


def is_micasense(tags: BandTags) -> bool:
    return "Camera:RadiometricCalibration" in tags.xmp or str(tags.tiff.get("Make", "")).startswith("MicaSense")


def _missing(tags: BandTags, xmp_keys, tiff_keys) -> None:
    missing = [k for k in xmp_keys if k not in tags.xmp] + [f"EXIF {k}" for k in tiff_keys
                                                            if k not in tags.tiff]
    if missing:
        raise InputError(f"{tags.path}: the MicaSense calibration tags {', '.join(missing)} are "
                         f"missing, so its digital numbers cannot be turned into radiance; use the "
                         f"camera's original band file (firmware 2.1.0 or later writes them)")


def exposure_and_gain(tags: BandTags) -> Tuple[float, float]:
    """(exposure time in s, gain) of a MicaSense band file."""
    iso = tags.tiff.get("ISOSpeed", tags.tiff.get("ISOSpeedRatings"))
    if iso is None or "ExposureTime" not in tags.tiff:
        _missing(tags, (), [k for k in ("ExposureTime", "ISOSpeed") if k not in tags.tiff])
    return float(tags.tiff["ExposureTime"]), float(iso) / 100.0


def micasense_radiance(raw: np.ndarray, tags: BandTags) -> Tuple[np.ndarray, str]:
    """Spectral radiance (W/m²/sr/nm, float64, the shape of ``raw``) of one MicaSense band file,
    and a note of the corrections."""
    _missing(tags, REQUIRED, ("BlackLevel", "BitsPerSample"))
    a1, a2, a3 = tags.numbers("Camera:RadiometricCalibration")[:3]
    cx, cy = tags.numbers("Camera:VignettingCenter")[:2]
    poly = tags.numbers("Camera:VignettingPolynomial")
    black = float(np.mean(np.atleast_1d(np.asarray(tags.tiff["BlackLevel"], dtype=float))))
    bits = int(np.atleast_1d(tags.tiff["BitsPerSample"])[0])
    exposure, gain = exposure_and_gain(tags)
    rows, cols = raw.shape
    y = np.arange(rows, dtype=float)[:, None]
    x = np.arange(cols, dtype=float)[None, :]
    r = np.hypot(x - cx, y - cy)
    denom = np.ones_like(r)
    for power, k in enumerate(poly, start=1):
        denom += k * r ** power
    row_gradient = 1.0 / (1.0 + a2 * y / exposure - a3 * y)
    signal = np.maximum(raw.astype(float) - black, 0.0) * row_gradient / denom
    radiance = signal / (gain * exposure) * a1 / float(2 ** bits)
    note = (f"MicaSense radiance: dark level {black:g}, vignetting (centre {cx:g}, {cy:g}), row "
            f"gradient, gain {gain:g}, exposure {exposure * 1000:g} ms")
    return radiance, note


def _scale(tags: BandTags) -> float:
    for key in ("DLS:IrradianceScaleToSIUnits", "Camera:IrradianceScaleToSIUnits"):
        value = tags.number(key)
        if value is not None:
            return value
    return 0.01 if "DLS:HorizontalIrradiance" in tags.xmp else 1.0


def _horizontal_valid(tags: BandTags) -> bool:
    good = GOOD_HORIZONTAL.get(str(tags.tiff.get("Model", "")).strip("\x00 "))
    if good is None:
        return True
    try:
        version = tuple(int(p) for p in str(tags.tiff.get("Software", "")).strip("\x00 v").split(".")[:3])
    except ValueError:
        return False
    return version >= good


def micasense_irradiance(tags: BandTags) -> Tuple[Optional[float], str]:
    """Horizontal spectral irradiance (W/m²/nm) under the DLS at this band file's capture, and
    how it was found; (None, why) when the photo has no DLS reading."""
    scale = _scale(tags)
    horizontal = tags.number("DLS:HorizontalIrradiance")
    direct, scattered = tags.number("DLS:DirectIrradiance"), tags.number("DLS:ScatteredIrradiance")
    if horizontal is not None and _horizontal_valid(tags):
        return horizontal * scale, "DLS 2 horizontal irradiance (the camera's sun-angle correction)"
    if direct and scattered:
        elevation = tags.number("DLS:SolarElevation")
        if elevation is None:
            elevation = math.radians(_sun(tags)[0])
        return ((direct * math.sin(elevation) + scattered) * scale,
                "DLS 2 direct·sin(sun elevation) + scattered irradiance")
    spectral = tags.number("DLS:SpectralIrradiance")
    if spectral is None:
        return None, "no DLS irradiance in the photo"
    elevation_deg, azimuth_deg = _sun(tags)
    el, az = math.radians(elevation_deg), math.radians(azimuth_deg)
    sun = np.array([math.cos(az) * math.cos(el), math.sin(az) * math.cos(el), -math.sin(el)])
    yaw, pitch, roll = (tags.number(f"DLS:{k}") or 0.0 for k in ("Yaw", "Pitch", "Roll"))
    sensor = _rotation(yaw, pitch, roll) @ np.array([0.0, 0.0, -1.0])
    theta = math.acos(max(-1.0, min(1.0, float(sun @ sensor))))
    transmission = fresnel_transmission(theta)
    direct_normal = spectral * scale / transmission / (DIFFUSE_SHARE + math.cos(theta))
    irradiance = direct_normal * math.sin(el) + direct_normal * DIFFUSE_SHARE
    return irradiance, (f"DLS 1 irradiance corrected for the sun–sensor angle {math.degrees(theta):.1f}° "
                        f"(sun elevation {elevation_deg:.1f}°, Fresnel diffuser, clear sky 6:1)")


def _rotation(yaw: float, pitch: float, roll: float) -> np.ndarray:
    """Body → north-east-down for yaw, pitch, roll (radians): Rz(yaw)·Ry(pitch)·Rx(roll)."""
    cy, sy, cp, sp, cr, sr = (math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch),
                              math.cos(roll), math.sin(roll))
    rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    return rz @ ry @ rx


def fresnel_transmission(theta: float) -> float:
    """Unpolarised transmission of the DLS diffuser's layers at incidence ``theta`` (radians)."""
    total, phi = 1.0, theta
    for n1, n2 in zip(DIFFUSER[:-1], DIFFUSER[1:]):
        phi = math.asin(math.sin(phi) / n1)
        c1 = math.cos(phi)
        c2 = math.sqrt(max(0.0, 1.0 - (n1 / n2 * math.sin(phi)) ** 2))
        rs = ((n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2)) ** 2
        rp = ((n1 * c2 - n2 * c1) / (n1 * c2 + n2 * c1)) ** 2
        total *= min(1.0, max(0.0, 1.0 - 0.5 * rs - 0.5 * rp))
    return total


def capture_time(tags: BandTags) -> datetime:
    """The UTC time of the capture (EXIF DateTimeOriginal + SubSecTime; MicaSense writes UTC)."""
    stamp = tags.tiff.get("DateTimeOriginal")
    if not stamp:
        _missing(tags, (), ("DateTimeOriginal",))
    when = datetime.strptime(str(stamp).strip("\x00 "), "%Y:%m:%d %H:%M:%S").replace(tzinfo=timezone.utc)
    sub = sub_seconds(tags)
    if sub.isdigit():
        when += timedelta(seconds=float("0." + sub))
    return when


def sub_seconds(tags: BandTags) -> str:
    """The EXIF sub-second digits of the capture time ('' when absent; tifffile spells the tag
    ``SubsecTimeOriginal``)."""
    for key in ("SubsecTimeOriginal", "SubSecTimeOriginal", "SubsecTime", "SubSecTime"):
        if tags.tiff.get(key):
            return str(tags.tiff[key]).strip("\x00 ")
    return ""


def gps_position(tags: BandTags) -> Tuple[float, float]:
    """(latitude, longitude) in degrees from the EXIF GPS tags."""
    gps = tags.tiff.get("GPSTag")
    if not isinstance(gps, dict) or "GPSLatitude" not in gps or "GPSLongitude" not in gps:
        _missing(tags, (), ("GPSLatitude", "GPSLongitude"))

    def degrees(value, ref, negative):
        flat = [float(v) for v in np.ravel(value)]
        parts = ([flat[i] / flat[i + 1] for i in range(0, len(flat), 2)] if len(flat) == 6 else flat)
        deg = parts[0] + (parts[1] / 60.0 if len(parts) > 1 else 0) + (parts[2] / 3600.0 if len(parts) > 2 else 0)
        return -deg if str(ref).strip("\x00 ").upper() == negative else deg

    return (degrees(gps["GPSLatitude"], gps.get("GPSLatitudeRef", "N"), "S"),
            degrees(gps["GPSLongitude"], gps.get("GPSLongitudeRef", "E"), "W"))


def _sun(tags: BandTags) -> Tuple[float, float]:
    """(elevation, azimuth) of the sun in degrees at the photo's time and place."""
    lat, lon = gps_position(tags)
    zenith, azimuth = sun_position(capture_time(tags), lon, lat)
    return 90.0 - float(zenith), float(azimuth)
