"""The demo trial: a breeding trial laid out by a known plot-grid layout, with its truth.

The demo survey's plots (:mod:`.scene`) are each turned by their own random angle (so that
back-projection meets rotated ROIs), so no grid layout reproduces them. The trial is the field a
plot-grid tool is for: :data:`TRIAL` rows × columns in two blocks (replicates), the field turned
by :data:`FIELD_BEARING`, serpentine numbering, a field book, sown crop rows inside every plot
(rows along the plot's x axis, 0.5 m apart, plants every 0.15 m, a bare 0.1 m edge) and
:data:`EMPTY` plots (bare soil, nothing sown). By default the plots touch their neighbours across
the rows (no alley between ranges: :data:`TRIAL`'s ``gap_y`` is 0; ``Hardness(touching=False)``
gives the 1 m alleys of :data:`TRIAL_WITH_ALLEYS`), and the field is as messy as a real one
(:class:`.trial_render.Hardness`: margin grass, weeds in the plots and alleys, uneven vigour,
missing row segments, lodging, shadows, a soil gradient).

The *layout* plots are what ``core.plotgrid.create_plot_grid`` makes from the four field
corners and the layout (``plots.gpkg``). The *planted* plots are where the crop really is:
the layout plot moved by a small planter offset (uniform in ±:data:`PLANTER_OFFSET` m along
each grid axis; none for the empty plots, which stay where the layout puts them)
(``planted.gpkg``). The layout, the offsets and the empty plots are written by this module with
loops and its own random stream, independently of ``core.plotgrid`` and of the rendering.
``make_demo_trial(folder)`` writes::

    orthomosaic.tif   RGB, 2 cm, tiled 256, deflate (EPSG:32654)
    corners.geojson   the four field corners, as points, in a shuffled order
    field_book.csv    plot_id, genotype, rep, treatment
    plots.gpkg        the layout plots (plot_id, plot_no, row, col, block + the field book)
    planted.gpkg      the planted plots (same fields, and empty = 1 for the empty plots)
    truth.json        the layout, the corners, the empty plots, every plot's offset, the
                      hardness parameters and what was drawn in each plot (weeds, lodging, …)
"""
import csv
import io
import math
import os
from dataclasses import dataclass
from typing import Dict, List, Optional

import numpy as np

from ..files import OutputFolder, write_bytes, write_json
from ..gpkg import GpkgTable, field_type, write_geopackage
from ..plotgrid import create_plot_grid, grid_options
from ..raster import epsg_geo_tags, write_geotiff
from .field import FieldLayout
from .trial_render import Hardness, render_field

EPSG = 32654
PIXEL = 0.02
UPPER_LEFT = (320000.0, 3956100.0)
FIELD_BEARING = 78.0          # degrees: the top edge, clockwise from grid north (east = 90)
PLANTER_OFFSET = 0.06         # m
MARGIN = 3.0                  # m of bare soil around the field in the orthomosaic
EMPTY = ("1-03-04", "1-06-02", "2-02-08", "2-07-09")
TRIAL = dict(rows=8, cols=10, size_x=3.0, size_y=1.5, gap_x=0.5, gap_y=0.0, blocks_x=2,
             block_gap_x=1.5, order="serpentine", start="top-left", start_id=101,
             pattern="{block}-{row:02d}-{col:02d}")
"""The layout (plots touching across the rows), as flat ``core.plotgrid.grid_options`` keywords."""
TRIAL_WITH_ALLEYS = dict(TRIAL, size_y=1.6, gap_y=1.0)
"""The layout with 1 m alleys between the ranges (``Hardness(touching=False)``)."""


def trial_layout(hardness: Optional[Hardness] = None) -> dict:
    """The layout of a trial of this hardness (default: :data:`TRIAL`)."""
    return TRIAL if hardness is None or hardness.touching else TRIAL_WITH_ALLEYS
ENTRIES = ("orthomosaic.tif", "corners.geojson", "field_book.csv", "plots.gpkg", "planted.gpkg",
           "truth.json")


@dataclass
class DemoTrial:
    folder: str
    orthomosaic: str
    corners: str
    field_book: str
    plots: str
    planted: str
    truth: str
    crs: str


