"""OpenDroneMap projects and OpenSfM datasets → :class:`~.model.Reconstruction`.

Accepted inputs: an ODM project folder (``images/``, ``opensfm/``, ``odm_georeferencing/``,
``odm_orthophoto/``, ``odm_dem/``…), an OpenSfM dataset folder (``reconstruction.json``,
``images/``), or a reconstruction file (``reconstruction.json``,
``reconstruction.topocentric.json``).

What ODM leaves (ODM ``stages/run_opensfm.py``, ``opendm/location.py``, ``opendm/shots.py``):

* ``opensfm/reconstruction.topocentric.json``: OpenSfM's own result, cameras in the
  topocentric frame (x east, y north, z up) about ``reference_lla`` on the WGS 84 ellipsoid.
* ``opensfm/reconstruction.json``: once the project is georeferenced, ODM replaces it with the
  output of ``opensfm export_geocoords --reconstruction --proj <UTM> --offset-x/-y``: the same
  cameras in *map coordinates minus an offset* (``odm_georeferencing/coords.txt``: line 1 the
  CRS, e.g. ``WGS84 UTM 32N``, ``EPSG:n`` or a PROJ string; line 2 ``east north`` offsets).
  That export is linear at the reference point and turns R·A⁻¹ (not a rotation when A carries
  the UTM scale factor k) into an axis-angle vector, so its cameras are off by up to about
  |1 − k| (positions scaled by 1/k about the offset point, rotations by tens of arc-seconds);
  ODM's products (DSM, orthophoto, point cloud) are made with those cameras.
* ``odm_report/shots.geojson``: camera centres in map coordinates (``translation``) from that
  file. An archive of the results may lack the topocentric file.

The topocentric file is preferred: it is the bundle adjustment itself, mapped exactly to any
CRS (topocentric → ECEF → CRS with pyproj, :class:`~.geodesy.GeocentricFrame`; heights are
WGS 84 ellipsoidal heights, as OpenSfM treats its altitudes). Without it, the frame of
``reconstruction.json`` is decided from the evidence (shots.geojson, else the photos' GPS
positions, which OpenSfM keeps topocentric in both files) and said in ``notes``. The map CRS
is ODM's (so ROIs in the orthophoto's CRS need no choice); for a plain OpenSfM dataset it is the
WGS 84 / UTM zone of the reference point, the zone ODM would use.
"""
import os
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
from pyproj import CRS

from ..crs import as_crs, same_crs, transformer
from ..errors import InputError, reads_file
from ..photos import PhotoFiles, photo_key
from ..raster import open_geotiff
from .geodesy import GeocentricFrame, LocalFrame, ModelFrame, OffsetFrame, geocentric_of
from .model import Camera, Marker, Reconstruction, Sensor
from .project_reader import OpenOptions, ProjectReader
from .opensfm import (camera_table, choose, load_json, normalised_to_pixels, read_gcp_json,
                      read_reconstruction_list, reference_lla, shot_counts, shot_pose)

ODM_FOLDERS = ("opensfm", "odm_orthophoto", "odm_dem", "odm_georeferencing", "odm_report",
               "odm_texturing", "odm_meshing", "odm_filterpoints")
RECONSTRUCTION = "reconstruction.json"
TOPOCENTRIC = "reconstruction.topocentric.json"
GEOCOORDS = "reconstruction.geocoords.json"         # export_geocoords' output before ODM renames it
WGS84_3D = CRS.from_epsg(4979)
LOCAL_CRS = CRS.from_wkt('LOCAL_CS["OpenSfM local frame (m)",LOCAL_DATUM["OpenSfM",0],'
                         'UNIT["metre",1],AXIS["x",EAST],AXIS["y",NORTH]]')
"""The CRS of a dataset OpenSfM could not georeference (its own metric frame, z up)."""
GEOCOORDS_MATCH_M = 0.01      # shots.geojson translation = centre + offset within this (m)


def is_odm_folder(p: Path) -> bool:
    """An ODM project: a folder holding ``opensfm/`` or any ``odm_*`` output folder."""
    return p.is_dir() and any((p / d).is_dir() for d in ODM_FOLDERS)


