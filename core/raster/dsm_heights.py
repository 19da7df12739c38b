"""ROI heights from a DSM: per vertex, or one statistic per polygon (the vocabulary of modes
and statistics: :mod:`core.height_statistics`).

Heights are in the DSM's own vertical reference and units. Nodata pixels are ignored; a vertex
or polygon without any valid pixel gets NaN and is reported, never 0.
"""
import numpy as np

from ..deprecation import renamed_parameters
from ..height_statistics import (HeightResult, check_heights_args, statistic_of, statistics_of,
                                 vertex_result)
from ..progress import as_progress
from ..roi import ROI, ROISet
from .dsm import as_dsm, valid_heights
from .roi_pixels import NO_PIXEL, place_rois, require_overlap, rois_in_raster_crs, span_pixels
from .sweep import sweep_windows

STATS_BATCH = 512     # ROIs whose pixels wait for their statistics (one numpy pass per batch)
PIXEL_CHUNK = 4096    # ROIs whose pixel indices are listed at once (roi_pixels.span_pixels)


@renamed_parameters(dsm_crs="source_crs")
def dsm_roi_heights(dsm, rois: ROISet, mode: str = "polygon", statistic: str = "mean",
                    percentile: float = 50.0, buffer: float = 0.0, sampling: str = "bilinear",
                    source_crs=None, progress=None, is_cancelled=None) -> HeightResult:
    """Heights of ROIs from a DSM, per vertex or one statistic per polygon.

    Heights are in the DSM's own vertical reference and units. ROIs in another CRS are
    reprojected to the DSM's for sampling; vertex heights stay aligned with the ROIs' own
    vertices. Pixels, CRS and heights follow the
    [Conventions](../background/conventions.md).

    Parameters
    ----------
    dsm : DSM, GeoTiff or path
        The DSM (a :class:`~.dsm.DSM`, an opened :class:`GeoTiff` or a GeoTIFF path).
    rois : ROISet
        The ROIs.
    mode : {"polygon", "vertex"}
        ``"vertex"``: the DSM sampled at every vertex (with ``sampling``); with ``buffer`` > 0,
        the ``statistic`` of the valid pixels whose centres lie within ``buffer`` of the vertex
        instead. ``"polygon"``: the ``statistic`` of the valid pixels whose centres are inside
        the polygon grown (``buffer`` > 0) or shrunk (< 0) by ``buffer``. EasyIDP's ``"point"``
        and ``"face"`` also work.
    statistic : str
        ``mean``, ``median``, ``min``, ``max``, ``std``, ``percentile``, ``pmin`` or ``pmax``
        (:mod:`core.height_statistics`).
    percentile : float
        The percentile (0–100) for ``statistic="percentile"``.
    buffer : float
        Map units of the DSM's CRS (see ``mode``).
    sampling : {"bilinear", "nearest"}
        How a vertex is sampled when ``buffer`` <= 0.
    source_crs : CRS, optional
        The CRS to assume for the DSM, instead of the one its GeoKeys give.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    HeightResult
        One value per ROI (per vertex in ``"vertex"`` mode), in the ROI order; NaN where no
        valid pixel is found, with the reason in ``missing``, never 0.
    """
    mode = check_heights_args(mode, statistic, percentile)
    prog = as_progress(progress, is_cancelled)
    dsm = as_dsm(dsm, source_crs)
    tif = dsm.tif
    local = rois_in_raster_crs(rois, tif)
    if mode == "vertex":
        xy = np.concatenate([r for roi in local for r in roi.rings])
        z = vertex_heights(dsm, xy[:, 0], xy[:, 1], sampling, buffer, statistic, percentile, prog)
        result = vertex_result(z, local, "some vertices fall outside the DSM or on nodata")
        result.notes.extend(tif.notes)
        return result
    placed, skipped = place_rois(tif, local, buffer=buffer)
    require_overlap(placed, skipped, local, tif)
    result = HeightResult("polygon", [np.nan] * len(local), dict(skipped), list(tif.notes))

    pending = {}         # ROI index → its valid pixels, their statistics taken in batches

    def flush() -> None:
        for i, v in zip(pending, statistics_of(list(pending.values()), statistic, percentile)):
            result.values[i] = float(v)
        pending.clear()

    chunks: dict = {}    # the small ROIs' pixel indices, listed PIXEL_CHUNK ROIs at a time
    left = [min(PIXEL_CHUNK, len(placed) - c) for c in range(0, len(placed), PIXEL_CHUNK)]

    def pixels_of(k: int):
        c = k // PIXEL_CHUNK
        if c not in chunks:
            chunks[c] = span_pixels(placed[c * PIXEL_CHUNK:(c + 1) * PIXEL_CHUNK])
        idx = chunks[c][k - c * PIXEL_CHUNK]
        left[c] -= 1
        if not left[c]:
            del chunks[c]
        return idx

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        a = arr[..., 0]
        idx = pixels_of(k)
        if idx is not None:             # the ROI's pixels by index, then the valid ones
            v = a.ravel()[idx]
            v = v[valid_heights(tif, v)]
            some, inside = len(v) > 0, len(idx) > 0
        else:
            mask = p.mask()
            sel = mask & valid_heights(tif, a)
            some = bool(sel.any())
            v, inside = (a[sel] if some else None), some or bool(mask.any())
        if some:
            pending[p.index] = v
            if len(pending) >= STATS_BATCH:
                flush()
        elif not inside:
            result.missing[p.index] = NO_PIXEL if p.buffer >= 0 else (
                f"the buffer of {p.buffer:g} (DSM map units) shrinks it to nothing: it is "
                f"narrower than {-2 * p.buffer:g}; use a smaller negative buffer")
        else:
            result.missing[p.index] = "all DSM pixels inside it are nodata"

    sweep_windows(tif, [p.window for p in placed], consume, prog)
    flush()
    return result


def vertex_heights(dsm, x: np.ndarray, y: np.ndarray, sampling: str = "bilinear",
                   buffer: float = 0.0, statistic: str = "mean", percentile: float = 50.0,
                   progress=None, is_cancelled=None) -> np.ndarray:
    """Heights at points (x, y) in the DSM CRS (``dsm``: as for :func:`dsm_roi_heights`): sampled
    (``buffer`` <= 0, :meth:`~.dsm.DSM.heights`), or the ``statistic`` of the valid pixels
    whose centres lie within ``buffer`` map units of each point. NaN where there is no valid
    pixel."""
    dsm = as_dsm(dsm)
    tif = dsm.tif
    prog = as_progress(progress, is_cancelled)
    if buffer <= 0:
        return dsm.heights(x, y, method=sampling, progress=prog)
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
        sel = (np.hypot(mx - x[p.index], my - y[p.index]) <= buffer) & valid_heights(tif, a)
        if sel.any():
            out[p.index] = statistic_of(a[sel], statistic, percentile)

    if placed:
        sweep_windows(tif, [p.window for p in placed], consume, prog)
    return out
