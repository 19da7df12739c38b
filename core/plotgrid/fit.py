"""Fit a plot grid to the crop rows of an orthomosaic.

1. **Vegetation image.** One sweep of the orthomosaic (``core.raster.sweep``: each tile
   decoded once, memory bounded, cancellable) over the plots' bounding box, read in strips
   that are averaged over k × k pixels as they arrive, so the working image has at most
   :data:`MAX_WORK_PIXELS` pixels whatever the raster's size. The index is ExG
   (2G − R − B)/(R + G + B) of RGB, or NDVI (NIR − R)/(NIR + R) of a multispectral raster; it is
   mapped to a vegetation weight in [0, 1] between the soil and leaf levels (Otsu's threshold
   splits the two; the weight ramps from the soil median to the leaf median).
2. **Crop rows.** The power spectrum of the weights over the field (Hann window) has its
   strongest peak, among periods shorter than half a plot, at the crop rows: its direction
   gives the rows' bearing and its frequency their spacing (sub-bin by a parabola). The rows
   are taken as parallel to the nearest grid axis, which gives a first rotation.
3. **Global correction.** Each plot is searched around its place (rotated by that first
   estimate) for the position where a box of its size holds the most vegetation (an integral
   image over a search window of ±0.45 of the plot spacing), then centred on its vegetation
   (the weighted centroid inside the plot grown by half the gap, three times). A least-squares
   affine transform from the grid's plot centres to these, with outliers (3 × the median
   residual) and bare plots left out, is reduced to a rotation, one spacing scale per grid axis
   and a shift; the plots are then searched again from it, in a smaller window.
4. **Per plot.** Around its globally corrected place, each plot is centred on its vegetation
   as in 3. The shift is kept when it is within ``max_shift``; plots that are bare (their cover
   under ``min_cover`` × the median cover), whose vegetation lies mostly outside them (score
   under ``min_score``: weeds, a missing plot between planted neighbours) or whose shift would
   exceed the bound are *left in place*: they keep the global correction and no shift.

Plots keep their shape and size; they turn by the global rotation about their centre. The score
of a plot is the share of the vegetation in its plot-plus-margin window that lies inside it.
"""
import math
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..errors import EasyIDPError
from ..progress import as_progress

MAX_WORK_PIXELS = 16_000_000
STRIP_ROWS = 512
CENTROID_ITERATIONS = 3

FLAG_BARE = "bare soil or missing"
FLAG_WEAK = "vegetation mostly outside the plot (weeds, or a missing plot)"
FLAG_BOUND = "shift beyond the bound"


@dataclass
class FitResult:
    """Per plot (input order): ``rings`` (fitted exterior rings), ``shift`` (n, 2) per-plot
    shift after the global correction (m; 0 for plots left in place), ``score``, ``cover``,
    ``flag`` ('' when fitted), ``moved`` (the per-plot shift was applied); global: ``rotation``
    (degrees, counter-clockwise), ``scale`` (spacing along the grid's x and y axes),
    ``translation`` (m, of the grid centre ``centre``), ``row_bearing`` (degrees, 0–180) and
    ``row_spacing`` (m) of the crop rows, or None; ``work_pixel`` (m); ``notes``."""
    rings: List[np.ndarray]
    shift: np.ndarray
    score: np.ndarray
    cover: np.ndarray
    flag: List[str]
    moved: np.ndarray
    rotation: float
    scale: Tuple[float, float]
    translation: Tuple[float, float]
    centre: Tuple[float, float]
    row_bearing: Optional[float]
    row_spacing: Optional[float]
    work_pixel: float
    notes: List[str] = field(default_factory=list)
    centres_in: Optional[np.ndarray] = None
    centres_out: Optional[np.ndarray] = None

    def move(self, i: int, xy) -> np.ndarray:
        """Points (n, 2) of plot ``i`` moved as the plot was (turned about its centre by the
        global rotation, then to its fitted centre): holes and other parts follow it."""
        t = math.radians(self.rotation)
        return (np.asarray(xy, float)[:, :2] - self.centres_in[i]) @ _rot(t).T + self.centres_out[i]

    @property
    def shift_m(self) -> np.ndarray:
        return np.hypot(self.shift[:, 0], self.shift[:, 1])

    def moved_over(self, threshold: float) -> int:
        return int(np.sum(self.moved & (self.shift_m > threshold)))

    def summary(self, threshold: float = 0.05) -> str:
        rows = "" if self.row_bearing is None else \
            f" Crop rows: bearing {self.row_bearing:.2f}°, spacing {self.row_spacing:.3f} m."
        left = len(self.flag) - int(self.moved.sum())
        return (f"Global correction: rotation {self.rotation:+.3f}°, spacing scale "
                f"{self.scale[0]:.4f} (x) {self.scale[1]:.4f} (y), shift "
                f"({self.translation[0]:+.3f}, {self.translation[1]:+.3f}) m.{rows} "
                f"{self.moved_over(threshold)} of {len(self.flag)} plots moved by more than "
                f"{threshold:g} m; {left} left in place.")


