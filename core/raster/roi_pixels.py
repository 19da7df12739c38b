"""ROIs on a raster's pixel grid: reprojection, pixel windows and masks (shared by crop and stats)."""
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from .. import geometry
from ..ragged import offsets, position_in_run, ranges
from ..crs import same_crs
from ..errors import InputError, ROIError
from ..gc_pause import paused_gc
from .geotiff import GeoTiff
from .sweep import Window
from ..roi import ROI, ROISet


SPAN_GROUP = 1_000_000     # edge × row crossings placed at once (:func:`geometry.row_spans`)
NO_PIXEL = ("contains no pixel centre of the raster (it is smaller than a pixel or lies on the "
            "edge); use all-touched to include it")


@dataclass
class PixelROI:
    """An ROI on one raster's grid: its window (the polygon's envelope, grown by the buffer and
    clipped to the raster) and its rings in pixel coordinates relative to that window. The mask
    is computed on demand, when the window's pixels arrive, so thousands of ROIs cost nothing
    while they wait for the sweep."""
    index: int                 # position in the ROI set
    roi: ROI
    window: Window
    rings: List[np.ndarray]    # (col, row) relative to the window's top-left corner
    all_touched: bool = False
    buffer: float = 0.0        # map units
    pixel_size: Tuple[float, float] = (1.0, 1.0)
    spans: Optional[Tuple[np.ndarray, np.ndarray]] = None   # per row [start, stop), when known

    def mask(self) -> np.ndarray:
        """(rows, cols) bool over the window, True inside (see :func:`place_rois`)."""
        w = self.window
        if self.spans is not None:
            c = np.arange(w.cols)
            return (c >= self.spans[0][:, None]) & (c < self.spans[1][:, None])
        if self.buffer == 0.0:
            return geometry.rasterize(self.rings, (w.rows, w.cols), self.all_touched)
        sx, sy = self.pixel_size   # distances in map units, also for non-square pixels
        cc, rr = np.meshgrid((np.arange(w.cols) + 0.5) * sx, (np.arange(w.rows) + 0.5) * sy)
        rings = [r * (sx, sy) for r in self.rings]
        inside = geometry.points_in_rings(cc, rr, rings)
        dist = geometry.distance_to_rings(cc, rr, rings)
        return (inside | (dist <= self.buffer)) if self.buffer > 0 else (inside & (dist > -self.buffer))


def bounding_box(mask: np.ndarray) -> Optional[Tuple[int, int, int, int]]:
    """(row0, row1, col0, col1), end-exclusive, of the True pixels; None when there is none."""
    rows = np.flatnonzero(mask.any(axis=1))
    if not len(rows):
        return None
    cols = np.flatnonzero(mask.any(axis=0))
    return int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1


def rois_in_raster_crs(rois: ROISet, tif: GeoTiff) -> ROISet:
    """The ROIs validated and reprojected to the raster's CRS (ROIs without a CRS are taken as is)."""
    rois.validate()
    if rois.crs is None or same_crs(rois.crs, tif.crs):
        return rois
    if tif.crs is None:
        raise InputError(f"The CRS of {tif.path} cannot be read from its GeoKeys, so the ROIs "
                         f"({rois.crs.name}) cannot be reprojected to it. Give the raster's CRS.")
    return rois.to_crs(tif.crs)


def place_rois(tif: GeoTiff, rois: ROISet, all_touched: bool = False, buffer: float = 0.0,
               ) -> Tuple[List[PixelROI], dict]:
    """The ROIs on the raster grid; ROIs whose envelope misses the raster are returned as skipped.

    A pixel is inside when its centre is inside the polygon (or, with ``all_touched``, when the
    polygon touches it). ``buffer`` (map units) grows (> 0) or shrinks (< 0) the polygon: a pixel
    is inside when its centre is within ``buffer`` of the polygon (or inside and further than
    ``-buffer`` from its boundary).
    Returns (placed ROIs, {ROI index: reason} for the ROIs skipped).
    """
    with paused_gc():
        return _place(tif, rois, all_touched, buffer)


