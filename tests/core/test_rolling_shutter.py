"""Rolling shutter on the real goya_test project (DJI FC7203, compensation on in Metashape).

Independent checks: Metashape's own pinned marker observations (real file), OpenCV's
projectPoints and Rodrigues for the pose of each point's row, a brute-force bisection on the
row, and the convention script's own formulas (scripts/rolling_shutter_conventions.py).
"""
import dataclasses
import io
import zipfile

import cv2
import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.reconstruction import BEHIND, INSIDE, OUTSIDE
from easyidp_toolbox.core.reconstruction.frame_model import project_block
from easyidp_toolbox.core.reconstruction.rolling_shutter import RollingShutter, project_block_rs
from easyidp_toolbox.core.rotations import rotation_vector


@pytest.fixture(scope="module")
def psx(realdata):
    return realdata / "easyidp" / "metashape" / "goya_test.psx"


@pytest.fixture(scope="module")
def goya(psx):
    return open_reconstruction(psx)


@pytest.fixture(scope="module")
def goya_off(psx):
    r = open_reconstruction(psx)
    for c in r.cameras:
        c.rolling_shutter = None
    return r


def _blocks(psx):
    import xml.etree.ElementTree as ET
    with zipfile.ZipFile(psx.parent / "goya_test.files" / "0" / "chunk.zip") as z:
        root = ET.fromstring(z.read("doc.xml"))
    out = {}
    for el in root.find("cameras").iter("camera"):
        rs = el.find("rolling_shutter")
        if rs is not None:
            out[el.get("label")] = (np.array(rs.find("rotation").text.split(), float).reshape(3, 3),
                                    np.array(rs.find("translation").text.split(), float))
    return root, out


def test_reader_keeps_every_cameras_motion(goya, psx):
    root, blocks = _blocks(psx)
    scale = float(root.find("components/component/transform/scale").text)
    assert goya.sensors["0"].rolling_shutter
    assert len(goya.rolling_shutter_cameras) == 256 == len(blocks)
    for cam in goya.rolling_shutter_cameras[::37]:
        Rs, t = blocks[cam.label]
        back, _ = cv2.Rodrigues(cam.rolling_shutter.rotation)       # OpenCV's exp
        assert np.abs(back - Rs).max() < 1e-12
        assert np.allclose(cam.rolling_shutter.translation, scale * t, rtol=1e-12, atol=0)
    assert any(n.startswith("rolling-shutter compensation applied: 256 of 256") for n in goya.notes)
    assert "rolling-shutter compensation on 256" in goya.summary()


def _marker_residuals(recon):
    """Triangulate each marker seen twice or more from its pinned observations, refine it on the
    reprojection error, return all pixel residuals and the positions."""
    res, pos = [], {}
    for m in recon.markers:
        obs = {k: np.asarray(v) for k, v in m.observations.items() if recon.camera(k).aligned}
        if len(obs) < 2:
            continue
        labels, uvs = list(obs), np.array(list(obs.values()))
        A, b = np.zeros((3, 3)), np.zeros(3)
        for lab, uv in obs.items():
            o, d = recon.pixel_to_ray(lab, [uv])
            P = np.eye(3) - np.outer(d[0], d[0])
            A, b = A + P, b + P @ np.broadcast_to(o, d.shape)[0]
        X = np.linalg.solve(A, b)

        def r(X):
            return (recon.project_points(X[None], cameras=labels).pixels[:, 0] - uvs).ravel()
        for _ in range(5):
            r0 = r(X)
            J = np.column_stack([(r(X + 1e-6 * e) - r0) / 1e-6 for e in np.eye(3)])
            X = X + np.linalg.lstsq(J, -r0, rcond=None)[0]
        res.append(np.hypot(*r(X).reshape(-1, 2).T))
        pos[m.label] = X
    return np.concatenate(res), pos


def test_markers_with_and_without_compensation(goya, goya_off, capsys):
    """Metashape's pinned observations (real file): 6 px median without the motion, a third of
    a pixel with it (Metashape's marker placement accuracy setting is 0.5 px); the scale bar
    90–92 that Metashape's adjustment held at 14.85 m comes out at 14.8500 m."""
    on, pos_on = _marker_residuals(goya)
    off, pos_off = _marker_residuals(goya_off)
    bar = lambda p: np.linalg.norm(p["target 90"] - p["target 92"])  # noqa: E731
    with capsys.disabled():
        print(f"\ngoya_test markers ({len(on)} observations): without compensation median "
              f"{np.median(off):.3f} px, max {off.max():.3f} px, bar {bar(pos_off):.4f} m; with it "
              f"median {np.median(on):.3f} px, max {on.max():.3f} px, bar {bar(pos_on):.4f} m")
    assert len(on) == len(off) == 184
    assert np.median(off) > 5.0 and off.max() > 20.0
    assert np.median(on) < 0.4 and on.max() < 1.0
    assert bar(pos_on) == pytest.approx(14.85, abs=2e-4)


