"""OpenSfM / OpenDroneMap reader and the camera models it needs.

Independent truths: the real OpenSfM reconstruction of ``realdata/opensfm_berlin`` and its
feature tracks (made by OpenSfM, not by us); OpenSfM's own formulas transcribed here from its
source (``geometry/camera_*_functions.h``, ``geo.py``, ``features.py``); OpenCV's
``projectPoints`` and ``fisheye.projectPoints``; pyproj for the geodesy of the references.
"""
import json
import shutil

import cv2
import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.reconstruction import Calibration, INSIDE, list_reconstructions
from easyidp_toolbox.core.rotations import rotation_matrix, rotation_vector

BERLIN_SIZE = (3264, 2448)


@pytest.fixture(scope="module")
def berlin(realdata):
    return realdata / "opensfm_berlin"


def _tracks(path):
    """``tracks.csv`` (OPENSFM_TRACKS_VERSION_v2): (image, track id, normalised x, y) rows."""
    lines = path.read_text().splitlines()
    assert lines[0].startswith("OPENSFM_TRACKS_VERSION")
    return [(t[0], t[1], float(t[3]), float(t[4])) for t in (ln.split("\t") for ln in lines[1:] if ln)]


def _opensfm_perspective(X, rvec, t, focal, k1, k2, w, h):
    """OpenSfM's own chain, transcribed: pose, PerspectiveProjection, Disto24, UniformScale
    (normalised coordinates), then ``features.denormalized_image_coordinates`` (OpenCV pixel
    centres) + 0.5 to our corner origin."""
    Xc = X @ rotation_matrix(rvec).T + t
    p = Xc[:, :2] / Xc[:, 2:]
    r2 = (p ** 2).sum(1, keepdims=True)
    n = focal * p * (1 + r2 * (k1 + k2 * r2))
    size = max(w, h)
    return np.column_stack([n[:, 0] * size - 0.5 + w / 2.0, n[:, 1] * size - 0.5 + h / 2.0]) + 0.5


def test_berlin_points_reproduce_the_feature_tracks(berlin):
    """SOURCES.md: the 1,430 points through the 3 shots give the tracks with a median residual of
    0.80 px over 3,082 observations; and the camera model equals OpenSfM's formula to 1e-9 px."""
    recon = open_reconstruction(berlin / "reconstruction_example.json")
    assert recon.software == "opensfm" and recon.crs.to_epsg() == 32633   # UTM zone of Berlin
    assert len(recon.aligned_cameras) == 3 and len(recon.sensors) == 1
    doc = json.loads((berlin / "reconstruction_example.json").read_text())[0]
    ids = list(doc["points"])
    assert len(ids) == 1430
    X = np.array([doc["points"][k]["coordinates"] for k in ids])
    p = recon.project_points(recon.from_model(X, "EPSG:4978"), "EPSG:4978")   # map projection
    row = {k: i for i, k in enumerate(ids)}
    cam = {lab: i for i, lab in enumerate(p.camera_labels)}
    obs = [(img, row[tr], xn, yn) for img, tr, xn, yn in _tracks(berlin / "tracks_example.csv") if tr in row]
    w, h = BERLIN_SIZE
    track_px = np.array([(w / 2 + xn * w, h / 2 + yn * w) for _, _, xn, yn in obs])
    ours = np.array([p.pixels[cam[img], i] for img, i, _, _ in obs])
    res = np.hypot(*(ours - track_px).T)
    print(f"\nBerlin: {len(res)} observations, median residual {np.median(res):.3f} px, "
          f"p90 {np.percentile(res, 90):.2f} px")
    assert len(res) == 3082
    assert np.median(res) == pytest.approx(0.80, abs=0.005)
    # the camera model alone (model frame, no map round trip) is OpenSfM's
    cam_doc = next(iter(doc["cameras"].values()))
    worst = walk = 0.0
    for img, shot in doc["shots"].items():
        mine = _model_pixels(recon, img, X)
        theirs = _opensfm_perspective(X, shot["rotation"], np.array(shot["translation"]),
                                      cam_doc["focal"], cam_doc["k1"], cam_doc["k2"], w, h)
        worst = max(worst, np.abs(mine - theirs).max())
        walk = max(walk, np.nanmax(np.abs(p.for_camera(img)[0] - mine)))
    assert worst < 1e-9
    assert walk < 1e-5                    # through the map CRS (UTM) and back: < 10 µpx


