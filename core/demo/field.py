"""A small synthetic field, written from a seed: orthomosaic, DSM and plot polygons.

The default field (:data:`DEMO_FIELD`) is 40 m × 30 m in WGS 84 / UTM 54N (EPSG:32654): gently
sloped bare soil with 24 slightly rotated plots (4 rows × 6 columns, 4 m × 2.5 m) of crop rows
some decimetres tall. The orthomosaic is RGB at 1 cm, tiled 256, deflate; the DSM is float32 at
2 cm with nodata -9999 (heights in metres above the ellipsoid, the truth being
``ground + canopy``). :class:`FieldLayout` describes other fields (the demo survey uses one).
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
    """(inside, height) of one plot's crop at map points (rows along the plot's long axis)."""
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    u = (x - p["centre"][0]) * ca + (y - p["centre"][1]) * sa
    v = -(x - p["centre"][0]) * sa + (y - p["centre"][1]) * ca
    inside = (np.abs(u) < p["size"][0] / 2 - EDGE) & (np.abs(v) < p["size"][1] / 2 - EDGE)
    rows = np.clip(np.cos(2 * np.pi * v / ROW_SPACING), 0, None) ** 2
    plants = 0.75 + 0.25 * np.cos(2 * np.pi * u / PLANT_SPACING)
    return inside, p["height"] * rows * plants


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

