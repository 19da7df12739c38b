"""How results land in the map, with QGIS's own loader (``handleAlgorithmResults``, what the
toolbox, batch and model dialogs call after a run: the ``load_results`` fixture) on the real
project: what is loaded and only when asked, names, groups, layer types and styles; help links
and number widgets."""
import re
from pathlib import Path

import pytest
from qgis.core import (QgsApplication, QgsLayerTreeGroup, QgsMapLayerType, QgsProcessingContext,
                       QgsProcessingFeedback, QgsProcessingOutputLayerDefinition,
                       QgsProcessingParameterNumber, QgsProject, QgsRasterLayer, QgsRenderContext,
                       QgsVectorLayer)

ROOT = Path(__file__).resolve().parents[2]
ZONES = "data-to-science/zones_inside_test_tif.geojson"
DSM = "data-to-science/test.tif"
PROJECT_FILE = "easyidp/metashape/wheat_tanashi.psx"


@pytest.fixture
def project():
    """The real project, emptied before and after; messages logged meanwhile are collected."""
    p = QgsProject.instance()
    p.clear()
    log = []

    def keep(message, tag, level):
        log.append((tag, int(level), message))
    QgsApplication.messageLog().messageReceived.connect(keep)
    yield p, log
    QgsApplication.messageLog().messageReceived.disconnect(keep)
    p.clear()


def _run_and_load(alg_id, params, project, load_results):
    """Run as the batch dialog does: a context on the project, ``alg.run``, then QGIS's loader
    of results (the ``load_results`` fixture)."""
    context = QgsProcessingContext()
    context.setProject(project)
    feedback = QgsProcessingFeedback()
    alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
    results, ok = alg.run(params, context, feedback)
    assert ok, feedback.textLog()
    queued = {d.outputName for d in context.layersToLoadOnCompletion().values()}
    assert load_results(alg, context, feedback, params)
    return results, queued


def _to_load(project):
    return QgsProcessingOutputLayerDefinition("TEMPORARY_OUTPUT", project)


def _tree(node):
    """[(name, kind, expanded)] of a group's children; kind: 'group' or the layer type."""
    out = []
    for ch in node.children():
        if isinstance(ch, QgsLayerTreeGroup):
            out.append((ch.name(), "group", ch.isExpanded()))
        else:
            out.append((ch.name(), ch.layer().type(), ch.isExpanded()))
    return out


def test_crops_load_in_one_group_below_the_rois_only_when_asked(provider, realdata, tmp_path, project,
                                                                load_results):
    proj, log = project
    dsm = proj.addMapLayer(QgsRasterLayer(str(realdata / DSM), "dsm"))
    zones = proj.addMapLayer(QgsVectorLayer(str(realdata / ZONES), "zones", "ogr"))
    params = {"INPUT": dsm.id(), "ROIS": zones.id(), "NAME_FIELD": "row",
              "OUTPUT_FOLDER": str(tmp_path / "a")}
    # not asked (a folder has no 'open' option; batch with 'Load layers on completion' off gives
    # the index a definition without a project): nothing new in the map
    _run_and_load("easyidp:croprasterbyrois", params, proj, load_results)
    _run_and_load("easyidp:croprasterbyrois", dict(
        params, OUTPUT_FOLDER=str(tmp_path / "b"),
        OUTPUT_INDEX=QgsProcessingOutputLayerDefinition("TEMPORARY_OUTPUT", None)), proj,
        load_results)
    assert len(proj.mapLayers()) == 2 and len(proj.layerTreeRoot().children()) == 2
    # asked: the index and the 20 crops, in one collapsed group just below the ROI layer
    res, queued = _run_and_load("easyidp:croprasterbyrois", dict(
        params, OUTPUT_FOLDER=str(tmp_path / "c"), OUTPUT_INDEX=_to_load(proj)), proj,
        load_results)
    assert queued == {"OUTPUT_INDEX", "OUTPUT_FILES"}
    root = proj.layerTreeRoot()
    assert [n for n, _, _ in _tree(root)] == ["zones", "Crops of dsm (20)", "dsm"]
    group = root.findGroup("Crops of dsm (20)")
    assert not group.isExpanded()
    inside = _tree(group)
    assert inside[0] == ("Index of the crops", QgsMapLayerType.VectorLayer, False)
    assert [n for n, _, _ in inside[1:]] == [Path(f).stem for f in res["OUTPUT_FILES"]]
    assert len({n for n, _, _ in inside}) == 21 and "1_2" in [n for n, _, _ in inside]
    assert all(kind == QgsMapLayerType.RasterLayer and not expanded for _, kind, expanded in inside[1:])
    index = group.children()[0].layer()
    assert index.renderer().type() == "RuleRenderer"
    assert {f["crop_status"] for f in index.getFeatures()} == {"written"} and index.featureCount() == 20
    # no crop was first tried as a vector (the layer type hint), no Python error
    assert not [m for tag, _, m in log if ".tif" in m and "Cannot open" in m]
    assert not [m for tag, level, m in log if tag == "Python error" or "Traceback" in m]
    assert res["CROPPED"] == 20


