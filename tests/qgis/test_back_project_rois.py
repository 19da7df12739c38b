"""Back-project ROIs in real QGIS (offscreen) and through qgis_process.

The photo-pixel layer's convention (x = column, y = −row) is checked against how QGIS itself
places a raw photo opened without georeference: that is the truth here, not our code.
"""
import json
import os

import numpy as np
import pytest
from qgis.core import (QgsApplication, QgsCoordinateReferenceSystem, QgsMapSettings, QgsPointXY,
                       QgsProcessingContext, QgsProcessingException,
                       QgsProcessingOutputLayerDefinition,
                       QgsProcessingFeedback, QgsProject, QgsRaster, QgsRasterLayer,
                       QgsRectangle, QgsVectorLayer)

ALG = "easyidp:backprojectrois"


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("bp_qgis")), seed=0, size="small")


def _run(params, context=None):
    import processing
    base = {"OUTPUT": "memory:", "OUTPUT_SUMMARY": "memory:"}
    return processing.run(ALG, dict(base, **params), context=context or QgsProcessingContext(),
                          feedback=QgsProcessingFeedback())


def test_qgis_places_a_raw_photo_at_x_column_y_minus_row(survey):
    """Truth kind: QGIS/GDAL. A JPEG without georeference spans x 0..w, y −h..0, and the
    pixel in row r, column c is found at (c + 0.5, −(r + 0.5))."""
    from easyidp_toolbox.core.projection import read_photo
    path = survey.photos[0]
    layer = QgsRasterLayer(path, "photo")
    assert layer.isValid()
    assert layer.extent() == QgsRectangle(0, -600, 800, 0) and not layer.crs().isValid()
    img = read_photo(path)
    prov = layer.dataProvider()
    for r, c in ((0, 0), (10, 700), (599, 799), (321, 123)):
        res = prov.identify(QgsPointXY(c + 0.5, -(r + 0.5)), QgsRaster.IdentifyFormatValue)
        vals = [res.results()[b] for b in (1, 2, 3)]
        assert vals == img[r, c].tolist()


def test_backproject_demo_plots(provider, survey, tmp_path):
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    res = _run({"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
                "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 1, "DSM": survey.dsm,
                "MAX_IMAGES": 4, "OUTPUT_JSON": str(tmp_path / "back2raw.json"),
                "CROPS_FOLDER": str(tmp_path / "crops"),
                "PREVIEW_FOLDER": str(tmp_path / "previews")}, context)
    pix, summary = res["OUTPUT"], res["OUTPUT_SUMMARY"]
    assert not pix.crs().isValid()          # photo pixels: no CRS, like the photo in QGIS
    feats = list(pix.getFeatures())
    assert 40 < len(feats) <= 160
    for f in feats:
        assert f["rank"] <= 4 and 0 < f["score"] <= 1 and f["photo_path"].endswith(".JPG")
        assert 0 <= f["occluded_fraction"] <= 0.5         # tested against the DSM (default on)
        box = f.geometry().boundingBox()
        assert box.xMinimum() >= -1e-6 and box.xMaximum() <= 800 + 1e-6
        assert box.yMaximum() <= 1e-6 and box.yMinimum() >= -600 - 1e-6
    assert summary.featureCount() == 40 and summary.crs().authid() == "EPSG:32654"
    for f in summary.getFeatures():
        assert f["photos"] >= 1 and f["best_photo"].startswith("DJI_") and f["best_score"] > 0
    # the polygons agree with the core result and with the JSON (x = column, y = -row)
    with open(res["OUTPUT_JSON"]) as fh:
        d = json.load(fh)
    f = feats[0]
    ring = np.array(d[f["roi"]][f["photo"]])
    verts = np.array([[p.x(), p.y()] for p in f.geometry().vertices()])
    assert np.allclose(verts, ring * [1, -1], atol=1e-9)
    # crops and previews
    crops = sorted((tmp_path / "crops").rglob("*.png"))
    assert len(crops) == len(feats) and len(list((tmp_path / "previews").glob("*.png"))) == 40
    side = json.loads(crops[0].with_suffix(".json").read_text())
    assert side["roi"] == crops[0].parent.name and "pixels" in side
    # overlay in QGIS's own placement: the polygon's centroid lies over the photo, and in a
    # map of any CRS neither CRS-less layer is transformed, so they stay on top of each other
    photo = QgsRasterLayer(f["photo_path"], "p")
    c = f.geometry().centroid().asPoint()
    assert photo.extent().contains(c)
    ms = QgsMapSettings()
    ms.setDestinationCrs(QgsCoordinateReferenceSystem("EPSG:32654"))
    for layer in (photo, pix):
        assert ms.layerToMapCoordinates(layer, QgsPointXY(c)) == QgsPointXY(c)


