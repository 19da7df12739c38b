"""Plot traits over a season (easyidp:seasontraits) inside real QGIS and through qgis_process,
on the small demo season (truth by construction: analytic heights and covers)."""
import csv
import json
import os
import shutil

import pytest
from qgis.core import (QgsFeature, QgsProcessingContext, QgsProcessingException,
                       QgsProcessingFeedback, QgsProcessingOutputLayerDefinition, QgsProject,
                       QgsVectorLayer)
from qgis.PyQt.QtCore import QDate, Qt

from easyidp_toolbox.scripts.qgis_process import run, run_algorithm
from easyidp_toolbox.tests.support.season_helpers import small_season

ALG = "easyidp:seasontraits"


@pytest.fixture(scope="module")
def season(tmp_path_factory):
    return small_season(tmp_path_factory.mktemp("season"))


def _run(params, context=None, feedback=None):
    import processing
    return processing.run(ALG, params, context=context or QgsProcessingContext(),
                          feedback=feedback or QgsProcessingFeedback())


class Log(QgsProcessingFeedback):
    def __init__(self):
        super().__init__()
        self.lines = []

    def pushInfo(self, info):  # noqa: N802 (QGIS API)
        self.lines.append(info)

    def pushWarning(self, warning):  # noqa: N802 (QGIS API)
        self.lines.append("WARNING " + warning)


def test_season_in_qgis_tables_layer_curves_and_style(provider, season, tmp_path):
    with open(season.truth) as fh:
        truth = json.load(fh)
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    layer_out = QgsProcessingOutputLayerDefinition(str(tmp_path / "latest.gpkg"),
                                                   QgsProject.instance())
    log = Log()
    res = _run({"SURVEYS": season.surveys, "ROIS": season.plots, "NAME_FIELD": "plot_id",
                "GROUP_FIELD": "variety", "GROUND": season.ground, "WORKERS": 2,
                "OUTPUT_TABLE": str(tmp_path / "traits.csv"), "OUTPUT_LAYER": layer_out,
                "OUTPUT_CURVES": str(tmp_path / "curves.png")}, context, log)
    with open(res["OUTPUT_TABLE"], newline="") as fh:
        rows = list(csv.DictReader(fh))
    values = {(r["roi"], r["date"], r["trait"]): float(r["value"]) for r in rows}
    for pid, t in truth["plots"].items():
        for k, d in enumerate(truth["dates"]):
            assert abs(values[(pid, d, "height_p99")] - t["height"][k]) < 0.05
            assert abs(values[(pid, d, "cover")] - t["cover"][k]) < 0.05
    wide = QgsVectorLayer(res["OUTPUT_LAYER"], "w", "ogr")
    assert wide.featureCount() == 6
    names = wide.fields().names()
    assert {"plot_id", "variety", "date", "height_p99", "cover", "cloud_height_p99"} <= set(names)
    assert {f["date"] for f in wide.getFeatures()} == {truth["dates"][-1]}
    assert os.path.getsize(res["OUTPUT_CURVES"]) > 10000
    assert any("values of" in line and "traits for 6 ROIs on 4 dates" in line for line in log.lines)
    # the wide layer is queued for the map with a graduated style on the height
    details = context.layerToLoadOnCompletionDetails(res["OUTPUT_LAYER"])
    assert details.name == "plots: latest traits"
    details.postProcessor().postProcessLayer(wide, context, log)
    assert wide.renderer().type() == "graduatedSymbol"
    assert wide.renderer().classAttribute() == "height_p99" and len(wide.renderer().ranges()) == 5


