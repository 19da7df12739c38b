"""core.plotgrid: plot grids from a layout, the field-book join, and the fit to crop rows.

Kinds of check: *hand* = expected polygons computed by hand in the test; *truth* = the demo
trial's truth, written by its generator from the layout with explicit loops (not with
core.plotgrid) and a rendering of the crop where the truth says it is planted.
"""
import json
import math

import numpy as np
import pytest

from easyidp_toolbox.core import Cancelled
from easyidp_toolbox.core.demo.trial import (EMPTY, FIELD_BEARING, TRIAL, layout_plots,
                                             make_demo_trial, perturbed_start, trial_corners)
from easyidp_toolbox.core.plotgrid import (PlotGridError, create_plot_grid, fit_plot_grid,
                                           join_field_book, read_field_book, sort_corners,
                                           write_plot_grid)
from easyidp_toolbox.core.roi import open_rois

UTM = "EPSG:32654"


def _load(path):
    with open(path, encoding="utf-8") as fh:
        return json.load(fh)


@pytest.fixture(scope="module")
def trial(tmp_path_factory):
    return make_demo_trial(str(tmp_path_factory.mktemp("trial")))


def _rect(x0, x1, y0, y1):
    """Clockwise from the upper-left corner (the grid's vertex order), y up."""
    return np.array([[x0, y1], [x1, y1], [x1, y0], [x0, y0]], float)


# ---- the demo trial recreated (truth) --------------------------------------------------------

def test_demo_trial_recreated_from_its_corners_and_layout(trial):
    """Truth: the corners as written (shuffled points) and the layout give the generator's
    plots to 1 mm, with the same names, numbers, rows, columns, blocks and field book."""
    doc = _load(trial.corners)
    pts = [f["geometry"]["coordinates"] for f in doc["features"]]
    assert [f["properties"]["corner"] for f in doc["features"]] != [1, 2, 3, 4]   # shuffled
    grid, report = create_plot_grid(UTM, corners=pts, field_book=read_field_book(trial.field_book),
                                    **TRIAL)
    assert report.unmatched_rows == [] and report.plots_without_row == []
    assert "upper-left (320000.00, 3956100.00)" in grid.notes[0]
    truth = open_rois(trial.plots, name_field="plot_id")
    assert len(grid) == len(truth) == TRIAL["rows"] * TRIAL["cols"]
    assert grid.plot_id == truth.names
    for i, roi in enumerate(truth):
        ring = roi.parts[0][0]
        assert np.abs(ring - grid.corners[i]).max() < 1e-3
        attrs = grid.attributes(i)
        for k, v in roi.attributes.items():
            if k in attrs:
                assert attrs[k] == v, (roi.name, k)
        assert set(roi.attributes) - {"fid"} <= set(attrs)
    # and the loops of the generator agree with the file
    assert [p["plot_id"] for p in layout_plots()] == grid.plot_id


def test_origin_and_bearing_and_boundary_give_the_same_grid(trial):
    """Truth: the three anchors of the same field give the same plots."""
    corners = trial_corners()
    a, _ = create_plot_grid(UTM, corners=corners, **TRIAL)
    b, _ = create_plot_grid(UTM, origin=corners[0], bearing=FIELD_BEARING, **TRIAL)
    # a boundary with extra vertices on its edges, and a notch inside the rectangle
    mid = (corners[0] + corners[1]) / 2
    notch = mid + 0.5 * (corners[3] - corners[0]) / np.linalg.norm(corners[3] - corners[0])
    boundary = [np.array([corners[0], mid, notch, corners[1], corners[2],
                          (corners[2] + corners[3]) / 2, corners[3]])]
    c, _ = create_plot_grid(UTM, boundary=boundary, **TRIAL)
    assert a.plot_id == b.plot_id == c.plot_id
    assert np.abs(a.corners - b.corners).max() < 1e-6
    assert np.abs(a.corners - c.corners).max() < 1e-6