def is_opensfm_input(p: Path) -> bool:
    """True for what :func:`open_opensfm` reads: a ``.json`` file, an ODM project folder or an
    OpenSfM dataset folder (one holding ``reconstruction.json``)."""
    if p.is_file():
        return p.suffix.lower() == ".json"
    return is_odm_folder(p) or (p.is_dir() and (p / RECONSTRUCTION).is_file())


def _refuse_split_merge(root: Path) -> None:
    """A split-merge ODM project (``--split``) has no merged reconstruction: each submodel under
    ``submodels/`` was adjusted on its own. Say so, and which folder to open instead."""
    names = sorted({p.parents[1].name for p in root.glob("submodels/submodel_*/opensfm/*.json")
                    if p.name in (RECONSTRUCTION, TOPOCENTRIC)})
    if names:
        raise InputError(
            f"{root} is a split-merge ODM project: its cameras are in {len(names)} submodels "
            f"(submodels/{names[0]} … {names[-1]}), each adjusted on its own, and there is no "
            f"merged {RECONSTRUCTION}. Open one submodel folder as the project (e.g. "
            f"{root / 'submodels' / names[0]}), for the photos it holds; reading all the "
            "submodels as one project is not supported yet.")


class _Layout:
    """Where things are: the reconstruction file, the OpenSfM dataset folder, the ODM root."""

    def __init__(self, path: Path):
        self.given = path
        self.odm_root: Optional[Path] = None
        if path.is_dir():
            if is_odm_folder(path) and not (path / RECONSTRUCTION).is_file():
                self.odm_root, self.dataset = path, path / "opensfm"
            else:
                self.dataset = path
            self.file = None
        elif path.is_file():
            self.dataset, self.file = path.parent, path
        else:
            raise InputError(f"{path}: file or folder not found.")
        if self.odm_root is None and self.dataset.name == "opensfm" and is_odm_folder(self.dataset.parent):
            self.odm_root = self.dataset.parent
        if self.dataset.name == "undistorted" or (self.file is not None and
                                                  self.file.name.startswith("undistorted")):
            raise InputError(f"{path}: this is the reconstruction of the *undistorted* copies of "
                             "the photos. Give opensfm/reconstruction.json (or the ODM project "
                             "folder): it describes the original photos.")
        if self.file is None:
            topo, main = self.dataset / TOPOCENTRIC, self.dataset / RECONSTRUCTION
            if not (topo.is_file() or main.is_file()):
                if self.odm_root is not None:
                    _refuse_split_merge(self.odm_root)
                    raise InputError(
                        f"{self.odm_root}: {main} is missing. The ODM run may have failed or "
                        "been stopped before its OpenSfM (structure from motion) stage finished; "
                        "check the task log and run it again from that stage.")
                raise InputError(f"{path}: no {RECONSTRUCTION} in this folder. Give an ODM project "
                                 "folder, an OpenSfM dataset folder or a reconstruction file.")
            self.file = main if main.is_file() else topo
        self.photos = next((d for d in ((self.odm_root / "images") if self.odm_root else None,
                                        self.dataset / "images") if d is not None and d.is_dir()), None)

    def odm(self, *parts) -> Optional[Path]:
        if self.odm_root is None:
            return None
        p = self.odm_root.joinpath(*parts)
        return p if p.exists() else None


# --- ODM georeferencing -------------------------------------------------------------------------
def parse_srs_header(line: str, where: str) -> CRS:
    """The CRS of a coords.txt / gcp_list.txt header: ``WGS84 UTM 32N``, ``EPSG:n`` or PROJ."""
    text = line.strip()
    tok = text.split()
    if len(tok) >= 3 and tok[0].upper() == "WGS84" and tok[1].upper() == "UTM":
        zone, hemi = tok[2][:-1], tok[2][-1:].upper()
        if zone.isdigit() and 1 <= int(zone) <= 60 and hemi in ("N", "S"):
            return CRS.from_epsg((32600 if hemi == "N" else 32700) + int(zone))
    try:
        return CRS.from_user_input(text.strip("'\""))
    except Exception:
        raise InputError(f"{where}: the first line {text[:80]!r} is not a CRS ODM writes "
                         "('WGS84 UTM 32N', 'EPSG:n' or a PROJ string).") from None


