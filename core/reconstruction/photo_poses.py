"""A rough camera per photo from its own tags (EXIF and XMP), without a photogrammetry project.

Conventions (stated once; ``docs/background/camera-models.md`` explains them with figures):

* **Position.** DJI XMP ``drone-dji:GpsLatitude``/``GpsLongtitude`` (sic; ``GpsLongitude``
  is read too) first, else EXIF ``GPSLatitude``/``GPSLongitude`` with their N/S, E/W refs.
* **Height**, said per source (:data:`CAMERA_HEIGHTS`): ``"absolute"`` takes DJI
  ``AbsoluteAltitude``, else EXIF ``GPSAltitude`` (negative with ``GPSAltitudeRef`` 1), as a
  height in the vertical of the map the cameras are used with (DJI writes the GNSS height; with
  RTK it is ellipsoidal, without it the receiver's mean-sea-level height and often off by
  metres); ``"relative"`` takes DJI ``RelativeAltitude`` (barometric, above the take-off point)
  plus a take-off height the caller gives (or the DSM under the first photo).
* **Attitude.** DJI ``GimbalYawDegree``/``GimbalPitchDegree``/``GimbalRollDegree``: yaw the
  azimuth of the optical axis clockwise from true north, pitch its elevation (−90° straight
  down, 0° level), roll about the optical axis, right side down positive. They are applied as
  aerospace Z-Y-X angles on north-east-down axes, R_nb = Rz(yaw)·Ry(pitch)·Rx(roll), with the
  camera's z (optical axis) along the body's x (forward), its x (image right) along the body's
  y (right) and its y (image down) along the body's z (down). ``Camera:Yaw/Pitch/Roll``
  (MicaSense, Sentera, Parrot) and senseFly's ``Yaw/Pitch/Roll`` use pitch 0° for a nadir
  camera: their pitch − 90° is the gimbal pitch. Azimuths are then turned from true north to the
  map's grid north by the meridian convergence at the photo.
* **Interior**, first found: DJI ``DewarpData`` (``date;fx,fy,cx,cy,k1,k2,p1,p2,k3``: focal
  lengths and the principal point's offset from the image centre in pixels of the size the EXIF
  ``PixelXDimension``/``PixelYDimension`` give, then OpenCV's Brown terms; OpenCV's p1/p2 are
  p2/p1 in :mod:`.frame_model`); else ``CalibratedFocalLength`` and
  ``CalibratedOpticalCenterX/Y`` (pixels of that size; no distortion); else EXIF
  ``FocalLength`` (mm) with ``FocalPlaneXResolution``/``FocalPlaneResolutionUnit``; else
  ``FocalLengthIn35mmFilm`` on the 43.27 mm diagonal of a 36 × 24 mm frame (CIPA DC-008).
  Every pixel value is scaled from the tagged size to the stored image size.

Pixels: top-left corner origin (see :mod:`.frame_model`).
"""
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from ..photos import CAMERA_NS, DJI, SENSEFLY, PhotoTags, scale_to
from .frame_model import Calibration

__all__ = ["PhotoPose", "photo_pose", "gimbal_rotation", "gimbal_angles", "CAMERA_HEIGHTS",
           "ANGLE_STD_DEG", "GNSS_STD_M", "RTK_FIXED"]

CAMERA_HEIGHTS = ("absolute", "relative")
ANGLE_STD_DEG = 1.5
"""The stated uncertainty (one standard deviation, degrees) of a drone's gimbal angles as the
tags give them; measured on the real OpenDroneMap survey (docs: user guide, photo folders)."""
GNSS_STD_M = (3.0, 10.0)
"""(horizontal, vertical) standard deviation in metres of a position without RTK: a consumer
GNSS receiver's horizontal error, and its height (DJI's absolute altitude is often off by
metres to tens of metres)."""
RELATIVE_STD_M = 1.0
"""Standard deviation (m) of DJI's barometric ``RelativeAltitude`` over one flight."""
RTK_FIXED = 50
"""DJI ``RtkFlag`` of a fixed RTK solution (16 single point, 34 float, 50 fixed)."""
DIAGONAL_35MM = float(np.hypot(36.0, 24.0))


@dataclass
class PhotoPose:
    """What one photo's tags say. Angles in degrees (gimbal convention of the module
    docstring); ``height`` in metres; ``std_h``/``std_v``: the position's standard deviation (m);
    ``calibration`` at the stored size; ``camera``: make model (serial) and stored size."""
    path: str
    lat: float
    lon: float
    height: float
    camera_heights: str
    yaw: float
    pitch: float
    roll: float
    attitude_source: str
    calibration: Calibration
    interior_source: str
    camera: str
    size: Tuple[int, int]
    std_h: float
    std_v: float
    position_source: str
    relative_height: Optional[float] = None


