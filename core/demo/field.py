"""A small synthetic field, written from a seed: orthomosaic, DSM and plot polygons.

The default field (:data:`DEMO_FIELD`) is 40 m × 30 m in WGS 84 / UTM 54N (EPSG:32654): gently
sloped bare soil with 24 slightly rotated plots (4 rows × 6 columns, 4 m × 2.5 m) of crop rows
some decimetres tall. The orthomosaic is RGB at 1 cm, tiled 256, deflate; the DSM is float32 at
2 cm with nodata -9999 (heights in metres above the ellipsoid, the truth being
``ground + canopy``). :class:`FieldLayout` describes other fields (the demo survey uses one).
:class:`FieldMess` and :func:`add_field_mess`, :func:`make_weeds` give a field what real ones have
(the demo survey's default; plots without those keys keep the tidy rows).
"""
from dataclasses import dataclass
from typing import List, Tuple

import numpy as np

from ..files import write_json


DOM_PIXEL, DSM_PIXEL = 0.01, 0.02
NODATA = -9999.0
ROW_SPACING = 0.5     # m between crop rows inside a plot (rows run along the plot's long axis)
PLANT_SPACING = 0.15  # m between plants along a row
EDGE = 0.1            # m of bare soil inside each plot edge


@dataclass(frozen=True)
class FieldLayout:
    """Where and how a field is laid out. Lengths in metres, map CRS ``epsg``.

    ``origin``: top-left corner (x, y); ``first_plot``: centre of plot A1 measured right and
    down from the origin; ``pitch``: distance between plot centres (columns along x, rows down);
    ``ground``: (height at the bottom-left corner, slope along x, slope along y), ellipsoidal;
    ``nodata_cols``: DSM columns without data along the western edge.
    """
    origin: Tuple[float, float] = (368000.0, 3956030.0)
    size: Tuple[float, float] = (40.0, 30.0)
    rows: int = 4
    cols: int = 6
    plot_size: Tuple[float, float] = (4.0, 2.5)
    first_plot: Tuple[float, float] = (4.0, 4.5)
    pitch: Tuple[float, float] = (6.4, 7.0)
    ground: Tuple[float, float, float] = (95.0, 0.02, 0.01)
    nodata_cols: int = 40
    epsg: int = 32654

    def ground_height(self, x, y):
        """Bare-soil height (m) at map points."""
        h0, sx, sy = self.ground
        return h0 + sx * (x - self.origin[0]) + sy * (y - self.origin[1] + self.size[1])

    def grid_shape(self, pixel: float) -> Tuple[int, int]:
        return round(self.size[1] / pixel), round(self.size[0] / pixel)

    def geotransform(self, pixel: float):
        return (self.origin[0], pixel, 0.0, self.origin[1], 0.0, -pixel)



def make_plots(layout: FieldLayout, rng) -> List[dict]:
    """Plot descriptions: id (row letter + column number), row, col, centre, angle (rad), crop
    height (m). Draws two uniforms per plot from ``rng``."""
    plots = []
    for r in range(layout.rows):
        for c in range(layout.cols):
            cx = layout.origin[0] + layout.first_plot[0] + c * layout.pitch[0]
            cy = layout.origin[1] - layout.first_plot[1] - r * layout.pitch[1]
            angle = np.deg2rad(rng.uniform(-4, 4))
            plots.append({"plot_id": f"{chr(ord('A') + r)}{c + 1}", "row": r + 1, "col": c + 1,
                          "centre": (cx, cy), "angle": angle, "height": rng.uniform(0.25, 0.7),
                          "size": layout.plot_size})
    return plots


def plot_corners(p: dict) -> np.ndarray:
    """(4, 2) corners of a plot, counter-clockwise from its lower-left corner."""
    w, h = p["size"]
    local = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    return local @ np.array([[ca, -sa], [sa, ca]]).T + p["centre"]


