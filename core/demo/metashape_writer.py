"""The flight as an Agisoft Metashape 1.x project: ``name.psx`` + ``name.files/``.

Layout as Metashape 1.6–1.8 saves it (compare the real projects in ``realdata/easyidp``):
``name.psx`` points at ``name.files/project.zip``; its ``doc.xml`` lists ``0/chunk.zip`` (sensor
with an adjusted frame calibration, components, cameras with 4×4 camera → chunk transforms,
markers, the chunk transform into WGS 84 geocentric with a rotation and a scale ≠ 1, the chunk
CRS as WKT) and ``0/0/frame.zip`` (photo paths relative to that zip, EXIF meta, marker pixels).

The true poses live in the map-based local frame (UTM minus offset, Pix4D-style), which is not
exactly Cartesian. Each geocentric pose is fitted (6 parameters, Gauss–Newton) so that it sees
63 surface points spread over the photo and over the crop heights in the same directions as the
true pose; the remaining differences are far below 0.001 px.

Rolling-shutter shots (``Shot.motion``) add the sensor's ``rolling_shutter`` property and one
``<rolling_shutter>`` block per camera (:func:`.readout_motion.metashape_block`).
"""
import io
import os
import zipfile
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np

from ..files import write_bytes
from ..rotations import rotation_matrix
from .flight import CameraModel, Shot
from .readout_motion import metashape_block
from .geo import METASHAPE_WGS84_WKT, ENUFrame, map_to_ecef, map_to_lonlat
from .scene import Scene

SOFTWARE_VERSION = "1.7.2.12070"
SAVED = "2024:06:01 12:00:00"
ZIP_TIME = (1980, 1, 1, 0, 0, 0)   # as in the real files: deterministic bytes


def _f(v) -> str:
    return format(float(v), ".16e")


def _fs(values) -> str:
    return " ".join(_f(v) for v in np.ravel(values))


def _zip_doc(path: Path, xml: str) -> None:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        info = zipfile.ZipInfo("doc.xml", date_time=ZIP_TIME)
        info.compress_type = zipfile.ZIP_DEFLATED
        z.writestr(info, xml.encode("utf-8"))
    path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes(path, buf.getvalue())


# --- poses -------------------------------------------------------------------------------------
def _samples(scene: Scene, camera: CameraModel, shot: Shot):
    """63 local surface-band points across the photo and their normalised image coordinates."""
    uu, vv = np.meshgrid(np.linspace(0, camera.width, 9), np.linspace(0, camera.height, 7))
    x, y = camera.calibration.pixel_to_normalised(uu.ravel(), vv.ravel())
    d = np.column_stack([x, y, np.ones_like(x)]) @ shot.R          # local directions
    hk = np.resize([0.0, 0.35, 0.7], len(x))
    a, bx, by = scene.ground_plane
    C = shot.C
    t = (a + bx * C[0] + by * C[1] + hk - C[2]) / (d[:, 2] - bx * d[:, 0] - by * d[:, 1])
    return C + t[:, None] * d, np.column_stack([x, y])


