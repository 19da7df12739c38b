"""What makes the demo trial look like a real field: margin grass, weeds, uneven vigour, missing
row segments, lodging, shadows and a soil-colour gradient (:class:`Hardness`), drawn into an RGB
orthomosaic by :func:`render_field`.

Everything is drawn from the planted plots and the parameters here with its own random stream,
so the truth written by :mod:`.trial` (layout, planted offsets, empty plots) does not depend on
any of it. Units: metres on the map; colours 0–255 RGB.

Crop rows run along each plot's x axis, ``ROW_SPACING`` apart, centred on the planted plot's
centre (a row through the centre), plants every ``PLANT_SPACING`` m, a bare ``EDGE`` m inside
every plot edge (:mod:`.field`'s conventions, written out here for the trial's own canopy).
"""
import math
from dataclasses import asdict, dataclass
from typing import List, Tuple

import numpy as np

from .field import EDGE, PLANT_SPACING, ROW_SPACING

SOIL_RGB = (122.0, 96.0, 72.0)
SOIL_RGB_FAR = (150.0, 122.0, 92.0)       # the soil colour at the far side of the gradient
LEAF_RGB = (58.0, 132.0, 46.0)
WEED_RGB = (70.0, 140.0, 52.0)
LODGED_RGB = (96.0, 130.0, 52.0)


@dataclass
class Hardness:
    """How field-like the trial is; the defaults are issue 32's hard levels.

    ``grass_greenness``: ExG of the margin grass's colour over the crop's (the grass band is
    ``grass_width`` m wide, ``grass_cover`` of it covered); ``weedy_plots``: share of the plots
    with weeds (``weeds_per_plot`` blobs each, 3–9 cm across) and ``alley_weeds`` blobs per m² of
    the whole field (alleys included); ``vigour_between``: the plots' vigour is uniform in
    [1 − this, 1]; ``vigour_within``: amplitude of a smooth vigour wave inside each plot;
    ``missing_segments``: mean number of missing row segments per plot (0.2–0.7 m long),
    ``missing_at_ends`` of them at a row end; ``lodged_plots``: share of plots with a lodged
    patch (rows flattened into an even cover, 0.3–0.6 m radius); ``shadows``: number of shadows
    (1–3 m radius, brightness × ``shadow_depth``); ``soil_gradient``: the soil goes from
    SOIL_RGB to SOIL_RGB_FAR across the field (0: none, 1: all the way); ``touching``: plots
    touch their neighbours across the rows (no alley between ranges)."""
    grass_greenness: float = 0.75
    grass_width: float = 2.5
    grass_cover: float = 0.85
    weedy_plots: float = 0.4
    weeds_per_plot: int = 12
    alley_weeds: float = 0.8
    vigour_between: float = 0.6
    vigour_within: float = 0.35
    missing_segments: float = 1.2
    missing_at_ends: float = 0.5
    lodged_plots: float = 0.15
    shadows: int = 6
    shadow_depth: float = 0.55
    soil_gradient: float = 1.0
    touching: bool = True

    def as_dict(self) -> dict:
        return asdict(self)


def _disks(img_shape, gt, centres, radii):
    """Yield ((i0, i1, j0, j1), inside mask) for each disk (map centre, radius m)."""
    x0, px, y0 = gt[0], gt[1], gt[3]
    ny, nx = img_shape
    for (cx, cy), r in zip(centres, radii):
        j0, j1 = max(int((cx - r - x0) / px), 0), min(int((cx + r - x0) / px) + 2, nx)
        i0, i1 = max(int((y0 - cy - r) / px), 0), min(int((y0 - cy + r) / px) + 2, ny)
        if j1 <= j0 or i1 <= i0:
            continue
        x = x0 + (np.arange(j0, j1) + 0.5) * px
        y = y0 - (np.arange(i0, i1) + 0.5) * px
        yield (i0, i1, j0, j1), (x[None, :] - cx) ** 2 + (y[:, None] - cy) ** 2 <= r * r


