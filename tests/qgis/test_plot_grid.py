"""easyidp:createplotgrid and easyidp:fitplotgrid inside real QGIS and through the real
qgis_process, with GeoPackage outputs.

Kinds of check: *truth* = the demo trial's truth (its generator writes the layout plots with
explicit loops and renders the crop where its truth says it was planted); *hand* = values
worked out in the test.
"""
import json

import numpy as np
import pytest
from qgis.core import (QgsApplication, QgsProcessingContext, QgsProcessingException,
                       QgsProcessingFeedback, QgsProject, QgsRasterLayer, QgsRenderContext,
                       QgsVectorLayer)

from easyidp_toolbox.core.demo.trial import EMPTY, TRIAL, make_demo_trial, \
    perturbed_start
from easyidp_toolbox.core.plotgrid import GridAnchor, GridLayout, create_plot_grid, write_plot_grid
from easyidp_toolbox.scripts.qgis_process import run, run_algorithm


def _load(path):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


@pytest.fixture(scope="module")
def trial(tmp_path_factory):
    return make_demo_trial(str(tmp_path_factory.mktemp("trial")))


def _layout_params(trial):
    """The trial's layout as the tool's parameters (serpentine = 1, top left = 0)."""
    return {"ANCHOR": 0, "CORNERS": trial.corners, "ROWS": TRIAL["rows"], "COLS": TRIAL["cols"],
            "SIZE_X": TRIAL["size_x"], "SIZE_Y": TRIAL["size_y"], "GAP_X": TRIAL["gap_x"],
            "GAP_Y": TRIAL["gap_y"], "BLOCKS_X": TRIAL["blocks_x"],
            "BLOCK_GAP_X": TRIAL["block_gap_x"], "ORDER": 1, "START": 0,
            "START_ID": TRIAL["start_id"], "PATTERN": TRIAL["pattern"]}


def _run(alg_id, params):
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    feedback = QgsProcessingFeedback()
    alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
    results, ok = alg.run(params, context, feedback)
    return results, ok, feedback.textLog()


def _features(path):
    layer = QgsVectorLayer(str(path), "out", "ogr")
    assert layer.isValid(), path
    out = {}
    for f in layer.getFeatures():
        ring = f.geometry().asMultiPolygon()[0][0] if f.geometry().isMultipart() else \
            f.geometry().asPolygon()[0]
        out[f["plot_id"]] = (np.array([(p.x(), p.y()) for p in ring[:-1]]),
                             dict(zip(layer.fields().names(), f.attributes())))
    return out, layer.crs().authid()


def test_create_plot_grid_recreates_the_demo_trial(plugin, trial, tmp_path):
    """Truth: from the corner points layer (shuffled) and the CSV field book opened by QGIS, the
    tool's GeoPackage holds the trial's layout plots to 1 mm, same names and fields."""
    book = QgsVectorLayer(f"file://{trial.field_book}?type=csv&detectTypes=yes&geomType=none",
                          "book", "delimitedtext")
    assert book.isValid()
    out = tmp_path / "grid.gpkg"
    res, ok, log = _run("easyidp:createplotgrid", dict(_layout_params(trial), FIELD_BOOK=book,
                                                       OUTPUT=str(out)))
    assert ok, log
    assert "Corners used as upper-left (320000.00, 3956100.00)" in log
    got, crs = _features(out)
    want, _ = _features(trial.plots)
    assert crs == "EPSG:32654" and set(got) == set(want) and len(got) == 80
    for pid, (ring, attrs) in want.items():
        g_ring, g_attrs = got[pid]
        assert np.abs(g_ring - ring).max() < 1e-3, pid
        for k, v in attrs.items():
            if k != "fid":
                assert g_attrs[k] == v, (pid, k)


