"""Each view's time and its sun: the acquisition time of its photo (EXIF, :func:`..radiometry.
acquisition_time`), the sun's zenith and azimuth at its ROI then (:mod:`..sun`, NOAA) and the
phase angle sun–ROI–camera (0: the camera looks along the sun's rays, the hot spot)."""
from datetime import timedelta, timezone
from typing import Dict, List, Optional

import numpy as np

from ..crs import as_crs, transform_xy
from ..geometry import area_centroid
from ..radiometry import acquisition_time
from ..sun import phase_angle, sun_position
from .result import BackProjection

EARTH_RADIUS = 6371008.8          # metres, mean: enough for the direction to a camera


def view_sun(result: BackProjection, rois, recon, paths: Dict[str, str],
             utc_offset: Optional[float] = None) -> dict:
    """{acquired (ISO strings, "" unknown), sun_zenith, sun_azimuth, phase_angle (degrees,
    NaN unknown), notes} of every record of ``result``; ``paths``: photo label → file;
    ``utc_offset``: hours, for photos whose time states no offset."""
    k = len(result)
    out = dict(acquired=[""] * k, sun_zenith=np.full(k, np.nan), sun_azimuth=np.full(k, np.nan),
               phase_angle=np.full(k, np.nan), notes=[])
    times = {lab: acquisition_time(p) for lab, p in paths.items()}
    naive = [lab for lab, t in times.items() if t is not None and t.tzinfo is None]
    if naive and utc_offset is not None:
        tz = timezone(timedelta(hours=float(utc_offset)))
        times.update({lab: times[lab].replace(tzinfo=tz) for lab in naive})
    elif naive:
        out["notes"].append(f"{len(naive)} photo(s) state their time without a UTC offset "
                            f"(e.g. {naive[0]}): no sun angles for them; give the UTC offset")
    for i in range(k):
        t = times.get(result.photo_labels[int(result.photo_index[i])])
        if t is not None:
            out["acquired"][i] = t.isoformat()
    if not any(t is not None and t.tzinfo is not None for t in times.values()):
        return out
    crs = getattr(rois, "crs", None) if rois is not None else None
    if recon is None or crs is None or recon.is_local:
        out["notes"].append("no sun angles: the ROIs or the project have no geographic CRS")
        return out
    wgs = as_crs("EPSG:4326")
    cen = np.array([area_centroid([[np.asarray(g)[:, :2] for g in part] for part in r.parts])[1]
                    for r in rois])                # the back-projection's centre of a ROI
    roi_ll = transform_xy(crs, wgs, cen)
    labels, centres = recon.camera_centres(as_crs("EPSG:4979"))
    cam_ll = dict(zip(labels, centres[:, :2]))
    by_photo: Dict[str, List[int]] = {}
    for i in range(k):
        by_photo.setdefault(result.photo_labels[int(result.photo_index[i])], []).append(i)
    for lab, recs in by_photo.items():
        t = times.get(lab)
        if t is None or t.tzinfo is None or lab not in cam_ll:
            continue
        recs = np.array(recs)
        ll = roi_ll[result.roi[recs]]
        z, a = sun_position(t.astimezone(timezone.utc), ll[:, 0], ll[:, 1])
        lon_c, lat_c = cam_ll[lab]
        east = np.radians(lon_c - ll[:, 0]) * np.cos(np.radians(ll[:, 1])) * EARTH_RADIUS
        north = np.radians(lat_c - ll[:, 1]) * EARTH_RADIUS
        view_az = np.degrees(np.arctan2(east, north)) % 360.0
        out["sun_zenith"][recs] = z
        out["sun_azimuth"][recs] = a
        out["phase_angle"][recs] = phase_angle(z, a, result.view_angle[recs], view_az)
    return out


__all__ = ["view_sun", "EARTH_RADIUS"]
