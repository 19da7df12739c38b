"""Camera model: OpenCV agreement, pixel → ray → plane → pixel round trip, Metashape variants
(.psz, cameras XML, groups, rigs, several chunks) built from the real wheat_tanashi documents."""
import io
import zipfile
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.reconstruction import Calibration, INSIDE

import cv2  # noqa: E402 (OpenCV: the independent reference)


@pytest.fixture(scope="module")
def ms(realdata):
    return realdata / "easyidp" / "metashape"


@pytest.fixture(scope="module")
def wheat(ms):
    return open_reconstruction(ms / "wheat_tanashi.psx")


@pytest.fixture(scope="module")
def goya(ms):
    return open_reconstruction(ms / "goya_test.psx")


def _opencv_case(recon, label, n=400, seed=0):
    cam = recon.camera(label)
    s = recon.sensors[cam.sensor_id]
    rng = np.random.default_rng(seed)
    uv = np.column_stack([rng.uniform(0, s.width, n), rng.uniform(0, s.height, n)])
    o, d = recon.pixel_to_ray(cam, uv)
    X = o + d * rng.uniform(5, 30, (n, 1))
    ours = recon.project_points(recon.from_model(X), cameras=[label]).pixels[0]
    K, dist = s.calibration.to_opencv()
    skew = K[0, 1]                                   # cv2.projectPoints ignores K[0, 1]: add b2·y'
    K[0, 1] = 0.0
    rvec, _ = cv2.Rodrigues(cam.R)
    tvec = -cam.R @ cam.C
    cvp, _ = cv2.projectPoints(X.reshape(-1, 1, 3), rvec, tvec, K, dist)
    cvp = cvp.reshape(-1, 2) + 0.5                   # OpenCV centres at integers → ours
    cvp[:, 0] += skew * (cvp[:, 1] - K[1, 2] - 0.5) / K[1, 1]
    return ours, cvp


def test_opencv_projectpoints_agrees(wheat):
    ours, theirs = _opencv_case(wheat, "DJI_0050")
    d = np.abs(ours - theirs).max()
    print(f"\nOpenCV projectPoints vs ours (wheat FC550, k1-k3, p1, p2): max {d:.1e} px")
    assert d < 1e-4                                  # includes a lon/lat/h round trip of X


def test_opencv_agrees_with_b1_b2_as_fx_and_skew(goya):
    """goya has b1, b2 (→ fx = f + b1, skew = b2) and k4 (no OpenCV term: compare with k4 = 0).
    One pose per photo here (its rolling shutter off); test_rolling_shutter.py compares the
    rolling-shutter poses with OpenCV."""
    import dataclasses
    s = goya.sensors["0"]
    orig = s.calibration
    cam = goya.camera("DJI_0300.JPG")
    rs = cam.rolling_shutter
    s.calibration, s._r2, cam.rolling_shutter = dataclasses.replace(orig, k4=0.0), None, None
    try:
        ours, theirs = _opencv_case(goya, "DJI_0300.JPG")
    finally:
        s.calibration, s._r2, cam.rolling_shutter = orig, None, rs
    d = np.abs(ours - theirs).max()
    print(f"OpenCV vs ours (goya b1, b2, skew): max {d:.1e} px")
    assert d < 1e-4