def odm_georeferencing(layout: _Layout, lla=None) -> Tuple[Optional[CRS], Optional[np.ndarray], str, str]:
    """(CRS, (east, north) offset or None, where the CRS came from, where the offset came from)
    of an ODM project.

    The CRS: ``odm_georeferencing/coords.txt`` line 1, else ``proj.txt``, else the CRS of the
    orthophoto or DSM. The offset: ``coords.txt`` line 2; else ``reference_lla`` (``lla``:
    lat, lon, alt) in that CRS, the point ODM hands OpenSfM as the reference of its offset
    (ODM writes its whole-metre offset point there, ``opendm/osfm.py`` ``write_reference_lla``;
    a reference that is not on whole metres, within 1 cm, is OpenSfM's own and is not used).
    """
    crs, offset, crs_src, off_src = None, None, "", ""
    coords = layout.odm("odm_georeferencing", "coords.txt")
    if coords is not None:
        lines = [ln for ln in coords.read_text(errors="replace").splitlines() if ln.strip()]
        if not lines:
            raise InputError(f"{coords}: the file is empty; ODM writes the CRS on its first line.")
        crs, crs_src = parse_srs_header(lines[0], str(coords)), str(coords)
        if len(lines) > 1:
            try:
                offset = np.array([float(v) for v in lines[1].split()[:2]])
            except ValueError:
                raise InputError(f"{coords}, line 2: expected the east and north offsets, found "
                                 f"{lines[1][:60]!r}.") from None
            if offset.shape != (2,) or not np.all(np.isfinite(offset)):
                raise InputError(f"{coords}, line 2: expected two numbers (east and north offsets).")
            off_src = f"{coords}, line 2"
    if crs is None:
        proj = layout.odm("odm_georeferencing", "proj.txt")
        if proj is not None:
            crs, crs_src = parse_srs_header(proj.read_text(errors="replace"), str(proj)), str(proj)
    if crs is None:
        for parts in (("odm_orthophoto", "odm_orthophoto.tif"), ("odm_dem", "dsm.tif"),
                      ("odm_dem", "dtm.tif")):
            tif = layout.odm(*parts)
            if tif is not None:
                g = open_geotiff(str(tif))
                if g.crs is not None:
                    crs, crs_src = g.crs, str(tif)
                    break
    if crs is not None and offset is None and lla is not None:  # ODM's offset point?
        lat, lon, _alt = lla
        e, n = transformer(WGS84_3D, crs).transform(lon, lat)
        at = np.array([e, n], dtype=np.float64)
        if np.all(np.abs(at - np.round(at)) < 0.01):
            offset = np.round(at)
            off_src = (f"reference_lla (lat {lat:.8f}, lon {lon:.8f}) in {crs.name}: "
                       f"E {offset[0]:.3f}, N {offset[1]:.3f}, whole metres: the offset point "
                       "ODM writes as OpenSfM's reference (opendm/osfm.py write_reference_lla)")
        else:
            off_src = (f"reference_lla is at E {at[0]:.3f}, N {at[1]:.3f} in {crs.name}, not on "
                       "whole metres, so it is not an offset ODM wrote (ODM's are whole metres)")
    return crs, offset, crs_src, off_src


def utm_of(lat: float, lon: float) -> CRS:
    """The WGS 84 / UTM zone of a place, chosen as ODM does (no Norway/Svalbard exceptions)."""
    zone = int(np.floor((lon + 180.0) / 6.0)) % 60 + 1
    return CRS.from_epsg((32700 if lat < 0 else 32600) + zone)


def _topocentric_to_map(lla: Tuple[float, float, float], crs: CRS, xyz: np.ndarray) -> np.ndarray:
    """Topocentric points about ``lla`` → ``crs`` (exact; used to test ODM's frame)."""
    frame = _topocentric_frame(lla, crs)
    return frame.from_model(xyz)


