"""Pix4D reader and camera model on the real pix4d_origin params set (168 DJI FC6310 images)."""
import numpy as np
import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.projection import camera_footprints
from easyidp_toolbox.core.reconstruction import INSIDE
from easyidp_toolbox.core.reconstruction.pix4d import (
    calibration_from_ccp, read_cam_file, read_calibrated_camera_parameters, read_pmatrix)
from easyidp_toolbox.core.roi import open_rois

UTM54 = "EPSG:32654"


@pytest.fixture(scope="module")
def p4(realdata):
    return realdata / "easyidp" / "pix4d_origin"


@pytest.fixture(scope="module")
def params(p4):
    return p4 / "1_initial" / "params"


@pytest.fixture(scope="module")
def recon(p4):
    return open_reconstruction(p4, source_crs=UTM54)


def test_reads_project_folder_params_folder_and_offset(p4, params, recon):
    assert recon.software == "pix4d"
    assert len(recon.cameras) == 168 and len(recon.aligned_cameras) == 168
    assert recon.label == "pix4d.origin"
    assert np.allclose(recon.frame.offset, [368109.0, 3956043.0, 96.0])
    s = next(iter(recon.sensors.values()))
    assert (s.width, s.height) == (5472, 3648)
    assert s.calibration.f == pytest.approx(4470.8971027662546)
    assert s.calibration.cx == pytest.approx(2806.803999853511)
    again = open_reconstruction(params, source_crs=UTM54)
    assert [c.label for c in again.cameras] == [c.label for c in recon.cameras]


def test_pmatrix_equals_krt_for_every_camera(params, recon):
    """pmatrix.txt against the K/R/t of the calibrated camera parameters, every camera.

    The file prints P with 6 decimals, so each element carries up to 5e-7 of rounding; the
    pixel differences must stay inside the bound that rounding allows, and P rebuilt at full
    precision from K/R/t must reproduce our pipeline to 1e-3 px (in fact ~1e-9)."""
    P = read_pmatrix(next(params.glob("*_pmatrix.txt")))
    ccp = read_calibrated_camera_parameters(next(params.glob("*_calibrated_camera_parameters.txt")))
    assert len(P) == len(ccp) == 168
    rng = np.random.default_rng(0)
    file_d, full_d = [], []
    for cam in recon.cameras:
        e = ccp[cam.label]
        P_full = e["K"] @ np.c_[e["R"], -e["R"] @ e["t"]]
        assert np.abs(P[cam.label] - P_full).max() <= 5.0001e-7
        # image points cast to the ground 10–16 m below the camera: the whole frame, corners too
        uv = np.column_stack([rng.uniform(0, 5472, 50), rng.uniform(0, 3648, 50)])
        uv[:4] = [[0.5, 0.5], [5471.5, 0.5], [0.5, 3647.5], [5471.5, 3647.5]]  # corner pixels
        o, d = recon.pixel_to_ray(cam, uv, distortion=False)
        local = o + d * (rng.uniform(10, 16, 50) / -d[:, 2])[:, None]
        proj = recon.project_points(local + recon.frame.offset, cameras=[cam.label],
                                    distortion=False)
        assert (proj.status == INSIDE).all()
        Xh = np.c_[local, np.ones(50)]
        for Pm, store in ((P[cam.label], file_d), (P_full, full_d)):
            h = Xh @ Pm.T
            store.append(np.abs(proj.pixels[0] - h[:, :2] / h[:, 2:]).max(axis=1))
        h = Xh @ P[cam.label].T
        bound = (5e-7 * np.abs(Xh).sum(axis=1)[:, None] * (1 + np.abs(h[:, :2] / h[:, 2:]))) / h[:, 2:]
        assert np.all(file_d[-1][:, None] <= bound.max(axis=1, keepdims=True) + 1e-9)
    file_d, full_d = np.concatenate(file_d), np.concatenate(full_d)
    print(f"\nPix4D pmatrix.txt vs K/R/t: median {np.median(file_d):.1e} px, max {file_d.max():.1e} px "
          f"(6-decimal file); full-precision K[R|-Rt]: max {full_d.max():.1e} px")
    assert full_d.max() < 1e-3
    assert np.median(file_d) < 1e-3 and file_d.max() < 0.02


