"""The OpenSfM file format: ``reconstruction.json``, its cameras and shots, ``reference_lla``.

``reconstruction.json`` is a JSON *list* of reconstructions (OpenSfM keeps partial models when
not every photo joins one), each ``{"cameras", "shots", "points", "reference_lla", …}``
(``opensfm/io.py``: ``reconstructions_from_json``, ``camera_from_json``):

* a shot's pose is world → camera: ``Xc = R·X + t`` with ``R`` the axis-angle vector
  ``rotation`` (Rodrigues) and ``t`` = ``translation``; the camera centre is ``C = −Rᵀt``. Camera
  axes are x right, y down, z forward, as ours, so ``Xc = R·(X − C)`` directly.
* cameras use *normalised image coordinates*: origin at the image centre, divided by
  ``size = max(width, height)`` (``features.normalized_image_coordinates``: ``xn = (u_cv + 0.5 −
  w/2) / size`` with OpenCV's integer pixel centres ``u_cv``). With our corner-origin pixels
  ``u = u_cv + 0.5``, so ``u = w/2 + size·xn`` and ``v = h/2 + size·yn``: no half-pixel shift.
  A camera model maps a normalised ray to ``xn = focal_x·x' + c_x``, ``yn = focal_y·y' + c_y``
  (``Affine``; ``perspective``/``fisheye``: one ``focal``, no principal point offset), so in
  pixels ``f = focal_y·size``, ``b1 = (focal_x − focal_y)·size``, ``cx = w/2 + c_x·size``,
  ``cy = h/2 + c_y·size`` (the conversion is done here, once).
* distortion (``geometry/camera_distortions_functions.h``) acts on the projected ray: radial
  ``1 + k1r² + k2r⁴ (+ k3r⁶)`` and OpenCV-ordered tangential terms ``2p1xy + p2(r² + 2x²)``,
  so OpenSfM p1 = our p2 and OpenSfM p2 = our p1. The fisheye projections put the equidistant
  θ = atan(r) first (``FisheyeProjection``), then ``Disto24`` (``fisheye``: k1, k2) or
  ``Disto2468`` (``fisheye_opencv``: k1–k4): the OpenCV fisheye model.
"""
import json
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..errors import InputError
from ..rotations import rotation_matrix
from .frame_model import BROWN, FISHEYE, Calibration

PROJECTION_TYPES = {
    # type: (lens model, focal keys, has principal point, distortion terms)
    "perspective": (BROWN, ("focal",), False, ("k1", "k2")),
    "simple_radial": (BROWN, ("focal_x", "focal_y"), True, ("k1",)),
    "radial": (BROWN, ("focal_x", "focal_y"), True, ("k1", "k2")),
    "brown": (BROWN, ("focal_x", "focal_y"), True, ("k1", "k2", "k3", "p1", "p2")),
    "fisheye": (FISHEYE, ("focal",), False, ("k1", "k2")),
    "fisheye_opencv": (FISHEYE, ("focal_x", "focal_y"), True, ("k1", "k2", "k3", "k4")),
}
"""OpenSfM projection types read exactly by :class:`Calibration` (``opensfm/io.py``)."""
REFUSED_TYPES = {
    "spherical": "a 360° panorama", "equirectangular": "a 360° panorama",
    "dual": "a blend of perspective and fisheye projections",
    "fisheye62": "a fisheye with k5, k6 and tangential terms",
    "fisheye624": "a fisheye with thin-prism terms",
}


def load_json(path: Path, what: str):
    """Parse a JSON file; a clear InputError when it is missing, unreadable or not JSON."""
    try:
        with open(path, "rb") as fh:
            return json.loads(fh.read().decode("utf-8", errors="replace"))
    except FileNotFoundError:
        raise InputError(f"{path}: {what} not found.") from None
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a readable JSON {what} ({exc}). The file is damaged or "
                         "was cut short; copy it again from the processing machine.") from None