@pytest.mark.parametrize("which", ["wheat", "goya"])
def test_round_trip_pixel_ray_plane_pixel(which, wheat, goya):
    recon = wheat if which == "wheat" else goya
    cam = recon.aligned_cameras[40]
    s = recon.sensors[cam.sensor_id]
    u, v = np.meshgrid(np.linspace(0, s.width, 33), np.linspace(0, s.height, 25))
    uv = np.column_stack([u.ravel(), v.ravel()])
    o, d = recon.pixel_to_ray(cam, uv)
    # a plane 15 m in front of the camera, tilted 10° off the image plane
    axis = cam.R[2]
    n = axis + 0.18 * cam.R[0]
    n /= np.linalg.norm(n)
    p0 = o + 15.0 * axis
    t = ((p0 - o) @ n) / (d @ n)
    X = o + t[:, None] * d
    p = recon.project_points(recon.from_model(X), cameras=[cam.label])
    err = np.hypot(*(p.pixels[0] - uv).T)
    corners = [0, 32, len(uv) - 33, len(uv) - 1]
    print(f"\nround trip {which}: max {err.max():.1e} px, corners {err[corners].max():.1e} px")
    assert err.max() < 1e-3
    interior = (uv[:, 0] > 0) & (uv[:, 0] < s.width) & (uv[:, 1] > 0) & (uv[:, 1] < s.height)
    assert (p.status[0][interior] == INSIDE).all()


def test_distortion_switch_and_far_points_not_folded_in():
    cal = Calibration(f=1000, cx=500, cy=400, k1=-0.3, k2=0.05)
    x, y = np.array([0.3]), np.array([0.2])
    assert cal.project_normalised(x, y, distortion=False)[0][0] == pytest.approx(800)
    assert cal.project_normalised(x, y)[0][0] != pytest.approx(800)
    # with k1 < 0 the polynomial folds back: r·(1 + k1r² + k2r⁴) decreases beyond ~1.3
    r2 = cal.valid_radius2(1000, 800)
    assert r2 < 4.0
    from easyidp_toolbox.core.reconstruction.frame_model import OUTSIDE, project_block
    far = np.array([[2.2, 0.0, 1.0]])                 # r = 2.2: distorted back to r ≈ 0.4
    uv, st = project_block(far, np.eye(3)[None], np.zeros((1, 3)), cal, 1000, 800, r2)
    assert st[0, 0] == OUTSIDE and np.isnan(uv[0, 0]).all()


# --- Metashape variants built from the real documents -------------------------------------------
def _docs(ms, name):
    base = ms / f"{name}.files"
    out = {}
    for rel in ("project.zip", "0/chunk.zip", "0/0/frame.zip"):
        with zipfile.ZipFile(base / rel) as z:
            out[rel] = z.read("doc.xml")
    return out


def _zip_bytes(doc: bytes) -> bytes:
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("doc.xml", doc)
    return buf.getvalue()


def _write_psx(folder, name, project: bytes, chunks: dict):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.psx").write_text('<?xml version="1.0" encoding="UTF-8"?>\n<document '
                                        'version="1.2.0" path="{projectname}.files/project.zip"/>')
    files = folder / f"{name}.files"
    for rel, doc in {"project.zip": project, **chunks}.items():
        p = files / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_bytes(_zip_bytes(doc))
    return folder / f"{name}.psx"


def test_psz_archive_and_cameras_xml_export(ms, wheat, tmp_path):
    d = _docs(ms, "wheat_tanashi")
    psz = tmp_path / "w.psz"
    with zipfile.ZipFile(psz, "w") as z:
        z.writestr("doc.xml", d["project.zip"])
        z.writestr("0/chunk.zip", _zip_bytes(d["0/chunk.zip"]))
        z.writestr("0/0/frame.zip", _zip_bytes(d["0/0/frame.zip"]))
    a = open_reconstruction(psz)
    chunk = ET.fromstring(d["0/chunk.zip"])
    doc = ET.Element("document", version="1.5.0")
    doc.append(chunk)
    xml = tmp_path / "cameras.xml"
    xml.write_bytes(ET.tostring(doc))
    b = open_reconstruction(xml)
    pts = np.array([m.reference for m in wheat.markers])
    ref = wheat.project_points(pts, "EPSG:4326")
    for r in (a, b):
        p = r.project_points(pts, "EPSG:4326")
        assert np.array_equal(p.status, ref.status)
        assert np.allclose(p.pixels[p.inside], ref.pixels[ref.inside], atol=1e-6)
    assert a.camera("DJI_0001").photo_path.endswith("DJI_0001.JPG")
    assert b.camera("DJI_0001").photo_path is None     # the export carries no photo paths