def test_create_plot_grid_bad_inputs_name_what_to_do(plugin, tmp_path):
    """Each bad input stops the run with the core's message (QgsProcessingException)."""
    geo = tmp_path / "corners_wgs84.geojson"
    geo.write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": c}}
        for c in ([141.0, 35.7], [141.001, 35.7], [141.001, 35.6995], [141.0, 35.6995])]}))
    res, ok, log = _run("easyidp:createplotgrid", {"CORNERS": str(geo), "ROWS": 2, "COLS": 2,
                                                   "OUTPUT": str(tmp_path / "a.gpkg")})
    assert not ok and "WGS 84 / UTM zone 54N (EPSG:32654)" in log
    three = tmp_path / "three.geojson"
    three.write_text(json.dumps({"type": "FeatureCollection", "crs": {
        "type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32654"}}, "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": c}}
        for c in ([0, 10], [20, 10], [20, 0])]}))
    res, ok, log = _run("easyidp:createplotgrid", {"CORNERS": str(three), "ROWS": 2, "COLS": 2,
                                                   "OUTPUT": str(tmp_path / "b.gpkg")})
    assert not ok and "has 3 points; exactly four are needed" in log
    res, ok, log = _run("easyidp:createplotgrid", {
        "ANCHOR": 2, "ORIGIN": "500000,4000000 [EPSG:32654]", "ROWS": 2, "COLS": 2, "SIZE_X": 2,
        "SIZE_Y": 1, "SPACING_X": 1.7, "GAP_Y": 1, "OUTPUT": str(tmp_path / "c.gpkg")})
    assert not ok and "overlap by 0.300 m along the columns" in log
    res, ok, log = _run("easyidp:createplotgrid", {"ANCHOR": 1, "ROWS": 2, "COLS": 2,
                                                   "OUTPUT": str(tmp_path / "d.gpkg")})
    assert not ok and "Field boundary: give a polygon layer" in log
    assert not any((tmp_path / n).exists() for n in ("a.gpkg", "b.gpkg", "c.gpkg", "d.gpkg"))


def test_origin_and_bearing_in_qgis_by_hand(plugin, tmp_path):
    """Hand: origin (500000, 4000000), bearing 90° (east), 1 row × 2 columns of 2 × 1 m plots
    1 m apart: plot 2 spans x 500003–500005, y 3999999–4000000."""
    out = tmp_path / "o.gpkg"
    res, ok, log = _run("easyidp:createplotgrid", {
        "ANCHOR": 2, "ORIGIN": "500000,4000000 [EPSG:32654]", "BEARING": 90, "ROWS": 1,
        "COLS": 2, "SIZE_X": 2, "SIZE_Y": 1, "GAP_X": 1, "GAP_Y": 0, "OUTPUT": str(out)})
    assert ok, log
    got, crs = _features(out)
    assert crs == "EPSG:32654"
    np.testing.assert_allclose(got["2"][0], [[500003, 4000000], [500005, 4000000],
                                             [500005, 3999999], [500003, 3999999]], atol=1e-6)


def _perturbed(path):
    """The trial's grid turned by 2°, shifted by 0.30 m, spacing 2 % off, as a GeoPackage."""
    grid, start = perturbed_start()
    grid.corners = np.array(start)
    return write_plot_grid(str(path), grid)


def test_fit_plot_grid_in_qgis_recovers_the_planted_plots(plugin, trial, tmp_path):
    """Truth: the fitted GeoPackage's plots are within 3 cm of the planted ones (median ≤ 1 cm);
    the empty plots are flagged, moved = 0, shift 0; the log gives the global correction."""
    start = _perturbed(tmp_path / "start.gpkg")
    out = tmp_path / "fitted.gpkg"
    res, ok, log = _run("easyidp:fitplotgrid", {"GRID": start, "ORTHOMOSAIC": trial.orthomosaic,
                                                "OUTPUT": str(out)})
    assert ok, log
    assert "Global correction: rotation -2.0" in log and "plots moved by more than 0.05 m" in log
    truth = _load(trial.truth)["plots"]
    got, crs = _features(out)
    err = np.array([np.hypot(*(ring - np.array(truth[pid]["planted"])).T)
                    for pid, (ring, _) in got.items()])
    assert np.median(err) <= 0.01 and err.max() <= 0.03
    for pid, (_, attrs) in got.items():
        if pid in EMPTY:
            assert attrs["moved"] == 0 and attrs["shift_m"] == 0 and attrs["fit_flag"]
            assert f"Plot '{pid}' left in place" in log
        else:
            assert attrs["moved"] == 1 and attrs["fit_flag"] in ("", None) and \
                attrs["fit_score"] > 0.3
    assert got["1-01-01"][1]["plot_no"] == 101          # the input's fields are kept


def test_fit_plot_grid_refuses_a_grid_off_the_orthomosaic(plugin, trial, tmp_path):
    grid, _ = create_plot_grid("EPSG:32654", 2, 2, anchor=GridAnchor(origin=(500000, 4000000)),
                               layout=GridLayout(size_x=2, size_y=1, gap_x=1, gap_y=1))
    path = write_plot_grid(str(tmp_path / "far.gpkg"), grid)
    res, ok, log = _run("easyidp:fitplotgrid", {"GRID": path, "ORTHOMOSAIC": trial.orthomosaic,
                                                "OUTPUT": str(tmp_path / "x.gpkg")})
    assert not ok and "do not lie on the orthomosaic" in log


