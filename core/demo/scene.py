"""The demo survey's field: plots, DSM, orthomosaic, ground control targets, surface sampling.

The field (:data:`SURVEY_FIELD`) is 60 m × 40 m in WGS 84 / UTM 54N (EPSG:32654), placed where
the UTM point scale factor is about 1 (so the projected CRS is as Cartesian as the photos need).
Heights are ellipsoidal (WGS 84), in metres. Geometry work is done in the *local frame*:
map coordinates minus ``offset`` (the Pix4D ``offset.xyz``), x east, y north, z up.

The *surface* is the DSM raster interpolated bilinearly between pixel centres (as
``core.raster.DSM.heights``); where the DSM has no data or outside it, the bare-ground
plane. Truth heights and ray intersections all refer to that surface.

The vegetation (:func:`make_scene`, ``mess``: :class:`.field.FieldMess`) is the plots' crop
(``field._plot_canopy``), the weeds (``field.make_weeds``) and the margin grass
(:func:`_margin_grass`); the DSM holds the tallest of them, the orthomosaic colours each texel by
the kind that is tallest there, with the soil's colour gradient (:func:`soil_colour`) and the
crop's cast shadows (:func:`shadow_factor`).
"""
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import List

import numpy as np

from .field import (DOM_PIXEL, DSM_PIXEL, NO_MESS, NODATA, FieldLayout, FieldMess, add_field_mess,
                    canopy_grid, make_plots, make_weeds, plot_corners, weed_grid)

SURVEY_FIELD = FieldLayout(origin=(319800.0, 3956050.0), size=(60.0, 40.0), rows=5, cols=8,
                           plot_size=(4.0, 2.5), first_plot=(5.0, 4.5), pitch=(7.0, 7.5),
                           ground=(95.0, 0.02, 0.01), nodata_cols=40, epsg=32654)
GCP_PLACES = ((2.0, 2.0), (58.0, 2.0), (2.0, 38.0), (58.0, 38.0), (29.5, 15.75))
"""Centres of the ground control targets, metres right and down from the field origin."""
GCP_SIZE = 0.6      # m, side of a black-and-white checkerboard target
BAND_ROWS = 500     # orthomosaic rows textured at once
CROP_BLOCK = 8      # DSM pixels per side of a surface-top block (16 cm)
CROP_GROW = 3       # blocks by which block tops are spread (rays cross the crop slanted)
SOIL_RGB = (122, 96, 72)       # orthomosaic soil colour (times the moisture shade)
LEAF_RGB = (58, 132, 46)       # leaf colour (times 0.75 + 0.45 · min(height / 0.7 m, 1))
LEAF_FULL = 0.05    # m of crop height at which a texel is all leaf (blended towards soil below)
MOISTURE = 0.07     # relative soil brightness change per unit of the smooth moisture field
WEED_RGB = (72, 128, 50)       # weed leaf colour (times the same height shade as the crop's)
DRY_GRASS_RGB = (150, 140, 88)  # the margin grass is a mix of this and the crop leaf colour
SOIL_TREND = (1.0, 0.55, 0.35)  # per band: how the soil colour gradient changes R, G, B
SUN = (1.0, 1.0)               # (columns, rows) per step towards the sun (south-east), DSM grid
GRASS_GCP_CLEAR = 0.6          # m around a ground control target kept free of grass


def bilinear_grid(a: np.ndarray, fx: np.ndarray, fy: np.ndarray) -> np.ndarray:
    """``a`` bilinear at fractional grid positions (column ``fx``, row ``fy``), clamped to the
    grid. ``fx`` and ``fy`` are modified in place (they are scratch arrays of the callers)."""
    np.clip(fx, 0.0, a.shape[1] - 1.001, out=fx)
    np.clip(fy, 0.0, a.shape[0] - 1.001, out=fy)
    ix, iy = fx.astype(np.int32), fy.astype(np.int32)
    fx -= ix
    fy -= iy
    flat = iy * np.int32(a.shape[1]) + ix
    r = a.ravel()
    top = r[flat]
    top += fx * (r[flat + 1] - top)
    flat += a.shape[1]
    bottom = r[flat]
    bottom += fx * (r[flat + 1] - bottom)
    top += fy * (bottom - top)
    return top


