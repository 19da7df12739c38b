"""The :class:`Reconstruction` type shared by the five project readers (Metashape, Pix4D, OPF,
OpenDroneMap and OpenSfM; :func:`open_reconstruction` picks one).

Cameras are kept in the reconstruction's *model frame* (see :mod:`.geodesy`): a Cartesian
frame in metres where a camera with rotation ``R`` and centre ``C`` sees a point ``X`` at
``Xc = R·(X − C)`` (x right, y down, z forward, i.e. +Zc in front of the lens).
Pixels: origin at the top-left image corner, centre of the top-left pixel at (0.5, 0.5).
A camera with a :class:`~.rolling_shutter.RollingShutter` has one pose per image row; ``R``/``C``
are then the pose of the centre row.
"""
import dataclasses
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Sequence, Tuple, Union

import numpy as np
from pyproj import CRS

from ..errors import EasyIDPError
from ..photos import photo_key, photo_size, resolve_photos, scale_to
from ..progress import as_progress
from .frame_model import BEHIND, INSIDE, OUTSIDE, Calibration, project_block
from .geodesy import ModelFrame, is_local
from .rolling_shutter import BLOCK_ELEMENTS as RS_BLOCK_ELEMENTS
from .rolling_shutter import RollingShutter, project_block_rs, ray_poses, row_tau, sensor_rows

__all__ = ["Sensor", "Camera", "Marker", "Reconstruction", "Projection", "VisiblePoints",
           "INSIDE", "BEHIND", "OUTSIDE"]

BLOCK_ELEMENTS = 1 << 19
"""Camera × point pairs projected at once; bounds the working memory (about 60 MB)."""


@dataclass
class Sensor:
    """A camera model: image size (px), calibration (None if never calibrated), model type."""
    id: str
    label: str
    width: int
    height: int
    calibration: Optional[Calibration]
    type: str = "frame"
    pixel_size_mm: Optional[float] = None
    focal_length_mm: Optional[float] = None
    rolling_shutter: bool = False
    master_id: Optional[str] = None          # multispectral rig: the master sensor
    rig_offset: Optional[np.ndarray] = None  # 4×4 slave camera → master camera transform
    _r2: Optional[float] = field(default=None, repr=False)

    @property
    def r2_limit(self) -> float:
        if self._r2 is None:
            self._r2 = self.calibration.valid_radius2(self.width, self.height)
        return self._r2


@dataclass
class Camera:
    """One photo. ``R``/``C`` (model frame) are None when the camera is not aligned;
    ``rolling_shutter``: its motion across the readout (None: one pose for the whole photo)."""
    id: str
    label: str
    sensor_id: str
    photo_path: Optional[str] = None
    enabled: bool = True
    group: Optional[str] = None
    master_id: Optional[str] = None
    R: Optional[np.ndarray] = None
    C: Optional[np.ndarray] = None
    rolling_shutter: Optional[RollingShutter] = None

    @property
    def aligned(self) -> bool:
        return self.R is not None


@dataclass
class Marker:
    """A ground control / check point: reference (x, y, z in the chunk CRS, or None) and
    the pixel observations placed in the photos {camera label: (u, v)} (project convention)."""
    id: str
    label: str
    reference: Optional[np.ndarray]
    reference_enabled: bool
    observations: Dict[str, Tuple[float, float]]


@dataclass
class Projection:
    """Dense result of :meth:`Reconstruction.project_points` for m cameras and n points.

    ``pixels`` (m, n, 2) float64, NaN where behind the camera or beyond the lens model's
    valid radius; ``status`` (m, n) uint8: INSIDE 0, BEHIND 1, OUTSIDE 2.
    """
    camera_labels: List[str]
    pixels: np.ndarray
    status: np.ndarray

    @property
    def inside(self) -> np.ndarray:
        return self.status == INSIDE

    def for_camera(self, label: str) -> Tuple[np.ndarray, np.ndarray]:
        i = self.camera_labels.index(label)
        return self.pixels[i], self.status[i]


@dataclass
class VisiblePoints:
    """Sparse result: only (camera, point) pairs that land inside the frame.

    ``camera`` (k,) index into ``camera_labels``, ``point`` (k,) index of the input point,
    ``pixels`` (k, 2). Memory grows with the hits, never with cameras × points.
    """
    camera_labels: List[str]
    camera: np.ndarray
    point: np.ndarray
    pixels: np.ndarray

    def for_camera(self, label: str) -> Tuple[np.ndarray, np.ndarray]:
        """(point indices, pixels) of one camera."""
        sel = self.camera == self.camera_labels.index(label)
        return self.point[sel], self.pixels[sel]

    def counts(self) -> np.ndarray:
        return np.bincount(self.camera, minlength=len(self.camera_labels))