def test_fit_plot_grid_is_cancellable(plugin, trial, tmp_path):
    start = _perturbed(tmp_path / "start.gpkg")
    context = QgsProcessingContext()
    feedback = QgsProcessingFeedback()
    feedback.progressChanged.connect(lambda p: feedback.cancel() if p > 10 else None)
    alg = QgsApplication.processingRegistry().createAlgorithmById("easyidp:fitplotgrid")
    with pytest.raises(QgsProcessingException, match="Cancelled"):
        alg.prepare({"GRID": start, "ORTHOMOSAIC": trial.orthomosaic,
                     "OUTPUT": str(tmp_path / "c.gpkg")}, context, feedback)
        alg.runPrepared({"GRID": start, "ORTHOMOSAIC": trial.orthomosaic,
                         "OUTPUT": str(tmp_path / "c.gpkg")}, context, feedback)
    assert not (tmp_path / "c.gpkg").exists()


def test_outputs_are_loaded_labelled_and_outlined(plugin, trial, tmp_path, load_results):
    """In the desktop's loader: the grid is loaded at the top of the tree (above the
    orthomosaic), labelled by plot_id and drawn as outlines; the fitted grid dashes the plots
    left in place."""
    from qgis.core import QgsProcessingOutputLayerDefinition
    proj = QgsProject.instance()
    proj.clear()
    try:
        proj.addMapLayer(QgsRasterLayer(trial.orthomosaic, "orthomosaic"))
        for alg_id, params in (
                ("easyidp:createplotgrid", _layout_params(trial)),
                ("easyidp:fitplotgrid", {"GRID": _perturbed(tmp_path / "s.gpkg"),
                                         "ORTHOMOSAIC": trial.orthomosaic})):
            context = QgsProcessingContext()
            context.setProject(proj)
            feedback = QgsProcessingFeedback()
            alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
            params = dict(params, OUTPUT=QgsProcessingOutputLayerDefinition(
                str(tmp_path / f"{alg.name()}.gpkg"), proj))
            results, ok = alg.run(params, context, feedback)
            assert ok, feedback.textLog()
            assert load_results(alg, context, feedback, params)
            top = proj.layerTreeRoot().children()[0].layer()
            assert top.labelsEnabled() and "plot_id" in top.labeling().settings().fieldName
            symbols = top.renderer().symbols(QgsRenderContext()) if hasattr(
                top.renderer(), "symbols") else []
            assert symbols and all(s.symbolLayer(0).brushStyle() == 0 or s.color().alpha() == 0
                                   for s in symbols)
        names = [ch.name() for ch in proj.layerTreeRoot().children()]
        assert names[-1] == "orthomosaic"
        assert names[1].startswith("Plot grid 8 × 10") and "fitted to orthomosaic" in names[0]
    finally:
        proj.clear()


# ---- headless, through the real qgis_process ---------------------------------------------------

def test_both_tools_through_qgis_process_to_geopackage(qp_env, trial, tmp_path):
    """Truth: qgis_process makes the grid from the corners and fits it; both GeoPackages hold
    80 plots, the fitted one within 3 cm of the planted plots."""
    params = _layout_params(trial)
    grid = tmp_path / "grid.gpkg"
    res = run_algorithm("easyidp:createplotgrid", dict(params, FIELD_BOOK=trial.field_book,
                                                       OUTPUT=grid), qp_env)
    assert res["OUTPUT"]
    start = _perturbed(tmp_path / "start.gpkg")
    fitted = tmp_path / "fitted.gpkg"
    run_algorithm("easyidp:fitplotgrid", {"GRID": start, "ORTHOMOSAIC": trial.orthomosaic,
                                          "OUTPUT": fitted}, qp_env)
    from osgeo import ogr
    truth = _load(trial.truth)["plots"]
    ds = ogr.Open(str(grid))
    feats = list(ds.GetLayer(0))
    assert len(feats) == 80 and feats[0].GetField("genotype")
    ds = ogr.Open(str(fitted))
    errs = []
    for f in ds.GetLayer(0):
        ring = f.GetGeometryRef().GetGeometryRef(0).GetGeometryRef(0)
        xy = np.array(ring.GetPoints())[:-1, :2]
        errs.append(np.hypot(*(xy - np.array(truth[f.GetField("plot_id")]["planted"])).T).max())
    assert len(errs) == 80 and max(errs) <= 0.03


