"""The point-cloud tools inside real QGIS (offscreen), on the real LAS/LAZ files of laspy."""
import os

import laspy
import numpy as np
import pytest
from plyfile import PlyData
from qgis.core import (QgsFeature, QgsGeometry, QgsProcessingContext, QgsProcessingException,
                       QgsProcessingFeedback, QgsProcessingOutputLayerDefinition,
                       QgsProcessingUtils, QgsProject, QgsVectorLayer)

from easyidp_toolbox.tests.support.pc_helpers import winding_inside
from easyidp_toolbox.tests.support.synthetic import write_tif

AUTZEN = "laspy/autzen_trim.laz"     # 110,000 points, CRS in the file (Oregon Lambert, ft)
SIMPLE = "laspy/simple.las"          # 1,065 points, no CRS
CRS = "EPSG:2994"                    # NAD83(HARN) / Oregon GIC Lambert (ft): autzen's CRS
CROP = "easyidp:croppointcloudbyrois"
STATS = "easyidp:pointcloudroistatistics"

# inside autzen (x 636001-637179, y 848935-849498); vertices off the 0.01 ft LAS grid
SQUARE = [(636100.013, 849000.017), (636300.029, 849000.017), (636300.029, 849180.031),
          (636100.013, 849180.031)]
HOLED = ([(636500.011, 849050.013), (636800.037, 849050.013), (636800.037, 849350.019),
          (636500.011, 849350.019)],
         [(636600.023, 849150.029), (636700.031, 849150.029), (636700.031, 849250.037),
          (636600.023, 849250.037)])
PARTS = [[(636900.007, 849300.011), (637000.019, 849300.011), (636950.013, 849420.023)],
         [(637050.017, 849000.021), (637150.027, 849000.021), (637150.027, 849080.029)]]
OUTSIDE = [(640000.01, 849000.01), (640100.01, 849000.01), (640100.01, 849100.01)]
# simple.las (x 635620-638983, y 848900-853535)
SIMPLE_ROI = [(636000.013, 849500.017), (637500.029, 849500.017), (637500.029, 851500.031),
              (636000.013, 851500.031)]


def _run(alg, params, feedback=None, context=None):
    import processing  # QGIS's processing plugin: importable once pytest-qgis initialised it
    context = context or QgsProcessingContext()
    return processing.run(alg, params, context=context, feedback=feedback or QgsProcessingFeedback())


def _wkt_ring(ring):
    return "(" + ", ".join(f"{x} {y}" for x, y in list(ring) + [ring[0]]) + ")"


def _wkt(poly):
    """WKT of a ring list [outer, hole…] or of a list of single-ring parts (MultiPolygon)."""
    if isinstance(poly, tuple):
        return "POLYGON(" + ", ".join(_wkt_ring(r) for r in poly) + ")"
    if isinstance(poly[0][0], tuple):
        return "MULTIPOLYGON(" + ", ".join("(" + _wkt_ring(p) + ")" for p in poly) + ")"
    return "POLYGON(" + _wkt_ring(poly) + ")"


def _rings(poly):
    if isinstance(poly, tuple):
        return [np.array(r) for r in poly]
    if isinstance(poly[0][0], tuple):
        return [np.array(p) for p in poly]
    return [np.array(poly)]


def _rois(named, crs=CRS):
    layer = QgsVectorLayer(f"MultiPolygon?crs={crs}&field=name:string", "plots", "memory")
    feats = []
    for name, poly in named:
        f = QgsFeature(layer.fields())
        f.setAttributes([name])
        f.setGeometry(QgsGeometry.fromWkt(_wkt(poly)))
        feats.append(f)
    layer.dataProvider().addFeatures(feats)
    return layer


PLOTS = [("square", SQUARE), ("holed", HOLED), ("parts", PARTS)]


def _las(realdata, rel):
    las = laspy.read(str(realdata / rel))
    return np.column_stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)])


def _truth(xyz, poly, z_min=-np.inf, z_max=np.inf):
    """Independent selection: winding-number point-in-polygon (even-odd over rings) and Z range."""
    inside = np.zeros(len(xyz), bool)
    rings = _rings(poly)
    if isinstance(poly, tuple):
        inside = winding_inside(xyz[:, 0], xyz[:, 1], rings)
    else:  # parts do not overlap: a point is in one of them
        for ring in rings:
            inside |= winding_inside(xyz[:, 0], xyz[:, 1], [ring])
    return inside & (xyz[:, 2] >= z_min) & (xyz[:, 2] <= z_max)


