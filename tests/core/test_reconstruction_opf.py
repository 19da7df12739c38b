"""Open Photogrammetry Format projects (PIX4Dmatic): ``open_reconstruction`` on a ``project.opf``.

Kinds of check, said per test:
- OpenCV: ``cv2.projectPoints`` with the pose built in the test from OPF's own definition
  (R_x(ω)R_y(φ)R_z(κ) from the image's right-top-back frame, then flipping y and z, as pyopf's
  ``examples/compute_reprojection_error.py`` does) and the OPF coefficients in OpenCV's order
  (k1, k2, T1, T2, k3: OPF's tangential formula is OpenCV's), on an OPF written here from known
  parameters and on the demo survey's OPF project read as plain JSON;
- brute force written in the test: Pix4D's fisheye formula, evaluated directly;
- the demo survey's truth (its poses, written before this reader existed), through back
  projection of the plots, its pixels by ``tests/support/independent_camera.py`` (independent); OPF holds one focal length, so the demo camera's affinity b1 is
  mapped out of the truth exactly (u → cx + (u − cx)·f/(f + b1));
- bad input: each damaged or incomplete project names the file and says what to do.
Needs pyopf (installed in both test environments).
"""
import json
import math
import shutil
import sys
from pathlib import Path

import cv2  # OpenCV: the independent reference
import numpy as np
import pytest
import pyopf  # noqa: F401 (required in both test environments: requirements/qgis.txt, current.txt)

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.demo.flight import make_camera
from easyidp_toolbox.core.projection import back_project
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.tests.support import independent_camera
from easyidp_toolbox.core.reconstruction import INSIDE
from easyidp_toolbox.core.roi import read_geojson

NO_DENSIFY = 1e12


def _opk(angles_deg):
    """R_x(ω)R_y(φ)R_z(κ), written out here (OPF specification, input cameras)."""
    o, p, k = np.radians(angles_deg)
    rx = np.array([[1, 0, 0], [0, np.cos(o), -np.sin(o)], [0, np.sin(o), np.cos(o)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(k), -np.sin(k), 0], [np.sin(k), np.cos(k), 0], [0, 0, 1]])
    return rx @ ry @ rz


def _opencv_pixels(points_canonical, position, angles_deg, internals):
    """OpenCV's projection of processing-CRS points for one OPF camera (perspective)."""
    pose = np.eye(4)
    pose[:3, :3] = _opk(angles_deg)
    pose[:3, 3] = position
    pose = pose @ np.diag([1.0, -1.0, -1.0, 1.0])      # right-bottom-front (OpenCV) camera
    world_to_cam = np.linalg.inv(pose)
    rvec, _ = cv2.Rodrigues(world_to_cam[:3, :3])
    K = np.array([[internals["focal_length_px"], 0, internals["principal_point_px"][0]],
                  [0, internals["focal_length_px"], internals["principal_point_px"][1]],
                  [0, 0, 1]])
    k1, k2, k3 = internals["radial_distortion"]
    t1, t2 = internals["tangential_distortion"]
    uv, _ = cv2.projectPoints(np.asarray(points_canonical, np.float64).reshape(-1, 1, 3), rvec,
                              world_to_cam[:3, 3], K, np.array([k1, k2, t1, t2, k3]))
    return uv.reshape(-1, 2)