def test_groups_noncontiguous_ids_disabled_and_several_chunks(ms, tmp_path):
    d = _docs(ms, "wheat_tanashi")
    chunk = ET.fromstring(d["0/chunk.zip"])
    cams = chunk.find("cameras")
    kids = list(cams)
    grp = ET.SubElement(cams, "group", id="0", label="flight 2", type="folder")
    for c in kids[100:]:
        cams.remove(c)
        grp.append(c)
    kids[5].set("enabled", "false")                    # a *string*, must not read as True
    kids[5].set("id", "500")                           # non-consecutive id (its photo stays)
    off = ET.tostring(chunk).replace(b'enabled="true"', b'enabled="false"', 1)
    proj = (b'<document version="1.2.0"><chunks next_id="8" active_id="0">'
            b'<chunk id="0" path="0/chunk.zip"/><chunk id="7" path="7/chunk.zip"/></chunks></document>')
    psx = _write_psx(tmp_path, "multi", proj, {"0/chunk.zip": ET.tostring(chunk),
                                               "0/0/frame.zip": d["0/0/frame.zip"],
                                               "7/chunk.zip": off, "7/0/frame.zip": d["0/0/frame.zip"]})
    with pytest.raises(InputError, match=r"2 chunks: id 0 'Chunk 1'; id 7 'Chunk 1' \(disabled\)"):
        open_reconstruction(psx)
    with pytest.raises(InputError, match="several chunks are labelled 'Chunk 1'"):
        open_reconstruction(psx, chunk="Chunk 1")
    r0 = open_reconstruction(psx, chunk=0)
    r7 = open_reconstruction(psx, chunk="7")
    assert r0.enabled and not r7.enabled
    c5 = r0.camera(kids[5].get("label"))
    assert c5.id == "500" and c5.enabled is False and c5.photo_path is None
    assert c5 not in r0.aligned_cameras and len(r0.aligned_cameras) == 137
    assert sum(c.group == "flight 2" for c in r0.cameras) == 38


def test_multispectral_slave_uses_its_rig_offset(ms, tmp_path):
    d = _docs(ms, "wheat_tanashi")
    chunk = ET.fromstring(d["0/chunk.zip"])
    sensors = chunk.find("sensors")
    slave = ET.fromstring(ET.tostring(sensors.find("sensor")))
    slave.set("id", "1")
    slave.set("master_id", "0")
    slave.set("label", "slave band")
    ET.SubElement(slave, "location").text = "0.05 -0.02 0.0"
    ang = np.radians(2.0)
    rot = np.array([[np.cos(ang), -np.sin(ang), 0], [np.sin(ang), np.cos(ang), 0], [0, 0, 1]])
    ET.SubElement(slave, "rotation").text = " ".join(f"{v:.17g}" for v in rot.ravel())
    sensors.append(slave)
    cams = chunk.find("cameras")
    ET.SubElement(cams, "camera", id="900", sensor_id="1", component_id="0",
                  label="DJI_0010_slave", master_id="9")
    psx = _write_psx(tmp_path, "ms", d["project.zip"], {"0/chunk.zip": ET.tostring(chunk),
                                                        "0/0/frame.zip": d["0/0/frame.zip"]})
    r = open_reconstruction(psx)
    master, sl = r.camera("DJI_0010"), r.camera("DJI_0010_slave")
    assert sl.aligned and not np.allclose(sl.C, master.C)
    scale = 2.3339589865785326                         # chunk scale: rig offsets are in chunk units
    assert np.allclose(sl.C, master.C + master.R.T @ (scale * np.array([0.05, -0.02, 0.0])), atol=1e-9)
    assert np.allclose(sl.R, rot.T @ master.R, atol=1e-12)
