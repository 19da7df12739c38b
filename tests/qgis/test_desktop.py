"""What a user sees in the real QGIS desktop (under Xvfb, a fresh profile, this checkout's plugin):
the session ``make screenshots`` records (``scripts/desktop_session.py``), run headless. The demo
survey and the tools through their own dialogs, batch mode both ways, the example model from the
toolbox both ways and in the modeler; asserted: the layers added (names, groups, order, count,
type), their renderers, the tools' last log line, and a message log free of Python errors and of
warnings about our outputs."""
import re
import time

import pytest

from easyidp_toolbox.scripts.qgis_desktop import (DesktopFailed, checkout_env, enable_plugin,
                                                  run_desktop, run_session)


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    found = run_session(str(tmp_path_factory.mktemp("desktop")))
    return found["session"]


def test_a_dialog_or_a_python_error_is_closed_and_quoted(tmp_path):
    """The driver closes a question and QGIS's Python error dialog at once, keeping their text,
    and keeps the error logged: a session never waits behind a dialog."""
    enable_plugin(str(tmp_path))
    found = run_desktop(str(tmp_path), {"probe": "dialog"}, timeout=180, extra_env=checkout_env())
    assert len(found["modal"]) == 2, found["modal"]
    assert any("ZeroDivisionError" in m for m in found["modal"])       # QGIS's error dialog
    assert any("Replace the planted file?" in m and "QMessageBox" in m for m in found["modal"])
    assert any("ZeroDivisionError" in e for e in found["python_errors"])


def test_a_crash_at_exit_and_an_error_in_the_message_bar_fail_the_run(tmp_path):
    """Negative control of the harness [independent: QGIS's own crash handler and its own
    transform error]. The error users met (a GeoPackage in photo pixels drawn in a map in
    EPSG:32654: "No transform available …" in red) and a signal 11 while QGIS quits (its crash
    handler aborts: 134) each fail the run, though the driver itself finished."""
    enable_plugin(str(tmp_path))
    with pytest.raises(DesktopFailed) as failed:
        run_desktop(str(tmp_path), {"probe": ["pixels_on_map", "crash"]}, timeout=180,
                    extra_env=checkout_env())
    message = str(failed.value)
    assert "(a crash: QGIS's crash handler aborted) after Project ▸ Exit QGIS" in message, message
    assert "No transform available" in message and "errors in the message bar" in message, message
    assert failed.value.found["doing"].startswith("exiting through Project ▸ Exit QGIS")


def test_a_desktop_that_hangs_fails_in_its_time_limit(tmp_path):
    """A run that never ends: the driver stops QGIS at its time limit and says what it was doing."""
    enable_plugin(str(tmp_path))
    started = time.time()
    with pytest.raises(RuntimeError, match=r"time limit of 30 s reached while the planted hang"):
        run_desktop(str(tmp_path), {"probe": "hang"}, timeout=60, extra_env=checkout_env())
    assert time.time() - started < 60


def _group(tree, name):
    for entry in tree:
        if entry.get("group") == name:
            return entry
        if "group" in entry:
            inner = _group(entry["children"], name)
            if inner is not None:
                return inner
    return None


def _layers(tree):
    for entry in tree:
        if "group" in entry:
            yield from _layers(entry["children"])
        else:
            yield entry


def _layer(tree, name):
    return next(e for e in _layers(tree) if e["name"] == name)


def test_every_run_succeeds_without_a_question_or_an_error(session):
    assert session["plugin_loaded"]
    assert session["modal"] == [], "\n\n".join(session["modal"])  # no dialog popped up
    assert all(step.get("ok", True) for step in session["steps"].values()), session["steps"]
    bad = [m for m in session["log"] if m[0] == "Python error" or m[1] >= 2
           or "Traceback" in m[2]]
    assert bad == [], "\n\n".join(f"{tag}: {text}" for tag, _, text in bad)
    ogr = [m for m in session["log"] if m[0] in ("OGR", "GDAL") and
           (".tif" in m[2] or "Cannot open" in m[2] or "easyidp" in m[2].lower())]
    assert ogr == []                                     # no crop was first opened as a vector