def _frame():
    """(upper-left corner, unit x along the top edge, unit y down the left edge)."""
    t = math.radians(FIELD_BEARING)
    ux = np.array([math.sin(t), math.cos(t)])
    return np.array(UPPER_LEFT), ux, np.array([ux[1], -ux[0]])


def _starts(T: dict = TRIAL):
    """Offsets of the plots' near edges along x (columns) and y (rows), and the field size."""
    per_block = T["cols"] // T["blocks_x"]
    xs = [c * T["size_x"] + c * T["gap_x"] + (c // per_block) * (T["block_gap_x"] - T["gap_x"])
          for c in range(T["cols"])]
    ys = [r * (T["size_y"] + T["gap_y"]) for r in range(T["rows"])]
    return xs, ys, (xs[-1] + T["size_x"], ys[-1] + T["size_y"])


def trial_corners(T: dict = TRIAL) -> np.ndarray:
    """(4, 2) field corners: upper-left, upper-right, lower-right, lower-left."""
    o, ux, uy = _frame()
    _, _, (w, h) = _starts(T)
    return np.array([o, o + w * ux, o + w * ux + h * uy, o + h * uy])


def layout_plots(T: dict = TRIAL) -> List[dict]:
    """The layout's plots in numbering order, written out from :data:`TRIAL` with loops (not
    with ``core.plotgrid``, which the tests check against them): serpentine rows from the
    upper-left corner, corners clockwise from each plot's upper-left one."""
    o, ux, uy = _frame()
    xs, ys, _ = _starts(T)
    per_block = T["cols"] // T["blocks_x"]
    plots, no = [], T["start_id"]
    for r in range(T["rows"]):
        cols = range(T["cols"]) if r % 2 == 0 else range(T["cols"] - 1, -1, -1)
        for c in cols:
            a, b = xs[c], ys[r]
            corners = np.array([o + (a + da) * ux + (b + db) * uy for da, db in
                                ((0, 0), (T["size_x"], 0), (T["size_x"], T["size_y"]),
                                 (0, T["size_y"]))])
            block = c // per_block + 1
            plots.append({"plot_id": f"{block}-{r + 1:02d}-{c + 1:02d}", "plot_no": no,
                          "row": r + 1, "col": c + 1, "block": block, "corners": corners})
            no += 1
    return plots


class _Layout:
    """The layout plots with the grid's attribute names (what the writers below need)."""

    def __init__(self, plots, book):
        self.plots = plots
        self.plot_id = [p["plot_id"] for p in plots]
        self.block = [p["block"] for p in plots]
        self.col = [p["col"] for p in plots]
        self.corners = np.array([p["corners"] for p in plots])
        by_id = {r["plot_id"]: r for r in book} if book else {}
        self.book = by_id

    def __len__(self):
        return len(self.plots)

    def field_names(self):
        extra = [k for k in next(iter(self.book.values()), {}) if k != "plot_id"]
        return ["plot_id", "plot_no", "row", "col", "block"] + extra

    def attributes(self, i):
        p = self.plots[i]
        out = {k: p[k] for k in ("plot_id", "plot_no", "row", "col", "block")}
        out.update({k: v for k, v in self.book.get(p["plot_id"], {}).items() if k != "plot_id"})
        return out


def field_book_rows(grid, seed: int = 0) -> List[dict]:
    """One row per plot: genotypes G01… shuffled within each block, rep = block, two
    treatments alternating by column."""
    rng = np.random.default_rng([seed, 25])
    rows = []
    for b in sorted(set(int(x) for x in grid.block)):
        idx = [i for i in range(len(grid)) if grid.block[i] == b]
        geno = rng.permutation(len(idx)) + 1
        for i, g in zip(idx, geno):
            rows.append({"plot_id": grid.plot_id[i], "genotype": f"G{g:02d}", "rep": b,
                         "treatment": "irrigated" if grid.col[i] % 2 else "rainfed"})
    return rows


def layout_grid(seed: int = 0, T: dict = TRIAL) -> _Layout:
    """The layout plots with the field book (what ``plots.gpkg`` holds)."""
    plots = _Layout(layout_plots(T), None)
    return _Layout(plots.plots, field_book_rows(plots, seed))


def planted_offsets(grid, seed: int = 0) -> Dict[str, tuple]:
    """Planter offsets (along the grid's x, y axes, m) per plot id; (0, 0) for empty plots."""
    rng = np.random.default_rng([seed, 26])
    off = rng.uniform(-PLANTER_OFFSET, PLANTER_OFFSET, (len(grid), 2))
    return {pid: ((0.0, 0.0) if pid in EMPTY else (float(o[0]), float(o[1])))
            for pid, o in zip(grid.plot_id, off)}


def planted_corners(grid, offsets) -> np.ndarray:
    _, ux, uy = _frame()
    return np.array([grid.corners[i] + offsets[p][0] * ux + offsets[p][1] * uy
                     for i, p in enumerate(grid.plot_id)])


def render_orthomosaic(grid, offsets, seed: int = 0, hardness: Optional[Hardness] = None,
                       T: dict = TRIAL):
    """(RGB uint8 image, geotransform, what was drawn in each plot) of the trial."""
    hardness = hardness or Hardness()
    corners = trial_corners(T)
    x0 = math.floor((corners[:, 0].min() - MARGIN) / PIXEL) * PIXEL
    x1 = math.ceil((corners[:, 0].max() + MARGIN) / PIXEL) * PIXEL
    y0 = math.floor((corners[:, 1].min() - MARGIN) / PIXEL) * PIXEL
    y1 = math.ceil((corners[:, 1].max() + MARGIN) / PIXEL) * PIXEL
    lay = FieldLayout(origin=(x0, y1), size=(x1 - x0, y1 - y0), epsg=EPSG)
    _, ux, _ = _frame()
    angle = math.atan2(ux[1], ux[0])
    gt = lay.geotransform(PIXEL)
    img, feats = render_field(lay.grid_shape(PIXEL), gt, planted_corners(grid, offsets), angle,
                              (T["size_x"], T["size_y"]), list(grid.plot_id),
                              [p in EMPTY for p in grid.plot_id], corners, hardness, seed)
    return img, gt, feats


def _csv_text(rows: List[dict]) -> bytes:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(rows[0]), lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return buf.getvalue().encode("utf-8")


def make_demo_trial(folder: str, seed: int = 0, overwrite: bool = False,
                    hardness: Optional[Hardness] = None) -> DemoTrial:
    """Write the demo trial into ``folder`` (see the module docstring); ``hardness``: how messy
    the field is (default: :class:`.trial_render.Hardness`'s hard levels)."""
    hardness = hardness or Hardness()
    T = trial_layout(hardness)
    with OutputFolder(folder, overwrite=overwrite, what="Demo trial folder") as out:
        out.claim(ENTRIES)
        folder = str(out.folder)
        grid = layout_grid(seed, T)
        offsets = planted_offsets(grid, seed)
        img, gt, feats = render_orthomosaic(grid, offsets, seed, hardness, T)
        paths = {k: os.path.join(folder, k) for k in ENTRIES}
        write_geotiff(paths["orthomosaic.tif"], img, gt, epsg_geo_tags(EPSG), rgb=True, tile=256)
        corners = trial_corners(T)
        order = [2, 0, 3, 1]                             # shuffled: the tool sorts them
        write_json(paths["corners.geojson"], {
            "type": "FeatureCollection", "name": "corners",
            "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{EPSG}"}},
            "features": [{"type": "Feature", "properties": {"corner": k + 1},
                          "geometry": {"type": "Point", "coordinates": corners[k].tolist()}}
                         for k in order]})
        book = field_book_rows(grid, seed)
        write_bytes(paths["field_book.csv"], _csv_text(book))
        names = grid.field_names()
        rows = [tuple(grid.attributes(i)[k] for k in names) for i in range(len(grid))]
        types = [field_type([r[j] for r in rows]) for j in range(len(names))]
        pc = planted_corners(grid, offsets)
        empty = [int(p in EMPTY) for p in grid.plot_id]
        write_geopackage(paths["plots.gpkg"], [GpkgTable(
            "plots", list(zip(names, types)), rows, [[[c]] for c in grid.corners], f"EPSG:{EPSG}")])
        write_geopackage(paths["planted.gpkg"], [GpkgTable(
            "planted", list(zip(names, types)) + [("empty", "INTEGER")],
            [r + (e,) for r, e in zip(rows, empty)], [[[c]] for c in pc], f"EPSG:{EPSG}")])
        write_json(paths["truth.json"], {
            "format": "easyidp-demo-trial-truth", "version": 1, "seed": seed,
            "crs": f"EPSG:{EPSG}", "pixel": PIXEL,
            "layout": T, "field_bearing": FIELD_BEARING, "hardness": hardness.as_dict(),
            "corners": {"order": ["upper-left", "upper-right", "lower-right", "lower-left"],
                        "xy": corners.tolist()},
            "empty_plots": list(EMPTY),
            "planter_offsets": "metres along the grid's x axis (top edge) and y axis (down the "
                               "left edge); planted plot = layout plot + offset",
            "plots": {p: {"offset": offsets[p], "layout": grid.corners[i].tolist(),
                          "planted": pc[i].tolist(), "drawn": feats[p]}
                      for i, p in enumerate(grid.plot_id)}},
            indent=None)
        return DemoTrial(folder, paths["orthomosaic.tif"], paths["corners.geojson"],
                         paths["field_book.csv"], paths["plots.gpkg"], paths["planted.gpkg"],
                         paths["truth.json"], f"EPSG:{EPSG}")


