"""The colour truth of the demo survey's plots, and the orthomosaic defects a survey can opt into.

**Truth** (:func:`plot_colour_truth`), derived from the scene generator's closed-form model, not
from any raster: over each plot rectangle, on a 5 mm grid in the plot's own axes, the crop height
``h`` (``field._plot_canopy``: rows along the long axis, plants along the rows, a bare edge, the
plot's vigour, gaps and lodging; the weeds of ``field.weed_height`` where they are taller, in
their own leaf colour), the noise-free texel colour ``soil·s·(1 − w) + leaf·k·w`` with the soil
colour of ``scene.soil_colour`` (its west–east gradient), the leaf weight ``w = min(h / 5 cm, 1)``,
the leaf shade ``k = 0.75 + 0.45·min(h / 0.7 m, 1)`` and the soil's moisture shade
``s = 1 + 0.07·moisture(x, y)`` (the generator's smooth field; its zero-mean grain and clods are
left out: they cancel in ExG's numerator and average out over a plot; the cast shadows scale a
texel's three bands alike, which changes neither ExG nor cover). Per plot:

* ``exg``: the mean over the rectangle of the texels' ExG (2G − R − B)/(R + G + B);
* ``cover``: the share of the rectangle whose texels are mostly leaf (w ≥ ½, i.e. h ≥ 2.5 cm).

**Defects** (:func:`add_ortho_defects`, ``make_demo_survey(..., ortho_defects=True)``): the
written orthomosaic, not the texture the photos are rendered from, gets the faults real
orthomosaics show, each over a rectangle around the plots of one field column:

* *ghosting* (column 3): a 50/50 blend with a copy of the texture offset by
  :data:`GHOST_OFFSET` (two misregistered photos blended at a seam over a wrong canopy DSM); the
  crop rows appear twice, half-transparent, and soil from beyond the plot is blended into it;
* *blur* (column 6): a Gaussian blur of σ = :data:`BLUR_SIGMA` (resampling smear).
"""
from typing import Dict, List, Tuple

import numpy as np

from .field import DOM_PIXEL, _plot_canopy, plot_corners, weed_height
from .scene import LEAF_FULL, LEAF_RGB, MOISTURE, WEED_RGB, Scene, _moisture_grid, soil_colour

TRUTH_STEP = 0.005          # m, grid of the truth integration
GHOST_COLUMN, BLUR_COLUMN = 3, 6
GHOST_OFFSET = (0.45, -0.25)  # m (east, north): where the ghost copy comes from, relative
BLUR_SIGMA = 0.08           # m
DEFECT_MARGIN = 0.8         # m around a plot's bounding box


def moisture(scene: Scene, seed: int, x, y) -> np.ndarray:
    """The generator's smooth soil moisture field (bilinear between 1 m nodes) at map points."""
    g = _moisture_grid(scene.layout, seed)
    r = (scene.layout.origin[1] - np.asarray(y, np.float64)) / 1.0
    c = (np.asarray(x, np.float64) - scene.layout.origin[0]) / 1.0
    ri = np.clip(r.astype(np.intp), 0, g.shape[0] - 2)
    ci = np.clip(c.astype(np.intp), 0, g.shape[1] - 2)
    wr, wc = r - ri, c - ci
    return (g[ri, ci] * (1 - wc) + g[ri, ci + 1] * wc) * (1 - wr) \
        + (g[ri + 1, ci] * (1 - wc) + g[ri + 1, ci + 1] * wc) * wr


