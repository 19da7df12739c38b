"""The first hit of rays on a DSM: exact, vectorised, reading only the DSM tiles along the rays.

A :class:`RaySurface` is made by :meth:`core.raster.dsm.DSM.ray_surface`; it needs no camera,
only a frame that maps model coordinates to the DSM's CRS and back (duck-typed:
``to_model`` / ``from_model``, as ``Reconstruction.frame`` has).

**Surface.** The DSM is the bilinear surface between pixel centres (ARCHITECTURE.md). Beyond
the outermost pixel centres, out to the raster edge, it continues flat (the edge rows and
columns are repeated), as :meth:`core.raster.dsm.DSM.heights` does; the *extent* is
the raster's [0, width] × [0, height] pixels. A dual *cell* is the square between four pixel
centres; a cell with a nodata corner is a nodata cell (the surface there is unknown).

**Rays** are given in the reconstruction's model frame (``Reconstruction.pixel_to_ray``) and
mapped to DSM pixel space (u = column + 0.5, v = row + 0.5, z = height in the DSM's vertical
reference) by an affine map: the model frame linearised at an anchor. The map is exact for
Pix4D projects in the DSM's CRS and for local frames; otherwise (Metashape's geocentric frame,
another CRS) its error is predicted on a lattice over where the rays cross the heights read,
and the rays are traversed in groups, each with its own anchor, split and re-run until the
error *measured* where they met the surface is below :data:`LINEARISATION_TOLERANCE`
(``RayHits.linearisation_error`` reports it).

**Traversal** (:mod:`.ray_traverse`). A lockstep 2-D DDA (Amanatides & Woo) over three
levels: tiles of :data:`TILE` cells (the unit read from the file, with their height range),
blocks of ``BLOCK`` cells (a max-mipmap level) and cells. A tile or block is entered, and
walked from, only where the ray comes down to its highest height; in a cell, the bilinear
height along the ray is a quadratic in the ray parameter, solved exactly for its smallest
root. Every cell crossed by the ray's ground track is visited in order, so no ridge can be
stepped over. Rays are traversed in batches, one thread per core; the tiles they first come
down into are read before, in two large sweeps (each file block decoded once), and the rest
as rays reach them.

**Result** per ray: ``HIT`` (the first point of the ray at or below the surface, from its
origin), ``MISS`` (it never reaches the surface inside the DSM within ``max_distance``, e.g.
it points up, passes over or beside the DSM, or enters the extent through its side already
under the surface), ``LEFT`` (it leaves the DSM extent at a height
where it could still meet the ground: below the highest height read), ``NODATA`` (it enters a
nodata cell below the highest height read, before any hit: what lies there is unknown).
"""
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from ..errors import EasyIDPError
from ..progress import as_progress
from .geotiff import GeoTiff
from .ray_traverse import (BLOCK, HIT, LEFT, MISS, NODATA, _nodata_ceiling, _Rays, _read_wanted,
                           _tile_walk, _traverse)
from .sweep import Window, sweep_windows, thread_pool

STATUS_NAMES = {HIT: "hit", MISS: "miss", LEFT: "left the DSM", NODATA: "nodata"}

TILE = 256          # cells per tile side: the unit read from the DSM
LINEARISATION_TOLERANCE = 5e-4   # m: largest accepted error of the linearised model frame
EXACT = 1e-9       # m: a linearisation this close over the whole DSM is the map itself
FAR = 1e7           # model units: the end of a ray without max_distance
BATCH = 16384       # rays traversed at once (per thread)


@dataclass
class RayHits:
    """First hits of n rays. ``distance`` (n,) along the ray in model-frame units, NaN where
    there is no hit; ``xyz`` (n, 3) of the hit in the DSM's CRS (its vertical reference),
    NaN where there is no hit; ``status`` (n,) uint8: HIT, MISS, LEFT or NODATA.
    ``linearisation_error``: largest measured error (m) of the model → DSM linearisation over
    the places where the rays met the surface (0 for an exact affine map)."""
    distance: np.ndarray
    xyz: np.ndarray
    status: np.ndarray
    linearisation_error: float = 0.0

    @property
    def hit(self) -> np.ndarray:
        return self.status == HIT