def test_convention_script_formulas_agree_with_the_core(psx, goya):
    """The evidence script poses each row with its own formulas (Rodrigues matrices, fixed-point
    row) from the raw blocks; for the chosen convention they give the core's residuals."""
    from easyidp_toolbox.scripts.rolling_shutter_conventions import Convention, Project, residuals
    p = Project(psx)
    theirs, _ = residuals(p, Convention("chosen"))
    ours, _ = _marker_residuals(goya)
    assert np.abs(np.sort(theirs) - np.sort(ours)).max() < 1e-4


def _points(recon, n, seed=0):
    """Random model points in the scene: between 0.5 and 4 m in front of random cameras."""
    rng = np.random.default_rng(seed)
    cams = recon.aligned_cameras
    out = []
    for i in rng.integers(0, len(cams), n):
        c = cams[i]
        d = np.array([rng.uniform(-0.9, 0.9), rng.uniform(-0.7, 0.7), 1.0]) @ c.R
        out.append(c.C + rng.uniform(0.5, 4.0) * d)
    return np.array(out)


@pytest.mark.parametrize("distortion", [True, False])
def test_round_trips(goya, distortion):
    """project_points → pixel_to_ray points back at the point (1e-9 rad); pixel_to_ray → a
    point on the ray → project_points returns the pixel (1e-6 px), over the whole frame."""
    X = _points(goya, 400)
    p = goya.project_points(goya.from_model(X), distortion=distortion)
    ci, pi = np.nonzero(p.inside)
    assert len(ci) > 3000
    worst = 0.0
    for c in np.unique(ci):
        k = pi[ci == c]
        o, d = goya.pixel_to_ray(p.camera_labels[c], p.pixels[c, k], distortion)
        v = X[k] - o
        v /= np.linalg.norm(v, axis=1, keepdims=True)
        worst = max(worst, float(np.linalg.norm(np.cross(v, d), axis=1).max()))
    assert worst < 1e-9
    s = goya.sensors["0"]
    u, v = np.meshgrid(np.linspace(0, s.width, 41), np.linspace(0, s.height, 31))
    uv = np.column_stack([u.ravel(), v.ravel()])
    for cam in goya.aligned_cameras[::50]:
        o, d = goya.pixel_to_ray(cam, uv, distortion)
        q = goya.project_points(goya.from_model(o + 2.5 * d), cameras=[cam], distortion=distortion)
        assert np.abs(q.pixels[0] - uv).max() < 1e-6
        interior = (uv[:, 0] > 0) & (uv[:, 0] < s.width) & (uv[:, 1] > 0) & (uv[:, 1] < s.height)
        assert (q.status[0][interior] == INSIDE).all()


def test_distortion_off_keeps_the_sensor_rows_pose(goya):
    """Without distortion a point keeps the pose of the sensor row it was exposed on: its pixel
    is the distorted pixel's, undistorted through the calibration alone."""
    X = _points(goya, 100, seed=3)
    on = goya.project_points(goya.from_model(X))
    off = goya.project_points(goya.from_model(X), distortion=False)
    cal = goya.sensors["0"].calibration
    ok = on.inside
    x, y = cal.pixel_to_normalised(on.pixels[ok][:, 0], on.pixels[ok][:, 1])
    u, v = cal.project_normalised(x, y, distortion=False)
    assert np.abs(np.column_stack([u, v]) - off.pixels[ok]).max() < 1e-6


