"""Open Photogrammetry Format projects (PIX4Dmatic exports): a ``project.opf`` and its items.

Read with pyopf (Pix4D's reader, imported at the read: an optional package). Used: the camera
list (image URIs), the input cameras (sensor sizes), the top-level scene reference frame (CRS)
and the first calibration's calibrated cameras. Conventions, from the OPF 1.0 specification
(https://pix4d.github.io/opf-spec) and pyopf's ``examples/compute_reprojection_error.py``:

* **Processing CRS.** Calibrated positions are in the *translated canonical* frame of the scene
  reference frame: canonical = swap_xy(scale · base) + shift, with ``base`` in the CRS's own
  axis order (``swap_xy`` is true only for a left-handed, northing-first CRS). In our (east,
  north, up) order that is model = (s_e·E, s_n·N, s_h·h) + shift: the model frame here (an
  :class:`~.geodesy.OffsetFrame` with per-axis scale).
* **Orientation.** ``orientation_deg`` = (ω, φ, κ): R_x(ω)R_y(φ)R_z(κ) maps the image frame
  (x right, y up, z back towards the viewer: "right-top-back") to the processing CRS;
  ``position`` is the centre C. Ours (x right, y down, z forward): R = diag(1, −1, −1)·R_opkᵀ.
* **Pixels.** ``principal_point_px`` is measured from the top-left *corner* of the top-left
  pixel, as ours: no half-pixel shift.
* **Perspective.** u = cx + f·x', v = cy + f·y' with x' = x·(1 + R1r² + R2r⁴ + R3r⁶) +
  2·T1·xy + T2·(r² + 2x²), y' = y·(…) + 2·T2·xy + T1·(r² + 2y²): OpenCV's order (T1 = OpenCV
  p1), so our p1 = T2, p2 = T1. One focal length: no affinity, no skew.
* **Fisheye** (Pix4D's): θ = 2/π·atan(r), ρ = p0 + p1θ + p2θ² + p3θ³, (u, v) = [c d; e f]·
  ρ·(x, y)/r + (cx, cy), in the same x-right, y-down image axes as the perspective model (the
  specification does not spell them out; c = f > 0 in its examples needs them). Read when it is
  our equidistant fisheye: p0 = p2 = 0 and e = 0 (then f_ours = f·p1·2/π, b1 = (c − f)·p1·2/π,
  b2 = d·p1·2/π, k1 = p3/p1·(2/π)²); other fisheyes and spherical cameras are refused.
* **Photos.** The camera list's URIs, relative to the folder of the file that lists them
  (``#page=n`` fragments dropped, ``file:`` URIs and Windows paths kept); the camera label is
  the image's file name. Cameras without a calibrated pose are kept, not aligned.
* Rolling-shutter parameters are not applied (said in the notes).
* **Rigs** (multispectral cameras: one capture, one camera per band). The specification gives
  every calibrated camera its own position and orientation, so each band file is placed by its
  own pose and the rig relatives are not needed. A band camera of a rig capture without a
  calibrated pose is not placed from its reference camera through the rig relatives: it is left
  unaligned, and a note names how many (no tool measures it).
"""
import math
import re
import warnings
from pathlib import Path
from typing import Dict, List, Optional
from urllib.parse import unquote, urlparse
from urllib.request import url2pathname

import numpy as np

from ..crs import project_crs
from ..errors import InputError
from ..photos import file_name, is_windows_path
from .frame_model import FISHEYE, Calibration
from .geodesy import OffsetFrame
from .model import Camera, Reconstruction, Sensor
from .project_reader import OpenOptions, ProjectReader

PYOPF_HINT = "pip install pyopf"
PROJECT_SUFFIX = ".opf"
AUTHORITY_CODES = re.compile(r"[A-Za-z]+:\d+(\+([A-Za-z]+:)?\d+)?")
"""OPF's CRS definitions by code: ``EPSG:32654``, ``EPSG:32654+5773``, ``EPSG:6677+EPSG:6695``."""