def test_pmatrix_only_project_matches_ccp_project(params, tmp_path, recon):
    """Without the calibrated camera parameters the pmatrix (RQ) + .cam path gives the same
    distorted pixels."""
    for f in params.iterdir():
        if not f.name.endswith("_calibrated_camera_parameters.txt"):
            (tmp_path / f.name).symlink_to(f)
    only_p = open_reconstruction(tmp_path, source_crs=UTM54)
    pts = np.column_stack([np.linspace(368095, 368125, 40), np.linspace(3956020, 3956060, 40),
                           np.full(40, 96.0)])
    a = recon.project_points(pts, UTM54)
    b = only_p.project_points(pts, UTM54)
    ok = a.status == INSIDE
    assert ok.sum() > 100
    assert np.array_equal(ok, b.status == INSIDE)
    # pmatrix.txt is printed with 6 decimals, so its K, R (RQ) carry ~1e-6 relative noise
    assert np.abs(a.pixels[ok] - b.pixels[ok]).max() < 0.02


def test_cam_file_and_calibrated_parameters_give_same_distortion(params):
    ccp = read_calibrated_camera_parameters(next(params.glob("*_calibrated_camera_parameters.txt")))
    a = calibration_from_ccp(next(iter(ccp.values())))
    b = read_cam_file(next(params.glob("*.cam")), 5472, 3648)
    u, v = np.meshgrid(np.linspace(0, 5472, 25), np.linspace(0, 3648, 19))
    x, y = a.pixel_to_normalised(u.ravel(), v.ravel(), distortion=False)
    ua, va = a.project_normalised(x, y)
    ub, vb = b.project_normalised(x, y)
    d = np.hypot(ua - ub, va - vb).max()
    print(f"\n.cam vs calibrated parameters: max distortion difference {d:.2e} px")
    assert d < 1e-6
    # and the distortion is not trivially zero: several pixels at the corners
    assert np.hypot(ua - u.ravel(), va - v.ravel()).max() > 5


def test_roi_polygons_land_in_expected_photos(p4, recon):
    rois = open_rois(p4 / "roi" / "roi.shp", name_field="id")   # closing vertex dropped
    assert rois.names == ["0", "1", "2"] and [len(r.rings[0]) for r in rois] == [12, 8, 47]
    assert rois.crs.to_epsg() == 32654
    wkt = rois.crs
    ground = 96.0                                    # offset z: the local origin height
    c0 = rois[0].rings[0].mean(axis=0)
    hits = recon.project_points([[c0[0], c0[1], ground]], wkt)
    assert int(hits.inside.sum()) == 17              # count measured independently (SOURCES.md)
    fps = {f.label: f for f in camera_footprints(recon, ground, per_edge=8)}
    for ring in (r.rings[0] for r in rois):
        xyz = np.column_stack([ring, np.full(len(ring), ground)])
        proj = recon.project_points(xyz, wkt)
        full = [lab for lab, ins in zip(proj.camera_labels, proj.inside.all(axis=1)) if ins]
        assert len(full) >= 5
        centroid = ring.mean(axis=0)
        for lab in full:                             # backward and forward agree
            fp = fps[lab].ring[:, :2]
            assert _inside(centroid, fp), lab


def _inside(pt, ring):
    x, y = ring[:, 0], ring[:, 1]
    xj, yj = np.roll(x, 1), np.roll(y, 1)
    cross = ((y > pt[1]) != (yj > pt[1])) & (pt[0] < (xj - x) * (pt[1] - y) / (yj - y + 1e-300) + x)
    return bool(cross.sum() % 2)
