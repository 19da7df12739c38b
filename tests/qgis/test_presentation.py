"""How results land in the map, with QGIS's own loader (``handleAlgorithmResults``, what the
toolbox, batch and model dialogs call after a run: the ``load_results`` fixture) on the real
project: what is loaded and only when asked, names, groups, layer types and styles; help links
and number widgets."""
import re
from pathlib import Path

import pytest
from qgis.core import (QgsApplication, QgsFeature, QgsGeometry, QgsLayerTreeGroup,
                       QgsMapLayerType, QgsProcessingContext, QgsProcessingFeedback, QgsProcessingOutputLayerDefinition,
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
    # the index opened, the crops not asked for: the index only (2,000 plots would bury the map)
    _, queued = _run_and_load("easyidp:croprasterbyrois", dict(
        params, OUTPUT_FOLDER=str(tmp_path / "i"), OUTPUT_INDEX=_to_load(proj)), proj,
        load_results)
    assert queued == {"OUTPUT_INDEX"} and len(proj.mapLayers()) == 3
    proj.removeMapLayers([v.id() for v in proj.mapLayers().values() if v.name() == "Index of the crops"])
    proj.layerTreeRoot().removeChildNode(proj.layerTreeRoot().findGroup("Crops of dsm (20)"))
    # asked: the index and the 20 crops, in one collapsed group just below the ROI layer
    res, queued = _run_and_load("easyidp:croprasterbyrois", dict(
        params, OUTPUT_FOLDER=str(tmp_path / "c"), OUTPUT_INDEX=_to_load(proj), OPEN_FILES=True),
        proj, load_results)
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


def test_crops_above_the_cap_are_not_opened(provider, realdata, tmp_path, project, load_results,
                                            monkeypatch):
    """Asked to open more crops than the cap (here 5, for 20 crops): none open, the index does,
    and the log says why and where the files are."""
    from easyidp_toolbox.easyidp_qgis import presentation
    monkeypatch.setattr(presentation, "MAX_LAYERS_TO_LOAD", 5)
    proj, _ = project
    dsm = proj.addMapLayer(QgsRasterLayer(str(realdata / DSM), "dsm"))
    zones = proj.addMapLayer(QgsVectorLayer(str(realdata / ZONES), "zones", "ogr"))
    context = QgsProcessingContext()
    context.setProject(proj)
    feedback = QgsProcessingFeedback()
    alg = QgsApplication.processingRegistry().createAlgorithmById("easyidp:croprasterbyrois")
    params = {"INPUT": dsm.id(), "ROIS": zones.id(), "OUTPUT_FOLDER": str(tmp_path / "a"),
              "OUTPUT_INDEX": _to_load(proj), "OPEN_FILES": True}
    results, ok = alg.run(params, context, feedback)
    assert ok and results["CROPPED"] == 20
    assert {d.outputName for d in context.layersToLoadOnCompletion().values()} == {"OUTPUT_INDEX"}
    assert "20 files are more than the 5 loaded into the map" in feedback.textLog()


def _legend(layer):
    return [item.label() for item in layer.renderer().legendSymbolItems()]


def test_every_legend_entry_says_what_it_shows(provider):
    """Each style the tools give a layer, applied by QGIS to a layer with the tool's fields:
    no legend entry is blank (the layers panel shows the text), and a count says what it
    counts ("3 photos")."""
    from easyidp_toolbox.easyidp_qgis import presentation
    from easyidp_toolbox.easyidp_qgis.algorithms import (back_project_rois, create_demo_survey,
                                                         create_plot_grid, fit_plot_grid,
                                                         forward_project_polygons)

    def layer(fields, values):
        lyr = QgsVectorLayer("Polygon?crs=EPSG:32654&" + "&".join(f"field={f}" for f in fields),
                             "t", "memory")
        feats = []
        for row in values:
            f = QgsFeature(lyr.fields())
            f.setAttributes(list(row))
            f.setGeometry(QgsGeometry.fromWkt("POLYGON((0 0,1 0,1 1,0 1,0 0))"))
            feats.append(f)
        lyr.dataProvider().addFeatures(feats)
        return lyr
    styles = {
        "photo pixels": (back_project_rois.pixel_style(), ["roi:string", "rank:integer"],
                         [("a", 1), ("a", 2)]),
        "summary": (back_project_rois.summary_style(), ["photos:integer"], [(3,), (5,), (11,)]),
        "forward": (forward_project_polygons.detection_style(),
                    ["label:string", "complete:boolean"], [("x", True), ("y", False)]),
        "fitted grid": (fit_plot_grid.fitted_style('"plot_id"'), ["plot_id:string", "moved:integer"],
                        [("1", 1), ("2", 0)]),
        "index": (presentation.index_style(), ["crop_file:string"], [("a.tif",), (None,)]),
        "plot grid": (create_plot_grid.grid_style(), ["plot_id:string"], [("1",)]),
        "demo plots": (create_demo_survey.plots_style(), ["plot_id:string"], [("1",)]),
    }
    legends = {}
    for name, (style, fields, values) in styles.items():
        lyr = layer(fields, values)
        style(lyr)
        legends[name] = _legend(lyr)
    blank = {n: labels for n, labels in legends.items() if len(labels) > 1 and not all(labels)}
    assert blank == {}, blank
    assert legends["summary"] == ["3 photos", "5 photos", "11 photos"]
    assert len(legends["photo pixels"]) == 2 and len(legends["forward"]) == 2
    assert len(legends["fitted grid"]) == 2 and len(legends["index"]) == 2


def test_the_plot_grid_is_not_drawn_like_the_demo_plots(provider):
    """A plot grid laid over the demo plots stands apart: another outline colour."""
    from easyidp_toolbox.easyidp_qgis.algorithms import create_demo_survey, create_plot_grid

    colours = []
    for style in (create_plot_grid.grid_style(), create_demo_survey.plots_style()):
        lyr = QgsVectorLayer("Polygon?crs=EPSG:32654&field=plot_id:string", "t", "memory")
        style(lyr)
        colours.append(lyr.renderer().symbol().symbolLayer(0).strokeColor().name())
    assert colours[0] != colours[1], colours


def _display_width(text: str) -> int:
    """Characters, a wide (CJK) one counting as two: the width a label takes on a line."""
    import unicodedata
    return sum(2 if unicodedata.east_asian_width(c) in "WF" else 1 for c in text)


def test_parameter_labels_are_short_and_say_optional_once(provider):
    """Every parameter label fits one line of the default dialog (English at most 60
    characters, Chinese and Japanese at most 64 columns, a CJK character counting two; the
    details are in each parameter's help), and no label of an optional parameter says
    "optional" itself: QGIS adds "[optional]"."""
    from xml.etree import ElementTree   # the plugin's own translation files

    from qgis.core import QgsProcessingParameterDefinition
    catalogues = {lang: {m.findtext("source"): m.findtext("translation") for m in
                         ElementTree.parse(ROOT / "i18n" / f"easyidp_{lang}.ts").getroot().iter("message")}
                  for lang in ("zh_CN", "ja")}
    optional_words = {"en": ("optional",), "zh_CN": ("可选",), "ja": ("任意", "オプション", "省略可")}
    long, twice = [], []
    for alg in provider.algorithms():
        for d in alg.parameterDefinitions():
            texts = {"en": d.description()}
            texts.update({lang: cat.get(d.description()) or "" for lang, cat in catalogues.items()})
            for lang, text in texts.items():
                if _display_width(text) > (60 if lang == "en" else 64):
                    long.append(f"{alg.name()}.{d.name()} [{lang}]: {text}")
                if d.flags() & QgsProcessingParameterDefinition.FlagOptional and any(
                        w in text.lower() for w in optional_words[lang]):
                    twice.append(f"{alg.name()}.{d.name()} [{lang}]: {text}")
    assert long == [], "\n".join(long)
    assert twice == [], "\n".join(twice)


def test_one_of_three_inputs_says_so(provider):
    """Forward-project's three annotation inputs are each optional to QGIS, but one is needed:
    each label says which of the three it is, and the help says to give exactly one."""
    alg = provider.algorithm("forwardprojectpolygons")
    labels = [alg.parameterDefinition(n).description() for n in ("INPUT", "INPUT_FOLDER", "INPUT_LAYER")]
    assert [re.search(r"(\d) of 3", t).group(1) for t in labels] == ["1", "2", "3"], labels
    assert all("exactly one" in alg.parameterDefinition(n).help()
               for n in ("INPUT", "INPUT_FOLDER", "INPUT_LAYER"))