def _dms(value, ref) -> Optional[float]:
    if isinstance(value, (tuple, list)) and len(value) >= 1:
        parts = [float(v) for v in value[:3]] + [0.0] * (3 - min(3, len(value)))
        deg = parts[0] + parts[1] / 60.0 + parts[2] / 3600.0
    elif isinstance(value, (int, float)):
        deg = float(value)
    else:
        return None
    return -deg if str(ref or "").strip().upper() in ("S", "W") else deg


def _position(t: PhotoTags, camera_heights: str, takeoff: Optional[float], problems: List):
    lat, lon = t.xmp_float(DJI, "GpsLatitude"), t.xmp_float(DJI, "GpsLongtitude")
    if lon is None:
        lon = t.xmp_float(DJI, "GpsLongitude")
    src = "DJI XMP GpsLatitude/GpsLongtitude"
    if lat is None or lon is None or (lat == 0.0 and lon == 0.0):
        lat = _dms(t.exif.get("GPSLatitude"), t.exif.get("GPSLatitudeRef"))
        lon = _dms(t.exif.get("GPSLongitude"), t.exif.get("GPSLongitudeRef"))
        src = "EXIF GPSLatitude/GPSLongitude"
    if lat is None or lon is None or (lat == 0.0 and lon == 0.0):
        problems.append(("no GPS position (EXIF GPSLatitude/GPSLongitude or DJI XMP "
                         "GpsLatitude/GpsLongtitude)", t.path))
        return None
    rel = t.xmp_float(DJI, "RelativeAltitude")
    if camera_heights == "relative":
        if rel is None:
            problems.append(("no DJI XMP RelativeAltitude (needed for heights above the "
                             "take-off point)", t.path))
            return None
        h = rel + (takeoff or 0.0)
    else:
        h = t.xmp_float(DJI, "AbsoluteAltitude")
        if h is None:
            h = t.exif_float("GPSAltitude")
            if h is not None and t.exif.get("GPSAltitudeRef") in (1, b"\x01", "1", "0x01"):
                h = -h
        if h is None:
            problems.append(("no height (DJI XMP AbsoluteAltitude or EXIF GPSAltitude)", t.path))
            return None
    std_h, std_v = GNSS_STD_M
    flag = t.xmp_float(DJI, "RtkFlag")
    stds = [t.xmp_float(DJI, n) for n in ("RtkStdLon", "RtkStdLat", "RtkStdHgt")]
    if flag is not None and all(s is not None for s in stds):
        std_h, std_v = float(np.hypot(stds[0], stds[1])), stds[2]
        src += f", RTK flag {flag:g} (DJI RtkStdLon/Lat/Hgt)"
    if camera_heights == "relative":
        std_v = RELATIVE_STD_M
    return lat, lon, h, rel, std_h, std_v, src


def _attitude(t: PhotoTags, problems: List):
    ypr = [t.xmp_float(DJI, f"Gimbal{n}Degree") for n in ("Yaw", "Pitch", "Roll")]
    if all(v is not None for v in ypr):
        if any(t.xmp.get((DJI, n), "0").strip() not in ("0", "") for n in
               ("CamReverse", "GimbalReverse")):
            problems.append(("DJI XMP CamReverse/GimbalReverse set (a gimbal mounted upside "
                             "down is not modelled)", t.path))
            return None
        return ypr[0], ypr[1], ypr[2], "DJI XMP GimbalYaw/Pitch/RollDegree"
    for ns, what in ((CAMERA_NS, "XMP Camera:Yaw/Pitch/Roll"), (SENSEFLY, "senseFly XMP Yaw/Pitch/Roll")):
        ypr = [t.xmp_float(ns, n) for n in ("Yaw", "Pitch", "Roll")]
        if all(v is not None for v in ypr):
            return ypr[0], ypr[1] - 90.0, ypr[2], what
    problems.append(("no camera attitude (DJI XMP GimbalYaw/Pitch/RollDegree or XMP "
                     "Camera:Yaw/Pitch/Roll)", t.path))
    return None


