"""The Processing tools inside real QGIS (offscreen): results, map loading, bad input."""
import hashlib
import os
import shutil

import numpy as np
import pytest
from qgis.core import (QgsApplication, QgsFeature, QgsGeometry, QgsProcessingContext,
                       QgsProcessingException, QgsProcessingFeedback, QgsProject, QgsRasterLayer,
                       QgsVectorLayer, QgsWkbTypes)

from easyidp_toolbox.tests.support.qgis_layers import memory_layer
from easyidp_toolbox.tests.support.synthetic import write_tif

ZONES = "data-to-science/zones_inside_test_tif.geojson"
DSM = "data-to-science/test.tif"


def _run(alg, params, feedback=None, context=None):
    import processing  # QGIS's processing plugin: importable once pytest-qgis initialised it
    context = context or QgsProcessingContext()
    return processing.run(alg, params, context=context, feedback=feedback or QgsProcessingFeedback())


def test_provider_and_algorithms_are_registered(provider):
    reg = QgsApplication.processingRegistry()
    assert reg.providerById("easyidp").name() == "EasyIDP"
    assert not provider.icon().isNull() and provider.svgIconPath().endswith("easyidp.svg")
    for alg_id in ("easyidp:croprasterbyrois", "easyidp:roiheightsfromdsm"):
        alg = reg.algorithmById(alg_id)
        assert alg is not None and alg.shortHelpString()


def test_plugin_registers_its_provider_in_init_processing(plugin):
    from easyidp_toolbox.easyidp_qgis.provider import EasyIDPProvider
    assert isinstance(plugin.provider, EasyIDPProvider)
    assert QgsApplication.processingRegistry().providerById("easyidp").id() == "easyidp"
    plugin.initProcessing()  # called again by initGui: no second provider
    assert [p.id() for p in QgsApplication.processingRegistry().providers()].count("easyidp") == 1


def test_crop_real_dsm_loads_nothing_unless_asked(provider, realdata, tmp_path):
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    res = _run("easyidp:croprasterbyrois",
               {"INPUT": str(realdata / DSM), "ROIS": str(realdata / ZONES), "NAME_FIELD": "row",
                "OUTPUT_FOLDER": str(tmp_path)}, context=context)
    assert res["CROPPED"] == 20 and res["SKIPPED"] == 0 and len(res["OUTPUT_FILES"]) == 20
    assert all(os.path.exists(f) for f in res["OUTPUT_FILES"])
    layer = QgsRasterLayer(res["OUTPUT_FILES"][0], "crop")
    assert layer.isValid() and layer.crs().authid() == "EPSG:32616"
    assert layer.dataProvider().sourceNoDataValue(1) == -32767
    # not asked to load (no index to open): nothing is queued, even with a project
    assert not context.layersToLoadOnCompletion()


def test_crop_rgb_gets_alpha_in_qgis(provider, tmp_path):
    img = np.random.default_rng(0).integers(0, 255, (200, 200, 3), dtype=np.uint8)
    src = write_tif(str(tmp_path / "dom.tif"), img, tile=64)
    rois = memory_layer("EPSG:32654", [("p1", "POLYGON((368010 3955990, 368040 3955990, "
                                                   "368040 3955960, 368010 3955990))")])
    res = _run("easyidp:croprasterbyrois", {"INPUT": src, "ROIS": rois, "NAME_FIELD": "name",
                                             "OUTPUT_FOLDER": str(tmp_path / "o")})
    layer = QgsRasterLayer(res["OUTPUT_FILES"][0], "p1")
    assert layer.bandCount() == 4 and os.path.basename(res["OUTPUT_FILES"][0]) == "p1.tif"
    from osgeo import gdal
    assert gdal.Open(res["OUTPUT_FILES"][0]).GetRasterBand(4).GetColorInterpretation() == gdal.GCI_AlphaBand