# ---- the vegetation image ---------------------------------------------------------------------

class _Work:
    """The vegetation weights on the working grid: ``w`` (rows, cols) float32; pixel centre
    (r, c) at map ``x0 + (c + 0.5)·px``, ``y0 − (r + 0.5)·py``."""

    def __init__(self, w, x0, y0, px, py):
        self.w, self.x0, self.y0, self.px, self.py = w, x0, y0, px, py

    def sample(self, x, y) -> np.ndarray:
        """Bilinear between pixel centres; 0 outside (the weights padded by one pixel of 0,
        made on the first call: the weights are final by then)."""
        if getattr(self, "_pad", None) is None:
            self._pad = np.pad(self.w, 1)
        pad = self._pad
        h, wd = self.w.shape
        c = (np.asarray(x) - self.x0) * (1.0 / self.px) + 0.5      # index in the padded array
        r = (self.y0 - np.asarray(y)) * (1.0 / self.py) + 0.5
        np.clip(c, 0, wd + 0.999, out=c)
        np.clip(r, 0, h + 0.999, out=r)
        c0 = c.astype(np.intp)
        r0 = r.astype(np.intp)
        fc = (c - c0).astype(np.float32)
        fr = (r - r0).astype(np.float32)
        flat = r0 * (wd + 2) + c0
        f = pad.ravel()
        a = f[flat]
        b = f[flat + 1]
        top = a + (b - a) * fc
        flat += wd + 2
        a = f[flat]
        b = f[flat + 1]
        bottom = a + (b - a) * fc
        return top + (bottom - top) * fr


def _index_of(block: np.ndarray, kind: str, bands) -> np.ndarray:
    """The vegetation index of (h, w, bands) float32 pixel means."""
    eps = np.float32(1e-6)
    if kind == "exg":
        r, g, b = (block[..., i] for i in bands)
        s = r + g + b
        return (2 * g - r - b) / np.maximum(s, eps)
    red, nir = (block[..., i] for i in bands)
    return (nir - red) / np.maximum(nir + red, eps)


