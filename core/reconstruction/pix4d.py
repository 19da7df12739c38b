"""Pix4Dmapper readers: the ``.p4d`` file, the project folder or ``1_initial/params``.

Files used (any subset that determines the cameras; ``<name>`` is the project prefix):

* ``<name>_offset.xyz`` (required): the model frame is project CRS − offset.
* ``<name>_calibrated_camera_parameters.txt``: per image K, radial R1..R3, tangential T1 T2,
  centre t and rotation R, with ``P = K[R | −Rt]``; preferred when present.
* ``<name>_pmatrix.txt``: ``name p11 … p34`` per image; used (RQ-decomposed) otherwise, with
  the distortion of the ``.cam`` file when there is one.
* ``<name>_pix4d_calibrated_internal_camera_parameters.cam`` (Pix4D "F/Px/Py" format) or the
  Inpho-style ``*_calibrated_internal_camera_parameters.cam`` (FOCAL/XPOFF/SYM_DIST).
* ``<name>_wkt.prj``: the output CRS.

Multispectral rigs: the calibrated camera parameters give every band file its own K,
distortion and pose, so each band is placed by its own camera and no rig relatives are needed.
Without that file, the pmatrix path takes the lens from the ``.cam`` file; one that holds
several camera models (one per band of a rig: ``camera_calibration_file 0``, ``1``, …) does not
say which image uses which, so such a project is refused with a message. Pix4Dmapper writes its
rig relatives only into its quality report, not into the params folder (the files listed in
Pix4D's "What does the Output Params Folder contain?"), so a band file that Pix4D did not
calibrate cannot be placed from its capture's other bands: a band file the ``.p4d`` lists without
a calibrated pose, whose capture's other bands are calibrated (MicaSense ``IMG_0001_3.tif``,
DJI ``…_MS_NIR.TIF``: the capture is the name before the band suffix), is kept unaligned, and a
note names the project and says what to do.

Pix4D pixel coordinates: the principal point is measured from the top-left *corner* (in the
.cam files cx = w/2 − XPOFF_px exactly, with fiducials at the sensor corners), the same
convention as ours, so no half-pixel shift is applied. Distortion acts on normalised
coordinates about the calibrated principal point, tangential in OpenCV order:
x' = x·rad + 2T1xy + T2(r² + 2x²) → in our model p1 = T2, p2 = T1.
"""
import os
import re
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..crs import as_crs, project_crs
from ..photos import file_name, is_windows_path, photo_key
from ..errors import InputError, reads_file
from ..safe_xml import XMLError, parse_xml
from .frame_model import Calibration
from .geodesy import OffsetFrame
from .model import Camera, Reconstruction, Sensor
from .project_reader import OpenOptions, ProjectReader


def _numbers(tokens: List[str], where: str, line_no: int) -> np.ndarray:
    try:
        vals = np.array([float(t) for t in tokens])
    except ValueError:
        raise InputError(f"{where}, line {line_no}: expected numbers, found "
                         f"{' '.join(tokens)[:80]!r}. The file is damaged.") from None
    if not np.all(np.isfinite(vals)):
        raise InputError(f"{where}, line {line_no}: a value is not finite.")
    return vals


def read_offset(path) -> np.ndarray:
    """``offset.xyz``: three numbers (trailing spaces / missing newline are fine)."""
    tok = Path(path).read_text(errors="replace").split()
    if len(tok) != 3:
        raise InputError(f"{path}: expected three numbers (x y z offset), found {len(tok)} values.")
    return _numbers(tok, str(path), 1)


def read_pmatrix(path) -> Dict[str, np.ndarray]:
    """``pmatrix.txt`` → {image name: 3×4 P} (undistorted pixels = P·[X − offset; 1])."""
    out = {}
    for i, line in enumerate(Path(path).read_text(errors="replace").splitlines(), 1):
        tok = line.split()
        if not tok:
            continue
        if len(tok) != 13:
            raise InputError(f"{path}, line {i}: expected an image name and 12 numbers, found "
                             f"{len(tok)} fields.")
        out[tok[0]] = _numbers(tok[1:], str(path), i).reshape(3, 4)
    if not out:
        raise InputError(f"{path}: no camera matrices in the file.")
    return out