def _model_pixels(recon, label, X):
    """Pixels of model-frame points through one camera, without any map CRS."""
    c = recon.camera(label)
    cal = recon.sensors[c.sensor_id].calibration
    Xc = (X - c.C) @ c.R.T
    return np.column_stack(cal.project_normalised(Xc[:, 0] / Xc[:, 2], Xc[:, 1] / Xc[:, 2]))


def _ecef_from_lla(lat, lon, alt):
    """OpenSfM ``geo.ecef_from_lla`` (WGS 84), transcribed."""
    a2, b2 = 6378137.0 ** 2, 6356752.314245 ** 2
    la, lo = np.radians(lat), np.radians(lon)
    L = 1.0 / np.sqrt(a2 * np.cos(la) ** 2 + b2 * np.sin(la) ** 2)
    return np.array([(a2 * L + alt) * np.cos(la) * np.cos(lo), (a2 * L + alt) * np.cos(la) * np.sin(lo),
                     (b2 * L + alt) * np.sin(la)])


def _ecef_from_topocentric(lat, lon, alt):
    """OpenSfM ``geo.ecef_from_topocentric_transform``, transcribed (4×4)."""
    x, y, z = _ecef_from_lla(lat, lon, alt)
    sa, ca, so, co = np.sin(np.radians(lat)), np.cos(np.radians(lat)), np.sin(np.radians(lon)), np.cos(np.radians(lon))
    return np.array([[-so, -sa * co, ca * co, x], [co, -sa * so, ca * so, y], [0, ca, sa, z], [0, 0, 0, 1]])


def test_berlin_topocentric_frame_is_opensfms(berlin):
    """Topocentric → ECEF with OpenSfM's formulas equals ours (through pyproj) to 1e-6 m; the
    camera centres lie within metres of the photos' GPS positions (what OpenSfM aligned to)."""
    recon = open_reconstruction(berlin / "reconstruction_example.json")
    doc = json.loads((berlin / "reconstruction_example.json").read_text())[0]
    ref = doc["reference_lla"]
    T = _ecef_from_topocentric(ref["latitude"], ref["longitude"], ref["altitude"])
    X = np.array([p["coordinates"] for p in doc["points"].values()])
    theirs = X @ T[:3, :3].T + T[:3, 3]
    ours = recon.from_model(X, "EPSG:4978")
    assert np.abs(ours - theirs).max() < 1e-6
    labels, C = recon.camera_centres(crs="EPSG:4978")
    gps = np.array([doc["shots"][lab]["gps_position"] for lab in labels])
    d = np.linalg.norm(C - (gps @ T[:3, :3].T + T[:3, 3]), axis=1)
    assert d.max() < 15                                  # phone GPS, DOP 5
    # and UTM from pyproj directly
    from pyproj import Transformer
    lon, lat, hh = Transformer.from_crs(4978, 4979, always_xy=True).transform(*theirs[:5].T)
    e, n = Transformer.from_crs(4326, 32633, always_xy=True).transform(lon, lat)
    assert np.abs(recon.from_model(X[:5]) - np.column_stack([e, n, hh])).max() < 1e-6