def write_opf(folder: Path, sensors, cameras, crs="EPSG:32654", shift=(0, 0, 0),
              scale=(1, 1, 1), swap_xy=False, photos=None):
    """A minimal OPF project written per the specification (not through our demo writer).
    ``sensors``: {id: (width, height, internals)}; ``cameras``: [(id, sensor id, position,
    angles)]."""
    folder.mkdir(parents=True, exist_ok=True)
    fmt = "application/opf-{}+json"
    photos = photos or {c[0]: f"images/IMG_{c[0]:04d}.JPG" for c in cameras}
    docs = {
        "cameras.json": {"format": fmt.format("camera-list"), "version": "1.0",
                         "cameras": [{"id": i, "uri": u} for i, u in photos.items()]},
        "input_cameras.json": {
            "format": fmt.format("input-cameras"), "version": "1.0",
            "sensors": [{"id": sid, "name": f"cam{sid}", "bands": [{"name": "Gray", "weight": 1.0}],
                         "image_size_px": [w, h], "pixel_size_um": 2.4, "internals": internals,
                         "shutter_type": "global"} for sid, (w, h, internals) in sensors.items()],
            "captures": [{"id": cid, "reference_camera_id": cid, "rig_model_source": "not_applicable",
                          "time": "2024-06-01T10:00:00",
                          "cameras": [{"id": cid, "sensor_id": sid, "model_source": "user",
                                       "pixel_type": "uint8", "pixel_range": {"min": 0, "max": 255}}]}
                         for cid, sid, _, _ in cameras]},
        "srf.json": {"format": fmt.format("scene-reference-frame"), "version": "1.0",
                     "crs": {"definition": crs},
                     "base_to_canonical": {"shift": list(shift), "scale": list(scale),
                                           "swap_xy": swap_xy}},
        "calib/calibrated_cameras.json": {
            "format": fmt.format("calibrated-cameras"), "version": "1.0",
            "sensors": [{"id": sid, "internals": internals} for sid, (_, _, internals) in sensors.items()],
            "cameras": [{"id": cid, "sensor_id": sid, "position": list(pos), "orientation_deg": list(ang)}
                        for cid, sid, pos, ang in cameras]},
    }
    ids = {"camera_list": "0bc95642-e37f-46df-a2c6-3ddd65881807",
           "input_cameras": "57608ca8-912d-4fee-b097-2648651474c4",
           "scene_reference_frame": "83291b5e-d239-4d94-93fb-226f70d7cd3c",
           "calibration": "54b313cf-9a5d-4bd7-8f51-b06577dedad1"}

    def item(kind, uri, res_format, sources=()):
        return {"id": ids[kind], "type": kind, "resources": [{"uri": uri, "format": fmt.format(res_format)}],
                "sources": [{"id": ids[s], "type": s} for s in sources]}
    docs["project.opf"] = {
        "format": fmt.format("project"), "version": "1.0", "id": "caa7754e-90dc-11ec-b909-0242ac120002",
        "name": "written in the test", "description": "",
        "items": [item("camera_list", "cameras.json", "camera-list"),
                  item("input_cameras", "input_cameras.json", "input-cameras", ("camera_list",)),
                  item("scene_reference_frame", "srf.json", "scene-reference-frame"),
                  item("calibration", "calib/calibrated_cameras.json", "calibrated-cameras",
                       ("input_cameras", "scene_reference_frame"))]}
    for name, doc in docs.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(json.dumps(doc, indent=1))
    return folder / "project.opf"


PERSPECTIVE = {"type": "perspective", "principal_point_px": [2012.7, 1490.3],
               "focal_length_px": 3200.5, "radial_distortion": [-0.081, 0.052, -0.013],
               "tangential_distortion": [0.0011, -0.0007]}
CAMERAS = [(11, 5, (12.0, -3.5, 80.2), (3.1, -2.4, 37.0)),
           (12, 5, (30.5, 4.0, 79.1), (-1.7, 4.2, -141.0)),
           (13, 5, (-8.0, 10.0, 81.0), (12.0, -8.0, 95.0))]


def _ground(n=400, seed=3):
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(-40, 60, n), rng.uniform(-40, 50, n), rng.uniform(-2, 6, n)])


