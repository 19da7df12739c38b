"""The demo survey: generated once per session (small), checked against its own truth file.

Truth kinds, said per test: *independent* checks compare with pixels computed by
``tests/support/independent_camera.py`` (OpenCV and the Metashape manual's formulas, from the
camera truth.json states; no ``core`` code) or by other software (easyidp 2.0.4, GDAL, a
winding-number count); *consistency only* checks compare our code with our code (the generator
renders photos and writes projects with the production camera model).

- independent: every truth point projects to its independent pixel (0.01 px) through the
  generated Metashape and Pix4D projects as our readers open them (and through the pmatrix +
  Inpho .cam alone), and through the OpenDroneMap project;
- camera footprints on the DSM contain the truth points each photo sees;
- the rendered photos match the orthomosaic at the independent pixels, and show the crop where
  the truth says a point is hidden;
- LabelMe vertices: their true map coordinates are on the DSM and project back to the clicks
  (independent, and through our readers);
- plots (GeoJSON, GeoPackage), point clouds (LAZ, PLY) agree with the DSM;
- same seed → identical files; generation time (printed);
- realism: easyidp 2.0.4, in its own environment, reproduces the independent pixels (< 0.5 px).
"""
import hashlib
import json
import os
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.demo import make_demo_survey
from easyidp_toolbox.core.reconstruction import INSIDE
from easyidp_toolbox.scripts.reference import REF_PYTHON
from easyidp_toolbox.tests.support import independent_camera

@pytest.fixture(scope="session")
def survey(tmp_path_factory):
    folder = tmp_path_factory.mktemp("demo_survey")
    t0, c0 = time.perf_counter(), time.process_time()
    s = make_demo_survey(str(folder), seed=0, size="small")
    s.wall_seconds = time.perf_counter() - t0
    s.cpu_seconds = time.process_time() - c0
    s.load = os.getloadavg()[0]
    return s


@pytest.fixture(scope="session")
def truth(survey):
    with open(survey.truth) as fh:
        t = json.load(fh)
    t["xyz"] = np.array(t["points"]["xyz"])
    obs = t["observations"]
    t["obs_point"] = np.array(obs["point"])
    t["obs_photo"] = obs["photo"]
    t["obs_pixel"] = independent_camera.observation_pixels(t)     # the independent truth
    return t


def test_generation_time_and_outputs(survey, truth, capsys):
    with capsys.disabled():
        print(f"\ndemo survey (small): {survey.wall_seconds:.1f} s ({survey.cpu_seconds:.1f} s CPU, "
              f"load average {survey.load:.1f}), {len(truth['photos'])} photos, "
              f"{len(truth['points']['id'])} truth points, {len(truth['obs_point'])} observations")
    for p in (survey.orthomosaic, survey.dsm, survey.plots_geojson, survey.plots_gpkg,
              survey.point_cloud_laz, survey.point_cloud_ply, survey.metashape_project,
              survey.pix4d_project, survey.truth, *survey.photos, *survey.labelme):
        assert os.path.isfile(p), p
    assert len(survey.plot_ids) == 40
    assert len(truth["photos"]) == 36
    assert len(truth["obs_point"]) > 5000
    # every truth point is in the frame of at least two photos (seen or hidden by the crop)
    n = len(truth["xyz"])
    seen = np.bincount(truth["obs_point"], minlength=n)
    framed = seen + np.bincount(truth["hidden"]["point"], minlength=n)
    assert framed.min() >= 2
    assert np.mean(seen >= 2) > 0.99


def _check_projection(recon, truth, label_of, crs="EPSG:32654"):
    p = recon.project_points(truth["xyz"], crs)
    index = {lab: i for i, lab in enumerate(p.camera_labels)}
    cam = np.array([index[label_of(n)] for n in truth["obs_photo"]])
    uv = p.pixels[cam, truth["obs_point"]]
    err = np.abs(uv - truth["obs_pixel"]).max()
    assert err < 0.01, f"max error {err:.4f} px"
    w, h = truth["image_size"]
    t = truth["obs_pixel"]
    margin = np.minimum.reduce([t[:, 0], w - t[:, 0], t[:, 1], h - t[:, 1]])
    assert np.all(p.status[cam, truth["obs_point"]][margin > 0.01] == INSIDE)
    return err