def test_berlin_ground_control_points_parsed(berlin, tmp_path):
    """``ground_control_points.json`` in the dataset folder becomes markers: pixels from the
    normalised projections, references in the map CRS (pyproj). The example reconstruction was
    not aligned to them (SOURCES.md), so only the parsing is checked."""
    shutil.copy(berlin / "reconstruction_example.json", tmp_path / "reconstruction.json")
    shutil.copy(berlin / "ground_control_points.json", tmp_path)
    recon = open_reconstruction(tmp_path)
    gcp = json.loads((berlin / "ground_control_points.json").read_text())["points"]
    assert [m.label for m in recon.markers] == [p["id"] for p in gcp]
    from pyproj import Transformer
    to_utm = Transformer.from_crs(4979, 32633, always_xy=True)
    w, h = BERLIN_SIZE
    for m, p in zip(recon.markers, gcp):
        if "position" in p:
            pos = p["position"]
            want = to_utm.transform(pos["longitude"], pos["latitude"], pos["altitude"])
            assert np.allclose(m.reference, want, atol=1e-6) and m.reference_enabled
        else:
            assert m.reference is None
        for o in p["observations"]:
            xn, yn = o["projection"]
            assert m.observations[o["shot_id"]] == pytest.approx((w / 2 + w * xn, h / 2 + w * yn))


# --- camera models against OpenCV --------------------------------------------------------------------
CAMERAS = {
    "perspective": {"projection_type": "perspective", "width": 4000, "height": 3000,
                    "focal": 0.85, "k1": -0.11, "k2": 0.04},
    "brown": {"projection_type": "brown", "width": 4000, "height": 3000, "focal_x": 0.851,
              "focal_y": 0.849, "c_x": 0.0031, "c_y": -0.0042, "k1": -0.11, "k2": 0.04,
              "k3": -0.008, "p1": 0.0012, "p2": -0.0007},
    "radial": {"projection_type": "radial", "width": 3000, "height": 4000, "focal_x": 0.7,
               "focal_y": 0.702, "c_x": -0.002, "c_y": 0.001, "k1": -0.05, "k2": 0.01},
    "simple_radial": {"projection_type": "simple_radial", "width": 1920, "height": 1080,
                      "focal_x": 0.9, "focal_y": 0.9, "c_x": 0.0, "c_y": 0.01, "k1": -0.02},
    "fisheye": {"projection_type": "fisheye", "width": 2000, "height": 1500, "focal": 0.5,
                "k1": 0.02, "k2": -0.004},
    "fisheye_opencv": {"projection_type": "fisheye_opencv", "width": 2000, "height": 1500,
                       "focal_x": 0.501, "focal_y": 0.499, "c_x": 0.004, "c_y": -0.003,
                       "k1": 0.02, "k2": -0.004, "k3": 0.001, "k4": -0.0002},
}
REF = {"latitude": 35.73, "longitude": 139.0, "altitude": 0.0}


def _dataset(folder, cameras, n_shots=4, seed=0, extra=None):
    """A minimal OpenSfM dataset: cameras, shots looking down at the origin from ~30 m."""
    rng = np.random.default_rng(seed)
    shots = {}
    keys = list(cameras)
    for i in range(n_shots):
        C = np.array([rng.uniform(-20, 20), rng.uniform(-20, 20), 30 + rng.uniform(-2, 2)])
        R = rotation_matrix(rng.normal(0, 0.05, 3)) @ np.diag([1.0, -1.0, -1.0])
        shots[f"IMG_{i:04d}.JPG"] = {"rotation": rotation_vector(R).tolist(),
                                     "translation": (-R @ C).tolist(), "camera": keys[i % len(keys)]}
    rec = dict({"cameras": cameras, "shots": shots, "points": {}, "reference_lla": REF}, **(extra or {}))
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "reconstruction.json").write_text(json.dumps([rec]))
    return folder / "reconstruction.json"