def _kabsch(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Rotation A minimising |A·P_i − Q_i| (rows are vectors)."""
    U, _, Vt = np.linalg.svd(P.T @ Q)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    return Vt.T @ D @ U.T


def fit_enu_pose(frame: ENUFrame, scene: Scene, camera: CameraModel, shot: Shot):
    """(R, C) in the ENU frame seeing the sample points where the true local pose sees them;
    also returns the largest residual in pixels."""
    S, n = _samples(scene, camera, shot)
    Y = frame.enu(S)
    C = frame.enu(shot.C[None])[0]
    R = shot.R @ _kabsch(S - shot.C, Y - C).T

    def resid(R, C):
        xc = (Y - C) @ R.T
        return (xc[:, :2] / xc[:, 2:] - n).ravel()

    for _ in range(4):
        r0 = resid(R, C)
        J = np.empty((len(r0), 6))
        for k in range(3):
            dv = np.zeros(3)
            dv[k] = 1e-7
            J[:, k] = (resid(rotation_matrix(dv) @ R, C) - r0) / 1e-7
            dc = np.zeros(3)
            dc[k] = 1e-5
            J[:, 3 + k] = (resid(R, C + dc) - r0) / 1e-5
        step = np.linalg.lstsq(J, -r0, rcond=None)[0]
        R = rotation_matrix(step[:3]) @ R
        C = C + step[3:]
    err = float(np.abs(resid(R, C)).max() * camera.calibration.f)
    return R, C, err


def random_rotation(rng) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


# --- documents ---------------------------------------------------------------------------------
def _project_doc() -> str:
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<document version="1.2.0">
  <chunks next_id="1" active_id="0">
    <chunk id="0" path="0/chunk.zip"/>
  </chunks>
  <meta>
    <property name="Info/LastSavedDateTime" value="{SAVED}"/>
    <property name="Info/LastSavedSoftwareVersion" value="{SOFTWARE_VERSION}"/>
    <property name="Info/OriginalDateTime" value="{SAVED}"/>
    <property name="Info/OriginalSoftwareName" value="Agisoft Metashape"/>
    <property name="Info/OriginalSoftwareVendor" value="Agisoft"/>
    <property name="Info/OriginalSoftwareVersion" value="{SOFTWARE_VERSION}"/>
  </meta>
</document>
"""


def _sensor_xml(camera: CameraModel, rolling_shutter: bool = False) -> str:
    c = camera.calibration
    w, h = camera.width, camera.height
    terms = [("f", c.f), ("cx", c.cx - w / 2), ("cy", c.cy - h / 2), ("b1", c.b1), ("b2", c.b2),
             ("k1", c.k1), ("k2", c.k2), ("k3", c.k3), ("p1", c.p1), ("p2", c.p2)]
    cal = "\n".join(f"        <{k}>{_f(v)}</{k}>" for k, v in terms)
    return f"""  <sensors next_id="1">
    <sensor id="0" label="{camera.label}" type="frame">
      <resolution width="{w}" height="{h}"/>
      <property name="pixel_width" value="{camera.pixel_mm!r}"/>
      <property name="pixel_height" value="{camera.pixel_mm!r}"/>
      <property name="focal_length" value="{round(camera.focal_mm, 2)!r}"/>
{'      <property name="rolling_shutter" value="true"/>' + chr(10) if rolling_shutter else ''}\
      <property name="layer_index" value="0"/>
      <bands>
        <band label="Red"/>
        <band label="Green"/>
        <band label="Blue"/>
      </bands>
      <data_type>uint8</data_type>
      <calibration type="frame" class="adjusted">
        <resolution width="{w}" height="{h}"/>
{cal}
      </calibration>
    </sensor>
  </sensors>
"""


def _transform_xml(M: np.ndarray, T: np.ndarray, s: float, indent: str) -> str:
    return (f"{indent}<transform>\n"
            f"{indent}  <rotation locked=\"true\">{_fs(M)}</rotation>\n"
            f"{indent}  <translation locked=\"true\">{_fs(T)}</translation>\n"
            f"{indent}  <scale locked=\"true\">{_f(s)}</scale>\n"
            f"{indent}</transform>\n")


def _shutter_xml(block) -> str:
    if block is None:
        return ""
    return (f"      <rolling_shutter>\n        <rotation>{_fs(block[0])}</rotation>\n"
            f"        <translation>{_fs(block[1])}</translation>\n      </rolling_shutter>\n")


def _chunk_doc(camera, shots, cam_T, gps_lla, M, T, s, region, markers, blocks=None) -> str:
    cams = []
    blocks = blocks or [None] * len(shots)
    for i, (shot, Tc, g) in enumerate(zip(shots, cam_T, gps_lla)):
        cams.append(f"""    <camera id="{i}" sensor_id="0" component_id="0" label="{shot.label}">
      <transform>{_fs(Tc[:3])} 0 0 0 1</transform>
{_shutter_xml(blocks[i])}\
      <orientation>1</orientation>
      <reference x="{g[0]:.12f}" y="{g[1]:.12f}" z="{g[2]:.3f}" yaw="{shot.yaw_deg:.1f}" pitch="0" roll="0" sxy="10" sz="10" enabled="true" rotation_enabled="false"/>
    </camera>
""")
    mks = []
    for j, m in enumerate(markers):
        lon, lat, hgt = m["lonlat"]
        mks.append(f"""    <marker id="{j}" label="{m['label']}">
      <reference x="{lon:.12f}" y="{lat:.12f}" z="{hgt:.4f}" enabled="true"/>
    </marker>
""")
    centre, size, rot = region
    return (f"""<?xml version="1.0" encoding="UTF-8"?>
<chunk version="1.2.0" label="Chunk 1" enabled="true">
{_sensor_xml(camera, blocks[0] is not None)}  <components next_id="1" active_id="0">
    <component id="0" label="Component 1">
{_transform_xml(M, T, s, "      ")}      <region>
        <center>{_fs(centre)}</center>
        <size>{_fs(size)}</size>
        <R>{_fs(rot)}</R>
      </region>
    </component>
  </components>
  <cameras next_id="{len(shots)}" next_group_id="0">
{''.join(cams)}  </cameras>
  <markers next_id="{len(markers)}" next_group_id="0">
{''.join(mks)}  </markers>
  <frames next_id="1">
    <frame id="0" path="0/frame.zip"/>
  </frames>
{_transform_xml(M, T, s, "  ")}  <reference>{METASHAPE_WGS84_WKT}</reference>
  <region>
    <center>{_fs(centre)}</center>
    <size>{_fs(size)}</size>
    <R>{_fs(rot)}</R>
  </region>
  <settings>
    <property name="accuracy_tiepoints" value="1"/>
    <property name="accuracy_cameras" value="10"/>
    <property name="accuracy_cameras_ypr" value="10"/>
    <property name="accuracy_markers" value="0.0050000000000000001"/>
    <property name="accuracy_scalebars" value="0.001"/>
    <property name="accuracy_projections" value="0.5"/>
  </settings>
  <meta>
    <property name="AlignCameras/adaptive_fitting" value="false"/>
    <property name="AlignCameras/level" value="1"/>
    <property name="Info/LastSavedDateTime" value="{SAVED}"/>
    <property name="Info/LastSavedSoftwareVersion" value="{SOFTWARE_VERSION}"/>
    <property name="OptimizeCameras/fit_b1" value="true"/>
    <property name="OptimizeCameras/fit_b2" value="true"/>
  </meta>
</chunk>
""")


def _frame_doc(camera, shots, photo_rel: Sequence[str], gps_lla, markers) -> str:
    cams = []
    for i, (shot, rel, g) in enumerate(zip(shots, photo_rel, gps_lla)):
        props = [("Exif/DateTime", shot.time), ("Exif/DateTimeOriginal", shot.time),
                 ("Exif/FocalLength", f"{camera.focal_mm:.2f}"),
                 ("Exif/GPSAltitude", f"{g[2]:.3f}"), ("Exif/GPSLatitude", f"{g[1]:.13f}"),
                 ("Exif/GPSLongitude", f"{g[0]:.12f}"), ("Exif/Make", "EasyIDP"),
                 ("Exif/Model", camera.model), ("Exif/Orientation", "1"),
                 ("File/ImageHeight", str(camera.height)), ("File/ImageWidth", str(camera.width))]
        meta = "\n".join(f'          <property name="{k}" value="{v}"/>' for k, v in props)
        cams.append(f"""    <camera camera_id="{i}">
      <photo path="{rel}">
        <meta>
{meta}
        </meta>
      </photo>
    </camera>
""")
    mks = []
    for j, m in enumerate(markers):
        locs = "".join(f'      <location camera_id="{i}" pinned="true" x="{u:.6f}" y="{v:.6f}"/>\n'
                       for i, (u, v) in sorted(m["pixels"].items()))
        mks.append(f'    <marker marker_id="{j}">\n{locs}    </marker>\n')
    return (f"""<?xml version="1.0" encoding="UTF-8"?>
<frame version="1.2.0">
  <cameras>
{''.join(cams)}  </cameras>
  <markers>
{''.join(mks)}  </markers>
</frame>
""")


def write_metashape(folder, name: str, scene: Scene, camera: CameraModel, shots: List[Shot],
                    photo_paths: Sequence[str], markers: List[Dict], rng) -> Dict:
    """Write ``folder/name.psx`` and ``folder/name.files``. ``photo_paths``: absolute photo paths
    (written relative to the frame zip); ``markers``: dicts with ``label``, ``xyz`` (map) and
    ``pixels`` {shot index: (u, v)}. Returns {"psx", "max_fit_px"}."""
    folder = Path(folder)
    files = folder / f"{name}.files"
    frame = ENUFrame(scene.offset)
    # chunk: internal → geocentric X = s·M·x + T, centred near the field
    M = random_rotation(rng)
    s = float(rng.uniform(0.4, 2.5))
    lay = scene.layout
    centre_map = np.array([lay.origin[0] + lay.size[0] / 2, lay.origin[1] - lay.size[1] / 2,
                           scene.offset[2]])
    centre_ecef = map_to_ecef(centre_map[None])[0]
    T = centre_ecef + rng.normal(0.0, 3.0, 3)
    cam_T, worst = [], 0.0
    for shot in shots:
        Re, Ce, err = fit_enu_pose(frame, scene, camera, shot)
        worst = max(worst, err)
        R_ecef = Re @ frame.rotation                      # geocentric → camera
        C_ecef = frame.to_ecef(Ce[None])[0]
        Tc = np.eye(4)
        Tc[:3, :3] = M.T @ R_ecef.T                       # camera → chunk
        Tc[:3, 3] = M.T @ (C_ecef - T) / s
        cam_T.append(Tc)
    blocks = None
    if any(shot.motion is not None for shot in shots):        # rolling-shutter photos
        fit = lambda sh: fit_enu_pose(frame, scene, camera, sh)[:2]   # noqa: E731
        blocks = [metashape_block(fit, shot, s) for shot in shots]
    region = (M.T @ (centre_ecef - T) / s, np.array([lay.size[0], lay.size[1], 6.0]) / s,
              (M.T @ frame.rotation.T).T)
    gps_lla = map_to_lonlat(np.array([sh.gps for sh in shots]))
    for m in markers:
        m["lonlat"] = map_to_lonlat(np.asarray(m["xyz"], float)[None])[0]
    frame_dir = files / "0" / "0"
    rel = [_relpath(p, frame_dir) for p in photo_paths]
    _zip_doc(files / "project.zip", _project_doc())
    _zip_doc(files / "0" / "chunk.zip",
             _chunk_doc(camera, shots, cam_T, gps_lla, M, T, s, region, markers, blocks))
    _zip_doc(frame_dir / "frame.zip", _frame_doc(camera, shots, rel, gps_lla, markers))
    psx = folder / f"{name}.psx"
    write_bytes(psx, b'<?xml version="1.0" encoding="UTF-8"?>\n'
                     b'<document version="1.2.0" path="{projectname}.files/project.zip"/>\n')
    return {"psx": str(psx), "max_fit_px": worst}


def _relpath(path, start: Path) -> str:
    """``path`` relative to the folder ``start``, with forward slashes (as Metashape writes)."""
    return Path(os.path.relpath(os.path.abspath(path), os.path.abspath(start))).as_posix()