def find_project_opf(path: Path) -> Optional[Path]:
    """The ``.opf`` file of ``path``: itself, or the one ``.opf`` in a folder (None if none)."""
    if path.is_file() and path.suffix.lower() == PROJECT_SUFFIX:
        return path
    if path.is_dir():
        found = sorted(p for p in path.iterdir() if p.suffix.lower() == PROJECT_SUFFIX and p.is_file())
        if len(found) > 1:
            raise InputError(f"{path}: several OPF projects ({', '.join(p.name for p in found)}); "
                             "give the .opf file.")
        return found[0] if found else None
    return None


def _load(opf: Path):
    """pyopf's resolved project; its failures (and skipped items) become one InputError."""
    try:
        from pyopf.io import load
        from pyopf.resolve import resolve
    except ImportError:
        raise InputError(f"{opf}: reading OPF projects needs the Python package pyopf, which is "
                         f"not installed. Install it ({PYOPF_HINT}) and run again.") from None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            raw = load(str(opf))
            project = resolve(raw)
        except Exception as exc:    # pyopf raises RuntimeError, AssertionError, KeyError, …
            cause = exc.__cause__ or exc
            raise InputError(f"{opf}: not a readable OPF project ({type(exc).__name__}: {exc}"
                             + (f"; {type(cause).__name__}: {cause}" if cause is not exc else "")
                             + "). Export the project from PIX4Dmatic again.") from None
    skipped = [str(w.message) for w in caught if "will not be loaded" in str(w.message)]
    return raw, project, skipped


def _resource_folder(raw, kind: str, opf: Path) -> Path:
    """The folder of the first resource of the project's first ``kind`` item: relative URIs in
    that resource are relative to it."""
    for item in raw.items:
        if getattr(item.type, "value", item.type) == kind and item.resources:
            uri = urlparse(item.resources[0].uri)
            rel = Path(url2pathname(uri.path)) if uri.scheme in ("", "file") else Path()
            return (rel if rel.is_absolute() else opf.parent / rel).parent
    return opf.parent


def _require(obj, kind: str, opf: Path, raw, skipped: List[str]):
    """``obj``, else an InputError naming the item's files and why pyopf skipped them."""
    if obj is None:
        files = [r.uri for item in raw.items if getattr(item.type, "value", item.type) == kind
                 for r in item.resources]
        what = kind.replace("_", " ")
        why = "; ".join(re.sub(r"^The item .*? will not be loaded: ", "", m) for m in skipped)
        raise InputError(f"{opf}: the project has no readable {what}"
                         + (f" ({', '.join(files)}: {why or 'not loaded'})" if files
                            else " (no such item)")
                         + ". Export the project from PIX4Dmatic again (with its calibration), "
                         "and keep the files the .opf lists beside it.")
    return obj


def _vector(values, n: int, what: str, opf: Path) -> np.ndarray:
    v = np.asarray(values, dtype=np.float64).ravel()
    if v.size != n or not np.all(np.isfinite(v)):
        raise InputError(f"{opf}: {what} must be {n} finite numbers, found {list(v)[:6]}.")
    return v


def opk_rotation(omega_phi_kappa_deg) -> np.ndarray:
    """OPF's R_x(ω)R_y(φ)R_z(κ) (image right-top-back → processing CRS) for angles in degrees."""
    o, p, k = np.radians(np.asarray(omega_phi_kappa_deg, dtype=np.float64))
    rx = np.array([[1, 0, 0], [0, math.cos(o), -math.sin(o)], [0, math.sin(o), math.cos(o)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(k), -math.sin(k), 0], [math.sin(k), math.cos(k), 0], [0, 0, 1]])
    return rx @ ry @ rz


