"""Headless runs through the real qgis_process.bin, as a newcomer's scripts would call it."""
import json
import os
from pathlib import Path

from easyidp_toolbox.scripts.qgis_process import run, run_algorithm

MODEL = Path(__file__).parent / "data" / "heights_then_crop.model3"


def test_provider_is_listed(qp_env):
    out = run(["list"], qp_env).stdout
    assert "EasyIDP" in out
    assert "easyidp:croprasterbyrois" in out and "easyidp:roiheightsfromdsm" in out


def test_help_lists_parameters(qp_env):
    out = run(["help", "easyidp:croprasterbyrois"], qp_env).stdout
    for p in ("INPUT", "ROIS", "NAME_FIELD", "ALL_TOUCHED", "OUTPUT_FOLDER"):
        assert p in out
    out = run(["help", "easyidp:roiheightsfromdsm"], qp_env).stdout
    for p in ("ROIS", "DSM", "MODE", "STATISTIC", "PERCENTILE", "BUFFER", "OUTPUT"):
        assert p in out


def test_crop_json_output_is_clean(qp_env, realdata, tmp_path):
    """--json output parses: importing the plugin prints nothing."""
    res = run_algorithm("easyidp:croprasterbyrois", {
        "INPUT": realdata / "d2spy/dsm.tif", "ROIS": realdata / "d2spy/feature_in_dsm.geojson",
        "OUTPUT_FOLDER": tmp_path / "crops"}, qp_env)
    assert res["CROPPED"] == 1 and os.path.exists(res["OUTPUT_FILES"][0])


def test_heights_to_geopackage(qp_env, realdata, tmp_path):
    out = tmp_path / "h.gpkg"
    run_algorithm("easyidp:roiheightsfromdsm", {
        "ROIS": realdata / "data-to-science/zones_inside_test_tif.geojson",
        "DSM": realdata / "data-to-science/test.tif", "MODE": 0, "STATISTIC": 4, "PERCENTILE": 95,
        "OUTPUT": out}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(str(out))
    layer = ds.GetLayer(0)
    assert layer.GetFeatureCount() == 20 and ogr.GT_HasZ(layer.GetGeomType())
    assert all(187 < f.GetField("height") < 189 for f in layer)


def test_bad_input_exits_1_with_the_message(qp_env, realdata, tmp_path):
    proc = run(["run", "easyidp:croprasterbyrois", "--",
                f"INPUT={realdata / 'd2spy/dsm.tif'}",
                f"ROIS={realdata / 'd2spy/feature_outside_dsm.geojson'}",
                f"OUTPUT_FOLDER={tmp_path / 'o'}"], qp_env)
    assert proc.returncode == 1
    assert "None of the 1 ROIs overlaps the raster" in proc.stderr + proc.stdout


def test_model_chaining_both_tools_runs_headless(qp_env, realdata, tmp_path):
    proc = run(["--json", "run", str(MODEL), "--",
                f"dsm={realdata / 'data-to-science/test.tif'}",
                f"plots={realdata / 'data-to-science/zones_inside_test_tif.geojson'}",
                "name_field=col", f"heights:Plots with heights={tmp_path / 'plots.gpkg'}",
                f"crop:Crops={tmp_path / 'crops'}"], qp_env)
    assert proc.returncode == 0, proc.stderr
    results = json.loads(proc.stdout)["results"]
    assert Path(results["heights:Plots with heights"]).exists()
    assert len(list((tmp_path / "crops").glob("*.tif"))) == 20


def test_camera_footprints_headless(qp_env, realdata, tmp_path):
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": realdata / "easyidp/metashape/wheat_tanashi.psx", "GROUND_HEIGHT": 97,
        "OUTPUT_CAMERAS": tmp_path / "cams.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(res["OUTPUT_FOOTPRINTS"])
    assert ds.GetLayer(0).GetFeatureCount() == 138


def _plots_geojson(path):
    """Two plots over autzen_trim.laz and one beside it, in EPSG:2994 (a legacy GeoJSON crs)."""
    boxes = {"p1": (636100.013, 849000.017, 636300.029, 849180.031),
             "p2": (636500.011, 849050.013, 636800.037, 849350.019),
             "far": (640000.01, 849000.01, 640100.01, 849100.01)}
    feats = [{"type": "Feature", "properties": {"plot": k},
              "geometry": {"type": "Polygon", "coordinates": [[[x0, y0], [x1, y0], [x1, y1],
                                                               [x0, y1], [x0, y0]]]}}
             for k, (x0, y0, x1, y1) in boxes.items()]
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats, "crs": {
        "type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2994"}}}))
    return path