def test_known_parameters_against_opencv(tmp_path):
    """OpenCV check: an OPF written in the test (UTM, shifted canonical frame) projects points
    as cv2.projectPoints does from OPF's definitions, to 1e-6 px; pixel → ray → pixel agrees."""
    shift = np.array([-500123.0, -3900456.0, -35.0])
    opf = write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, shift=shift)
    recon = open_reconstruction(opf)
    assert recon.software == "opf" and recon.crs.to_epsg() == 32654
    assert len(recon.aligned_cameras) == 3 and recon.cameras[0].label == "IMG_0011.JPG"
    assert recon.cameras[0].photo_path == str((tmp_path / "p" / "images" / "IMG_0011.JPG").resolve())
    canonical = _ground()
    p = recon.project_points(canonical - shift, "EPSG:32654")      # map = canonical − shift
    checked = 0
    for i, (cid, _, pos, ang) in enumerate(CAMERAS):
        cv = _opencv_pixels(canonical, pos, ang, PERSPECTIVE)
        inside = p.status[i] == INSIDE
        assert inside.sum() > 20
        assert np.abs(p.pixels[i][inside] - cv[inside]).max() < 1e-6
        back = recon.pixel_to_ray(recon.cameras[i].label, cv[inside])
        d = canonical[inside] - np.asarray(pos)
        cos = np.sum(back[1] * d, axis=1) / np.linalg.norm(d, axis=1)
        assert np.all(cos > 1 - 1e-12)
        checked += inside.sum()
    assert np.allclose(recon.camera_centres("EPSG:32654")[1], np.array([c[2] for c in CAMERAS]) - shift)
    print(f"\nOPF written from known parameters vs cv2.projectPoints: {checked} pixels, < 1e-6 px")


def test_scale_and_swapped_axes_of_the_scene_reference_frame(tmp_path):
    """Truth by construction: a northing-first CRS (EPSG:3006 is N, E) with swap_xy and a
    vertical scale: canonical = swap(scale · base) + shift, so (E, N, h) map points land where
    the canonical points do."""
    scale, shift = np.array([1.0, 1.0, 0.5]), np.array([-600000.0, -6500000.0, -10.0])
    opf = write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, crs="EPSG:3006",
                    shift=shift, scale=scale, swap_xy=True)
    recon = open_reconstruction(opf)
    canonical = _ground()
    # base (N, E, h) = unscale(unswap(canonical − shift)); our map points are (E, N, h)
    base = (canonical - shift)[:, [1, 0, 2]] / scale
    east_north_h = base[:, [1, 0, 2]]
    p = recon.project_points(east_north_h, "EPSG:3006")
    cv = _opencv_pixels(canonical, CAMERAS[0][2], CAMERAS[0][3], PERSPECTIVE)
    inside = p.status[0] == INSIDE
    assert inside.sum() > 20 and np.abs(p.pixels[0][inside] - cv[inside]).max() < 1e-6
    bad = write_opf(tmp_path / "q", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, crs="EPSG:3006")
    with pytest.raises(InputError, match=r"project\.opf: swap_xy is False but the CRS .* northing first"):
        open_reconstruction(bad)


@pytest.mark.parametrize("definition", ["wkt2", "EPSG:6677+6695", "EPSG:6677+EPSG:6695"])
def test_crs_definitions(tmp_path, definition):
    """OPF's CRS definitions: a WKT 2 string, a compound of codes (JGD2011 plane IX: northing
    first, so swap_xy); 2D map points are placed in the compound CRS as they are."""
    from pyproj import CRS
    wkt = CRS.from_epsg(6677).to_wkt(version="WKT2_2019") if definition == "wkt2" else definition
    opf = write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, crs=wkt, swap_xy=True)
    recon = open_reconstruction(opf)
    assert recon.crs.equals(CRS.from_epsg(6677)) if definition == "wkt2" else \
        recon.crs.sub_crs_list[0].to_epsg() == 6677
    assert recon.notes == []
    canonical = _ground()
    # canonical = swap(base), base = (N, E, h) in the CRS's order: canonical is (E, N, h), ours
    p = recon.project_points(canonical, "EPSG:6677")
    cv = _opencv_pixels(canonical, CAMERAS[0][2], CAMERAS[0][3], PERSPECTIVE)
    inside = p.status[0] == INSIDE
    assert inside.sum() > 20 and np.abs(p.pixels[0][inside] - cv[inside]).max() < 1e-6


