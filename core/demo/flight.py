"""The camera and a lawnmower flight over the demo field, in the scene's local frame.

Local frame: map coordinates (EPSG:32654, ellipsoidal heights) minus the scene offset; x east,
y north, z up, metres. A pose is (R, C): a point X is seen at ``Xc = R·(X − C)`` with x right,
y down, z forward (into the scene). Pixels follow the project convention (origin at the top-left
image corner, centre of the top-left pixel at (0.5, 0.5)); the calibration is a
:class:`core.reconstruction.Calibration` in that convention.
"""
from dataclasses import dataclass
from typing import List, Optional

import numpy as np

from ..reconstruction import Calibration, project_block
from ..rotations import rotation_matrix
from .scene import Scene

SIZES = {"small": (800, 600), "medium": (1600, 1200)}
ALTITUDE = 25.0        # m above the field's mean ground
LINE_SPACING = 12.0    # m between flight lines (about 60 % side overlap)
PHOTO_SPACING = 6.0    # m between photos along a line (about 70 % forward overlap)
LINES = 3
PHOTOS_PER_LINE = 12
SENSOR_WIDTH_MM = 13.2
TILT_SD, TILT_MAX, YAW_SD = 1.5, 4.0, 1.0   # degrees
START = (2024, 6, 1, 10, 0, 0)


@dataclass(frozen=True)
class CameraModel:
    """One frame camera. ``calibration`` in pixels of this image size, ``pixel_mm`` square."""
    label: str
    model: str
    width: int
    height: int
    calibration: Calibration
    pixel_mm: float

    @property
    def focal_mm(self) -> float:
        return self.calibration.f * self.pixel_mm


@dataclass
class Shot:
    """One photo: local pose, flight line, compass yaw (degrees clockwise from north), GNSS
    position as the drone logged it (map coordinates, with metre-level error) and time;
    ``motion``: a rolling-shutter :class:`.rolling_shutter.Motion` (None: global shutter)."""
    label: str
    filename: str
    R: np.ndarray
    C: np.ndarray
    line: int
    yaw_deg: float
    gps: np.ndarray
    time: str
    motion: Optional[object] = None


def make_camera(size: str) -> CameraModel:
    """The demo camera at ``size`` ('small' 800×600 or 'medium' 1600×1200): a 13.2 mm wide
    sensor with an adjusted calibration that has every Metashape frame term but the skew b2 and
    k4/p3/p4. No skew: OpenSfM (the ODM project) has no skew term, and with it the ODM project
    would miss the photos by b2·(v − cy)/f (0.12 px); b2 is tested on the real goya_test."""
    if size not in SIZES:
        raise ValueError(f"size must be one of {sorted(SIZES)}, not {size!r}")
    w, h = SIZES[size]
    s = w / 800.0
    cal = Calibration(f=680.0 * s, cx=(400.0 + 3.2) * s, cy=(300.0 - 2.1) * s,
                      b1=0.62 * s, b2=0.0, k1=-0.062, k2=0.041, k3=-0.012,
                      p1=0.0009, p2=-0.0006)
    px = SENSOR_WIDTH_MM / w
    return CameraModel(label=f"DemoCam ({cal.f * px:.2f}mm)", model="DemoCam", width=w, height=h,
                       calibration=cal, pixel_mm=px)


def nadir_rotation(heading: float) -> np.ndarray:
    """Local → camera rotation of a nadir camera whose image top points along ``heading``
    (radians, counter-clockwise from east)."""
    c, s = np.cos(heading), np.sin(heading)
    return np.array([[s, -c, 0.0],      # image x (right)
                     [-c, -s, 0.0],     # image y (down) = backwards
                     [0.0, 0.0, -1.0]])  # optical axis = down


def plan_flight(scene: Scene, rng) -> List[Shot]:
    """Three lines along x, alternately eastwards and westwards, 12 photos each, with slight
    tilts (sd 1.5°, at most 4°), yaw jitter and position noise of a real drone."""
    lay, off = scene.layout, scene.offset
    xc = lay.origin[0] + lay.size[0] / 2 - off[0]
    yc = lay.origin[1] - lay.size[1] / 2 - off[1]
    z = float(scene.ground_local(xc, yc)) + ALTITUDE
    xs = xc + PHOTO_SPACING * (np.arange(PHOTOS_PER_LINE) - (PHOTOS_PER_LINE - 1) / 2)
    shots, t = [], 0
    for line in range(LINES):
        y = yc + LINE_SPACING * ((LINES - 1) / 2 - line)
        eastwards = line % 2 == 0
        heading = 0.0 if eastwards else np.pi
        for x in (xs if eastwards else xs[::-1]):
            tilt = np.clip(rng.normal(0.0, TILT_SD, 2), -TILT_MAX, TILT_MAX)
            yaw_j = rng.normal(0.0, YAW_SD)
            R = rotation_matrix(np.radians([tilt[0], tilt[1], yaw_j])) @ nadir_rotation(heading)
            C = np.array([x, y, z]) + rng.normal(0.0, [0.15, 0.15, 0.1])
            gps = C + off + rng.normal(0.0, [0.8, 0.8, 1.5])
            n = len(shots) + 1
            sec = START[5] + t
            shots.append(Shot(label=f"DJI_{n:04d}", filename=f"DJI_{n:04d}.JPG", R=R, C=C,
                              line=line + 1, yaw_deg=float((90.0 - np.degrees(heading) - yaw_j) % 360.0),
                              gps=gps, time=f"{START[0]:04d}:{START[1]:02d}:{START[2]:02d} "
                                            f"{START[3]:02d}:{START[4] + sec // 60:02d}:{sec % 60:02d}"))
            t += 2
        t += 10
    return shots


def project_still(camera: CameraModel, shots: List[Shot], xyz_local: np.ndarray):
    """Pixels (m, n, 2) and status (m, n) of local points in the shots at their poses, the
    motion ignored (a global shutter)."""
    cal = camera.calibration
    R = np.array([s.R for s in shots])
    C = np.array([s.C for s in shots])
    return project_block(np.asarray(xyz_local, np.float64), R, C, cal, camera.width, camera.height,
                         cal.valid_radius2(camera.width, camera.height))
