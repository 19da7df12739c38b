"""Agisoft Metashape readers: ``.psx`` + ``.files/``, ``.psz`` archives, exported cameras XML.

Layout of a project: ``name.psx`` points at ``name.files/project.zip``, whose ``doc.xml``
lists the chunks (``0/chunk.zip``); each chunk ``doc.xml`` holds sensors, cameras (groups,
rigs), markers, the chunk transform and CRS, and points at ``0/frame.zip`` (photo paths,
marker observations). A ``.psz`` packs the same tree in one zip. File → Export Cameras
writes ``<document><chunk>…`` with the same chunk content (no photo paths).

Camera pose (manual, Appendix C): camera → chunk 4×4 ``T``; chunk → geocentric (datum of the
chunk CRS) ``X = s·R·x + t``; for a local CRS the same transform gives local coordinates.
Marker pixel observations are in Metashape pixels (top-left corner origin), like ours.

Rolling shutter: when the sensor's ``rolling_shutter`` property is on, each aligned camera's
``<rolling_shutter>`` block (a rotation matrix and a translation, camera frame, chunk units) is
its motion from the centre row to the last row; it becomes a
:class:`~.rolling_shutter.RollingShutter` (rotation vector, translation in model units).
"""
import io
import posixpath
import re
import zipfile
from pathlib import Path
from typing import Dict, List, Optional, Tuple, Union

import numpy as np
from pyproj import CRS

from ..crs import as_crs, project_crs
from ..errors import InputError, reads_file
from .frame_model import Calibration
from .geodesy import GeocentricFrame, LocalFrame, is_local
from .model import Camera, Marker, Reconstruction, Sensor
from .project_reader import OpenOptions, ProjectReader
from ..rotations import rotation_vector
from ..safe_xml import Element, XMLError, parse_xml
from .rolling_shutter import RollingShutter

SUPPORTED_SENSOR_TYPES = {"frame"}
_FALSE = {"false", "0", "no", "off"}
_SHUTTER_OFF = _FALSE | {"disabled", "none"}     # Metashape 2.x names its shutter models


# --- small parsing helpers --------------------------------------------------------------------
def _bool(value: Optional[str], default: bool = True) -> bool:
    """Metashape writes enabled="false" as a *string*: never use bool(str)."""
    if value is None:
        return default
    return value.strip().lower() not in _FALSE


def _floats(text: Optional[str], n: Optional[int], what: str, where: str) -> np.ndarray:
    parts = (text or "").split()
    try:
        vals = np.array([float(p) for p in parts], dtype=np.float64)
    except ValueError:
        raise InputError(f"{where}: {what} holds a value that is not a number: "
                         f"{(text or '').strip()[:80]!r}. The file is damaged.") from None
    if (n is not None and vals.size != n) or not np.all(np.isfinite(vals)):
        raise InputError(f"{where}: {what} should hold {n} finite numbers, found "
                         f"{(text or '').strip()[:80]!r}. The file is damaged.")
    return vals


def _float_attr(el: Element, name: str, where: str) -> Optional[float]:
    v = el.get(name)
    return None if v is None else float(_floats(v, 1, f"attribute {name} of <{el.tag}>", where)[0])


def _parse_xml(data: bytes, where: str) -> Element:
    try:
        return parse_xml(data)
    except XMLError as exc:
        raise InputError(f"{where}: not a readable XML document ({exc}).") from None