def test_fisheye_against_pix4d_formula(tmp_path):
    """Brute force: Pix4D's fisheye formula evaluated in the test (θ = 2/π·atan(r), polynomial,
    affine) for an equidistant fisheye (p0 = p2 = 0); a fisheye outside that form is refused."""
    fish = {"type": "fisheye", "principal_point_px": [1001.5, 748.2], "affine": [705.0, 1.3, 0.0, 703.2],
            "is_p0_zero": True, "is_symmetric_affine": False, "polynomial": [0.0, 1.0, 0.0, -0.11]}
    opf = write_opf(tmp_path / "f", {7: (2000, 1500, fish)}, [(21, 7, (5.0, 5.0, 60.0), (4.0, -3.0, 20.0))])
    recon = open_reconstruction(opf)
    pts = _ground(2000)
    p = recon.project_points(pts, "EPSG:32654")
    R = np.diag([1.0, -1.0, -1.0]) @ _opk((4.0, -3.0, 20.0)).T
    Xc = (pts - [5.0, 5.0, 60.0]) @ R.T
    r = np.hypot(Xc[:, 0], Xc[:, 1]) / Xc[:, 2]
    theta = 2 / math.pi * np.arctan(r)
    rho = theta - 0.11 * theta ** 3
    xh, yh = rho * Xc[:, 0] / np.hypot(Xc[:, 0], Xc[:, 1]), rho * Xc[:, 1] / np.hypot(Xc[:, 0], Xc[:, 1])
    u = 705.0 * xh + 1.3 * yh + 1001.5
    v = 703.2 * yh + 748.2
    inside = p.status[0] == INSIDE
    assert inside.sum() > 200
    assert np.abs(p.pixels[0][inside] - np.column_stack([u, v])[inside]).max() < 1e-6
    fish["polynomial"] = [0.0, 1.0, 0.0152646, -0.161096]     # the specification's example
    opf = write_opf(tmp_path / "g", {7: (2000, 1500, fish)}, [(21, 7, (5.0, 5.0, 60.0), (0, 0, 0))])
    with pytest.raises(InputError, match=r"project\.opf, sensor 'cam7': a fisheye .* not supported"):
        open_reconstruction(opf)


def test_demo_opf_project_against_opencv(demo):
    """OpenCV check on the demo survey's OPF project, its JSON read here as plain JSON: every
    camera's pixels of the truth points, to 1e-6 px."""
    folder = Path(demo.opf_project).parent
    cal = json.loads((folder / "calibrated_cameras.json").read_text())
    srf = json.loads((folder / "scene_reference_frame.json").read_text())
    shift = np.array(srf["base_to_canonical"]["shift"])
    uris = {c["id"]: c["uri"] for c in json.loads((folder / "camera_list.json").read_text())["cameras"]}
    internals = cal["sensors"][0]["internals"]
    recon = open_reconstruction(demo.opf_project)
    xyz = np.array(demo.truth_doc["points"]["xyz"])
    p = recon.project_points(xyz, "EPSG:32654")
    worst = 0.0
    for cam in cal["cameras"]:
        i = p.camera_labels.index(Path(uris[cam["id"]]).name)
        cv = _opencv_pixels(xyz + shift, cam["position"], cam["orientation_deg"], internals)
        inside = p.status[i] == INSIDE
        worst = max(worst, float(np.abs(p.pixels[i][inside] - cv[inside]).max()))
    print(f"\ndemo OPF project vs cv2.projectPoints: max {worst:.1e} px")
    assert len(cal["cameras"]) == 36 and worst < 1e-6


def _without_b1(uv, cal, b1):
    """The truth's pixels as a camera without the affinity b1 sees them (exact)."""
    out = np.array(uv, dtype=np.float64)
    out[..., 0] = cal.cx + (out[..., 0] - cal.cx) * cal.f / (cal.f + b1)
    return out


