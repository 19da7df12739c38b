"""The tools through real qgis_process on a folder of photos with no project file (issue 28):
the real OpenDroneMap survey's photos (realdata/orthority_odm/images), cameras from their EXIF
and XMP tags. GeoPackage outputs, read back with OGR. The geometry itself is checked at core
level (tests/core/test_photo_folder.py, against ODM's solved cameras and Orthority)."""
import pytest

from easyidp_toolbox.scripts.qgis_process import run_algorithm
from easyidp_toolbox.tests.support import real_survey as rs


@pytest.fixture(scope="module")
def odm(realdata):
    return realdata / "orthority_odm"


def _features(path):
    from osgeo import ogr
    ds = ogr.Open(str(path))
    return [{k: f.GetField(k) for k in f.keys()} for f in ds.GetLayer(0)]


def test_footprints_and_back_projection_from_photos(qp_env, odm, tmp_path):
    """[consistency only] footprints of the four photos (heights: relative altitude + a take-off
    height) and the five plots back-projected to one named photo (PHOTO), each pixel feature
    with its photo's uncertainty_px."""
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": odm / "images", "DSM": odm / "odm_dem" / "dsm.tif", "CAMERA_HEIGHTS": 1,
        "TAKEOFF_HEIGHT": 86.61,
        "OUTPUT_CAMERAS": tmp_path / "cams.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    assert len(_features(res["OUTPUT_FOOTPRINTS"])) == 4
    from osgeo import ogr
    ds = ogr.Open(str(res["OUTPUT_CAMERAS"]))
    z = {f["label"]: (f.GetGeometryRef().GetZ(), f["view_angle"]) for f in ds.GetLayer(0)}
    ds = None
    assert z["100_0005_0018"][0] == pytest.approx(86.61 + 99.96, abs=1e-6)   # + RelativeAltitude
    assert all(v == pytest.approx(30.0, abs=1e-6) for _, v in z.values())    # gimbal pitch −60°
    rois = rs.write_rois_geojson(tmp_path / "plots.geojson")
    res = run_algorithm("easyidp:backprojectrois", {
        "ROIS": rois, "NAME_FIELD": "name", "PROJECT": odm / "images", "HEIGHT_SOURCE": 1,
        "DSM": odm / "odm_dem" / "dsm.tif", "PHOTO": "100_0005_0142.tif",
        "OUTPUT": tmp_path / "pixels.gpkg", "OUTPUT_SUMMARY": tmp_path / "summary.gpkg"}, qp_env)
    pix = _features(res["OUTPUT"])
    assert {f["photo"] for f in pix} == {"100_0005_0142"}
    assert {f["roi"] for f in pix} == {rs.roi_name(p) for p in rs.PAIR_CENTRES if "100_0005_0142" in p}
    assert all(20 < f["uncertainty_px"] < 30 for f in pix)


def test_bad_photo_folder_writes_nothing(qp_env, tmp_path):
    """A folder of photos without GPS: the tool stops with one line naming the photos and the
    tags, and writes no output."""
    from PIL import Image
    photos = tmp_path / "photos"
    photos.mkdir()
    for name in ("DJI_0001.JPG", "DJI_0002.JPG"):
        Image.new("RGB", (32, 24)).save(photos / name)
    with pytest.raises(RuntimeError) as err:
        run_algorithm("easyidp:camerafootprints", {
            "PROJECT": photos, "GROUND_HEIGHT": 0, "OUTPUT_CAMERAS": tmp_path / "cams.gpkg",
            "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    msg = str(err.value)
    assert "no GPS position" in msg and "DJI_0001.JPG, DJI_0002.JPG" in msg
    assert "no camera attitude" in msg and "Pix4D" not in msg
    assert not (tmp_path / "cams.gpkg").exists() and not (tmp_path / "fp.gpkg").exists()


@pytest.mark.parametrize("heights, why", [
    ({"CAMERA_HEIGHTS": 1}, "need the take-off height"),
    ({"CAMERA_HEIGHTS": 2}, "need a DSM"),
])
def test_camera_heights_need_their_input(qp_env, odm, tmp_path, heights, why):
    """Heights above the take-off point without the take-off height, or from the DSM without a
    DSM: the tool stops saying which parameter to set, and writes nothing."""
    with pytest.raises(RuntimeError, match=why):
        run_algorithm("easyidp:camerafootprints", {
            "PROJECT": odm / "images", "GROUND_HEIGHT": 80, **heights,
            "OUTPUT_CAMERAS": tmp_path / "cams.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"},
            qp_env)
    assert not (tmp_path / "cams.gpkg").exists() and not (tmp_path / "fp.gpkg").exists()