class _Source:
    """Reads ``doc.xml`` of nested zips, from a folder (.psx) or inside one archive (.psz)."""

    def __init__(self, root: Union[Path, zipfile.ZipFile], label: str):
        self.root, self.label = root, label

    def read(self, rel: str) -> bytes:
        if isinstance(self.root, zipfile.ZipFile):
            if rel not in self.root.namelist():
                raise InputError(f"{self.label}: the archive has no {rel}; it is incomplete.")
            return _zip_member(self.root, rel, self.label)
        p = self.root / rel
        if not p.is_file():
            raise InputError(f"{p}: file is missing; the project folder {self.root} is incomplete.")
        return p.read_bytes()

    def where(self, rel: str) -> str:
        return f"{self.label}!{rel}" if isinstance(self.root, zipfile.ZipFile) else str(self.root / rel)

    def doc(self, rel: str) -> Element:
        """doc.xml of the zip at ``rel`` (or the xml file itself)."""
        where = self.where(rel)
        data = self.read(rel)
        if not rel.endswith(".zip"):
            return _parse_xml(data, where)
        try:
            z = zipfile.ZipFile(io.BytesIO(data))
        except (zipfile.BadZipFile, ValueError, OSError, EOFError):
            raise InputError(f"{where}: not a valid zip archive; the project is damaged.") from None
        with z:
            if "doc.xml" not in z.namelist():
                raise InputError(f"{where}: no doc.xml inside this zip (found "
                                 f"{', '.join(z.namelist()[:5]) or 'nothing'}); the project "
                                 "is damaged or was not written by Metashape.")
            return _parse_xml(_zip_member(z, "doc.xml", where), f"{where}!doc.xml")


MAX_DOC_BYTES = 1 << 30
"""The largest project document read (a damaged zip may claim any size)."""


def _zip_member(z: zipfile.ZipFile, name: str, where: str) -> bytes:
    """One member of a project zip; a damaged archive raises :class:`InputError`."""
    try:
        info = z.getinfo(name)
        if info.file_size > MAX_DOC_BYTES:
            raise InputError(f"{where}: {name} claims {info.file_size:,} bytes; the project is "
                             "damaged.")
        return z.read(info)
    except InputError:
        raise
    except Exception as exc:    # zlib.error, BadZipFile, EOFError, bad seeks, … from zipfile
        raise InputError(f"{where}: {name} cannot be read from the archive ({type(exc).__name__}: "
                         f"{exc}); the project is damaged.") from None


# --- project / chunk selection ----------------------------------------------------------------
def list_chunks(path) -> List[Dict]:
    """The chunks of a .psx/.psz: [{"id", "label", "enabled", "path"}]."""
    src, doc = _open_project(Path(path))
    return [dict(c) for c in _chunk_entries(src, doc)]


def _open_project(path: Path) -> Tuple[_Source, Element]:
    if not path.is_file():
        raise InputError(f"{path}: file not found.")
    if path.suffix.lower() == ".psz":
        try:
            z = zipfile.ZipFile(path)
        except (zipfile.BadZipFile, ValueError, OSError, EOFError):
            raise InputError(f"{path}: not a valid .psz (zip) archive; the file is damaged.") from None
        src = _Source(z, str(path))
        if "doc.xml" not in z.namelist():
            raise InputError(f"{path}: no doc.xml inside this .psz archive; it is damaged.")
        return src, _parse_xml(_zip_member(z, "doc.xml", str(path)), f"{path}!doc.xml")
    root = _parse_xml(path.read_bytes(), str(path))
    rel = root.get("path")
    if rel is None:
        raise InputError(f"{path}: the .psx has no path attribute pointing to its project data.")
    rel = rel.replace("{projectname}", path.stem)
    folder = path.parent / Path(rel).parent
    if not folder.is_dir():
        raise InputError(f"{path}: its data folder {folder} is missing. A .psx is only a "
                         "pointer: copy the whole '.files' folder next to it.")
    src = _Source(folder, str(folder))
    return src, src.doc(Path(rel).name)


def _chunk_entries(src: _Source, doc: Element):
    chunks = doc.find("chunks")
    out = []
    for el in (chunks if chunks is not None else []):
        if el.tag != "chunk":
            continue
        rel = el.get("path")
        cdoc = src.doc(rel) if rel else el
        out.append({"id": el.get("id", str(len(out))), "label": cdoc.get("label", ""),
                    "enabled": _bool(cdoc.get("enabled")), "path": rel, "_doc": cdoc})
    if not out:
        raise InputError(f"{src.label}: the project has no chunks.")
    return out


def _choose_chunk(entries, chunk, where: str):
    table = "; ".join(f"id {e['id']} {e['label']!r}" + ("" if e["enabled"] else " (disabled)")
                      for e in entries)
    if chunk is None:
        if len(entries) == 1:
            return entries[0]
        raise InputError(f"{where} has {len(entries)} chunks: {table}. Choose one by id or label.")
    key = str(chunk)
    by_id = [e for e in entries if e["id"] == key]
    if by_id:
        return by_id[0]
    by_label = [e for e in entries if e["label"] == key]
    if len(by_label) == 1:
        return by_label[0]
    what = "several chunks are labelled" if by_label else "no chunk has id or label"
    raise InputError(f"{where}: {what} {key!r}. Chunks: {table}.")