class _Log(QgsProcessingFeedback):
    def __init__(self, cancel_after=None):
        super().__init__()
        self.infos, self.warnings, self.n = [], [], cancel_after

    def pushInfo(self, text):  # noqa: N802
        self.infos.append(text)
        super().pushInfo(text)

    def pushWarning(self, text):  # noqa: N802
        self.warnings.append(text)
        super().pushWarning(text)

    def isCanceled(self):  # noqa: N802
        if self.n is None:
            return False
        self.n -= 1
        return self.n < 0


@pytest.fixture(scope="module")
def autzen(realdata):
    return _las(realdata, AUTZEN)


# ---- Crop point cloud by ROIs ------------------------------------------------------------------

def test_crop_counts_equal_an_independent_count(provider, realdata, autzen, tmp_path):
    log = _Log()
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    res = _run(CROP, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS + [("far", OUTSIDE)]),
                      "NAME_FIELD": "name", "OUTPUT_FOLDER": str(tmp_path / "o"),
                      "OUTPUT_INDEX": QgsProcessingOutputLayerDefinition("TEMPORARY_OUTPUT",
                                                                         QgsProject.instance()),
                      "OPEN_FILES": True},
               log, context)
    assert (res["CROPPED"], res["EMPTY"], res["MISSED"]) == (3, 0, 1)
    index = {f["name"]: (f["points"], f["crop_status"]) for f in res["OUTPUT_INDEX"].getFeatures()}
    assert index["far"] == (0, "missed") and all(index[n][1] == "written" for n, _ in PLOTS)
    assert res["OUTPUT_FOLDER"] == str(tmp_path / "o")
    assert [os.path.basename(f) for f in res["OUTPUT_FILES"]] == ["square.laz", "holed.laz", "parts.laz"]
    for (name, poly), path in zip(PLOTS, res["OUTPUT_FILES"]):
        truth = autzen[_truth(autzen, poly)]
        out = laspy.read(path)
        assert len(out.points) == len(truth) > 100, name
        got = np.column_stack([out.x, out.y, out.z])
        assert np.array_equal(got[np.lexsort(got.T)], truth[np.lexsort(truth.T)])
        assert out.header.parse_crs() is not None and out.header.point_format.id == 3
    assert any("far" in w and "outside the point cloud" in w for w in log.warnings)
    from easyidp_toolbox.easyidp_qgis.algorithms.crop_point_cloud_by_rois import \
        point_cloud_provider_available
    if not point_cloud_provider_available():        # the log says why nothing was queued
        assert any("no point cloud provider" in i for i in log.infos)
        assert [d.outputName for d in context.layersToLoadOnCompletion().values()] == ["OUTPUT_INDEX"]


def test_crop_queues_las_outputs_where_qgis_has_a_point_cloud_provider(provider, realdata, tmp_path,
                                                                       monkeypatch):
    from easyidp_toolbox.easyidp_qgis.algorithms import crop_point_cloud_by_rois as module
    monkeypatch.setattr(module, "point_cloud_provider_available", lambda: True)
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    params = {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "NAME_FIELD": "name",
              "OUTPUT_FOLDER": str(tmp_path / "o")}
    _run(CROP, params, context=context)
    assert not context.layersToLoadOnCompletion()          # loading not asked for
    params.update(OUTPUT_FOLDER=str(tmp_path / "o2"), OUTPUT_INDEX=QgsProcessingOutputLayerDefinition(
        "TEMPORARY_OUTPUT", QgsProject.instance()))
    _run(CROP, params, context=context)                   # the index opens; the crops not asked
    assert [d.outputName for d in context.layersToLoadOnCompletion().values()] == ["OUTPUT_INDEX"]
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    params.update(OUTPUT_FOLDER=str(tmp_path / "o3"), OPEN_FILES=True)
    _run(CROP, params, context=context)
    queued = context.layersToLoadOnCompletion()
    clouds = {d.name: d.layerTypeHint for d in queued.values() if d.outputName == "OUTPUT_FILES"}
    assert clouds == {n: QgsProcessingUtils.LayerHint.PointCloud for n in ("holed", "parts", "square")}
    assert [d.name for d in queued.values() if d.outputName == "OUTPUT_INDEX"] == \
        ["Index of the point cloud crops"]