def calibration_from_internals(internals, where: str) -> Calibration:
    """Our :class:`Calibration` of OPF perspective or (equidistant) fisheye internals."""
    kind = getattr(internals, "type", None)
    pp = np.asarray(internals.principal_point_px, dtype=np.float64)
    if kind == "perspective":
        k = list(np.asarray(internals.radial_distortion, dtype=np.float64)) + [0.0] * 3
        t = list(np.asarray(internals.tangential_distortion, dtype=np.float64)) + [0.0] * 2
        return Calibration(f=float(internals.focal_length_px), cx=pp[0], cy=pp[1],
                           k1=k[0], k2=k[1], k3=k[2], p1=t[1], p2=t[0])
    if kind == "fisheye":
        poly = list(np.asarray(internals.polynomial, dtype=np.float64)) + [0.0] * 4
        c, d, e, f = np.asarray(internals.affine, dtype=np.float64)
        p0, p1, p2, p3 = poly[:4]
        if p0 != 0.0 or p2 != 0.0 or e != 0.0 or p1 <= 0.0 or any(poly[4:]):
            raise InputError(f"{where}: a fisheye sensor with polynomial {poly[:4]} and affine "
                             f"[{c:g} {d:g}; {e:g} {f:g}] is not supported: only the equidistant "
                             "form (p0 = p2 = 0, no higher terms, e = 0) is. Calibrate it as a "
                             "perspective camera, or export the project from Pix4Dmapper.")
        s = p1 * 2.0 / math.pi
        return Calibration(f=f * s, cx=pp[0], cy=pp[1], b1=(c - f) * s, b2=d * s,
                           k1=p3 / p1 * (2.0 / math.pi) ** 2, model=FISHEYE)
    raise InputError(f"{where}: sensor model {kind!r} is not supported (only perspective and "
                     "equidistant fisheye cameras are).")


def _photo_path(uri: str, base: Path) -> str:
    """The file of a camera-list URI (a relative reference, a ``file:`` URI or a Windows path)."""
    uri = uri.split("#", 1)[0]
    if is_windows_path(uri):
        return uri
    url = urlparse(uri)
    if url.scheme == "file":
        path = url2pathname(url.path)
        return path.lstrip("\\/") if is_windows_path(path.lstrip("\\/")) else path
    path = Path(unquote(url.path))
    return str(path if path.is_absolute() else (base / path).resolve())


