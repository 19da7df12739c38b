"""Which pixels of a ROI in a photo show the ROI: the per-pixel occlusion test of plot statistics.

**Rule.** A pixel inside a ROI's polygon in a photo (its centre inside: the raster rule) shows the
ROI when the line of sight through its centre (:meth:`Reconstruction.pixel_to_ray`, lens
distortion inverted) first meets the DSM (:func:`core.raster.first_hits`, the exact bilinear
surface) inside the ROI, or within ``tolerance`` (default one DSM pixel) of its boundary, in the
DSM's CRS. Otherwise the pixel shows something in front of the ROI (a tree, the next plot's
canopy, a wall), or beyond it: it is *occluded* and left out. A line of sight that enters DSM
nodata, leaves the DSM or misses it cannot be decided: the pixel is kept and counted as
*undecided*.

**Sampling.** Rays are cast adaptively, for all the ROIs of a photo at once. First on a grid of
square cells of ``s0`` px (a power of two giving about ``coarse`` cells per ROI), one ray per cell
through a pixel of the polygon in it (the cell's centre pixel when it is inside); every pixel of
the cell takes that verdict. Then every cell with a neighbour (8-connected) of another verdict is
split in four, each quarter with its own ray, down to single pixels. So the boundary of an
occluded region is found to the pixel wherever the coarse grid sees the region; a region that no
coarse sample meets (narrower than about ``s0`` px) is missed, the same limit as the backward
projection's ``occlusion_samples`` points per ROI. A ROI with nothing occluded costs about
``coarse`` rays per photo.
"""
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..crs import as_crs, same_crs, transform_xy
from ..errors import Cancelled
from ..geometry import distance_to_rings, points_in_rings
from ..raster import HIT, RaySurface, first_hits

COARSE_SAMPLES = 256
"""Cells of the first grid per ROI (its spacing is the power of two closest to
sqrt(pixels / COARSE_SAMPLES))."""
VISIBLE, OCCLUDED, UNDECIDED, EMPTY = 0, 1, 2, -1


@dataclass
class PixelJob:
    """One ROI in one photo: ``mask`` (h, w) the pixels inside its polygon, the window's top-left
    pixel ``(r0, c0)`` in the photo, ``roi`` its index (for its rings)."""
    roi: int
    r0: int
    c0: int
    mask: np.ndarray
    occluded: Optional[np.ndarray] = None      # (h, w) bool, after :func:`test_pixels`
    undecided: int = 0
    rays: int = 0
    _s: int = 1
    _lab: Optional[np.ndarray] = None
    _want: Optional[np.ndarray] = None           # (ny, nx) cells to sample this round
    _rc: tuple = field(default_factory=tuple)    # (rows, cols) of the samples of this round