@pytest.mark.parametrize("ptype", list(CAMERAS))
def test_camera_models_against_opencv_and_round_trip(ptype, tmp_path):
    """Each supported projection type, read from JSON, against cv2.projectPoints (pinhole types)
    or cv2.fisheye.projectPoints (fisheye types) to 1e-6 px; pixel → ray → pixel to 1e-6 px
    (in the model frame); through the map CRS and back (UTM, pyproj) to 1e-5 px."""
    recon = open_reconstruction(_dataset(tmp_path, {"cam": CAMERAS[ptype]}, n_shots=1))
    cam = recon.aligned_cameras[0]
    s = recon.sensors["cam"]
    cal = s.calibration
    c = CAMERAS[ptype]
    w, h = c["width"], c["height"]
    size = max(w, h)
    fx = c.get("focal_x", c.get("focal")) * size
    fy = c.get("focal_y", c.get("focal")) * size
    K = np.array([[fx, 0, w / 2 + c.get("c_x", 0) * size - 0.5],
                  [0, fy, h / 2 + c.get("c_y", 0) * size - 0.5], [0, 0, 1.0]])
    rng = np.random.default_rng(1)
    uv = np.column_stack([rng.uniform(0, w, 300), rng.uniform(0, h, 300)])
    o, d = recon.pixel_to_ray(cam, uv)
    X = o + d * rng.uniform(5, 40, (len(uv), 1))
    ours = _model_pixels(recon, cam.label, X)
    Xc = (X - cam.C) @ cam.R.T
    mapped = recon.project_points(recon.from_model(X), cameras=[cam.label])
    if "fisheye" in ptype:
        D = np.array([c.get(k, 0.0) for k in ("k1", "k2", "k3", "k4")])
        cv, _ = cv2.fisheye.projectPoints(Xc.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    else:
        D = np.array([c.get("k1", 0.0), c.get("k2", 0.0), c.get("p1", 0.0), c.get("p2", 0.0),
                      c.get("k3", 0.0)])                  # OpenSfM p1, p2 are OpenCV's
        cv, _ = cv2.projectPoints(Xc.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D)
    cv = cv.reshape(-1, 2) + 0.5                          # OpenCV centres at integers → ours
    err_cv = np.abs(ours - cv).max()
    err_rt = np.abs(ours - uv).max()
    print(f"\n{ptype}: OpenCV {err_cv:.1e} px, round trip {err_rt:.1e} px")
    assert err_cv < 1e-6 and err_rt < 1e-6
    assert np.abs(mapped.pixels[0] - uv).max() < 1e-5 and (mapped.status[0] == INSIDE).all()
    assert cal.model == ("fisheye" if "fisheye" in ptype else "brown")
    assert s.type == ("fisheye" if "fisheye" in ptype else "frame")
    K2, D2 = cal.to_opencv()
    assert np.allclose(K2, K) and np.allclose(D2, D)


def test_fisheye_model_wide_angles_and_limits():
    """The fisheye branch: OpenCV agreement out to 85° off the axis, with skew (alpha); rays
    beyond 90° have no pixel; the valid radius stops before the polynomial folds back."""
    cal = Calibration(f=500, cx=1000.2, cy=751.3, b1=1.5, b2=0.3, k1=0.05, k2=-0.02, k3=0.004,
                      k4=-0.0005, model="fisheye")
    th = np.radians(np.linspace(0, 85, 50))
    ph = np.linspace(0, 2 * np.pi, 50)
    X = np.column_stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
    u, v = cal.project_normalised(X[:, 0] / X[:, 2], X[:, 1] / X[:, 2])
    K, D = cal.to_opencv()
    alpha = K[0, 1] / K[0, 0]
    K[0, 1] = 0.0
    cv, _ = cv2.fisheye.projectPoints(X.reshape(-1, 1, 3), np.zeros(3), np.zeros(3), K, D, alpha=alpha)
    assert np.abs(cv.reshape(-1, 2) + 0.5 - np.column_stack([u, v])).max() < 1e-6
    x, y = cal.pixel_to_normalised(u, v)
    u2, v2 = cal.project_normalised(x, y)
    assert np.abs(np.column_stack([u2 - u, v2 - v])).max() < 1e-6
    far = cal.pixel_to_normalised(np.array([cal.cx + cal.f * 1.7]), np.array([cal.cy]))[0]
    assert np.isnan(far).all()                            # θ > 90°: no ray in front
    assert not Calibration(f=500, cx=0, cy=0).has_distortion
    assert Calibration(f=500, cx=0, cy=0, model="fisheye").has_distortion
    bent = Calibration(f=2000, cx=1000, cy=750, k1=-0.3, model="fisheye")
    r2 = bent.valid_radius2(2000, 1500)                   # θ(1 − 0.3θ²) peaks at θ = 1/√0.9
    assert np.arctan(np.sqrt(r2)) == pytest.approx(np.sqrt(1 / 0.9), abs=2e-3)
    plain = Calibration(f=2000, cx=1000, cy=750, model="fisheye")
    assert np.degrees(np.arctan(np.sqrt(plain.valid_radius2(2000, 1500)))) == pytest.approx(
        1.5 * np.degrees(1250 / 2000))                    # 1.5 × the corner angle
    with pytest.raises(ValueError, match="lens model"):
        Calibration(f=500, cx=0, cy=0, model="spherical")
    with pytest.raises(ValueError, match="fisheye"):
        Calibration(f=500, cx=0, cy=0, p1=0.001, model="fisheye").to_opencv()


def test_rotation_vectors_against_opencv():
    rng = np.random.default_rng(3)
    vecs = [rng.normal(0, 1, 3) for _ in range(50)] + [np.array([np.pi, 0, 0]),
                                                        np.array([0, 1e-9, 0]), np.zeros(3),
                                                        np.array([0.0, 2.0, 2.0]) * (np.pi - 1e-7) / np.sqrt(8)]
    for v in vecs:
        R = rotation_matrix(v)
        assert np.allclose(R, cv2.Rodrigues(v)[0], atol=1e-12)
        assert np.allclose(rotation_matrix(rotation_vector(R)), R, atol=1e-12)


# --- partial models, photos, unaligned ------------------------------------------------------------------
def test_partial_models_default_to_the_largest(tmp_path):
    recs = []
    for i, n in enumerate((1, 3, 2)):
        f = _dataset(tmp_path / f"r{i}", {"cam": CAMERAS["brown"]}, n_shots=n, seed=i)
        rec = json.loads(f.read_text())[0]
        rec["shots"] = {f"r{i}_{k}": v for k, v in rec["shots"].items()}
        recs.append(rec)
    ds = tmp_path / "dataset"
    (ds / "images").mkdir(parents=True)
    (ds / "reconstruction.json").write_text(json.dumps(recs))
    for name in ["r1_IMG_0000.JPG", "lost.JPG", "notes.txt"]:
        (ds / "images" / name).write_bytes(b"x")
    recon = open_reconstruction(ds)
    assert recon.label == "reconstruction 1 of 3" and len(recon.aligned_cameras) == 3
    assert any("using #1, the largest" in n for n in recon.notes)
    assert len(recon.unaligned_cameras) == 3              # the shots of the other two models
    assert recon.camera("r1_IMG_0000.JPG").photo_path == str(ds / "images" / "r1_IMG_0000.JPG")
    assert any("1 photo(s)" in n and "lost.JPG" in n for n in recon.notes)
    two = open_reconstruction(ds, chunk="2")
    assert [c.label for c in two.aligned_cameras] == ["r2_IMG_0000.JPG", "r2_IMG_0001.JPG"]
    assert open_reconstruction(ds, chunk="#0").aligned_cameras[0].label == "r0_IMG_0000.JPG"
    assert [r["photos"] for r in list_reconstructions(ds)] == [1, 3, 2]
    with pytest.raises(InputError, match=r"no reconstruction #5: it holds 3 \(#0: 1 photos, #1: 3"):
        open_reconstruction(ds, chunk=5)
    with pytest.raises(InputError, match="give the index of a reconstruction"):
        open_reconstruction(ds, chunk="Chunk 1")


def test_not_georeferenced_dataset_is_local(tmp_path):
    f = _dataset(tmp_path, {"cam": CAMERAS["perspective"]})
    rec = json.loads(f.read_text())
    rec[0]["reference_lla"] = {"latitude": 0.0, "longitude": 0.0, "altitude": 0.0}
    f.write_text(json.dumps(rec))
    recon = open_reconstruction(f)
    assert recon.is_local and "local" in recon.crs.name
    assert any("not georeferenced" in n for n in recon.notes)
    X = np.array([[1.0, 2.0, 3.0]])
    assert np.array_equal(recon.from_model(X), X)
    with pytest.raises(InputError, match="not georeferenced.*EPSG:32654|not georeferenced"):
        open_reconstruction(f, source_crs="EPSG:32654")


def test_map_crs_can_be_chosen_for_a_plain_dataset(tmp_path):
    f = _dataset(tmp_path, {"cam": CAMERAS["brown"]})
    a = open_reconstruction(f)
    b = open_reconstruction(f, source_crs="EPSG:6677")            # JGD2011 / Japan Plane IX
    assert a.crs.to_epsg() == 32654 and b.crs.to_epsg() == 6677
    X = np.array([[3.0, -4.0, 1.5], [-10.0, 7.0, 0.2]])
    assert np.abs(a.to_model(b.from_model(X), b.crs) - X).max() < 1e-6


# --- bad input ----------------------------------------------------------------------------------------
def test_odm_folder_without_reconstruction(tmp_path):
    (tmp_path / "images").mkdir()
    (tmp_path / "opensfm").mkdir()
    (tmp_path / "odm_orthophoto").mkdir()
    with pytest.raises(InputError, match=r"opensfm/reconstruction\.json is missing\. The ODM run may "
                                         r"have failed or been stopped before its OpenSfM"):
        open_reconstruction(tmp_path)


def test_split_merge_project_names_its_submodels(tmp_path):
    """ODM's split-merge layout: no merged reconstruction at the top, one per submodel. The
    error says so and names a folder that opens."""
    (tmp_path / "opensfm").mkdir()
    (tmp_path / "odm_orthophoto").mkdir()
    for k in range(3):
        sub = tmp_path / "submodels" / f"submodel_{k:04d}"
        (sub / "images").mkdir(parents=True)
        _dataset(sub / "opensfm", {"cam": CAMERAS["brown"]}, seed=k)
    with pytest.raises(InputError, match=r"split-merge ODM project: its cameras are in 3 "
                                         r"submodels \(submodels/submodel_0000 … submodel_0002\)"):
        open_reconstruction(tmp_path)
    recon = open_reconstruction(tmp_path / "submodels" / "submodel_0000")
    assert len(recon.aligned_cameras) == 4


def test_empty_and_damaged_files(tmp_path):
    f = tmp_path / "reconstruction.json"
    f.write_text("[]")
    with pytest.raises(InputError, match=r"reconstruction\.json: the file holds no reconstruction"):
        open_reconstruction(f)
    f.write_text('[{"cameras": {}, "shots": {}')
    with pytest.raises(InputError, match="not a readable JSON OpenSfM reconstruction file"):
        open_reconstruction(f)
    f.write_text('{"type": "FeatureCollection"}')
    with pytest.raises(InputError, match="not an OpenSfM reconstruction file"):
        open_reconstruction(f)
    f.write_text(json.dumps([{"cameras": {"c": CAMERAS["brown"]}, "shots": {}}]))
    with pytest.raises(InputError, match="has no photos"):
        open_reconstruction(f)


@pytest.mark.parametrize("ptype", ["spherical", "equirectangular", "dual", "fisheye624", "pinhole_x"])
def test_unknown_or_unsupported_projection_type(ptype, tmp_path):
    cam = dict(CAMERAS["perspective"], projection_type=ptype)
    f = _dataset(tmp_path, {"cam": cam})
    with pytest.raises(InputError, match=rf"camera 'cam' uses the OpenSfM projection type '{ptype}'"):
        open_reconstruction(f)


def test_shot_camera_missing_and_bad_pose(tmp_path):
    f = _dataset(tmp_path, {"cam": CAMERAS["brown"]})
    rec = json.loads(f.read_text())
    rec[0]["shots"]["IMG_0001.JPG"]["camera"] = "gone"
    f.write_text(json.dumps(rec))
    with pytest.raises(InputError, match=r"shot 'IMG_0001\.JPG' uses camera 'gone', which "
                                         r"reconstruction #0 does not define \(cameras: cam\)"):
        open_reconstruction(f)
    rec[0]["shots"]["IMG_0001.JPG"]["camera"] = "cam"
    del rec[0]["shots"]["IMG_0002.JPG"]["translation"]
    f.write_text(json.dumps(rec))
    with pytest.raises(InputError, match=r"shot 'IMG_0002\.JPG' has no 'translation'"):
        open_reconstruction(f)
    rec[0]["shots"]["IMG_0002.JPG"]["translation"] = [1, 2]
    f.write_text(json.dumps(rec))
    with pytest.raises(InputError, match=r"pose of shot 'IMG_0002\.JPG' should be two vectors"):
        open_reconstruction(f)
    rec[0]["shots"]["IMG_0002.JPG"]["translation"] = [1, 2, 3]
    del rec[0]["cameras"]["cam"]["focal_y"]
    f.write_text(json.dumps(rec))
    with pytest.raises(InputError, match=r"camera 'cam': 'focal_y' is missing"):
        open_reconstruction(f)


def test_undistorted_reconstruction_refused(tmp_path):
    f = _dataset(tmp_path / "opensfm" / "undistorted", {"cam": CAMERAS["perspective"]})
    with pytest.raises(InputError, match="undistorted.*Give opensfm/reconstruction.json"):
        open_reconstruction(f)


def test_odm_crs_conflict_and_bad_coords_file(tmp_path):
    _dataset(tmp_path / "opensfm", {"cam": CAMERAS["brown"]})
    geo = tmp_path / "odm_georeferencing"
    geo.mkdir()
    (geo / "coords.txt").write_text("WGS84 UTM 54N\n319830 3956030\n")
    recon = open_reconstruction(tmp_path)
    assert recon.software == "odm" and recon.crs.to_epsg() == 32654
    # the name of EPSG:6677 is PROJ's: JGD2011 in Debian 12 and 13, JGD2024 in sid's newer EPSG data
    with pytest.raises(InputError, match=r"georeferenced in WGS 84 / UTM zone 54N.*do not pass "
                                         r"another project CRS \(JGD20(11|24) / Japan Plane"):
        open_reconstruction(tmp_path, source_crs="EPSG:6677")
    (geo / "coords.txt").write_text("NAD27 somewhere\n1 2\n")
    with pytest.raises(InputError, match=r"coords\.txt: the first line 'NAD27 somewhere' is not a CRS"):
        open_reconstruction(tmp_path)
    (geo / "coords.txt").write_text("EPSG:32654\nabc def\n")
    with pytest.raises(InputError, match=r"coords\.txt, line 2: expected the east and north offsets"):
        open_reconstruction(tmp_path)


def test_geocoords_export_without_its_crs_is_refused(tmp_path):
    f = _dataset(tmp_path, {"cam": CAMERAS["brown"]})
    f.rename(tmp_path / "reconstruction.geocoords.json")
    with pytest.raises(InputError, match=r"export to map coordinates.*Give reconstruction\.json"):
        open_reconstruction(tmp_path / "reconstruction.geocoords.json")


def test_not_a_project(tmp_path):
    (tmp_path / "x.json").write_text(json.dumps({"a": 1}))
    with pytest.raises(InputError, match="not an OpenSfM reconstruction file"):
        open_reconstruction(tmp_path / "x.json")
    with pytest.raises(InputError, match="not found"):
        open_reconstruction(tmp_path / "opensfm" / "reconstruction.json")