def test_truth_points_project_through_metashape(survey, truth):
    """Independent: the truth points through our Metashape reader land on the independent
    pixels; so do the markers' pinned pixels the generator wrote."""
    recon = open_reconstruction(survey.metashape_project)
    assert recon.software == "metashape" and recon.crs.to_epsg() == 4326
    assert len(recon.aligned_cameras) == 36
    assert [os.path.realpath(c.photo_path) for c in recon.cameras] == \
        [os.path.realpath(p) for p in survey.photos]
    s = recon.sensors["0"].calibration
    assert s.b1 != 0 and s.k3 != 0 and s.p1 != 0 and s.p2 != 0   # no skew: ODM has none
    err = _check_projection(recon, truth, lambda name: name)
    print(f"Metashape: max error {err:.2e} px")
    # the ground control markers carry exact pixel observations
    gcp = {m.label: m for m in recon.markers}
    assert sorted(gcp) == [f"GCP{i}" for i in range(1, 6)]
    ids = truth["points"]["id"]
    for label, m in gcp.items():
        k = ids.index(label)
        sel = truth["obs_point"] == k
        want = {truth["obs_photo"][i]: truth["obs_pixel"][i] for i in np.flatnonzero(sel)}
        assert set(m.observations) == set(want)
        for cam, uv in m.observations.items():
            assert np.allclose(uv, want[cam], atol=1e-5)


def test_truth_points_project_through_pix4d(survey, truth):
    """Independent: the truth points through our Pix4D reader land on the independent pixels."""
    recon = open_reconstruction(survey.pix4d_project)
    assert recon.software == "pix4d" and recon.crs.to_epsg() == 32654
    assert len(recon.aligned_cameras) == 36 and len(recon.sensors) == 1
    cam = recon.aligned_cameras[0]
    assert os.path.realpath(cam.photo_path) == os.path.realpath(
        os.path.join(survey.photo_folder, cam.label))
    err = _check_projection(recon, truth, lambda name: name + ".JPG")
    print(f"Pix4D: max error {err:.2e} px")


def test_pix4d_pmatrix_and_inpho_cam_alone_give_the_same_pixels(survey, truth, tmp_path):
    """Independent: without the calibrated camera parameters, pmatrix (6 decimals) + Inpho-style
    .cam, on the independent pixels."""
    params = Path(survey.pix4d_params)
    for suffix in ("offset.xyz", "pmatrix.txt", "calibrated_internal_camera_parameters.cam",
                   "wkt.prj"):
        shutil.copy(params / f"demo_survey_{suffix}", tmp_path)
    recon = open_reconstruction(tmp_path)
    err = _check_projection(recon, truth, lambda name: name + ".JPG")
    assert err < 0.01


@pytest.mark.parametrize("project", ["metashape", "pix4d", "odm", "opf"])
def test_footprints_contain_the_truth_points_each_photo_sees(survey, truth, project):
    """Truth points (seen pairs: the generator's ray marching) inside the footprints; the
    border margin from the independent pixels."""
    from easyidp_toolbox.core.geometry import points_in_rings
    from easyidp_toolbox.core.raster import DSM
    from easyidp_toolbox.core.projection import camera_footprints
    recon = open_reconstruction({"metashape": survey.metashape_project, "pix4d": survey.pix4d_project,
                                 "odm": survey.odm_project, "opf": survey.opf_project}[project])
    dsm = DSM(survey.dsm)
    fps = camera_footprints(recon, dsm, output_crs="EPSG:32654", per_edge=24)
    (west, east), (north, south) = dsm.tif.pixel_to_map(np.array([40.0, dsm.tif.width]),
                                                       np.array([0.0, dsm.tif.height]))
    w, h = truth["image_size"]
    t = truth["obs_pixel"]
    # crop up to 0.7 m tall near the border pulls the ring inwards by up to ~15 px
    deep = np.minimum.reduce([t[:, 0], w - t[:, 0], t[:, 1], h - t[:, 1]]) > 30
    photos = np.array(truth["obs_photo"])
    checked = 0
    for fp in fps:
        x, y = fp.ring[:, 0], fp.ring[:, 1]
        on_data = ((x.min() > west + 0.05) & (x.max() < east - 0.05)
                   & (y.min() > south + 0.05) & (y.max() < north - 0.05))
        assert fp.complete == on_data, fp.label       # beyond the DSM's data: on a plane
        name = fp.label.replace(".JPG", "")
        sel = (photos == name) & deep
        xy = truth["xyz"][truth["obs_point"][sel], :2]
        inside = points_in_rings(xy[:, 0], xy[:, 1], [np.vstack([fp.ring[:, :2], fp.ring[:1, :2]])])
        assert inside.all(), (fp.label, int((~inside).sum()))
        checked += len(xy)
    assert checked > 5000


