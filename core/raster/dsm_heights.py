"""Heights for ROIs from a DSM GeoTIFF: per vertex, or one statistic per polygon.

Heights are in the DSM's own vertical reference and units. Nodata pixels are ignored; a vertex
or polygon without any valid pixel gets NaN and is reported, never 0.
"""
import numpy as np

from ..errors import InputError
from ..heights import HeightResult, check_heights_args, statistic_of, vertex_result
from ..progress import as_progress
from ..roi import ROI, ROISet
from .geotiff import GeoTiff, open_geotiff
from .roi_pixels import NO_PIXEL, place_rois, require_overlap, rois_in_raster_crs
from .sweep import Window, sweep_windows

SAMPLING = ("nearest", "bilinear")
SAMPLE_CELL = 256  # pixels: points are read from the DSM in windows of at most this size (+1)

def _valid(tif: GeoTiff, arr: np.ndarray) -> np.ndarray:
    ok = np.isfinite(arr) if arr.dtype.kind == "f" else np.ones(arr.shape, bool)
    if tif.nodata is not None:
        ok &= arr != np.asarray(tif.nodata, dtype=arr.dtype)
    return ok


def _single_band(tif: GeoTiff) -> None:
    if tif.bands != 1:
        raise InputError(f"The DSM {tif.path} has {tif.bands} bands; a DSM must have exactly one "
                         "(heights). Choose the elevation raster.")