# ---- FIELDimageR's conventions (hand) ----------------------------------------------------------

def test_fieldimager_corner_order_serpentine_and_negative_buffer():
    """Hand: a 12 × 6 m field split into 2 rows × 3 columns of 4 × 3 m cells (FIELDimageR's
    fieldShape: plot = cell, no gaps), clicked upper-left, upper-right, lower-right, lower-left;
    serpentine numbering (fieldMap ``decreasing``: left to right, then right to left) from the
    upper-left; buffer −0.5 m. Then the same field turned by 30° about (100, 200)."""
    clicked = [(0, 6), (12, 6), (12, 0), (0, 0)]
    expected = [_rect(0.5, 3.5, 3.5, 5.5), _rect(4.5, 7.5, 3.5, 5.5), _rect(8.5, 11.5, 3.5, 5.5),
                _rect(8.5, 11.5, 0.5, 2.5), _rect(4.5, 7.5, 0.5, 2.5), _rect(0.5, 3.5, 0.5, 2.5)]
    for order in ([0, 1, 2, 3], [2, 0, 3, 1], [3, 2, 1, 0]):
        pts = np.array(clicked, float)[order]
        assert np.array_equal(sort_corners(pts), np.array(clicked, float))
        grid, _ = create_plot_grid(UTM, 2, 3, corners=pts, order="serpentine", buffer=-0.5)
        assert list(grid.plot_no) == [1, 2, 3, 4, 5, 6]
        assert list(grid.row) == [1, 1, 1, 2, 2, 2] and list(grid.col) == [1, 2, 3, 3, 2, 1]
        for got, want in zip(grid.corners, expected):
            np.testing.assert_allclose(got, want, atol=1e-9)
    t = math.radians(30)
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    turn = lambda p: np.asarray(p, float) @ R.T + (100.0, 200.0)   # noqa: E731
    grid, _ = create_plot_grid(UTM, 2, 3, corners=turn(clicked)[[1, 3, 0, 2]],
                               order="serpentine", buffer=-0.5, pattern="P{plot_no:03d}")
    assert grid.plot_id == ["P001", "P002", "P003", "P004", "P005", "P006"]
    for got, want in zip(grid.corners, expected):
        np.testing.assert_allclose(got, turn(want), atol=1e-9)


def test_start_corner_start_id_blocks_and_gaps_by_hand():
    """Hand: 2 rows × 4 columns of 2 × 1 m plots, gap 0.5 m between plots, 2 blocks along x
    1.0 m apart, alley 2 m between the rows, from origin (0, 10) bearing 90° (east); numbered
    row-major from the bottom-right corner starting at 11; a +0.1 m buffer."""
    grid, _ = create_plot_grid(UTM, 2, 4, origin=(0, 10), bearing=90, size_x=2, size_y=1,
                               gap_x=0.5, gap_y=2, blocks_x=2, block_gap_x=1.0, buffer=0.1,
                               start="bottom-right", start_id=11,
                               pattern="{block}-{row}-{col}")
    # x edges: 0–2, 2.5–4.5 | 5.5–7.5, 8–10 ; y: top row 10–9, bottom row 7–6
    xs = [(0, 2), (2.5, 4.5), (5.5, 7.5), (8, 10)]
    ys = [(9, 10), (6, 7)]
    b = 0.1
    # numbering from the bottom-right: row 1 = the bottom row, col 1 = the rightmost column
    want_ids, want = [], []
    for r in range(2):
        for c in range(4):
            gx = xs[3 - c]
            gy = ys[1 - r]
            want.append(_rect(gx[0] - b, gx[1] + b, gy[0] - b, gy[1] + b))
            want_ids.append(f"{1 + c // 2}-{r + 1}-{c + 1}")
    assert grid.plot_id == want_ids
    assert list(grid.plot_no) == list(range(11, 19))
    for got, w in zip(grid.corners, want):
        np.testing.assert_allclose(got, w, atol=1e-9)