def plot_features(plot_ids: List[str], empty, hard: Hardness, seed: int) -> dict:
    """Per plot: vigour, vigour wave, missing segments (row, u from, u to; u along the plot's x
    from its centre), lodged patch (u, v, radius) and weed blobs ((u, v, radius) in the plot
    frame) — drawn from ``seed`` alone (the truth's generator does not read them)."""
    rng = np.random.default_rng([seed, 40])
    out = {}
    for pid in plot_ids:
        f = {"vigour": float(1 - hard.vigour_between * rng.random()),
             "wave": (float(rng.uniform(0.4, 1.2)), float(rng.uniform(0, 2 * math.pi)),
                      float(rng.uniform(0, math.pi))),
             "missing": [], "lodged": None, "weeds": []}
        for _ in range(rng.poisson(hard.missing_segments)):
            row = int(rng.integers(-1, 2))
            length = float(rng.uniform(0.2, 0.7))
            if rng.random() < hard.missing_at_ends:
                end = 1.5 - EDGE
                a = end - length if rng.random() < 0.5 else -end
                f["missing"].append((row, a, a + length))
            else:
                a = float(rng.uniform(-1.2, 1.2 - length))
                f["missing"].append((row, a, a + length))
        if rng.random() < hard.lodged_plots:
            f["lodged"] = (float(rng.uniform(-1.0, 1.0)), float(rng.uniform(-0.4, 0.4)),
                           float(rng.uniform(0.3, 0.6)))
        if rng.random() < hard.weedy_plots:
            f["weeds"] = [(float(rng.uniform(-1.5, 1.5)), float(rng.uniform(-0.8, 0.8)),
                           float(rng.uniform(0.03, 0.09))) for _ in range(hard.weeds_per_plot)]
        out[pid] = f
    return out


def _crop_cover(f: dict, u, v, size) -> np.ndarray:
    """Leaf cover (0–1) of one plot's crop at plot-frame points (u along the rows)."""
    inside = (np.abs(u) < size[0] / 2 - EDGE) & (np.abs(v) < size[1] / 2 - EDGE)
    k, ph, th = f["wave"]
    vig = f["vigour"] * (1 + f["_within"] * np.sin(k * (u * math.cos(th) + v * math.sin(th)) + ph))
    rows = np.clip(np.cos(2 * np.pi * v / ROW_SPACING), 0, None) ** 2
    plants = 0.75 + 0.25 * np.cos(2 * np.pi * u / PLANT_SPACING)
    cover = np.clip(2.2 * vig * rows * plants, 0, 1)
    row_no = np.round(v / ROW_SPACING)
    for row, a, b in f["missing"]:
        cover[(row_no == row) & (u >= a) & (u <= b)] = 0
    if f["lodged"] is not None:
        lu, lv, r = f["lodged"]
        flat = (u - lu) ** 2 + (v - lv) ** 2 <= r * r
        cover = np.where(flat, -0.7 * np.clip(vig, 0.3, 1), cover)   # < 0: lodged (even cover)
    return np.where(inside, cover, 0.0)