@dataclass
class Reconstruction:
    """A solved photogrammetry project (one Metashape chunk or one Pix4D project).

    ``crs``: the project CRS (pyproj), None when unknown; ``is_local`` says it is a local /
    engineering system that cannot be related to map CRSs. ``frame`` converts map ↔ model.
    ``uncertainty_px``: camera label → the expected error (one standard deviation, pixels) of a
    ground point projected into that photo, for cameras read from photo tags; empty for solved
    projects (their error is not known per photo).
    """
    source: Path
    software: str
    label: str
    crs: Optional[CRS]
    frame: ModelFrame
    sensors: Dict[str, Sensor]
    cameras: List[Camera]
    enabled: bool = True
    markers: List[Marker] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    uncertainty_px: Dict[str, float] = field(default_factory=dict)

    # --- look-ups ----------------------------------------------------------------------------
    @property
    def is_local(self) -> bool:
        return is_local(self.crs)

    @property
    def rolling_shutter_cameras(self) -> List[Camera]:
        """Aligned cameras whose projections use a rolling-shutter motion."""
        return [c for c in self.cameras if c.aligned and c.rolling_shutter is not None]

    def camera(self, label: str) -> Camera:
        """The camera labelled ``label``, else the one photo it names by
        :func:`~..photos.photo_key` (``dji_0018.jpg`` finds ``DJI_0018``)."""
        for c in self.cameras:
            if c.label == label:
                return c
        key = photo_key(label)
        hits = [c for c in self.cameras if key in (photo_key(c.label), photo_key(c.photo_path or ""))]
        if len(hits) == 1:
            return hits[0]
        if hits:
            raise EasyIDPError(f"{self.source}: {label!r} could be any of the cameras "
                               f"{', '.join(c.label for c in hits[:5])}; give the camera's label.")
        raise EasyIDPError(f"{self.source}: no camera labelled {label!r}.")

    @property
    def aligned_cameras(self) -> List[Camera]:
        return [c for c in self.cameras if c.aligned and c.enabled]

    @property
    def unaligned_cameras(self) -> List[Camera]:
        return [c for c in self.cameras if not c.aligned]

    def select_cameras(self, cameras=None) -> List[Camera]:
        """The cameras to project with: ``cameras`` (Camera objects or labels), or by default
        the aligned, enabled ones. Raises :class:`EasyIDPError` for a camera that is not
        aligned (it has no pose)."""
        if cameras is None:
            return self.aligned_cameras
        out = []
        for c in cameras:
            cam = c if isinstance(c, Camera) else self.camera(str(c))
            if not cam.aligned:
                raise EasyIDPError(f"{self.source}: camera {cam.label!r} is not aligned; it "
                                   "has no pose to project with.")
            out.append(cam)
        return out

    def calibrated_sensor(self, cam: Camera) -> Sensor:
        """The sensor of ``cam``; raises :class:`EasyIDPError` when it has no adjusted
        calibration (the cameras were not aligned or optimised)."""
        s = self.sensors[cam.sensor_id]
        if s.calibration is None:
            raise EasyIDPError(f"{self.source}: sensor {s.label!r} (camera {cam.label!r}) has no "
                               "adjusted calibration; align/optimise the cameras first.")
        return s

    # --- coordinates -------------------------------------------------------------------------
    def to_model(self, xyz, crs=None) -> np.ndarray:
        """Map points (n, 3) in ``crs`` (default: the project CRS) → model frame."""
        return self.frame.to_model(xyz, crs)

    def from_model(self, xyz, crs=None) -> np.ndarray:
        """Model-frame points (n, 3) → map coordinates in ``crs`` (default: project CRS)."""
        return self.frame.from_model(xyz, crs)

    def camera_centres(self, crs=None, cameras=None) -> Tuple[List[str], np.ndarray]:
        """(labels, (m, 3) centres in ``crs``) of the aligned, enabled cameras."""
        cams = self.select_cameras(cameras)
        if not cams:
            return [], np.zeros((0, 3))
        return [c.label for c in cams], self.from_model(np.array([c.C for c in cams]), crs)

    # --- projection --------------------------------------------------------------------------
    def _blocks(self, xyz_model: np.ndarray, cams: List[Camera], distortion: bool,
                progress, inside_only: bool = False
                ) -> Iterator[Tuple[np.ndarray, slice, np.ndarray, np.ndarray]]:
        n = len(xyz_model)
        groups: Dict[Tuple[str, bool], List[int]] = {}     # (sensor, rolling shutter) → cameras
        for i, c in enumerate(cams):
            groups.setdefault((c.sensor_id, c.rolling_shutter is not None), []).append(i)
        total = max(1, len(cams) * n)
        done = 0
        for (sid, rolling), idx in groups.items():
            s = self.calibrated_sensor(cams[idx[0]])
            elements = RS_BLOCK_ELEMENTS if rolling else BLOCK_ELEMENTS
            pt_block = int(min(max(n, 1), elements))
            cam_block = max(1, elements // pt_block)
            for c0 in range(0, len(idx), cam_block):
                ci = np.array(idx[c0:c0 + cam_block])
                R = np.array([cams[i].R for i in ci])
                C = np.array([cams[i].C for i in ci])
                if rolling:
                    om = np.array([cams[i].rolling_shutter.rotation for i in ci])
                    sh = np.array([cams[i].rolling_shutter.translation for i in ci])
                for p0 in range(0, n, pt_block):
                    progress.check()
                    sl = slice(p0, min(n, p0 + pt_block))
                    if rolling:
                        uv, st = project_block_rs(xyz_model[sl], R, C, om, sh, s.calibration,
                                                  s.width, s.height, s.r2_limit, distortion,
                                                  inside_only)
                    else:
                        uv, st = project_block(xyz_model[sl], R, C, s.calibration, s.width,
                                               s.height, s.r2_limit, distortion)
                    yield ci, sl, uv, st
                    done += len(ci) * (sl.stop - sl.start)
                    progress.set(100.0 * done / total)

    def project_points(self, xyz, crs=None, *, cameras: Optional[Sequence] = None,
                       distortion: bool = True, inside_only: bool = False,
                       progress=None, is_cancelled=None) -> Union[Projection, VisiblePoints]:
        """Project map points into photos.

        ``xyz`` (n, 3) in ``crs`` (default: the project CRS; heights as described in
        :mod:`.geodesy`). ``cameras``: labels or Camera objects (default: all aligned, enabled).
        Returns a dense :class:`Projection` ((m, n, 2) pixels and (m, n) status), or with
        ``inside_only=True`` a sparse :class:`VisiblePoints` whose memory grows only with the
        hits (use it for large n). Work is done in blocks of cameras × points, so the working
        memory stays bounded. A point is INSIDE when Zc > 0 (tested first), it is within the
        lens model's valid radius, and 0 <= u <= w, 0 <= v <= h.

        ``distortion=False`` gives pixels of the photo with its *lens* distortion removed
        (k1–k4, p1–p4 dropped): an ideal pinhole that keeps the sensor's pixel grid, i.e. the
        focal length, principal point and Metashape's affinity and skew terms b1, b2
        (u = cx + x(f + b1) + y·b2, v = cy + y·f); :meth:`pixel_to_ray` reads such pixels the
        same way. A rolling-shutter camera's motion is part of the exposure and is applied in
        both modes: each point takes the pose of the sensor row it was exposed on (see
        :mod:`.rolling_shutter`).
        """
        return self.project_model_points(self.to_model(xyz, crs), cameras=cameras,
                                         distortion=distortion, inside_only=inside_only,
                                         progress=progress, is_cancelled=is_cancelled)

    def project_model_points(self, xyz_model, *, cameras: Optional[Sequence] = None,
                             distortion: bool = True, inside_only: bool = False,
                             progress=None, is_cancelled=None) -> Union[Projection, VisiblePoints]:
        """:meth:`project_points` of points already in the model frame (:meth:`to_model`): for
        a caller that projects the same points into photos one by one (the CRS transformation
        done once)."""
        prog = as_progress(progress, is_cancelled)
        cams = self.select_cameras(cameras)
        labels = [c.label for c in cams]
        xyz_model = np.asarray(xyz_model, np.float64).reshape(-1, 3)
        n = len(xyz_model)
        if inside_only:
            parts_c, parts_p, parts_uv = [], [], []
            for ci, sl, uv, st in self._blocks(xyz_model, cams, distortion, prog, True):
                mi, pi = np.nonzero(st == INSIDE)
                parts_c.append(ci[mi].astype(np.int32))
                parts_p.append((pi + sl.start).astype(np.int64))
                parts_uv.append(uv[mi, pi])
            if not parts_c:
                return VisiblePoints(labels, np.zeros(0, np.int32), np.zeros(0, np.int64),
                                     np.zeros((0, 2)))
            cam_i = np.concatenate(parts_c)
            order = np.argsort(cam_i, kind="stable")
            return VisiblePoints(labels, cam_i[order], np.concatenate(parts_p)[order],
                                 np.concatenate(parts_uv)[order])
        pixels = np.empty((len(cams), n, 2))
        status = np.empty((len(cams), n), dtype=np.uint8)
        for ci, sl, uv, st in self._blocks(xyz_model, cams, distortion, prog):
            pixels[ci, sl] = uv
            status[ci, sl] = st
        return Projection(labels, pixels, status)

    def pixel_to_ray(self, camera, uv, distortion: bool = True) -> Tuple[np.ndarray, np.ndarray]:
        """Pixels (n, 2) of one photo → rays in the model frame.

        Returns (origins, unit directions (n, 3)). The origin is the camera centre (3,), or for a
        rolling-shutter camera the centre at each pixel's row (n, 3); both broadcast against
        the directions. The lens distortion is inverted by Newton iteration to better than
        1e-6 px; ``distortion=False`` reads pixels of the undistorted photo, exactly as
        :meth:`project_points` writes them. Intersect with a surface in the model frame and
        convert with :meth:`from_model` to get map coordinates.
        """
        cam = self.select_cameras([camera])[0]
        s = self.calibrated_sensor(cam)
        uv = np.atleast_2d(np.asarray(uv, dtype=np.float64))
        x, y = s.calibration.pixel_to_normalised(uv[:, 0], uv[:, 1], distortion)
        if cam.rolling_shutter is None:
            d = np.column_stack([x, y, np.ones_like(x)]) @ cam.R   # Rᵀ·(x, y, 1)
            return cam.C.copy(), d / np.linalg.norm(d, axis=1, keepdims=True)
        rows = sensor_rows(s.calibration, x, y, uv[:, 1], s.r2_limit, distortion)
        origins, d = ray_poses(cam.R, cam.C, cam.rolling_shutter, row_tau(rows, s.height), x, y)
        return origins, d / np.linalg.norm(d, axis=1, keepdims=True)

    def summary(self) -> str:
        """A short human-readable description (what a user checks first)."""
        crs = "none" if self.crs is None else self.crs.name + (" (local)" if self.is_local else "")
        return (f"{self.software} {self.label!r} from {self.source}: CRS {crs}; "
                f"{len(self.sensors)} sensor(s); {len(self.cameras)} camera(s), "
                f"{len(self.aligned_cameras)} aligned and enabled, "
                f"{len(self.unaligned_cameras)} not aligned"
                + (f"; rolling-shutter compensation on {len(self.rolling_shutter_cameras)}"
                   if self.rolling_shutter_cameras else ""))


def fit_sensors_to_photos(recon: "Reconstruction") -> "Reconstruction":
    """Sensors fitted to the photo files as they are stored (in place; returns ``recon``).

    Photos resized with the same aspect (e.g. a 5472×3648 sensor's photos saved at 1368×912)
    get a copy of their sensor whose calibration is scaled by s = photo / sensor size: f, cx,
    cy, b1, b2 (pixels) × s; distortion terms act on normalised coordinates and are unchanged.
    With pixels measured from the image corner this is exactly u_photo = s·u_sensor. Said in
    ``notes``. Photos of another aspect ratio are left with their sensor and noted: they are
    not copies of what the sensor took, and the tools refuse them naming both sizes. Photos
    whose file is not found (or whose header cannot be read) are not looked at.
    """
    cams = [c for c in recon.cameras if c.photo_path and recon.sensors.get(c.sensor_id) is not None
            and recon.sensors[c.sensor_id].calibration is not None]
    found, _missing = resolve_photos([c.label for c in cams], [c.photo_path for c in cams])
    groups: Dict[Tuple[str, Tuple[int, int]], List[Camera]] = {}
    for c in cams:
        size = photo_size(found[c.label]) if c.label in found else None
        s = recon.sensors[c.sensor_id]
        if size is not None and size != (s.width, s.height):
            groups.setdefault((c.sensor_id, size), []).append(c)
    for (sid, (w, h)), group in groups.items():
        s = recon.sensors[sid]
        k = scale_to((s.width, s.height), (w, h))
        names = ", ".join(os.path.basename(found[c.label]) for c in group[:3]) + \
            (" …" if len(group) > 3 else "")
        if k is None:
            recon.notes.append(
                f"{len(group)} photo(s) of sensor {s.label!r} ({names}) are {w}×{h} px but the "
                f"sensor is {s.width}×{s.height} px, another aspect ratio: not resized copies "
                "of its photos (cropped?); they are refused")
            continue
        cal = s.calibration
        scaled = dataclasses.replace(cal, f=cal.f * k, cx=cal.cx * k, cy=cal.cy * k,
                                     b1=cal.b1 * k, b2=cal.b2 * k)
        new = dataclasses.replace(s, id=f"{sid}@{w}x{h}", label=f"{s.label} (scaled to {w}×{h})",
                                  width=w, height=h, calibration=scaled, _r2=None,
                                  pixel_size_mm=s.pixel_size_mm / k if s.pixel_size_mm else None)
        recon.sensors[new.id] = new
        for c in group:
            c.sensor_id = new.id
        recon.notes.append(
            f"{len(group)} photo(s) of sensor {s.label!r} ({names}) are {w}×{h} px, the sensor "
            f"{s.width}×{s.height} px: resized copies (×{k:g}); the calibration is scaled to "
            "match (f, cx, cy × the same factor), so pixels refer to the photos as stored")
    return recon