def test_tool_names_fit_the_toolbox_in_every_language(session):
    """Every tool name, in English, Chinese and Japanese, fits the toolbox at its default dock
    width on a 1280 × 800 screen: measured in the desktop with ``QFontMetrics`` of the view's
    font (CJK from fonts-noto-cjk) against the room the item's row leaves (the session's
    ``toolbox_fit``). The details are in each tool's help."""
    fit = session["toolbox_fit"]
    assert {lang for lang, *_ in fit} == {"en", "zh_CN", "ja"}
    assert len([f for f in fit if f[0] == "en"]) >= 14
    assert all(room > 100 for *_, room in fit), fit            # measured in a laid-out view
    cut = [f"{lang}: {name!r} is {width} px in {room} px" for lang, name, width, room in fit
           if width > room]
    assert cut == [], "\n".join(cut)


def test_demo_survey_lands_as_one_group(session):
    demo = _group(session["tree_demo"], "Demo survey")
    assert demo is not None and demo["expanded"]
    assert [(e["name"], e["type"]) for e in demo["children"]] == [
        ("Demo plots", "vector"), ("Demo orthomosaic", "raster"), ("Demo DSM", "raster")]
    plots = demo["children"][0]
    assert plots["fill_alpha"] == 0 and plots["labels"]  # outlines over the orthomosaic


def test_crops_in_one_collapsed_group_below_the_plots(session):
    """Asked for ('Open the crops in the map too'), the crops open in one collapsed group with
    their index, below the plots."""
    assert len(session["steps"]["crop"]["added"]) == 41
    demo = _group(session["tree_map"], "Demo survey")["children"]
    names = [e.get("name") or e.get("group") for e in demo]
    at = names.index("Demo plots")
    assert names[at + 1] == "Crops of Demo orthomosaic (40)"
    crops = demo[at + 1]
    assert not crops["expanded"] and len(crops["children"]) == 41
    index, rasters = crops["children"][0], crops["children"][1:]
    assert index["name"] == "Index of the crops" and index["fill_alpha"] == 0
    assert [r["name"] for r in rasters] == [f"{row}{col}" for row in "ABCDE" for col in range(1, 9)]
    assert all(r["type"] == "raster" and r["provider"] == "gdal" and r["valid"]
               and not r["expanded"] for r in rasters)


def test_heights_and_footprints_read_over_the_orthomosaic(session):
    tree = session["tree_map"]
    heights = _layer(tree, "Demo plots: height p95 from Demo DSM")
    assert heights["renderer"] == "graduatedSymbol" and heights["class_attribute"] == "height"
    assert 0 < heights["fill_alpha"] < 255 and heights["labels"]
    footprints = _layer(tree, "Camera footprints of demo_survey.psx")
    assert footprints["fill_alpha"] == 0 and footprints["features"] == 36   # outlines only
    cameras = _layer(tree, "Cameras of demo_survey.psx")
    assert cameras["geometry"] == "Point" and cameras["labels"] and cameras["features"] == 36
    assert all(e["crs"] == "EPSG:32654" for e in (heights, footprints, cameras))


def test_projection_outputs_are_named_and_styled(session):
    tree = session["tree_projection"]
    summary = _layer(tree, "Demo plots: photos of demo_survey.psx that see them")
    assert summary["renderer"] in ("categorizedSymbol", "graduatedSymbol")
    assert 0 < summary["fill_alpha"] < 255
    forward = _layer(tree, "labelme on the map (through demo_survey.psx onto Demo DSM)")
    assert forward["features"] == 16 and forward["crs"] == "EPSG:32654"
    assert 0 < forward["fill_alpha"] <= 60 and forward["labels"]