def test_bad_input_through_qgis_process_exits_1_with_the_message(qp_env, tmp_path):
    proc = run(["run", "easyidp:createplotgrid", "--", "ANCHOR=2",
                "ORIGIN=141.0,35.7 [EPSG:4326]", "ROWS=2", "COLS=2", "SIZE_X=2", "SIZE_Y=1",
                "GAP_X=1", "GAP_Y=1", f"OUTPUT={tmp_path / 'g.gpkg'}"], qp_env)
    assert proc.returncode == 1
    assert "reproject it to WGS 84 / UTM zone 54N (EPSG:32654)" in proc.stderr + proc.stdout
    assert not (tmp_path / "g.gpkg").exists()


# ---- hostile input through qgis_process (issue 40): one refusal, no traceback, nothing written -

def _refused(proc, *needles):
    text = proc.stderr + proc.stdout
    assert proc.returncode == 1, text
    assert "Traceback" not in text, text
    for n in needles:
        assert n in text, (n, text)


def test_huge_layouts_are_refused_before_allocating_for_every_anchor(qp_env, trial, tmp_path):
    """100,000 × 100,000 plots by corners, by a boundary and by an origin: the plot count is
    checked before anything is allocated (numpy would ask for 74.5 GiB)."""
    boundary = tmp_path / "boundary.geojson"
    corners = _load(trial.corners)
    ring = sorted(f["geometry"]["coordinates"] for f in corners["features"])
    ring = [ring[0], ring[1], ring[3], ring[2], ring[0]]
    boundary.write_text(json.dumps({
        "type": "FeatureCollection", "crs": corners["crs"],
        "features": [{"type": "Feature", "properties": {},
                      "geometry": {"type": "Polygon", "coordinates": [ring]}}]}))
    for anchor in (["ANCHOR=0", f"CORNERS={trial.corners}"],
                   ["ANCHOR=1", f"BOUNDARY={boundary}"],
                   ["ANCHOR=2", "ORIGIN=320000.0,3956100.0 [EPSG:32654]", "SIZE_X=2", "SIZE_Y=1",
                    "GAP_X=1", "GAP_Y=1"]):
        out = tmp_path / f"huge{anchor[0][-1]}.gpkg"
        proc = run(["run", "easyidp:createplotgrid", "--", *anchor, "ROWS=100000",
                    "COLS=100000", f"OUTPUT={out}"], qp_env)
        _refused(proc, "10,000,000,000 plots; a grid holds at most 1,000,000")
        assert not out.exists()


def test_name_patterns_that_cannot_be_formatted_get_one_message(qp_env, tmp_path):
    for pattern in ("{row.foo}-{col}", "{row[0]}", "{plot_no:q}", "{nope}"):
        proc = run(["run", "easyidp:createplotgrid", "--", "ANCHOR=2",
                    "ORIGIN=320000.0,3956100.0 [EPSG:32654]", "ROWS=2", "COLS=2", "SIZE_X=2",
                    "SIZE_Y=1", "GAP_X=1", "GAP_Y=1", f"PATTERN={pattern}",
                    f"OUTPUT={tmp_path / 'p.gpkg'}"], qp_env)
        _refused(proc, f"Name pattern '{pattern}' cannot be formatted", "{plot_no}, {row}, {col}")
        assert not (tmp_path / "p.gpkg").exists()


def test_an_origin_without_its_crs_is_named(qp_env, tmp_path):
    proc = run(["run", "easyidp:createplotgrid", "--", "ANCHOR=2", "ORIGIN=320000.0,3956100.0",
                "ROWS=2", "COLS=2", "SIZE_X=2", "SIZE_Y=1", "GAP_X=1", "GAP_Y=1",
                f"OUTPUT={tmp_path / 'o.gpkg'}"], qp_env)
    _refused(proc, "Origin '320000.0,3956100.0' has no CRS", "[EPSG:32654]")
    assert "the layer has no CRS" not in proc.stderr + proc.stdout
    # with the output CRS set, the origin is taken in it
    res = run_algorithm("easyidp:createplotgrid", {
        "ANCHOR": 2, "ORIGIN": "320000.0,3956100.0", "CRS": "EPSG:32654", "ROWS": 2, "COLS": 2,
        "SIZE_X": 2, "SIZE_Y": 1, "GAP_X": 1, "GAP_Y": 1, "OUTPUT": tmp_path / "o2.gpkg"}, qp_env)
    assert res["OUTPUT"]