@dataclass
class Scene:
    """Everything known about the ground. ``dsm`` float32 with ``NODATA``; ``ortho`` uint8
    (rows, cols, 3) at 1 cm; ``rel`` float32 surface height above the ground plane on the DSM
    grid, nodata filled with 0 and padded with one row/column of zeros on every side."""
    layout: FieldLayout
    plots: List[dict]
    offset: np.ndarray
    dsm: np.ndarray
    ortho: np.ndarray
    rel: np.ndarray
    gcps: np.ndarray          # (k, 3) map coordinates of the target centres
    gcp_labels: List[str]
    rel_min: float            # range of ``rel`` (m)
    rel_max: float
    bare_max: float           # highest ``rel`` where there is no crop (m)
    top_blocks: np.ndarray    # float32: highest ``rel`` per CROP_BLOCK² DSM pixels, grown by CROP_GROW
    mess: FieldMess = FieldMess()
    weeds: np.ndarray = None  # (n, 4) map x, y, radius, height (m): :func:`.field.make_weeds`

    # --- geometry in the local frame -------------------------------------------------------------
    def ground_local(self, x, y):
        """Ground-plane height (local z) at local (x, y)."""
        o = self.offset
        return self.layout.ground_height(x + o[0], y + o[1]) - o[2]

    @property
    def ground_plane(self):
        """(a, bx, by): local ground z = a + bx·x + by·y."""
        _, sx, sy = self.layout.ground
        return float(self.ground_local(0.0, 0.0)), sx, sy

    def rel_at(self, x, y, fast: bool = False):
        """Bilinear surface height above the ground plane at local (x, y) (0 outside the DSM).
        ``fast``: grid positions in float32 (about 5 µm), for rendering; else float64."""
        a = self.rel
        dt = np.float32 if fast else np.float64
        ox = dt((self.offset[0] - self.layout.origin[0]) / DSM_PIXEL + 0.5)
        oy = dt((self.layout.origin[1] - self.offset[1]) / DSM_PIXEL + 0.5)
        fx = np.asarray(x, dt) * dt(1 / DSM_PIXEL)
        fx += ox
        fy = np.asarray(y, dt) * dt(-1 / DSM_PIXEL)
        fy += oy
        return bilinear_grid(a, fx, fy)

    def surface_local(self, x, y):
        """Surface height (local z) at local (x, y), float64."""
        return self.ground_local(x, y) + self.rel_at(x, y).astype(np.float64)

    def dsm_valid(self, x, y, margin: float = 0.0):
        """True where the four DSM pixels around local (x, y) (grown by ``margin`` m) have data."""
        lay = self.layout
        col = (x + self.offset[0] - lay.origin[0]) / DSM_PIXEL
        row = (lay.origin[1] - (y + self.offset[1])) / DSM_PIXEL
        ny, nx = self.dsm.shape
        m = margin / DSM_PIXEL
        return (col >= lay.nodata_cols + 1 + m) & (col <= nx - 1 - m) & (row >= 1 + m) & (row <= ny - 1 - m)


