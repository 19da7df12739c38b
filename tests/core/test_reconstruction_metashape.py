"""Metashape readers on the real wheat_tanashi and goya_test projects."""
import numpy as np
import pytest

from easyidp_toolbox.core import Reconstruction, open_reconstruction
from easyidp_toolbox.core.reconstruction import BEHIND, INSIDE, list_chunks


@pytest.fixture(scope="module")
def ms(realdata):
    return realdata / "easyidp" / "metashape"


@pytest.fixture(scope="module")
def wheat(ms) -> Reconstruction:
    return open_reconstruction(ms / "wheat_tanashi.psx")


@pytest.fixture(scope="module")
def goya(ms) -> Reconstruction:
    return open_reconstruction(ms / "goya_test.psx")


def test_wheat_reads_chunk_crs_sensor_cameras(ms, wheat):
    assert wheat.label == "Chunk 1" and wheat.enabled
    assert wheat.crs.to_epsg() == 4326 and not wheat.is_local
    assert len(wheat.cameras) == 138 and len(wheat.aligned_cameras) == 138
    s = wheat.sensors["0"]
    assert (s.width, s.height) == (4608, 3456)
    assert s.calibration.cx == pytest.approx(2304 + 48.037918055786299)
    assert s.calibration.cy == pytest.approx(1728 - 73.278107967250861)
    cam = wheat.camera("DJI_0001")
    assert cam.photo_path.endswith("wheat_tanashi_kato3N_20190314_Ins1RGB_30m/DJI_0001.JPG")
    # R is a proper rotation
    assert np.allclose(cam.R @ cam.R.T, np.eye(3), atol=1e-9) and np.linalg.det(cam.R) > 0
    assert list_chunks(ms / "wheat_tanashi.psx")[0]["label"] == "Chunk 1"
    # chunk selection by id and by label
    assert open_reconstruction(ms / "wheat_tanashi.psx", chunk=0).label == "Chunk 1"
    assert open_reconstruction(ms / "wheat_tanashi.psx", chunk="Chunk 1").label == "Chunk 1"


def test_wheat_camera_centres_match_their_gnss_references(ms, wheat):
    """Centres in lon/lat/h lie within the DJI GNSS accuracy of the <reference> of each camera."""
    import xml.etree.ElementTree as ET
    import zipfile
    with zipfile.ZipFile(ms / "wheat_tanashi.files" / "0" / "chunk.zip") as z:
        root = ET.fromstring(z.read("doc.xml"))
    ref = {c.get("label"): [float(c.find("reference").get(k)) for k in "xyz"]
           for c in root.find("cameras").iter("camera")}
    labels, centres = wheat.camera_centres("EPSG:4326")
    r = np.array([ref[lab] for lab in labels])
    dy = (centres[:, 1] - r[:, 1]) * 111e3
    dx = (centres[:, 0] - r[:, 0]) * 111e3 * np.cos(np.radians(35.74))
    assert np.median(np.hypot(dx, dy)) < 5.0          # metres (sxy = 10 m in the project)
    assert np.median(np.abs(centres[:, 2] - r[:, 2])) < 10.0


def test_wheat_markers_reproduce_metashape_observations(wheat):
    """Projecting the six GCP references (WGS 84 lon/lat/ellipsoidal h) reproduces the pixel
    positions placed by hand in Metashape (frame.zip) within a few pixels."""
    errs = []
    assert len(wheat.markers) == 6
    for m in wheat.markers:
        assert m.reference is not None and m.observations
        p = wheat.project_points(m.reference[None], "EPSG:4326", cameras=list(m.observations))
        assert (p.status == INSIDE).all()
        for lab, uv in m.observations.items():
            q, _ = p.for_camera(lab)
            errs.append(np.hypot(*(q[0] - uv)))
    errs = np.array(errs)
    print(f"\nwheat_tanashi markers: {len(errs)} observations, median {np.median(errs):.2f} px, "
          f"max {errs.max():.2f} px")
    assert len(errs) == 23
    assert np.median(errs) < 8.0 and errs.max() < 15.0
    # the same points in UTM 54N give the same pixels (CRS conversion is part of the path)
    m = wheat.markers[0]
    from pyproj import Transformer
    e, n = Transformer.from_crs(4326, 32654, always_xy=True).transform(*m.reference[:2])
    a = wheat.project_points(m.reference[None], "EPSG:4326", cameras=list(m.observations))
    b = wheat.project_points([[e, n, m.reference[2]]], "EPSG:32654", cameras=list(m.observations))
    assert np.abs(a.pixels - b.pixels).max() < 1e-4


