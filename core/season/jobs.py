"""One job = one file of one survey (an orthomosaic, a DSM, a point cloud) or the season's
ground raster: every ROI's traits from it in one pass, on whichever process runs it.

:func:`run_job` is a plain top-level function of plain, picklable data, so any executor runs
it: a local process pool or Dask workers (which must be able to import
``easyidp_toolbox.core``). Errors caused by the input (:class:`EasyIDPError`: a corrupt
raster, a CRS that cannot be related to the ROIs, no ROI over the data) come back in
``JobResult.error`` and are reported by row; the season goes on.
"""
import os
import socket
import sys
import time
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..crs import same_crs, transform_xy
from ..errors import Cancelled, EasyIDPError
from ..pointcloud import crop_indices, crop_point_cloud, read_point_cloud
from ..progress import Progress
from ..raster import (NO_PIXEL, GeoTiff, crop_raster_by_rois, open_geotiff, place_rois,
                      require_overlap, rois_in_raster_crs, sweep_windows, valid_heights)
from ..roi import ROISet
from . import traits as tr
from .. import indices
from .ground import Plane, fit_plane, low_plane

KINDS = ("ground", "orthomosaic", "dsm", "point_cloud")


@dataclass
class Job:
    """What one job computes. ``kind``: 'ground' (the season's DTM → a plane per ROI),
    'orthomosaic', 'dsm' or 'point_cloud'. ``ground``: one plane per ROI (from the ground job)
    or None (each ROI's own low points, ``ground_percentile``). ``crops``: a folder for the
    crops of this file, or None. ``cancel_file``: the job stops when this file exists.
    ``threads``: decoding threads (default: the cores)."""
    key: str
    kind: str
    path: str
    rois: ROISet
    row: int = 0
    date: str = ""
    crs: Optional[str] = None
    bands: Optional[Tuple[str, ...]] = None
    traits: Tuple[str, ...] = tr.TRAIT_GROUPS
    percentiles: Tuple[float, ...] = tr.DEFAULT_PERCENTILES
    ground: Optional[List[Optional[Plane]]] = None
    ground_percentile: float = 2.0
    cover_threshold: Optional[float] = None
    crops: Optional[str] = None
    overwrite: bool = False
    cancel_file: Optional[str] = None
    threads: Optional[int] = None


@dataclass
class JobResult:
    """``values``: ROI index → {trait: value}; ``planes``: the ground job's planes (by ROI
    index); ``skipped``: ROI name → why it has no value; ``notes``: facts worth a log line
    (e.g. the cover threshold); ``error``: why the whole file was left out. ``worker``:
    host:pid that ran it, ``peak_mb``: that process's peak resident memory so far."""
    key: str
    kind: str
    row: int
    date: str
    path: str
    values: Dict[int, Dict[str, float]] = field(default_factory=dict)
    planes: Optional[List[Optional[Plane]]] = None
    skipped: Dict[str, str] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)
    error: Optional[str] = None
    seconds: float = 0.0
    worker: str = ""
    peak_mb: Optional[float] = None


def run_job(job: Job) -> JobResult:
    """Compute one job (see :class:`Job`). Raises only on cancellation or a bug."""
    t0 = time.perf_counter()
    res = JobResult(job.key, job.kind, job.row, job.date, job.path)
    cancel = job.cancel_file
    prog = Progress(None, (lambda: os.path.exists(cancel)) if cancel else None)
    try:
        {"ground": _ground, "orthomosaic": _orthomosaic, "dsm": _dsm,
         "point_cloud": _point_cloud}[job.kind](job, res, prog)
    except Cancelled:
        raise
    except EasyIDPError as exc:
        res.error = str(exc)
        res.values, res.planes = {}, None
    res.seconds = time.perf_counter() - t0
    res.worker = f"{socket.gethostname()}:{os.getpid()}"
    res.peak_mb = peak_memory_mb()
    return res


def peak_memory_mb() -> Optional[float]:
    """This process's peak resident set size in MiB (None where the OS does not say)."""
    try:
        import resource
    except ImportError:   # Windows
        return None
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / (1024.0 * 1024.0) if sys.platform == "darwin" else peak / 1024.0


# ---- helpers ----------------------------------------------------------------------------------

