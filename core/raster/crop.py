"""Crop many ROIs out of a GeoTIFF (DOM, DSM, multispectral) in one sweep over its tiles or strips.

Each output is a GeoTIFF on the source's pixel grid, cut to the ROI's bounding box (clipped to
the raster), with the source's CRS and a mask of the pixels outside the ROI:

* one band (DSM) and multiband (multispectral): outside pixels set to nodata, the source's or,
  when it has none, a declared one (-32767 for floats, the type's maximum for unsigned integers,
  its minimum for signed ones);
* RGB: an alpha band is added (255 inside, 0 outside);
* RGBA: the existing alpha is combined with the ROI mask.
"""
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import ROIError
from ..files import OutputFolder
from ..naming import unique_names
from ..progress import as_progress
from ..roi import ROISet
from .geotiff import GeoTiff, open_geotiff
from .geotiff_write import write_geotiff
from .roi_pixels import NO_PIXEL, bounding_box, place_rois, require_overlap, rois_in_raster_crs
from .sweep import sweep_windows, thread_pool

MAX_PENDING_WRITES = 32


@dataclass
class RasterCropResult:
    """The files :func:`crop_raster_by_rois` wrote, sorted by path, and the ROIs it skipped."""

    files: List[str] = field(default_factory=list)
    names: List[str] = field(default_factory=list)        # ROI name of each file
    rois: List[int] = field(default_factory=list)         # ROI index of each file
    skipped: Dict[int, str] = field(default_factory=dict)  # ROI index -> reason
    nodata: Optional[float] = None
    notes: List[str] = field(default_factory=list)         # problems met reading the raster


def declared_nodata(tif: GeoTiff):
    """(value, text) of the nodata written to crops of ``tif``: its own, or a sensible one."""
    if tif.nodata is not None:
        return tif.nodata, tif.nodata_text
    dt = tif.dtype
    if dt.kind == "f":
        value = -32767.0
    elif dt.kind == "u":
        value = float(np.iinfo(dt).max)
    else:
        value = float(np.iinfo(dt).min)
    return value, repr(value) if dt.kind == "f" else str(int(value))


@renamed_parameters(raster_crs="source_crs")
def crop_raster_by_rois(raster: str, rois: ROISet, output_folder: str, all_touched: bool = False,
                        source_crs=None, overwrite: bool = False, progress=None, is_cancelled=None,
                        workers: Optional[int] = None) -> RasterCropResult:
    """Crop every ROI out of ``raster`` into ``output_folder/<name>.tif``.

    ROIs are reprojected to the raster's CRS when they differ. A pixel belongs to an ROI when
    its centre is inside ([Conventions](../background/conventions.md)). File names are the ROI
    names made safe and unique. The output folder is checked and locked before any work
    (:class:`..files.OutputFolder`); every file is written atomically, so a cancelled or failed
    run leaves only complete files.

    Parameters
    ----------
    raster : str or path
        A GeoTIFF: orthomosaic, DSM or multispectral map.
    rois : ROISet
        The ROIs; those that miss the raster are listed in ``result.skipped``.
    output_folder : str or path
        The folder the crops are written into.
    all_touched : bool
        Also take the pixels the ROI only touches.
    source_crs : CRS, optional
        The CRS to assume for the raster, instead of the one its GeoKeys give.
    overwrite : bool
        Replace this run's earlier outputs; without it an existing file stops the run before any
        work, listing the names taken. The input is never replaced.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    workers : int, optional
        Threads that decode and write (default: the CPU count).

    Returns
    -------
    RasterCropResult
        The files written, sorted by path, and the ROIs skipped with the reason.

    Raises
    ------
    ROIError
        When no ROI overlaps the raster or none contains a pixel centre.
    """
    prog = as_progress(progress, is_cancelled)
    tif = open_geotiff(raster, crs=source_crs)
    rois = rois_in_raster_crs(rois, tif)
    placed, skipped = place_rois(tif, rois, all_touched)
    require_overlap(placed, skipped, rois, tif)
    with OutputFolder(output_folder, overwrite=overwrite, inputs=[raster]) as out:
        stems = unique_names(p.roi.name for p in placed)
        paths = [str(p) for p in out.claim(s + ".tif" for s in stems)]
        result = _crop(tif, placed, skipped, paths, prog, workers)
    if not result.files:
        raise ROIError(f"None of the {len(rois)} ROIs contains a pixel centre of {raster}: they are "
                       "smaller than a pixel or lie on its edges. Use all-touched to include them.")
    order = sorted(range(len(result.files)), key=lambda j: result.files[j])
    result.files = [result.files[j] for j in order]
    result.names = [result.names[j] for j in order]
    result.rois = [result.rois[j] for j in order]
    return result


def _crop(tif: GeoTiff, placed, skipped, paths, prog, workers) -> RasterCropResult:
    """The sweep: mask each window as it completes and hand it to a pool of writers."""
    nodata, nodata_text = declared_nodata(tif)
    kind = tif.kind
    result = RasterCropResult(skipped=skipped, nodata=None if kind == "rgb" else nodata,
                        notes=list(tif.notes))
    pending = []

    def finish(k: int, arr: np.ndarray) -> None:
        p = placed[k]
        mask = p.mask()
        box = bounding_box(mask)   # the crop is the bounding box of the ROI's pixels
        if box is None:
            skipped[p.index] = NO_PIXEL
            return
        r0, r1, c0, c1 = box
        mask, arr = mask[r0:r1, c0:c1], arr[r0:r1, c0:c1]
        gt = tif.window_geotransform(p.window.row + r0, p.window.col + c0)
        if kind == "rgb":
            out = np.empty(arr.shape[:2] + (4,), np.uint8)
            np.multiply(arr, mask[..., None], out=out[..., :3])
            np.multiply(mask, 255, out=out[..., 3], casting="unsafe")
            job = (paths[k], out, gt, tif.geo_tags, None, True, (2,))
        elif kind == "rgba":
            arr[..., tif.alpha_band] *= mask
            extras = (0,) * (tif.bands - 4) + (2,) if tif.bands >= 4 and tif.photometric == 2 else \
                (0,) * (tif.bands - 2) + (2,)
            job = (paths[k], arr, gt, tif.geo_tags, tif.nodata_text, tif.photometric == 2, extras)
        else:
            np.copyto(arr, np.asarray(nodata, dtype=arr.dtype), where=~mask[..., None])
            job = (paths[k], arr, gt, tif.geo_tags, nodata_text, False, ())
        pending.append((k, pool.submit(write_geotiff, *job, is_cancelled=prog.cancelled)))
        while len(pending) > MAX_PENDING_WRITES:
            _collect(pending.pop(0))

    def _collect(item) -> None:
        k, fut = item
        result.files.append(fut.result())
        result.names.append(placed[k].roi.name)
        result.rois.append(placed[k].index)

    with thread_pool(workers) as pool:  # writers; the sweep has its own pool of decoders
        try:
            sweep_windows(tif, [p.window for p in placed], finish, prog, workers)
            for item in pending:
                _collect(item)
            prog.check()        # a cancel during the last writes: the run is not reported done
        except BaseException:   # also Cancelled: finish or drop pending writes, then re-raise
            for k, fut in pending:
                fut.cancel()
            for k, fut in pending:
                if not fut.cancelled():
                    try:
                        fut.result()
                    except BaseException:
                        pass
            raise
    return result