def test_wheat_behind_camera_flag_comes_before_bounds(wheat):
    cam = wheat.camera("DJI_0001")
    ahead = cam.C + 20.0 * cam.R[2]                    # on the optical axis, in front
    behind = cam.C - 20.0 * cam.R[2]                   # mirror point: would land at the centre
    pts = wheat.from_model(np.array([ahead, behind]))
    p = wheat.project_points(pts, cameras=["DJI_0001"], distortion=False)
    assert p.status[0].tolist() == [INSIDE, BEHIND]
    assert np.isnan(p.pixels[0, 1]).all()
    s = wheat.sensors[cam.sensor_id].calibration
    assert np.allclose(p.pixels[0, 0], [s.cx, s.cy], atol=1e-6)


def test_wheat_sparse_equals_dense(wheat):
    rng = np.random.default_rng(1)
    m = np.array([mk.reference for mk in wheat.markers])
    pts = np.repeat(m, 50, axis=0) + np.column_stack([rng.normal(0, 1e-4, 300), rng.normal(0, 1e-4, 300),
                                                       rng.normal(0, 0.5, 300)])
    dense = wheat.project_points(pts, "EPSG:4326")
    sparse = wheat.project_points(pts, "EPSG:4326", inside_only=True)
    ci, pi = np.nonzero(dense.inside)
    assert len(sparse.point) == len(pi) > 0
    order = np.lexsort((pi, ci))
    order_s = np.lexsort((sparse.point, sparse.camera))
    assert np.array_equal(sparse.camera[order_s], ci[order])
    assert np.allclose(sparse.pixels[order_s], dense.pixels[ci[order], pi[order]])
    assert sparse.counts().sum() == len(pi)


def test_goya_local_crs_b1_b2_k4_unaligned_rolling_shutter(goya):
    assert goya.is_local and goya.crs is not None and "Local" in goya.crs.name
    cal = goya.sensors["0"].calibration
    assert cal.b1 == pytest.approx(2.1663197269770209) and cal.b2 == pytest.approx(1.3172242107907306)
    assert cal.k4 == pytest.approx(-0.042086840510821462)
    assert goya.sensors["0"].rolling_shutter
    assert len(goya.cameras) == 259
    assert sorted(c.label for c in goya.unaligned_cameras) == ["DJI_0538.JPG", "DJI_0539.JPG",
                                                              "DJI_0540.JPG"]
    assert any("not aligned" in n for n in goya.notes)
    assert any("rolling" in n for n in goya.notes)
    # projection works in local coordinates; map CRSs are refused clearly
    p = goya.project_points([[9.3, 0.8, 2.58]])
    assert p.inside.sum() > 5
    with pytest.raises(Exception, match="local coordinate system"):
        goya.project_points([[139.5, 35.7, 10.0]], "EPSG:4326")
    with pytest.raises(Exception, match="not aligned"):
        goya.project_points([[9.3, 0.8, 2.58]], cameras=["DJI_0538.JPG"])


def test_goya_marker_triangulation_is_consistent(goya):
    """Markers triangulated from their pinned observations reproject onto them: checks the
    b1/b2/k4 model, its inverse, the rolling-shutter poses and the local chunk transform (scale
    bar 90–92 = 14.85 m). test_rolling_shutter.py has the residuals with and without."""
    pos, res = {}, []
    for m in goya.markers:
        obs = {k: v for k, v in m.observations.items() if goya.camera(k).aligned}
        if len(obs) < 2:
            continue
        A, b = np.zeros((3, 3)), np.zeros(3)
        for lab, uv in obs.items():
            o, d = goya.pixel_to_ray(lab, [uv])
            P = np.eye(3) - np.outer(d[0], d[0])
            A += P
            b += P @ np.broadcast_to(o, d.shape)[0]
        X = np.linalg.solve(A, b)
        pos[m.label] = X
        p = goya.project_points(X[None], cameras=list(obs))
        res += [np.hypot(*(p.for_camera(lab)[0][0] - uv)) for lab, uv in obs.items()]
    res = np.array(res)
    print(f"\ngoya_test marker triangulation residuals: median {np.median(res):.2f} px, "
          f"max {res.max():.2f} px over {len(res)} observations")
    assert len(res) > 150 and np.median(res) < 1.0
    assert np.linalg.norm(pos["target 90"] - pos["target 92"]) == pytest.approx(14.85, abs=0.02)
