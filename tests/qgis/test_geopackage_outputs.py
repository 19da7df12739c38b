"""Every layer-writing tool through the real qgis_process with GeoPackage outputs (QGIS's default
format), as a user runs them: the outputs of one run side by side in one folder.

A tool that opens an output while its writer still has the file open makes SQLite wait for its
lock ('ERROR 1: database is locked', seconds per open; 40 s for 1,600 ROIs) or reads a file not
yet written ('ERROR 4: ... not recognized as a supported file format'). Memory layers and
shapefiles never show it, so these runs write GeoPackages. Any ERROR line fails the run; every
output must open with the features the tool says it wrote (or the truth says it must hold).
"""
import glob
import json
import re
from pathlib import Path

import pytest

from easyidp_toolbox.scripts.qgis_process import run
from easyidp_toolbox.tests.support.season_helpers import small_season

PLOTS = 40          # the demo survey's plots
CAMERAS = 36        # and its photos


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("gpkg_survey")), seed=0, size="small")


@pytest.fixture(scope="module")
def trial(tmp_path_factory):
    from easyidp_toolbox.core.demo.trial import make_demo_trial
    return make_demo_trial(str(tmp_path_factory.mktemp("gpkg_trial")))


@pytest.fixture(scope="module")
def season(tmp_path_factory):
    return small_season(tmp_path_factory.mktemp("gpkg_season"), dates=2)


def _count(path) -> int:
    from osgeo import ogr
    ds = ogr.Open(str(path))
    assert ds is not None, f"{path} does not open"
    assert ds.GetLayerCount() == 1, path
    return ds.GetLayer(0).GetFeatureCount()


def _log_count(log, pattern) -> int:
    """The number the tool's own log gives for what it wrote (``pattern`` has one group)."""
    hits = [int(m.group(1)) for line in log for m in [re.search(pattern, line)] if m]
    assert hits, f"no log line matches {pattern!r}: {log}"
    return hits[-1]


def _run(qp_env, alg, params):
    """Run ``alg`` through qgis_process --json; fail on any ERROR line or lock message; returns
    (results, log lines)."""
    proc = run(["--json", "run", alg, "--"] + [f"{k}={v}" for k, v in params.items()], qp_env)
    assert proc.returncode == 0, proc.stderr
    bad = [line for line in (proc.stderr + "\n" + proc.stdout).splitlines()
           if re.search(r"\bERROR\b", line) or "database is locked" in line]
    assert not bad, f"{alg} logged errors:\n" + "\n".join(bad)
    out = json.loads(proc.stdout)
    log = [line for lines in out.get("log", {}).values() for line in lines]
    return out["results"], log


def _labelme_shapes(folder) -> int:
    return sum(len(json.loads(Path(f).read_text())["shapes"]) for f in glob.glob(f"{folder}/*.json"))


def case_backprojectrois(s, season, out, trial):
    params = {"ROIS": s.plots_gpkg, "NAME_FIELD": "plot_id", "PROJECT": s.metashape_project,
              "HEIGHT_SOURCE": 1, "DSM": s.dsm, "OUTPUT": out / "plots_in_photos.gpkg",
              "OUTPUT_SUMMARY": out / "plots_best_photo.gpkg", "OUTPUT_JSON": out / "b.json"}

    def expect(res, log):
        with open(res["OUTPUT_JSON"]) as fh:
            pairs = sum(len(v) for v in json.load(fh).values())
        assert pairs == _log_count(log, r"^(\d+) ROI × photo pairs") and pairs > PLOTS
        return {"OUTPUT": pairs, "OUTPUT_SUMMARY": PLOTS}
    return params, expect


def case_camerafootprints(s, season, out, trial):
    params = {"PROJECT": s.metashape_project, "DSM": s.dsm, "OUTPUT_CAMERAS": out / "cameras.gpkg",
              "OUTPUT_FOOTPRINTS": out / "footprints.gpkg"}
    return params, lambda res, log: {"OUTPUT_CAMERAS": CAMERAS, "OUTPUT_FOOTPRINTS": CAMERAS}


def case_croprasterbyrois(s, season, out, trial):
    params = {"INPUT": s.orthomosaic, "ROIS": s.plots_gpkg, "NAME_FIELD": "plot_id",
              "OUTPUT_FOLDER": out / "crops", "OUTPUT_INDEX": out / "crops_index.gpkg"}

    def expect(res, log):
        assert res["CROPPED"] == PLOTS
        return {"OUTPUT_INDEX": PLOTS}
    return params, expect


def case_croppointcloudbyrois(s, season, out, trial):
    params = {"INPUT": s.point_cloud_laz, "ROIS": s.plots_gpkg, "NAME_FIELD": "plot_id",
              "OUTPUT_FOLDER": out / "clouds", "OUTPUT_INDEX": out / "clouds_index.gpkg"}

    def expect(res, log):
        assert res["CROPPED"] == PLOTS
        return {"OUTPUT_INDEX": PLOTS}
    return params, expect


def case_orthorectifyrois(s, season, out, trial):
    params = {"ROIS": s.plots_gpkg, "NAME_FIELD": "plot_id", "PROJECT": s.metashape_project,
              "DSM": s.dsm, "OUTPUT_FOLDER": out / "ortho", "OUTPUT_INDEX": out / "ortho_index.gpkg"}

    def expect(res, log):
        assert res["WRITTEN"] == PLOTS
        return {"OUTPUT_INDEX": PLOTS}
    return params, expect