def test_demo_opf_back_projection_equals_the_truth(demo):
    """Independent (corners: tests/support/independent_camera.py; photo sets: the generator's,
    consistency only): plots back-projected through the OPF project (DSM heights, whole plots only):
    photo sets as the truth's and corners on the true pixels to 0.01 px, once the affinity b1
    OPF cannot hold is mapped out of the truth; the raw difference is that term (≤ |b1|·|x'|)."""
    recon = open_reconstruction(demo.opf_project)
    b1 = make_camera(demo.size).calibration.b1
    cal = recon.sensors[recon.cameras[0].sensor_id].calibration
    assert cal.b1 == 0.0 and b1 > 0
    truth = demo.truth_doc
    plots = read_geojson(demo.plots_geojson, name_field="plot_id")
    res = back_project(plots, recon, heights=DSM(demo.dsm), clip=False, min_visible=0,
                       densify_tolerance=NO_DENSIFY)
    pix = independent_camera.observation_lookup(truth)
    worst = raw = 0.0
    n = 0
    for i in range(len(res)):
        ring = res.rings_of(i)[0]
        name = res.roi_names[res.roi[i]]
        for k in range(4):
            key = (f"{name}_c{k + 1}", Path(res.photo[i]).stem)
            if key in pix:
                worst = max(worst, float(np.abs(ring[k] - _without_b1(pix[key], cal, b1)).max()))
                raw = max(raw, float(np.abs(ring[k] - pix[key]).max()))
                n += 1
    print(f"\ndemo OPF back-projection: {n} corners, max {worst:.1e} px from the truth (b1 mapped "
          f"out), {raw:.2f} px raw")
    assert n > 500 and worst < 0.01 and raw < abs(b1) * 0.65
    differ = [name for name in plots.names
              if {Path(p).stem for p in res.photo[res.records_of(name)]}
              != set(truth["plots"][name]["photos_whole"])]
    assert len(differ) <= 2, differ          # a plot corner within b1·|x'| of the frame edge


def test_folder_and_photos_found_by_stem(demo, tmp_path):
    """The folder holding project.opf opens; a moved photo set is found by the PHOTOS lookup."""
    recon = open_reconstruction(Path(demo.opf_project).parent)
    assert recon.software == "opf" and recon.cameras[0].photo_path == str(
        (Path(demo.photo_folder) / "DJI_0001.JPG").resolve())
    from easyidp_toolbox.core.photos import resolve_photos
    moved = tmp_path / "moved"
    moved.mkdir()
    shutil.copy(Path(demo.photo_folder) / "DJI_0003.JPG", moved / "dji_0003.jpg")
    found, missing = resolve_photos(["DJI_0003.JPG"], [recon.camera("DJI_0003.JPG").photo_path],
                                    folder=str(moved))
    assert Path(found["DJI_0003.JPG"]).name == "dji_0003.jpg" and not missing


def test_image_uris_of_the_camera_list(tmp_path):
    """Relative references (percent-encoded), page fragments, file: URIs and Windows paths."""
    photos = {11: "../photos/IMG%200011.tif#page=1", 12: "file:///c:/data/images/DJI_0012.JPG",
              13: "C:\\flights\\DJI_0013.JPG"}
    opf = write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, photos=photos)
    paths = [c.photo_path for c in open_reconstruction(opf).cameras]
    assert paths == [str(tmp_path / "photos" / "IMG 0011.tif"), "c:/data/images/DJI_0012.JPG",
                     "C:\\flights\\DJI_0013.JPG"]
    assert [c.label for c in open_reconstruction(opf).cameras] == \
        ["IMG 0011.tif", "DJI_0012.JPG", "DJI_0013.JPG"]


# --- bad input ------------------------------------------------------------------------------------
@pytest.fixture
def good(tmp_path):
    return write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS)


def test_truncated_project_file(good):
    good.write_text(good.read_text()[:200])
    with pytest.raises(InputError, match=r"project\.opf: not a readable OPF project .* Export the "
                                         r"project from PIX4Dmatic again"):
        open_reconstruction(good)


def test_missing_calibration_names_the_project_and_the_item(good):
    (good.parent / "calib" / "calibrated_cameras.json").unlink()
    with pytest.raises(InputError, match=r"project\.opf: the project has no readable calibration "
                                         r"\(calib/calibrated_cameras\.json: .*No such file"):
        open_reconstruction(good)


def test_damaged_calibrated_cameras(good):
    path = good.parent / "calib" / "calibrated_cameras.json"
    doc = json.loads(path.read_text())
    del doc["cameras"][0]["orientation_deg"]
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError, match=r"project\.opf: the project has no readable calibration "
                                         r"\(calib/calibrated_cameras\.json: Error decoding"):
        open_reconstruction(good)


def test_not_an_opf_project(tmp_path):
    bad = tmp_path / "project.opf"
    bad.write_text(json.dumps({"format": "application/json", "version": "1.0"}))
    with pytest.raises(InputError, match=r"project\.opf: not a readable OPF project"):
        open_reconstruction(bad)
    with pytest.raises(InputError, match=r"nothere\.opf: file not found"):
        open_reconstruction(tmp_path / "nothere.opf")