def make_scene(seed: int, layout: FieldLayout = SURVEY_FIELD, mess: FieldMess = NO_MESS) -> Scene:
    """Plots, DSM and orthomosaic from ``seed`` (deterministic, whatever the thread timing), with
    what real fields have (``mess``, :class:`.field.FieldMess`; its features drawn from their
    own random streams of the seed: weeds, grass, vigour, gaps, lodging, shadows, soil colour).
    The default is the tidy field; :func:`.survey.make_demo_survey` passes its own (its default
    is the messy ``FieldMess()``; ``DemoSurvey.field_mess`` says which a survey has)."""
    rng = np.random.default_rng(seed)
    plots = add_field_mess(make_plots(layout, rng), mess, np.random.default_rng([seed, 30]))
    weeds = make_weeds(layout, plots, mess, np.random.default_rng([seed, 31]))
    x0, y0 = layout.origin
    w, h = layout.size
    centre_g = layout.ground_height(x0 + w / 2, y0 - h / 2)
    offset = np.array([round(x0 + w / 2), round(y0 - h / 2), round(centre_g)], dtype=np.float64)

    ny, nx = layout.grid_shape(DSM_PIXEL)
    crop = canopy_grid(layout, plots, DSM_PIXEL)
    weed = weed_grid(layout, weeds, DSM_PIXEL)
    grass = _margin_grass(layout, plots, mess, seed)
    canopy = np.maximum.reduce([crop, weed, grass])
    kind = np.select([canopy <= 0, grass >= canopy, weed >= canopy], [0, 3, 2], 1).astype(np.uint8)
    noise = rng.normal(0.0, 0.004, (ny, nx))
    y = y0 - (np.arange(ny) + 0.5)[:, None] * DSM_PIXEL
    x = x0 + (np.arange(nx) + 0.5)[None, :] * DSM_PIXEL
    dsm = (layout.ground_height(x, y) + canopy + noise).astype(np.float32)
    rel = np.zeros((ny + 2, nx + 2), np.float32)
    rel[1:-1, 1:-1] = dsm - layout.ground_height(x, y)
    dsm[:, :layout.nodata_cols] = NODATA
    rel[1:-1, 1:layout.nodata_cols + 1] = 0.0

    gcps = np.array([[x0 + dx, y0 - dy, 0.0] for dx, dy in GCP_PLACES])
    ortho = _orthomosaic(layout, canopy, kind, gcps[:, :2], seed, mess)
    bare_max = float(rel[1:-1, 1:-1][canopy == 0].max())
    scene = Scene(layout, plots, offset, dsm, ortho, rel, gcps,
                  [f"GCP{i + 1}" for i in range(len(gcps))],
                  float(rel.min()), float(rel.max()), bare_max, _top_blocks(rel), mess, weeds)
    loc = gcps - offset
    scene.gcps[:, 2] = scene.surface_local(loc[:, 0], loc[:, 1]) + offset[2]
    return scene


