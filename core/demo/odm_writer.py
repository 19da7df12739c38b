"""The flight as an OpenDroneMap project, as ODM 3.x leaves a georeferenced run.

``odm/`` holds what ODM's stages write (ODM ``stages/run_opensfm.py``, ``opendm/location.py``,
``opendm/shots.py``, OpenSfM ``io.py``):

    images/DJI_xxxx.JPG                      the photos (hard links, or copies)
    opensfm/reconstruction.topocentric.json  OpenSfM's result: topocentric frame about reference_lla
    opensfm/reconstruction.json              ODM's export of it: UTM minus the coords.txt offset
    opensfm/reference_lla.json, camera_models.json, image_list.txt
    odm_georeferencing/coords.txt            "WGS84 UTM 54N", the offset, the photos' GPS positions
    odm_report/shots.geojson                 camera positions in map coordinates
    cameras.json                             the adjusted camera model
    odm_dem/dsm.tif, odm_orthophoto/odm_orthophoto.tif   the survey's DSM and orthomosaic (same)

The reference point is the mean GPS position at altitude 0, as OpenSfM chooses it; the offset is
the floor of the photos' mean UTM position, as ODM chooses it. The map-coordinate file is the
truth frame itself (UTM minus an offset), so it holds the true poses. The topocentric poses are
fitted like the Metashape ones (:func:`.metashape_writer.fit_enu_pose`: they see the surface in
the same directions, far below 0.001 px apart). The camera is ``brown``: OpenSfM has no skew
term, and neither has the demo camera (see :func:`.flight.make_camera`).
"""
import json
import os
import shutil
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np
from pyproj import CRS

from ..crs import transformer
from ..files import atomic_output, write_bytes
from ..rotations import rotation_vector
from .flight import CameraModel, Shot
from .geo import MAP_EPSG, ENUFrame, map_to_lonlat
from .metashape_writer import fit_enu_pose
from .scene import Scene

CAPTURE_T0 = 1717236000.0      # 2024-06-01 10:00:00 UTC, the demo flight's first photo
GPS_DOP = 5.0


class TopocentricFrame(ENUFrame):
    """OpenSfM's topocentric frame about a reference point at ellipsoidal height 0, for points
    given in the scene's local frame (map − ``scene.offset``)."""

    def __init__(self, reference_map_xy, scene_offset):
        super().__init__(np.array([reference_map_xy[0], reference_map_xy[1], 0.0]))
        self.shift = np.asarray(scene_offset, float) - self.offset

    def enu(self, local: np.ndarray) -> np.ndarray:
        return super().enu(local + self.shift)


def camera_key(camera: CameraModel) -> str:
    return f"v2 easyidp {camera.model.lower()} {camera.width} {camera.height} brown " \
           f"{camera.calibration.f / max(camera.width, camera.height):.4f}"


def opensfm_camera(camera: CameraModel) -> dict:
    """The demo camera as an OpenSfM ``brown`` camera (normalised by max(w, h); no skew)."""
    c, w, h = camera.calibration, camera.width, camera.height
    size = float(max(w, h))
    return {"projection_type": "brown", "width": w, "height": h,
            "focal_x": (c.f + c.b1) / size, "focal_y": c.f / size,
            "c_x": (c.cx - w / 2) / size, "c_y": (c.cy - h / 2) / size,
            "k1": c.k1, "k2": c.k2, "p1": c.p2, "p2": c.p1, "k3": c.k3}


def _shot(R, C, key, gps_topo, i) -> dict:
    return {"rotation": rotation_vector(R).tolist(), "translation": (-R @ C).tolist(),
            "camera": key, "orientation": 1, "capture_time": CAPTURE_T0 + 2.0 * i,
            "gps_dop": GPS_DOP, "gps_position": gps_topo.tolist(), "vertices": [], "faces": [],
            "scale": 1.0, "covariance": [], "merge_cc": 0}


def _reconstruction(cams: dict, poses, names, gps_topo, points, lla) -> List[dict]:
    key = next(iter(cams))
    shots = {n: _shot(R, C, key, g, i) for i, (n, (R, C), g) in enumerate(zip(names, poses, gps_topo))}
    return [{
        "cameras": cams, "shots": shots,
        "points": {str(i): {"color": [128.0, 128.0, 128.0], "coordinates": p.tolist()}
                   for i, p in enumerate(points)},
        "biases": {key: {"rotation": [0.0, 0.0, 0.0], "translation": [0.0, 0.0, 0.0], "scale": 1.0}},
        "rig_cameras": {"rig_camera": {"rotation": [0.0, 0.0, 0.0], "translation": [0.0, 0.0, 0.0]}},
        "rig_instances": {str(i): {"translation": shots[n]["translation"],
                                   "rotation": shots[n]["rotation"],
                                   "rig_camera_ids": {n: "rig_camera"}} for i, n in enumerate(names)},
        "reference_lla": lla}]


