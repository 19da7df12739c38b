"""Each tool's pure step, parameters → (core callable, keyword arguments), exercised without
running the tool (as the GDAL provider's getConsoleCommands): real QGIS offscreen, a
QgsProcessingContext and parameter dicts. Nothing is computed or written by the step."""
import os

import numpy as np
import pytest
from qgis.core import (QgsApplication, QgsProcessingContext, QgsProcessingException,
                       QgsProcessingFeedback)

from easyidp_toolbox.tests.support.qgis_layers import memory_layer
from easyidp_toolbox.tests.support.season_helpers import small_season
from easyidp_toolbox.tests.support.synthetic import write_tif


def _step(alg_id, parameters):
    """The tool's CoreStep for ``parameters`` (the tool is not run)."""
    alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
    context = QgsProcessingContext()
    return alg.step(parameters, context, QgsProcessingFeedback())


PLOTS = [("a", "POLYGON((368002 3955998, 368010 3955998, 368010 3955990, 368002 3955998))"),
         ("b", "POLYGON((368012 3955998, 368020 3955998, 368020 3955990, 368012 3955998))")]


@pytest.fixture(scope="module")
def raster(tmp_path_factory):
    folder = tmp_path_factory.mktemp("steps")
    return write_tif(str(folder / "dem.tif"), np.zeros((40, 40), np.float32), pixel=1.0,
                     origin=(368000, 3956000))


@pytest.fixture(scope="module")
def season(tmp_path_factory):
    return small_season(tmp_path_factory.mktemp("season_steps"))


# ---- Crop raster by ROIs -----------------------------------------------------------------------

@pytest.mark.parametrize("all_touched, overwrite", [(False, False), (True, True)])
def test_crop_raster_step(provider, raster, tmp_path, all_touched, overwrite):
    from easyidp_toolbox.core.progress import Progress
    from easyidp_toolbox.core.raster import crop_raster_by_rois
    out = tmp_path / "crops"
    step = _step("easyidp:croprasterbyrois", {
        "INPUT": raster, "ROIS": memory_layer("EPSG:32654", PLOTS), "NAME_FIELD": "name",
        "ALL_TOUCHED": all_touched, "OVERWRITE": overwrite, "OUTPUT_FOLDER": str(out)})
    assert step.function is crop_raster_by_rois
    kw = step.kwargs
    assert set(kw) == {"raster", "rois", "output_folder", "all_touched", "source_crs", "overwrite",
                       "progress"}
    assert kw["raster"] == raster and kw["output_folder"] == str(out)
    assert kw["all_touched"] is all_touched and kw["overwrite"] is overwrite
    assert kw["source_crs"] == "EPSG:32654" and kw["rois"].names == ["a", "b"]
    assert isinstance(kw["progress"], Progress)
    assert len(step.inputs["features"]) == 2
    assert not out.exists()                       # the step ran nothing


def _ascii_grid(path):
    path.write_text("ncols 2\nnrows 2\nxllcorner 368000\nyllcorner 3955998\ncellsize 1\n"
                    "1 2\n3 4\n")
    return str(path)


@pytest.mark.parametrize("bad, match", [
    ("not_geotiff", r"Raster: .*dem\.asc is not a GeoTIFF"),
    ("points", r"ROIs: the ROI layer 'rois' has Point geometries"),
    ("name_field", r"ROIs: the ROI layer has no field 'plot_id'"),
])
def test_crop_raster_step_refuses_bad_parameters(provider, raster, tmp_path, bad, match):
    params = {"INPUT": raster, "ROIS": memory_layer("EPSG:32654", PLOTS),
              "OUTPUT_FOLDER": str(tmp_path / "o")}
    if bad == "not_geotiff":
        params["INPUT"] = _ascii_grid(tmp_path / "dem.asc")
    elif bad == "points":
        params["ROIS"] = memory_layer("EPSG:32654", [("p", "POINT(368005 3955995)")],
                                      kind="Point")
    else:
        params["NAME_FIELD"] = "plot_id"
    with pytest.raises(QgsProcessingException, match=match):
        _step("easyidp:croprasterbyrois", params)


# ---- Forward-project photo polygons ------------------------------------------------------------

@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("fwd_steps")), seed=0, size="small")


@pytest.mark.parametrize("merge, mode, densify", [(0, "none", 4.0), (1, "union", 0.0),
                                                  (2, "best", 2.5), (3, "fuse", 4.0)])