def test_survey_table_as_layers(provider, season, tmp_path):
    """A CSV layer with QGIS's type detection (which reads '2024-05-22/dsm.tif' as a date) is
    read from its file; a table without a file (memory, QDate dates) through its features."""
    uri = f"file://{season.surveys}?delimiter=,&detectTypes=yes&geomType=none"
    csv_layer = QgsVectorLayer(uri, "surveys", "delimitedtext")
    assert csv_layer.isValid() and csv_layer.fields().field("dsm").typeName().lower() == "date"
    memory = QgsVectorLayer("None?field=date:date&field=dsm:string", "surveys", "memory")
    feats = []
    for d, dsm in zip(season.dates, season.dsms):
        f = QgsFeature(memory.fields())
        f.setAttributes([QDate.fromString(d, Qt.ISODate), dsm])
        feats.append(f)
    memory.dataProvider().addFeatures(feats)
    for table in (csv_layer, memory):
        res = _run({"SURVEYS": table, "ROIS": season.plots, "NAME_FIELD": "plot_id",
                    "TRAITS": [0], "WORKERS": 1, "OUTPUT_TABLE": "TEMPORARY_OUTPUT",
                    "OUTPUT_LAYER": "TEMPORARY_OUTPUT"})
        long = res["OUTPUT_TABLE"]
        assert {f["date"] for f in long.getFeatures()} == set(season.dates)
        assert {f["trait"] for f in long.getFeatures()} == {"height_p50", "height_p95",
                                                            "height_p99"}


def test_every_row_bad_is_an_error_and_bad_rows_are_warned(provider, season, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("date,orthomosaic,dsm\n2024-06-01,nope.tif,\nyesterday,,x.tif\n")
    with pytest.raises(QgsProcessingException, match="Nothing to compute"):
        _run({"SURVEYS": str(bad), "ROIS": season.plots, "OUTPUT_TABLE": "TEMPORARY_OUTPUT",
              "OUTPUT_LAYER": "TEMPORARY_OUTPUT"})
    with pytest.raises(QgsProcessingException, match="(?i)inputs are never overwritten"):
        _run({"SURVEYS": season.surveys, "ROIS": season.plots, "OUTPUT_TABLE": season.surveys,
              "OUTPUT_LAYER": "TEMPORARY_OUTPUT"})
    with open(season.surveys) as fh:
        assert fh.readline().startswith("date,orthomosaic")
    mixed = tmp_path / "mixed.csv"
    mixed.write_text(f"date,dsm\n{season.dates[0]},{season.dsms[0]}\n{season.dates[1]},gone.tif\n")
    log = Log()
    _run({"SURVEYS": str(mixed), "ROIS": season.plots, "NAME_FIELD": "plot_id", "TRAITS": [0],
          "WORKERS": 1, "OUTPUT_TABLE": "TEMPORARY_OUTPUT", "OUTPUT_LAYER": "TEMPORARY_OUTPUT"},
         feedback=log)
    assert any(line.startswith(f"WARNING Survey row 2 ({season.dates[1]}), dsm: file not found")
               for line in log.lines)


def test_season_headless_with_qgis_process_and_a_dask_local_cluster(qp_env, season, tmp_path):
    out = run(["help", ALG], qp_env).stdout
    for p in ("SURVEYS", "ROIS", "NAME_FIELD", "GROUP_FIELD", "TRAITS", "GROUND", "WORKERS",
              "DASK_SCHEDULER", "CROPS", "OUTPUT_TABLE", "OUTPUT_LAYER", "OUTPUT_CURVES"):
        assert p in out
    table = tmp_path / "surveys.csv"
    shutil.copy(season.surveys, table)   # relative paths now point nowhere: reported, not fatal
    with open(table, "a") as fh:
        fh.write(f"{season.dates[0]},{season.orthomosaics[0]},{season.dsms[0]},,\n")
    res = run_algorithm(ALG, {
        "SURVEYS": table, "ROIS": season.plots, "NAME_FIELD": "plot_id", "GROUND": season.ground,
        "WORKERS": 2, "DASK_SCHEDULER": "local", "CROPS": tmp_path / "crops",
        "OUTPUT_TABLE": tmp_path / "t.gpkg", "OUTPUT_LAYER": tmp_path / "w.gpkg",
        "OUTPUT_CURVES": tmp_path / "c.png"}, qp_env)
    from osgeo import ogr
    ds = ogr.Open(res["OUTPUT_TABLE"])
    assert {f.GetField("date") for f in ds.GetLayer(0)} == {season.dates[0]}
    assert len(list((tmp_path / "crops" / season.dates[0] / "orthomosaic").glob("*.tif"))) == 6
    assert os.path.exists(res["OUTPUT_CURVES"])
