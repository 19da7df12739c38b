"""The sun's position seen from a place at a time: NOAA's solar position equations.

The equations of NOAA's Global Monitoring Laboratory solar calculator (after Meeus,
*Astronomical Algorithms*): geometric mean longitude and anomaly of the sun, equation of centre,
apparent longitude, obliquity, declination, equation of time, true solar time and hour angle.
Accurate to about 0.01° between 1800 and 2100; atmospheric refraction is not added (the angles
are geometric), which matters only within a few degrees of the horizon.
"""
import math
from datetime import datetime, timezone
from typing import Tuple

__all__ = ["sun_position"]


def sun_position(when: datetime, latitude: float, longitude: float) -> Tuple[float, float]:
    """(elevation, azimuth) of the sun's centre, degrees, at ``when`` (aware, or naive = UTC)
    seen from ``latitude``, ``longitude`` (degrees, WGS 84, east and north positive).

    Elevation is above the horizon (90 = overhead); azimuth is clockwise from north (90 = east).
    """
    if when.tzinfo is None:
        when = when.replace(tzinfo=timezone.utc)
    seconds = when.timestamp()
    jc = (2440587.5 + seconds / 86400.0 - 2451545.0) / 36525.0
    mean_long = (280.46646 + jc * (36000.76983 + jc * 0.0003032)) % 360.0
    mean_anom = 357.52911 + jc * (35999.05029 - 0.0001537 * jc)
    ecc = 0.016708634 - jc * (0.000042037 + 0.0000001267 * jc)
    m = math.radians(mean_anom)
    centre = (math.sin(m) * (1.914602 - jc * (0.004817 + 0.000014 * jc))
              + math.sin(2 * m) * (0.019993 - 0.000101 * jc) + math.sin(3 * m) * 0.000289)
    omega = math.radians(125.04 - 1934.136 * jc)
    app_long = mean_long + centre - 0.00569 - 0.00478 * math.sin(omega)
    mean_obliq = 23.0 + (26.0 + (21.448 - jc * (46.815 + jc * (0.00059 - jc * 0.001813))) / 60.0) / 60.0
    obliq = math.radians(mean_obliq + 0.00256 * math.cos(omega))
    decl = math.asin(math.sin(obliq) * math.sin(math.radians(app_long)))
    var_y = math.tan(obliq / 2.0) ** 2
    l0 = math.radians(mean_long)
    eq_time = 4.0 * math.degrees(
        var_y * math.sin(2 * l0) - 2 * ecc * math.sin(m) + 4 * ecc * var_y * math.sin(m) * math.cos(2 * l0)
        - 0.5 * var_y ** 2 * math.sin(4 * l0) - 1.25 * ecc ** 2 * math.sin(2 * m))
    minutes = (seconds % 86400.0) / 60.0
    solar_time = (minutes + eq_time + 4.0 * longitude) % 1440.0
    hour_angle = math.radians(solar_time / 4.0 + 180.0 if solar_time < 0 else solar_time / 4.0 - 180.0)
    lat = math.radians(latitude)
    cos_zen = math.sin(lat) * math.sin(decl) + math.cos(lat) * math.cos(decl) * math.cos(hour_angle)
    zen = math.acos(max(-1.0, min(1.0, cos_zen)))
    denom = math.cos(lat) * math.sin(zen)
    if abs(denom) < 1e-12:
        azimuth = 180.0 if latitude > math.degrees(decl) else 0.0
    else:
        cos_az = max(-1.0, min(1.0, (math.sin(lat) * math.cos(zen) - math.sin(decl)) / denom))
        az = math.degrees(math.acos(cos_az))
        azimuth = (az + 180.0) % 360.0 if hour_angle > 0 else (540.0 - az) % 360.0
    return 90.0 - math.degrees(zen), azimuth
