"""DJI P4 Multispectral and Mavic 3M: digital numbers → camera signal → reflectance.

The model of DJI's *P4 Multispectral Image Processing Guide* (v1.0, 2020, section "NDVI
calculation", Eqs. 6–9), which the Mavic 3M's user manual and tags follow, per band file:

* normalised values: the pixel value ``I`` and the black level ``I_BL`` (``drone-dji:BlackLevel``,
  else EXIF ``BlackLevel``), each divided by 65535;
* vignetting (Eq. 8, 9): ``I_v = I · (k5·r⁶ + k4·r⁵ + … + k0·r + 1)`` with
  ``r = hypot(x − CenterX, y − CenterY)``, ``k`` = ``drone-dji:VignettingData`` (P4M) or
  ``VignettingPolynomial`` (M3M), the centre ``drone-dji:CalibratedOpticalCenterX``/``Y`` (P4M)
  or ``VignettingCenter`` (M3M); ``x`` the column, ``y`` the row index;
* camera value (Eq. 7): ``X_camera = (I_v − I_BL) / (gain · exposure / 10⁶)`` with
  ``drone-dji:SensorGain`` and ``drone-dji:ExposureTime`` (µs);
* reflectance (Eq. 6): ``ρ = pCam · X_camera / X_LS`` with ``pCam`` =
  ``drone-dji:SensorGainAdjustment`` (the band's gain relative to the reference module) and
  ``X_LS`` = ``drone-dji:Irradiance``, the sunlight sensor's reading as the drone compensated it
  for the sensor's attitude (the uncompensated value is ``SunSensor``).
"""
from typing import Optional, Tuple

import numpy as np

from ..errors import InputError
from ..photos import BandTags

__all__ = ["is_dji_multispectral", "dji_signal", "dji_irradiance"]

FULL_SCALE = 65535.0


def is_dji_multispectral(tags: BandTags) -> bool:
    return any(k.startswith("drone-dji:") for k in tags.xmp) and "Camera:BandName" in tags.xmp


def _first(tags: BandTags, *keys) -> Optional[str]:
    return next((k for k in keys if k in tags.xmp), None)


def dji_signal(raw: np.ndarray, tags: BandTags) -> Tuple[np.ndarray, str]:
    """``pCam · X_camera`` (float64, the shape of ``raw``): the band's signal in the units in which
    ``drone-dji:Irradiance`` gives the light, and a note of the corrections."""
    poly_key = _first(tags, "drone-dji:VignettingData", "drone-dji:VignettingPolynomial",
                      "Camera:VignettingPolynomial")
    needed = ["drone-dji:SensorGain", "drone-dji:ExposureTime", "drone-dji:SensorGainAdjustment"]
    missing = [k for k in needed if k not in tags.xmp]
    if poly_key is None:
        missing.append("drone-dji:VignettingData")
    centre = None
    if "drone-dji:CalibratedOpticalCenterX" in tags.xmp and "drone-dji:CalibratedOpticalCenterY" in tags.xmp:
        centre = (tags.number("drone-dji:CalibratedOpticalCenterX"),
                  tags.number("drone-dji:CalibratedOpticalCenterY"))
    else:
        key = _first(tags, "drone-dji:VignettingCenter", "Camera:VignettingCenter")
        if key is None:
            missing.append("drone-dji:CalibratedOpticalCenterX/Y")
        else:
            centre = tuple(tags.numbers(key)[:2])
    black = tags.number("drone-dji:BlackLevel")
    if black is None and "BlackLevel" in tags.tiff:
        black = float(np.mean(np.atleast_1d(np.asarray(tags.tiff["BlackLevel"], dtype=float))))
    if black is None:
        missing.append("drone-dji:BlackLevel")
    if missing:
        raise InputError(f"{tags.path}: the DJI calibration tags {', '.join(missing)} are missing, "
                         f"so its digital numbers cannot be turned into reflectance; use the drone's "
                         f"original TIFF band file (not an exported or edited copy)")
    poly = tags.numbers(poly_key)
    gain = tags.number("drone-dji:SensorGain")
    exposure_us = tags.number("drone-dji:ExposureTime")
    p_cam = tags.number("drone-dji:SensorGainAdjustment")
    rows, cols = raw.shape
    y = np.arange(rows, dtype=float)[:, None]
    x = np.arange(cols, dtype=float)[None, :]
    r = np.hypot(x - centre[0], y - centre[1])
    factor = np.ones_like(r)
    for power, k in enumerate(poly, start=1):
        factor += k * r ** power
    camera = (raw.astype(float) / FULL_SCALE * factor - black / FULL_SCALE) / (gain * exposure_us / 1e6)
    signal = p_cam * np.maximum(camera, 0.0)
    note = (f"DJI camera value: black level {black:g}, vignetting (centre {centre[0]:g}, "
            f"{centre[1]:g}), gain {gain:g}, exposure {exposure_us:g} µs, gain adjustment {p_cam:g}")
    return signal, note


def dji_irradiance(tags: BandTags) -> Tuple[Optional[float], str]:
    """The sunlight sensor's compensated irradiance (``drone-dji:Irradiance``), or (None, why)."""
    value = tags.number("drone-dji:Irradiance")
    if value is None or value <= 0:
        return None, "no sunlight-sensor irradiance (drone-dji:Irradiance) in the photo"
    return value, "sunlight-sensor irradiance drone-dji:Irradiance (attitude-compensated by the drone)"