def test_whole_only_and_constant_height(provider, survey):
    res = _run({"ROIS": survey.plots_gpkg, "PROJECT": survey.pix4d_project, "HEIGHT_SOURCE": 3,
                "GROUND_HEIGHT": 95.5, "CLIP": 1, "MIN_VISIBLE": 0})
    feats = list(res["OUTPUT"].getFeatures())
    assert feats and all(not f["clipped"] and f["visible_fraction"] == 1 for f in feats)


@pytest.mark.parametrize("params, message", [
    ({"HEIGHT_SOURCE": 1}, "choose the DSM"),
    ({"HEIGHT_SOURCE": 2}, "choose the height attribute"),
    ({"HEIGHT_SOURCE": 3}, "give the height"),
    ({"HEIGHT_SOURCE": 0}, "have no Z"),
])
def test_missing_height_source(provider, survey, params, message):
    with pytest.raises(QgsProcessingException, match=message):
        _run(dict({"ROIS": survey.plots_gpkg, "PROJECT": survey.metashape_project}, **params))


def test_photos_folder_of_other_photos(provider, survey, tmp_path):
    other = tmp_path / "other"
    other.mkdir()
    (other / "IMG_9999.JPG").write_bytes(b"not a photo")
    with pytest.raises(QgsProcessingException, match="holds none of the project's"):
        _run({"ROIS": survey.plots_gpkg, "PROJECT": survey.metashape_project,
              "HEIGHT_SOURCE": 3, "GROUND_HEIGHT": 95.5, "PHOTOS": str(other),
              "CROPS_FOLDER": str(tmp_path / "crops")})


def test_through_qgis_process(qp_env, survey, tmp_path):
    from easyidp_toolbox.scripts.qgis_process import run_algorithm
    res = run_algorithm(ALG, {"ROIS": survey.plots_geojson, "NAME_FIELD": "plot_id",
                              "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 1,
                              "DSM": survey.dsm, "MAX_IMAGES": 2,
                              "OUTPUT": tmp_path / "pixels.gpkg",
                              "OUTPUT_SUMMARY": tmp_path / "summary.gpkg",
                              "OUTPUT_JSON": tmp_path / "b.json",
                              "CROPS_FOLDER": tmp_path / "crops"}, qp_env)
    layer = QgsVectorLayer(res["OUTPUT"], "pixels", "ogr")
    assert layer.isValid() and layer.featureCount() == 80
    # GeoPackage has no "no CRS": GDAL stores its undefined SRS (QGIS shows "Undefined ...")
    assert not layer.crs().isValid() or layer.crs().description().startswith("Undefined")
    assert QgsVectorLayer(res["OUTPUT_SUMMARY"], "s", "ogr").featureCount() == 40
    assert os.path.isfile(res["OUTPUT_JSON"]) and len(list((tmp_path / "crops").rglob("*.png"))) == 80


def test_photo_pixel_layer_is_the_core_result_record_by_record(provider, survey, tmp_path):
    """The GeoPackage the tool writes (columns converted at once, geometries built in one pass)
    holds each record of the core's result, in order: the reference is the result itself, read
    element by element here (NaN as NULL; x = column, y = −row, rings closed)."""
    from qgis.core import QgsApplication
    params = {"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
              "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 3, "GROUND_HEIGHT": 95.5,
              "MIN_VISIBLE": 0, "OUTPUT": str(tmp_path / "pixels.gpkg"),
              "OUTPUT_SUMMARY": str(tmp_path / "summary.gpkg")}
    alg = QgsApplication.processingRegistry().createAlgorithmById(ALG)
    step = alg.step(params, QgsProcessingContext(), QgsProcessingFeedback())
    result = step.function(**step.kwargs)
    assert result.clipped.any() and np.isnan(result.occluded_fraction).all()
    layer = QgsVectorLayer(_run(params)["OUTPUT"], "pixels", "ogr")
    feats = sorted(layer.getFeatures(), key=lambda f: f.id())
    assert len(feats) == len(result) > 40
    for i, f in enumerate(feats):
        j = int(result.photo_index[i])
        want = [result.roi_names[result.roi[i]], str(result.photo[i]), result.photo_paths[j],
                int(result.rank[i]), float(result.score[i]), float(result.view_angle[i]),
                float(result.gsd[i]), float(result.visible_fraction[i]), None,
                float(result.centre_distance[i]), bool(result.clipped[i]),
                int(result.image_sizes[j][0]), int(result.image_sizes[j][1]),
                None]                     # uncertainty_px: NULL for a solved project
        assert result.uncertainty_px.get(str(result.photo[i])) is None
        got = [None if v is None or (hasattr(v, "isNull") and v.isNull()) else v
               for v in f.attributes()[1:]]
        assert got == want, i
        polys = result.polygons_of(i)
        geom = f.geometry().constGet()
        assert geom.numGeometries() == len(polys)
        for k, rings in enumerate(polys):
            part = geom.geometryN(k)
            assert part.numInteriorRings() == len(rings) - 1
            for r, ring in enumerate(rings):
                line = part.exteriorRing() if r == 0 else part.interiorRing(r - 1)
                xy = np.array([[p.x(), p.y()] for p in line.points()])
                assert np.array_equal(xy, np.vstack([ring, ring[:1]]) * [1.0, -1.0])