def _place(tif: GeoTiff, rois: ROISet, all_touched: bool, buffer: float):
    placed, skipped = [], {}
    size = (abs(tif.geotransform[1]), abs(tif.geotransform[5]))
    grow_px = max(buffer, 0.0) / min(size)
    # every vertex of every ROI to pixels at once, then each ROI's window from its extent
    rings = [ring for roi in rois for ring in roi.rings]
    ring_offs = offsets([len(r) for r in rings])
    roi_rings = offsets([len(roi.rings) for roi in rois])
    xy = np.concatenate(rings) if rings else np.zeros((0, 2))
    px = np.column_stack(tif.map_to_pixel(xy[:, 0], xy[:, 1]))
    starts = ring_offs[roi_rings[:-1]]
    lo = np.floor(np.minimum.reduceat(px, starts, axis=0) - grow_px) if len(px) else px
    hi = np.ceil(np.maximum.reduceat(px, starts, axis=0) + grow_px) if len(px) else px
    c0, r0 = np.maximum(lo, 0).astype(np.int64).T
    c1 = np.minimum(hi[:, 0], tif.width).astype(np.int64)
    r1 = np.minimum(hi[:, 1], tif.height).astype(np.int64)
    px -= np.repeat(np.column_stack([c0, r0]), np.diff(ring_offs[roi_rings]), axis=0)
    cuts = ring_offs.tolist()
    px_rings = [px[a:b] for a, b in zip(cuts[:-1], cuts[1:])]
    per_roi = roi_rings.tolist()
    for i, (roi, row, col, rows, cols) in enumerate(zip(rois, r0.tolist(), c0.tolist(),
                                                        (r1 - r0).tolist(), (c1 - c0).tolist())):
        if rows <= 0 or cols <= 0:
            skipped[i] = "outside the raster"
            continue
        placed.append(PixelROI(i, roi, Window(row, col, rows, cols),
                               px_rings[per_roi[i]:per_roi[i + 1]], all_touched, buffer, size))
    if buffer == 0.0 and not all_touched:     # the one-ring ROIs' masks, a few passes
        simple = [p for p in placed if len(p.rings) == 1]
        work = np.cumsum([p.window.rows * len(p.rings[0]) for p in simple])
        # groups of about SPAN_GROUP edge-row crossings each: memory stays a few tens of MB
        cuts = np.searchsorted(work, np.arange(1, int(work[-1]) // SPAN_GROUP + 1) * SPAN_GROUP) \
            if len(work) else []
        for a, b in zip([0, *cuts], [*cuts, len(simple)]):
            group = simple[a:b]
            for p, sp in zip(group, geometry.row_spans([p.rings[0] for p in group],
                                                       [(p.window.rows, p.window.cols)
                                                        for p in group])):
                p.spans = sp
    return placed, skipped


SMALL_WINDOW = 4096        # pixels: the windows whose pixels :func:`span_pixels` lists


def span_pixels(placed: List[PixelROI]) -> List[Optional[np.ndarray]]:
    """Per placed ROI, the flat indices (row-major in its window, int32) of its pixels, from
    its row spans, all computed in one pass; None for an ROI without spans or with a window
    of more than :data:`SMALL_WINDOW` pixels (its :meth:`PixelROI.mask` says). Reading
    ``window.ravel()[indices]`` costs less per small ROI than building its mask."""
    out: List[Optional[np.ndarray]] = [None] * len(placed)
    have = [k for k, p in enumerate(placed) if p.spans is not None
            and p.window.rows * p.window.cols <= SMALL_WINDOW]
    if not have:
        return out
    start = np.concatenate([placed[k].spans[0] for k in have])
    stop = np.concatenate([placed[k].spans[1] for k in have])
    rows = np.array([placed[k].window.rows for k in have], np.int64)
    cols = np.repeat(np.array([placed[k].window.cols for k in have], np.int64), rows)
    row = position_in_run(rows)
    stop = np.maximum(stop, start)
    flat = ranges(row * cols + start, row * cols + stop).astype(np.int32)
    per_roi = np.add.reduceat(stop - start, offsets(rows)[:-1]) if len(start) else rows * 0
    cuts = offsets(per_roi).tolist()
    for j, k in enumerate(have):
        out[k] = flat[cuts[j]:cuts[j + 1]]
    return out


def require_overlap(placed, skipped, rois: ROISet, tif: GeoTiff) -> None:
    """Raise a clear :class:`ROIError` when no ROI overlaps the raster."""
    if placed:
        return
    c, a, _, f, _, e = tif.geotransform
    ext = (c, f + e * tif.height, c + a * tif.width, f)
    allxy = np.concatenate([r for roi in rois for r in roi.rings])
    rext = (*allxy.min(axis=0), *allxy.max(axis=0))
    crs = tif.crs.name if tif.crs is not None else "the raster CRS"
    raise ROIError.of("rois_miss_raster", count=len(rois), raster=tif.path,
                      raster_extent=_fmt(ext), roi_extent=_fmt(rext), crs=crs)


def _fmt(e) -> str:
    return "({:.3f}, {:.3f}) – ({:.3f}, {:.3f})".format(*e)