def test_format_conversion_and_z_range(provider, realdata, autzen, tmp_path):
    z_min, z_max = 420.0, 450.0
    for fmt, ext in ((1, ".las"), (3, ".ply")):
        res = _run(CROP, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "NAME_FIELD": "name",
                          "Z_MIN": z_min, "Z_MAX": z_max, "FORMAT": fmt,
                          "OUTPUT_FOLDER": str(tmp_path / ext[1:])})
        assert res["CROPPED"] == 3 and all(f.endswith(ext) for f in res["OUTPUT_FILES"])
        for (name, poly), path in zip(PLOTS, res["OUTPUT_FILES"]):
            truth = autzen[_truth(autzen, poly, z_min, z_max)]
            if ext == ".ply":
                v = PlyData.read(path)["vertex"]
                got = np.column_stack([v["x"], v["y"], v["z"]]).astype(np.float64)
                assert {"red", "green", "blue", "intensity"} <= set(v.data.dtype.names)
            else:
                las = laspy.read(path)
                got = np.column_stack([las.x, las.y, las.z])
                assert las.header.are_points_compressed is False
            assert len(got) == len(truth) > 10, (fmt, name)
            assert np.allclose(got[np.lexsort(got.T)], truth[np.lexsort(truth.T)], atol=1e-6, rtol=0)


def test_las_without_crs_needs_input_crs(provider, realdata, tmp_path):
    rois = _rois([("a", SIMPLE_ROI)])
    with pytest.raises(QgsProcessingException, match="simple.las.*no coordinate reference system.*INPUT_CRS"):
        _run(CROP, {"INPUT": str(realdata / SIMPLE), "ROIS": rois, "OUTPUT_FOLDER": str(tmp_path / "o")})
    res = _run(CROP, {"INPUT": str(realdata / SIMPLE), "INPUT_CRS": CRS, "ROIS": rois,
                      "NAME_FIELD": "name", "OUTPUT_FOLDER": str(tmp_path / "o")})
    xyz = _las(realdata, SIMPLE)
    out = laspy.read(res["OUTPUT_FILES"][0])
    assert len(out.points) == _truth(xyz, SIMPLE_ROI).sum() > 50
    assert out.header.parse_crs().to_epsg() == 2994  # the CRS given is written into the crop


def test_ply_without_crs_is_refused_and_works_with_one(provider, realdata, autzen, tmp_path):
    box = [(636050.011, 848990.013), (636400.037, 848990.013), (636250.019, 849350.019)]
    ply = _run(CROP, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois([("whole", box)]),
                      "NAME_FIELD": "name", "FORMAT": 3,
                      "OUTPUT_FOLDER": str(tmp_path / "ply")})["OUTPUT_FILES"][0]
    rois = _rois([("square", SQUARE)])
    with pytest.raises(QgsProcessingException, match="whole.ply.*no coordinate reference system.*INPUT_CRS"):
        _run(CROP, {"INPUT": ply, "ROIS": rois, "OUTPUT_FOLDER": str(tmp_path / "o")})
    res = _run(CROP, {"INPUT": ply, "INPUT_CRS": CRS, "ROIS": rois, "NAME_FIELD": "name",
                      "FORMAT": 2, "OUTPUT_FOLDER": str(tmp_path / "o")})
    assert res["OUTPUT_FILES"][0].endswith("square.laz")
    # the square is partly outside the triangle cut to PLY: an independent count of both
    both = _truth(autzen, SQUARE) & _truth(autzen, box)
    assert len(laspy.read(res["OUTPUT_FILES"][0]).points) == both.sum()


def test_no_roi_over_the_cloud_is_an_error(provider, realdata, tmp_path):
    with pytest.raises(QgsProcessingException, match="None of the 1 ROIs overlaps the point cloud"):
        _run(CROP, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois([("far", OUTSIDE)]),
                    "OUTPUT_FOLDER": str(tmp_path / "o")})


def test_empty_crops_are_reported_and_written_only_when_asked(provider, realdata, tmp_path):
    params = {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "NAME_FIELD": "name",
              "Z_MIN": 9000, "OUTPUT_FOLDER": str(tmp_path / "o")}
    log = _Log()
    res = _run(CROP, params, log)
    assert (res["CROPPED"], res["EMPTY"], res["OUTPUT_FILES"]) == (0, 3, [])
    assert any("contain no point" in w and "square" in w for w in log.warnings)
    res = _run(CROP, dict(params, WRITE_EMPTY=True))
    assert len(res["OUTPUT_FILES"]) == 3 and len(laspy.read(res["OUTPUT_FILES"][0]).points) == 0
    with pytest.raises(QgsProcessingException, match="Z range"):
        _run(CROP, dict(params, Z_MIN=500, Z_MAX=400))