def _topocentric_frame(lla: Tuple[float, float, float], crs: CRS) -> GeocentricFrame:
    """OpenSfM's topocentric frame about ``lla`` (WGS 84) as a frame of map CRS ``crs``."""
    lat, lon, alt = lla
    x, y, z = transformer(WGS84_3D, geocentric_of(crs)).transform(lon, lat, alt)
    return GeocentricFrame(crs, np.array([x, y, z]))


# --- which frame is reconstruction.json in? ------------------------------------------------------
def _geocoords_evidence(layout: _Layout, recon: dict, centres: Dict[str, np.ndarray],
                        lla, crs: CRS, offset: Optional[np.ndarray]) -> Tuple[bool, str]:
    """(True when ``reconstruction.json`` is ODM's map-coordinate export, why)."""
    shots_geojson = layout.odm("odm_report", "shots.geojson")
    if shots_geojson is not None and offset is not None:
        doc = load_json(shots_geojson, "shots.geojson")
        feats = doc.get("features", []) if isinstance(doc, dict) else []
        d = []
        for f in feats:
            p = f.get("properties", {}) if isinstance(f, dict) else {}
            name, t = p.get("filename"), p.get("translation")
            if name in centres and isinstance(t, list) and len(t) == 3:
                d.append(np.abs(centres[name] + [offset[0], offset[1], 0.0] - np.asarray(t, float)).max())
        if d:
            geo = max(d) < GEOCOORDS_MATCH_M
            return geo, (f"{shots_geojson.name}: the camera centres {'equal' if geo else 'differ from'} "
                         f"its map positions minus the offset (max {max(d):.3g} m)")
    gps = {k: np.asarray(s["gps_position"], float) for k, s in recon["shots"].items()
           if k in centres and isinstance(s.get("gps_position"), list) and len(s["gps_position"]) == 3}
    if gps and lla is not None and offset is not None:
        keys = sorted(gps)
        g = np.array([gps[k] for k in keys])
        c = np.array([centres[k] for k in keys])
        as_map = _topocentric_to_map(lla, crs, g) - [offset[0], offset[1], 0.0]
        topo_m = float(np.median(np.linalg.norm(c - g, axis=1)))
        geo_m = float(np.median(np.linalg.norm(c - as_map, axis=1)))
        geo = geo_m < topo_m
        return geo, (f"the camera centres are {min(geo_m, topo_m):.2f} m (median) from the photos' "
                     f"GPS positions in the {'map' if geo else 'topocentric'} frame and "
                     f"{max(geo_m, topo_m):.2f} m in the {'topocentric' if geo else 'map'} one")
    return True, ("no shots.geojson and no GPS positions to tell; assumed to be ODM's "
                  "map-coordinate export, as ODM writes once a project is georeferenced")


# --- the reader ----------------------------------------------------------------------------------------
def list_reconstructions(path) -> List[dict]:
    """The reconstructions of an ODM/OpenSfM input: [{"index", "photos", "points", "cameras"}]."""
    layout = _Layout(Path(path))
    recons = read_reconstruction_list(layout.file)
    return [{"index": i, "photos": n, "points": len(r.get("points", {})),
             "cameras": len(r.get("cameras", {}))} for i, (r, n) in enumerate(zip(recons, shot_counts(recons)))]