def test_sizes_or_gaps_solved_from_the_corners():
    """Hand: 3 columns of 3 m in a 10 m field: the gap is (10 − 9) / 2 = 0.5 m; without sizes
    the plots fill the field between 0.25 m gaps: (10 − 0.5) / 3."""
    corners = [(0, 4), (10, 4), (10, 0), (0, 0)]
    g, _ = create_plot_grid(UTM, 1, 3, corners=corners, size_x=3.0)
    np.testing.assert_allclose(g.corners[1], _rect(3.5, 6.5, 0, 4), atol=1e-9)
    g, _ = create_plot_grid(UTM, 1, 3, corners=corners, gap_x=0.25)
    w = (10 - 0.5) / 3
    np.testing.assert_allclose(g.corners[2], _rect(10 - w, 10, 0, 4), atol=1e-9)
    g, _ = create_plot_grid(UTM, 1, 3, corners=corners, size_x=2.0, gap_x=1.0)   # centred
    np.testing.assert_allclose(g.corners[0], _rect(1.0, 3.0, 0, 4), atol=1e-9)


def test_geopackage_round_trip(tmp_path):
    grid, _ = create_plot_grid(UTM, 2, 3, origin=(500000, 4000000), bearing=60, size_x=3,
                               size_y=2, gap_x=1, gap_y=1)
    grid.fields["genotype"] = ["a", "b", None, "d", "e", "f"]
    path = write_plot_grid(str(tmp_path / "grid.gpkg"), grid)
    back = open_rois(path, name_field="plot_id")
    assert back.names == grid.plot_id and back.crs.to_epsg() == 32654
    assert [r.attributes["genotype"] for r in back] == grid.fields["genotype"]
    for roi, c in zip(back, grid.corners):
        np.testing.assert_allclose(roi.parts[0][0], c, atol=1e-6)


# ---- the field book --------------------------------------------------------------------------

def test_field_book_join_reports_by_name(tmp_path):
    grid, _ = create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=1, size_y=1, gap_x=1, gap_y=1,
                               pattern="{row_letter}{col}")
    assert grid.plot_id == ["A1", "A2", "B1", "B2"]
    csv = tmp_path / "book.csv"
    csv.write_text("\ufeffplot;genotype;yield\nA1;G1;1.5\nA2;G2;2\nB1;G3;\nZ9;G9;3\n",
                   encoding="utf-8")
    report = join_field_book(grid, read_field_book(str(csv)), "plot_id", book_id="plot")
    assert report.unmatched_rows == ["Z9"] and report.plots_without_row == ["B2"]
    assert grid.fields["genotype"] == ["G1", "G2", "G3", None]
    assert grid.fields["yield"] == [1.5, 2.0, None, None]
    msgs = report.messages()
    assert "match no plot (1): Z9" in msgs[0] and "no field-book row (1): B2" in msgs[1]
    # by row and column; a column called 'block' does not replace the grid's
    g2, _ = create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=1, size_y=1, gap_x=1, gap_y=1)
    rep = join_field_book(g2, [{"r": "1", "c": "2.0", "block": "x"}], "row_col", book_row="r",
                          book_col="c")
    assert g2.fields["book_block"] == [None, "x", None, None]
    assert rep.plots_without_row == ["1", "3", "4"]
    with pytest.raises(PlotGridError, match=r"key '1/2' \(r/c\) is on two rows"):
        join_field_book(g2, [{"r": 1, "c": 2}, {"r": "1", "c": "2"}], "row_col", book_row="r",
                        book_col="c")
    with pytest.raises(PlotGridError, match="no column 'plot_id'.*its columns: r, c"):
        join_field_book(g2, [{"r": 1, "c": 2}])


# ---- bad input -------------------------------------------------------------------------------