# --- chunk content -----------------------------------------------------------------------------
def _calibration(sensor: Element, width: int, height: int, where: str) -> Optional[Calibration]:
    cals = sensor.findall("calibration")
    # by class, never by truth value: an Element's truth is its number of children
    ranked = sorted(cals, key=lambda c: {"adjusted": 0, "initial": 1}.get(c.get("class"), 2))
    cal = ranked[0] if ranked else None
    if cal is None or cal.find("f") is None:
        return None
    vals = {}
    for name in ("f", "cx", "cy", "b1", "b2", "k1", "k2", "k3", "k4", "p1", "p2", "p3", "p4"):
        el = cal.find(name)
        if el is not None:
            vals[name] = float(_floats(el.text, 1, f"<{name}> of sensor {sensor.get('label')!r}", where)[0])
    res = cal.find("resolution")
    cw = int(res.get("width", width)) if res is not None else width
    ch = int(res.get("height", height)) if res is not None else height
    vals["cx"] = cw / 2.0 + vals.get("cx", 0.0)   # Metashape cx, cy: offsets from the centre
    vals["cy"] = ch / 2.0 + vals.get("cy", 0.0)
    try:
        return Calibration(**vals)
    except ValueError as exc:
        raise InputError(f"{where}: sensor {sensor.get('label')!r}: {exc}.") from None


def _rig_offset(sensor: Element, where: str) -> Optional[np.ndarray]:
    loc, rot = sensor.find("location"), sensor.find("rotation")
    if loc is None and rot is None:
        return None
    T = np.eye(4)
    if loc is not None:
        if loc.get("x") is not None:
            T[:3, 3] = [_float_attr(loc, k, where) for k in "xyz"]
        elif (loc.text or "").strip():
            T[:3, 3] = _floats(loc.text, 3, "<location> of a slave sensor", where)
    if rot is not None and (rot.text or "").strip():
        T[:3, :3] = _floats(rot.text, 9, "<rotation> of a slave sensor", where).reshape(3, 3)
    return T


def _sensors(chunk: Element, where: str) -> Dict[str, Sensor]:
    out = {}
    for s in chunk.iter("sensor"):
        sid, label, typ = s.get("id"), s.get("label", ""), s.get("type", "frame")
        if typ not in SUPPORTED_SENSOR_TYPES:
            raise InputError(f"{where}: sensor {label!r} uses the {typ!r} camera model, which is "
                             "not supported yet (only 'frame'). Remove its cameras or convert "
                             "the project.")
        res = s.find("resolution")
        if res is None:
            raise InputError(f"{where}: sensor {label!r} has no <resolution>.")
        w = int(_floats(res.get("width"), 1, "sensor width", where)[0])
        h = int(_floats(res.get("height"), 1, "sensor height", where)[0])
        props = {p.get("name"): p.get("value") for p in s.findall("property")}
        px = props.get("pixel_width")
        fmm = props.get("focal_length")
        out[sid] = Sensor(
            id=sid, label=label, width=w, height=h, calibration=_calibration(s, w, h, where),
            type=typ, pixel_size_mm=float(px) if px else None,
            focal_length_mm=float(fmm) if fmm else None,
            rolling_shutter=(props.get("rolling_shutter") or "false").strip().lower()
            not in _SHUTTER_OFF,
            master_id=s.get("master_id"), rig_offset=_rig_offset(s, where))
    return out


def _transform(el: Optional[Element], where: str) -> Optional[np.ndarray]:
    """<transform> as 4×4: either rotation/translation/scale children or 16 numbers."""
    if el is None:
        return None
    rot, tr, sc = el.find("rotation"), el.find("translation"), el.find("scale")
    if rot is None and tr is None and (el.text or "").strip():
        return _floats(el.text, 16, "chunk <transform>", where).reshape(4, 4)
    M = np.eye(4)
    s = float(_floats(sc.text, 1, "chunk transform <scale>", where)[0]) if sc is not None else 1.0
    if rot is not None:
        M[:3, :3] = s * _floats(rot.text, 9, "chunk transform <rotation>", where).reshape(3, 3)
    else:
        M[:3, :3] *= s
    if tr is not None:
        M[:3, 3] = _floats(tr.text, 3, "chunk transform <translation>", where)
    return M