def _cells(mask: np.ndarray, s: int):
    """(has, rows, cols) per cell of s × s px: whether it holds a pixel of the mask, and the
    window pixel its ray goes through (the centre pixel when inside, else the first inside)."""
    h, w = mask.shape
    ny, nx = -(-h // s), -(-w // s)
    pad = np.zeros((ny * s, nx * s), bool)
    pad[:h, :w] = mask
    blk = pad.reshape(ny, s, nx, s).transpose(0, 2, 1, 3).reshape(ny, nx, s * s)
    has = blk.any(axis=2)
    centre = (s // 2) * s + s // 2
    pick = np.where(blk[:, :, centre], centre, blk.argmax(axis=2))
    rows = np.arange(ny)[:, None] * s + pick // s
    cols = np.arange(nx)[None, :] * s + pick % s
    return has, rows, cols


def _boundary(lab: np.ndarray) -> np.ndarray:
    """Cells with a verdict whose 8-neighbourhood holds another verdict."""
    pad = np.full((lab.shape[0] + 2, lab.shape[1] + 2), EMPTY, lab.dtype)
    pad[1:-1, 1:-1] = lab
    out = np.zeros(lab.shape, bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy or dx:
                nb = pad[1 + dy:1 + dy + lab.shape[0], 1 + dx:1 + dx + lab.shape[1]]
                out |= (nb != EMPTY) & (nb != lab)
    return out & (lab != EMPTY)


def _start(job: PixelJob, coarse: int) -> None:
    n = int(job.mask.sum())
    s = 1
    while s * 2 <= max(1.0, np.sqrt(n / max(coarse, 1))) * np.sqrt(2):
        s *= 2
    job._s = s
    has, rows, cols = _cells(job.mask, s)
    job._lab = np.where(has, UNDECIDED, EMPTY).astype(np.int8)
    job._want = has
    job._rc = (rows[has], cols[has])


def _advance(job: PixelJob, verdict: np.ndarray) -> None:
    """Take this round's verdicts; plan the next round (or finish)."""
    job._lab[job._want] = verdict
    job.rays += len(verdict)
    if job._s > 1:
        split = _boundary(job._lab)
        if split.any():
            s = job._s // 2
            has, rows, cols = _cells(job.mask, s)
            ny, nx = has.shape
            lab = np.repeat(np.repeat(job._lab, 2, 0), 2, 1)[:ny, :nx]
            want = np.repeat(np.repeat(split, 2, 0), 2, 1)[:ny, :nx] & has
            lab[~has] = EMPTY
            job._s, job._lab, job._want = s, lab, want
            job._rc = (rows[want], cols[want])
            return
    s = job._s
    h, w = job.mask.shape
    pix = np.repeat(np.repeat(job._lab, s, 0), s, 1)[:h, :w]
    job.occluded = (pix == OCCLUDED) & job.mask
    job.undecided = int(((pix == UNDECIDED) & job.mask).sum())
    job._lab = job._want = None
    job._rc = ()


def test_pixels(jobs: Sequence[PixelJob], recon, camera, surface: RaySurface,
                rings_dsm: Dict[int, List[np.ndarray]], *, distortion: bool = True,
                tolerance: Optional[float] = None, coarse: int = COARSE_SAMPLES,
                is_cancelled=None) -> None:
    """Fill ``occluded`` and ``undecided`` of the ``jobs`` (ROIs of one photo, ``camera``) by
    the rule of the module docstring. ``rings_dsm``: {roi: its rings in the DSM's CRS}."""
    tol = abs(float(surface.tif.geotransform[1])) if tolerance is None else float(tolerance)
    active = [j for j in jobs if j.mask.any()]
    for j in jobs:
        if not j.mask.any():
            j.occluded = np.zeros(j.mask.shape, bool)
    for j in active:
        _start(j, coarse)
    while active:
        if is_cancelled is not None and is_cancelled():
            raise Cancelled("cancelled")
        uv = np.concatenate([np.column_stack([j._rc[1] + j.c0 + 0.5, j._rc[0] + j.r0 + 0.5])
                             for j in active])
        counts = [len(j._rc[0]) for j in active]
        origin, d = recon.pixel_to_ray(camera, uv, distortion)
        hits = first_hits(surface, recon.frame, origin, d, is_cancelled=is_cancelled)
        k = 0
        for j, n in zip(active, counts):
            st = hits.status[k:k + n]
            xy = hits.xyz[k:k + n, :2]
            k += n
            verdict = np.full(n, UNDECIDED, np.int8)
            hit = st == HIT
            if hit.any():
                rings = rings_dsm[j.roi]
                inside = points_in_rings(xy[hit, 0], xy[hit, 1], rings)
                if (~inside).any():
                    near = distance_to_rings(xy[hit, 0][~inside], xy[hit, 1][~inside], rings) <= tol
                    inside[np.flatnonzero(~inside)[near]] = True
                verdict[hit] = np.where(inside, VISIBLE, OCCLUDED)
            _advance(j, verdict)
        active = [j for j in active if j.occluded is None]


def rings_in_dsm_crs(rois, surface: RaySurface, which: Sequence[int]) -> Dict[int, List[np.ndarray]]:
    """{roi index: its rings in the DSM's CRS} for the ROIs ``which``."""
    dcrs, rcrs = surface.crs, as_crs(rois.crs)
    out = {}
    for r in which:
        rings = rois[int(r)].rings
        if dcrs is not None and rcrs is not None and not same_crs(rcrs, dcrs):
            rings = [transform_xy(rcrs, dcrs, ring) for ring in rings]
        out[int(r)] = rings
    return out
