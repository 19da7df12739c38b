"""DJI-style EXIF and XMP for the demo photos, so that the photo folder alone gives cameras.

Each photo gets what a DJI drone writes (see :mod:`core.reconstruction.photo_poses` for how
they are read): EXIF Make/Model, FocalLength, focal-plane resolution, image size and GPS; XMP
``drone-dji:`` GpsLatitude/GpsLongtitude, AbsoluteAltitude, RelativeAltitude,
GimbalYaw/Pitch/RollDegree and the camera's calibration as DewarpData and
CalibratedFocalLength/OpticalCenter. Values come from the truth with stated noise:

* position: the GNSS position the drone logged (:class:`~.flight.Shot` ``gps``: the truth
  + 0.8 m horizontal and 1.5 m vertical standard deviation), as WGS 84 latitude/longitude and
  the map height;
* angles: the true camera rotation as gimbal angles + normal noise of :data:`ANGLE_NOISE_DEG`;
* relative altitude: the true height above the take-off point (the ground under the first
  photo) + 0.3 m (barometer);
* the lens: the true calibration, exactly.

The noise has its own random stream, so the rest of the survey is unchanged.
"""
from typing import Dict

import numpy as np
from pyproj import CRS

from ..crs import transformer
from ..reconstruction.photo_folder import convergence
from ..reconstruction.photo_poses import gimbal_angles

__all__ = ["ANGLE_NOISE_DEG", "BARO_NOISE_M", "photo_tag_segments", "tag_jpeg", "noise_note"]

ANGLE_NOISE_DEG = (1.0, 0.5, 0.5)
"""Standard deviation (degrees) of the noise added to the true gimbal yaw, pitch and roll."""
BARO_NOISE_M = 0.3
XMP_HEAD = b"http://ns.adobe.com/xap/1.0/\x00"
XMP = ('<?xpacket begin="\ufeff" id="W5M0MpCehiHzreSzNTczkc9d"?>'
       '<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
       'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description '
       'rdf:about="DJI Meta Data" xmlns:drone-dji="http://www.dji.com/drone-dji/1.0/" '
       '{attrs}/></rdf:RDF></x:xmpmeta><?xpacket end="w"?>')


def _dms(deg: float):
    deg = abs(deg)
    d = int(deg)
    m = int((deg - d) * 60)
    return (float(d), float(m), round((deg - d - m / 60) * 3600, 6))


def photo_tag_segments(scene, camera, shots, seed: int) -> Dict[str, bytes]:
    """{photo label: the APP1 EXIF and APP1 XMP segments to put after the JPEG's SOI}."""
    from PIL import Image

    rng = np.random.default_rng([seed, 3])
    to_geo = transformer(CRS.from_epsg(scene.layout.epsg), CRS.from_epsg(4326))
    to_map = transformer(CRS.from_epsg(4326), CRS.from_epsg(scene.layout.epsg))
    off = np.asarray(scene.offset, dtype=np.float64)
    first = shots[0].C
    takeoff = float(scene.ground_local(first[0], first[1]))
    cal, w, h = camera.calibration, camera.width, camera.height
    dewarp = ",".join(f"{v:.6f}" for v in (
        cal.f + cal.b1, cal.f, cal.cx - w / 2, cal.cy - h / 2, cal.k1, cal.k2, cal.p2, cal.p1, cal.k3))
    out: Dict[str, bytes] = {}
    for s in shots:
        lon, lat = to_geo.transform(s.gps[0], s.gps[1])
        t_lon, t_lat = to_geo.transform(s.C[0] + off[0], s.C[1] + off[1])
        ypr = np.array(gimbal_angles(s.R, convergence(to_map, t_lon, t_lat)))
        ypr += rng.normal(0.0, ANGLE_NOISE_DEG)
        rel = float(s.C[2] - takeoff + rng.normal(0.0, BARO_NOISE_M))
        exif = Image.Exif()
        exif[0x010F], exif[0x0110] = "EasyIDP demo", camera.model
        exif[0x8769] = {0x920A: round(camera.focal_mm, 4), 0xA002: w, 0xA003: h,
                        0xA20E: round(10.0 / camera.pixel_mm, 4), 0xA210: 3}   # px per cm
        exif[0x8825] = {1: "N" if lat >= 0 else "S", 2: _dms(lat), 3: "E" if lon >= 0 else "W",
                        4: _dms(lon), 5: b"\x00" if s.gps[2] >= 0 else b"\x01",
                        6: round(abs(float(s.gps[2])), 3)}
        attrs = " ".join(f'drone-dji:{k}="{v}"' for k, v in (
            ("GpsLatitude", f"{lat:.9f}"), ("GpsLongtitude", f"{lon:.9f}"),
            ("AbsoluteAltitude", f"{s.gps[2]:+.3f}"), ("RelativeAltitude", f"{rel:+.3f}"),
            ("GimbalYawDegree", f"{(ypr[0] + 180) % 360 - 180:+.3f}"),
            ("GimbalPitchDegree", f"{ypr[1]:+.3f}"), ("GimbalRollDegree", f"{ypr[2]:+.3f}"),
            ("CamReverse", "0"), ("GimbalReverse", "0"),
            ("CalibratedFocalLength", f"{cal.f:.6f}"),
            ("CalibratedOpticalCenterX", f"{cal.cx:.6f}"),
            ("CalibratedOpticalCenterY", f"{cal.cy:.6f}"),
            ("DewarpData", f"2024-06-01;{dewarp}")))
        raw = exif.tobytes()                   # Pillow: "Exif\0\0" + the TIFF block
        out[s.label] = _app1(raw if raw.startswith(b"Exif\x00\x00") else b"Exif\x00\x00" + raw) + \
            _app1(XMP_HEAD + XMP.format(attrs=attrs).encode("utf-8"))
    return out


def _app1(payload: bytes) -> bytes:
    return b"\xff\xe1" + (len(payload) + 2).to_bytes(2, "big") + payload


def tag_jpeg(data: bytes, segments: bytes) -> bytes:
    """The JPEG ``data`` with ``segments`` right after its SOI marker."""
    return data[:2] + segments + data[2:]


def noise_note() -> str:
    """The noise levels, said once (the truth file and the demo's printout)."""
    return (f"photo tags: GNSS position (truth + 0.8 m horizontal, 1.5 m vertical), gimbal "
            f"angles (truth + {ANGLE_NOISE_DEG[0]:g}° yaw, {ANGLE_NOISE_DEG[1]:g}° pitch and "
            f"roll), relative altitude (truth + {BARO_NOISE_M:g} m), the lens exact")