@reads_file("Run the OpenDroneMap task again or restore the project from a copy.")
def open_opensfm(path, chunk=None, crs=None) -> Reconstruction:
    """Open an ODM project folder, an OpenSfM dataset folder or a reconstruction file.

    ``chunk``: index of the reconstruction (partial model) to use; default the one with the
    most photos (said in ``notes``). ``crs``: the map CRS for a dataset that ODM did not
    georeference (default: the WGS 84 / UTM zone of the reference point); an ODM project
    brings its own, and a different ``crs`` is refused.
    """
    layout = _Layout(Path(path))
    notes: List[str] = []
    main = layout.file
    topo = layout.dataset / TOPOCENTRIC
    file = main
    if main.name == RECONSTRUCTION and topo.is_file():
        file = topo
        notes.append(f"read {topo.name}, OpenSfM's own result (ODM's {main.name} is a copy "
                     "linearised to map coordinates)")
    where = str(file)
    recons = read_reconstruction_list(file)
    index, note = choose(recons, chunk, where)
    if note:
        notes.append(note)
    recon = recons[index]
    user_crs = as_crs(crs)

    cams = camera_table(recon, where)
    shots = recon["shots"]
    if not shots:
        raise InputError(f"{where}: reconstruction #{index} has no photos (no 'shots').")
    poses = {}
    for key, shot in shots.items():
        if not isinstance(shot, dict):
            raise InputError(f"{where}: shot {key!r} is not an object.")
        ck = str(shot.get("camera"))
        if ck not in cams:
            raise InputError(f"{where}: shot {key!r} uses camera {ck!r}, which reconstruction "
                             f"#{index} does not define (cameras: {', '.join(cams) or 'none'}). "
                             "The file is incomplete or was edited.")
        poses[str(key)] = shot_pose(str(key), shot, where)

    lla = reference_lla(recon, layout.dataset, where)
    if lla is not None and lla[0] == 0.0 and lla[1] == 0.0:
        lla = None                       # OpenSfM's reference when no photo had a GPS position
    odm_crs, offset, georef_src, offset_src = odm_georeferencing(layout, lla) if layout.odm_root \
        else (None, None, "", "")
    if odm_crs is not None and user_crs is not None and not same_crs(odm_crs, user_crs):
        raise InputError(f"{layout.odm_root}: the ODM project is georeferenced in {odm_crs.name} "
                         f"({georef_src}); do not pass another project CRS ({user_crs.name}). "
                         "Choose the output CRS instead.")

    geocoords = False
    if file.name == GEOCOORDS:
        if odm_crs is None or offset is None:
            raise InputError(f"{where}: this is OpenSfM's export to map coordinates, and neither "
                             "it nor the folder records the CRS and offset it used. Give "
                             f"{RECONSTRUCTION} (or {TOPOCENTRIC}) of the same dataset instead.")
        geocoords = True
        notes.append(f"{file.name} read as map coordinates minus the offset from {offset_src}")
    elif file.name == RECONSTRUCTION and layout.odm_root is not None and odm_crs is not None:
        geocoords, why = _geocoords_evidence(layout, recon, {k: C for k, (R, C) in poses.items()},
                                             lla, odm_crs, offset)
        notes.append(f"{file.name} read as {'map coordinates minus the offset (ODM export)' if geocoords else 'topocentric (OpenSfM)'}: {why}")
    frame: ModelFrame
    if geocoords:
        if offset is None:
            coords = layout.odm_root / "odm_georeferencing" / "coords.txt"
            raise InputError(
                (f"{coords}: the east/north offset (line 2) is missing" if coords.is_file()
                 else f"{coords} is missing") +
                (f", and {offset_src}" if offset_src else
                 f", and {file} has no reference_lla to derive the offset from") +
                ", so its cameras (map coordinates minus that offset) cannot be placed on the "
                "map. Restore odm_georeferencing/coords.txt from the ODM run.")
        frame = OffsetFrame(odm_crs, np.array([offset[0], offset[1], 0.0]))
        map_crs = odm_crs
        notes.append(f"map offset from {offset_src}; CRS from {georef_src}")
        notes.append("cameras as ODM exported them (its linearised map frame, heights as ODM's DSM)")
    elif lla is not None:
        map_crs = odm_crs or user_crs or utm_of(lla[0], lla[1])
        frame = _topocentric_frame(lla, map_crs)
        how = (f"ODM's CRS ({georef_src})" if odm_crs is not None else
               "as given" if user_crs is not None else
               "the WGS 84 / UTM zone of the reference point")
        notes.append(f"topocentric frame about lat {lla[0]:.8f}, lon {lla[1]:.8f}, alt {lla[2]:.3f} m "
                     f"(WGS 84 ellipsoid); map CRS {map_crs.name}, {how}")
    else:
        if user_crs is not None:
            raise InputError(f"{where}: the reconstruction is not georeferenced (no "
                             "reference_lla, or the photos had no GPS), so it cannot be placed "
                             f"in {user_crs.name}; do not pass a project CRS.")
        map_crs = LOCAL_CRS
        frame = LocalFrame(LOCAL_CRS)
        notes.append("not georeferenced (no reference_lla, or the photos had no GPS): "
                     "coordinates are OpenSfM's local ones")

    sensors = {k: Sensor(id=k, label=f"{k} ({ptype})", width=w, height=h, calibration=cal,
                         type="fisheye" if cal.model == "fisheye" else "frame")
               for k, (cal, w, h, ptype) in cams.items()}
    files = PhotoFiles(layout.photos, recursive=False) if layout.photos is not None else None

    def photo(k):                       # shot keys may lack the extension or differ in case
        if files is None:
            return None
        hit, _why = files.find(k)
        return hit or str(layout.photos / k)
    cameras = [Camera(id=k, label=k, sensor_id=str(shots[k]["camera"]), photo_path=photo(k),
                      R=R, C=C) for k, (R, C) in poses.items()]
    # photos of the other partial models: known, but without a pose in this one
    for i, other in enumerate(recons):
        if i == index:
            continue
        for k, s in other["shots"].items():
            if k in poses or not isinstance(s, dict):
                continue
            ck = str(s.get("camera"))
            if ck not in sensors:
                c = other["cameras"].get(ck, {})
                sensors[ck] = Sensor(id=ck, label=ck, width=int(c.get("width", 0) or 0),
                                     height=int(c.get("height", 0) or 0), calibration=None)
            cameras.append(Camera(id=k, label=k, sensor_id=ck, photo_path=photo(k)))
            poses[k] = None
    if files is not None:
        keys = {photo_key(k) for k in poses}
        missing = sorted(os.path.basename(p) for p in files.photos() if photo_key(p) not in keys)
        if missing:
            notes.append(f"{len(missing)} photo(s) in {layout.photos} are in no reconstruction: "
                         + ", ".join(missing[:10]) + (" …" if len(missing) > 10 else ""))
    odd = sorted({int(shots[k].get("orientation", 1)) for k in shots} - {1})
    if odd:
        notes.append(f"some photos have EXIF orientation {odd}: OpenSfM works on them turned "
                     "upright, so their pixels refer to the upright photo")

    markers = _markers(layout, frame, map_crs, cameras, sensors, lla)
    return Reconstruction(source=Path(path), software="odm" if layout.odm_root else "opensfm",
                          label=f"reconstruction {index}" + (f" of {len(recons)}" if len(recons) > 1 else ""),
                          crs=map_crs, frame=frame, sensors=sensors, cameras=cameras,
                          markers=markers, notes=notes)