def test_forward_project_step(provider, survey, merge, mode, densify):
    from easyidp_toolbox.core.projection import forward_project_photos
    from easyidp_toolbox.core.raster import DSM
    step = _step("easyidp:forwardprojectpolygons", {
        "INPUT_FOLDER": os.path.dirname(survey.labelme[0]), "PROJECT": survey.metashape_project,
        "DSM": survey.dsm, "MERGE": merge, "DENSIFY": densify, "OUTPUT": "memory:"})
    assert step.function is forward_project_photos
    kw = step.kwargs
    assert set(kw) == {"items", "recon", "dsm", "merge", "densify", "progress"}
    assert kw["merge"] == mode and kw["densify"] == densify
    assert isinstance(kw["dsm"], DSM)
    assert [cam.label for _, cam in kw["items"]] and \
        all(ann.shapes for ann, _ in kw["items"])
    assert step.inputs["what"] == os.path.basename(os.path.dirname(survey.labelme[0]))


@pytest.mark.parametrize("inputs", [(), ("INPUT", "INPUT_FOLDER")])
def test_forward_project_step_needs_exactly_one_input(provider, tmp_path, inputs):
    params = {"PROJECT": str(tmp_path / "none.psx"), "DSM": str(tmp_path / "none.tif"),
              "OUTPUT": "memory:"}
    params.update({name: str(tmp_path) for name in inputs})
    with pytest.raises(QgsProcessingException, match="Give exactly one input"):
        _step("easyidp:forwardprojectpolygons", params)


# ---- Plot traits over a season -----------------------------------------------------------------

@pytest.mark.parametrize("traits, percentiles, scheduler, expect", [
    ([0], "5, 50;95", "", dict(traits=["height"], percentiles=[5.0, 50.0, 95.0],
                                scheduler=None, local_cluster=False)),
    ([1, 3], "", "local", dict(traits=["cover", "index"], percentiles=[50.0, 95.0, 99.0],
                               scheduler=None, local_cluster=True)),
    ([4], "99", "tcp://10.0.0.1:8786", dict(traits=["cloud"], percentiles=[99.0],
                                            scheduler="tcp://10.0.0.1:8786",
                                            local_cluster=False)),
])
def test_season_step(provider, season, tmp_path, traits, percentiles, scheduler, expect):
    from easyidp_toolbox.core.season import run_season
    step = _step("easyidp:seasontraits", {
        "SURVEYS": season.surveys, "ROIS": season.plots, "NAME_FIELD": "plot_id",
        "TRAITS": traits, "PERCENTILES": percentiles, "DASK_SCHEDULER": scheduler,
        "WORKERS": 3, "COVER_THRESHOLD": 0.1, "CROPS": str(tmp_path / "crops"),
        "OUTPUT_TABLE": "TEMPORARY_OUTPUT", "OUTPUT_LAYER": "TEMPORARY_OUTPUT"})
    assert step.function is run_season
    kw = step.kwargs
    for name, value in expect.items():
        assert kw[name] == value, name
    assert kw["workers"] == 3 and kw["cover_threshold"] == pytest.approx(0.1)
    assert kw["ground"] is None and kw["crops"] == str(tmp_path / "crops")
    assert len(kw["table"].surveys) == len(season.dates) and len(kw["rois"]) == 6
    assert not (tmp_path / "crops").exists()


@pytest.mark.parametrize("change, match", [
    (dict(TRAITS=[]), "Traits: choose at least one"),
    (dict(PERCENTILES="5, abc"), "Percentiles: 'abc' is not a number from 0 to 100"),
    (dict(OUTPUT_CURVES="@surveys"), "(?i)inputs are never overwritten"),
])
def test_season_step_refuses_bad_parameters(provider, season, change, match):
    params = {"SURVEYS": season.surveys, "ROIS": season.plots, "OUTPUT_TABLE": "TEMPORARY_OUTPUT",
              "OUTPUT_LAYER": "TEMPORARY_OUTPUT", **change}
    if params.get("OUTPUT_CURVES") == "@surveys":    # a file the table names (a DSM)
        params["OUTPUT_CURVES"] = season.dsms[0]
    with pytest.raises(QgsProcessingException, match=match):
        _step("easyidp:seasontraits", params)


# ---- ROI heights from DSM, Create plot grid, Create demo survey ------------------------------

@pytest.mark.parametrize("mode, function, extra", [
    (0, "dsm_roi_heights", {"mode": "polygon"}),
    (1, "vertex_heights", {"sampling": "nearest"}),
])
def test_roi_heights_step(provider, raster, mode, function, extra):
    from easyidp_toolbox.core import raster as core_raster
    step = _step("easyidp:roiheightsfromdsm", {
        "ROIS": memory_layer("EPSG:32654", PLOTS), "DSM": raster, "MODE": mode,
        "STATISTIC": 4, "PERCENTILE": 90, "SAMPLING": 1, "OUTPUT": "memory:"})
    assert step.function is getattr(core_raster, function)
    kw = step.kwargs
    assert kw["statistic"] == "percentile" and kw["percentile"] == 90 and kw["buffer"] == 0
    for name, value in extra.items():
        assert kw[name] == value
    if mode == 1:       # the layer's own vertices, closing ones included: 4 per triangle
        assert len(kw["x"]) == len(kw["y"]) == 8 and kw["x"][0] == 368002