def test_opencv_sees_each_point_at_its_pixel_with_the_pose_of_its_row(goya):
    """Independent: for every projected pixel, the pose of its row (OpenCV Rodrigues for
    exp(τ[ω]×)) and OpenCV's projectPoints (goya's lens with k4 = 0) give the same pixel."""
    s = goya.sensors["0"]
    orig = s.calibration
    s.calibration, s._r2 = dataclasses.replace(orig, k4=0.0), None
    try:
        X = _points(goya, 300, seed=1)
        p = goya.project_points(goya.from_model(X))
        K, dist = s.calibration.to_opencv()
        skew = K[0, 1]
        K[0, 1] = 0.0
        ci, pi = np.nonzero(p.inside)
        errs = []
        for c, i in zip(ci[::7], pi[::7]):
            cam = goya.camera(p.camera_labels[c])
            uv = p.pixels[c, i]
            tau = np.clip((uv[1] - s.height / 2) / (s.height / 2), -1, 1)
            E, _ = cv2.Rodrigues(tau * cam.rolling_shutter.rotation)
            R = E @ cam.R
            C = cam.C + tau * cam.rolling_shutter.translation @ cam.R
            q, _ = cv2.projectPoints(X[i].reshape(1, 1, 3), cv2.Rodrigues(R)[0], -R @ C, K, dist)
            q = q.reshape(2) + 0.5
            q[0] += skew * (q[1] - K[1, 2] - 0.5) / K[1, 1]
            errs.append(np.abs(q - uv).max())
    finally:
        s.calibration, s._r2 = orig, None
    assert len(errs) > 400 and max(errs) < 1e-6


def _brute_force(R, C, rs, cal, w, h, r2, X):
    """Status and pixel by bisection on τ in [−1, 1] (a fine τ grid first: pairs whose validity
    changes across the readout are returned as None)."""
    taus = np.linspace(-1, 1, 41)

    def at(tau):
        E, _ = cv2.Rodrigues(tau * rs.rotation)
        xc = E @ (R @ (X - C) - tau * rs.translation)
        if xc[2] <= 0:
            return "behind", None
        x, y = xc[0] / xc[2], xc[1] / xc[2]
        if x * x + y * y > r2:
            return "far", None
        return "ok", np.array([a[0] for a in cal.project_normalised(np.array([x]), np.array([y]))])

    kinds = {at(t)[0] for t in taus}
    if kinds == {"behind"}:
        return BEHIND, None
    if kinds == {"far"}:
        return OUTSIDE, None
    if kinds != {"ok"}:
        return None, None
    F = lambda t: np.clip((at(t)[1][1] - h / 2) / (h / 2), -1, 1) - t  # noqa: E731 (decreasing)
    lo, hi = -1.0, 1.0
    if F(hi) >= 0:
        lo = hi
    elif F(lo) <= 0:
        hi = lo
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if F(mid) > 0 else (lo, mid)
    uv = at(0.5 * (lo + hi))[1]
    inside = 0 <= uv[0] <= w and 0 <= uv[1] <= h
    return (INSIDE if inside else OUTSIDE), uv


def test_brute_force_rows_statuses_and_the_shortcuts(goya):
    """Points all around a camera (behind it, beside it, near its plane, far off-axis): every
    status and pixel equals a brute-force bisection; the bounds that settle pairs without
    iterating (dense and inside_only) never change a result."""
    cam = goya.camera("DJI_0300.JPG")
    s = goya.sensors["0"]
    rng = np.random.default_rng(7)
    d = rng.normal(size=(1500, 3))
    X = cam.C + d / np.linalg.norm(d, axis=1, keepdims=True) * rng.uniform(0.05, 6.0, (1500, 1))
    rs = cam.rolling_shutter
    args = (X, cam.R[None], cam.C[None], rs.rotation[None], rs.translation[None], s.calibration,
            s.width, s.height, s.r2_limit)
    uv, st = project_block_rs(*args, True, False)
    uv_s, st_s = project_block_rs(*args, True, True)
    assert np.array_equal(st_s[0] == INSIDE, st[0] == INSIDE)
    assert np.array_equal(uv_s[0][st[0] == INSIDE], uv[0][st[0] == INSIDE])
    checked = {INSIDE: 0, OUTSIDE: 0, BEHIND: 0}
    for i in range(len(X)):
        want, q = _brute_force(cam.R, cam.C, rs, s.calibration, s.width, s.height, s.r2_limit, X[i])
        if want is None:
            continue
        assert st[0, i] == want, i
        if q is not None:
            assert np.abs(uv[0, i] - q).max() < 1e-6, i
        checked[want] += 1
    assert min(checked.values()) > 100, checked


