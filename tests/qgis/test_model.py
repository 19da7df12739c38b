"""The example model: valid in QGIS's own check, laid out, and run inside QGIS with its name field."""
from pathlib import Path

from qgis.core import (QgsProcessingContext, QgsProcessingFeedback, QgsProcessingModelAlgorithm,
                       QgsProcessingOutputLayerDefinition, QgsProject)

MODEL = Path(__file__).parent / "data" / "heights_then_crop.model3"


def _model():
    model = QgsProcessingModelAlgorithm()
    assert model.fromFile(str(MODEL))
    return model


def test_model_is_valid_and_laid_out(provider):
    model = _model()
    ok, issues = model.validate()          # what the modeler shows in red and Run asks about
    assert ok and issues == []
    assert {c.algorithmId() for c in model.childAlgorithms().values()} == \
        {"easyidp:croprasterbyrois", "easyidp:roiheightsfromdsm"}
    boxes = [(p.position().x(), p.position().y()) for p in model.parameterComponents().values()]
    for child in model.childAlgorithms().values():
        boxes.append((child.position().x(), child.position().y()))
        boxes += [(o.position().x(), o.position().y()) for o in child.modelOutputs().values()]
    assert len(set(boxes)) == len(boxes) == 8                # nothing on top of anything
    assert all(abs(a[0] - b[0]) >= 200 or abs(a[1] - b[1]) >= 30
               for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert model.parameterDefinition("name_field").parentLayerParameterName() == "plots"
    assert model.shortHelpString()
    ok, msg = model.checkParameterValues({}, QgsProcessingContext())
    assert not ok  # the DSM and plots are required


def test_model_runs_with_its_name_field(provider, realdata, tmp_path):
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    results, ok = _model().run(
        {"dsm": str(realdata / "data-to-science/test.tif"),
         "plots": str(realdata / "data-to-science/zones_inside_test_tif.geojson"),
         "name_field": "col",
         "heights:Plots with heights": str(tmp_path / "p.gpkg"),
         "crop:Crops": str(tmp_path / "crops"),
         "crop:Index of the crops": QgsProcessingOutputLayerDefinition(str(tmp_path / "index.gpkg"),
                                                               QgsProject.instance())},
        context, QgsProcessingFeedback())
    assert ok
    names = sorted(p.stem for p in (tmp_path / "crops").glob("*.tif"))
    assert len(names) == 20 and "1" in names and "1_2" in names         # named by 'col'
    # the index is a model output set to open: it is queued; the crops are not, as the model
    # (saved before 'Open the crops in the map too' existed) does not ask for them
    queued = context.layersToLoadOnCompletion().values()
    assert sum(d.outputName == "OUTPUT_FILES" for d in queued) == 0
    assert [d.name for d in queued if d.outputName == "OUTPUT_INDEX"] == ["Index of the crops"]


def test_no_tool_gains_a_mandatory_parameter(provider):
    """Models, batch files and scripts saved with 0.3.0 stay valid: a parameter added since is
    optional (QGIS's model validation calls every non-optional parameter without a value
    "mandatory", a default notwithstanding). The mandatory parameters of 0.3.0 are in
    ``data/mandatory_parameters_0.3.0.json`` (listed from the 0.3.0 code by QGIS itself)."""
    import json

    from qgis.core import QgsProcessingParameterDefinition
    was = json.loads((Path(__file__).parent / "data" / "mandatory_parameters_0.3.0.json").read_text())
    gained = {}
    for alg in provider.algorithms():
        now = {d.name() for d in alg.parameterDefinitions()
               if not d.flags() & QgsProcessingParameterDefinition.FlagOptional}
        new = now - set(was.get(alg.name(), now))
        if new:
            gained[alg.name()] = sorted(new)
    assert gained == {}