def _photo_pixels(path, uv):
    import imagecodecs
    img = imagecodecs.jpeg8_decode(open(path, "rb").read())
    h, w = img.shape[:2]
    c = np.clip(np.floor(uv[:, 0]).astype(int), 0, w - 1)
    r = np.clip(np.floor(uv[:, 1]).astype(int), 0, h - 1)
    return img[r, c].astype(float)


def test_rendered_photos_match_the_orthomosaic_at_projected_points(survey, truth):
    """Independent pixels: colour of the photo pixel holding each independent truth pixel vs the
    orthomosaic around the point (4 cm × 4 cm, about the photo's ground resolution) on a sample
    of observations (the photos are rendered with the production model: this shows that the
    rendering agrees with the independent camera)."""
    import tifffile
    ortho = tifffile.imread(survey.orthomosaic).astype(float)
    rng = np.random.default_rng(5)
    pick = rng.choice(len(truth["obs_point"]), 3000, replace=False)
    photos = np.array(truth["obs_photo"])[pick]
    xyz = truth["xyz"][truth["obs_point"][pick]]
    x0, y0 = 319800.0, 3956050.0          # orthomosaic origin (1 cm pixels)
    col = ((xyz[:, 0] - x0) / 0.01).astype(int)
    row = ((y0 - xyz[:, 1]) / 0.01).astype(int)
    ref = np.mean([ortho[np.clip(row + dr, 0, ortho.shape[0] - 1), np.clip(col + dc, 0, ortho.shape[1] - 1)]
                   for dr in range(-2, 2) for dc in range(-2, 2)], axis=0)

    def photo_colours(shift):
        out = np.empty((len(pick), 3))
        for name in sorted(set(photos)):
            sel = photos == name
            path = os.path.join(survey.folder, truth["photos"][name]["file"])
            out[sel] = _photo_pixels(path, truth["obs_pixel"][pick][sel] + shift)
        return out

    got = photo_colours(np.zeros(2))
    diff = np.abs(got - ref)
    green = lambda c: c[:, 1] - c[:, 0]                  # noqa: E731 (vegetation contrast)
    corr = np.corrcoef(green(got), green(ref))[0, 1]
    print(f"colour: median |diff| {np.median(diff):.1f}, 90th pct {np.percentile(diff, 90):.1f}, "
          f"green-red correlation {corr:.3f}")
    assert np.median(diff) < 8
    assert np.percentile(diff.max(axis=1), 90) < 40
    assert corr > 0.9
    # the test has power: 6 px off (about 22 cm) the agreement collapses. Tolerance: 0.3 before
    # the field had margin grass (issue 32); the grass strip is green at any shift, which keeps
    # about 0.8 of the correlation (0.78 measured with seed 0), so the drop asked is 0.15
    off = photo_colours(np.array([6.0, 0.0]))
    assert np.corrcoef(green(off), green(ref))[0, 1] < corr - 0.15