def test_geographic_crs_names_the_utm_zone():
    with pytest.raises(PlotGridError) as e:
        create_plot_grid("EPSG:4326", 2, 2, corners=[(141.0, 35.7), (141.001, 35.7),
                                                      (141.001, 35.6995), (141.0, 35.6995)])
    msg = str(e.value)
    assert "geographic" in msg and "WGS 84 / UTM zone 54N (EPSG:32654)" in msg
    assert "\n" not in msg
    with pytest.raises(PlotGridError, match=r"UTM zone 19S \(EPSG:32719\)"):
        create_plot_grid("EPSG:4326", 1, 1, origin=(-70.0, -33.0), size_x=1, size_y=1, gap_x=0,
                         gap_y=0)


def test_web_mercator_metres_are_refused_with_the_utm_zone():
    """Hand: at latitude 35.7° Web Mercator stretches distances by 1/cos(35.7°) = 1.2314."""
    from pyproj import Transformer
    x, y = Transformer.from_crs(4326, 3857, always_xy=True).transform(141.0, 35.7)
    with pytest.raises(PlotGridError, match=r"stretches distances by 1\.231 at the field.*23 % "
                                            r"off: reproject it to WGS 84 / UTM zone 54N"):
        create_plot_grid("EPSG:3857", 1, 1, origin=(x, y), size_x=1, size_y=1, gap_x=0, gap_y=0)
    create_plot_grid("EPSG:32654", 1, 1, origin=(500000, 3950000), size_x=1, size_y=1, gap_x=0,
                     gap_y=0)                                    # UTM: scale 0.9996, accepted


def test_corners_that_make_no_rectangle_say_by_how_much():
    # hand: a symmetric trapezoid, top edge 20 m, bottom edge 22 m, 10 m apart: the nearest
    # rectangle is 21 × 10 m, and every corner is 0.5 m from it
    with pytest.raises(PlotGridError, match=r"not a rectangle: the upper-left corner is 0\.500 m "
                                            r"from the nearest rectangle \(tolerance 0\.25 m"):
        create_plot_grid(UTM, 2, 2, corners=[(0, 10), (20, 10), (21, 0), (-1, 0)])
    g, _ = create_plot_grid(UTM, 1, 1, corners=[(0, 10), (20, 10), (21, 0), (-1, 0)],
                            tolerance=0.6)
    np.testing.assert_allclose(g.corners[0], _rect(-0.5, 20.5, 0, 10), atol=1e-9)
    with pytest.raises(PlotGridError, match="exactly four points"):
        create_plot_grid(UTM, 2, 2, corners=[(0, 10), (20, 10), (20, 0)])


def test_overlapping_plots_say_by_how_much():
    with pytest.raises(PlotGridError, match=r"overlap by 0\.300 m along the columns"):
        create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=2, size_y=1, spacing_x=1.7, gap_y=1)
    with pytest.raises(PlotGridError, match=r"overlap by 0\.200 m along the rows.*buffer adds "
                                            r"0\.35 m"):
        create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=2, size_y=1, gap_x=1, gap_y=0.5,
                         buffer=0.35)
    with pytest.raises(PlotGridError, match=r"do not fit in the field.*1\.000 m too long"):
        create_plot_grid(UTM, 1, 3, corners=[(0, 4), (10, 4), (10, 0), (0, 0)], size_x=3,
                         gap_x=1)
    with pytest.raises(PlotGridError, match="collapse to a line"):
        create_plot_grid(UTM, 1, 3, corners=[(0, 4), (10, 4), (10, 0), (0, 0)], gap_x=6)
    with pytest.raises(PlotGridError, match="does not divide the 3 columns"):
        create_plot_grid(UTM, 1, 3, corners=[(0, 4), (10, 4), (10, 0), (0, 0)], blocks_x=2)
    with pytest.raises(PlotGridError, match="same name to several plots"):
        create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=1, size_y=1, gap_x=1, gap_y=1,
                         pattern="{row}")
    with pytest.raises(PlotGridError, match="Name pattern '{genotype}'"):
        create_plot_grid(UTM, 2, 2, origin=(0, 0), size_x=1, size_y=1, gap_x=1, gap_y=1,
                         pattern="{genotype}")


