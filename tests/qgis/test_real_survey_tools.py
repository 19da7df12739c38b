"""Every projection tool through qgis_process on the real OpenDroneMap survey
(realdata/orthority_odm), opened as ODM left it: no offset, no photos folder (issue 24).
GeoPackage outputs, read back with OGR / sqlite. The geometry itself is checked at core level
(tests/core/test_real_survey.py, against OpenCV); here: the tools run headless on it and their
outputs hold what the core found."""
import json
import os
import sqlite3

import pytest

from easyidp_toolbox.tests.support import real_survey as rs
from easyidp_toolbox.scripts.qgis_process import run_algorithm


@pytest.fixture(scope="module")
def odm(realdata):
    return realdata / "orthority_odm"


@pytest.fixture(scope="module")
def project(odm):
    return odm / "opensfm" / "reconstruction.json"   # the file parameter takes no folders


@pytest.fixture(scope="module")
def rois(tmp_path_factory):
    return rs.write_rois_geojson(tmp_path_factory.mktemp("rois") / "plots.geojson")


def _features(path):
    from osgeo import ogr
    ds = ogr.Open(str(path))
    layer = ds.GetLayer(0)
    srs = layer.GetSpatialRef()
    code = srs.GetAuthorityCode(None) if srs is not None else None   # read while ds is open
    return [{k: f.GetField(k) for k in f.keys()} for f in layer], code


def test_footprints(qp_env, project, odm, tmp_path):
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": project, "DSM": odm / "odm_dem" / "dsm.tif",
        "OUTPUT_CAMERAS": tmp_path / "cams.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    cams, srs = _features(res["OUTPUT_CAMERAS"])
    assert sorted(os.path.basename(c["photo_path"]) for c in cams) == [p + ".tif" for p in rs.PHOTOS]
    assert srs == str(rs.UTM51N)
    fps, _ = _features(res["OUTPUT_FOOTPRINTS"])
    assert len(fps) == 4


def test_back_projection_with_crops_and_previews(qp_env, project, odm, rois, tmp_path):
    res = run_algorithm("easyidp:backprojectrois", {
        "ROIS": rois, "NAME_FIELD": "name", "PROJECT": project, "HEIGHT_SOURCE": 1,
        "DSM": odm / "odm_dem" / "dsm.tif", "OUTPUT": tmp_path / "pixels.gpkg",
        "OUTPUT_SUMMARY": tmp_path / "summary.gpkg", "CROPS_FOLDER": tmp_path / "crops",
        "PREVIEW_FOLDER": tmp_path / "previews"}, qp_env)
    pix, _ = _features(res["OUTPUT"])
    seen = {}
    for f in pix:
        seen.setdefault(f["roi"], set()).add(f["photo"])
        assert f["photo_path"].endswith(".tif") and os.path.isfile(f["photo_path"])
    for pair in rs.PAIR_CENTRES:
        assert set(pair) <= seen[rs.roi_name(pair)]
    crops = list((tmp_path / "crops").rglob("*.png"))
    assert len(crops) == len(pix)
    assert len(list((tmp_path / "previews").iterdir())) == len(rs.PAIR_CENTRES)
    # photo pixels: GeoPackage's undefined *Cartesian* SRS (-1), not the geographic one (0)
    con = sqlite3.connect(res["OUTPUT"])
    assert con.execute("SELECT srs_id FROM gpkg_geometry_columns").fetchall() == [(-1,)]


def test_forward_projection(qp_env, project, odm, tmp_path):
    doc = {"version": "5.0.1", "flags": {}, "imagePath": "C:\\survey\\images\\100_0005_0140.TIF",
           "imageData": None, "imageWidth": 1368, "imageHeight": 912,
           "shapes": [{"label": "crown", "points": [[600, 400], [700, 400], [700, 480], [600, 480]],
                       "shape_type": "polygon", "flags": {}, "group_id": None}]}
    (tmp_path / "a.json").write_text(json.dumps(doc))
    res = run_algorithm("easyidp:forwardprojectpolygons", {
        "INPUT": tmp_path / "a.json", "PROJECT": project, "DSM": odm / "odm_dem" / "dsm.tif",
        "OUTPUT": tmp_path / "map.gpkg"}, qp_env)
    feats, srs = _features(res["OUTPUT"])
    assert len(feats) == 1 and srs == str(rs.UTM51N)
    area = [v for k, v in feats[0].items() if "area" in k.lower()]
    assert area and 100 < area[0] < 400


def test_orthorectification(qp_env, project, odm, rois, tmp_path):
    res = run_algorithm("easyidp:orthorectifyrois", {
        "ROIS": rois, "NAME_FIELD": "name", "PROJECT": project,
        "DSM": odm / "odm_dem" / "dsm.tif", "SELECTION": 1, "OUTPUT_FOLDER": tmp_path / "ortho",
        "OUTPUT_INDEX": tmp_path / "index.gpkg"}, qp_env)
    files = sorted(p.name for p in (tmp_path / "ortho").glob("*.tif"))
    for pair in rs.PAIR_CENTRES:
        for p in pair:
            assert f"{rs.roi_name(pair)}_{p}.tif" in files
    index, _ = _features(res["OUTPUT_INDEX"])
    assert len(index) == len(files)


def test_plot_statistics(qp_env, project, odm, rois, tmp_path):
    res = run_algorithm("easyidp:photostatistics", {
        "ROIS": rois, "NAME_FIELD": "name", "PROJECT": project, "HEIGHT_SOURCE": 1,
        "DSM": odm / "odm_dem" / "dsm.tif", "OUTPUT": tmp_path / "stats.gpkg",
        "OUTPUT_VIEWS": tmp_path / "views.gpkg"}, qp_env)
    feats, srs = _features(res["OUTPUT"])
    assert len(feats) == len(rs.PAIR_CENTRES) and srs == str(rs.UTM51N)
    for f in feats:
        red = [v for k, v in f.items() if k.startswith("red") and "mean" in k]
        assert red and all(0 < v < 255 for v in red)