class RaySurface:
    """A DSM as a surface for ray casting; its tiles are read on demand and kept.

    Made by :meth:`core.raster.dsm.DSM.ray_surface` from the DSM's (one-band, validated)
    :class:`GeoTiff`. Heights are in the DSM's own vertical reference and units. ``tile``:
    cells per tile side (a multiple of :data:`BLOCK`).
    """

    def __init__(self, tif: GeoTiff, tile: int = TILE):
        if tile % BLOCK:
            raise ValueError(f"tile must be a multiple of {BLOCK}")
        self.tif = tif
        self.crs = tif.crs
        self.T = int(tile)
        self.W, self.H = tif.width, tif.height
        nc_u, nc_v = self.W + 1, self.H + 1                 # cells per row / column
        self.ntu, self.ntv = -(-nc_u // self.T), -(-nc_v // self.T)
        nb = self.T // BLOCK
        self.slot = np.full((self.ntv, self.ntu), -1, np.int64)
        self.tile_max = np.full((self.ntv, self.ntu), -np.inf)     # highest valid height
        self.tile_nod = np.zeros((self.ntv, self.ntu), bool)       # has a nodata cell
        self.block_max = np.full((self.ntv * nb, self.ntu * nb), -np.inf)
        self.block_nod = np.zeros((self.ntv * nb, self.ntu * nb), bool)
        self.dtype = np.float64 if tif.dtype == np.float64 else np.float32
        self._store = np.zeros((0, self.T + 1, self.T + 1), self.dtype)   # cell corners
        self._cmax = np.zeros((0, self.T, self.T), self.dtype)           # cell maxima, NaN: nodata
        self._n = 0
        self.zmin, self.zmax = np.inf, -np.inf               # valid heights read so far
        self.tiles_read = 0
        self._lock = threading.Lock()
        self._range_lock = threading.Lock()

    # --- geometry ------------------------------------------------------------------------------
    def map_to_uv(self, x, y):
        """Map (x, y) in the DSM CRS → (u, v) = (column + 0.5, row + 0.5)."""
        col, row = self.tif.map_to_pixel(x, y)
        return col + 0.5, row + 0.5

    def uv_to_map(self, u, v):
        return self.tif.pixel_to_map(np.asarray(u) - 0.5, np.asarray(v) - 0.5)

    @property
    def loaded(self) -> int:
        return self._n

    # --- reading -------------------------------------------------------------------------------
    def load(self, tiles, progress=None) -> None:
        """Read tiles (iterable of (tile row, tile column)) not yet in memory, in one sweep.
        Thread-safe: traversal threads share the surface."""
        with self._lock:
            self._load(tiles, progress)

    def _load(self, tiles, progress) -> None:
        todo = sorted({(int(a), int(b)) for a, b in tiles if self.slot[a, b] < 0})
        if not todo:
            return
        T, H, W = self.T, self.H, self.W
        wins = []
        for ti, tj in todo:
            r0, r1 = max(ti * T - 1, 0), min((ti + 1) * T - 1, H - 1)
            c0, c1 = max(tj * T - 1, 0), min((tj + 1) * T - 1, W - 1)
            wins.append(Window(r0, c0, r1 - r0 + 1, c1 - c0 + 1))
        need = self._n + len(todo)
        if need > len(self._store):
            grown = np.empty((max(need, 2 * len(self._store)), T + 1, T + 1), self.dtype)
            grown[:self._n] = self._store[:self._n]
            cgrown = np.empty((len(grown), T, T), self.dtype)
            cgrown[:self._n] = self._cmax[:self._n]
            self._cmax = cgrown
            self._store = grown
        tif = self.tif

        def prepare(k: int, arr: np.ndarray) -> None:
            ti, tj = todo[k]
            w = wins[k]
            # sample s (cell corner) ↔ pixel s − 1, clamped to the raster (flat beyond the edge)
            rows = np.clip(np.arange(ti * T, ti * T + T + 1) - 1, 0, H - 1) - w.row
            cols = np.clip(np.arange(tj * T, tj * T + T + 1) - 1, 0, W - 1) - w.col
            slot = self._n + k
            s = self._store[slot]
            raw = arr[..., 0]
            if rows[0] == 0 and rows[-1] == T and cols[0] == 0 and cols[-1] == T:
                s[...] = raw[:T + 1, :T + 1]                 # inside the raster: a plain copy
            else:
                s[...] = raw[np.clip(rows, 0, w.rows - 1)][:, np.clip(cols, 0, w.cols - 1)]
            if tif.nodata is not None:
                s[s == np.asarray(tif.nodata, s.dtype)] = np.nan
            if s.dtype.kind == "f":
                s[np.isinf(s)] = np.nan
            self._summarise(ti, tj, s, self._cmax[slot])
            self.slot[ti, tj] = slot

        try:
            with thread_pool() as pool:     # copies and maxima beside the decoding
                jobs = []
                sweep_windows(tif, wins, lambda k, arr: jobs.append(pool.submit(prepare, k, arr)),
                              as_progress(progress))
                for job in jobs:
                    job.result()
        except BaseException:               # cancelled or unreadable: forget the partial read
            self.slot[self.slot >= self._n] = -1
            raise
        self._n = need
        self.tiles_read += len(todo)

    def _summarise(self, ti: int, tj: int, s: np.ndarray, cell_max: np.ndarray) -> None:
        """Tile and block maxima (valid heights) and nodata flags of a freshly read tile."""
        T, nb = self.T, self.T // BLOCK
        nv = min(T, self.H + 1 - ti * T)                     # real cells of this tile
        nu = min(T, self.W + 1 - tj * T)
        # NaN (nodata) propagates through maximum: a cell with a nodata corner gets NaN
        np.maximum(np.maximum(s[:-1, :-1], s[1:, :-1]), np.maximum(s[:-1, 1:], s[1:, 1:]),
                   out=cell_max)
        cell_max[nv:, :] = -np.inf
        cell_max[:, nu:] = -np.inf
        nod = np.isnan(cell_max)
        valid = np.where(nod, -np.inf, cell_max)
        bm = valid.reshape(nb, BLOCK, nb, BLOCK).max(axis=(1, 3))
        bn = nod.reshape(nb, BLOCK, nb, BLOCK).any(axis=(1, 3))
        self.block_max[ti * nb:(ti + 1) * nb, tj * nb:(tj + 1) * nb] = bm
        self.block_nod[ti * nb:(ti + 1) * nb, tj * nb:(tj + 1) * nb] = bn
        self.tile_max[ti, tj] = bm.max()
        self.tile_nod[ti, tj] = bn.any()
        lo = np.fmin.reduce(s[:nv + 1, :nu + 1], axis=None)
        hi = float(bm.max())
        if np.isfinite(hi):
            with self._range_lock:
                self.zmin = min(self.zmin, float(lo))
                self.zmax = max(self.zmax, hi)

    def heights(self, x, y, progress=None) -> np.ndarray:
        """Surface heights at map points (x, y) in the DSM's CRS: bilinear between pixel
        centres, flat out to the raster edge; NaN outside the raster and on nodata cells (the
        surface the rays meet). Reads the tiles it needs (kept for the rays)."""
        u, v = self.map_to_uv(np.ravel(x), np.ravel(y))
        u, v = np.asarray(u, np.float64), np.asarray(v, np.float64)
        out = np.full(u.shape, np.nan)
        inside = (u >= 0.5) & (u <= self.W + 0.5) & (v >= 0.5) & (v <= self.H + 0.5)
        k = np.flatnonzero(inside)
        if k.size:
            iu = np.clip(np.floor(u[k]).astype(np.int64), 0, self.W)
            iv = np.clip(np.floor(v[k]).astype(np.int64), 0, self.H)
            T, T1 = self.T, self.T + 1
            tid = (iv // T) * self.ntu + iu // T
            tiles = np.flatnonzero(np.bincount(tid, minlength=self.ntv * self.ntu))
            self.load(zip((tiles // self.ntu).tolist(), (tiles % self.ntu).tolist()), progress)
            f = self.slot.reshape(-1)[tid] * (T1 * T1) + (iv % T) * T1 + iu % T
            st = self.samples_flat()
            a, b = u[k] - iu, v[k] - iv
            h00, h10 = st[f].astype(np.float64), st[f + 1].astype(np.float64)
            h01, h11 = st[f + T1].astype(np.float64), st[f + T1 + 1].astype(np.float64)
            out[k] = (h00 * (1 - a) + h10 * a) * (1 - b) + (h01 * (1 - a) + h11 * a) * b
        return out.reshape(np.shape(x))

    def samples_flat(self) -> np.ndarray:
        """The corner heights of the tiles read, flat: tile slot k, corner (v, u) at
        k·(T+1)² + v·(T+1) + u (NaN: nodata)."""
        return self._store.reshape(-1)

    def cell_max_flat(self) -> np.ndarray:
        """The highest corner of every cell of the tiles read, flat (k·T² + v·T + u); NaN
        for a nodata cell."""
        return self._cmax.reshape(-1)


# ---- model frame → DSM pixel space ---------------------------------------------------------------
class _Affine:
    """Model-frame point p → (u, v, z) = M·p + m, linearised at ``anchor`` (DSM CRS x, y, z)."""

    def __init__(self, frame, surface: RaySurface, anchor_xyz):
        self.frame, self.surface = frame, surface
        anchor = np.asarray(anchor_xyz, np.float64).reshape(1, 3)
        p0 = frame.to_model(anchor, surface.crs)[0]
        h = 1.0
        pts = np.vstack([p0 + h * np.eye(3), p0 - h * np.eye(3)])
        g = frame.from_model(pts, surface.crs)
        J = (g[:3] - g[3:]).T / (2 * h)                      # d(x, y, z)/d(model)
        c, a, _, f, _, e = surface.tif.geotransform
        P = np.diag([1 / a, 1 / e, 1.0])
        q = np.array([-c / a + 0.5, -f / e + 0.5, 0.0])
        self.M = P @ J
        self.m = P @ (anchor[0] - J @ p0) + q
        self.metres = 1.0 / np.linalg.norm(self.M, axis=1)  # model units per pixel (u, v) / per z unit

    def error(self, x0, x1, y0, y1, z0, z1, n: int = 5) -> float:
        """Largest error (model units, i.e. metres) of the linearisation on an n×n×3 lattice
        over the DSM-CRS box [x0, x1] × [y0, y1] × [z0, z1]."""
        gx, gy, gz = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n),
                                 np.linspace(z0, z1, 3))
        xyz = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
        p = self.frame.to_model(xyz, self.surface.crs)
        u, v = self.surface.map_to_uv(xyz[:, 0], xyz[:, 1])
        exact = np.column_stack([u, v, xyz[:, 2]])
        d = (p @ self.M.T + self.m - exact) * self.metres
        return float(np.sqrt((d * d).sum(axis=1)).max())


def _clip_to_extent(surface: RaySurface, o, d, tmax):
    """Ray parameter range [t0, t1] inside the extent (slab method) and whether t1 is the
    extent's edge (not ``tmax``)."""
    lo = np.array([0.5, 0.5])
    hi = np.array([surface.W + 0.5, surface.H + 0.5])
    t0 = np.zeros(len(o))
    t1 = np.array(tmax, np.float64)
    edge = np.zeros(len(o), bool)
    for k in range(2):
        dk, ok = d[:, k], o[:, k]
        with np.errstate(divide="ignore", invalid="ignore"):
            ta = (lo[k] - ok) / dk
            tb = (hi[k] - ok) / dk
        near = np.where(dk != 0, np.minimum(ta, tb), np.where((ok >= lo[k]) & (ok <= hi[k]), -np.inf, np.inf))
        far = np.where(dk != 0, np.maximum(ta, tb), np.where((ok >= lo[k]) & (ok <= hi[k]), np.inf, -np.inf))
        t0 = np.maximum(t0, near)
        edge = np.where(far < t1, True, edge)
        t1 = np.minimum(t1, far)
    # shrink by a hair so that the first/last cell indices stay inside the grid
    return t0, t1, edge


def _first_wave(surface: RaySurface, r: _Rays, prog, waves: int = 2) -> None:
    """Read the tiles all rays come down into first, in a few large sweeps, before threads
    traverse batches of them: threads that read in turn, tile by tile, would decode the file
    blocks shared by neighbouring tiles again and again. Nothing to do (and no walk) once
    every tile is in memory."""
    idx = np.flatnonzero(r.t0 < r.t1)
    for _ in range(waves):
        if (surface.slot >= 0).all():
            return
        code, tv, tu, ta, _ = _tile_walk(surface, r, idx, r.t0[idx], _nodata_ceiling(surface))
        want = np.flatnonzero(code == 2)
        if not want.size:
            return
        _read_wanted(surface, r, idx[want], tv[want], tu[want], ta[want], prog)


def _run(surface: RaySurface, aff: _Affine, origins, directions, tmax, prog):
    o = origins @ aff.M.T + aff.m
    d = directions @ aff.M.T
    t0, t1, edge = _clip_to_extent(surface, o, d, tmax)
    n = len(o)
    t = np.full(n, np.nan)
    st = np.full(n, MISS, np.uint8)
    side_entry = np.zeros(n, bool)

    def batch(b0: int) -> None:
        sl = slice(b0, min(n, b0 + BATCH))
        r = _Rays(o[sl], d[sl], t0[sl], t1[sl], edge[sl])
        tb_, sb_ = _traverse(surface, r, prog)
        # entering the extent through its side, under the surface: the ray met the ground (if
        # at all) outside the DSM
        side = (sb_ == HIT) & (tb_ <= r.t0) & (r.t0 > 0)
        sb_[side] = MISS
        side_entry[sl] = side
        t[sl], st[sl] = tb_, sb_

    starts = list(range(0, n, BATCH))
    if len(starts) == 1:
        batch(0)
    else:                      # numpy releases the GIL in its loops: one thread per core
        with ThreadPoolExecutor(min(len(starts), os.cpu_count() or 2)) as pool:
            list(pool.map(batch, starts))
    # rays whose range ended without a hit: LEFT when they leave the extent at a height where
    # they could still meet the ground (the highest height the whole run read: not the order
    # in which threads read tiles), else MISS
    ended = (st == MISS) & (t0 < t1) & ~side_entry
    st[ended] = np.where(edge[ended] & (o[ended, 2] + d[ended, 2] * t1[ended] <= surface.zmax),
                         LEFT, MISS)
    return o, d, t, st, t0, t1


def first_hits(surface: RaySurface, frame, origins, directions, *, max_distance=None,
               progress=None, is_cancelled=None,
               tolerance: float = LINEARISATION_TOLERANCE) -> RayHits:
    """First hit of each ray on the DSM surface.

    ``frame``: the reconstruction's :class:`~core.reconstruction.geodesy.ModelFrame`
    (``recon.frame``); ``origins`` (3,) or (n, 3) and unit ``directions`` (n, 3) in that frame
    (as ``Reconstruction.pixel_to_ray`` returns). ``max_distance`` (scalar or (n,)) ends the
    rays, in model units. The DSM's CRS must be one the frame can convert to (a DSM without a
    CRS is taken to be in the project's CRS).
    """
    prog = as_progress(progress, is_cancelled)
    d = np.atleast_2d(np.asarray(directions, np.float64))
    if d.ndim != 2 or d.shape[1] != 3:
        raise EasyIDPError(f"directions must be an (n, 3) array, not {d.shape}")
    n = len(d)
    o = np.broadcast_to(np.asarray(origins, np.float64), (n, 3)).copy()
    if not (np.isfinite(o).all() and np.isfinite(d).all()):
        raise EasyIDPError("ray origins and directions must be finite numbers")
    norm = np.linalg.norm(d, axis=1)
    if np.any(norm == 0):
        raise EasyIDPError("a ray direction is the zero vector")
    d = d / norm[:, None]
    tmax = np.full(n, FAR) if max_distance is None else \
        np.minimum(np.broadcast_to(np.asarray(max_distance, np.float64), (n,)), FAR)
    if n == 0:
        return RayHits(np.zeros(0), np.zeros((0, 3)), np.zeros(0, np.uint8))
    tif = surface.tif
    # pass 1: one linearisation at the rays' side of the DSM
    cx, cy = tif.pixel_to_map(surface.W / 2, surface.H / 2)
    probe = _Affine(frame, surface, (cx, cy, 0.0))
    op = o @ probe.M.T + probe.m
    u = np.clip(np.median(op[:, 0]), 0.5, surface.W + 0.5)
    v = np.clip(np.median(op[:, 1]), 0.5, surface.H + 0.5)
    ax, ay = surface.uv_to_map(u, v)
    z_guess = surface.zmax if np.isfinite(surface.zmax) else 0.0
    aff = _Affine(frame, surface, (float(ax), float(ay), z_guess))
    po, pd = o @ aff.M.T + aff.m, d @ aff.M.T
    t0, t1, edge = _clip_to_extent(surface, po, pd, tmax)
    _first_wave(surface, _Rays(po, pd, t0, t1, edge), prog)
    # where the rays cross the heights read: is one linearisation enough there? (not asked
    # where the map is affine over the whole extent: a DSM in the project's CRS, a local frame)
    full = _affine_error(surface, aff)
    exact = full <= EXACT
    err, regrouped = (full if exact else 0.0), False
    if np.isfinite(surface.zmin) and not exact:
        with np.errstate(divide="ignore", invalid="ignore"):
            t_low = np.where(pd[:, 2] < 0, (surface.zmin - po[:, 2]) / pd[:, 2], t1)
        status = np.where(t0 < t1, HIT, MISS).astype(np.uint8)
        box = _band_box(surface, po, pd, np.clip(t_low, t0, t1), status, t0)
        if box is not None and aff.error(*box) > tolerance:    # groups, each traversed once
            t = np.full(n, np.nan)
            err, xyz_groups = _regroup(surface, frame, o, d, tmax, np.clip(t_low, t0, t1),
                                       status, po, pd, t0, tolerance, prog, t)
            regrouped = True
    if not regrouped:
        po, pd, t, status, t0, _ = _run(surface, aff, o, d, tmax, prog)
        if np.isfinite(surface.zmin) and not exact:
            box = _band_box(surface, po, pd, t, status, t0)
            if box is not None:
                err = aff.error(*box)
                if err > tolerance:         # the rays met heights not read before
                    err, xyz_groups = _regroup(surface, frame, o, d, tmax, t, status, po, pd,
                                               t0, tolerance, prog, t)
                    regrouped = True
    xyz = np.full((n, 3), np.nan)
    hit = status == HIT
    if hit.any():
        p = o[hit] + t[hit, None] * d[hit]
        if regrouped:                       # each group through its own map
            xyz[hit] = xyz_groups[hit]
        else:
            q = p @ aff.M.T + aff.m
            x, y = surface.uv_to_map(q[:, 0], q[:, 1])
            xyz[hit] = np.column_stack([x, y, q[:, 2]])
    return RayHits(np.where(hit, t, np.nan), xyz, status, float(err))


def _affine_error(surface, aff: _Affine) -> float:
    """The linearisation's error over the whole extent and the heights read (or 0–1 before
    any): at most :data:`EXACT` where the map is affine (then no band needs checking)."""
    x0, y0 = surface.tif.pixel_to_map(0.0, 0.0)
    x1, y1 = surface.tif.pixel_to_map(float(surface.W), float(surface.H))
    z0, z1 = (surface.zmin, surface.zmax) if np.isfinite(surface.zmin) else (0.0, 1.0)
    return aff.error(min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1), z0, z1)


def _band_box(surface, po, pd, t, status, t0, sel=None):
    """DSM-CRS box (x0, x1, y0, y1, z0, z1) over which rays cross the height band read."""
    idx = np.flatnonzero((status == HIT) | (status == LEFT) | (status == NODATA))
    if sel is not None:
        idx = np.intersect1d(idx, sel)
    if not idx.size:
        return None
    zt = surface.zmax
    with np.errstate(divide="ignore", invalid="ignore"):
        t_top = np.where(pd[idx, 2] < 0, (zt - po[idx, 2]) / pd[idx, 2], t0[idx])
    t_top = np.maximum(np.nan_to_num(t_top, nan=0.0), t0[idx])
    t_end = np.where(np.isfinite(t[idx]), t[idx], t_top)
    pts = np.vstack([po[idx] + t_top[:, None] * pd[idx], po[idx] + t_end[:, None] * pd[idx]])
    u = np.clip(pts[:, 0], 0.5, surface.W + 0.5)
    v = np.clip(pts[:, 1], 0.5, surface.H + 0.5)
    x, y = surface.uv_to_map(u, v)
    return (float(x.min()), float(x.max()), float(y.min()), float(y.max()),
            surface.zmin, surface.zmax)


def _regroup(surface, frame, o, d, tmax, t_plan, status, po, pd, t0, tolerance, prog, t):
    """Run the rays in groups by where they meet the surface, each with its own
    linearisation, until each group's measured error is within ``tolerance``. Groups are
    planned on a geometry (``t_plan``, ``status``: a first pass's hits, or where the rays
    cross the heights read), splitting in four about the medians while the error predicted
    over a group's box exceeds ``tolerance``; then each is traversed once and its error
    measured again. Writes ``t`` and ``status`` in place; returns (largest measured error, hit
    coordinates (n, 3) in the DSM's CRS from each group's own map)."""
    t_end = np.where(np.isfinite(t_plan), t_plan, t0)
    p = po + t_end[:, None] * pd
    x, y = surface.uv_to_map(p[:, 0], p[:, 1])
    zmid = 0.5 * (surface.zmin + surface.zmax)
    xyz = np.full((len(o), 3), np.nan)

    def anchor(g):
        gx, gy = x[g], y[g]
        return _Affine(frame, surface, (0.5 * (gx.min() + gx.max()), 0.5 * (gy.min() + gy.max()),
                                        zmid))

    def split(g):
        gx, gy = x[g], y[g]
        mx, my = np.median(gx), np.median(gy)
        return [g[qx & qy] for qx in (gx <= mx, gx > mx) for qy in (gy <= my, gy > my)
                if (qx & qy).any()]

    todo = [np.flatnonzero(status != MISS)]
    planned = []
    for _ in range(16):                          # plan on the given geometry
        nxt = []
        for g in todo:
            box = _band_box(surface, po[g], pd[g], t_plan[g], status[g], t0[g])
            if box is None or len(g) == 1 or anchor(g).error(*box) <= 0.8 * tolerance:
                planned.append(g)
            else:
                nxt.extend(split(g))
        todo = nxt
        if not todo:
            break
    planned.extend(todo)
    worst = 0.0
    todo = planned
    for _ in range(12):
        nxt = []
        for g in todo:
            aff = anchor(g)
            go, gd, gt, gs, gt0, _ = _run(surface, aff, o[g], d[g], tmax[g], prog)
            box = _band_box(surface, go, gd, gt, gs, gt0)
            e = aff.error(*box) if box is not None else 0.0
            if e <= tolerance or len(g) == 1:
                t[g], status[g] = gt, gs
                worst = max(worst, e)
                h = gs == HIT
                q = go[h] + gt[h, None] * gd[h]
                hx, hy = surface.uv_to_map(q[:, 0], q[:, 1])
                xyz[g[h]] = np.column_stack([hx, hy, q[:, 2]])
                continue
            nxt.extend(split(g))
        todo = nxt
        if not todo:
            break
    else:
        raise EasyIDPError("The model frame could not be linearised to within "
                           f"{tolerance * 1000:.1f} mm over the DSM; report this case.")
    return worst, xyz