def test_heights_per_polygon_and_per_vertex(provider, realdata):
    from easyidp_toolbox.core import read_geojson
    from easyidp_toolbox.core.raster import dsm_roi_heights
    truth = dsm_roi_heights(str(realdata / DSM), read_geojson(str(realdata / ZONES)), statistic="median").values
    res = _run("easyidp:roiheightsfromdsm", {"ROIS": str(realdata / ZONES), "DSM": str(realdata / DSM),
                                             "MODE": 0, "STATISTIC": 1, "OUTPUT": "memory:"})
    layer = res["OUTPUT"]
    assert QgsWkbTypes.hasZ(layer.wkbType()) and layer.featureCount() == 20
    for feat, t in zip(layer.getFeatures(), truth):
        assert feat["height"] == pytest.approx(t)
        assert all(v.z() == pytest.approx(t) for v in feat.geometry().vertices())
        assert feat["row"] is not None  # source attributes kept
    res = _run("easyidp:roiheightsfromdsm", {"ROIS": str(realdata / ZONES), "DSM": str(realdata / DSM),
                                             "MODE": 1, "OUTPUT": "memory:"})
    zs = [v.z() for f in res["OUTPUT"].getFeatures() for v in f.geometry().vertices()]
    assert len(zs) == 100 and all(187 < z < 189 for z in zs)


def test_heights_missing_are_null_not_zero(provider, tmp_path):
    z = np.full((40, 40), -32767, np.float32)
    dsm = write_tif(str(tmp_path / "nd.tif"), z, nodata=-32767, pixel=1.0, origin=(368000, 3956000))
    rois = memory_layer("EPSG:32654", [("a", "POLYGON((368002 3955998, 368010 3955998, "
                                                  "368010 3955990, 368002 3955998))")])
    feedback = QgsProcessingFeedback()
    res = _run("easyidp:roiheightsfromdsm", {"ROIS": rois, "DSM": dsm, "OUTPUT": "memory:"}, feedback)
    feat = next(res["OUTPUT"].getFeatures())
    assert feat["height"] is None or str(feat["height"]) == "NULL"


def test_heights_output_geometry_of_every_polygon_kind(provider, tmp_path):
    """[independent] Per polygon, the output geometry is the ROI's own (x, y), closing vertices
    and holes included, as a MultiPolygonZ with Z = the height at every vertex, whatever the
    input carried (Z, M, single or multi), checked against the
    input's vertices and the mean of the DSM written here (a plane z = 10 + x/100)."""
    x0, y1 = 368000, 3956000
    cols = np.arange(40) + 0.5
    z = (10 + (x0 + cols) / 100)[None, :].repeat(40, axis=0).astype(np.float64)
    dsm = write_tif(str(tmp_path / "plane.tif"), z, pixel=1.0, origin=(x0, y1))
    wkts = [("zm", "PolygonZM", "POLYGON ZM((368002 3955998 5 1, 368012 3955998 5 1, 368012 3955990 5 1, "
                   "368002 3955990 5 1, 368002 3955998 5 1))"),
            ("holed", "MultiPolygon", "MULTIPOLYGON(((368020 3955998, 368036 3955998, 368036 3955982, "
                      "368020 3955982, 368020 3955998), (368024 3955994, 368030 3955994, "
                      "368030 3955988, 368024 3955988, 368024 3955994)))")]
    for name, kind, wkt in wkts:
        rois = memory_layer("EPSG:32654", [(name, wkt)], kind=kind)
        assert next(rois.getFeatures()).geometry().wkbType() == QgsGeometry.fromWkt(wkt).wkbType()
        res = _run("easyidp:roiheightsfromdsm", {"ROIS": rois, "DSM": dsm, "NAME_FIELD": "name",
                                                 "OUTPUT": "memory:"})
        feat = next(res["OUTPUT"].getFeatures())
        g = feat.geometry()
        assert QgsWkbTypes.hasZ(g.wkbType()) and g.isMultipart(), name
        assert all(v.z() == pytest.approx(feat["height"]) for v in g.vertices()), name
        src = QgsGeometry.fromWkt(wkt)
        assert [(v.x(), v.y()) for v in g.vertices()] == [(v.x(), v.y()) for v in src.vertices()]
        # the plane's mean over the polygon is the plane at the centroid of its pixel centres
        assert 10 + 368000 / 100 < feat["height"] < 10 + 368040 / 100, name
        assert feat["height"] == pytest.approx(10 + src.centroid().asPoint().x() / 100, abs=0.02), name



