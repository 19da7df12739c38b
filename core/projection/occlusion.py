"""Occlusion of ROIs in photos by the DSM surface (tall canopy, trees, buildings, oblique views).

**Rule.** Sample points are spread over each ROI on a regular grid (about ``samples`` cell
centres inside the polygon, in the DSM's CRS) and placed **on the DSM surface** (bilinear
between pixel centres, the surface the rays are cast on). A sample seen by a photo (inside its
frame) is *occluded* when the line of sight from the camera centre to the sample meets the
surface more than ``tolerance`` before the sample (:func:`core.raster.first_hits`
with the ray ended at ``distance − tolerance``). ``occluded_fraction`` is the share of the
in-frame samples that are occluded.

**Memory.** When the DSM's tiles would take more than :data:`SURFACE_BYTES` as a ray surface
(a season's DSM), the ROIs are tested band by band of the DSM (:data:`BAND_TILES` tile rows),
and the next band starts on a fresh surface once the tiles held pass that budget.

Why on the surface: the ROI's own vertex heights may lie below the canopy top (a plot at its
ground height, or its mean DSM height); a line of sight to such a point passes through the
ROI's own canopy and would call the ROI occluded by itself. What a photo shows of a ROI is its
visible surface, so the samples are taken there. Samples on DSM nodata are left out; a line
of sight that crosses nodata before the sample cannot be decided and counts as not occluded
(reported). ``tolerance`` (default one DSM pixel, in model units) absorbs the surface right
at the sample: a point on a face turned away from the camera by less than that is visible.
"""
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..crs import as_crs, same_crs, transform_xy
from ..geometry import area as rings_area
from ..geometry import points_in_rings
from ..progress import as_progress
from ..raster import HIT, NODATA, RaySurface, as_dsm, first_hits
from ..raster.ray_surface import TILE as RAY_TILE
from ..reconstruction import INSIDE

MAX_REFINE = 4     # halvings of the grid spacing for thin ROIs with too few samples inside
RAYS_AT_ONCE = 1 << 18   # lines of sight cast per call (bounds the memory of the ray caster)
BAND_TILES = 4           # ROIs are tested band by band of this many ray-surface tile rows
SURFACE_BYTES = 1 << 30  # DSM tiles kept; past it, the next band starts on a fresh ray surface


def sample_grid(rings: List[np.ndarray], n: int) -> np.ndarray:
    """(k, 2) cell centres of a regular grid inside the rings (even-odd), about ``n`` of them."""
    allxy = np.concatenate(rings)
    x0, y0 = allxy.min(axis=0)
    x1, y1 = allxy.max(axis=0)
    a = abs(rings_area(rings))
    if not a > 0:
        return np.zeros((0, 2))
    s = np.sqrt(a / max(n, 1))
    pts = np.zeros((0, 2))
    for _ in range(MAX_REFINE + 1):
        gx = np.arange(x0 + s / 2, x1, s)
        gy = np.arange(y0 + s / 2, y1, s)
        xx, yy = np.meshgrid(gx, gy)
        xx, yy = xx.ravel(), yy.ravel()
        inside = points_in_rings(xx, yy, rings)
        pts = np.column_stack([xx[inside], yy[inside]])
        if len(pts) >= n / 2:
            break
        s /= np.sqrt(2.0)
    return pts