def read_reconstruction_list(path: Path) -> List[dict]:
    """The list of reconstructions in an OpenSfM ``reconstruction*.json`` (checked for shape)."""
    doc = load_json(path, "OpenSfM reconstruction file")
    if isinstance(doc, dict) and "shots" in doc:      # a single reconstruction (not a list)
        doc = [doc]
    if not isinstance(doc, list) or not all(isinstance(r, dict) for r in doc):
        raise InputError(f"{path}: not an OpenSfM reconstruction file (expected a list of "
                         "reconstructions with 'cameras' and 'shots').")
    if not doc:
        raise InputError(f"{path}: the file holds no reconstruction (an empty list): OpenSfM "
                         "could not orient the photos. Check the processing log (too little "
                         "overlap or too few features) and run the reconstruction again.")
    for i, r in enumerate(doc):
        if not isinstance(r.get("cameras"), dict) or not isinstance(r.get("shots"), dict):
            raise InputError(f"{path}: reconstruction {i} has no 'cameras' or 'shots' table; "
                             "this is not an OpenSfM reconstruction file.")
    return doc


# --- cameras ----------------------------------------------------------------------------------------
def _number(obj: dict, key: str, where: str, default: Optional[float] = None) -> float:
    v = obj.get(key, default)
    if v is None:
        raise InputError(f"{where}: '{key}' is missing; the camera model is incomplete.")
    try:
        v = float(v)
    except (TypeError, ValueError):
        raise InputError(f"{where}: '{key}' is not a number ({v!r}).") from None
    if not np.isfinite(v):
        raise InputError(f"{where}: '{key}' is not a finite number.")
    return v


def camera_calibration(key: str, cam: dict, where: str) -> Tuple[Calibration, int, int, str]:
    """(Calibration in our pixels, width, height, OpenSfM projection type) of one camera."""
    here = f"{where}: camera {key!r}"
    ptype = str(cam.get("projection_type", "perspective"))
    if ptype in REFUSED_TYPES or ptype not in PROJECTION_TYPES:
        what = REFUSED_TYPES.get(ptype, "a projection this reader does not know")
        raise InputError(f"{here} uses the OpenSfM projection type {ptype!r} ({what}), which "
                         "EasyIDP does not support: supported are "
                         f"{', '.join(PROJECTION_TYPES)}. Reprocess with another camera model "
                         "(ODM option --camera-lens).")
    model, focal_keys, has_pp, terms = PROJECTION_TYPES[ptype]
    w, h = int(_number(cam, "width", here, 0)), int(_number(cam, "height", here, 0))
    if w <= 0 or h <= 0:
        raise InputError(f"{here} has no image size (width {w}, height {h}); the camera model "
                         "is incomplete.")
    size = float(max(w, h))
    fx = _number(cam, focal_keys[0], here)
    fy = _number(cam, focal_keys[-1], here)
    if fx <= 0 or fy <= 0:
        raise InputError(f"{here}: the focal length ({fx}, {fy}) must be positive.")
    k = {t: _number(cam, t, here, 0.0) for t in terms}
    cx = w / 2.0 + (_number(cam, "c_x", here, 0.0) * size if has_pp else 0.0)
    cy = h / 2.0 + (_number(cam, "c_y", here, 0.0) * size if has_pp else 0.0)
    cal = Calibration(f=fy * size, cx=cx, cy=cy, b1=(fx - fy) * size,
                      k1=k.get("k1", 0.0), k2=k.get("k2", 0.0), k3=k.get("k3", 0.0),
                      k4=k.get("k4", 0.0), p1=k.get("p2", 0.0), p2=k.get("p1", 0.0), model=model)
    return cal, w, h, ptype


def normalised_to_pixels(xn, yn, width: int, height: int) -> Tuple[np.ndarray, np.ndarray]:
    """OpenSfM normalised image coordinates → our pixels (see the module docstring)."""
    size = float(max(width, height))
    return width / 2.0 + size * np.asarray(xn, float), height / 2.0 + size * np.asarray(yn, float)


# --- shots ------------------------------------------------------------------------------------------
def shot_pose(key: str, shot: dict, where: str) -> Tuple[np.ndarray, np.ndarray]:
    """(R world → camera, centre C) of one shot."""
    try:
        r = np.asarray(shot["rotation"], dtype=np.float64)
        t = np.asarray(shot["translation"], dtype=np.float64)
    except KeyError as exc:
        raise InputError(f"{where}: shot {key!r} has no {exc.args[0]!r}; the pose is "
                         "incomplete.") from None
    except (TypeError, ValueError):
        raise InputError(f"{where}: the pose of shot {key!r} is not made of numbers.") from None
    if r.shape != (3,) or t.shape != (3,) or not (np.all(np.isfinite(r)) and np.all(np.isfinite(t))):
        raise InputError(f"{where}: the pose of shot {key!r} should be two vectors of 3 finite "
                         "numbers (rotation, translation).")
    R = rotation_matrix(r)
    return R, -R.T @ t