def test_heights_of_a_curved_roi_and_plain_ones_in_one_layer(provider, tmp_path):
    """[independent] A layer mixing a curved polygon (read through QGIS's vertices, not the
    one-pass WKB reader) with plain ones: every ROI gets the mean of a plane DSM written here
    (z = 10 + x/100) over its pixel centres, within the plane's range at its x extent, and a
    MultiPolygonZ with Z = that height."""
    x0, y1 = 368000, 3956000
    cols = np.arange(60) + 0.5
    z = (10 + (x0 + cols) / 100)[None, :].repeat(60, axis=0).astype(np.float64)
    dsm = write_tif(str(tmp_path / "plane.tif"), z, pixel=1.0, origin=(x0, y1))
    wkts = [("curve", "CURVEPOLYGON(CIRCULARSTRING(368010 3955980, 368020 3955990, 368030 "
                      "3955980, 368020 3955970, 368010 3955980))", (368010, 368030)),
            ("square", "POLYGON((368040 3955990, 368050 3955990, 368050 3955980, 368040 3955980, "
                       "368040 3955990))", (368040, 368050)),
            ("tri", "MULTIPOLYGON(((368002 3955950, 368008 3955950, 368005 3955956, "
                    "368002 3955950)))", (368002, 368008))]
    rois = memory_layer("EPSG:32654", [(n, w) for n, w, _ in wkts], kind="CurvePolygon")
    res = _run("easyidp:roiheightsfromdsm", {"ROIS": rois, "DSM": dsm, "OUTPUT": "memory:"})
    got = {f["name"]: f for f in res["OUTPUT"].getFeatures()}
    for name, wkt, (xa, xb) in wkts:
        f = got[name]
        assert 10 + xa / 100 < f["height"] < 10 + xb / 100, name
        g = f.geometry()
        assert QgsWkbTypes.hasZ(g.wkbType()) and g.isMultipart(), name
        assert all(v.z() == pytest.approx(f["height"]) for v in g.vertices()), name
    assert got["square"]["height"] == pytest.approx(10 + 368045 / 100, abs=1e-9)

# ---- bad input ---------------------------------------------------------------------------------

def _crop(src, rois, out, **kw):
    return _run("easyidp:croprasterbyrois", dict({"INPUT": src, "ROIS": rois, "OUTPUT_FOLDER": out}, **kw))


def test_non_geotiff_raster_layer_is_refused(provider, tmp_path, realdata):
    from osgeo import gdal
    asc = str(tmp_path / "dsm.asc")
    gdal.Translate(asc, str(realdata / DSM), format="AAIGrid")
    with pytest.raises(QgsProcessingException, match="dsm.asc is not a GeoTIFF.*Translate"):
        _crop(asc, str(realdata / ZONES), str(tmp_path / "o"))


