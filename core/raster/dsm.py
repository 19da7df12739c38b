"""The DSM: a one-band GeoTIFF of heights, the one object a DSM travels as in the engine.

:class:`DSM` opens a DSM (from a path or an opened :class:`GeoTiff`) and checks it once, samples
its heights at points given in any CRS (:meth:`DSM.heights`), and gives its ray surface
(:meth:`DSM.ray_surface`, the first hits of rays: :mod:`.ray_surface`). Functions that take a
DSM accept a :class:`DSM`, a path or a :class:`GeoTiff` and turn it into one with
:func:`as_dsm`.

Heights are in the DSM's own vertical reference and units; map coordinates are (x, y) =
(easting, northing) / (lon, lat), in the DSM's CRS unless another is given. A pixel holds no
height when it is nodata or not finite (:func:`valid_heights`); there the DSM gives NaN.
"""
import os
import threading
from dataclasses import replace

import numpy as np

from ..crs import as_crs, same_crs, transform_xy
from ..errors import InputError
from ..progress import as_progress
from .geotiff import GeoTiff, open_geotiff
from .ray_surface import TILE, RaySurface
from .sweep import Window, sweep_windows

SAMPLING = ("nearest", "bilinear")
SAMPLE_CELL = 256  # pixels: points are read from the DSM in windows of at most this size (+1)


def valid_heights(tif: GeoTiff, arr: np.ndarray) -> np.ndarray:
    """True where ``arr`` (pixels of the height raster ``tif``) holds a height: finite (float
    rasters) and not ``tif``'s nodata."""
    ok = np.isfinite(arr) if arr.dtype.kind == "f" else np.ones(arr.shape, bool)
    if tif.nodata is not None:
        ok &= arr != np.asarray(tif.nodata, dtype=arr.dtype)
    return ok


class DSM:
    """A digital surface model: one band of heights on a north-up grid.

    ``source``: a GeoTIFF path or an opened :class:`GeoTiff`; ``crs`` (anything pyproj accepts)
    overrides the CRS of its GeoKeys. Raises :class:`InputError` for what :func:`open_geotiff`
    refuses and for a raster with more than one band.
    """

    def __init__(self, source, crs=None):
        if isinstance(source, GeoTiff):
            tif = source if crs is None else replace(source, crs=as_crs(crs, f"CRS of {source.path}"))
        else:
            tif = open_geotiff(os.fspath(source), crs=crs)
        if tif.bands != 1:
            raise InputError(f"The DSM {tif.path} has {tif.bands} bands; a DSM must have exactly "
                             "one (heights). Choose the elevation raster.")
        self.tif = tif
        self._surfaces = {}
        self._lock = threading.Lock()

    @property
    def path(self) -> str:
        return self.tif.path

    @property
    def crs(self):
        """The DSM's pyproj CRS (None when the file has none and none was given)."""
        return self.tif.crs

    @property
    def notes(self):
        """Problems met reading the file (e.g. a CRS that could not be read), for the caller."""
        return self.tif.notes

    def __repr__(self) -> str:
        return f"DSM({self.path!r})"

    def describe(self) -> str:
        """How the DSM gives vertex heights (the height-source description of back-projection)."""
        return f"DSM {self.path} (bilinear per vertex)"

    # ---- heights at points ----------------------------------------------------------------------
    def heights(self, x, y, *, crs=None, method: str = "bilinear", progress=None,
                is_cancelled=None) -> np.ndarray:
        """DSM heights at points (x, y), an array of the shape of ``x``; NaN outside the raster
        or where there is no height.

        ``crs``: the CRS of the points (default: the DSM's); they are transformed to the DSM's
        CRS when both are known and differ. ``nearest``: the pixel containing the point.
        ``bilinear``: interpolation between the four nearest pixel centres, with the weights of
        neighbours without a height dropped (NaN if none has one); beyond the outermost
        centres, out to the raster edge, the edge pixels' heights. Points are read in groups
        (one window per occupied cell of ``SAMPLE_CELL`` pixels), so millions of dense points
        (a point cloud's ground) cost one read of the pixels under them, not one window each.
        """
        if method not in SAMPLING:
            raise ValueError(f"sampling must be one of {SAMPLING}, not {method!r}")
        src = as_crs(crs)
        if self.crs is not None and src is not None and not same_crs(src, self.crs):
            xy = transform_xy(src, self.crs, np.column_stack([np.ravel(x), np.ravel(y)]))
            return self._sample(xy[:, 0], xy[:, 1], method, progress, is_cancelled) \
                .reshape(np.shape(x))
        return self._sample(x, y, method, progress, is_cancelled)

    def _sample(self, x, y, method, progress, is_cancelled) -> np.ndarray:
        tif = self.tif
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
            ok_px = valid_heights(tif, vals)
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
                    out[idx[g]] = np.where(weight > 0, total / np.where(weight > 0, weight, 1),
                                           np.nan)

        prog = as_progress(progress, is_cancelled)
        keep = [k for k, w in enumerate(windows) if w.rows > 0 and w.cols > 0]
        if keep:
            groups = [groups[k] for k in keep]
            windows = [windows[k] for k in keep]
            sweep_windows(tif, windows, consume, prog)
        return out.reshape(np.shape(x))

    # ---- rays ------------------------------------------------------------------------------------
    def ray_surface(self, tile: int = TILE) -> RaySurface:
        """The DSM as a surface for ray casting (:func:`.ray_surface.first_hits`), made on first
        use and kept: the tiles the rays read stay in memory for later rays on this DSM (drop
        the DSM to free them). ``tile``: cells per tile side."""
        with self._lock:
            if tile not in self._surfaces:
                self._surfaces[tile] = RaySurface(self.tif, tile)
            return self._surfaces[tile]


def as_dsm(dsm, crs=None) -> DSM:
    """A :class:`DSM` from a DSM, a GeoTIFF path or an opened :class:`GeoTiff`; ``crs``
    overrides the DSM's CRS (a DSM given without ``crs`` is returned as it is)."""
    if isinstance(dsm, DSM):
        return dsm if crs is None else DSM(dsm.tif, crs)
    return DSM(dsm, crs)
