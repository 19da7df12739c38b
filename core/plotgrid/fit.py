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
of a plot is how much more of the vegetation of its plot-plus-margin window lies inside it than
an even spread would put there: (f − a) / (1 − a), f the share inside, a the plot's share of the
window's area (1: all inside; 0: weeds or a crop that fills the alleys as much as the plot).
"""
import math
import os
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..errors import EasyIDPError
from ..geometry import ring_moments
from ..progress import as_progress
from ..ragged import offsets
from ..raster import GeoTiff, open_geotiff

MAX_WORK_PIXELS = 16_000_000
CENTROID_ITERATIONS = 2

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
    seconds: dict = field(default_factory=dict)     # wall time of each stage

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
        """Bilinear between pixel centres at map points; 0 outside."""
        c = (np.asarray(x, np.float64) - self.x0) * (1.0 / self.px) - 0.5
        r = (self.y0 - np.asarray(y, np.float64)) * (1.0 / self.py) - 0.5
        return self.sample_px(c.astype(np.float32), r.astype(np.float32))

    def sample_px(self, c: np.ndarray, r: np.ndarray) -> np.ndarray:
        """Bilinear at pixel-centre coordinates (column ``c``, row ``r``: the centre of pixel
        (0, 0) is (0, 0)), float32, modified in place; 0 outside. The weights are padded by
        one pixel of 0 on the first call (they are final by then)."""
        if getattr(self, "_pad", None) is None:
            self._pad = np.pad(self.w, 1)
        h, wd = self.w.shape
        c += 1.0                                     # index in the padded array
        r += 1.0
        np.clip(c, 0, wd + 0.999, out=c)
        np.clip(r, 0, h + 0.999, out=r)
        c0 = c.astype(np.int32)
        r0 = r.astype(np.int32)
        c -= c0
        r -= r0
        flat = r0
        flat *= wd + 2
        flat += c0
        f = self._pad.ravel()
        a = f[flat]
        top = f[flat + 1]
        top -= a
        top *= c
        top += a
        flat += wd + 2
        a = f[flat]
        bottom = f[flat + 1]
        bottom -= a
        bottom *= c
        bottom += a
        bottom -= top
        bottom *= r
        bottom += top
        return bottom


def _index_of(block: np.ndarray, kind: str, bands) -> np.ndarray:
    """The vegetation index of (h, w, bands) float32 pixel means."""
    eps = np.float32(1e-6)
    if kind == "exg":
        r, g, b = (block[..., i] for i in bands)
        s = r + g + b
        return (2 * g - r - b) / np.maximum(s, eps)
    red, nir = (block[..., i] for i in bands)
    return (nir - red) / np.maximum(nir + red, eps)


def _read_work(tif, bbox, kind: str, bands, prog, workers=None) -> Tuple[_Work, int]:
    """The index averaged over k × k pixels over the map ``bbox``: every tile or strip that
    meets it is decoded once (``GeoTiff.read_block``, on a pool of threads, a bounded number at
    a time) and summed into the k × k cells it covers where it was decoded; nothing is
    assembled at full resolution, so memory is the working image plus a few blocks."""
    xmin, ymin, xmax, ymax = bbox
    c_a, r_a = tif.map_to_pixel(np.array([xmin, xmax]), np.array([ymax, ymin]))
    col0, col1 = max(int(math.floor(c_a.min())), 0), min(int(math.ceil(c_a.max())), tif.width)
    row0, row1 = max(int(math.floor(r_a.min())), 0), min(int(math.ceil(r_a.max())), tif.height)
    if col1 - col0 < 2 or row1 - row0 < 2:
        raise EasyIDPError("Plot grid: the plots do not lie on the orthomosaic (check that the "
                           "grid and the orthomosaic are of the same field and in the same CRS).")
    k = max(1, int(math.ceil(math.sqrt((col1 - col0) * (row1 - row0) / MAX_WORK_PIXELS))))
    bh, bw = tif.block_height, tif.block_width
    # tiles whose side k divides, read from a tile corner: every cell lies in one tile, so each
    # tile's cells are final where it is decoded (no shared sums, no lock)
    g = math.gcd(bh, bw) if tif.tiled else 0
    aligned = next((d for d in range(k, 2 * k + 1) if g and g % d == 0), None)
    if aligned:
        k = aligned
        row0, col0 = (row0 // bh) * bh, (col0 // bw) * bw
    ncols, nrows = -(-(col1 - col0) // k), -(-(row1 - row0) // k)
    if ncols < 2 or nrows < 2:
        raise EasyIDPError("Plot grid: the plots cover less than two pixels of the orthomosaic.")
    nb = len(bands)
    if aligned:
        vi_out = np.full((nrows, ncols), np.nan, np.float32)
    else:
        sums = np.zeros((nrows, ncols, nb), np.float32)
        counts = np.zeros((nrows, ncols), np.float32)
    alpha, nodata = tif.alpha_band, tif.nodata
    small = tif.dtype == np.uint8 and k <= 16
    acc = np.uint16 if small else np.float64
    all_bands = list(bands) == list(range(tif.bands))
    lock = threading.Lock()
    # tasks: runs of up to 4096 px of tiles along a tile row (one strip for stripped rasters),
    # decoded tile by tile and reduced together, so a task makes few numpy calls: many small
    # ones per tile keep two threads waiting on each other for the GIL
    per_task = max(1, 4096 // bw)
    across = list(range(col0 // bw, (col1 - 1) // bw + 1))
    blocks = [(br, tuple(across[i:i + per_task])) for br in range(row0 // bh, (row1 - 1) // bh + 1)
              for i in range(0, len(across), per_task)]
    fd = os.open(tif.path, os.O_RDONLY)

    def cell_sums(buf):
        """Sums over k × k cells of an array whose height and width are multiples of k
        (strided adds: several times faster than ``reduceat`` or a reshaped sum)."""
        if k == 1:
            return buf.astype(acc)
        sr = np.add(buf[0::k], buf[1::k], dtype=acc)
        for i in range(2, k):
            sr += buf[i::k]
        out = np.add(sr[:, 0::k], sr[:, 1::k])
        for j in range(2, k):
            out += sr[:, j::k]
        return out

    def one(br, bcs):
        if prog.cancelled():
            return
        tiles = [tif.read_block(fd, br, bc) for bc in bcs]
        blk = tiles[0] if len(tiles) == 1 else np.concatenate(tiles, axis=1)
        del tiles
        r0, c0 = br * bh, bcs[0] * bw
        ra, rb = max(r0, row0), min(r0 + blk.shape[0], row1)
        ca, cb = max(c0, col0), min(c0 + blk.shape[1], col1)
        if rb <= ra or cb <= ca:
            return
        sub = blk[ra - r0:rb - r0, ca - c0:cb - c0]
        data = sub if all_bands else sub[..., list(bands)]
        mask = None
        if alpha is not None:
            mask = sub[..., alpha] > 0
        if nodata is not None:
            nd = np.all(data == nodata, axis=-1)
            mask = ~nd if mask is None else mask & ~nd
        if mask is not None:
            data = data * mask[..., None].astype(data.dtype)
        h, w = rb - ra, cb - ca
        off_r, off_c = (ra - row0) % k, (ca - col0) % k     # the block starts inside a cell
        H, W = -(-(off_r + h) // k) * k, -(-(off_c + w) // k) * k
        if (off_r, off_c, H, W) != (0, 0, h, w):
            buf = np.zeros((H, W, data.shape[2]), data.dtype)
            buf[off_r:off_r + h, off_c:off_c + w] = data
            data = buf
            if mask is not None:
                mb = np.zeros((H, W), bool)
                mb[off_r:off_r + h, off_c:off_c + w] = mask
                mask = mb
        part = cell_sums(data)
        i0, j0 = (ra - row0) // k, (ca - col0) // k
        whole = mask is None and off_r == 0 and off_c == 0 and H == h and W == w
        if aligned and whole:
            # every cell complete: ExG and NDVI are ratios, so the sums give the means' index
            vi_out[i0:i0 + H // k, j0:j0 + W // k] = _index_of(part.astype(np.float32), kind,
                                                               range(nb))
            return
        if mask is None:
            lr = np.full(H // k, k)
            lr[0] -= off_r
            lr[-1] -= H - off_r - h
            lc = np.full(W // k, k)
            lc[0] -= off_c
            lc[-1] -= W - off_c - w
            cnt = np.outer(lr, lc)
        else:
            cnt = cell_sums(mask[..., None])[..., 0]
        if aligned:
            with np.errstate(invalid="ignore", divide="ignore"):
                vi = _index_of(part.astype(np.float32) / cnt[..., None].astype(np.float32),
                               kind, range(nb))
            vi[cnt < 0.25 * k * k] = np.nan
            vi_out[i0:i0 + H // k, j0:j0 + W // k] = vi
            return
        with lock:
            sums[i0:i0 + H // k, j0:j0 + W // k] += part
            counts[i0:i0 + H // k, j0:j0 + W // k] += cnt

    try:
        with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 2) as pool:
            ahead = 2 * (workers or os.cpu_count() or 2)
            pending, done = set(), 0
            for br, bc in blocks:
                pending.add(pool.submit(one, br, bc))
                if len(pending) >= ahead:
                    finished, pending = wait(pending, return_when=FIRST_COMPLETED)
                    for f in finished:
                        f.result()
                    done += len(finished)
                    prog.set(100.0 * done / len(blocks))
                    prog.check()
            for f in pending:
                f.result()
    finally:
        os.close(fd)
    prog.check()
    if aligned:
        vi = vi_out
    else:
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = sums / counts[..., None]
        vi = _index_of(mean, kind, range(nb)).astype(np.float32)
        vi[counts < 0.25 * k * k] = np.nan
    x0, y0 = tif.pixel_to_map(col0, row0)
    a, e = tif.geotransform[1], tif.geotransform[5]
    return _Work(vi, float(x0), float(y0), abs(a) * k, abs(e) * k), k


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
    flat = v.ravel()[:: max(1, v.size // 1_000_000)]        # the levels from about 1 M cells
    sample = flat[np.isfinite(flat)]
    if sample.size < 16:
        raise EasyIDPError("Plot grid: the orthomosaic has no valid pixels under the plots.")
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

def _centroids(rings: Sequence[np.ndarray]) -> np.ndarray:
    """Area centroids (R, 2) of the plot rings; a ring without area gives its vertex mean."""
    area, moment = ring_moments(np.concatenate(rings), offsets([len(r) for r in rings]))
    flat = np.abs(area) < 1e-12
    with np.errstate(invalid="ignore", divide="ignore"):
        centres = moment / area[:, None]
    for i in np.flatnonzero(flat):
        centres[i] = rings[i].mean(axis=0)
    return centres


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


# ---- measuring plots, many at a time --------------------------------------------------------

BATCH_SAMPLES = 1_000_000      # samples per batch of plots (memory: a few × 4 MB per thread)


class _Measure:
    """Plots of one size (``half``: half sizes along the frame's axes) on the weights, in a
    frame turned by ``axes`` (rows: unit x, unit y on the map)."""

    def __init__(self, work: _Work, axes: np.ndarray, half: np.ndarray, margin: np.ndarray,
                 prog, pool=None):
        self.work, self.axes, self.half, self.margin, self.prog = work, axes, half, margin, prog
        self.step = min(work.px, work.py)
        self.pool = pool

    def _lattice(self, ext, step=None):
        s = step or self.step
        nu, nv = max(int(math.ceil(2 * ext[0] / s)), 2), max(int(math.ceil(2 * ext[1] / s)), 2)
        u = ((np.arange(nu) + 0.5) * (2 * ext[0] / nu) - ext[0]).astype(np.float64)
        v = ((np.arange(nv) + 0.5) * (2 * ext[1] / nv) - ext[1]).astype(np.float64)
        return u, v

    def _sample(self, centres, u, v):
        """(m, nv, nu) weights at the lattice around each centre."""
        wk, ax = self.work, self.axes
        cc = ((centres[:, 0] - wk.x0) / wk.px - 0.5).astype(np.float32)
        cr = ((wk.y0 - centres[:, 1]) / wk.py - 0.5).astype(np.float32)
        du = (u[None, :] * (ax[0, 0] / wk.px) + v[:, None] * (ax[1, 0] / wk.px)).astype(np.float32)
        dv = (u[None, :] * (-ax[0, 1] / wk.py) + v[:, None] * (-ax[1, 1] / wk.py)).astype(np.float32)
        return wk.sample_px(cc[:, None, None] + du[None], cr[:, None, None] + dv[None])

    def _each(self, n, per_plot, fn) -> None:
        """``fn(slice)`` over batches of the n plots, on the pool's threads (numpy's gathers
        and reductions release the GIL); the batches write disjoint rows of the outputs."""
        b = max(1, BATCH_SAMPLES // max(per_plot, 1))
        slices = [slice(i, min(n, i + b)) for i in range(0, n, b)]

        def run(sl):
            self.prog.check()
            fn(sl)
        if self.pool is None or len(slices) < 2:
            for sl in slices:
                run(sl)
        else:
            for _ in self.pool.map(run, slices):
                pass

    def box_search(self, centres, reach) -> np.ndarray:
        """Offsets (map, (m, 2)) of the box of the plot's size holding the most vegetation
        within ``reach`` (u, v) of each centre: the middle of the positions within 0.5 % of the
        best (the box slides over a plateau while the crop, narrower than the plot, is inside)."""
        # a coarse lattice: the search only has to bring the crop inside the centroid window
        u, v = self._lattice(self.half + reach, max(self.step, float(min(self.half)) / 8))
        du, dv = u[1] - u[0], v[1] - v[0]
        bu = max(int(round(2 * self.half[0] / du)), 1)
        bv = max(int(round(2 * self.half[1] / dv)), 1)
        out = np.zeros((len(centres), 2))
        if bu >= len(u) or bv >= len(v):
            return out
        def batch(sl):
            S = self._sample(centres[sl], u, v).astype(np.float64)
            I = np.zeros((S.shape[0], S.shape[1] + 1, S.shape[2] + 1))
            I[:, 1:, 1:] = S.cumsum(1).cumsum(2)
            box = I[:, bv:, bu:] - I[:, :-bv, bu:] - I[:, bv:, :-bu] + I[:, :-bv, :-bu]
            best = box.max(axis=(1, 2))
            top = box >= (best * 0.995)[:, None, None]
            cnt = top.sum(axis=(1, 2))
            jj = (top.sum(axis=2) * np.arange(top.shape[1])).sum(axis=1) / cnt
            ii = (top.sum(axis=1) * np.arange(top.shape[2])).sum(axis=1) / cnt
            ou = u[0] - du / 2 + (ii + bu / 2) * du
            ov = v[0] - dv / 2 + (jj + bv / 2) * dv
            ok = best > 0
            out[sl] = np.where(ok[:, None], ou[:, None] * self.axes[0] + ov[:, None] * self.axes[1],
                               0.0)
        self._each(len(centres), len(u) * len(v), batch)
        return out

    def centre_on_rows(self, centres, iterations: int = CENTROID_ITERATIONS, coarse: int = 1):
        """(centres, scores): each plot moved to the vegetation centroid in the plot grown by the
        margin, the window recentred ``iterations`` times; the scores as :meth:`score`, from
        the last window (centred where the last move started)."""
        u, v = self._lattice(self.half + self.margin, self.step * coarse)
        inside = (np.abs(v)[:, None] <= self.half[1]) & (np.abs(u)[None, :] <= self.half[0])
        c = np.array(centres, float)
        sc = np.zeros((len(c), 2))
        def batch(sl):
            cs = c[sl]
            for _ in range(iterations):
                S = self._sample(cs, u, v)
                tot = S.sum(axis=(1, 2), dtype=np.float64)
                mu = (S.sum(axis=1, dtype=np.float64) @ u) / np.maximum(tot, 1e-12)
                mv = (S.sum(axis=2, dtype=np.float64) @ v) / np.maximum(tot, 1e-12)
                move = np.where((tot > 0)[:, None], mu[:, None] * self.axes[0] +
                                mv[:, None] * self.axes[1], 0.0)
                cs = cs + move
            ins = (S * inside).sum(axis=(1, 2), dtype=np.float64)
            sc[sl, 0] = _containment(ins, tot, inside)
            sc[sl, 1] = ins / max(int(inside.sum()), 1)
            c[sl] = cs
        self._each(len(c), len(u) * len(v), batch)
        return c, sc

    def score(self, centres) -> np.ndarray:
        """(m, 2): the share of the vegetation of the grown window inside the plot, and the
        plot's mean vegetation weight (its cover)."""
        u, v = self._lattice(self.half + self.margin)
        inside = (np.abs(v)[:, None] <= self.half[1]) & (np.abs(u)[None, :] <= self.half[0])
        out = np.zeros((len(centres), 2))
        def batch(sl):
            S = self._sample(np.asarray(centres[sl], float), u, v)
            tot = S.sum(axis=(1, 2), dtype=np.float64)
            ins = (S * inside).sum(axis=(1, 2), dtype=np.float64)
            out[sl, 0] = _containment(ins, tot, inside)
            out[sl, 1] = ins / max(int(inside.sum()), 1)
        self._each(len(centres), len(u) * len(v), batch)
        return out