def _markers(layout: _Layout, frame, map_crs, cameras, sensors, lla) -> List[Marker]:
    """OpenSfM's ``ground_control_points.json`` as markers (pixels in our convention)."""
    path = layout.dataset / "ground_control_points.json"
    if not path.is_file():
        return []
    size = {c.label: (sensors[c.sensor_id].width, sensors[c.sensor_id].height) for c in cameras}
    out = []
    to_map = transformer(WGS84_3D, map_crs) if not isinstance(frame, LocalFrame) else None
    for p in read_gcp_json(path):
        ref = None
        if p["lla"] is not None and to_map is not None:
            lat, lon, alt = p["lla"]
            ref = np.array(to_map.transform(lon, lat, alt), dtype=np.float64)
        obs = {}
        for shot, xn, yn in p["observations"]:
            if shot in size and size[shot][0] > 0:
                u, v = normalised_to_pixels(xn, yn, *size[shot])
                obs[shot] = (float(u), float(v))
        out.append(Marker(p["id"], p["id"], ref, ref is not None, obs))
    return out


# --- the reader of open_reconstruction (readers.py) ---------------------------------------------
def _open(path: Path, options: OpenOptions) -> Reconstruction:
    return open_opensfm(path, options.chunk, options.source_crs)


READER = ProjectReader("OpenDroneMap / OpenSfM", "an ODM project folder (opensfm/, odm_*/), an "
                       "OpenSfM dataset folder or its reconstruction.json", is_opensfm_input,
                       _open)