def test_labelme_polygons_and_their_true_map_coordinates(survey, truth):
    """Independent: the LabelMe truth's map points (cast by the generator) project, by the
    independent camera, onto the clicks; our readers do too (0.01 px)."""
    from easyidp_toolbox.core.raster import DSM
    assert len(survey.labelme) == 4
    ms = open_reconstruction(survey.metashape_project)
    p4 = open_reconstruction(survey.pix4d_project)
    lm_truth = truth["labelme"]
    n = 0
    for path in survey.labelme:
        with open(path) as fh:
            doc = json.load(fh)
        assert set(doc) >= {"version", "flags", "shapes", "imagePath", "imageData",
                            "imageHeight", "imageWidth"}
        assert os.path.isfile(os.path.join(os.path.dirname(path), doc["imagePath"]))
        assert (doc["imageWidth"], doc["imageHeight"]) == tuple(truth["image_size"])
        t = lm_truth[os.path.relpath(path, survey.folder).replace(os.sep, "/")]
        assert 3 <= len(doc["shapes"]) <= 5
        for shape, st in zip(doc["shapes"], t["shapes"]):
            assert shape["shape_type"] == "polygon" and shape["label"] == st["label"]
            uv = np.array(shape["points"])
            xyz = np.array(st["map"])
            assert np.allclose(uv, st["pixels"])
            # the true map point is on the DSM surface and projects back to the clicked pixel
            assert np.allclose(DSM(survey.dsm).heights(xyz[:, 0], xyz[:, 1]), xyz[:, 2], atol=2e-4)
            ind, framed = independent_camera.photo_pixels(truth, t["photo"], xyz)
            assert framed.all() and np.abs(ind - uv).max() < 0.01
            for recon, name in ((ms, t["photo"]), (p4, t["photo"] + ".JPG")):
                back = recon.project_points(xyz, "EPSG:32654", cameras=[name]).pixels[0]
                assert np.abs(back - uv).max() < 0.01
            # and lies at the plot's outline (a few cm of hand jitter, or on the crop next to it)
            corners = np.array(truth["plots"][st["label"]]["corners"])
            assert np.min(np.hypot(*(xyz[0, :2] - corners[:, :2]).T)) < 0.6
            n += 1
    assert n >= 12


def test_plot_layers_and_point_cloud(survey):
    import sqlite3
    from easyidp_toolbox.core import read_geojson, read_point_cloud
    from easyidp_toolbox.core.raster import DSM
    rois = read_geojson(survey.plots_geojson, "plot_id")
    assert len(rois) == 40
    con = sqlite3.connect(survey.plots_gpkg)
    try:
        rows = con.execute('SELECT plot_id, "row", col, geom FROM plots ORDER BY fid').fetchall()
        srs = con.execute("SELECT srs_id FROM gpkg_geometry_columns WHERE table_name='plots'").fetchone()
    finally:
        con.close()
    assert srs == (32654,) and [r[0] for r in rows] == survey.plot_ids
    laz = read_point_cloud(survey.point_cloud_laz)
    ply = read_point_cloud(survey.point_cloud_ply, source_crs="EPSG:32654")
    assert laz.crs.to_epsg() == 32654 and len(laz) == len(ply) > 200_000
    xyz = laz.xyz
    assert {"red", "green", "blue"} <= set(laz.attribute_names)
    pick = np.random.default_rng(1).choice(len(xyz), 2000, replace=False)
    z = DSM(survey.dsm).heights(xyz[pick, 0], xyz[pick, 1])
    assert np.nanmax(np.abs(z - xyz[pick, 2])) < 1e-3
    assert np.allclose(ply.xyz[pick], xyz[pick], atol=1e-3)


def test_same_seed_gives_identical_files(survey, tmp_path):
    again = make_demo_survey(str(tmp_path / "again"), seed=0, size="small")

    def digests(root):
        out = {}
        for dirpath, _, files in os.walk(root):
            for f in files:
                p = os.path.join(dirpath, f)
                with open(p, "rb") as fh:
                    out[os.path.relpath(p, root)] = hashlib.sha256(fh.read()).hexdigest()
        return out
    a, b = digests(survey.folder), digests(again.folder)
    assert sorted(a) == sorted(b) and len(a) >= 60
    assert a == b


EASYIDP_SCRIPT = r"""
import json, sys
import numpy as np, pyproj
import easyidp as idp
truth_path, folder, out = sys.argv[1:4]
with open(truth_path) as fh:
    truth = json.load(fh)
xyz = np.array(truth["points"]["xyz"])
w, h = truth["image_size"]
obs = truth["observations"]
point, photo, pixel = np.array(obs["point"]), np.array(obs["photo"]), np.array(obs["pixel"])
# points within 1 px of the border may fall out of the frame for easyidp (it drops the photo)
keep = (pixel[:, 0] > 1) & (pixel[:, 0] < w - 1) & (pixel[:, 1] > 1) & (pixel[:, 1] < h - 1)
ms = idp.Metashape(folder + "/metashape/demo_survey.psx", chunk_id=0)
ms.crs = pyproj.CRS.from_epsg(32654)          # as its docs say: the CRS of the ROI / DSM
p4d = idp.Pix4D(folder + "/pix4d/demo_survey.p4d", raw_img_folder=folder + "/photos")
result = {}
for name, recon in (("metashape", ms), ("pix4d", p4d)):
    res = {}
    for label in sorted(set(photo)):
        sel = (photo == label) & keep
        got = recon.back2raw_crs(xyz[point[sel]])
        res[label] = {"index": np.flatnonzero(sel).tolist(),
                      "pixel": np.asarray(got[label]).tolist() if label in got else None}
    result[name] = res
with open(out, "w") as fh:
    json.dump(result, fh)
"""