def test_ten_thousand_plots_quickly():
    import time
    t = time.perf_counter()
    grid, _ = create_plot_grid(UTM, 100, 100, origin=(500000, 4000000), bearing=80, size_x=3,
                               size_y=1.5, gap_x=0.5, gap_y=1.0, order="serpentine",
                               pattern="{block}-{row:03d}-{col:03d}")
    assert len(grid) == 10_000 and len(set(grid.plot_id)) == 10_000
    assert time.perf_counter() - t < 5      # the bench's target is 1 s; shared test machines


# ---- the fit (truth) -------------------------------------------------------------------------

def test_fit_recovers_the_planted_plots(trial):
    """Truth: from the grid turned by 2°, shifted by 0.30 m and with its spacing 2 % off, every
    plot's fitted outline is within 5 cm of where the crop was planted (median ≤ 2 cm); the
    empty plots are flagged and not moved by a per-plot shift."""
    truth = _load(trial.truth)
    grid, start = perturbed_start()
    before = np.array([np.hypot(*(s - np.array(truth["plots"][p]["planted"])).T)
                       for s, p in zip(start, grid.plot_id)])
    assert np.median(before) > 0.3                       # the start is far off
    res = fit_plot_grid(start, trial.orthomosaic)
    err = np.array([np.hypot(*(r - np.array(truth["plots"][p]["planted"])).T)
                    for r, p in zip(res.rings, grid.plot_id)])
    assert np.median(err) <= 0.02 and err.max() <= 0.05, (np.median(err), err.max())
    assert abs(res.rotation + 2.0) < 0.1
    assert all(abs(s - 1 / 1.02) < 0.005 for s in res.scale)
    assert abs(res.row_spacing - 0.5) < 0.03
    assert abs((res.row_bearing - FIELD_BEARING + 90) % 180 - 90) < 0.5
    empty = [i for i, p in enumerate(grid.plot_id) if p in EMPTY]
    assert sorted(grid.plot_id[i] for i in range(len(grid)) if res.flag[i]) == sorted(EMPTY)
    for i in empty:
        assert not res.moved[i] and np.all(res.shift[i] == 0) and res.flag[i] == "bare soil or missing"
    planted = [i for i in range(len(grid)) if i not in empty]
    assert res.moved[planted].all() and res.score[planted].min() > 0.9
    # the per-plot shifts are the planter offsets (up to 6 cm each way)
    assert res.moved_over(0.02) > 20
    assert "Global correction: rotation" in res.summary()


def test_fit_is_cancellable(trial):
    grid, start = perturbed_start()
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) > 3

    with pytest.raises(Cancelled):
        fit_plot_grid(start, trial.orthomosaic, is_cancelled=cancel)


def test_fit_bad_input(trial):
    grid, start = perturbed_start()
    with pytest.raises(Exception, match="do not lie on the orthomosaic"):
        fit_plot_grid([s + (5000.0, 0.0) for s in start], trial.orthomosaic)
    with pytest.raises(Exception, match="NDVI: give the band numbers"):
        fit_plot_grid(start, trial.orthomosaic, index="ndvi")
    with pytest.raises(Exception, match=r"Band numbers \[1, 2, 5\]"):
        fit_plot_grid(start, trial.orthomosaic, bands=(1, 2, 5))


def _fit_errors(trial, raster, **kw):
    truth = _load(trial.truth)
    grid, start = perturbed_start()
    res = fit_plot_grid(start, raster, **kw)
    err = np.array([np.hypot(*(r - np.array(truth["plots"][p]["planted"])).T)
                    for r, p in zip(res.rings, grid.plot_id)])
    flagged = sorted(p for p, f in zip(grid.plot_id, res.flag) if f)
    return err, flagged, res