def test_photo_pixels_go_to_the_viewer_not_to_the_map(provider, survey, load_results, tmp_path):
    """Back-project ROIs with both outputs saved to GeoPackages and set to open, loaded by
    QGIS's own loader: the summary lands in the layer tree; the layer in photo pixels goes
    into the project without a place in the tree and without a CRS, marked for the photo
    viewer, so no map ever draws it (a GeoPackage gives it the undefined Cartesian SRS, which a
    map in EPSG:32654 reports as "No transform available")."""
    from easyidp_toolbox.easyidp_qgis import presentation
    proj = QgsProject()
    plots = QgsVectorLayer(survey.plots_gpkg, "plots", "ogr")
    proj.addMapLayer(plots)
    context = QgsProcessingContext()
    context.setProject(proj)
    feedback = QgsProcessingFeedback()
    params = {"ROIS": plots.id(), "NAME_FIELD": "plot_id", "PROJECT": survey.metashape_project,
              "HEIGHT_SOURCE": 3, "GROUND_HEIGHT": 95.0, "MAX_IMAGES": 2,
              "OUTPUT": QgsProcessingOutputLayerDefinition(str(tmp_path / "pixels.gpkg"), proj),
              "OUTPUT_SUMMARY": QgsProcessingOutputLayerDefinition(str(tmp_path / "summary.gpkg"),
                                                                    proj)}
    alg = QgsApplication.processingRegistry().createAlgorithmById(ALG)
    _, ok = alg.run(params, context, feedback)
    assert ok, feedback.textLog()
    assert load_results(alg, context, feedback, params)
    in_tree = [n.layer().name() for n in proj.layerTreeRoot().findLayers()]
    assert "plots: photos of demo_survey.psx that see them" in in_tree
    pixels = presentation.photo_pixel_layers(proj)
    assert [v.name() for v in pixels] == ["plots in the photos of demo_survey.psx (photo pixels)"]
    layer = pixels[0]
    assert layer.name() not in in_tree and not layer.crs().isValid()
    assert layer.source().startswith(str(tmp_path / "pixels.gpkg")) and layer.featureCount() > 40
    assert layer.renderer().type() == "RuleRenderer"


def test_crops_in_celsius(provider, survey, tmp_path):
    """[independent] Crops with VALUES = temperature from the demo's thermal photos (FLIR
    JPEGs of a known field): GDAL reads float32 TIFFs whose first band says degC, with NaN
    nodata and the conversion note; each crop pixel equals the raw value flyr (an independent
    FLIR reader) decodes at that photo pixel, converted by the test's own Planck formula, to
    0.01 °C."""
    import flyr
    from osgeo import gdal
    from easyidp_toolbox.core.demo.thermal import THERMAL_CAMERA, write_thermal_photos
    from easyidp_toolbox.tests.support.planck_reference import planck_by_hand
    th = write_thermal_photos(survey.folder, seed=0, limit=2)
    res = _run({"ROIS": survey.plots_geojson, "NAME_FIELD": "plot_id",
                "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 1, "DSM": survey.dsm,
                "OCCLUSION": False, "PHOTO": "DJI_0002", "PHOTOS": th["folder"],
                "CROPS_FOLDER": str(tmp_path / "crops"), "VALUES": 1})
    c = {k: float(v) for k, v in THERMAL_CAMERA.as_dict().items()}
    raw = flyr.unpack(os.path.join(th["folder"], "DJI_0002.JPG"))._FlyrThermogram__thermal
    sides = [os.path.join(d, f) for d, _, fs in os.walk(res["CROPS_FOLDER"]) for f in fs
             if f.endswith(".json")]
    assert len(sides) >= 3
    for side in sides[:3]:
        with open(side) as fh:
            meta = json.load(fh)
        ds = gdal.Open(os.path.join(os.path.dirname(side), meta["file"]))
        band = ds.GetRasterBand(1)
        assert band.DataType == gdal.GDT_Float32 and band.GetUnitType() == "degC"
        assert np.isnan(band.GetNoDataValue()) and "Planck" in ds.GetMetadataItem("EASYIDP_VALUES_NOTE")
        t = band.ReadAsArray()
        (x0, y0), (w, h) = meta["offset"], meta["crop_size"]
        window = raw[y0:y0 + h, x0:x0 + w]
        table = {int(v): planck_by_hand(float(v), c["r1"], c["r2"], c["b"], c["f"], c["o"],
                                        c["emissivity"], c["object_distance"],
                                        c["reflected_temperature"], c["atmospheric_temperature"],
                                        c["relative_humidity"]) for v in np.unique(window)}
        want = np.vectorize(table.get, otypes=[np.float64])(window)
        assert np.abs(t - want).max() < 0.01
        del ds