def test_cameras_without_motion_are_bit_identical_to_the_global_shutter_model(goya_off):
    """Non-rolling-shutter cameras go through the unchanged global-shutter block."""
    X = _points(goya_off, 200, seed=2)
    cams = goya_off.aligned_cameras[:40]
    p = goya_off.project_points(goya_off.from_model(X), cameras=cams)
    s = goya_off.sensors["0"]
    uv, st = project_block(X, np.array([c.R for c in cams]), np.array([c.C for c in cams]),
                           s.calibration, s.width, s.height, s.r2_limit)
    assert np.array_equal(p.pixels, uv, equal_nan=True) and np.array_equal(p.status, st)


def test_sparse_equals_dense(goya):
    X = _points(goya, 500, seed=4)
    dense = goya.project_points(goya.from_model(X))
    sparse = goya.project_points(goya.from_model(X), inside_only=True)
    ci, pi = np.nonzero(dense.inside)
    assert len(sparse.point) == len(pi) > 1000
    order = np.lexsort((pi, ci))
    order_s = np.lexsort((sparse.point, sparse.camera))
    assert np.array_equal(sparse.camera[order_s], ci[order])
    assert np.array_equal(sparse.pixels[order_s], dense.pixels[ci[order], pi[order]])


def test_rotation_vector_and_motion_validation():
    for w in ([0.0, 0.0, 0.0], [1e-9, -2e-9, 3e-9], [0.01, -0.02, 0.005], [1.0, 2.0, -0.5]):
        M, _ = cv2.Rodrigues(np.array(w))
        assert np.abs(rotation_vector(M) - w).max() < 1e-12
    with pytest.raises(ValueError, match="not finite"):
        RollingShutter(np.array([np.nan, 0, 0]), np.zeros(3))
    assert RollingShutter(np.zeros(3), np.zeros(3)).is_zero


# --- reader: what is applied, what is not, damaged blocks -------------------------------------
def _project_with(psx, tmp_path, edit):
    """A copy of goya_test whose chunk doc.xml is edited by ``edit(text) -> text``."""
    import shutil
    dst = tmp_path / "goya.files"
    shutil.copytree(psx.parent / "goya_test.files", dst, copy_function=shutil.copyfile)
    for p in [dst, *dst.rglob("*")]:
        p.chmod(0o755 if p.is_dir() else 0o644)
    chunk = dst / "0" / "chunk.zip"
    with zipfile.ZipFile(chunk) as z:
        text = z.read("doc.xml").decode()
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        z.writestr("doc.xml", edit(text))
    chunk.write_bytes(buf.getvalue())
    (tmp_path / "goya.psx").write_bytes((psx).read_bytes())
    return open_reconstruction(tmp_path / "goya.psx")


def test_compensation_off_in_the_sensor_ignores_stale_blocks(psx, tmp_path, goya_off):
    for value in ("false", "disabled"):
        sub = tmp_path / value
        sub.mkdir()
        r = _project_with(psx, sub, lambda t: t.replace(
            '<property name="rolling_shutter" value="true"/>',
            f'<property name="rolling_shutter" value="{value}"/>'))
        assert not r.sensors["0"].rolling_shutter and not r.rolling_shutter_cameras
        assert any("compensation is off: not applied" in n for n in r.notes)
        X = _points(goya_off, 50)
        want = goya_off.project_points(goya_off.from_model(X)).pixels
        assert np.array_equal(r.project_points(r.from_model(X)).pixels, want, equal_nan=True)


def test_cameras_without_a_block_keep_one_pose(psx, tmp_path):
    import re

    def drop_first(t):
        return re.sub(r"<rolling_shutter>.*?</rolling_shutter>", "", t, count=1, flags=re.S)
    r = _project_with(psx, tmp_path, drop_first)
    assert r.camera("DJI_0284.JPG").rolling_shutter is None
    assert len(r.rolling_shutter_cameras) == 255
    assert any("1 aligned camera(s) have no (or a zero) motion estimate" in n for n in r.notes)


def test_damaged_block_is_refused_with_the_camera_named(psx, tmp_path):
    def damage(t):
        i = t.index("<rolling_shutter>")
        j = t.index("<rotation>", i) + len("<rotation>")
        return t[:j] + "2" + t[t.index(" ", j):]           # first element 2: not a rotation
    with pytest.raises(InputError, match="camera 'DJI_0284.JPG' is not a rotation matrix"):
        _project_with(psx, tmp_path, damage)
    sub = tmp_path / "nan"
    sub.mkdir()
    with pytest.raises(InputError, match="rolling_shutter><translation> of camera 'DJI_0284.JPG'"):
        _project_with(psx, sub, lambda t: t.replace(
            "<translation>4.9306893030630081e-03", "<translation>nan", 1))