def _shutter_block(el: Element, label: str, where: str):
    """(rotation 3×3, translation (3,)) of a camera's <rolling_shutter> block, or None."""
    rs = el.find("rolling_shutter")
    if rs is None:
        return None
    rot, tr = rs.find("rotation"), rs.find("translation")
    what = f"of camera {label!r}"
    M = np.eye(3) if rot is None else \
        _floats(rot.text, 9, f"<rolling_shutter><rotation> {what}", where).reshape(3, 3)
    t = np.zeros(3) if tr is None else \
        _floats(tr.text, 3, f"<rolling_shutter><translation> {what}", where)
    if not np.allclose(M @ M.T, np.eye(3), atol=1e-6) or np.linalg.det(M) <= 0:
        raise InputError(f"{where}: the <rolling_shutter> rotation of camera {label!r} is not a "
                         "rotation matrix. The file is damaged.")
    return M, t


def _iter_with_group(parent: Optional[Element], tag: str):
    """Yield (element, group label) for ``tag`` children, looking inside <group> elements."""
    if parent is None:
        return
    for el in parent:
        if el.tag == tag:
            yield el, None
        elif el.tag == "group":
            for sub in el:
                if sub.tag == tag:
                    yield sub, el.get("label")


def _crs(chunk: Element, where: str, given=None) -> Tuple[Optional[CRS], str]:
    """(chunk CRS, how it was resolved: :func:`~..crs.project_crs`) of the chunk ``<reference>``."""
    ref = chunk.find("reference")
    text = (ref.text or "").strip() if ref is not None else ""
    if not text:
        return (as_crs(given, "The project CRS") if given is not None else None), ""
    return project_crs(text, f"{where}, chunk <reference>", given)


def _frame_doc(src: Optional[_Source], chunk_rel: Optional[str], chunk: Element):
    """(photo paths {camera id: path}, observations {marker id: [(camera id, u, v)]},
    frame doc path, problem message or None)."""
    paths, obs = {}, {}
    frames = chunk.find("frames")
    fr = frames.find("frame") if frames is not None else None
    if fr is None:
        return paths, obs, None, None
    if fr.get("path") and src is not None and chunk_rel is not None:
        rel = posixpath.join(posixpath.dirname(chunk_rel), fr.get("path"))
        try:
            doc, base = src.doc(rel), rel
        except InputError as exc:                  # photo paths and marker pixels unknown
            return paths, obs, None, str(exc)
    else:
        doc, base = fr, None
    where = src.where(base) if (src is not None and base) else "frame"
    cams = doc.find("cameras")
    for c in (cams if cams is not None else []):
        ph = c.find("photo")
        if ph is not None and ph.get("path"):
            paths[c.get("camera_id")] = ph.get("path")
    mks = doc.find("markers")
    for m in (mks if mks is not None else []):
        for loc in m.findall("location"):
            if not _bool(loc.get("valid"), True):
                continue
            obs.setdefault(m.get("marker_id"), []).append(
                (loc.get("camera_id"), _float_attr(loc, "x", where), _float_attr(loc, "y", where)))
    return paths, obs, base, None


def _resolve_photo(path: str, src: Optional[_Source], frame_rel: Optional[str]) -> str:
    if re.match(r"^([A-Za-z]:[\\/]|/|\\\\)", path) or src is None or frame_rel is None \
            or isinstance(src.root, zipfile.ZipFile):
        return path
    return str((src.root / posixpath.dirname(frame_rel) / path).resolve())