def plot_colour_truth(scene: Scene, seed: int, step: float = TRUTH_STEP) -> Dict[str, dict]:
    """{plot id: {"exg": mean ExG, "cover": share with w ≥ ½}} (see the module docstring)."""
    leaf = np.array(LEAF_RGB, np.float64)
    weed_leaf = np.array(WEED_RGB, np.float64)
    weeds = scene.weeds if scene.weeds is not None else np.zeros((0, 4))
    out = {}
    for p in scene.plots:
        w, h = p["size"]
        u = (np.arange(int(round(w / step))) + 0.5) * step - w / 2
        v = (np.arange(int(round(h / step))) + 0.5) * step - h / 2
        uu, vv = [a.ravel() for a in np.meshgrid(u, v)]
        ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
        x = p["centre"][0] + uu * ca - vv * sa
        y = p["centre"][1] + uu * sa + vv * ca
        inside, height = _plot_canopy(p, x, y)
        height = np.where(inside, height, 0.0)
        near = np.hypot(weeds[:, 0] - p["centre"][0], weeds[:, 1] - p["centre"][1]) < np.hypot(w, h)
        weed = weed_height(weeds[near], x, y)
        is_weed = (weed > 0) & (weed >= height)
        height = np.maximum(height, weed)
        wgt = np.clip(height / LEAF_FULL, 0, 1)[:, None]
        k = (0.75 + 0.45 * np.clip(height / 0.7, 0, 1))[:, None]
        s = (1 + MOISTURE * moisture(scene, seed, x, y))[:, None]
        rgb = soil_colour(scene.layout, scene.mess, x) * s * (1 - wgt) \
            + np.where(is_weed[:, None], weed_leaf, leaf) * k * wgt
        exg = (2 * rgb[:, 1] - rgb[:, 0] - rgb[:, 2]) / rgb.sum(axis=1)
        out[p["plot_id"]] = {"exg": float(exg.mean()), "cover": float(np.mean(wgt[:, 0] >= 0.5))}
    return out


def _window(scene: Scene, p: dict) -> Tuple[int, int, int, int]:
    """Orthomosaic (row0, row1, col0, col1) of a plot's bounding box grown by the margin."""
    c = plot_corners(p)
    x0, y0 = scene.layout.origin
    col0 = int(np.floor((c[:, 0].min() - DEFECT_MARGIN - x0) / DOM_PIXEL))
    col1 = int(np.ceil((c[:, 0].max() + DEFECT_MARGIN - x0) / DOM_PIXEL))
    row0 = int(np.floor((y0 - c[:, 1].max() - DEFECT_MARGIN) / DOM_PIXEL))
    row1 = int(np.ceil((y0 - c[:, 1].min() + DEFECT_MARGIN) / DOM_PIXEL))
    return row0, row1, col0, col1


def _gaussian(a: np.ndarray, sigma_px: float) -> np.ndarray:
    """Separable Gaussian blur of (rows, cols, bands) float32 (edges repeated)."""
    r = int(np.ceil(3 * sigma_px))
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma_px) ** 2)
    k /= k.sum()
    for axis in (0, 1):
        pad = [(0, 0)] * a.ndim
        pad[axis] = (r, r)
        p = np.pad(a, pad, mode="edge")
        out = np.zeros_like(a)
        n = a.shape[axis]
        for i, kw in enumerate(k):
            out += kw * np.take(p, np.arange(i, i + n), axis=axis)
        a = out
    return a


def add_ortho_defects(ortho: np.ndarray, scene: Scene) -> Tuple[np.ndarray, Dict[str, List[str]]]:
    """(a copy of the orthomosaic with ghosting and blur, {"ghosting": plot ids, "blur": …})."""
    out = ortho.copy()
    defects: Dict[str, List[str]] = {"ghosting": [], "blur": []}
    dr = int(round(-GHOST_OFFSET[1] / DOM_PIXEL))     # rows grow southwards
    dc = int(round(GHOST_OFFSET[0] / DOM_PIXEL))
    for p in scene.plots:
        r0, r1, c0, c1 = _window(scene, p)
        if p["col"] == GHOST_COLUMN:
            a = ortho[r0:r1, c0:c1].astype(np.float32)
            b = ortho[r0 + dr:r1 + dr, c0 + dc:c1 + dc].astype(np.float32)
            out[r0:r1, c0:c1] = np.clip(0.5 * (a + b) + 0.5, 0, 255).astype(np.uint8)
            defects["ghosting"].append(p["plot_id"])
        elif p["col"] == BLUR_COLUMN:
            a = _gaussian(ortho[r0:r1, c0:c1].astype(np.float32), BLUR_SIGMA / DOM_PIXEL)
            out[r0:r1, c0:c1] = np.clip(a + 0.5, 0, 255).astype(np.uint8)
            defects["blur"].append(p["plot_id"])
    return out, defects