def _plot_canopy(p: dict, x, y):
    """(inside, height) of one plot's crop at map points (rows along the plot's long axis).

    A plot from :func:`add_field_mess` also has: ``row_fill`` (share of the row spacing under a
    round-topped canopy, instead of the narrow default rows), ``vigour`` (within-plot height
    factors: amplitude, wavelength and phase along the rows, one factor per row), ``gaps``
    (missing row segments: row offset v, u from, u to) and ``lodged`` (a patch, u0, u1, v0, v1,
    where the crop lies flat at ``LODGED_HEIGHT`` × its height, over rows and furrows alike)."""
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    u = (x - p["centre"][0]) * ca + (y - p["centre"][1]) * sa
    v = -(x - p["centre"][0]) * sa + (y - p["centre"][1]) * ca
    inside = (np.abs(u) < p["size"][0] / 2 - EDGE) & (np.abs(v) < p["size"][1] / 2 - EDGE)
    phase = np.cos(2 * np.pi * v / ROW_SPACING)
    if "row_fill" in p:
        c0 = np.cos(np.pi * p["row_fill"])
        rows = np.sqrt(np.clip(ROW_WALL * (phase - c0) / (1 - c0), 0, 1))
    else:
        rows = np.clip(phase, 0, None) ** 2
    plants = 0.75 + 0.25 * np.cos(2 * np.pi * u / PLANT_SPACING)
    h = p["height"] * rows * plants
    if "vigour" in p:
        a, wave, ph, row_factor = p["vigour"]
        k = np.clip(np.round(v / ROW_SPACING).astype(int) + len(row_factor) // 2, 0,
                    len(row_factor) - 1)
        h = h * (1 - a * (0.5 + 0.5 * np.sin(2 * np.pi * u / wave + ph))) * np.asarray(row_factor)[k]
    for rv, u0, u1 in p.get("gaps", ()):
        h = np.where((np.abs(v - rv) < ROW_SPACING / 2) & (u >= u0) & (u <= u1), 0.0, h)
    if "lodged" in p:
        u0, u1, v0, v1 = p["lodged"]
        flat = (u >= u0) & (u <= u1) & (v >= v0) & (v <= v1)
        h = np.where(flat, LODGED_HEIGHT * p["height"] * (0.9 + 0.1 * plants), h)
    return inside, h


# --- what real fields have (the demo survey) ---------------------------------------------------
LODGED_HEIGHT = 0.3    # lodged crop: this share of the plot's crop height, flat over the patch
ROW_WALL = 6.0        # how steeply a filled row rises at its edge (a canopy wall, full height within ~5 cm)


@dataclass(frozen=True)
class FieldMess:
    """What real fields have, each with its parameter (0 or False turns it off); everything is
    drawn from the scene's seed, in random streams of its own. Lengths in metres.

    ``margin_grass``: greenness (ExG) of the grass in the field margins as a share of the crop
    leaf's (``grass_cover`` of the margin is grass, from ``margin`` m outside the plot block);
    ``weedy_plots``: share of the plots with ``weeds_per_plot`` weeds, and ``alley_weeds`` weeds
    between the plots; ``vigour``: the largest height loss within a plot (along and across its
    rows; between plots the heights differ anyway); ``gaps_per_row``: missing row segments per
    row, on average, a third of them at a row end; ``empty_plots``: plots without crop;
    ``lodged_plots``: plots with a lodged patch; ``shadow``: darkening of what lies in the crop's
    shadow (sun from the south-east, 45° high); ``soil_gradient``: relative change of the soil
    colour from the west edge to the east edge (redder and darker eastwards); ``row_fill``: share
    of the row spacing under canopy (with the crop heights, the rows hide the soil between them
    from oblique views); ``touching``: plots D5–D8 and E5–E8 form one block without alleys.
    """
    margin_grass: float = 0.6
    grass_cover: float = 0.85
    margin: float = 1.5
    weedy_plots: float = 0.4
    weeds_per_plot: int = 6
    alley_weeds: int = 80
    vigour: float = 0.3
    gaps_per_row: float = 0.5
    empty_plots: int = 3
    lodged_plots: int = 4
    shadow: float = 0.3
    soil_gradient: float = 0.15
    row_fill: float = 0.8
    touching: bool = True


NO_MESS = FieldMess(margin_grass=0.0, weedy_plots=0.0, alley_weeds=0, vigour=0.0, gaps_per_row=0.0,
                    empty_plots=0, lodged_plots=0, shadow=0.0, soil_gradient=0.0, row_fill=0.0,
                    touching=False)
"""The tidy field of earlier versions (narrow rows, no weeds, no grass)."""

TOUCHING_BLOCK = ((4, 5), (5, 6, 7, 8))     # field rows and columns of the block without alleys