def case_pointcloudroistatistics(s, season, out, trial):
    params = {"INPUT": s.point_cloud_laz, "ROIS": s.plots_gpkg, "OUTPUT": out / "cloud_stats.gpkg"}
    return params, lambda res, log: {"OUTPUT": PLOTS}


def case_roiheightsfromdsm(s, season, out, trial):
    params = {"ROIS": s.plots_gpkg, "DSM": s.dsm, "OUTPUT": out / "heights.gpkg"}
    return params, lambda res, log: {"OUTPUT": PLOTS}


def case_forwardprojectpolygons(s, season, out, trial):
    folder = Path(s.labelme[0]).parent
    params = {"INPUT_FOLDER": folder, "PROJECT": s.metashape_project, "DSM": s.dsm,
              "OUTPUT": out / "labelme_on_map.gpkg"}

    def expect(res, log):
        n = _labelme_shapes(folder)          # MERGE none: one polygon per photo polygon
        assert n == _log_count(log, r"^(\d+) polygons from") and n > 0
        return {"OUTPUT": n}
    return params, expect


def case_photostatistics(s, season, out, trial):
    params = {"ROIS": s.plots_gpkg, "NAME_FIELD": "plot_id", "PROJECT": s.metashape_project,
              "HEIGHT_SOURCE": 1, "DSM": s.dsm, "OUTPUT_VIEWS": out / "photo_views.gpkg",
              "OUTPUT": out / "photo_statistics.gpkg"}

    def expect(res, log):
        views = _log_count(log, r"^(\d+) views measured")
        assert views > PLOTS
        return {"OUTPUT_VIEWS": views, "OUTPUT": PLOTS}
    return params, expect


def case_seasontraits(s, season, out, trial):
    params = {"SURVEYS": season.surveys, "ROIS": season.plots, "NAME_FIELD": "plot_id",
              "GROUND": season.ground, "WORKERS": 1, "OUTPUT_TABLE": out / "season_traits.gpkg",
              "OUTPUT_LAYER": out / "season_latest.gpkg"}

    def expect(res, log):
        plots = len(season.plot_ids)
        values = _log_count(log, r"^(\d+) values of \d+ traits for %d ROIs on 2 dates" % plots)
        return {"OUTPUT_TABLE": values, "OUTPUT_LAYER": plots}
    return params, expect


def case_createplotgrid(s, season, out, trial):
    from easyidp_toolbox.core.demo.trial import TRIAL
    params = {"ANCHOR": 0, "CORNERS": trial.corners, "ROWS": TRIAL["rows"], "COLS": TRIAL["cols"],
              "SIZE_X": TRIAL["size_x"], "SIZE_Y": TRIAL["size_y"], "GAP_X": TRIAL["gap_x"],
              "GAP_Y": TRIAL["gap_y"], "OUTPUT": out / "plot_grid.gpkg"}
    return params, lambda res, log: {"OUTPUT": TRIAL["rows"] * TRIAL["cols"]}


def case_fitplotgrid(s, season, out, trial):
    from easyidp_toolbox.core.demo.trial import FIELD_BEARING, TRIAL, trial_corners
    from easyidp_toolbox.core.plotgrid import create_plot_grid, grid_options, write_plot_grid
    grid, _ = create_plot_grid("EPSG:32654", **grid_options(
        origin=trial_corners()[0], bearing=FIELD_BEARING, **TRIAL))
    params = {"GRID": write_plot_grid(str(out / "plot_grid.gpkg"), grid),
              "ORTHOMOSAIC": trial.orthomosaic, "OUTPUT": out / "fitted.gpkg"}
    return params, lambda res, log: {"OUTPUT": TRIAL["rows"] * TRIAL["cols"]}


CASES = {name[len("case_"):]: f for name, f in dict(globals()).items() if name.startswith("case_")}


def test_every_layer_writing_tool_is_covered(provider):
    """A new tool that writes a layer gets a case here (the provider says which tools do)."""
    from qgis.core import QgsProcessingParameterFeatureSink, QgsProcessingParameterVectorDestination
    writers = {a.name() for a in provider.algorithms()
               if any(isinstance(p, (QgsProcessingParameterFeatureSink,
                                     QgsProcessingParameterVectorDestination))
                      for p in a.destinationParameterDefinitions())}
    assert writers and writers == set(CASES)


@pytest.mark.parametrize("tool", sorted(CASES))
def test_geopackage_outputs_through_qgis_process(qp_env, survey, season, trial, tmp_path, tool):
    params, expect = CASES[tool](survey, season, tmp_path, trial)
    res, log = _run(qp_env, f"easyidp:{tool}", params)
    counts = expect(res, log)
    layers = {k for k, v in params.items() if k.startswith("OUTPUT") and str(v).endswith(".gpkg")}
    assert set(counts) == layers               # every GeoPackage output is checked
    for name, n in counts.items():
        assert Path(res[name]) == Path(params[name])
        assert _count(res[name]) == n, name
    if tool == "backprojectrois":              # photo pixels: written without a CRS
        from qgis.core import QgsVectorLayer
        layer = QgsVectorLayer(str(res["OUTPUT"]), "pixels", "ogr")
        assert not layer.crs().isValid() or layer.crs().description().startswith("Undefined")