def sample_points(dsm, x: np.ndarray, y: np.ndarray, method: str = "bilinear", progress=None,
                  is_cancelled=None) -> np.ndarray:
    """DSM heights at map points (x, y) in the DSM's CRS; NaN outside the raster or on nodata.

    ``nearest``: the pixel containing the point. ``bilinear``: interpolation between the four
    nearest pixel centres, with the weights of nodata neighbours dropped (NaN if all are nodata).
    ``dsm`` is a path or an opened :class:`GeoTiff`. Points are read in groups (one window per
    occupied cell of ``SAMPLE_CELL`` pixels), so millions of dense points (a point cloud's
    ground) cost one read of the pixels under them, not one window each.
    """
    if method not in SAMPLING:
        raise ValueError(f"sampling must be one of {SAMPLING}, not {method!r}")
    tif = dsm if isinstance(dsm, GeoTiff) else open_geotiff(dsm)
    _single_band(tif)
    col, row = tif.map_to_pixel(np.ravel(x), np.ravel(y))
    col, row = np.asarray(col, np.float64), np.asarray(row, np.float64)
    out = np.full(col.shape, np.nan)
    inside = (col >= 0) & (col <= tif.width) & (row >= 0) & (row <= tif.height)
    idx = np.flatnonzero(inside)
    if not len(idx):
        return out.reshape(np.shape(x))
    if method == "nearest":  # the pixel containing the point (the last one on the far edges)
        c0 = np.clip(np.floor(col[idx]), 0, tif.width - 1).astype(np.int64)
        r0 = np.clip(np.floor(row[idx]), 0, tif.height - 1).astype(np.int64)
        span = 1
    else:  # the 2 x 2 pixel centres around the point; those outside the raster get no weight
        c0 = np.floor(col[idx] - 0.5).astype(np.int64)
        r0 = np.floor(row[idx] - 0.5).astype(np.int64)
        span = 2
    # one window per occupied cell: the pixels under that cell's points, clipped to the raster
    cell = (r0 // SAMPLE_CELL) * (tif.width // SAMPLE_CELL + 2) + (c0 // SAMPLE_CELL)
    order = np.argsort(cell, kind="stable")
    bounds = np.flatnonzero(np.diff(cell[order])) + 1
    groups = np.split(order, bounds)
    windows = []
    for g in groups:
        wr0, wc0 = max(int(r0[g].min()), 0), max(int(c0[g].min()), 0)
        wr1 = min(int(r0[g].max()) + span, tif.height)
        wc1 = min(int(c0[g].max()) + span, tif.width)
        windows.append(Window(wr0, wc0, wr1 - wr0, wc1 - wc0))

    def consume(k: int, arr: np.ndarray) -> None:
        g, w = groups[k], windows[k]
        vals = arr[..., 0]
        ok_px = _valid(tif, vals)
        total = np.zeros(len(g))
        weight = np.zeros(len(g))
        if method == "nearest":
            offsets = [(0, 0, np.ones(len(g)))]
        else:
            fc = col[idx[g]] - 0.5 - c0[g]
            fr = row[idx[g]] - 0.5 - r0[g]
            offsets = [(0, 0, (1 - fr) * (1 - fc)), (0, 1, (1 - fr) * fc),
                       (1, 0, fr * (1 - fc)), (1, 1, fr * fc)]
        for dr, dc, wt in offsets:
            r, c = r0[g] + dr - w.row, c0[g] + dc - w.col
            there = (r >= 0) & (r < w.rows) & (c >= 0) & (c < w.cols)
            rc, cc = np.where(there, r, 0), np.where(there, c, 0)
            ok = there & ok_px[rc, cc]
            wt = np.where(ok, wt, 0.0)
            total += wt * np.where(ok, vals[rc, cc].astype(np.float64), 0.0)
            weight += wt
        if method == "nearest":
            out[idx[g]] = np.where(weight > 0, total, np.nan)
        else:
            with np.errstate(invalid="ignore", divide="ignore"):
                out[idx[g]] = np.where(weight > 0, total / np.where(weight > 0, weight, 1), np.nan)

    prog = as_progress(progress, is_cancelled)
    keep = [k for k, w in enumerate(windows) if w.rows > 0 and w.cols > 0]
    if keep:
        groups = [groups[k] for k in keep]
        windows = [windows[k] for k in keep]
        sweep_windows(tif, windows, consume, prog)
    return out.reshape(np.shape(x))


def roi_heights(dsm, rois: ROISet, mode: str = "polygon", statistic: str = "mean",
                percentile: float = 50.0, buffer: float = 0.0, sampling: str = "bilinear",
                dsm_crs=None, progress=None, is_cancelled=None) -> HeightResult:
    """Heights of ROIs from a DSM (a path or an opened :class:`GeoTiff`).

    ``mode="vertex"``: the DSM sampled at every vertex (``sampling`` nearest or bilinear); with
    ``buffer`` > 0, the ``statistic`` of the valid pixels whose centres lie within ``buffer``
    (map units of the DSM CRS) of the vertex instead.
    ``mode="polygon"``: the ``statistic`` (see :mod:`..heights`) of the valid pixels whose
    centres are inside the polygon grown (``buffer`` > 0) or shrunk (< 0) by ``buffer``. ROIs in
    another CRS are reprojected to the DSM's for sampling; vertex heights stay aligned with the
    ROIs' own vertices.
    """
    mode = check_heights_args(mode, statistic, percentile)
    prog = as_progress(progress, is_cancelled)
    tif = dsm if isinstance(dsm, GeoTiff) else open_geotiff(dsm, crs=dsm_crs)
    _single_band(tif)
    local = rois_in_raster_crs(rois, tif)
    if mode == "vertex":
        xy = np.concatenate([r for roi in local for r in roi.rings])
        z = vertex_heights(tif, xy[:, 0], xy[:, 1], sampling, buffer, statistic, percentile, prog)
        result = vertex_result(z, local, "some vertices fall outside the DSM or on nodata")
        result.notes.extend(tif.notes)
        return result
    placed, skipped = place_rois(tif, local, buffer=buffer)
    require_overlap(placed, skipped, local, tif)
    result = HeightResult("polygon", [np.nan] * len(local), dict(skipped), list(tif.notes))

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        a = arr[..., 0]
        mask = p.mask()
        sel = mask & _valid(tif, a)
        if sel.any():
            result.values[p.index] = statistic_of(a[sel], statistic, percentile)
        elif not mask.any():
            result.missing[p.index] = NO_PIXEL if p.buffer >= 0 else (
                f"the buffer of {p.buffer:g} (DSM map units) shrinks it to nothing: it is "
                f"narrower than {-2 * p.buffer:g}; use a smaller negative buffer")
        else:
            result.missing[p.index] = "all DSM pixels inside it are nodata"

    sweep_windows(tif, [p.window for p in placed], consume, prog)
    return result


def vertex_heights(dsm, x: np.ndarray, y: np.ndarray, sampling: str = "bilinear",
                   buffer: float = 0.0, statistic: str = "mean", percentile: float = 50.0,
                   progress=None, is_cancelled=None) -> np.ndarray:
    """Heights at points (x, y) in the DSM CRS: sampled (``buffer`` <= 0), or the ``statistic``
    of the valid pixels whose centres lie within ``buffer`` map units of each point. NaN where
    there is no valid pixel."""
    tif = dsm if isinstance(dsm, GeoTiff) else open_geotiff(dsm)
    prog = as_progress(progress, is_cancelled)
    if buffer <= 0:
        return sample_points(tif, x, y, sampling, prog)
    _single_band(tif)
    x, y = np.ravel(np.asarray(x, float)), np.ravel(np.asarray(y, float))
    t = np.linspace(0, 2 * np.pi, 33)[:-1]
    grow = buffer / np.cos(np.pi / 32)  # polygon circumscribing the disc
    discs = [ROI(str(k), [[np.column_stack([xk + grow * np.cos(t), yk + grow * np.sin(t)])]])
             for k, (xk, yk) in enumerate(zip(x, y))]
    placed, _ = place_rois(tif, ROISet(discs, None))
    out = np.full(x.shape, np.nan)

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        w = p.window
        cc, rr = np.meshgrid(np.arange(w.cols) + w.col + 0.5, np.arange(w.rows) + w.row + 0.5)
        mx, my = tif.pixel_to_map(cc, rr)
        a = arr[..., 0]
        sel = (np.hypot(mx - x[p.index], my - y[p.index]) <= buffer) & _valid(tif, a)
        if sel.any():
            out[p.index] = statistic_of(a[sel], statistic, percentile)

    if placed:
        sweep_windows(tif, [p.window for p in placed], consume, prog)
    return out