def test_crop_point_cloud_to_las(qp_env, realdata, tmp_path):
    res = run_algorithm("easyidp:croppointcloudbyrois", {
        "INPUT": realdata / "laspy/autzen_trim.laz", "ROIS": _plots_geojson(tmp_path / "plots.geojson"),
        "NAME_FIELD": "plot", "FORMAT": 1, "OUTPUT_FOLDER": tmp_path / "crops"}, qp_env)
    assert (res["CROPPED"], res["EMPTY"], res["MISSED"]) == (2, 0, 1)
    assert sorted(os.path.basename(f) for f in res["OUTPUT_FILES"]) == ["p1.las", "p2.las"]
    import laspy
    assert all(len(laspy.read(f).points) > 1000 for f in res["OUTPUT_FILES"])


def test_point_cloud_statistics_to_geopackage(qp_env, realdata, tmp_path):
    out = tmp_path / "stats.gpkg"
    run_algorithm("easyidp:pointcloudroistatistics", {
        "INPUT": realdata / "laspy/autzen_trim.laz", "ROIS": _plots_geojson(tmp_path / "plots.geojson"),
        "GROUND_HEIGHT": 400, "PERCENTILES": "50,95", "OUTPUT": out}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(str(out))  # keep the data source alive while its features are used
    rows = {f.GetField("plot"): f for f in ds.GetLayer(0)}
    assert rows["p1"].GetField("count") > 1000 and rows["far"].GetField("count") == 0
    assert rows["p1"].GetField("ground") == 400 and rows["p1"].GetField("h_p95") > 0
    assert not rows["far"].IsFieldSetAndNotNull("h_p95")


def test_camera_footprints_of_an_odm_project_headless(qp_env, realdata, tmp_path):
    """PROJECT = opensfm/reconstruction.json of an ODM project folder (the file parameter does
    not take folders yet): the real OpenSfM reconstruction placed as ODM leaves it, photos
    looked up in the project's images/ folder."""
    odm = tmp_path / "odm"
    (odm / "opensfm").mkdir(parents=True)
    (odm / "images").mkdir()
    import shutil
    shutil.copy(realdata / "opensfm_berlin/reconstruction_example.json", odm / "opensfm/reconstruction.json")
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": odm / "opensfm" / "reconstruction.json", "GROUND_HEIGHT": 0, "OUTPUT_CAMERAS": tmp_path / "cams.gpkg",
        "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(res["OUTPUT_CAMERAS"])
    layer = ds.GetLayer(0)
    assert layer.GetFeatureCount() == 3
    assert {f.GetField("photo_path") for f in layer} == {str(odm / "images" / n) for n in
                                                          ("01.jpg", "02.jpg", "03.jpg")}


def test_numbers_and_choices_out_of_range_name_the_range(qp_env, realdata, tmp_path):
    """qgis_process: a NaN ground height, a percentile of 150 and a mode of 5 are refused with
    the parameter, the value and the range or the choices; a Pix4D params *folder* is accepted."""
    rois, dsm = realdata / "data-to-science/zones_inside_test_tif.geojson", realdata / "data-to-science/test.tif"
    cases = [({"STATISTIC": 4, "PERCENTILE": 150}, "150 is outside the range 0–100"),
             ({"MODE": 5}, "5 is not one of the choices (0 = Per polygon")]
    for extra, message in cases:
        args = ["run", "easyidp:roiheightsfromdsm", "--", f"ROIS={rois}", f"DSM={dsm}",
                f"OUTPUT={tmp_path / 'h.gpkg'}"] + [f"{k}={v}" for k, v in extra.items()]
        proc = run(args, qp_env)
        assert proc.returncode != 0 and message in proc.stdout + proc.stderr, proc.stderr[-800:]
    params = realdata / "easyidp/pix4d_origin/1_initial/params"
    proc = run(["run", "easyidp:camerafootprints", "--", f"PROJECT={params}",
                "PROJECT_CRS=EPSG:32654", "GROUND_HEIGHT=nan",
                f"OUTPUT_CAMERAS={tmp_path / 'c.gpkg'}", f"OUTPUT_FOOTPRINTS={tmp_path / 'f.gpkg'}"], qp_env)
    assert proc.returncode != 0 and "nan is not a number" in proc.stdout + proc.stderr
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": params, "PROJECT_CRS": "EPSG:32654", "GROUND_HEIGHT": 96,
        "OUTPUT_CAMERAS": tmp_path / "c.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "f.gpkg"}, qp_env)
    assert os.path.exists(res["OUTPUT_FOOTPRINTS"])


def _opf_project(folder):
    """An OPF project of three nadir photos 50 m over flat ground at 30 m (EPSG:32654), written
    by the demo's OPF writer (per the specification); the photos themselves are not needed."""
    import numpy as np
    from easyidp_toolbox.core.demo.flight import Shot, make_camera, nadir_rotation
    from easyidp_toolbox.core.demo.opf_writer import write_opf
    offset = np.array([380000.0, 3950000.0, 30.0])
    shots = [Shot(label=f"DJI_{i:04d}", filename=f"DJI_{i:04d}.JPG", R=nadir_rotation(0.3 * i),
                  C=np.array([10.0 * i, 5.0, 50.0]), line=1, yaw_deg=0.0, gps=np.zeros(3),
                  time="2024:06:01 10:00:0" + str(i)) for i in range(1, 4)]
    photos = [str(folder / "photos" / s.filename) for s in shots]
    return write_opf(folder / "opf", make_camera("small"), shots, offset, photos, 32654)["project"], \
        [s.C + offset for s in shots]


def test_camera_footprints_of_an_opf_project_headless(qp_env, tmp_path):
    """An OPF project.opf (PIX4Dmatic) through qgis_process: cameras at their positions, and
    each footprint on the ground around the camera's nadir (truth by construction)."""
    import numpy as np
    opf, centres = _opf_project(tmp_path)
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": opf, "GROUND_HEIGHT": 30, "OUTPUT_CAMERAS": tmp_path / "cams.gpkg",
        "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(res["OUTPUT_CAMERAS"])
    got = {f.GetField("label"): f.GetGeometryRef().GetPoint() for f in ds.GetLayer(0)}
    assert set(got) == {"DJI_0001.JPG", "DJI_0002.JPG", "DJI_0003.JPG"}
    for i, c in enumerate(centres, 1):
        assert np.allclose(got[f"DJI_{i:04d}.JPG"][:2], c[:2], atol=1e-6)
    fp = ogr.Open(res["OUTPUT_FOOTPRINTS"])
    for f in fp.GetLayer(0):
        geom = f.GetGeometryRef()
        c = centres[int(f.GetField("label")[4:8]) - 1]
        nadir = ogr.Geometry(ogr.wkbPoint)
        nadir.AddPoint_2D(float(c[0]), float(c[1]))
        assert geom.Contains(nadir)
        # 800 × 600 px, f = 680 px, 50 m above the ground: about 58.8 m × 44.1 m
        assert 0.9 < geom.GetArea() / (800 * 50 / 680 * 600 * 50 / 680) < 1.2


def test_a_damaged_opf_project_exits_1_naming_the_file(qp_env, tmp_path):
    opf, _ = _opf_project(tmp_path)
    Path(opf).write_text(Path(opf).read_text()[:150])
    proc = run(["run", "easyidp:camerafootprints", "--", f"PROJECT={opf}", "GROUND_HEIGHT=30",
                f"OUTPUT_CAMERAS={tmp_path / 'c.gpkg'}", f"OUTPUT_FOOTPRINTS={tmp_path / 'f.gpkg'}"],
               qp_env)
    assert proc.returncode == 1
    assert f"{opf}: not a readable OPF project" in proc.stderr + proc.stdout