def open_opf(path, crs=None) -> Reconstruction:
    """Open an OPF project: a ``project.opf`` or the folder that holds one. ``crs``: the project
    CRS when the scene reference frame has none PROJ can use (a different CRS is refused)."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: file not found.")
    opf = find_project_opf(path)
    if opf is None:
        raise InputError(f"{path}: no .opf project file found.")
    raw, project, skipped = _load(opf)
    srf = _require(project.scene_reference_frame, "scene_reference_frame", opf, raw, skipped)
    calibration = _require(project.calibration, "calibration", opf, raw, skipped)
    calibrated = _require(calibration.calibrated_cameras, "calibration", opf, raw, skipped)
    camera_list = _require(project.camera_list, "camera_list", opf, raw, skipped)
    inputs = _require(project.input_cameras, "input_cameras", opf, raw, skipped)
    notes = []

    definition = srf.crs.definition
    crs_, how = project_crs(definition, f"{opf} (scene reference frame)", crs)
    if how and not (AUTHORITY_CODES.fullmatch(definition.strip()) and "kept as written" in how):
        notes.append(how)            # a compound of two codes (EPSG:6677+6695) has no code of its own
    if crs_ is not None and crs_.is_geographic:
        raise InputError(f"{opf}: the scene reference frame's CRS {crs_.name!r} is geographic; OPF "
                         "requires a projected (or engineering) one. Export the project again.")
    b2c = srf.base_to_canonical
    scale = _vector(b2c.scale, 3, "base_to_canonical.scale", opf)
    shift = _vector(b2c.shift, 3, "base_to_canonical.shift", opf)
    if not np.all(scale > 0):
        raise InputError(f"{opf}: base_to_canonical.scale {list(scale)} must be positive.")
    north_first = crs_ is not None and len(crs_.axis_info) >= 2 and \
        crs_.axis_info[0].direction.lower() == "north"
    if bool(b2c.swap_xy) != north_first:
        raise InputError(f"{opf}: swap_xy is {bool(b2c.swap_xy)} but the CRS "
                         f"{crs_.name if crs_ else definition!r} has its "
                         f"{'northing' if north_first else 'easting'} first; the scene reference "
                         "frame contradicts itself. Export the project again.")
    if b2c.swap_xy:                      # base (N, E, h) scaled, then swapped: (s1·E, s0·N, s2·h)
        scale = scale[[1, 0, 2]]
    frame = OffsetFrame(crs_, -shift, scale=scale)

    sizes: Dict[int, tuple] = {}
    names: Dict[int, str] = {}
    for s in inputs.sensors:
        w, h = (int(v) for v in s.image_size_px)
        sizes[s.id.int] = (w, h)
        names[s.id.int] = s.name
    sensors: Dict[str, Sensor] = {}
    for s in calibrated.sensors:
        sid = s.id.int
        if sid not in sizes:
            raise InputError(f"{opf}: calibrated sensor {sid} is not among the input cameras' "
                             "sensors (its image size is unknown).")
        where = f"{opf}, sensor {names[sid]!r}"
        cal = calibration_from_internals(s.internals, where)
        w, h = sizes[sid]
        sensors[str(sid)] = Sensor(id=str(sid), label=f"{names[sid]} ({w}x{h})", width=w, height=h,
                                   calibration=cal, type="fisheye" if cal.model == FISHEYE else "frame")
        if s.rig_relatives is not None:
            notes.append(f"sensor {names[sid]!r} is in a rig: each of its cameras is placed by its "
                         "own calibrated pose (the rig relatives are not needed)")

    base = _resource_folder(raw, "camera_list", opf)
    uris = {c.id.int: c.uri for c in camera_list.cameras}
    input_sensor = {cam.id.int: cam.sensor_id.int for cap in inputs.captures for cam in cap.cameras}
    poses = {c.id.int: c for c in calibrated.cameras}
    cameras: List[Camera] = []
    rolling = 0
    for cid, sensor_of in input_sensor.items():
        uri = uris.get(cid)
        if uri is None:
            raise InputError(f"{opf}: input camera {cid} is not in the camera list (no image).")
        photo = _photo_path(uri, base)
        pose = poses.get(cid)
        R = C = None
        sid = str(sensor_of)
        if pose is not None:
            sid = str(pose.sensor_id.int)
            if sid not in sensors:
                raise InputError(f"{opf}: calibrated camera {cid} uses sensor {sid}, which has no "
                                 "calibrated internals.")
            C = _vector(pose.position, 3, f"position of camera {cid}", opf)
            R = np.diag([1.0, -1.0, -1.0]) @ opk_rotation(
                _vector(pose.orientation_deg, 3, f"orientation_deg of camera {cid}", opf)).T
            rolling += pose.rolling_shutter is not None
        elif sid not in sensors:
            w, h = sizes.get(sensor_of, (0, 0))
            sensors[sid] = Sensor(id=sid, label=f"{names.get(sensor_of, sid)} ({w}x{h})",
                                  width=w, height=h, calibration=None)
        cameras.append(Camera(id=str(cid), label=file_name(photo), sensor_id=sid,
                              photo_path=photo, R=R, C=C))
    if rolling:
        notes.append(f"{rolling} camera(s) carry rolling-shutter parameters; they are not applied")
    unplaced = [uris.get(cam.id.int, str(cam.id.int)) for cap in inputs.captures
                if len(cap.cameras) > 1 for cam in cap.cameras if cam.id.int not in poses]
    if unplaced:
        notes.append(f"{len(unplaced)} band camera(s) of rig captures have no calibrated pose "
                     f"(e.g. {file_name(unplaced[0])}); their pose is not derived from the rig "
                     "relatives, so they are left unaligned and not measured: calibrate them in "
                     "PIX4Dmatic, or use a Metashape project (its rig offsets are applied)")
    missing = len(cameras) - sum(c.aligned for c in cameras)
    if missing:
        notes.append(f"{missing} camera(s) have no calibrated pose (not aligned)")
    label = getattr(raw, "name", None) or opf.stem
    return Reconstruction(source=opf, software="opf", label=label, crs=crs_, frame=frame,
                          sensors=sensors, cameras=cameras, notes=notes)


# --- the reader of open_reconstruction (readers.py) ---------------------------------------------
def recognises(path: Path) -> bool:
    """An ``.opf`` path (a missing one too: :func:`open_opf` says so), or a folder holding one
    (several: :func:`find_project_opf` refuses them)."""
    return path.suffix.lower() == PROJECT_SUFFIX or (path.is_dir()
                                                     and find_project_opf(path) is not None)


def _open(path: Path, options: OpenOptions) -> Reconstruction:
    return open_opf(path, options.source_crs)


READER = ProjectReader("OPF (PIX4Dmatic)", "a project.opf or the folder that holds it (needs "
                       "pyopf)", recognises, _open)