def render_field(shape: Tuple[int, int], gt, planted: np.ndarray, angle: float, size,
                 plot_ids: List[str], empty, field_corners: np.ndarray, hard: Hardness,
                 seed: int) -> Tuple[np.ndarray, dict]:
    """(RGB uint8 image, per-plot features) of the trial: ``planted`` (n, 4, 2) planted plot
    corners, ``angle`` the plots' x axis (radians from east, counter-clockwise), ``size`` the plot
    size (m), ``field_corners`` (4, 2) the layout's corners (the grass band lies outside them)."""
    ny, nx = shape
    x0, px, y0 = gt[0], gt[1], gt[3]
    rng = np.random.default_rng([seed, 41])
    feats = plot_features(plot_ids, empty, hard, seed)
    ca, sa = math.cos(angle), math.sin(angle)
    xs = x0 + (np.arange(nx) + 0.5) * px
    ys = y0 - (np.arange(ny) + 0.5) * px
    # soil: a gradient across the field, grain and clods
    t = np.clip((xs - xs[0]) / max(xs[-1] - xs[0], 1e-9), 0, 1)[None, :] * hard.soil_gradient
    t = t + 0.15 * hard.soil_gradient * ((ys - ys[-1]) / max(ys[0] - ys[-1], 1e-9))[:, None]
    soil_a, soil_b = np.array(SOIL_RGB), np.array(SOIL_RGB_FAR)
    grain = 1 + 0.05 * rng.standard_normal((ny, nx))
    img = np.empty((ny, nx, 3), np.float32)
    for c in range(3):
        img[..., c] = (soil_a[c] + (soil_b[c] - soil_a[c]) * t) * grain
    # margin grass: a band outside the field's corners, patchy
    fc = field_corners.mean(axis=0)
    gu = (xs[None, :] - fc[0]) * ca + (ys[:, None] - fc[1]) * sa
    gv = -(xs[None, :] - fc[0]) * sa + (ys[:, None] - fc[1]) * ca
    cu = (field_corners - fc) @ np.array([ca, sa])
    cv = (field_corners - fc) @ np.array([-sa, ca])
    out_u = np.abs(gu) - np.abs(cu).max()
    out_v = np.abs(gv) - np.abs(cv).max()
    beyond = np.maximum(out_u, out_v)
    band = (beyond > 0.25) & (beyond < 0.25 + hard.grass_width)
    del gu, gv, out_u, out_v, beyond
    patch = rng.random((ny // 4 + 1, nx // 4 + 1))
    patch = np.repeat(np.repeat(patch, 4, 0), 4, 1)[:ny, :nx]
    grass = band & (patch < hard.grass_cover)
    grass_rgb = grass_colour(hard.grass_greenness)
    shade = (0.85 + 0.3 * rng.random((ny, nx))).astype(np.float32)
    for c in range(3):
        img[..., c] = np.where(grass, grass_rgb[c] * shade, img[..., c])
    del grass, band, patch
    # the crop, plot by plot
    for i, pid in enumerate(plot_ids):
        f = feats[pid]
        f["_within"] = hard.vigour_within
        if empty[i]:
            continue
        cen = planted[i].mean(axis=0)
        q = planted[i]
        j0, j1 = max(int((q[:, 0].min() - x0) / px) - 1, 0), min(int((q[:, 0].max() - x0) / px) + 2, nx)
        i0, i1 = max(int((y0 - q[:, 1].max()) / px) - 1, 0), min(int((y0 - q[:, 1].min()) / px) + 2, ny)
        X, Y = xs[None, j0:j1], ys[i0:i1, None]
        u = (X - cen[0]) * ca + (Y - cen[1]) * sa
        v = -(X - cen[0]) * sa + (Y - cen[1]) * ca
        cov = _crop_cover(f, u, v, size)
        lodged = cov < 0
        cov = np.abs(cov)
        bright = 0.8 + 0.3 * np.clip(f["vigour"], 0, 1)
        win = img[i0:i1, j0:j1]
        for c in range(3):
            col = np.where(lodged, LODGED_RGB[c], LEAF_RGB[c] * bright)
            win[..., c] = win[..., c] * (1 - cov) + col * cov
    # weeds: blobs in the weedy plots and over the whole field (alleys included)
    centres, radii = [], []
    for i, pid in enumerate(plot_ids):
        cen = planted[i].mean(axis=0)
        for wu, wv, r in feats[pid]["weeds"]:
            centres.append((cen[0] + wu * ca - wv * sa, cen[1] + wu * sa + wv * ca))
            radii.append(r)
    lo, hi = field_corners.min(axis=0) - 0.2, field_corners.max(axis=0) + 0.2
    n_alley = rng.poisson(hard.alley_weeds * float(np.prod(hi - lo)))
    for _ in range(n_alley):
        centres.append(tuple(rng.uniform(lo, hi)))
        radii.append(float(rng.uniform(0.03, 0.1)))
    for (a, b, c0, c1), m in _disks((ny, nx), gt, centres, radii):
        img[a:b, c0:c1][m] = np.array(WEED_RGB) * rng.uniform(0.85, 1.15)
    # shadows
    span = field_corners.max(axis=0) - field_corners.min(axis=0)
    sc = field_corners.min(axis=0) + rng.random((hard.shadows, 2)) * span
    for (a, b, c0, c1), m in _disks((ny, nx), gt, sc, rng.uniform(1.0, 3.0, hard.shadows)):
        img[a:b, c0:c1][m] *= hard.shadow_depth
    for f in feats.values():
        f.pop("_within", None)
    return np.clip(img, 0, 255).astype(np.uint8), feats


def grass_colour(ratio: float) -> np.ndarray:
    """The grass colour: soil and leaf mixed so that its ExG is ``ratio`` × the crop colour's."""
    def exg(c):
        return (2 * c[1] - c[0] - c[2]) / sum(c)
    target = ratio * exg(LEAF_RGB)
    soil = np.array(SOIL_RGB)
    lo, hi = 0.0, 1.0                     # mix of soil and a leaf green giving the target ExG
    leaf = np.array(LEAF_RGB) * 1.05
    for _ in range(40):
        mid = (lo + hi) / 2
        if exg(soil * (1 - mid) + leaf * mid) < target:
            lo = mid
        else:
            hi = mid
    return soil * (1 - hi) + leaf * hi