def read_chunk(chunk: Element, where: str, source: Path, src: Optional[_Source] = None,
               chunk_rel: Optional[str] = None, chunk_key: str = "0", crs=None) -> Reconstruction:
    """A :class:`Reconstruction` from a chunk element (project chunk or exported cameras XML).
    ``crs``: the chunk CRS when its ``<reference>`` cannot be used (see :func:`_crs`)."""
    sensors = _sensors(chunk, where)
    crs, crs_note = _crs(chunk, where, crs)
    chunk_T = _transform(chunk.find("transform"), where)
    comp_T = {}
    comps = chunk.find("components")
    for comp in (comps if comps is not None else []):
        if comp.find("transform") is not None:
            comp_T[comp.get("id")] = _transform(comp.find("transform"), where)
    paths, obs, frame_rel, problem = _frame_doc(src, chunk_rel, chunk)
    notes = [f"no photo paths or marker observations: {problem}"] if problem else []
    if crs_note:
        notes.append(crs_note)

    # camera → chunk transforms, rig slaves composed with their master
    raw, shutter, cams = {}, {}, []
    for el, group in _iter_with_group(chunk.find("cameras"), "camera"):
        cid = el.get("id")
        label = el.get("label", f"camera {cid}")
        if el.get("sensor_id") not in sensors:
            raise InputError(f"{where}: camera {label!r} refers to sensor "
                             f"{el.get('sensor_id')!r}, which the chunk does not define.")
        tel = el.find("transform")
        raw[cid] = _floats(tel.text, 16, f"<transform> of camera {label!r}", where).reshape(4, 4) \
            if tel is not None else None
        shutter[cid] = _shutter_block(el, label, where)
        photo = paths.get(cid)
        cams.append((el, Camera(id=cid, label=label, sensor_id=el.get("sensor_id"),
                                photo_path=_resolve_photo(photo, src, frame_rel) if photo else None,
                                enabled=_bool(el.get("enabled")), group=group,
                                master_id=el.get("master_id"))))
    for el, cam in cams:
        if raw[cam.id] is None and cam.master_id not in (None, cam.id) and raw.get(cam.master_id) is not None:
            off = sensors[cam.sensor_id].rig_offset
            raw[cam.id] = raw[cam.master_id] @ (off if off is not None else np.eye(4))

    aligned = [(el, cam) for el, cam in cams if raw[cam.id] is not None]
    if not aligned:
        raise InputError(f"{where}: chunk {chunk.get('label', chunk_key)!r} has no aligned cameras "
                         f"({len(cams)} camera(s), none with a pose). Align the photos in "
                         "Metashape and save the project first.")

    def chunk_matrix(el):
        M = comp_T.get(el.get("component_id"))
        return M if M is not None else (chunk_T if chunk_T is not None else np.eye(4))

    if crs is None or is_local(crs):
        frame = LocalFrame(crs)
        if chunk_T is None and not comp_T:
            notes.append("chunk is not georeferenced: coordinates are Metashape's internal ones")
        to_model_c = lambda c: c
        rot_model = np.eye(3)
    else:
        centres = np.array([(chunk_matrix(el) @ raw[c.id][:, 3])[:3] for el, c in aligned])
        frame = GeocentricFrame(crs, centres.mean(axis=0))
        to_model_c = frame.ecef_to_model
        rot_model = frame.rotation
    for el, cam in aligned:
        M = chunk_matrix(el)
        T = M @ raw[cam.id]
        A = T[:3, :3]
        scale = np.cbrt(np.linalg.det(A))
        cam.R = (A / scale).T @ rot_model.T        # model → camera
        cam.C = to_model_c(T[:3, 3][None, :])[0]
        block = shutter[cam.id]
        if block is not None and sensors[cam.sensor_id].rolling_shutter:
            rs = RollingShutter(rotation_vector(block[0]), scale * block[1])
            cam.rolling_shutter = None if rs.is_zero else rs
    notes += _shutter_notes(sensors, [c for _, c in aligned], shutter,
                            "local units" if crs is None or is_local(crs) else "m")
    n_unaligned = len(cams) - len(aligned)
    if n_unaligned:
        notes.append(f"{n_unaligned} camera(s) not aligned")

    id2label = {c.id: c.label for _, c in cams}
    markers = []
    for el, _group in _iter_with_group(chunk.find("markers"), "marker"):
        ref = el.find("reference")
        xyz, ref_on = None, False
        if ref is not None and ref.get("x") is not None:
            xyz = np.array([_float_attr(ref, k, where) if ref.get(k) is not None else np.nan
                            for k in "xyz"])
            ref_on = _bool(ref.get("enabled"))
        o = {id2label[c]: (u, v) for c, u, v in obs.get(el.get("id"), []) if c in id2label}
        markers.append(Marker(el.get("id"), el.get("label", ""), xyz, ref_on, o))

    return Reconstruction(source=source, software="metashape", label=chunk.get("label", chunk_key),
                          crs=crs, frame=frame, sensors=sensors, cameras=[c for _, c in cams],
                          enabled=_bool(chunk.get("enabled")), markers=markers, notes=notes)