def perturbed_start(rotation_deg: float = 2.0, shift=(0.3 * math.cos(0.5), 0.3 * math.sin(0.5)),
                    spacing: float = 1.02, T: dict = TRIAL):
    """The fit's starting grid in the demo and the tests: the trial's layout (as
    ``create_plot_grid`` makes it) with the plots' centres spread ``spacing`` × from the grid's
    centre (plot sizes right; below 1 touching plots overlap), then the whole turned by
    ``rotation_deg`` (degrees, counter-clockwise) about that centre and shifted by ``shift``
    (east, north in m; 0.30 m). Returns (the grid as made, its corners moved: one (4, 2) array
    per plot)."""
    grid, _ = create_plot_grid(f"EPSG:{EPSG}", **grid_options(origin=trial_corners(T)[0],
                                                              bearing=FIELD_BEARING, **T))
    c = grid.corners.reshape(-1, 2).mean(axis=0)
    t = math.radians(rotation_deg)
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    out = []
    for q in grid.corners:
        m = q.mean(axis=0)
        out.append((c + (m - c) * spacing + (q - m)) @ R.T + (c - c @ R.T) + np.asarray(shift))
    return grid, out


def start_grids(count: int = 8, seed: int = 0):
    """``count`` start grids for the fit, spread over seeds: rotation up to ±3°, shift up to
    0.5 m, spacing ±3 % (the corners first at the extremes, then random). Returns
    [((rotation°, (dx, dy) m, spacing), (grid, corners))]."""
    rng = np.random.default_rng([seed, 32])
    out = []
    for k in range(count):
        if k < 4:
            rot = (3.0, -3.0, 3.0, -3.0)[k]
            sp = (1.03, 0.97, 0.97, 1.03)[k]
            ang = k * math.pi / 2 + 0.4
            shift = (0.5 * math.cos(ang), 0.5 * math.sin(ang))
        else:
            rot, sp = float(rng.uniform(-3, 3)), float(rng.uniform(0.97, 1.03))
            r, ang = 0.5 * math.sqrt(rng.random()), rng.uniform(0, 2 * math.pi)
            shift = (r * math.cos(ang), r * math.sin(ang))
        out.append(((rot, shift, sp), perturbed_start(rot, shift, sp)))
    return out


FIT_SEEDS = (0, 1, 2)
"""The trial seeds the fit is checked on (issue 32: start grids spread over seeds)."""


def start_grids_over_seeds(seeds=FIT_SEEDS, count: int = 9):
    """:func:`start_grids` (``count`` of them) dealt to the trial ``seeds`` in turn, so that
    each seed gets extremes and random ones. Returns [(seed, (rotation°, (dx, dy) m,
    spacing), (grid, corners))]."""
    return [(seeds[k % len(seeds)],) + start for k, start in enumerate(start_grids(count))]