def test_cancel_removes_every_crop(provider, realdata, tmp_path):
    out = tmp_path / "o"
    with pytest.raises(QgsProcessingException, match="Cancelled"):  # after two of three crops
        _run(CROP, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "OUTPUT_FOLDER": str(out)},
             _Log(cancel_after=6))
    assert not out.exists() or os.listdir(out) == []


@pytest.mark.parametrize("name, make, message", [
    ("missing.las", None, "does not exist"),
    ("cut.las", lambda d: d[: len(d) // 2], "cut.las.*truncated"),
    ("cut.laz", lambda d: d[: len(d) // 2], "cut.laz.*(truncated|cannot be read)"),
    ("noise.ply", lambda d: b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n",
     "noise.ply.*x/y/z"),
    ("cloud.txt", lambda d: d, "unsupported file type"),
])
def test_bad_point_cloud_files(provider, realdata, tmp_path, name, make, message):
    path = tmp_path / name
    if make is not None:
        src = realdata / (AUTZEN if name.endswith(".laz") else SIMPLE)
        path.write_bytes(make(src.read_bytes()))
    for alg, extra in ((CROP, {"OUTPUT_FOLDER": str(tmp_path / "o")}), (STATS, {"OUTPUT": "memory:"})):
        with pytest.raises(QgsProcessingException, match=message):
            _run(alg, dict({"INPUT": str(path), "INPUT_CRS": CRS, "ROIS": _rois(PLOTS)}, **extra))
    assert not (tmp_path / "o").exists() or os.listdir(tmp_path / "o") == []


# ---- Point cloud statistics per ROI ------------------------------------------------------------

def _stats(realdata, rois, **params):
    log = _Log()
    res = _run(STATS, dict({"INPUT": str(realdata / AUTZEN), "ROIS": rois, "OUTPUT": "memory:"},
                           **params), log)
    return {f["name"]: f for f in res["OUTPUT"].getFeatures()}, res["OUTPUT"], log


def test_statistics_with_the_rois_own_ground(provider, realdata, autzen):
    rows, layer, log = _stats(realdata, _rois(PLOTS + [("far", OUTSIDE)]))
    names = layer.fields().names()
    assert names == ["name", "count", "density", "z_min", "z_mean", "z_max", "ground", "h_mean",
                     "h_max", "h_p5", "h_p50", "h_p95", "h_p99"]
    assert layer.crs().authid() == CRS and layer.featureCount() == 4
    for name, poly in PLOTS:
        z = autzen[_truth(autzen, poly), 2]
        row = rows[name]
        assert row["count"] == len(z) > 100
        assert row["z_min"] == pytest.approx(z.min()) and row["z_max"] == pytest.approx(z.max())
        g = np.percentile(z, 1)
        assert row["ground"] == pytest.approx(g)
        assert row["h_p95"] == pytest.approx(np.percentile(z - g, 95))
        assert row["density"] == pytest.approx(len(z) / rows[name].geometry().area(), rel=1e-6)
    far = rows["far"]
    assert far["count"] == 0 and far["density"] == 0
    assert all(far[k] is None or str(far[k]) == "NULL" for k in names[3:])  # never 0
    assert any("contain no point" in w for w in log.warnings)


def test_statistics_above_a_ground_height_and_a_ground_dsm(provider, realdata, autzen, tmp_path):
    sel = _truth(autzen, SQUARE)
    z = autzen[sel, 2]
    rows, _, _ = _stats(realdata, _rois([("square", SQUARE)]), GROUND_HEIGHT=400,
                        PERCENTILES="50, 99.5")
    row = rows["square"]
    assert row["ground"] == 400 and row["h_mean"] == pytest.approx(z.mean() - 400)
    assert row["h_p99_5"] == pytest.approx(np.percentile(z - 400, 99.5))
    # a tilted DTM in the cloud's CRS: bilinear sampling is exact on a plane
    x0, y0, px = 635990.0, 849510.0, 10.0
    cy, cx = np.mgrid[0:70, 0:130] + 0.5
    plane = (390 + 0.01 * cx * px + 0.02 * cy * px).astype(np.float64)
    dtm = write_tif(str(tmp_path / "dtm.tif"), plane, origin=(x0, y0), pixel=px, epsg=2994)
    rows, _, _ = _stats(realdata, _rois([("square", SQUARE)]), GROUND_DSM=dtm)
    g = 390 + 0.01 * (autzen[sel, 0] - x0) + 0.02 * (y0 - autzen[sel, 1])
    assert rows["square"]["ground"] == pytest.approx(g.mean())
    assert rows["square"]["h_p95"] == pytest.approx(np.percentile(z - g, 95))
    with pytest.raises(QgsProcessingException, match="not both"):
        _stats(realdata, _rois([("square", SQUARE)]), GROUND_DSM=dtm, GROUND_HEIGHT=400)


def test_ground_dsm_in_another_crs_is_sampled_at_the_reprojected_points(provider, realdata, autzen,
                                                                       tmp_path):
    from pyproj import Transformer
    x, y = Transformer.from_crs(CRS, "EPSG:32610", always_xy=True).transform(
        [636100.0, 636300.0], [849000.0, 849180.0])
    # a flat UTM DTM just around the square: points not reprojected would all miss it
    dtm = write_tif(str(tmp_path / "utm.tif"), np.full((100, 100), 410.0, np.float32),
                    origin=(min(x) - 10, max(y) + 10), pixel=1.0, epsg=32610)
    rows, _, _ = _stats(realdata, _rois([("square", SQUARE)]), GROUND_DSM=dtm)
    z = autzen[_truth(autzen, SQUARE), 2]
    assert rows["square"]["ground"] == 410 and rows["square"]["h_max"] == pytest.approx(z.max() - 410)


def test_statistics_bad_input(provider, realdata, tmp_path):
    rois = _rois([("a", SIMPLE_ROI)])
    with pytest.raises(QgsProcessingException, match="simple.las.*no coordinate reference system.*INPUT_CRS"):
        _run(STATS, {"INPUT": str(realdata / SIMPLE), "ROIS": rois, "OUTPUT": "memory:"})
    res = _run(STATS, {"INPUT": str(realdata / SIMPLE), "INPUT_CRS": CRS, "ROIS": rois,
                       "OUTPUT": "memory:"})
    assert next(res["OUTPUT"].getFeatures())["count"] == _truth(_las(realdata, SIMPLE), SIMPLE_ROI).sum()
    with pytest.raises(QgsProcessingException, match="Percentiles: 'abc'"):
        _stats(realdata, _rois(PLOTS), PERCENTILES="5,abc")
    with pytest.raises(QgsProcessingException, match="Percentiles: '150'"):
        _stats(realdata, _rois(PLOTS), PERCENTILES="150")
    out = tmp_path / "far.gpkg"     # a failed run leaves no output file behind
    with pytest.raises(QgsProcessingException, match="None of the 1 ROIs contains a point"):
        _stats(realdata, _rois([("far", OUTSIDE)]), OUTPUT=str(out))
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    with pytest.raises(QgsProcessingException, match="Cancelled"):
        _run(STATS, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "OUTPUT": "memory:"},
             _Log(cancel_after=4))


def test_unreadable_crs_record_is_a_warning_in_the_log(provider, realdata, tmp_path):
    las = laspy.read(str(realdata / SIMPLE))
    las.header.vlrs.append(laspy.vlrs.known.WktCoordinateSystemVlr("this is not WKT"))
    path = tmp_path / "badcrs.las"
    las.write(str(path))
    log = _Log()
    _run(CROP, {"INPUT": str(path), "INPUT_CRS": CRS, "ROIS": _rois([("s", SIMPLE_ROI)]),
                "OUTPUT_FOLDER": str(tmp_path / "o")}, log)
    assert any("badcrs.las" in w and "CRS record cannot be read" in w for w in log.warnings)


def test_all_nodata_ground_raster_is_a_warning(provider, realdata, tmp_path):
    x0, y1 = 636000.0, 849600.0
    dsm = write_tif(str(tmp_path / "ground.tif"), np.full((80, 80), -9999, np.float32),
                    origin=(x0, y1), pixel=20.0, nodata=-9999, epsg=2994)
    log = _Log()
    _run(STATS, {"INPUT": str(realdata / AUTZEN), "ROIS": _rois(PLOTS), "GROUND_DSM": dsm,
                 "OUTPUT": str(tmp_path / "s.gpkg")}, log)
    assert any("has no data under the points of 3 of the 3 ROIs" in w for w in log.warnings), \
        log.warnings