def test_fit_multispectral_ndvi_and_the_other_reading_paths(trial, tmp_path, monkeypatch):
    """Truth: the trial as a 4-band uint16 multispectral raster (NIR from the green band, with
    a nodata value), fitted on NDVI; and the RGB trial read in strips and in tiles with 2 × 2
    cells (the general and the tile-aligned reading): the same errors and flags."""
    import tifffile
    from easyidp_toolbox.core.raster.geotiff import open_geotiff
    from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, write_geotiff
    from easyidp_toolbox.core.plotgrid import fit as fit_module
    rgb = tifffile.imread(trial.orthomosaic).astype(np.uint16)
    gt = open_geotiff(trial.orthomosaic).geotransform
    ms = np.stack([rgb[..., 2] * 10, rgb[..., 1] * 10, rgb[..., 0] * 10, rgb[..., 1] * 30], -1)
    ms[:5] = 0                                           # a nodata strip along the top
    path = str(tmp_path / "ms.tif")
    write_geotiff(path, ms.astype(np.uint16), gt, epsg_geo_tags(32654), nodata_text="0", tile=256)
    err, flagged, res = _fit_errors(trial, path, index="ndvi", bands=(3, 4))
    assert np.median(err) <= 0.02 and err.max() <= 0.05 and flagged == sorted(EMPTY)
    assert "NDVI" in res.notes[0]
    strips = str(tmp_path / "strips.tif")
    write_geotiff(strips, tifffile.imread(trial.orthomosaic), gt, epsg_geo_tags(32654), rgb=True,
                  rowsperstrip=7)
    monkeypatch.setattr(fit_module, "MAX_WORK_PIXELS", 1_000_000)      # cells of 2 × 2 pixels
    for raster in (strips, trial.orthomosaic):
        err, flagged, res = _fit_errors(trial, raster)
        assert abs(res.work_pixel - 0.04) < 1e-9
        assert np.median(err) <= 0.02 and err.max() <= 0.05 and flagged == sorted(EMPTY)
    with pytest.raises(Exception, match="not RGB: choose the NDVI index"):
        fit_plot_grid(perturbed_start()[1], path)


def test_fit_flags_a_weedy_plot_and_keeps_a_shift_within_the_bound(trial, tmp_path):
    """Truth: weeds (vegetation blobs) sown over one plot and its surroundings make it 'weak'
    and left in place; with a bound of 1 cm the plots planted further off are left in place."""
    import tifffile
    from easyidp_toolbox.core.raster.geotiff import open_geotiff
    from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, write_geotiff
    truth = _load(trial.truth)
    img = tifffile.imread(trial.orthomosaic).copy()
    info = open_geotiff(trial.orthomosaic)
    weedy = "1-05-03"
    c = np.array(truth["plots"][weedy]["planted"]).mean(axis=0)
    col, row = info.map_to_pixel(c[0], c[1])
    rng = np.random.default_rng(5)
    for _ in range(400):                                # blobs over a 5 × 4 m area
        r0 = int(row + rng.uniform(-100, 100))
        c0 = int(col + rng.uniform(-125, 125))
        img[max(r0 - 8, 0):r0 + 8, max(c0 - 8, 0):c0 + 8] = (60, 140, 48)
    path = str(tmp_path / "weedy.tif")
    write_geotiff(path, img, info.geotransform, epsg_geo_tags(32654), rgb=True, tile=256)
    err, flagged, res = _fit_errors(trial, path)
    grid, _ = perturbed_start()
    i = grid.plot_id.index(weedy)
    assert res.flag[i] and not res.moved[i], res.flag[i]
    offsets = {p: np.hypot(*truth["plots"][p]["offset"]) for p in grid.plot_id}
    err, flagged, res = _fit_errors(trial, trial.orthomosaic, max_shift=0.01)
    for p, f, m, s in zip(grid.plot_id, res.flag, res.moved, res.shift_m):
        assert s <= 0.01
        if offsets[p] > 0.02 and p not in EMPTY:
            assert f == "shift beyond the bound" and not m