def test_damaged_and_keyless_field_books_say_what_is_wrong(qp_env, trial, tmp_path):
    params = [f"{k}={v}" for k, v in _layout_params(trial).items()]
    cases = {
        "binary.csv": (b"plot_id,genotype\n" + bytes(range(256)) * 8, "is not a text table"),
        "workbook.csv": (b"PK\x03\x04" + b"\x00" * 200, "an Excel workbook (.xlsx)"),
        "empty.csv": (b"", "is empty (0 bytes)"),
    }
    from pathlib import Path
    book = Path(trial.field_book).read_text(encoding="utf-8").splitlines()
    keyless = "\n".join(book[:2] + ["," + book[2].split(",", 1)[1]] + book[3:]) + "\n"
    for name, (data, needle) in cases.items():
        path = tmp_path / name
        path.write_bytes(data)
        proc = run(["run", "easyidp:createplotgrid", "--", *params, f"FIELD_BOOK={path}",
                    f"OUTPUT={tmp_path / 'b.gpkg'}"], qp_env)
        _refused(proc, f"Field book '{path}'", needle)
        assert not (tmp_path / "b.gpkg").exists()
    path = tmp_path / "keyless.csv"
    path.write_text(keyless, encoding="utf-8")
    proc = run(["run", "easyidp:createplotgrid", "--", *params, f"FIELD_BOOK={path}",
                f"OUTPUT={tmp_path / 'b.gpkg'}"], qp_env)
    _refused(proc, "1 row(s) have no plot_id (empty; rows 3 of the file")
    assert "on two rows" not in proc.stderr + proc.stdout


def test_fit_on_bare_soil_says_so_and_writes_nothing(qp_env, trial, tmp_path):
    import tifffile
    from easyidp_toolbox.core.raster.geotiff import open_geotiff
    from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, write_geotiff
    shape = tifffile.imread(trial.orthomosaic).shape
    rng = np.random.default_rng(4)
    soil = np.clip(np.array([122, 96, 72]) * (1 + 0.05 * rng.standard_normal(shape[:2]))[..., None],
                   0, 255).astype(np.uint8)
    tif = str(tmp_path / "soil.tif")
    write_geotiff(tif, soil, open_geotiff(trial.orthomosaic).geotransform, epsg_geo_tags(32654),
                  rgb=True, tile=256)
    start = _perturbed(tmp_path / "start.gpkg")
    out = tmp_path / "fitted.gpkg"
    proc = run(["run", "easyidp:fitplotgrid", "--", f"GRID={start}", f"ORTHOMOSAIC={tif}",
                f"OUTPUT={out}"], qp_env)
    _refused(proc, "there is no vegetation on the orthomosaic under the plots to fit the grid to",
             "the grid is left as it is")
    assert not out.exists()


def test_fit_names_and_skips_null_and_empty_geometries(qp_env, trial, tmp_path):
    """A grid with a NULL and an empty geometry among its plots: both named in the log, written
    out unchanged with the reason; the other plots fitted (truth: within 3 cm)."""
    from osgeo import ogr
    start = _perturbed(tmp_path / "start.gpkg")
    ds = ogr.Open(start, 1)
    lyr = ds.GetLayer(0)
    for pid, geom in (("null-plot", None), ("empty-plot", ogr.Geometry(ogr.wkbPolygon))):
        f = ogr.Feature(lyr.GetLayerDefn())
        f.SetField("plot_id", pid)
        if geom is not None:
            f.SetGeometry(geom)
        assert lyr.CreateFeature(f) == 0
    ds = None
    out = tmp_path / "fitted.gpkg"
    proc = run(["run", "easyidp:fitplotgrid", "--", f"GRID={start}",
                f"ORTHOMOSAIC={trial.orthomosaic}", f"OUTPUT={out}"], qp_env)
    text = proc.stderr + proc.stdout
    assert proc.returncode == 0, text
    assert "2 features have no polygon" in text and "null-plot" in text and "empty-plot" in text
    truth = _load(trial.truth)["plots"]
    ds = ogr.Open(str(out))
    seen = {}
    for f in ds.GetLayer(0):
        seen[f.GetField("plot_id")] = f.GetField("fit_flag")
        if f.GetField("plot_id") in truth:
            ring = f.GetGeometryRef().GetGeometryRef(0).GetGeometryRef(0)
            xy = np.array(ring.GetPoints())[:-1, :2]
            assert np.hypot(*(xy - np.array(truth[f.GetField("plot_id")]["planted"])).T).max() <= 0.03
    assert len(seen) == 82
    assert seen["null-plot"].startswith("no polygon") and seen["empty-plot"].startswith("no polygon")