def read_calibrated_camera_parameters(path) -> Dict[str, dict]:
    """``calibrated_camera_parameters.txt`` → {image: {width, height, K, radial, tangential, t, R}}."""
    lines = [(i, ln.split()) for i, ln in enumerate(Path(path).read_text(errors="replace").splitlines(), 1)]
    lines = [(i, t) for i, t in lines if t]
    # header: lines until the first "name width height" line followed by a 3-number K row
    k = 0
    while k < len(lines) and not (len(lines[k][1]) == 3 and _is_int(lines[k][1][1])
                                  and _is_int(lines[k][1][2]) and k + 1 < len(lines)
                                  and _is_num_row(lines[k + 1][1], 3)):
        k += 1
    out = {}
    where = str(path)
    while k < len(lines):
        block = lines[k:k + 10]
        if len(block) < 10:
            raise InputError(f"{path}, line {lines[k][0]}: incomplete camera block "
                             "(expected 10 lines: name, K, radial, tangential, t, R).")
        name = block[0][1][0]
        try:
            w, h = int(block[0][1][1]), int(block[0][1][2])
        except (ValueError, IndexError):
            raise InputError(f"{path}, line {block[0][0]}: expected 'name width height'.") from None
        rows = [_numbers(t, where, i) for i, t in block[1:]]
        sizes = [len(r) for r in rows]
        if sizes != [3, 3, 3, 3, 2, 3, 3, 3, 3]:
            raise InputError(f"{path}, line {block[0][0]}: camera block of {name} has rows of "
                             f"{sizes} numbers, expected [3,3,3,3,2,3,3,3,3].")
        out[name] = {"width": w, "height": h, "K": np.array(rows[0:3]), "radial": rows[3],
                     "tangential": rows[4], "t": rows[5], "R": np.array(rows[6:9])}
        k += 10
    if not out:
        raise InputError(f"{path}: no camera blocks found.")
    return out


def _is_int(s: str) -> bool:
    return s.isdigit()


def _is_num_row(tok, n) -> bool:
    try:
        return len(tok) == n and all(np.isfinite(float(t)) for t in tok)
    except ValueError:
        return False


def read_cam_file(path, width: int, height: int) -> Calibration:
    """Internal parameters of a ``.cam`` file as a :class:`Calibration` for a w×h image.

    Two formats exist. Pix4D's "Pix4D camera calibration file" (F, Px, Py in mm from the
    top-left corner; K1..K3, T1, T2 on normalised coordinates) and the Inpho-style
    ``camera_calibration_file`` (FOCAL mm, XPOFF/YPOFF px from the centre, SYM_DIST and
    DEC_DIST in mm-based units). For the Inpho file Pix4D writes K_i = R_i / F^(2i+1) and
    P_j = T_j / F² (F in mm), which is inverted here (checked against the calibrated camera
    parameters of a real project to 1e-12).
    """
    text = Path(path).read_text(errors="replace")
    vals: Dict[str, List[str]] = {}
    for ln in text.splitlines():
        tok = ln.split()
        if tok and not tok[0].startswith("#"):
            vals.setdefault(tok[0].upper(), []).append(tok[1:])
    where = str(path)

    def num(key, i=0, occurrence=-1):
        try:
            return float(vals[key][occurrence][i])
        except (KeyError, IndexError):
            raise InputError(f"{path}: no {key} value; the .cam file is incomplete.") from None
        except ValueError:
            raise InputError(f"{path}: {key} is not a number.") from None

    first = text.lstrip().split("\n", 1)[0].lower()
    if "FOCAL" in vals:                       # Inpho style
        F = num("FOCAL")
        w_mm = _sensor_width_mm(text, where)
        f_px = F * width / w_mm
        # the last XPOFF/YPOFF pair is in pixels (comment "in pixel")
        xpoff, ypoff = num("XPOFF"), num("YPOFF")
        sym = _numbers(vals.get("SYM_DIST", [["0", "0", "0", "0"]])[-1], where, 0)
        dec = _numbers(vals.get("DEC_DIST", [["0", "0", "0"]])[-1], where, 0)
        k = [sym[i] * F ** (2 * i + 1) if i < len(sym) else 0.0 for i in (1, 2, 3)]
        t1, t2 = dec[0] * F ** 2, dec[1] * F ** 2
        return Calibration(f=f_px, cx=width / 2.0 - xpoff, cy=height / 2.0 - ypoff,
                           k1=k[0], k2=k[1], k3=k[2], p1=t2, p2=t1)
    if "F" in vals and "PX" in vals:          # Pix4D format, mm from the top-left corner
        w_mm = _sensor_width_mm(text, where)
        s = width / w_mm
        return Calibration(f=num("F") * s, cx=num("PX") * s, cy=num("PY") * s,
                           k1=num("K1"), k2=num("K2"), k3=num("K3"), p1=num("T2"), p2=num("T1"))
    raise InputError(f"{path}: not a Pix4D .cam file I can read (first line {first[:60]!r}).")