def test_truncated_tiff_names_the_file(provider, tmp_path, realdata):
    data = (realdata / DSM).read_bytes()
    p = tmp_path / "cut.tif"
    p.write_bytes(data[: len(data) // 2])
    with pytest.raises(QgsProcessingException, match="cut.tif is (truncated|corrupt|not)"):
        _crop(str(p), str(realdata / ZONES), str(tmp_path / "o"))
    assert not _leftovers(tmp_path / "o")


def _leftovers(folder):
    """The temporary files (``core.files.part_name``) left in ``folder`` (none if it is absent)."""
    from easyidp_toolbox.core.files import is_part_name
    return [f for f in os.listdir(folder) if is_part_name(f)] if os.path.isdir(folder) else []


@pytest.mark.parametrize("target", ["A1.tif", "A1.part.tif", "notes", "plot.gpkg"])
def test_the_leftover_check_finds_a_planted_temporary_file(tmp_path, target):
    from easyidp_toolbox.core.files import part_name
    (tmp_path / target).write_bytes(b"done")
    assert _leftovers(tmp_path) == []
    part_name(tmp_path / target).write_bytes(b"half")
    assert _leftovers(tmp_path) == [part_name(tmp_path / target).name]


def test_raster_without_georeferencing(provider, tmp_path, realdata):
    p = write_tif(str(tmp_path / "plain.tif"), np.zeros((50, 50), np.float32), georef=False)
    with pytest.raises(QgsProcessingException, match="plain.tif has no georeferencing"):
        _crop(p, str(realdata / ZONES), str(tmp_path / "o"))


def test_rotated_raster_is_refused(provider, tmp_path, realdata):
    m = np.eye(4)
    m[0, :] = [0.5, 0.1, 0, 504630]
    m[1, :] = [0.1, -0.5, 0, 4588060]
    p = write_tif(str(tmp_path / "rot.tif"), np.zeros((50, 50), np.float32), transformation=m, epsg=32616)
    with pytest.raises(QgsProcessingException, match="rot.tif has a rotated geotransform"):
        _crop(p, str(realdata / ZONES), str(tmp_path / "o"))


def test_point_and_line_layers_are_refused(provider, tmp_path, realdata):
    for geom in ("Point", "LineString"):
        layer = QgsVectorLayer(f"{geom}?crs=EPSG:32616", "trees", "memory")
        f = QgsFeature()
        f.setGeometry(QgsGeometry.fromWkt("POINT(504640 4588050)" if geom == "Point"
                                          else "LINESTRING(504640 4588050, 504641 4588051)"))
        layer.dataProvider().addFeatures([f])
        with pytest.raises(QgsProcessingException, match="ROI"):
            _crop(str(realdata / DSM), layer, str(tmp_path / "o"))


def test_invalid_and_empty_polygons_are_named(provider, tmp_path, realdata):
    bow = memory_layer("EPSG:32616", [("bowtie", "POLYGON((504640 4588050, 504642 4588052, "
                                                     "504642 4588050, 504640 4588053, 504640 4588050))")])
    context = QgsProcessingContext()
    context.setInvalidGeometryCheck(QgsFeatureRequest_no_check())
    with pytest.raises(QgsProcessingException, match="bowtie.*crosses itself"):
        _run("easyidp:croprasterbyrois", {"INPUT": str(realdata / DSM), "ROIS": bow, "NAME_FIELD": "name",
                                          "OUTPUT_FOLDER": str(tmp_path / "o")}, context=context)
    empty = memory_layer("EPSG:32616", [("nothing", "POLYGON EMPTY")])
    with pytest.raises(QgsProcessingException, match="nothing.*empty"):
        _run("easyidp:croprasterbyrois", {"INPUT": str(realdata / DSM), "ROIS": empty, "NAME_FIELD": "name",
                                          "OUTPUT_FOLDER": str(tmp_path / "o")}, context=context)


def QgsFeatureRequest_no_check():  # noqa: N802
    from qgis.core import QgsFeatureRequest
    return QgsFeatureRequest.GeometryNoCheck


def test_invalid_polygon_with_default_settings_is_stopped(provider, tmp_path, realdata):
    bow = memory_layer("EPSG:32616", [("bowtie", "POLYGON((504640 4588050, 504642 4588052, "
                                                     "504642 4588050, 504640 4588053, 504640 4588050))")])
    with pytest.raises(QgsProcessingException, match="(?i)invalid|crosses itself"):
        _crop(str(realdata / DSM), bow, str(tmp_path / "o"))


def test_rois_in_another_crs_and_outside(provider, tmp_path, realdata):
    res = _crop(str(realdata / "d2spy/dsm.tif"), str(realdata / "d2spy/feature_in_dsm.geojson"),
                str(tmp_path / "o"))
    assert res["CROPPED"] == 1
    with pytest.raises(QgsProcessingException, match="None of the 1 ROIs overlaps the raster"):
        _crop(str(realdata / "d2spy/dsm.tif"), str(realdata / "d2spy/feature_outside_dsm.geojson"),
              str(tmp_path / "o2"))


def test_duplicate_names_and_input_in_output_folder(provider, tmp_path, realdata):
    folder = tmp_path / "work"
    folder.mkdir()
    src = folder / "test.tif"
    shutil.copy(realdata / DSM, src)
    digest = hashlib.sha256(src.read_bytes()).hexdigest()
    layer = memory_layer("EPSG:4326", [("test", "POLYGON((-86.94452 41.44408, -86.94450 41.44408, "
                                                    "-86.94450 41.44406, -86.94452 41.44408))"),
                                           ("test", "POLYGON((-86.94446 41.44408, -86.94444 41.44408, "
                                                    "-86.94444 41.44406, -86.94446 41.44408))")])
    with pytest.raises(QgsProcessingException, match="test.tif' is the input file itself"):
        _crop(str(src), layer, str(folder), NAME_FIELD="name", OVERWRITE=True)
    assert os.listdir(folder) == ["test.tif"]
    assert hashlib.sha256(src.read_bytes()).hexdigest() == digest
    res = _crop(str(src), layer, str(tmp_path / "crops"), NAME_FIELD="name")
    assert sorted(os.path.basename(f) for f in res["OUTPUT_FILES"]) == ["test.tif", "test_2.tif"]


class _CancelAfter(QgsProcessingFeedback):
    def __init__(self, n):
        super().__init__()
        self.n = n

    def isCanceled(self):  # noqa: N802
        self.n -= 1
        return self.n < 0


def test_cancel_mid_run_leaves_no_partial_file(provider, tmp_path):
    img = np.random.default_rng(0).integers(0, 255, (2048, 300, 3), dtype=np.uint8)
    src = write_tif(str(tmp_path / "dom.tif"), img, rowsperstrip=1)
    wkts = [(f"r{k}", f"POLYGON((368001 {3956000 - 40 * k - 1}, 368100 {3956000 - 40 * k - 1}, "
                     f"368100 {3956000 - 40 * k - 30}, 368001 {3956000 - 40 * k - 1}))") for k in range(25)]
    rois = memory_layer("EPSG:32654", wkts)
    out = tmp_path / "o"
    with pytest.raises(QgsProcessingException, match="Cancelled"):
        _run("easyidp:croprasterbyrois", {"INPUT": src, "ROIS": rois, "OUTPUT_FOLDER": str(out)},
             feedback=_CancelAfter(30))
    files = os.listdir(out)
    assert len(files) < 25 and all(f.endswith(".tif") and not f.startswith(".") for f in files)


def test_dsm_with_several_bands_is_refused(provider, realdata):
    with pytest.raises(QgsProcessingException, match="test_multispectral.tif has 6 bands"):
        _run("easyidp:roiheightsfromdsm", {"ROIS": str(realdata / ZONES),
                                           "DSM": str(realdata / "data-to-science/test_multispectral.tif"),
                                           "OUTPUT": "memory:"})


def test_missing_raster_file_is_named(provider, realdata, tmp_path):
    with pytest.raises(QgsProcessingException, match="/no/such/ortho.tif"):
        _crop("/no/such/ortho.tif", str(realdata / ZONES), str(tmp_path / "o"))
    with pytest.raises(QgsProcessingException, match="/no/such/dsm.tif"):
        _run("easyidp:roiheightsfromdsm", {"ROIS": str(realdata / ZONES), "DSM": "/no/such/dsm.tif",
                                           "OUTPUT": "memory:"})


def test_rois_are_reprojected_with_the_projects_transform_context(provider, tmp_path):
    """A datum transformation chosen in the project (here a custom operation that adds 10 m of
    easting) is what the tools use to bring lon/lat ROIs onto a UTM raster, as QGIS's own
    tools do; without it, PROJ's default is used."""
    from qgis.core import QgsCoordinateReferenceSystem, QgsCoordinateTransformContext
    import tifffile
    src = write_tif(str(tmp_path / "dem.tif"), np.zeros((200, 200), np.float32),
                    origin=(368000.0, 3956100.0), pixel=0.5)
    from pyproj import Transformer
    lon, lat = Transformer.from_crs(32654, 4326, always_xy=True).transform(368040.0, 3956040.0)
    d = 0.0002
    rois = memory_layer("EPSG:4326", [("p", f"POLYGON(({lon} {lat}, {lon + d} {lat}, "
                                                f"{lon + d} {lat + d}, {lon} {lat + d}, {lon} {lat}))")])
    plain = _run("easyidp:croprasterbyrois", {"INPUT": src, "ROIS": rois,
                                              "OUTPUT_FOLDER": str(tmp_path / "a")})
    tc = QgsCoordinateTransformContext()
    assert tc.addCoordinateOperation(
        QgsCoordinateReferenceSystem("EPSG:4326"), QgsCoordinateReferenceSystem("EPSG:32654"),
        "+proj=pipeline +step +proj=unitconvert +xy_in=deg "
        "+xy_out=rad +step +proj=utm +zone=54 +ellps=WGS84 +step +proj=affine +xoff=10")
    context = QgsProcessingContext()
    context.setTransformContext(tc)
    shifted = _run("easyidp:croprasterbyrois", {"INPUT": src, "ROIS": rois,
                                                "OUTPUT_FOLDER": str(tmp_path / "b")}, context=context)

    def origin(path):
        with tifffile.TiffFile(path) as t:
            return t.pages[0].tags[33922].value[3]
    assert origin(shifted["OUTPUT_FILES"][0]) - origin(plain["OUTPUT_FILES"][0]) == pytest.approx(10, abs=0.5)


def test_outputs_never_replace_inputs_each_other_or_existing_files(provider, realdata, tmp_path):
    """ROI heights writing over its own ROI GeoPackage, footprints with both outputs on one file,
    and a sink onto a user's existing file: each refused before anything is written."""
    gpkg = tmp_path / "plots.gpkg"
    from osgeo import gdal
    gdal.VectorTranslate(str(gpkg), str(realdata / ZONES), format="GPKG", layerName="plots")
    digest = hashlib.sha256(gpkg.read_bytes()).hexdigest()
    with pytest.raises(QgsProcessingException, match="is also the input 'ROIs"):
        _run("easyidp:roiheightsfromdsm", {"ROIS": f"{gpkg}|layername=plots",
                                           "DSM": str(realdata / DSM), "OUTPUT": str(gpkg)})
    assert hashlib.sha256(gpkg.read_bytes()).hexdigest() == digest
    one = tmp_path / "cams.gpkg"
    with pytest.raises(QgsProcessingException, match="are both .*cams.gpkg"):
        _run("easyidp:camerafootprints", {
            "PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx"), "GROUND_HEIGHT": 100,
            "OUTPUT_CAMERAS": str(one), "OUTPUT_FOOTPRINTS": str(one)})
    assert not one.exists()
    mine = tmp_path / "mine.gpkg"
    mine.write_bytes(b"a user's file")
    params = {"ROIS": str(realdata / ZONES), "DSM": str(realdata / DSM), "OUTPUT": str(mine)}
    with pytest.raises(QgsProcessingException, match="mine.gpkg already exists and nothing was written"):
        _run("easyidp:roiheightsfromdsm", params)
    assert mine.read_bytes() == b"a user's file"
    _run("easyidp:roiheightsfromdsm", dict(params, OVERWRITE=True))
    assert mine.read_bytes()[:15] == b"SQLite format 3"