def _read_work(tif, bbox, kind: str, bands, prog, workers=None) -> _Work:
    """The index averaged over k × k pixels over the map ``bbox`` (one sweep, by strips)."""
    from ..raster.sweep import Window, sweep_windows
    xmin, ymin, xmax, ymax = bbox
    c_a, r_a = tif.map_to_pixel(np.array([xmin, xmax]), np.array([ymax, ymin]))
    col0, col1 = max(int(math.floor(c_a.min())), 0), min(int(math.ceil(c_a.max())), tif.width)
    row0, row1 = max(int(math.floor(r_a.min())), 0), min(int(math.ceil(r_a.max())), tif.height)
    if col1 - col0 < 2 or row1 - row0 < 2:
        raise EasyIDPError("Plot grid: the plots do not lie on the orthomosaic (check that the "
                           "grid and the orthomosaic are of the same field and in the same CRS).")
    k = max(1, int(math.ceil(math.sqrt((col1 - col0) * (row1 - row0) / MAX_WORK_PIXELS))))
    ncols, nrows = (col1 - col0) // k, (row1 - row0) // k
    if ncols < 2 or nrows < 2:
        raise EasyIDPError("Plot grid: the plots cover less than two pixels of the orthomosaic.")
    strip = k * max(1, STRIP_ROWS // k)
    windows = [Window(row0 + r, col0, min(strip, nrows * k - r), ncols * k)
               for r in range(0, nrows * k, strip)]
    out = np.full((nrows, ncols), np.nan, np.float32)
    alpha = tif.alpha_band
    nodata = tif.nodata

    def consume(i, arr):
        w = windows[i]
        h = w.rows // k
        a = arr.reshape(h, k, ncols, k, arr.shape[2])
        sel = list(bands) + ([alpha] if alpha is not None else [])
        m = np.empty((h, ncols, len(sel)), np.float32)
        for j, b in enumerate(sel):
            m[..., j] = a[..., b].sum(axis=(1, 3), dtype=np.float32)
        m /= k * k
        vi = _index_of(m, kind, range(len(bands)))
        bad = np.zeros(vi.shape, bool)
        if alpha is not None:
            bad |= m[..., -1] < 0.5 * np.iinfo(tif.dtype).max if tif.dtype.kind == "u" else False
        if nodata is not None:
            bad |= np.all(a[:, 0, :, 0, :][..., list(bands)] == nodata, axis=-1)
        vi[bad] = np.nan
        r = (w.row - row0) // k
        out[r:r + h] = vi

    sweep_windows(tif, windows, consume, prog, workers)
    x0, y0 = tif.pixel_to_map(col0, row0)
    a, e = tif.geotransform[1], tif.geotransform[5]
    return _Work(out, float(x0), float(y0), abs(a) * k, abs(e) * k), k


def _otsu(v: np.ndarray) -> float:
    hist, edges = np.histogram(v, bins=256)
    p = hist.astype(np.float64) / max(hist.sum(), 1)
    mids = (edges[:-1] + edges[1:]) / 2
    w0 = np.cumsum(p)
    m0 = np.cumsum(p * mids)
    mt = m0[-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        between = (mt * w0 - m0) ** 2 / (w0 * (1 - w0))
    return float(mids[int(np.nanargmax(between))])


def _weights(work: _Work) -> Tuple[float, float]:
    """Turn the index image into vegetation weights in place; returns (soil, leaf) levels."""
    v = work.w
    fin = v[np.isfinite(v)]
    if fin.size < 16:
        raise EasyIDPError("Plot grid: the orthomosaic has no valid pixels under the plots.")
    sample = fin[:: max(1, fin.size // 2_000_000)]
    t = _otsu(sample)
    lo = float(np.median(sample[sample <= t])) if np.any(sample <= t) else float(sample.min())
    hi = float(np.median(sample[sample > t])) if np.any(sample > t) else float(sample.max())
    if not hi > lo:
        hi = lo + 1e-6
    np.subtract(v, lo, out=v)
    v *= 1.0 / (hi - lo)
    np.clip(v, 0, 1, out=v)
    v[~np.isfinite(v)] = 0
    return lo, hi


def _rows_spectrum(work: _Work, centre, max_period: float):
    """(direction of the rows (radians from east, counter-clockwise), spacing m, strength) of
    the strongest periodic pattern with a period below ``max_period``, or None."""
    h, wd = work.w.shape
    n = 1024
    r0 = int(np.clip((work.y0 - centre[1]) / work.py - n / 2, 0, max(h - n, 0)))
    c0 = int(np.clip((centre[0] - work.x0) / work.px - n / 2, 0, max(wd - n, 0)))
    a = work.w[r0:r0 + n, c0:c0 + n].astype(np.float64)
    if min(a.shape) < 32:
        return None
    a = a - a.mean()
    a *= np.hanning(a.shape[0])[:, None] * np.hanning(a.shape[1])[None, :]
    P = np.abs(np.fft.fft2(a)) ** 2
    fy = np.fft.fftfreq(a.shape[0], work.py)          # cycles per metre along the rows index
    fx = np.fft.fftfreq(a.shape[1], work.px)
    FX, FY = np.meshgrid(fx, -fy)                       # map y is up, the row index down
    f = np.hypot(FX, FY)
    fmax = 1.0 / (3 * max(work.px, work.py))
    band = (f > 1.0 / max_period) & (f < fmax) & (FX >= 0)
    if not band.any():
        return None
    Pb = np.where(band, P, 0)
    i = np.unravel_index(int(np.argmax(Pb)), P.shape)
    peak = P[i]
    strength = float(peak / (np.median(P[band]) + 1e-12))

    def interp(vals):
        lft, mid, rgt = vals
        d = lft - 2 * mid + rgt
        return 0.0 if d == 0 else 0.5 * (lft - rgt) / d

    dy = interp([P[(i[0] - 1) % P.shape[0], i[1]], peak, P[(i[0] + 1) % P.shape[0], i[1]]])
    dx = interp([P[i[0], (i[1] - 1) % P.shape[1]], peak, P[i[0], (i[1] + 1) % P.shape[1]]])
    ky = np.fft.fftfreq(a.shape[0])[i[0]] + dy / a.shape[0]
    kx = np.fft.fftfreq(a.shape[1])[i[1]] + dx / a.shape[1]
    wx, wy = kx / work.px, -ky / work.py
    spacing = 1.0 / math.hypot(wx, wy)
    direction = math.atan2(wy, wx) + math.pi / 2
    return direction, spacing, strength


# ---- plot geometry ----------------------------------------------------------------------------

def _centroid(ring: np.ndarray) -> np.ndarray:
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cr = x * y1 - x1 * y
    a = cr.sum() / 2
    if abs(a) < 1e-12:
        return ring.mean(axis=0)
    return ring[0] + np.array([((x + x1) * cr).sum(), ((y + y1) * cr).sum()]) / (6 * a)


def _grid_axis(rings: Sequence[np.ndarray]) -> float:
    """The grid's x-axis angle (radians): the plots' edges, mod 90°, weighted by length."""
    s = c = 0.0
    for r in rings:
        d = np.roll(r, -1, axis=0) - r
        L = np.hypot(d[:, 0], d[:, 1])
        t = 4 * np.arctan2(d[:, 1], d[:, 0])
        s += float((L * np.sin(t)).sum())
        c += float((L * np.cos(t)).sum())
    return math.atan2(s, c) / 4


def _pitch(values: np.ndarray, tol: float) -> float:
    """The smallest spacing between distinct clusters of ``values``."""
    v = np.sort(values)
    d = np.diff(v)
    d = d[d > tol]
    return float(d.min()) if d.size else math.inf


def _rot(t: float) -> np.ndarray:
    return np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])


# ---- measuring one plot -----------------------------------------------------------------------

class _Plot:
    def __init__(self, work: _Work, axes: np.ndarray, half: np.ndarray):
        self.work, self.axes, self.half = work, axes, half   # axes: rows are ux, uy (map)
        self.step = min(work.px, work.py)

    def _grid(self, centre, ext_u, ext_v):
        s = self.step
        nu, nv = max(int(math.ceil(2 * ext_u / s)), 2), max(int(math.ceil(2 * ext_v / s)), 2)
        u = (np.arange(nu) + 0.5) * (2 * ext_u / nu) - ext_u
        v = (np.arange(nv) + 0.5) * (2 * ext_v / nv) - ext_v
        U, V = np.meshgrid(u, v)
        x = centre[0] + U * self.axes[0, 0] + V * self.axes[1, 0]
        y = centre[1] + U * self.axes[0, 1] + V * self.axes[1, 1]
        return u, v, self.work.sample(x, y)

    def box_search(self, centre, half, reach) -> np.ndarray:
        """The offset (map) of the box of the plot's size holding the most vegetation within
        ``reach`` (u, v) of ``centre``: the middle of the positions within 0.5 % of the best."""
        ext = half + reach
        u, v, S = self._grid(centre, ext[0], ext[1])
        du, dv = u[1] - u[0], v[1] - v[0]
        bu, bv = max(int(round(2 * half[0] / du)), 1), max(int(round(2 * half[1] / dv)), 1)
        if bu >= len(u) or bv >= len(v):
            return np.zeros(2)
        I = np.zeros((S.shape[0] + 1, S.shape[1] + 1))
        I[1:, 1:] = S.cumsum(0).cumsum(1)
        box = I[bv:, bu:] - I[:-bv, bu:] - I[bv:, :-bu] + I[:-bv, :-bu]
        best = box.max()
        if best <= 0:
            return np.zeros(2)
        jj, ii = np.nonzero(box >= best * 0.995)
        ou = u[0] - du / 2 + (ii.mean() + bu / 2) * du
        ov = v[0] - dv / 2 + (jj.mean() + bv / 2) * dv
        return ou * self.axes[0] + ov * self.axes[1]

    def centre_on_rows(self, centre, half, margin):
        """(centre, score, cover): the vegetation centroid in the plot grown by ``margin``,
        recentred :data:`CENTROID_ITERATIONS` times; the score and cover at the result."""
        c = np.asarray(centre, float)
        for _ in range(CENTROID_ITERATIONS):
            u, v, S = self._grid(c, half[0] + margin[0], half[1] + margin[1])
            tot = S.sum()
            if tot <= 0:
                break
            U, V = np.meshgrid(u, v)
            c = c + (float((S * U).sum()) / tot) * self.axes[0] + \
                (float((S * V).sum()) / tot) * self.axes[1]
        return c

    def score(self, centre, half, margin):
        u, v, S = self._grid(centre, half[0] + margin[0], half[1] + margin[1])
        inside = (np.abs(u)[None, :] <= half[0]) & (np.abs(v)[:, None] <= half[1])
        tot = float(S.sum())
        ins = float(S[inside].sum())
        return (ins / tot if tot > 0 else 0.0), (ins / max(int(inside.sum()), 1))


# ---- the fit ----------------------------------------------------------------------------------

def _similarity(nominal, measured, ok, c0, axes):
    """(rotation, (su, sv), t) with measured ≈ c0 + t + R·G·S·Gᵀ·(nominal − c0)."""
    P = nominal[ok] - c0
    Q = measured[ok] - c0
    X = np.column_stack([P, np.ones(len(P))])
    coef, *_ = np.linalg.lstsq(X, Q, rcond=None)
    A = coef[:2].T                                 # Q ≈ A·P + t
    G = np.column_stack([axes[0], -axes[1]])       # right-handed: ux, and ux turned left
    Ag = G.T @ A @ G
    theta = math.atan2(Ag[1, 0] - Ag[0, 1], Ag[0, 0] + Ag[1, 1])
    S = _rot(-theta) @ Ag
    su, sv = float(S[0, 0]), float(S[1, 1])
    M = _rot(theta) @ G @ np.diag([su, sv]) @ G.T
    t = (Q - P @ M.T).mean(axis=0)
    return theta, (su, sv), t, M


def fit_plot_grid(rings: Sequence[np.ndarray], orthomosaic, *, crs=None, index: str = "auto",
                  bands: Optional[Sequence[int]] = None, max_shift: float = 0.25,
                  search: Optional[float] = None, min_cover: float = 0.3,
                  min_score: float = 0.6, progress=None, is_cancelled=None,
                  workers: Optional[int] = None) -> FitResult:
    """Fit plots (their exterior rings, map coordinates in the orthomosaic's CRS) to the crop
    rows of ``orthomosaic`` (a path or an opened ``GeoTiff``); see the module docstring.

    ``index``: "exg" (RGB), "ndvi" (multispectral) or "auto" (ExG for an RGB raster);
    ``bands``: 1-based band numbers, (red, green, blue) for ExG, (red, nir) for NDVI (defaults
    1, 2, 3 for ExG); ``max_shift``: the per-plot bound (m); ``search``: how far (m) a plot
    is searched for before the global correction (default 0.45 of the plot spacing).
    """
    from ..raster.geotiff import GeoTiff, open_geotiff
    prog = as_progress(progress, is_cancelled)
    tif = orthomosaic if isinstance(orthomosaic, GeoTiff) else open_geotiff(str(orthomosaic), crs=crs)
    rings = [np.asarray(r, float)[:, :2] for r in rings]
    if not rings:
        raise EasyIDPError("Plot grid: the grid has no plots.")
    if index == "auto":
        if tif.kind in ("rgb", "rgba") or (bands is not None and len(bands) == 3):
            index = "exg"
        elif bands is not None and len(bands) == 2:
            index = "ndvi"
        else:
            raise EasyIDPError(f"Orthomosaic {tif.path}: a {tif.bands}-band raster is not RGB: "
                               "choose the NDVI index and give the red and NIR band numbers.")
    if index not in ("exg", "ndvi"):
        raise EasyIDPError(f"Vegetation index {index!r}: choose exg or ndvi.")
    if bands is None:
        if index == "ndvi":
            raise EasyIDPError("NDVI: give the band numbers of the red and the NIR bands.")
        bands = (1, 2, 3)
    need = 3 if index == "exg" else 2
    if len(bands) != need or any(not 1 <= int(b) <= tif.bands for b in bands):
        raise EasyIDPError(f"Band numbers {list(bands)}: {index.upper()} needs {need} band "
                           f"numbers between 1 and {tif.bands} (the orthomosaic's bands).")
    bands = [int(b) - 1 for b in bands]

    # --- plot geometry in the grid frame
    alpha = _grid_axis(rings)
    ux = np.array([math.cos(alpha), math.sin(alpha)])
    uy = np.array([ux[1], -ux[0]])
    axes = np.array([ux, uy])
    centres = np.array([_centroid(r) for r in rings])
    half = np.array([[np.abs((r - c) @ ux).max(), np.abs((r - c) @ uy).max()]
                     for r, c in zip(rings, centres)])
    size = 2 * np.median(half, axis=0)
    cu, cv = centres @ ux, centres @ uy
    pitch = np.array([_pitch(cu, size[0] / 2), _pitch(cv, size[1] / 2)])
    gap = np.where(np.isfinite(pitch), pitch - size, np.inf)
    margin = np.clip(np.where(np.isfinite(gap), 0.5 * gap, max(max_shift, 0.1)), 0, None)
    margin = np.minimum(margin, max(max_shift, 0.05) + 0.1)
    reach = np.where(np.isfinite(pitch), 0.45 * pitch, 0.45 * size + 1.0)
    if search is not None:
        reach = np.minimum(reach, search) if search > 0 else reach
    c0 = centres.mean(axis=0)

    # --- the vegetation image
    grow = float(reach.max() + margin.max() + half.max())
    xs = np.concatenate([r[:, 0] for r in rings])
    ys = np.concatenate([r[:, 1] for r in rings])
    bbox = (xs.min() - grow, ys.min() - grow, xs.max() + grow, ys.max() + grow)
    work, k = _read_work(tif, bbox, index, bands, prog.sub(0, 70), workers)
    soil, leaf = _weights(work)
    notes = [f"Vegetation index {index.upper()} averaged over {k}×{k} pixels "
             f"({work.px:.3f} m); soil {soil:.3f}, leaf {leaf:.3f}."]
    if np.isfinite(pitch).all() and (gap < 2 * work.px).any():
        notes.append("The plots touch (no gap between them along an axis): the per-plot fit "
                     "cannot tell a plot from its neighbour there and is weak.")
    prog.check()

    # --- crop rows and the first rotation
    rows = _rows_spectrum(work, c0, 0.5 * size.min())
    theta0, row_bearing, row_spacing = 0.0, None, None
    if rows is not None and rows[2] > 20:
        direction, row_spacing, _ = rows
        row_bearing = math.degrees(math.atan2(math.cos(direction), math.sin(direction))) % 180.0
        d = (direction - alpha + math.pi / 4) % (math.pi / 2) - math.pi / 4
        theta0 = d
        notes.append(f"Crop rows: bearing {row_bearing:.2f}°, spacing {row_spacing:.3f} m "
                     f"(spectrum peak {rows[2]:.0f}× the median).")
    else:
        notes.append("No crop-row pattern found in the spectrum: the rotation comes from the plot "
                     "positions only.")

    n = len(rings)

    def measure(pred, R_use, reach_use, use_box=True):
        rot_axes = (R_use @ axes.T).T
        pl = _Plot(work, rot_axes, half)
        out = np.empty_like(pred)
        for i in range(n):
            if i % 64 == 0:
                prog.check()
            c = pred[i]
            if use_box:
                c = c + pl.box_search(c, half[i], reach_use)
            out[i] = pl.centre_on_rows(c, half[i], margin)
        return out, pl

    def covers(pos, pl):
        return np.array([pl.score(pos[i], half[i], margin) for i in range(n)])

    # pass A: from the first rotation
    R0 = _rot(theta0)
    pred = c0 + (centres - c0) @ R0.T
    meas, pl = measure(pred, R0, reach)
    prog.set(80)
    sc = covers(meas, pl)
    good = sc[:, 1] >= min_cover * np.median(sc[:, 1])
    theta, scale, t, M = theta0, (1.0, 1.0), np.zeros(2), R0
    for reach_next in (0.2 * np.where(np.isfinite(pitch), pitch, size), None):
        ok = good.copy()
        for _ in range(3):
            if ok.sum() < 3:
                raise EasyIDPError("Plot grid: fewer than three plots have crop where the grid "
                                   "puts them: check that the grid belongs to this orthomosaic "
                                   "and that the crop is visible (or lower the cover threshold).")
            theta, scale, t, M = _similarity(centres, meas, ok, c0, axes)
            res = np.hypot(*(meas - (c0 + t + (centres - c0) @ M.T)).T)
            lim = max(3 * np.median(res[ok]), 2 * work.px, 0.02)
            new_ok = good & (res <= lim)
            if (new_ok == ok).all():
                break
            ok = new_ok
        if reach_next is None:
            break
        pred = c0 + t + (centres - c0) @ M.T
        Rt = _rot(theta)
        meas, pl = measure(pred, Rt, reach_next)
        sc = covers(meas, pl)
        good = sc[:, 1] >= min_cover * np.median(sc[:, 1])
    prog.set(90)

    # per plot, from the global correction
    Rt = _rot(theta)
    pred = c0 + t + (centres - c0) @ M.T
    meas, pl = measure(pred, Rt, None, use_box=False)
    sc = covers(meas, pl)
    cover = sc[:, 1]
    med = float(np.median(cover))
    shift = meas - pred
    flags = []
    for i in range(n):
        if cover[i] < min_cover * med:
            flags.append(FLAG_BARE)
        elif sc[i, 0] < min_score:
            flags.append(FLAG_WEAK)
        elif math.hypot(*shift[i]) > max_shift:
            flags.append(FLAG_BOUND)
        else:
            flags.append("")
    moved = np.array([f == "" for f in flags])
    shift[~moved] = 0.0
    final = pred + shift
    score = np.array([pl.score(final[i], half[i], margin)[0] for i in range(n)])
    out_rings = [(r - centres[i]) @ Rt.T + final[i] for i, r in enumerate(rings)]
    prog.set(100)
    return FitResult(out_rings, shift, score, cover, flags, moved, math.degrees(theta),
                     scale, (float(t[0]), float(t[1])), (float(c0[0]), float(c0[1])),
                     row_bearing, row_spacing, work.px, notes, centres, final)