def _sensor_width_mm(text: str, where: str) -> float:
    m = re.search(r"sensor width of\s*([0-9.eE+-]+)\s*x\s*([0-9.eE+-]+)", text)
    if not m:
        raise InputError(f"{where}: the sensor size ('sensor width of W x H mm') is missing.")
    return float(m.group(1))


def calibration_from_ccp(entry: dict) -> Calibration:
    """Calibration from one ``calibrated_camera_parameters`` block (K about the top-left corner)."""
    K, r, t = entry["K"], entry["radial"], entry["tangential"]
    return Calibration(f=K[1, 1], cx=K[0, 2], cy=K[1, 2], b1=K[0, 0] - K[1, 1], b2=K[0, 1],
                       k1=r[0], k2=r[1], k3=r[2], p1=t[1], p2=t[0])


def decompose_pmatrix(P: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """P = K[R | −RC] → (K with positive diagonal, K[2,2] = 1; R; C)."""
    M = P[:, :3]
    C = -np.linalg.solve(M, P[:, 3])
    # RQ decomposition through QR of the flipped matrix
    flip = np.flipud(np.eye(3))
    q, r = np.linalg.qr((flip @ M).T)
    K = flip @ r.T @ flip
    R = flip @ q.T
    D = np.diag(np.sign(np.diag(K)))
    K, R = K @ D, D @ R
    if np.linalg.det(R) < 0:
        R = -R
    return K / K[2, 2], R, C


# --- project discovery --------------------------------------------------------------------------
_SUFFIXES = {
    "offset": "_offset.xyz", "pmatrix": "_pmatrix.txt",
    "ccp": "_calibrated_camera_parameters.txt",
    "cam": "_pix4d_calibrated_internal_camera_parameters.cam",
    "cam_inpho": "_calibrated_internal_camera_parameters.cam", "prj": "_wkt.prj",
}


def _find_params(path: Path) -> Tuple[Path, Optional[Path]]:
    """(params folder, .p4d file or None) from a .p4d, a project folder or a params folder."""
    p4d = None
    if path.is_file() and path.suffix.lower() == ".p4d":
        p4d = path
        candidates = [path.parent / path.stem / "1_initial" / "params", path.parent / "1_initial" / "params"]
    elif path.is_dir():
        candidates = [path, path / "1_initial" / "params"]
        p4ds = sorted(path.glob("*.p4d")) or sorted(path.parent.glob(path.name + ".p4d"))
        p4d = p4ds[0] if p4ds else None
    else:
        raise InputError(f"{path}: not found, or not a .p4d file or Pix4D project folder.")
    for c in candidates:
        if c.is_dir() and any(c.glob("*_offset.xyz")) or c.is_dir() and any(c.glob("*_pmatrix.txt")):
            return c, p4d
    for c in candidates:
        if c.is_dir() and c.name == "params":
            return c, p4d
    raise InputError(f"{path}: no Pix4D params folder (1_initial/params with *_offset.xyz and "
                     "*_pmatrix.txt) was found. Give the project folder, the .p4d file or the "
                     "params folder.")


def _pick(folder: Path, key: str) -> Optional[Path]:
    suf = _SUFFIXES[key]
    hits = sorted(p for p in folder.iterdir() if p.name.endswith(suf))
    if key == "cam_inpho":
        hits = [p for p in hits if not p.name.endswith(_SUFFIXES["cam"])]
    if len(hits) > 1:
        raise InputError(f"{folder}: several files end with {suf} ({', '.join(h.name for h in hits)}); "
                         "keep only one project in this folder.")
    return hits[0] if hits else None


def _p4d_photos(p4d: Optional[Path]) -> Dict[str, str]:
    if p4d is None:
        return {}
    try:
        root = parse_xml(p4d.read_bytes())
    except (XMLError, OSError) as exc:
        raise InputError(f"{p4d}: not a readable .p4d XML file ({exc}).") from None
    out = {}
    for im in root.iter("image"):
        p = im.get("path")
        if p:
            out[photo_key(p)] = str((p4d.parent / p).resolve()) \
                if not (Path(p).is_absolute() or is_windows_path(p)) else p
    return out


@reads_file("Export the params folder from Pix4D again.")
def open_pix4d(path, crs=None) -> Reconstruction:
    """Open a Pix4D project; ``crs`` overrides/supplies the output CRS when no ``_wkt.prj``."""
    path = Path(path)
    folder, p4d = _find_params(path)
    files = {k: _pick(folder, k) for k in _SUFFIXES}
    if files["offset"] is None:
        raise InputError(f"{folder}: no *_offset.xyz file. Pix4D writes it in 1_initial/params; "
                         "without it the camera positions cannot be placed in map coordinates.")
    if files["pmatrix"] is None and files["ccp"] is None:
        raise InputError(f"{folder}: no *_pmatrix.txt (nor *_calibrated_camera_parameters.txt): "
                         "the camera poses are missing. Re-export the params folder from Pix4D.")
    offset = read_offset(files["offset"])
    notes = []
    if crs is None and files["prj"] is not None:
        crs, how = project_crs(files["prj"].read_text(errors="replace"), str(files["prj"]))
        if how:
            notes.append(how)
    crs = as_crs(crs)
    photos = _p4d_photos(p4d)
    if crs is None:
        notes.append("no *_wkt.prj and no crs given: the project CRS is unknown")

    sensors: Dict[Tuple, Sensor] = {}
    cameras: List[Camera] = []

    def sensor_for(cal: Calibration, w: int, h: int) -> str:
        key = (w, h) + tuple(round(v, 9) if isinstance(v, float) else v for v in cal.__dict__.values())
        if key not in sensors:
            sensors[key] = Sensor(id=str(len(sensors)), label=f"Pix4D camera {len(sensors)} ({w}x{h})",
                                  width=w, height=h, calibration=cal)
        return sensors[key].id

    if files["ccp"] is not None:
        for name, e in read_calibrated_camera_parameters(files["ccp"]).items():
            sid = sensor_for(calibration_from_ccp(e), e["width"], e["height"])
            cameras.append(Camera(id=name, label=name, sensor_id=sid,
                                  photo_path=photos.get(photo_key(name)),
                                  R=e["R"], C=e["t"]))
    else:
        cam_file = files["cam"] or files["cam_inpho"]
        if cam_file is not None:
            models = len(re.findall(r"(?im)^\s*(?:camera_calibration_file|pix4d camera calibration file)\b",
                                    cam_file.read_text(errors="replace")))
            if models > 1:
                raise InputError(
                    f"{cam_file}: {models} camera models (a multi-camera rig: one per band of a "
                    "multispectral camera), and without *_calibrated_camera_parameters.txt nothing "
                    "says which band file uses which; export the params folder from Pix4D with "
                    "its calibrated camera parameters, or use the Metashape or OPF project")
        for name, P in read_pmatrix(files["pmatrix"]).items():
            K, R, C = decompose_pmatrix(P)
            w, h = _image_size(K, cam_file)
            dist = read_cam_file(cam_file, w, h) if cam_file else None
            cal = Calibration(f=K[1, 1], cx=K[0, 2], cy=K[1, 2], b1=K[0, 0] - K[1, 1], b2=K[0, 1],
                              **({} if dist is None else {k: getattr(dist, k) for k in
                                                          ("k1", "k2", "k3", "p1", "p2")}))
            sid = sensor_for(cal, w, h)
            cameras.append(Camera(id=name, label=name, sensor_id=sid,
                                  photo_path=photos.get(photo_key(name)),
                                  R=R, C=C))
        if cam_file is None:
            notes.append("no .cam file: lens distortion unknown, projections are undistorted")
    unplaced = _uncalibrated_bands(photos, cameras)
    if unplaced:
        sid, first = str(len(sensors)), next(iter(sensors.values()))
        sensors[("unplaced",)] = Sensor(id=sid, label="band cameras without a calibrated pose",
                                        width=first.width, height=first.height, calibration=None)
        cameras += [Camera(id=k, label=file_name(photos[k]), sensor_id=sid, photo_path=photos[k])
                    for k in unplaced]
        notes.append(f"{p4d or folder}: {len(unplaced)} band file(s) of rig captures have no "
                     f"calibrated pose (e.g. {file_name(photos[unplaced[0]])}), and Pix4D's "
                     "params folder holds no rig relatives to place them from their capture's "
                     "other bands, so they are not measured: enable them in Pix4Dmapper and run "
                     "its initial processing again, or use a Metashape project of the same "
                     "photos (its rig offsets are applied)")
    return Reconstruction(source=path, software="pix4d", label=files["offset"].name[:-len(_SUFFIXES["offset"])],
                          crs=crs, frame=OffsetFrame(crs, offset),
                          sensors={s.id: s for s in sensors.values()}, cameras=cameras, notes=notes)


_BAND_SUFFIX = re.compile(r"(?i)^(.+)_(\d|ms_[a-z]+)$")   # IMG_0001_3, DJI_…_MS_NIR


def _uncalibrated_bands(photos: Dict[str, str], cameras: List[Camera]) -> List[str]:
    """Photo keys of the ``.p4d`` that have no camera and whose capture (the name before the
    band suffix) has calibrated band files."""
    calibrated = {photo_key(c.label) for c in cameras}
    captures = {m.group(1) for m in map(_BAND_SUFFIX.match, calibrated) if m}
    return [k for k in photos if k not in calibrated and
            (lambda m: m is not None and m.group(1) in captures)(_BAND_SUFFIX.match(k))]


def _image_size(K: np.ndarray, cam_file: Optional[Path]) -> Tuple[int, int]:
    if cam_file is not None:
        m = re.search(r"Image size\s*([0-9.]+)\s*x\s*([0-9.]+)", cam_file.read_text(errors="replace"))
        if m:
            return int(round(float(m.group(1)))), int(round(float(m.group(2))))
    raise InputError(f"{cam_file or 'params folder'}: the image size is unknown (no "
                     "*_calibrated_camera_parameters.txt and no .cam with 'Image size').")


# --- the reader of open_reconstruction (readers.py) ---------------------------------------------
PARAM_FILES = ("_pmatrix.txt", "_offset.xyz", "_calibrated_camera_parameters.txt",
               "_calibrated_internal_camera_parameters.cam", "_wkt.prj")
"""Files of a params folder: any of them stands for its folder."""


def recognises(path: Path) -> bool:
    """A ``.p4d`` path (a missing one too: :func:`open_pix4d` says so), a file of a params folder
    (:data:`PARAM_FILES`), or a folder that looks like Pix4D's: a ``params`` folder, one holding
    ``1_initial``, a ``.p4d`` or params files, or one with a ``.p4d`` of its name beside it."""
    if path.suffix.lower() == ".p4d":
        return True
    if path.is_file():
        return path.name.endswith(PARAM_FILES)
    if not path.is_dir():
        return False
    if path.name == "params" or (path / "1_initial").is_dir() \
            or (path.parent / (path.name + ".p4d")).is_file():
        return True
    return any(n.lower().endswith(".p4d") or n.endswith(PARAM_FILES) for n in os.listdir(path))


def _open(path: Path, options: OpenOptions) -> Reconstruction:
    folder = path.parent if path.is_file() and path.name.endswith(PARAM_FILES) else path
    return open_pix4d(folder, options.source_crs)


READER = ProjectReader("Pix4D", "a .p4d, the project folder (1_initial/params) or the params "
                       "folder (*_offset.xyz, *_pmatrix.txt), or a file of it", recognises, _open)