@pytest.mark.gdal
def test_plots_geopackage_reads_back_with_gdal(survey):
    """GDAL (independent of our writer) reads the plots as a GeoPackage layer."""
    from osgeo import ogr
    ds = ogr.Open(survey.plots_gpkg)
    layer = ds.GetLayer(0)
    assert layer.GetFeatureCount() == 40
    assert layer.GetSpatialRef().GetAuthorityCode(None) == "32654"
    areas = [f.GetGeometryRef().GetArea() for f in layer]
    assert np.allclose(areas, 10.0)


def test_easyidp_204_agrees_with_the_truth(survey, truth, tmp_path):
    """Independent (other software, other truth code): easyidp 2.0.4 (its own environment) opens
    both projects and projects the truth points (its public back2raw_crs) to within 0.5 px of the
    independent pixels."""
    assert REF_PYTHON.exists(), (f"reference environment with easyidp 2.0.4 not found at "
                                 f"{REF_PYTHON}: make env-ref creates it")
    script, out = tmp_path / "easyidp_check.py", tmp_path / "easyidp.json"
    script.write_text(EASYIDP_SCRIPT)
    env = {**os.environ, "HOME": str(tmp_path), "XDG_DATA_HOME": str(tmp_path)}
    t0 = time.perf_counter()
    proc = subprocess.run([str(REF_PYTHON), str(script), survey.truth, survey.folder, str(out)],
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    with open(out) as fh:
        result = json.load(fh)
    for name in ("metashape", "pix4d"):
        errs, n = [], 0
        for label, r in result[name].items():
            assert r["pixel"] is not None, f"{name}: easyidp lost photo {label}"
            idx = np.array(r["index"])
            errs.append(np.abs(np.array(r["pixel"]) - truth["obs_pixel"][idx]).max())
            n += len(idx)
        print(f"easyidp 2.0.4 {name}: {n} observations, max error {max(errs):.4f} px "
              f"({time.perf_counter() - t0:.1f} s)")
        assert n > 10000
        assert max(errs) < 0.5


def test_hidden_pairs_show_the_crop_in_front_of_the_soil(survey, truth):
    """Independent pixels: a truth point on soil that the truth says is hidden in a photo shows
    up as crop at its independent pixel there; one it says is seen shows up as soil."""
    import tifffile
    hid = truth["hidden"]
    assert 0 < len(hid["point"]) < len(truth["obs_point"]) / 10
    ortho = tifffile.imread(survey.orthomosaic).astype(float)
    def green(points, photos):
        """(G − R) of the orthomosaic under each point and of the photo pixel holding it."""
        xyz = truth["xyz"][points]
        o = ortho[((3956050.0 - xyz[:, 1]) / 0.01).astype(int), ((xyz[:, 0] - 319800.0) / 0.01).astype(int)]
        p = np.empty_like(o)
        for name in sorted(set(photos)):
            sel = photos == name
            uv = independent_camera.photo_pixels(truth, name, xyz[sel])[0]
            p[sel] = _photo_pixels(os.path.join(survey.photo_folder, name + ".JPG"), uv)
        return o[:, 1] - o[:, 0], p[:, 1] - p[:, 0]

    o, p = green(np.array(hid["point"]), np.array(hid["photo"]))
    soil = o < 0
    assert soil.sum() > 50 and np.mean(p[soil] > 30) > 0.6
    pick = np.random.default_rng(2).choice(len(truth["obs_point"]), 3000, replace=False)
    o, p = green(truth["obs_point"][pick], np.array(truth["obs_photo"])[pick])
    soil = o < 0
    assert soil.sum() > 1000 and np.mean(p[soil] > 30) < 0.1


def test_bad_size_and_cancellation(tmp_path):
    from easyidp_toolbox.core import Cancelled, InputError
    with pytest.raises(InputError):
        make_demo_survey(str(tmp_path / "a"), size="huge")
    with pytest.raises(Cancelled):
        make_demo_survey(str(tmp_path / "b"), is_cancelled=lambda: True)


def test_plots_seen_whole(truth):
    plots = truth["plots"]
    assert len(plots) == 40
    for pid, p in plots.items():
        assert len(p["photos_whole"]) >= 2, pid
        assert set(p["photos_whole"]) <= set(p["photos_corners"])


def test_point_cloud_cropped_by_the_plots_matches_an_independent_count(survey, tmp_path):
    """Issue 5's check on the demo survey: per-plot counts of the one-pass crop equal a
    winding-number count, and the kept points are exactly those points."""
    import laspy

    from easyidp_toolbox.core import crop_point_cloud, read_geojson
    from easyidp_toolbox.tests.support.pc_helpers import winding_inside

    plots = read_geojson(survey.plots_geojson, name_field="plot_id")
    res = crop_point_cloud(survey.point_cloud_laz, plots, str(tmp_path / "crops"), fmt="las")
    las = laspy.read(survey.point_cloud_laz)
    x, y = np.asarray(las.x), np.asarray(las.y)
    by_name = {item.name: item for item in res.items}
    assert len(by_name) == len(plots) == 40
    for roi in plots:
        inside = winding_inside(x, y, roi.rings)
        item = by_name[roi.name]
        assert item.count == int(inside.sum()) > 0
        kept = laspy.read(item.file)
        assert np.array_equal(np.sort(np.asarray(kept.x)), np.sort(x[inside]))


# --- the OpenDroneMap project ----------------------------------------------------------------------
def _odm_check(recon, truth, survey):
    """Max pixel error of the truth observations through an ODM reconstruction."""
    p = recon.project_points(truth["xyz"], "EPSG:32654")
    index = {lab: i for i, lab in enumerate(p.camera_labels)}
    cam = np.array([index[n + ".JPG"] for n in truth["obs_photo"]])
    return float(np.abs(p.pixels[cam, truth["obs_point"]] - truth["obs_pixel"]).max())


def test_truth_points_project_through_the_odm_project(survey, truth):
    """Independent: the ODM project folder: OpenSfM's topocentric file is read (mapped exactly
    with pyproj); photos come from images/; the independent pixels are met to 0.01 px."""
    recon = open_reconstruction(survey.odm_project)
    assert recon.software == "odm" and recon.crs.to_epsg() == 32654
    assert len(recon.aligned_cameras) == 36 and not recon.unaligned_cameras
    assert any("reconstruction.topocentric.json" in n for n in recon.notes)
    cam = recon.camera("DJI_0007.JPG")
    assert cam.photo_path == os.path.join(survey.odm_project, "images", "DJI_0007.JPG")
    with open(cam.photo_path, "rb") as a, open(os.path.join(survey.photo_folder, "DJI_0007.JPG"), "rb") as b:
        assert a.read() == b.read()
    err = _odm_check(recon, truth, survey)
    print(f"\nODM (topocentric): max {err:.1e} px")
    assert err < 0.01


def test_odm_map_coordinate_file_and_how_its_frame_is_told(survey, truth, tmp_path):
    """Without reconstruction.topocentric.json (as in some ODM downloads), reconstruction.json is
    ODM's map-coordinate export: told from shots.geojson, else from the photos' GPS positions
    (independent pixels)."""
    from easyidp_toolbox.core import InputError
    odm = tmp_path / "odm"
    shutil.copytree(survey.odm_project, odm, ignore=shutil.ignore_patterns("*.tif", "images"))
    (odm / "opensfm" / "reconstruction.topocentric.json").unlink()
    recon = open_reconstruction(odm / "opensfm" / "reconstruction.json")
    assert any("map coordinates minus the offset" in n and "shots.geojson" in n for n in recon.notes)
    assert _odm_check(recon, truth, survey) < 0.01
    geo = odm / "opensfm" / "reconstruction.geocoords.json"       # export_geocoords' own name
    shutil.copy(odm / "opensfm" / "reconstruction.json", geo)
    assert _odm_check(open_reconstruction(geo), truth, survey) < 0.01
    geo.unlink()
    (odm / "odm_report" / "shots.geojson").unlink()
    recon = open_reconstruction(odm)
    assert any("map coordinates minus the offset" in n and "GPS positions" in n for n in recon.notes)
    assert _odm_check(recon, truth, survey) < 0.01
    (odm / "odm_georeferencing" / "coords.txt").write_text("WGS84 UTM 54N\n")
    with pytest.raises(InputError, match=r"coords\.txt: the east/north offset \(line 2\) is missing"):
        open_reconstruction(odm)


def test_plots_back_projected_through_the_three_projects_land_on_the_same_pixels(survey, truth):
    """Consistency only (our readers against each other): the plot corners (on the DSM surface)
    through the Metashape, Pix4D and ODM projects of the demo: the same pixels, to 0.01 px."""
    corners = np.array([c for p in truth["plots"].values() for c in p["corners"]])
    px = {}
    for name, path in (("metashape", survey.metashape_project), ("pix4d", survey.pix4d_project),
                       ("odm", survey.odm_project)):
        p = open_reconstruction(path).project_points(corners, "EPSG:32654")
        order = np.argsort([lab.split(".")[0] for lab in p.camera_labels])
        px[name] = (p.pixels[order], p.status[order])
    ms_uv, ms_st = px["metashape"]
    seen = ms_st == INSIDE
    assert seen.sum() > 500
    for name in ("pix4d", "odm"):
        uv, st = px[name]
        margin = np.minimum.reduce([ms_uv[..., 0], truth["image_size"][0] - ms_uv[..., 0],
                                    ms_uv[..., 1], truth["image_size"][1] - ms_uv[..., 1]])
        assert (st[seen & (margin > 0.2)] == INSIDE).all()
        d = np.abs(uv[seen] - ms_uv[seen]).max()
        print(f"\nplot corners, {name} vs Metashape: {d:.1e} px")
        assert d < 0.01


# --- a field as messy as real ones (issue 32) ------------------------------------------------------
def test_the_field_has_what_real_fields_have(survey, truth):
    """Measured on the written files (orthomosaic, DSM, plots) against the truth's per-plot
    features, at the default levels issue 32 asks for: margin grass at least half as green as
    the crop; weeds in a third of the plots and in the alleys; uneven vigour between and within
    plots; missing row segments, some at row ends; 3 empty plots; lodged patches, shadows and a
    soil-colour gradient; one block of plots without alleys."""
    import tifffile
    from easyidp_toolbox.core import read_geojson
    from easyidp_toolbox.core.geometry import points_in_rings
    from easyidp_toolbox.core.raster import DSM
    feats = {k: v["field"] for k, v in truth["plots"].items()}
    assert sum(f["empty"] for f in feats.values()) >= 3
    assert sum(f["weeds"] > 0 for f in feats.values()) >= len(feats) / 3
    assert sum(f["gaps_at_row_end"] for f in feats.values()) >= 5
    assert sum(f["gaps"] > 0 for f in feats.values()) >= len(feats) / 2
    assert sum(f["lodged"] for f in feats.values()) >= 2
    block = sorted(k for k, f in feats.items() if f["no_alley"])
    assert len(block) == 8
    corners = {k: np.array(truth["plots"][k]["corners"])[:, :2] for k in block}
    for k in block:                     # each shares an edge (two corners) with a neighbour
        shared = max(int((np.hypot(*(corners[o][None] - corners[k][:, None]).transpose(2, 0, 1))
                          .min(axis=1) < 1e-6).sum()) for o in block if o != k)
        assert shared >= 2, k

    ortho = tifffile.imread(survey.orthomosaic).astype(np.float32)
    exg = (2 * ortho[..., 1] - ortho[..., 0] - ortho[..., 2]) / np.maximum(ortho.sum(axis=2), 1)
    rows, cols = np.mgrid[0:ortho.shape[0]:4, 0:ortho.shape[1]:4]
    x, y = 319800.0 + (cols + 0.5) * 0.01, 3956050.0 - (rows + 0.5) * 0.01
    e = exg[::4, ::4]
    rois = read_geojson(survey.plots_geojson, "plot_id")
    rings = {r.name: r.rings[0] for r in rois}
    allc = np.vstack([c for c in (np.array(p["corners"])[:, :2] for p in truth["plots"].values())])
    (x0, y0), (x1, y1) = allc.min(axis=0), allc.max(axis=0)
    margin = ~((x > x0 - 1.6) & (x < x1 + 1.6) & (y > y0 - 1.6) & (y < y1 + 1.6))
    crop = np.zeros(x.shape, bool)
    for k, f in feats.items():
        if not f["empty"]:
            crop |= points_in_rings(x.ravel(), y.ravel(), [rings[k]]).reshape(x.shape)
    leaf = np.percentile(e[crop], 90)
    grass = np.median(e[margin])
    print(f"\nExG: crop leaf (90th pct in the plots) {leaf:.3f}, margin grass (median) {grass:.3f}")
    assert grass >= 0.5 * leaf
    # weeds in the alleys: vegetation in the plot block outside every plot (grown by 10 cm)
    dsm = DSM(survey.dsm)
    block_area = (x > x0) & (x < x1) & (y > y0) & (y < y1) & ~margin
    near_plot = np.zeros(x.shape, bool)
    for r in rois:
        c = np.array(r.rings[0])
        ctr = c[:-1].mean(axis=0)
        grown = ctr + (c - ctr) * 1.05
        near_plot |= points_in_rings(x.ravel(), y.ravel(), [grown]).reshape(x.shape)
    alley = block_area & ~near_plot
    assert np.sum(e[alley] > 0.3) > 200
    # vigour: heights differ between plots, and within a plot its halves differ
    heights = [truth["plots"][k]["crop_height"] for k, f in feats.items() if not f["empty"]]
    assert np.std(heights) > 0.08
    ground = np.nanmedian(dsm.heights(x[margin][::50], y[margin][::50])
                          - 95.0 - 0.02 * (x[margin][::50] - 319800.0)
                          - 0.01 * (y[margin][::50] - 3956010.0))
    assert abs(ground) < 0.08              # grass on the ground plane (heights ≤ 7 cm)
    # soil colour: the east is redder than the west (soil texels: ExG < 0)
    soil = e < 0
    west, east = soil & (x < 319800.0 + 15), soil & (x > 319800.0 + 45)
    r_g = lambda m: np.median(ortho[::4, ::4, 0][m] / ortho[::4, ::4, 1][m])      # noqa: E731
    print(f"soil R/G west {r_g(west):.3f}, east {r_g(east):.3f}")
    assert r_g(east) > r_g(west) + 0.02
    # shadows: soil just north-west of the crop is darker than soil elsewhere
    bright = ortho[::4, ::4].sum(axis=2)
    nw = np.zeros(soil.shape, bool)
    veg = e > 0.3
    nw[:-2, :-2] = veg[2:, 2:]            # 8 cm south-east of it there is vegetation
    assert np.median(bright[soil & nw & crop]) < 0.85 * np.median(bright[soil & ~nw & ~crop & ~margin])


def test_rows_hide_the_soil_between_them_in_oblique_views(truth):
    """Truth points on bare soil inside planted plots (surface within 2 cm of the ground, in a
    plot with crop): in views that look across the rows at 15° or more the generator's segment
    test finds most of them hidden by the rows; straight down, none."""
    from easyidp_toolbox.core.geometry import points_in_rings
    xyz = truth["xyz"]
    rel = xyz[:, 2] - (95.0 + 0.02 * (xyz[:, 0] - 319800.0) + 0.01 * (xyz[:, 1] - 3956010.0))
    furrow = np.zeros(len(xyz), bool)
    for k, p in truth["plots"].items():
        if p["field"]["empty"] or p["crop_height"] < 0.3:
            continue
        c = np.array(p["corners"])[:, :2]
        ctr = c.mean(axis=0)
        inner = ctr + (c - ctr) * 0.85
        furrow |= points_in_rings(xyz[:, 0], xyz[:, 1], [np.vstack([inner, inner[:1]])])
    furrow &= rel < 0.02
    centres = {k: np.array(v["centre"]) for k, v in truth["photos"].items()}
    pairs = [(p, ph, False) for p, ph in zip(truth["obs_point"], truth["obs_photo"])] + \
        [(p, ph, True) for p, ph in zip(truth["hidden"]["point"], truth["hidden"]["photo"])]
    across, hid = [], []
    for p, ph, h in pairs:
        if furrow[p]:
            d = xyz[p] - centres[ph]
            across.append(np.degrees(np.arctan2(abs(d[1]), -d[2])))   # rows run east-west (±4°)
            hid.append(h)
    across, hid = np.array(across), np.array(hid)
    steep, oblique = across < 5, across >= 15
    print(f"\nfurrow soil points: hidden in {hid[oblique].mean():.0%} of {oblique.sum()} views "
          f"15° or more across the rows, {hid[steep].mean():.0%} of {steep.sum()} under 5°")
    assert oblique.sum() > 30 and hid[oblique].mean() > 0.5 and hid[steep].mean() < 0.1