def _shutter_notes(sensors: Dict[str, Sensor], aligned: List[Camera], shutter,
                   unit: str) -> List[str]:
    """What the reader did with rolling shutter, for ``Reconstruction.notes``."""
    on = [c for c in aligned if c.rolling_shutter is not None]
    flagged = [c for c in aligned if sensors[c.sensor_id].rolling_shutter]
    stale = sum(1 for c in aligned if shutter[c.id] is not None
                and not sensors[c.sensor_id].rolling_shutter)
    notes = []
    if on:
        ang = np.degrees([np.linalg.norm(c.rolling_shutter.rotation) for c in on])
        mov = [np.linalg.norm(c.rolling_shutter.translation) for c in on]
        notes.append(f"rolling-shutter compensation applied: {len(on)} of {len(aligned)} aligned "
                     f"camera(s) have a pose per image row (Metashape's per-photo readout "
                     f"motion, centre row to last row: median {np.median(ang):.3f}°, "
                     f"{np.median(mov):.3g} {unit})")
    if len(flagged) > len(on):
        notes.append(f"rolling-shutter compensation is enabled but {len(flagged) - len(on)} "
                     "aligned camera(s) have no (or a zero) motion estimate: one pose per photo")
    if stale:
        notes.append(f"{stale} camera(s) keep <rolling_shutter> estimates but the sensor's "
                     "compensation is off: not applied, as in Metashape")
    return notes


@reads_file("Open and save it again in Metashape, or restore it from a copy.")
def open_metashape(path, chunk=None, crs=None) -> Reconstruction:
    """Open a Metashape ``.psx``/``.psz`` (one chunk, by id or label) or a cameras ``.xml``.
    ``crs``: the chunk CRS, only for a chunk whose ``<reference>`` PROJ cannot use and that
    matches no EPSG code (:func:`~..crs.project_crs`); a different CRS is refused otherwise."""
    return _open_metashape(Path(path), chunk, crs)


def _open_metashape(path: Path, chunk, crs=None) -> Reconstruction:
    if path.suffix.lower() == ".xml":
        if not path.is_file():
            raise InputError(f"{path}: file not found.")
        root = _parse_xml(path.read_bytes(), str(path))
        chunks = [root] if root.tag == "chunk" else root.findall("chunk")
        if not chunks:
            raise InputError(f"{path}: no <chunk> element; this is not a Metashape cameras export.")
        entries = [{"id": str(i), "label": c.get("label", ""), "enabled": _bool(c.get("enabled")),
                    "_doc": c} for i, c in enumerate(chunks)]
        e = _choose_chunk(entries, chunk, str(path))
        return read_chunk(e["_doc"], str(path), path, chunk_key=e["id"], crs=crs)
    src, doc = _open_project(path)
    e = _choose_chunk(_chunk_entries(src, doc), chunk, str(path))
    where = src.where(e["path"]) if e["path"] else str(path)
    return read_chunk(e["_doc"], where, path, src, e["path"], e["id"], crs)


# --- the reader of open_reconstruction (readers.py) ---------------------------------------------
SUFFIXES = (".psx", ".psz", ".xml")


def recognises(path: Path) -> bool:
    """A ``.psx``, ``.psz`` or cameras ``.xml`` path, by its suffix alone (a missing one too:
    :func:`open_metashape` then says it is missing)."""
    return path.suffix.lower() in SUFFIXES


def _open(path: Path, options: OpenOptions) -> Reconstruction:
    return open_metashape(path, options.chunk, options.source_crs)


READER = ProjectReader("Metashape", "a .psx or .psz project, or a cameras .xml (File > Export "
                       "Cameras)", recognises, _open)
