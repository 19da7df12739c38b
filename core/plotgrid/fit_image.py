"""The plot-grid fit's vegetation image: the orthomosaic under the plots read once
(``core.raster.sweep``), averaged over k × k pixels as it arrives, turned into a vegetation
index (``core.indices``: ExG of RGB, NDVI of red and NIR) and then into a weight in [0, 1]
between the soil and leaf levels that Otsu's threshold (``core.indices.otsu_threshold``)
separates.

The working image (:class:`VegetationImage`) has at most :data:`MAX_WORK_PIXELS` pixels whatever
the raster's size: pixel centre (r, c) lies at map ``x0 + (c + 0.5)·px``, ``y0 − (r + 0.5)·py``.
"""
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from .. import indices
from ..errors import EasyIDPError
from ..raster.sweep import Window, sweep_windows

MAX_WORK_PIXELS = 16_000_000
STRIP_ROWS = 512          # raster rows per window of the sweep (rounded to a multiple of k)


class VegetationImage:
    """Vegetation weights ``w`` (rows, cols) float32 on the working grid (see the module)."""

    def __init__(self, w, x0, y0, px, py):
        self.w, self.x0, self.y0, self.px, self.py = w, x0, y0, px, py
        self._pad = None

    def sample_px(self, c: np.ndarray, r: np.ndarray) -> np.ndarray:
        """Bilinear at pixel-centre coordinates (column ``c``, row ``r``: the centre of pixel
        (0, 0) is (0, 0)), float32, ``c`` and ``r`` modified in place; 0 outside."""
        if self._pad is None:
            self._pad = np.pad(self.w, 1)
        h, wd = self.w.shape
        c += 1.0
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

    def sample_frame(self, centres: np.ndarray, axes: np.ndarray, u: np.ndarray,
                     v: np.ndarray) -> np.ndarray:
        """(m, len(v), len(u)) weights at ``centre + u·axes[0] + v·axes[1]`` (map metres)."""
        cc = ((centres[:, 0] - self.x0) / self.px - 0.5).astype(np.float32)
        cr = ((self.y0 - centres[:, 1]) / self.py - 0.5).astype(np.float32)
        du = (u[None, :] * (axes[0, 0] / self.px) + v[:, None] * (axes[1, 0] / self.px))
        dv = (u[None, :] * (-axes[0, 1] / self.py) + v[:, None] * (-axes[1, 1] / self.py))
        return self.sample_px(cc[:, None, None] + du.astype(np.float32)[None],
                              cr[:, None, None] + dv.astype(np.float32)[None])


def read_vegetation(tif, bbox, kind: str, bands: Sequence[int], prog,
                    workers: Optional[int] = None) -> Tuple[VegetationImage, int, dict]:
    """(image, k, levels) of the index ``kind`` ("exg" or "ndvi"; ``bands`` 0-based, red,
    green, blue or red, nir) over the map ``bbox``, averaged over k × k pixels, as weights;
    ``levels``: soil, leaf and Otsu's threshold of the index. Pixels under alpha 0 or equal to
    the nodata value in every band are left out of the means (a cell with under a quarter of
    its pixels valid is NaN, weight 0)."""
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
    col1, row1 = col0 + ncols * k, row0 + nrows * k
    step = max(k, (STRIP_ROWS // k) * k)
    windows = [Window(r, col0, min(step, row1 - r), col1 - col0) for r in range(row0, row1, step)]
    vi = np.full((nrows, ncols), np.nan, np.float32)
    names = ["red", "green", "blue"] if kind == "exg" else ["red", "nir"]
    alpha, nodata = tif.alpha_band, tif.nodata
    # 8-bit sums of up to 16 × 16 pixels fit 16 bits: half the memory traffic of 32
    acc = (np.uint16 if k <= 16 else np.uint32) if tif.dtype == np.uint8 else np.float64
    all_bands = list(bands) == list(range(tif.bands))

    def cell_sums(buf):
        """Sums over k × k cells (strided adds: faster than a reshaped sum)."""
        if k == 1:
            return buf.astype(acc)
        sr = np.add(buf[0::k], buf[1::k], dtype=acc)
        for i in range(2, k):
            sr += buf[i::k]
        out = np.add(sr[:, 0::k], sr[:, 1::k])
        for j in range(2, k):
            out += sr[:, j::k]
        return out

    def consume(i, arr):
        data = arr if all_bands else arr[..., list(bands)]
        mask = None
        if alpha is not None:
            mask = arr[..., alpha] > 0
        if nodata is not None:
            nd = np.all(data == nodata, axis=-1)
            mask = ~nd if mask is None else mask & ~nd
        if mask is not None:
            data = data * mask[..., None].astype(data.dtype)
        sums = cell_sums(data)
        h, w = sums.shape[:2]
        vals = indices.compute(kind, sums.reshape(-1, len(bands)).T, names,
                               dtype=np.float32).reshape(h, w)
        if mask is not None:
            cnt = cell_sums(mask[..., None].astype(np.uint8))[..., 0]
            vals[cnt < 0.25 * k * k] = np.nan
        r = (windows[i].row - row0) // k
        vi[r:r + h] = vals

    sweep_windows(tif, windows, consume, prog, workers)
    prog.check()
    levels = _levels(vi, kind)
    w = vi
    np.subtract(w, levels["soil"], out=w)
    w *= 1.0 / (levels["leaf"] - levels["soil"])
    np.clip(w, 0, 1, out=w)
    w[~np.isfinite(w)] = 0
    x0, y0 = tif.pixel_to_map(col0, row0)
    a, e = tif.geotransform[1], tif.geotransform[5]
    return VegetationImage(w, float(x0), float(y0), abs(a) * k, abs(e) * k), k, levels


NO_VEGETATION = ("Plot grid: there is no vegetation on the orthomosaic under the plots to fit "
                 "the grid to ({why}); nothing was fitted and the grid is left as it is. Check "
                 "that the orthomosaic shows the crop (an image from before emergence or after "
                 "harvest has none), and the index and bands.")


def _levels(vi: np.ndarray, kind: str) -> dict:
    """Soil and leaf levels of the index: the medians of the values under and over Otsu's
    threshold (from about 1 M cells)."""
    flat = vi.ravel()[:: max(1, vi.size // 1_000_000)]
    sample = flat[np.isfinite(flat)]
    if sample.size < 16:
        raise EasyIDPError("Plot grid: the orthomosaic has no valid pixels under the plots.")
    counts = np.zeros(indices.INDEX_BINS, np.int64)
    indices.add_histogram(counts, indices.index_histogram(kind, sample))
    t = indices.otsu_threshold(kind, counts)
    if t is None:
        raise EasyIDPError(NO_VEGETATION.format(why=f"{kind.upper()} is the same everywhere"))
    lo = float(np.median(sample[sample < t])) if np.any(sample < t) else float(sample.min())
    hi = float(np.median(sample[sample >= t])) if np.any(sample >= t) else float(sample.max())
    # vegetation is ExG ≳ 0.1 (NDVI ≳ 0.3) over a soil level at least that much lower
    floor = 0.1 if kind == "exg" else 0.3
    if not (hi > floor and hi - lo > 0.5 * floor):
        raise EasyIDPError(NO_VEGETATION.format(
            why=f"the greenest part has {kind.upper()} {hi:.3f}, the rest {lo:.3f}"))
    return {"soil": lo, "leaf": hi, "threshold": float(t)}