def test_heights_are_named_coloured_by_value_and_labelled(provider, realdata, project,
                                                          load_results):
    proj, _ = project
    zones = proj.addMapLayer(QgsVectorLayer(str(realdata / ZONES), "zones", "ogr"))
    _run_and_load("easyidp:roiheightsfromdsm", {
        "ROIS": zones.id(), "DSM": str(realdata / DSM), "STATISTIC": 4, "PERCENTILE": 95,
        "OUTPUT": _to_load(proj)}, proj, load_results)
    layer = next(v for v in proj.mapLayers().values() if v.name() != "zones")
    assert layer.name() == "zones: height p95 from test"
    renderer = layer.renderer()
    assert renderer.type() == "graduatedSymbol" and renderer.classAttribute() == "height"
    assert len(renderer.ranges()) == 5
    for r in renderer.ranges():                  # the orthomosaic shows through every class
        assert 0 < r.symbol().symbolLayer(0).fillColor().alpha() < 255
    assert layer.labelsEnabled() and "height" in layer.labeling().settings().fieldName


def test_footprints_are_outlines_and_cameras_small_dots(provider, realdata, project,
                                                        load_results):
    proj, _ = project
    _run_and_load("easyidp:camerafootprints", {
        "PROJECT": str(realdata / PROJECT_FILE), "GROUND_HEIGHT": 97,
        "OUTPUT_CAMERAS": _to_load(proj), "OUTPUT_FOOTPRINTS": _to_load(proj)}, proj, load_results)
    layers = {v.name(): v for v in proj.mapLayers().values()}
    assert set(layers) == {"Camera footprints of wheat_tanashi.psx", "Cameras of wheat_tanashi.psx"}
    fp = layers["Camera footprints of wheat_tanashi.psx"]
    assert fp.renderer().type() == "singleSymbol"
    for symbol in fp.renderer().symbols(QgsRenderContext()):
        sl = symbol.symbolLayer(0)
        assert sl.brushStyle() == 0 or sl.fillColor().alpha() == 0     # no fill at all
        assert sl.strokeColor().alpha() == 255
    cams = layers["Cameras of wheat_tanashi.psx"]
    assert cams.renderer().type() == "singleSymbol" and cams.renderer().symbol().size() < 2.5
    settings = cams.labeling().settings()
    assert cams.labelsEnabled() and settings.scaleVisibility and settings.minimumScale > 0
    assert "label" in cams.mapTipTemplate()


def test_every_tool_has_help_with_a_readme_anchor(provider):
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    anchors = set(re.findall(r'<a name="([^"]+)"></a>', readme))
    for alg in provider.algorithms():
        url = alg.helpUrl()
        assert url.startswith("https://") and "#" in url, alg.id()
        assert url.split("#", 1)[1] in anchors, f"{alg.id()}: no anchor {url} in README.md"
        assert alg.shortHelpString()


def test_numbers_show_as_a_user_types_them(provider):
    """Percentiles and shares get 1 and 2 decimals (QGIS shows 6: 95.000000)."""
    reg = QgsApplication.processingRegistry()
    for alg_id, name, places in (("easyidp:roiheightsfromdsm", "PERCENTILE", 1),
                                 ("easyidp:backprojectrois", "MIN_VISIBLE", 2),
                                 ("easyidp:pointcloudroistatistics", "GROUND_PERCENTILE", 1),
                                 ("easyidp:forwardprojectpolygons", "DENSIFY", 1)):
        p = reg.algorithmById(alg_id).parameterDefinition(name)
        assert isinstance(p, QgsProcessingParameterNumber)
        assert p.metadata()["widget_wrapper"]["decimals"] == places
