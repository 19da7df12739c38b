"""The example model, run inside QGIS: both tools work as model children."""
from pathlib import Path

from qgis.core import QgsProcessingContext, QgsProcessingFeedback, QgsProcessingModelAlgorithm

MODEL = Path(__file__).parent / "data" / "heights_then_crop.model3"


def test_model_loads_and_runs(provider, realdata, tmp_path):
    model = QgsProcessingModelAlgorithm()
    assert model.fromFile(str(MODEL))
    assert {c.algorithmId() for c in model.childAlgorithms().values()} == \
        {"easyidp:croprasterbyrois", "easyidp:roiheightsfromdsm"}
    ok, msg = model.checkParameterValues({}, QgsProcessingContext())
    assert not ok  # the DSM and plots are required
    results, ok = model.run({"dsm": str(realdata / "data-to-science/test.tif"),
                             "plots": str(realdata / "data-to-science/zones_inside_test_tif.geojson"),
                             "heights:plots_with_heights": str(tmp_path / "p.gpkg"),
                             "crop:crops": str(tmp_path / "crops")},
                            QgsProcessingContext(), QgsProcessingFeedback())
    assert ok and len(list((tmp_path / "crops").glob("*.tif"))) == 20