def _top_blocks(rel: np.ndarray) -> np.ndarray:
    """Highest surface (above the ground plane) per CROP_BLOCK² DSM pixels, then the maximum
    over the CROP_GROW neighbouring blocks in every direction (a conservative band top)."""
    b, g = CROP_BLOCK, CROP_GROW
    a = rel[1:-1, 1:-1]
    ny, nx = -(-a.shape[0] // b), -(-a.shape[1] // b)
    pad = np.full((ny * b + 2, nx * b + 2), a.min(), np.float32)   # + the bilinear reach
    pad[1:a.shape[0] + 1, 1:a.shape[1] + 1] = a
    m = np.maximum.reduce([pad[i:i + ny * b, j:j + nx * b] for i in range(3) for j in range(3)])
    blocks = m.reshape(ny, b, nx, b).max(axis=(1, 3))
    grown = np.full((ny + 2 * g, nx + 2 * g), blocks.min(), np.float32)
    out = blocks.copy()
    grown[g:g + ny, g:g + nx] = blocks
    for dy in range(2 * g + 1):
        for dx in range(2 * g + 1):
            np.maximum(out, grown[dy:dy + ny, dx:dx + nx], out=out)
    return out


def _margin_grass(layout: FieldLayout, plots, mess: FieldMess, seed: int) -> np.ndarray:
    """Grass height (m) on the DSM grid: ``grass_cover`` of the cells beyond ``margin`` m outside
    the plot block's bounding box (not on the ground control targets), 2–7 cm tall."""
    shape = layout.grid_shape(DSM_PIXEL)
    if not mess.margin_grass or not plots:
        return np.zeros(shape)
    rng = np.random.default_rng([seed, 32])
    c = np.vstack([plot_corners(p) for p in plots])
    (x0, y0), (x1, y1) = c.min(axis=0) - mess.margin, c.max(axis=0) + mess.margin
    x = layout.origin[0] + (np.arange(shape[1]) + 0.5)[None, :] * DSM_PIXEL
    y = layout.origin[1] - (np.arange(shape[0]) + 0.5)[:, None] * DSM_PIXEL
    margin = ~((x > x0) & (x < x1) & (y > y0) & (y < y1))
    for gx, gy in GCP_PLACES:
        gx, gy = layout.origin[0] + gx, layout.origin[1] - gy
        margin &= ~((np.abs(x - gx) < GRASS_GCP_CLEAR) & (np.abs(y - gy) < GRASS_GCP_CLEAR))
    grass = margin & (rng.uniform(size=shape) < mess.grass_cover)
    return np.where(grass, rng.uniform(0.02, 0.07, shape), 0.0)


def grass_rgb(share: float) -> np.ndarray:
    """The margin grass colour: the mix of DRY_GRASS_RGB and LEAF_RGB whose ExG is ``share`` ×
    the crop leaf's (bisection on the mix)."""
    exg = lambda c: (2 * c[1] - c[0] - c[2]) / c.sum()           # noqa: E731
    dry, leaf = np.array(DRY_GRASS_RGB, float), np.array(LEAF_RGB, float)
    lo, hi = 0.0, 1.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if exg(dry + mid * (leaf - dry)) < share * exg(leaf) else (lo, mid)
    return dry + lo * (leaf - dry)


def soil_colour(layout: FieldLayout, mess: FieldMess, x) -> np.ndarray:
    """Soil colour (…, 3) before the moisture shade at map x: SOIL_RGB, changed from the west
    edge to the east edge by ``soil_gradient`` (SOIL_TREND per band)."""
    t = (np.asarray(x, np.float64) - layout.origin[0]) / layout.size[0] - 0.5
    return np.array(SOIL_RGB) * (1 + mess.soil_gradient * t[..., None] * np.array(SOIL_TREND))


def shadow_factor(canopy: np.ndarray, mess: FieldMess) -> np.ndarray:
    """Brightness factor (DSM grid, float32) of the crop's cast shadows: 1 − ``shadow`` where
    vegetation towards the sun (SUN steps, 45° elevation) rises above the line to the sun."""
    out = np.ones(canopy.shape, np.float32)
    if not mess.shadow:
        return out
    ny, nx = canopy.shape
    lit = np.ones(canopy.shape, bool)
    step = DSM_PIXEL * np.hypot(*SUN)
    for k in range(1, int(np.ceil(canopy.max() / step)) + 1):
        dc, dr = int(SUN[0] * k), int(SUN[1] * k)
        if dc >= nx or dr >= ny:
            break
        lit[:ny - dr, :nx - dc] &= canopy[dr:, dc:] <= canopy[:ny - dr, :nx - dc] + k * step
    out[~lit] = 1 - mess.shadow
    return out


# --- orthomosaic texture ------------------------------------------------------------------------
def _orthomosaic(layout: FieldLayout, canopy: np.ndarray, kind: np.ndarray, gcp_xy: np.ndarray,
                 seed: int, mess: FieldMess = FieldMess()) -> np.ndarray:
    """RGB uint8 at 1 cm: soil (smooth moisture on 1 m, clods on 4 cm, grain on 1 cm, the colour
    gradient), leaves coloured by height and ``kind`` (1 crop, 2 weed, 3 grass), cast shadows,
    checkerboard ground control targets. Rows are textured in bands on two threads; each band
    has its own random stream, so the result does not depend on timing."""
    ny, nx = layout.grid_shape(DOM_PIXEL)
    out = np.empty((ny, nx, 3), np.uint8)
    g = _moisture_grid(layout, seed)
    x = layout.origin[0] + (np.arange(nx) + 0.5) * DOM_PIXEL
    soil_cols = soil_colour(layout, mess, x).astype(np.float32)          # (nx, 3)
    leaf_rgb = np.array([[0, 0, 0], LEAF_RGB, WEED_RGB, grass_rgb(mess.margin_grass or 0.5)],
                        np.float32)
    sun = shadow_factor(canopy, mess)
    ratio = round(DSM_PIXEL / DOM_PIXEL)

    def band(b0: int):
        b1 = min(b0 + BAND_ROWS, ny)
        rows = b1 - b0
        rng = np.random.default_rng([seed, 11, b0])
        # 4 cm cells: smooth moisture (bilinear over 1 m) and clods
        r = (np.arange(b0 // 4, -(-b1 // 4)) + 0.5) / 25.0
        c = (np.arange(-(-nx // 4)) + 0.5) / 25.0
        ri, ci = r.astype(np.intp), c.astype(np.intp)
        wr, wc = (r - ri)[:, None], (c - ci)[None, :]
        moist = (g[ri][:, ci] * (1 - wc) + g[ri][:, ci + 1] * wc) * (1 - wr) \
            + (g[ri + 1][:, ci] * (1 - wc) + g[ri + 1][:, ci + 1] * wc) * wr
        shade4 = (1 + MOISTURE * moist + 0.05 * rng.standard_normal(moist.shape)).astype(np.float32)
        shade = np.repeat(np.repeat(shade4, 4, 0), 4, 1)[b0 - (b0 // 4) * 4:][:rows, :nx]
        grain = rng.integers(-9, 10, (rows, nx), dtype=np.int8)
        tmp = np.empty((rows, nx), np.float32)
        up = lambda a: np.repeat(np.repeat(a[b0 // ratio:-(-b1 // ratio)], ratio, 0), ratio, 1)[  # noqa: E731
            b0 - (b0 // ratio) * ratio:][:rows]
        sun_b = up(sun)
        for k in range(3):
            np.multiply(shade, soil_cols[:, k], out=tmp)
            tmp += grain
            tmp *= sun_b
            np.clip(tmp, 0, 255, out=tmp)
            out[b0:b1, :, k] = tmp
        # leaves where the vegetation is: blend towards green by height (grass: all leaf)
        h = up(canopy)
        rr, cc = np.nonzero(h > 0)
        hv = h[rr, cc].astype(np.float32)
        kv = up(kind)[rr, cc]
        leaf = np.where(kv == 3, 1.0, np.clip(hv / LEAF_FULL, 0, 1)).astype(np.float32)[:, None]
        gr = grain[rr, cc].astype(np.float32)[:, None]
        soil = soil_cols[cc] * shade[rr, cc][:, None] + gr
        green = leaf_rgb[kv] * (0.75 + 0.45 * np.clip(hv / 0.7, 0, 1))[:, None] + 1.3 * gr
        out[b0 + rr, cc] = np.clip((soil * (1 - leaf) + green * leaf) * sun_b[rr, cc][:, None],
                                   0, 255).astype(np.uint8)

    with ThreadPoolExecutor(2) as pool:
        list(pool.map(band, range(0, ny, BAND_ROWS)))

    half = GCP_SIZE / 2
    n = int(round(GCP_SIZE / DOM_PIXEL))
    rr, cc = np.mgrid[0:n, 0:n]
    target = np.where(((rr < n // 2) == (cc < n // 2))[..., None], 235, 25).astype(np.uint8)
    for gx, gy in gcp_xy:
        c0 = int(round((gx - half - layout.origin[0]) / DOM_PIXEL))
        r0 = int(round((layout.origin[1] - (gy + half)) / DOM_PIXEL))
        out[r0:r0 + n, c0:c0 + n] = target
    return out


def _moisture_grid(layout: FieldLayout, seed: int) -> np.ndarray:
    """The soil moisture field's values at 1 m nodes (bilinear between them)."""
    ny, nx = layout.grid_shape(DOM_PIXEL)
    return np.random.default_rng([seed, 7]).standard_normal((ny // 100 + 2, nx // 100 + 2))


def surface_cloud(scene: Scene, rng, stride: int = 5):
    """A dense-cloud-like sample of the surface: one point at a random place in every
    ``stride``² block of DSM pixels with data. Returns map xyz (n, 3) and RGB (n, 3) uint8
    (the orthomosaic pixel under each point)."""
    lay = scene.layout
    ny, nx = scene.dsm.shape
    by, bx = ny // stride, nx // stride
    cols = (np.arange(bx) * stride)[None, :] + rng.uniform(0, stride, (by, bx))
    rows = (np.arange(by) * stride)[:, None] + rng.uniform(0, stride, (by, bx))
    keep = cols >= lay.nodata_cols + 0.5
    cols, rows = cols[keep], rows[keep]
    x = lay.origin[0] + cols * DSM_PIXEL - scene.offset[0]
    y = lay.origin[1] - rows * DSM_PIXEL - scene.offset[1]
    z = scene.surface_local(x, y)
    ratio = DSM_PIXEL / DOM_PIXEL
    rgb = scene.ortho[(rows * ratio).astype(np.intp), (cols * ratio).astype(np.intp)]
    return np.column_stack([x, y, z]) + scene.offset, rgb


def ortho_level(ortho: np.ndarray, level: int) -> np.ndarray:
    """The orthomosaic averaged over 2^level × 2^level pixels (uint8)."""
    a = ortho
    for _ in range(level):
        r, c = a.shape[0] // 2 * 2, a.shape[1] // 2 * 2
        s = a[:r:2, :c:2].astype(np.uint16) + a[1:r:2, :c:2] + a[:r:2, 1:c:2] + a[1:r:2, 1:c:2]
        a = ((s + 2) // 4).astype(np.uint8)
    return a