def test_values_without_crops_say_so(provider, survey):
    """[independent] VALUES = temperature without a crops or previews folder: the log warns
    that the values apply to those only (nothing else changes)."""
    import processing
    feedback = QgsProcessingFeedback()
    processing.run(ALG, {"ROIS": survey.plots_geojson, "NAME_FIELD": "plot_id",
                         "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 3,
                         "GROUND_HEIGHT": 0.0, "PHOTO": "DJI_0002", "VALUES": 1,
                         "OUTPUT": "memory:", "OUTPUT_SUMMARY": "memory:"},
                   context=QgsProcessingContext(), feedback=feedback)
    assert "apply to the crops and previews only" in feedback.textLog()
def test_geopackage_file_written_by_the_engine_is_what_qgis_writes(provider, survey, tmp_path):
    """[independent] QGIS's own writer is the truth: a GeoPackage file output is written by the
    engine (core.gpkg), a layer added into a GeoPackage ('ogr:dbname=… table=…') still by a
    QGIS feature sink; both hold the same fields (names, types), values (NULLs included),
    geometries and undefined CRS, and the engine's file has no spatial index."""
    import sqlite3
    params = {"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
              "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 3, "GROUND_HEIGHT": 95.5,
              "MIN_VISIBLE": 0}
    ours = _run(dict(params, OUTPUT=str(tmp_path / "ours.gpkg")))["OUTPUT"]
    sink = tmp_path / "sink.gpkg"
    theirs = _run(dict(params, OUTPUT=f"ogr:dbname='{sink}' table=\"pixels\" (geom)"))["OUTPUT"]
    assert ours == str(tmp_path / "ours.gpkg") and "layername=pixels" in theirs
    a, b = QgsVectorLayer(ours, "a", "ogr"), QgsVectorLayer(theirs, "b", "ogr")
    assert a.isValid() and b.isValid() and a.featureCount() == b.featureCount() > 40
    assert [(f.name(), f.typeName()) for f in a.fields()] == \
        [(f.name(), f.typeName()) for f in b.fields()]
    assert a.wkbType() == b.wkbType() and a.crs() == b.crs()
    fa = sorted(a.getFeatures(), key=lambda f: f.id())
    fb = sorted(b.getFeatures(), key=lambda f: f.id())
    nulls = 0
    for x, y in zip(fa, fb):
        assert x.attributes()[1:] == y.attributes()[1:], x.id()
        assert x.geometry().equals(y.geometry()), x.id()
        nulls += sum(1 for v in x.attributes() if v is None or (hasattr(v, "isNull") and v.isNull()))
    assert nulls >= len(fa)               # occluded_fraction and uncertainty_px are NULL here
    con = sqlite3.connect(ours)
    assert not [n for (n,) in con.execute("SELECT name FROM sqlite_master") if "rtree" in n]
    con.close()


def test_the_engines_geopackage_never_replaces_an_input_or_a_users_file(provider, survey, tmp_path):
    """The GeoPackage the engine writes obeys the output policy as a sink does: onto the ROI
    layer's own file, or onto a user's file without OVERWRITE, the run is refused and the file
    is untouched (its bytes); with OVERWRITE the file is replaced whole, no temporary file left."""
    import hashlib
    import shutil
    rois = tmp_path / "plots.gpkg"
    shutil.copy(survey.plots_gpkg, rois)
    digest = hashlib.sha256(rois.read_bytes()).hexdigest()
    params = {"ROIS": str(rois), "NAME_FIELD": "plot_id", "PROJECT": survey.metashape_project,
              "HEIGHT_SOURCE": 3, "GROUND_HEIGHT": 95.5, "MAX_IMAGES": 1}
    with pytest.raises(QgsProcessingException, match="is also the input 'ROIs"):
        _run(dict(params, OUTPUT=str(rois)))
    assert hashlib.sha256(rois.read_bytes()).hexdigest() == digest
    mine = tmp_path / "mine.gpkg"
    mine.write_bytes(b"a user's file")
    with pytest.raises(QgsProcessingException, match="mine.gpkg already exists and nothing was written"):
        _run(dict(params, OUTPUT=str(mine)))
    assert mine.read_bytes() == b"a user's file"
    res = _run(dict(params, OUTPUT=str(mine), OVERWRITE=True))
    assert res["OUTPUT"] == str(mine) and QgsVectorLayer(str(mine), "m", "ogr").featureCount() == 40
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.gpkg", "plots.gpkg"]