def test_photo_pixels_live_in_the_viewer_not_in_the_map(session):
    """Back-project ROIs, saved to GeoPackages and opened: the layer in photo pixels is in the
    project (for the viewer) but not in the layer tree, so the map never draws it in a fake CRS
    and no "No transform available" error shows (the run itself fails on any message-bar error:
    ``test_a_crash_at_exit_and_an_error_in_the_message_bar_fail_the_run`` is its control)."""
    viewer = session["viewer"]
    assert session["steps"]["backward"]["results"]["OUTPUT"].endswith("rois_in_photos.gpkg")
    assert viewer["pixel_layers"] == ["Demo plots in the photos of demo_survey.psx (photo pixels)"]
    assert viewer["pixel_layers_in_tree"] == [] and viewer["pixel_layer_crs"] == [""]
    names = [e["name"] for e in _layers(session["tree_projection"])]
    assert not any(n.endswith("(photo pixels)") for n in names)
    assert "Demo plots: photos of demo_survey.psx that see them" in names
    assert viewer["layer_rows"] > 40 and viewer["raw_photo"]["rois"] >= 6


def test_the_viewer_lists_the_photos_back_project_rois_lists(session):
    """[consistency only: the same core ranking] The EasyIDP toolbar button and menu entry open
    the viewer; plot C2 selected, *Selected plots* lists the photos, ranks and scores that Back-
    project ROIs wrote for C2 (its GeoPackage), with a thumbnail each and the best photo at full
    resolution; the mouse over the plot's outline on the photo puts the map marker inside the
    plot [independent: the plot polygon]; a point clicked on the map with the viewer's tool lists
    photos too."""
    viewer = session["viewer"]
    assert viewer["toolbar"] and viewer["menu"] and viewer["dock_visible"]
    assert len(viewer["plot_rows"]) >= 3, viewer["status"]
    ours, tool = sorted(viewer["plot_rows"]), viewer["tool_rows"]
    assert [r[:3] for r in ours] == [r[:3] for r in tool]
    assert all(abs(a[3] - b[3]) < 0.01 for a, b in zip(ours, tool))    # a sample of occlusion
    assert [r[2] for r in viewer["plot_rows"]] == list(range(1, len(viewer["plot_rows"]) + 1))
    assert viewer["thumbnails"] == len(viewer["plot_rows"]) and viewer["full_resolution"]
    assert viewer["after_next_previous"] == 0
    assert viewer["marker_in_plot"], viewer.get("marker")
    assert viewer["map_tool"] and viewer["point_rows"] >= 3


def test_every_tool_ends_with_a_one_line_summary(session):
    expected = {"demo": r"^Demo survey written in .* 36 photos, 40 plots",
                "crop": r"^40 GeoTIFFs written, 0 ROIs skipped\.$",
                "heights": r"^Heights \(p95\) of 40 ROIs: 9\d\.\d{3} to 9\d\.\d{3} .*0 empty",
                "footprints": r"^36 cameras and 36 footprints written\.$",
                "backward": r"ROI × photo pairs for 40 of 40 ROIs",
                "forward": r"^16 polygons from 4 photos written to the map"}
    for step, pattern in expected.items():
        log = session["steps"][step]["log"]
        last = log[log.index("Results:") - 2]           # QGIS adds the time, then the results
        assert re.search(pattern, last), (step, last)


def test_load_layers_on_completion_is_honoured_in_batch_mode(session):
    assert session["steps"]["batch_off"]["added"] == []
    assert all(len(w) == 40 for w in session["steps"]["batch_off"]["written"])  # written anyway
    on = session["steps"]["batch_on"]
    assert len(on["added"]) == 2          # the indexes only: the crops were not asked for
    assert all(len(w) == 40 for w in on["written"])
    assert on["groups"] == ["Crops of Demo DSM (40)", "Crops of Demo orthomosaic (40)"]


def test_the_model_loads_only_what_is_set_to_open(session):
    assert session["model_in_toolbox"] and session["model_valid"] == [True, []]
    assert session["steps"]["model_off"]["added"] == []
    added = session["steps"]["model_on"]["added"]
    # the crops are not asked for: the index opens, the 40 crops do not bury the map
    assert len(added) == 2 and "Plots with heights" in added and "Index of the crops" in added
    assert session["modeler_messages"] == [] and "modeler_error" not in session


def test_help_buttons_lead_to_the_readme(session):
    assert len(session["help"]) >= 10
    assert all(re.search(r"#easyidp-[a-z]+$", url) for url in session["help"].values())