def _json(path: Path, obj) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes(path, json.dumps(obj, indent=4).encode())


def _copy(src: str, dst: Path) -> None:
    """``dst`` with the bytes of ``src``: a hard link where the file system allows (no extra
    space), else a copy."""
    dst.parent.mkdir(parents=True, exist_ok=True)
    with atomic_output(dst) as tmp:
        try:
            os.link(src, tmp)
        except OSError:
            shutil.copyfile(src, tmp)


def write_odm(folder, scene: Scene, camera: CameraModel, shots: List[Shot],
              photo_paths: Sequence[str], truth_points: np.ndarray, dsm: str,
              orthomosaic: str) -> Dict[str, str]:
    """Write the ODM project into ``folder`` (see the module docstring). ``truth_points``
    (map coordinates) become the sparse points; returns {"project", "reconstruction",
    "max_fit_px"}."""
    root = Path(folder)
    names = [s.filename for s in shots]
    gps = np.array([s.gps for s in shots])                       # map coordinates
    ref_map = _mean_gps_map(gps)
    frame = TopocentricFrame(ref_map, scene.offset)
    lon, lat, _ = map_to_lonlat(np.array([[ref_map[0], ref_map[1], 0.0]]))[0]
    lla = {"latitude": float(lat), "longitude": float(lon), "altitude": 0.0}
    offset = np.floor(gps[:, :2].mean(axis=0))
    key = camera_key(camera)
    cams = {key: opensfm_camera(camera)}
    gps_topo = frame.enu(gps - scene.offset)

    fits = [fit_enu_pose(frame, scene, camera, s) for s in shots]
    topo_poses = [(R, C) for R, C, _ in fits]
    shift = scene.offset - [offset[0], offset[1], 0.0]
    map_poses = [(s.R, s.C + shift) for s in shots]
    pts = np.asarray(truth_points, float)
    topo = _reconstruction(cams, topo_poses, names, gps_topo, frame.enu(pts - scene.offset), lla)
    geo = _reconstruction(cams, map_poses, names, gps_topo, pts - [offset[0], offset[1], 0.0], lla)

    osfm = root / "opensfm"
    _json(osfm / "reconstruction.topocentric.json", topo)
    _json(osfm / "reconstruction.json", geo)
    _json(osfm / "reference_lla.json", lla)
    prior = dict(cams[key], focal_x=camera.calibration.f / max(camera.width, camera.height),
                 c_x=0.0, c_y=0.0, k1=0.0, k2=0.0, p1=0.0, p2=0.0, k3=0.0)
    prior["focal_y"] = prior["focal_x"]
    _json(osfm / "camera_models.json", {key: prior})
    write_bytes(osfm / "image_list.txt", "".join(f"../images/{n}\n" for n in names).encode())
    _json(root / "cameras.json", cams)
    (root / "odm_georeferencing").mkdir(parents=True, exist_ok=True)
    write_bytes(root / "odm_georeferencing" / "coords.txt", (
        f"WGS84 UTM {MAP_EPSG - 32600}N\n{int(offset[0])} {int(offset[1])}\n"
        + "".join(f"{g[0] - offset[0]} {g[1] - offset[1]} {g[2]}\n" for g in gps)).encode())
    feats = []
    for n, (R, C), ll in zip(names, map_poses, map_to_lonlat(np.array([C + [offset[0], offset[1], 0.0]
                                                                          for _, C in map_poses]))):
        t = C + [offset[0], offset[1], 0.0]
        feats.append({"type": "Feature",
                      "properties": {"filename": n, "focal": cams[key]["focal_x"],
                                     "width": camera.width, "height": camera.height,
                                     "translation": t.tolist(), "rotation": rotation_vector(R).tolist()},
                      "geometry": {"type": "Point", "coordinates": ll.tolist()}})
    _json(root / "odm_report" / "shots.geojson", {"type": "FeatureCollection", "features": feats})
    for p in photo_paths:
        _copy(p, root / "images" / os.path.basename(p))
    _copy(dsm, root / "odm_dem" / "dsm.tif")
    _copy(orthomosaic, root / "odm_orthophoto" / "odm_orthophoto.tif")
    return {"project": str(root), "reconstruction": str(osfm / "reconstruction.json"),
            "max_fit_px": max(e for _, _, e in fits)}


def _mean_gps_map(gps: np.ndarray) -> np.ndarray:
    """Map (x, y) of the mean GPS latitude and longitude (OpenSfM's reference_lla, equal DOPs)."""
    ll = map_to_lonlat(gps)
    x, y = transformer(CRS.from_epsg(4326), CRS.from_epsg(MAP_EPSG)).transform(ll[:, 0].mean(),
                                                                                 ll[:, 1].mean())
    return np.array([x, y])