def add_field_mess(plots: List[dict], mess: FieldMess, rng) -> List[dict]:
    """Copies of ``plots`` with the per-plot features of ``mess`` (see :func:`_plot_canopy`)."""
    plots = [dict(p) for p in plots]
    rows, cols = TOUCHING_BLOCK
    block = [p for p in plots if p["row"] in rows and p["col"] in cols]
    if mess.touching and block:
        first = block[0]
        ca, sa = np.cos(first["angle"]), np.sin(first["angle"])
        w, h = first["size"]
        for p in block:
            i, j = p["col"] - cols[0], p["row"] - rows[0]
            du, dv = i * w, -j * h
            p["centre"] = (first["centre"][0] + du * ca - dv * sa, first["centre"][1] + du * sa + dv * ca)
            p["angle"] = first["angle"]
    free = [k for k, p in enumerate(plots) if not (mess.touching and p in block)]
    empty = set(rng.choice(free, mess.empty_plots, replace=False).tolist()) if mess.empty_plots else set()
    lodged = set(rng.choice([k for k in range(len(plots)) if k not in empty], mess.lodged_plots,
                            replace=False).tolist()) if mess.lodged_plots else set()
    for k, p in enumerate(plots):
        w, h = p["size"]
        n_rows = int(np.floor((h / 2 - EDGE) / ROW_SPACING)) * 2 + 1
        if mess.row_fill:
            p["row_fill"] = mess.row_fill
        if mess.vigour:
            factor = 1 - mess.vigour / 2 * rng.uniform(0, 1, n_rows)
            factor[rng.integers(n_rows)] = 1.0
            p["vigour"] = (mess.vigour / 2, rng.uniform(1.5, 3.5), rng.uniform(0, 2 * np.pi),
                           factor.tolist())
        gaps = []
        for r in range(n_rows) if mess.gaps_per_row else ():
            for _ in range(rng.poisson(mess.gaps_per_row)):
                length = rng.uniform(0.2, 0.8)
                end = w / 2 - EDGE
                where = rng.uniform()
                u0 = -end if where < 1 / 6 else end - length if where < 1 / 3 else \
                    rng.uniform(-end, end - length)
                gaps.append(((r - n_rows // 2) * ROW_SPACING, u0, u0 + length))
        if gaps:
            p["gaps"] = gaps
        if k in lodged:
            lu, lv = rng.uniform(0.6, 1.4), rng.uniform(0.6, 1.2)
            u0, v0 = rng.uniform(-w / 2, w / 2 - lu), rng.uniform(-h / 2, h / 2 - lv)
            p["lodged"] = (u0, u0 + lu, v0, v0 + lv)
        if k in empty:
            p["height"] = 0.0
            p["empty"] = True
    return plots


def make_weeds(layout: FieldLayout, plots: List[dict], mess: FieldMess, rng) -> np.ndarray:
    """Weeds (n, 4): map x, y, radius, height (m), dome-shaped: in ``weedy_plots`` of the plots
    (anywhere inside them) and in the alleys of the plot block (outside every plot)."""
    out = []
    n_weedy = int(round(mess.weedy_plots * len(plots)))
    for k in (sorted(rng.choice(len(plots), n_weedy, replace=False).tolist()) if n_weedy else ()):
        p = plots[k]
        w, h = p["size"]
        ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
        for _ in range(mess.weeds_per_plot):
            u, v = rng.uniform(-w / 2 + 0.15, w / 2 - 0.15), rng.uniform(-h / 2 + 0.15, h / 2 - 0.15)
            out.append((p["centre"][0] + u * ca - v * sa, p["centre"][1] + u * sa + v * ca,
                        rng.uniform(0.04, 0.12), rng.uniform(0.05, 0.2)))
    if mess.alley_weeds and plots:
        c = np.vstack([plot_corners(p) for p in plots])
        (x0, y0), (x1, y1) = c.min(axis=0), c.max(axis=0)
        n = 0
        while n < mess.alley_weeds:
            x, y = rng.uniform(x0, x1), rng.uniform(y0, y1)
            if any(_inside_plot(p, x, y, 0.15) for p in plots):
                continue
            out.append((x, y, rng.uniform(0.04, 0.12), rng.uniform(0.05, 0.2)))
            n += 1
    return np.array(out, np.float64).reshape(-1, 4)


def _inside_plot(p: dict, x, y, grow: float = 0.0):
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    u = (x - p["centre"][0]) * ca + (y - p["centre"][1]) * sa
    v = -(x - p["centre"][0]) * sa + (y - p["centre"][1]) * ca
    return (np.abs(u) < p["size"][0] / 2 + grow) & (np.abs(v) < p["size"][1] / 2 + grow)


def weed_height(weeds: np.ndarray, x, y) -> np.ndarray:
    """Height (m) of the weeds at map points (0 where there is none): domes h·√(1 − (d/r)²)."""
    x, y = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
    out = np.zeros(x.shape)
    for wx, wy, r, h in weeds:
        near = (np.abs(x - wx) < r) & (np.abs(y - wy) < r)
        if near.any():
            d2 = ((x[near] - wx) ** 2 + (y[near] - wy) ** 2) / (r * r)
            out[near] = np.maximum(out[near], h * np.sqrt(np.clip(1 - d2, 0, None)))
    return out


def weed_grid(layout: FieldLayout, weeds: np.ndarray, pixel: float) -> np.ndarray:
    """Weed height (m) at the pixel centres of the ``pixel`` grid of ``layout``."""
    out = np.zeros(layout.grid_shape(pixel))
    x0, y0 = layout.origin
    for wx, wy, r, h in weeds:
        j0, j1 = max(int((wx - r - x0) / pixel), 0), min(int((wx + r - x0) / pixel) + 2, out.shape[1])
        i0, i1 = max(int((y0 - wy - r) / pixel), 0), min(int((y0 - wy + r) / pixel) + 2, out.shape[0])
        if j1 <= j0 or i1 <= i0:
            continue
        x = x0 + (np.arange(j0, j1) + 0.5)[None, :] * pixel
        y = y0 - (np.arange(i0, i1) + 0.5)[:, None] * pixel
        d2 = ((x - wx) ** 2 + (y - wy) ** 2) / (r * r)
        out[i0:i1, j0:j1] = np.maximum(out[i0:i1, j0:j1], h * np.sqrt(np.clip(1 - d2, 0, None)))
    return out


def plot_window(layout: FieldLayout, p: dict, pixel: float):
    """((i0, i1, j0, j1), x, y): the rows and columns of the ``pixel`` grid of ``layout`` around
    plot ``p`` (one pixel of margin) and the map coordinates of their centres, broadcast to the
    window's shape; None when the plot lies outside the grid."""
    ny, nx = layout.grid_shape(pixel)
    x0, y0 = layout.origin
    c = plot_corners(p)
    j0 = max(int(np.floor((c[:, 0].min() - x0) / pixel)) - 1, 0)
    j1 = min(int(np.ceil((c[:, 0].max() - x0) / pixel)) + 1, nx)
    i0 = max(int(np.floor((y0 - c[:, 1].max()) / pixel)) - 1, 0)
    i1 = min(int(np.ceil((y0 - c[:, 1].min()) / pixel)) + 1, ny)
    if j1 <= j0 or i1 <= i0:
        return None
    x = x0 + (np.arange(j0, j1) + 0.5)[None, :] * pixel
    y = y0 - (np.arange(i0, i1) + 0.5)[:, None] * pixel
    return (i0, i1, j0, j1), *np.broadcast_arrays(x, y)


def canopy_grid(layout: FieldLayout, plots: List[dict], pixel: float) -> np.ndarray:
    """Crop height (m, float64) at the pixel centres of the ``pixel`` grid of ``layout``;
    each plot is evaluated only in its bounding window."""
    h = np.zeros(layout.grid_shape(pixel))
    for p in plots:
        win = plot_window(layout, p, pixel)
        if win is None:
            continue
        (i0, i1, j0, j1), x, y = win
        inside, val = _plot_canopy(p, x, y)
        h[i0:i1, j0:j1] = np.where(inside, np.maximum(h[i0:i1, j0:j1], val), h[i0:i1, j0:j1])
    return h


def write_plots_geojson(path: str, plots: List[dict], epsg: int) -> str:
    """Plot rectangles as a GeoJSON FeatureCollection (fields plot_id, row, col; legacy crs)."""
    features = [{"type": "Feature",
                 "properties": {k: p[k] for k in ("plot_id", "row", "col")},
                 "geometry": {"type": "Polygon",
                              "coordinates": [np.vstack([plot_corners(p), plot_corners(p)[:1]]).tolist()]}}
                for p in plots]
    write_json(path, {"type": "FeatureCollection", "name": "plots",
                      "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{epsg}"}},
                      "features": features})
    return path

