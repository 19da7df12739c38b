"""The sun's position: zenith and azimuth angles at a place and a UTC time, by NOAA's solar
position algorithm (the NOAA Global Monitoring Division's solar calculator, after Meeus,
*Astronomical Algorithms*, 1991), and the phase angle between the sun and a viewer.

Angles in degrees. Zenith: from the vertical, without atmospheric refraction (the geometric
sun); azimuth: clockwise from true north. NOAA states 0.0167° accuracy for years 1800–2100 (for
these angles; tested against pvlib's SPA to 0.02°).
"""
import math
from datetime import datetime, timezone
from typing import Tuple

import numpy as np


def julian_day(when: datetime) -> float:
    """The Julian day of an aware ``datetime`` (naive ones are taken as UTC)."""
    if when.tzinfo is None:
        when = when.replace(tzinfo=timezone.utc)
    unix = when.timestamp()
    return unix / 86400.0 + 2440587.5


def sun_position(when: datetime, lon_deg, lat_deg) -> Tuple[np.ndarray, np.ndarray]:
    """(zenith, azimuth) in degrees of the sun at ``lon_deg``, ``lat_deg`` (arrays or floats)
    at the time ``when`` (aware; naive is UTC)."""
    jd = julian_day(when)
    t = (jd - 2451545.0) / 36525.0                              # Julian century
    l0 = (280.46646 + t * (36000.76983 + t * 0.0003032)) % 360.0  # mean longitude
    m = 357.52911 + t * (35999.05029 - 0.0001537 * t)           # mean anomaly
    e = 0.016708634 - t * (0.000042037 + 0.0000001267 * t)      # eccentricity
    mr = math.radians(m)
    c = (math.sin(mr) * (1.914602 - t * (0.004817 + 0.000014 * t))
         + math.sin(2 * mr) * (0.019993 - 0.000101 * t) + math.sin(3 * mr) * 0.000289)
    true_long = l0 + c
    omega = 125.04 - 1934.136 * t
    app_long = true_long - 0.00569 - 0.00478 * math.sin(math.radians(omega))
    eps0 = 23.0 + (26.0 + (21.448 - t * (46.815 + t * (0.00059 - t * 0.001813))) / 60.0) / 60.0
    eps = math.radians(eps0 + 0.00256 * math.cos(math.radians(omega)))
    decl = math.asin(math.sin(eps) * math.sin(math.radians(app_long)))
    y = math.tan(eps / 2) ** 2
    l0r = math.radians(l0)
    eq_time = 4 * math.degrees(y * math.sin(2 * l0r) - 2 * e * math.sin(mr)
                               + 4 * e * y * math.sin(mr) * math.cos(2 * l0r)
                               - 0.5 * y * y * math.sin(4 * l0r) - 1.25 * e * e * math.sin(2 * mr))
    utc = when if when.tzinfo is None else when.astimezone(timezone.utc)
    minutes = utc.hour * 60 + utc.minute + (utc.second + utc.microsecond / 1e6) / 60.0
    lon = np.asarray(lon_deg, float)
    lat = np.radians(np.asarray(lat_deg, float))
    true_solar = (minutes + eq_time + 4 * lon) % 1440.0
    hour_angle = np.radians(np.where(true_solar / 4 < 0, true_solar / 4 + 180, true_solar / 4 - 180))
    cos_z = np.sin(lat) * math.sin(decl) + np.cos(lat) * math.cos(decl) * np.cos(hour_angle)
    zen = np.arccos(np.clip(cos_z, -1, 1))
    with np.errstate(invalid="ignore", divide="ignore"):
        cos_a = (np.sin(lat) * np.cos(zen) - math.sin(decl)) / (np.cos(lat) * np.sin(zen))
    az = np.degrees(np.arccos(np.clip(cos_a, -1, 1)))
    az = np.where(hour_angle > 0, (az + 180) % 360, (540 - az) % 360)
    return np.degrees(zen), az


def phase_angle(sun_zenith, sun_azimuth, view_zenith, view_azimuth):
    """Degrees between the directions from a point to the sun and to a viewer (each given by
    its zenith and azimuth from that point): 0 when the viewer looks along the sun's rays (the
    hot spot), large for views against the sun."""
    sz, sa, vz, va = (np.radians(np.asarray(a, float)) for a in
                      (sun_zenith, sun_azimuth, view_zenith, view_azimuth))
    cos_p = np.cos(sz) * np.cos(vz) + np.sin(sz) * np.sin(vz) * np.cos(sa - va)
    return np.degrees(np.arccos(np.clip(cos_p, -1.0, 1.0)))


__all__ = ["sun_position", "phase_angle", "julian_day"]