def _to_roi_crs(src_crs, rois: ROISet):
    """(x, y) → (x, y) in the ROIs' CRS from ``src_crs`` (identity when they agree)."""
    if src_crs is None or rois.crs is None or same_crs(src_crs, rois.crs):
        return lambda x, y: (x, y)

    def f(x, y):
        xy = transform_xy(src_crs, rois.crs, np.column_stack([x, y]))
        return xy[:, 0], xy[:, 1]
    return f


def _centre(roi) -> Tuple[float, float]:
    x0, y0, x1, y1 = roi.bounds
    return (x0 + x1) / 2.0, (y0 + y1) / 2.0


def _placed(tif: GeoTiff, rois: ROISet):
    local = rois_in_raster_crs(rois, tif)
    placed, skipped = place_rois(tif, local)
    require_overlap(placed, skipped, local, tif)
    return placed, skipped


def _pixel_xy(tif: GeoTiff, window, flat: np.ndarray):
    """Map coordinates of the centres of window pixels given by flat (row-major) indices."""
    rr, cc = np.divmod(flat, window.cols)
    return tif.pixel_to_map(window.col + cc + 0.5, window.row + rr + 0.5)


def _take(arr: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """The values (n, bands) of a window array at flat pixel indices (a fast gather)."""
    return np.take(arr.reshape(-1, arr.shape[-1]), flat, axis=0)


def _single_band(tif: GeoTiff, what: str) -> None:
    if tif.bands != 1:
        raise EasyIDPError(f"The {what} {tif.path} has {tif.bands} bands; it must have exactly one "
                           "(heights). Check the table's column.")


# ---- the four kinds ---------------------------------------------------------------------------

def _ground(job: Job, res: JobResult, prog: Progress) -> None:
    """A plane per ROI through the ground raster's valid pixels inside it."""
    tif = open_geotiff(job.path, crs=job.crs)
    _single_band(tif, "ground raster")
    placed, res.skipped = _placed(tif, job.rois)
    to_roi = _to_roi_crs(tif.crs, job.rois)
    planes: List[Optional[Plane]] = [None] * len(job.rois)

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        flat = np.flatnonzero(p.mask() & valid_heights(tif, arr[..., 0]))
        if not len(flat):
            res.skipped[p.roi.name] = "no valid pixel of the ground raster inside it"
            return
        x, y = to_roi(*_pixel_xy(tif, p.window, flat))
        planes[p.index] = fit_plane(x, y, _take(arr, flat)[:, 0], _centre(job.rois[p.index]))

    sweep_windows(tif, [p.window for p in placed], consume, prog, job.threads)
    res.planes = planes


def _dsm(job: Job, res: JobResult, prog: Progress) -> None:
    """height_pNN above the ground plane of each ROI."""
    tif = open_geotiff(job.path, crs=job.crs)
    _single_band(tif, "DSM")
    placed, res.skipped = _placed(tif, job.rois)
    to_roi = _to_roi_crs(tif.crs, job.rois)

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        mask = p.mask()
        flat = np.flatnonzero(mask & valid_heights(tif, arr[..., 0]))
        if not len(flat):
            res.skipped[p.roi.name] = NO_PIXEL if not mask.any() else "all DSM pixels inside it are nodata"
            return
        x, y = to_roi(*_pixel_xy(tif, p.window, flat))
        z = _take(arr, flat)[:, 0].astype(np.float64)
        plane = _plane(job, p.index, x, y, z)
        if plane is None:
            res.skipped[p.roi.name] = "no ground under it (the ground raster has no pixel there)"
            return
        res.values[p.index] = tr.height_percentiles(z - plane.at(x, y), job.percentiles, "height")

    sweep_windows(tif, [p.window for p in placed], consume, prog, job.threads)
    _crop_raster(job, res, prog)


def _plane(job: Job, index: int, x, y, z) -> Optional[Plane]:
    if job.ground is not None:
        return job.ground[index]
    return low_plane(x, y, z, job.ground_percentile, _centre(job.rois[index]))


def _orthomosaic(job: Job, res: JobResult, prog: Progress) -> None:
    """Band means, the vegetation index and canopy cover of each ROI."""
    tif = open_geotiff(job.path, crs=job.crs)
    names = tr.band_names(tif, job.bands)
    colour = [b for b in range(tif.bands) if b != tif.alpha_band]
    kind = indices.cover_kind(names)
    want_cover = "cover" in job.traits and kind is not None
    want_index = "index" in job.traits and kind is not None
    if kind is None and ("cover" in job.traits or "index" in job.traits):
        res.notes.append(f"no vegetation index or cover: the bands ({', '.join(names)}) are not "
                         "named red, green, blue or red and nir; name them in a 'bands' column")
    placed, res.skipped = _placed(tif, job.rois)
    nodata = None if tif.nodata is None else np.asarray(tif.nodata, dtype=tif.dtype)
    hists: Dict[int, tuple] = {}
    threshold = job.cover_threshold

    def consume(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        mask = p.mask()
        ok = mask.copy()
        if tif.alpha_band is not None:
            ok &= arr[..., tif.alpha_band] > 0
        if nodata is not None:
            ok &= ~np.all(arr[..., colour] == nodata, axis=-1)
        if tif.dtype.kind == "f":
            ok &= np.all(np.isfinite(arr[..., colour]), axis=-1)
        if not ok.any():
            res.skipped[p.roi.name] = NO_PIXEL if not mask.any() else "all pixels inside it are nodata"
            return
        v = _take(arr, np.flatnonzero(ok))
        bands = np.ascontiguousarray(v.T[colour], dtype=np.float64)   # (bands, n): fast sums
        out: Dict[str, float] = {}
        if "bands" in job.traits:
            means = bands.sum(axis=1) / bands.shape[1]
            out.update({f"mean_{n}": float(m) for n, m in zip(names, means)})
        if want_index or want_cover:
            idx = indices.compute(kind, bands, names)
            if want_index:
                finite = idx[np.isfinite(idx)]
                out[kind] = float(finite.mean()) if len(finite) else float("nan")
            if want_cover:
                if threshold is None:
                    hists[p.index] = indices.index_histogram(kind, idx)
                else:
                    finite = idx[np.isfinite(idx)]
                    out["cover"] = indices.cover(finite, threshold)
        res.values[p.index] = out

    sweep_windows(tif, [p.window for p in placed], consume, prog, job.threads)
    if want_cover and threshold is None:
        total = np.zeros(indices.INDEX_BINS, np.int64)
        for h in hists.values():
            indices.add_histogram(total, h)
        t = indices.otsu_threshold(kind, total)
        if t is None:
            res.notes.append(f"cover: Otsu's threshold is undefined (the {kind} values of the "
                             "ROIs are all alike); give a threshold")
        else:
            res.notes.append(f"cover threshold {t:.3f} ({kind.upper()}, Otsu over "
                             f"{int(total.sum()):,} pixels)")
            for i, h in hists.items():
                res.values[i]["cover"] = indices.cover_from_histogram(kind, h, t)
    _crop_raster(job, res, prog)


def _point_cloud(job: Job, res: JobResult, prog: Progress) -> None:
    """cloud_points and cloud_height_pNN above the ground plane of each ROI."""
    cloud = read_point_cloud(job.path, job.crs)
    idx, _, local = crop_indices(cloud, job.rois, progress=prog)
    if not any(len(ii) for ii in idx):
        raise EasyIDPError(f"None of the {len(job.rois)} ROIs contains a point of "
                           f"{os.path.basename(job.path)}: check that the cloud and the ROIs are "
                           "in the right CRS (give a 'crs' column for files without one).")
    to_roi = _to_roi_crs(cloud.crs, job.rois)
    for i, ii in enumerate(idx):
        out: Dict[str, float] = {"cloud_points": float(len(ii))}
        plane = None
        if len(ii):
            xyz = cloud.take(ii).xyz
            x, y = to_roi(xyz[:, 0], xyz[:, 1])
            plane = _plane(job, i, x, y, xyz[:, 2])
        if plane is None:
            out.update(tr.height_percentiles(np.zeros(0), job.percentiles, "cloud_height"))
            if len(ii):
                res.skipped[job.rois[i].name] = "no ground under it"
        else:
            out.update(tr.height_percentiles(xyz[:, 2] - plane.at(x, y), job.percentiles,
                                             "cloud_height"))
        res.values[i] = out
    if job.crops:
        crop_point_cloud(cloud, job.rois, job.crops, overwrite=job.overwrite, progress=prog)


def _crop_raster(job: Job, res: JobResult, prog: Progress) -> None:
    """The optional crops of this raster (a second sweep, only when asked)."""
    if not job.crops:
        return
    crop_raster_by_rois(job.path, job.rois, job.crops, source_crs=job.crs,
                        overwrite=job.overwrite, progress=prog, workers=job.threads)