def occluded_fractions(rois, rec_roi: np.ndarray, rec_cam: np.ndarray, recon, cams, dsm,
                       samples: int = 256, tolerance: Optional[float] = None,
                       progress=None) -> Tuple[np.ndarray, List[str]]:
    """Occluded share of each record (ROI ``rec_roi[i]`` in camera ``cams[rec_cam[i]]``);
    NaN where no sample of the ROI is inside the photo. ``dsm``: a :class:`~core.raster.DSM`
    (or a path or ``GeoTiff``). Returns (fractions, notes)."""
    prog = as_progress(progress)
    dsm = as_dsm(dsm)
    surface, banded = _ray_surface(dsm)
    tif = dsm.tif
    dcrs = dsm.crs
    rcrs = as_crs(rois.crs)
    notes: List[str] = []
    need = np.unique(rec_roi)
    # samples per ROI, on the DSM surface, in the DSM's CRS
    starts: Dict[int, Tuple[int, int]] = {}
    xy_all, k = [], 0
    for r in need:
        rings = rois[int(r)].rings
        if dcrs is not None and rcrs is not None and not same_crs(rcrs, dcrs):
            rings = [transform_xy(rcrs, dcrs, ring) for ring in rings]
        pts = sample_grid(rings, samples)
        xy_all.append(pts)
        starts[int(r)] = (k, k + len(pts))
        k += len(pts)
    xy = np.concatenate(xy_all) if xy_all else np.zeros((0, 2))
    z = dsm.heights(xy[:, 0], xy[:, 1]) if len(xy) else np.zeros(0)
    valid = np.isfinite(z)
    empty = [rois[int(r)].name for r in need if not valid[slice(*starts[int(r)])].any()]
    if empty:
        notes.append(f"occlusion not tested for {len(empty)} ROI(s) without DSM data inside: "
                     + ", ".join(map(repr, empty[:10])) + (" …" if len(empty) > 10 else ""))
    xyz = np.column_stack([xy, z])
    model = np.full((len(xy), 3), np.nan)
    if valid.any():
        model[valid] = recon.to_model(xyz[valid], dcrs)
    tol = _tolerance(recon, tif, dcrs) if tolerance is None else float(tolerance)
    # in-frame samples per record (one projection per photo and band); lines of sight cast in
    # batches of RAYS_AT_ONCE across photos, band by band of the DSM, so memory stays bounded
    # whatever the number of pairs and the size of the DSM (see SURFACE_BYTES)
    C = np.array([c.C for c in cams])
    n_in = np.zeros(len(rec_roi), np.int64)
    blocked = np.zeros(len(rec_roi), np.int64)
    band = _roi_bands(need, starts, xy, surface, len(rois)) if banded else \
        np.zeros(len(rois), np.int64)
    state = {"undecided": 0, "surface": surface}
    del surface                       # a replaced surface must not stay referenced here
    pending: List[Tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    queued = [0]

    def cast():
        if not pending:
            return
        owner = np.concatenate([p[0] for p in pending])
        target = np.concatenate([p[1] for p in pending])
        cam_of = np.concatenate([p[2] for p in pending])
        pending.clear()
        queued[0] = 0
        o = C[cam_of]
        d = model[target] - o
        dist = np.linalg.norm(d, axis=1)
        hits = first_hits(state["surface"], recon.frame, o, d / dist[:, None],
                          max_distance=np.maximum(dist - tol, 0.0), is_cancelled=prog.cancelled)
        blocked[:] += np.bincount(owner[hits.status == HIT], minlength=len(rec_roi))
        state["undecided"] += int((hits.status == NODATA).sum())

    key = band[rec_roi] * (int(rec_cam.max(initial=0)) + 1) + rec_cam
    order = np.argsort(key, kind="stable")
    groups = np.split(order, np.flatnonzero(np.diff(key[order])) + 1) if len(order) else []
    one = None
    if len(need) == 1 and groups:     # one ROI (a clicked point): its samples in every photo at once
        a, b = starts[int(need[0])]
        one = recon.project_model_points(
            model[np.arange(a, b)[valid[a:b]]],
            cameras=[cams[int(rec_cam[grp[0]])] for grp in groups]).status == INSIDE
    for g_i, grp in enumerate(groups):
        prog.check()
        cam_i = int(rec_cam[grp[0]])
        if g_i and band[rec_roi[grp[0]]] != band[rec_roi[groups[g_i - 1][0]]]:
            cast()                    # a new band: the tiles of the ones before are not needed
            if surface_bytes(state["surface"]) > SURFACE_BYTES:
                state["surface"] = RaySurface(dsm.tif)
        idx, owner = [], []
        for i in grp:
            a, b = starts[int(rec_roi[i])]
            sel = np.arange(a, b)[valid[a:b]]
            idx.append(sel)
            owner.append(np.full(len(sel), i))
        idx, owner = np.concatenate(idx), np.concatenate(owner)
        if len(idx):
            seen = one[g_i] if one is not None else recon.project_model_points(
                model[idx], cameras=[cams[cam_i]]).status[0] == INSIDE
            np.add.at(n_in, owner[seen], 1)
            pending.append((owner[seen], idx[seen], np.full(int(seen.sum()), cam_i)))
            queued[0] += int(seen.sum())
            if queued[0] >= RAYS_AT_ONCE:
                cast()
        prog.set(100.0 * (g_i + 1) / len(groups))
    cast()
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(n_in > 0, blocked / np.maximum(n_in, 1), np.nan)
    if state["undecided"]:
        notes.append(f"{state['undecided']} line(s) of sight crossed DSM nodata before their "
                     "sample point and were counted as not occluded")
    return out, notes


def _tile_bytes(tile: int, dtype) -> int:
    """Bytes of one ray-surface tile (its cell corners and cell maxima)."""
    return ((tile + 1) ** 2 + tile ** 2) * np.dtype(dtype).itemsize


def surface_bytes(surface) -> int:
    """Bytes of the DSM tiles a ray surface holds."""
    return surface.loaded * _tile_bytes(surface.T, surface.dtype)


def _ray_surface(dsm):
    """(surface, banded): the DSM's own ray surface (kept for later rays) when all its tiles fit
    in SURFACE_BYTES; else one of this call only, replaced band by band as it fills."""
    tif, t = dsm.tif, RAY_TILE
    tiles = -(-(tif.width + 1) // t) * -(-(tif.height + 1) // t)
    dtype = np.float64 if tif.dtype == np.float64 else np.float32   # as RaySurface keeps them
    if tiles * _tile_bytes(t, dtype) <= SURFACE_BYTES:
        return dsm.ray_surface(), False
    return RaySurface(tif), True


def _roi_bands(need, starts, xy, surface, n_rois: int) -> np.ndarray:
    """(n_rois,) band of each ROI: BAND_TILES ray-surface tile rows, by the mean row of its
    samples on the DSM (0 for ROIs without samples). Lines of sight are short next to the
    DSM's size, so the tiles a band's rays read are those of the band and its edges."""
    band = np.zeros(n_rois, np.int64)
    for r in need:
        a, b = starts[int(r)]
        if b > a:
            _, v = surface.map_to_uv(xy[a:b, 0], xy[a:b, 1])
            band[int(r)] = int(np.mean(v) // (surface.T * BAND_TILES))
    return band


def _tolerance(recon, tif, dcrs) -> float:
    """One DSM pixel, in model-frame units, at the DSM's centre."""
    cx, cy = tif.pixel_to_map(np.array([tif.width / 2, tif.width / 2 + 1.0]),
                              np.array([tif.height / 2, tif.height / 2]))
    p = recon.to_model(np.column_stack([cx, cy, [0.0, 0.0]]), dcrs)
    return float(np.linalg.norm(p[1] - p[0]))