def _containment(ins, tot, inside) -> np.ndarray:
    """The fit score: how much more of the window's vegetation is inside the plot than if it
    were spread evenly (0: even, as weeds or a crop that fills the alleys; 1: all inside)."""
    share = inside.mean()
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(tot > 0, ins / np.maximum(tot, 1e-12), 0.0)
    return np.clip((frac - share) / (1 - share), 0.0, 1.0) if share < 1 else frac


def _groups(half: np.ndarray):
    """Indices of the plots of each size (half sizes to the millimetre)."""
    keys = {}
    for i, h in enumerate(np.round(half, 3)):
        keys.setdefault((h[0], h[1]), []).append(i)
    return [np.array(v) for v in keys.values()]


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
    prog = as_progress(progress, is_cancelled)
    tif = orthomosaic if isinstance(orthomosaic, GeoTiff) else open_geotiff(str(orthomosaic), crs=crs)
    rings = [np.asarray(r, float)[:, :2] for r in rings]
    if len(rings) < 3:
        raise EasyIDPError(f"Plot grid: {len(rings)} plots; the fit needs at least three (it "
                           "estimates the grid's rotation, spacing and shift from them).")
    if index == "auto":
        if tif.kind in ("rgb", "rgba") or tif.is_colour or (bands is not None and len(bands) == 3):
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
    centres = _centroids(rings)
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
    clock = [time.perf_counter()]
    seconds = {}

    def lap(name):
        now = time.perf_counter()
        seconds[name] = now - clock[0]
        clock[0] = now

    work, k = _read_work(tif, bbox, index, bands, prog.sub(0, 70), workers)
    lap("read")
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

    lap("weights and crop rows")
    with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 2) as pool:
        n = len(rings)
        groups = _groups(half)

        def measure(pred, R_use, reach_use, iterations, coarse=1):
            """(centres, scores) found around ``pred`` (a box search within ``reach_use`` when
            given, then the centroid), in the frame turned by ``R_use``."""
            rot_axes = (R_use @ axes.T).T
            out, sc = np.empty_like(pred), np.empty((n, 2))
            for idx in groups:
                m = _Measure(work, rot_axes, half[idx[0]], margin, prog, pool)
                c = pred[idx]
                if reach_use is not None:
                    c = c + m.box_search(c, reach_use)
                out[idx], sc[idx] = m.centre_on_rows(c, iterations, coarse)
            return out, sc

        def scores(pos, R_use):
            rot_axes = (R_use @ axes.T).T
            out = np.empty((n, 2))
            for idx in groups:
                out[idx] = _Measure(work, rot_axes, half[idx[0]], margin, prog, pool).score(pos[idx])
            return out

        # pass A: from the first rotation, searched; pass B: from the global fit of pass A
        R0 = _rot(theta0)
        pred = c0 + (centres - c0) @ R0.T
        # passes A and B only feed the global fit (many plots): a lattice twice as coarse will do
        meas, sc = measure(pred, R0, reach, 1, coarse=2)
        lap("search")
        prog.set(80)
        good = sc[:, 1] >= min_cover * np.median(sc[:, 1])
        theta, scale, t, M = theta0, (1.0, 1.0), np.zeros(2), R0
        for again in (True, False):
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
            if not again:
                break
            pred = c0 + t + (centres - c0) @ M.T
            meas, sc = measure(pred, _rot(theta), None, 1, coarse=2)
            good = sc[:, 1] >= min_cover * np.median(sc[:, 1])
        lap("global fit")
        prog.set(90)

        # per plot, from the global correction
        Rt = _rot(theta)
        pred = c0 + t + (centres - c0) @ M.T
        # from where pass B found each plot (its crop is inside the window by then), on the fine
        # lattice; plots pass B saw no crop in start from the prediction
        start = np.where((sc[:, 1] > 0)[:, None], meas, pred)
        meas, sc = measure(start, Rt, None, 1)
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
        score = sc[:, 0].copy()
        if (~moved).any():
            score[~moved] = scores(final, Rt)[~moved, 0]
    out_rings = [(r - centres[i]) @ Rt.T + final[i] for i, r in enumerate(rings)]
    lap("per plot")
    prog.set(100)
    return FitResult(out_rings, shift, score, cover, flags, moved, math.degrees(theta),
                     scale, (float(t[0]), float(t[1])), (float(c0[0]), float(c0[1])),
                     row_bearing, row_spacing, work.px, notes, centres, final, seconds)