def test_create_plot_grid_step(provider, tmp_path):
    from easyidp_toolbox.core.plotgrid import create_plot_grid
    step = _step("easyidp:createplotgrid", {
        "ANCHOR": 2, "ORIGIN": "500000,4000000 [EPSG:32654]", "ROWS": 2, "COLS": 3, "SIZE_X": 2,
        "SIZE_Y": 1, "SPACING_X": 2.5, "GAP_Y": 1, "OUTPUT": str(tmp_path / "c.gpkg")})
    assert step.function is create_plot_grid
    kw = step.kwargs
    assert (kw["crs"], kw["rows"], kw["cols"]) == ("EPSG:32654", 2, 3)
    assert kw["anchor"].origin == pytest.approx((500000, 4000000))
    lay = kw["layout"]
    assert lay.spacing_x == 2.5 and lay.size_x == 2 and lay.gap_y == 1 and lay.gap_x is None
    assert kw["field_book"] is None and kw["numbering"].pattern == "{plot_no}"
    assert not (tmp_path / "c.gpkg").exists()


@pytest.mark.parametrize("size, seed", [(0, 0), (1, 7)])
def test_create_demo_survey_step(provider, tmp_path, size, seed):
    from easyidp_toolbox.core.demo import make_demo_survey
    step = _step("easyidp:createdemosurvey", {"OUTPUT_FOLDER": str(tmp_path / "demo"),
                                               "SIZE": size, "SEED": seed})
    assert step.function is make_demo_survey
    assert {k: step.kwargs[k] for k in ("folder", "seed", "size", "overwrite")} == {
        "folder": str(tmp_path / "demo"), "seed": seed, "size": ["small", "medium"][size],
        "overwrite": False}
    assert not (tmp_path / "demo").exists()


@pytest.mark.parametrize("ground", ["dsm", "height"])
def test_camera_footprints_step(provider, survey, ground):
    from easyidp_toolbox.core.projection import camera_footprints
    from easyidp_toolbox.core.raster import DSM
    params = {"PROJECT": survey.metashape_project, "OUTPUT_CAMERAS": "memory:",
              "OUTPUT_FOOTPRINTS": "memory:"}
    params.update({"DSM": survey.dsm} if ground == "dsm" else {"GROUND_HEIGHT": 12.5})
    step = _step("easyidp:camerafootprints", params)
    assert step.function is camera_footprints
    kw = step.kwargs
    assert set(kw) == {"recon", "ground", "output_crs", "cameras", "progress", "is_cancelled"}
    assert isinstance(kw["ground"], DSM) if ground == "dsm" else kw["ground"] == 12.5
    assert kw["cameras"] and all(c.aligned for c in kw["cameras"])
    assert step.inputs["qcrs"].isValid()


def test_camera_footprints_step_needs_a_ground(provider, survey):
    with pytest.raises(QgsProcessingException, match="Give a DSM or a ground height"):
        _step("easyidp:camerafootprints", {"PROJECT": survey.metashape_project,
                                           "OUTPUT_CAMERAS": "memory:",
                                           "OUTPUT_FOOTPRINTS": "memory:"})


@pytest.mark.parametrize("occlusion", [False, True])
def test_photo_statistics_step(provider, survey, tmp_path, occlusion):
    from easyidp_toolbox.core.projection import roi_photo_statistics
    from easyidp_toolbox.core.raster import DSM
    step = _step("easyidp:photostatistics", {
        "ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id", "PROJECT": survey.metashape_project,
        "HEIGHT_SOURCE": 1, "DSM": survey.dsm, "OCCLUSION": occlusion, "MAX_IMAGES": 3,
        "OUTPUT": str(tmp_path / "stats.gpkg"), "OUTPUT_VIEWS": str(tmp_path / "views.gpkg")})
    assert step.function is roi_photo_statistics
    kw = step.kwargs
    assert kw["backprojection"] is None and kw["max_views"] == 3
    assert kw["occlusion"] is occlusion and isinstance(kw["occlusion_dsm"], DSM)
    assert len(kw["rois"]) == 40 and kw["heights"].describe().startswith("DSM")
    assert not (tmp_path / "stats.gpkg").exists()           # the step ran nothing


def test_every_tool_has_a_core_step(provider):
    """Every tool is parameters → one core call (core_step) → outputs (write_outputs)."""
    from easyidp_toolbox.easyidp_qgis.algorithms import ALGORITHMS
    without = sorted(a.NAME for a in ALGORITHMS if "core_step" not in vars(a))
    assert without == []