def reference_lla(recon: dict, dataset: Optional[Path], where: str) -> Optional[Tuple[float, float, float]]:
    """(lat, lon, alt) of the topocentric frame: the reconstruction's ``reference_lla``, else
    the dataset's ``reference_lla.json``; None when neither exists."""
    ref = recon.get("reference_lla")
    src = where
    if ref is None and dataset is not None and (dataset / "reference_lla.json").is_file():
        src = str(dataset / "reference_lla.json")
        ref = load_json(dataset / "reference_lla.json", "reference_lla.json")
    if ref is None:
        return None
    if not isinstance(ref, dict):
        raise InputError(f"{src}: reference_lla should be {{latitude, longitude, altitude}}.")
    lat, lon = _number(ref, "latitude", src), _number(ref, "longitude", src)
    alt = _number(ref, "altitude", src, 0.0)
    if not (-90 <= lat <= 90 and -180 <= lon <= 360):
        raise InputError(f"{src}: reference_lla latitude {lat}, longitude {lon} are not "
                         "geographic coordinates.")
    return lat, lon, alt


def read_gcp_json(path: Path) -> List[dict]:
    """``ground_control_points.json`` → [{"id", "lla" (lat, lon, alt) or None,
    "observations": [(shot id, xn, yn)]}] (normalised image coordinates)."""
    doc = load_json(path, "ground control point file")
    pts = doc.get("points") if isinstance(doc, dict) else None
    if not isinstance(pts, list):
        raise InputError(f"{path}: expected {{\"points\": [...]}} (OpenSfM ground control points).")
    out = []
    for i, p in enumerate(pts):
        where = f"{path}, point {i}"
        if not isinstance(p, dict):
            raise InputError(f"{where}: not an object.")
        pos = p.get("position")
        lla = None if pos is None else (_number(pos, "latitude", where),
                                        _number(pos, "longitude", where),
                                        _number(pos, "altitude", where, 0.0))
        obs = []
        for o in p.get("observations", []):
            xy = o.get("projection") if isinstance(o, dict) else None
            if not isinstance(xy, list) or len(xy) != 2 or "shot_id" not in o:
                raise InputError(f"{where}: an observation needs 'shot_id' and a 2-number "
                                 "'projection'.")
            obs.append((str(o["shot_id"]), float(xy[0]), float(xy[1])))
        out.append({"id": str(p.get("id", i)), "lla": lla, "observations": obs})
    return out


def shot_counts(recons: List[dict]) -> List[int]:
    return [len(r.get("shots", {})) for r in recons]


def choose(recons: List[dict], chunk, where: str) -> Tuple[int, Optional[str]]:
    """(index, note) of the reconstruction to use: ``chunk`` (index) or the largest."""
    counts = shot_counts(recons)
    table = ", ".join(f"#{i}: {n} photos" for i, n in enumerate(counts))
    if chunk is None or str(chunk).strip() == "":
        i = int(np.argmax(counts))
        note = None if len(recons) == 1 else (
            f"{where} holds {len(recons)} reconstructions (partial models: {table}); using #{i}, "
            "the largest. Choose another with the chunk (CHUNK) parameter.")
        return i, note
    key = str(chunk).strip().lstrip("#")
    try:
        i = int(key)
    except ValueError:
        raise InputError(f"{where}: reconstruction {chunk!r}: give the index of a "
                         f"reconstruction ({table}).") from None
    if not 0 <= i < len(recons):
        raise InputError(f"{where} has no reconstruction #{i}: it holds {len(recons)} ({table}).")
    return i, None


def camera_table(recon: dict, where: str) -> Dict[str, Tuple[Calibration, int, int, str]]:
    return {str(k): camera_calibration(str(k), v, where) for k, v in recon["cameras"].items()
            if isinstance(v, dict)}