def test_geographic_scene_reference_frame_refused(tmp_path):
    opf = write_opf(tmp_path / "p", {5: (4000, 3000, PERSPECTIVE)}, CAMERAS, crs="EPSG:4326")
    with pytest.raises(InputError, match=r"project\.opf: the scene reference frame's CRS 'WGS 84' "
                                         r"is geographic"):
        open_reconstruction(opf)


def test_spherical_sensor_refused(tmp_path):
    sph = {"type": "spherical", "principal_point_px": [2000.0, 1000.0]}
    opf = write_opf(tmp_path / "s", {9: (4000, 2000, sph)}, [(31, 9, (0, 0, 10), (0, 0, 0))])
    with pytest.raises(InputError, match=r"sensor model 'spherical' is not supported"):
        open_reconstruction(opf)


def test_without_pyopf_the_message_says_how_to_install(good, monkeypatch):
    """pyopf made unimportable (as where it is not installed): the message names the file and
    the command."""
    for name in [m for m in sys.modules if m == "pyopf" or m.startswith("pyopf.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "pyopf", None)
    with pytest.raises(InputError, match=r"project\.opf: reading OPF projects needs the Python "
                                         r"package pyopf.*pip install pyopf"):
        open_reconstruction(good)


def test_rig_band_cameras(tmp_path):
    """[independent] a multispectral rig written per the specification: one capture, a camera per
    band (sensors 5 and 6, calibrated rig relatives on sensor 6). A band camera with its own
    calibrated pose is placed by it (OpenCV check); a band camera without one is not derived from
    the rig relatives: it is left unaligned, and a note says so, naming the band file."""
    cams = [(11, 5, (12.0, -3.5, 80.2), (3.1, -2.4, 37.0)), (12, 6, (12.05, -3.5, 80.2), (3.0, -2.3, 37.1)),
            (21, 5, (30.5, 4.0, 79.1), (-1.7, 4.2, -141.0)), (22, 6, None, None)]
    opf = write_opf(tmp_path / "rig", {5: (4000, 3000, PERSPECTIVE), 6: (4000, 3000, PERSPECTIVE)},
                    [c for c in cams if c[2] is not None],
                    photos={c[0]: f"images/IMG_{c[0] // 10:04d}_{c[1] - 4}.tif" for c in cams})
    inputs = json.loads((tmp_path / "rig" / "input_cameras.json").read_text())
    cap = inputs["captures"]
    cam_doc = [dict(cap[0]["cameras"][0], id=cid, sensor_id=sid) for cid, sid, _, _ in cams]
    inputs["captures"] = [dict(cap[0], id=1, reference_camera_id=11, rig_model_source="database",
                               cameras=cam_doc[:2]),
                          dict(cap[0], id=2, reference_camera_id=21, rig_model_source="database",
                               cameras=cam_doc[2:])]
    (tmp_path / "rig" / "input_cameras.json").write_text(json.dumps(inputs))
    calib = tmp_path / "rig" / "calib" / "calibrated_cameras.json"
    doc = json.loads(calib.read_text())
    doc["sensors"][1]["rig_relatives"] = {"translation": [0.05, 0.0, 0.0],
                                          "rotation_angles_deg": [0.1, -0.1, 0.05]}
    calib.write_text(json.dumps(doc))
    recon = open_reconstruction(opf)
    labels = {c.label: c.aligned for c in recon.cameras}
    assert labels == {"IMG_0001_1.tif": True, "IMG_0001_2.tif": True, "IMG_0002_1.tif": True,
                      "IMG_0002_2.tif": False}
    assert any("placed by its own calibrated pose" in n for n in recon.notes)
    assert any("1 band camera(s) of rig captures have no calibrated pose (e.g. IMG_0002_2.tif)" in n
               for n in recon.notes)
    canonical = _ground()
    p = recon.project_points(canonical, "EPSG:32654")
    cv = _opencv_pixels(canonical, cams[1][2], cams[1][3], PERSPECTIVE)
    inside = p.status[1] == INSIDE
    assert inside.sum() > 20 and np.abs(p.pixels[1][inside] - cv[inside]).max() < 1e-6