def _interior(t: PhotoTags, problems: List):
    w, h = t.size
    tw, th = t.exif.get("PixelXDimension"), t.exif.get("PixelYDimension")
    tagged = (int(tw), int(th)) if isinstance(tw, (int, float)) and isinstance(th, (int, float)) \
        and tw > 0 and th > 0 else (w, h)
    s = scale_to(tagged, (w, h))
    if s is None:
        problems.append((f"tags describe a {tagged[0]}×{tagged[1]} image (EXIF PixelXDimension/"
                         "PixelYDimension), another aspect ratio than the stored one: a crop", t.path))
        return None
    W, H = tagged
    dewarp = t.xmp.get((DJI, "DewarpData"), "")
    nums = []
    try:
        nums = [float(v) for v in dewarp.split(";")[-1].split(",")] if dewarp.strip() else []
    except ValueError:
        nums = []
    if len(nums) == 9 and nums[0] > 0 and nums[1] > 0:
        fx, fy, dcx, dcy, k1, k2, p1, p2, k3 = nums
        return Calibration(f=fy * s, b1=(fx - fy) * s, cx=(W / 2 + dcx) * s, cy=(H / 2 + dcy) * s,
                           k1=k1, k2=k2, k3=k3, p1=p2, p2=p1), "DJI XMP DewarpData"
    f = t.xmp_float(DJI, "CalibratedFocalLength")
    cx, cy = t.xmp_float(DJI, "CalibratedOpticalCenterX"), t.xmp_float(DJI, "CalibratedOpticalCenterY")
    if f and f > 0 and cx is not None and cy is not None:
        return Calibration(f=f * s, cx=cx * s, cy=cy * s), \
            "DJI XMP CalibratedFocalLength/CalibratedOpticalCenterX/Y"
    f_mm = t.exif_float("FocalLength")
    res, unit = t.exif_float("FocalPlaneXResolution"), t.exif.get("FocalPlaneResolutionUnit")
    mm_per_unit = {2: 25.4, 3: 10.0, 4: 1.0, 5: 0.001}.get(unit if isinstance(unit, int) else -1)
    if f_mm and f_mm > 0 and res and res > 0 and mm_per_unit:
        return Calibration(f=f_mm * res / mm_per_unit * s, cx=w / 2, cy=h / 2), \
            "EXIF FocalLength and FocalPlaneXResolution (sensor size)"
    f35 = t.exif_float("FocalLengthIn35mmFilm")
    if f35 and f35 > 0:
        return Calibration(f=f35 * float(np.hypot(w, h)) / DIAGONAL_35MM, cx=w / 2, cy=h / 2), \
            "EXIF FocalLengthIn35mmFilm"
    problems.append(("no focal length (DJI XMP DewarpData or CalibratedFocalLength, EXIF "
                     "FocalLength with FocalPlaneXResolution, or FocalLengthIn35mmFilm)", t.path))
    return None


def photo_pose(t: PhotoTags, camera_heights: str = "absolute",
               takeoff_height: Optional[float] = None, problems: Optional[List] = None
               ) -> Optional[PhotoPose]:
    """The :class:`PhotoPose` of one photo's tags, or None with (cause, photo path) pairs
    appended to ``problems`` for each missing part (every cause is looked for)."""
    problems = [] if problems is None else problems
    pos = _position(t, camera_heights, takeoff_height, problems)
    att = _attitude(t, problems)
    interior = _interior(t, problems)
    if pos is None or att is None or interior is None:
        return None
    lat, lon, h, rel, std_h, std_v, psrc = pos
    cam = " ".join(str(t.exif.get(k, "")).strip() for k in ("Make", "Model")).strip() or "unknown camera"
    return PhotoPose(t.path, lat, lon, h, camera_heights, att[0], att[1], att[2], att[3],
                     interior[0], interior[1], f"{cam} {t.size[0]}×{t.size[1]}", t.size,
                     std_h, std_v, psrc, rel)


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


CAMERA_TO_BODY = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
"""Camera axes (x right, y down, z optical axis) in body axes (x forward, y right, z down)."""
NED_TO_ENU = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])


def gimbal_rotation(yaw: float, pitch: float, roll: float, convergence: float = 0.0) -> np.ndarray:
    """R (3×3) of the model frame (x, y, z) = (map east, map north, up): Xc = R·(X − C), camera
    x right, y down, z forward, from DJI gimbal angles in degrees (module docstring).
    ``convergence``: the azimuth of true north in the map grid, degrees clockwise from grid
    north (added to every azimuth)."""
    r_nb = _rz(np.radians(yaw + convergence)) @ _ry(np.radians(pitch)) @ _rx(np.radians(roll))
    return (NED_TO_ENU @ r_nb @ CAMERA_TO_BODY).T


def gimbal_angles(R: np.ndarray, convergence: float = 0.0) -> Tuple[float, float, float]:
    """(yaw, pitch, roll) in degrees of the model-frame rotation ``R`` (Xc = R·(X − C)): the
    inverse of :func:`gimbal_rotation` (yaw in [0, 360), pitch in [−90, 90])."""
    r_nb = NED_TO_ENU.T @ np.asarray(R, dtype=np.float64).T @ CAMERA_TO_BODY.T
    yaw = np.degrees(np.arctan2(r_nb[1, 0], r_nb[0, 0])) - convergence
    pitch = np.degrees(-np.arcsin(np.clip(r_nb[2, 0], -1.0, 1.0)))
    roll = np.degrees(np.arctan2(r_nb[2, 1], r_nb[2, 2]))
    return float(yaw % 360.0), float(pitch), float(roll)
