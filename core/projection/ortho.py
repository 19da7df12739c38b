"""Orthorectified ROI images from the raw photos: true geometry, the photo's own sharpness.

For each ROI and photo: a north-up map grid over the ROI in the DSM's CRS (``gsd`` given, or
the photo's native ground resolution at the ROI); each output pixel centre gets its height
from the DSM (bilinear between pixel centres), is projected into the photo with the solved
camera (``Reconstruction.project_points``, lens distortion included) and the photo is sampled
there bilinearly (``scipy.ndimage.map_coordinates``, order 1). Output pixels outside the ROI,
on DSM nodata, outside the photo's frame, or whose line of sight to the camera the DSM blocks
(:func:`core.raster.first_hits`, the first hit more than ``occlusion_tolerance`` before the
point) get alpha 0. GeoTIFF (the photo's bands and data type, plus an alpha band), written
atomically with the DSM's georeferencing keys.

``values`` temperature or reflectance (:func:`..radiometry.read_photo_values`, the one place
where pixels become physical values): float32 GeoTIFF of those values plus the alpha band, the
unit and what was applied in GDAL's metadata (:mod:`..radiometry.output_tags`); NaN (the
nodata, alpha 0) where no value is shown, and where the bilinear sample touches a pixel that
is not valid (saturated, unreadable: masked, never averaged in).

Photos: ``best`` (the backward projection's best-scored photo per ROI,
:func:`.backward.back_project`), ``all`` (every photo that sees the ROI) or ``photo`` (one
named photo).
"""
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError, InputError
from ..files import OutputFolder
from ..geometry import rasterize
from ..naming import unique_names
from ..photos import DecodedPhotos, resolve_photos
from ..progress import as_progress
from ..radiometry import NODATA_TEXT, PhotoValues, gdal_metadata, photo_decoder
from ..raster import (HIT, MISS, TAG_GDAL_METADATA, RaySurface, as_dsm, first_hits,
                      rois_in_raster_crs, write_geotiff)
from ..roi import ROISet
from .backward import back_project

SELECTIONS = ("best", "all", "photo")
MAX_PIXELS = 50_000_000        # output pixels per ROI image
EXTRASAMPLE_ALPHA = 2          # TIFF ExtraSamples: unassociated alpha


@dataclass
class OrthoResult:
    """``files``/``rois``/``indices``/``photos``/``visible``: one entry per image written
    (``indices``: the ROI's position in the set given; ``visible`` = share of the ROI's output
    pixels that the photo shows); ``skipped``: ROI (or ROI × photo)
    → why no image was written; ``occluded``: share of the ROI's pixels inside the frame that
    the DSM hides from the photo; ``gsd``: output pixel size per image (DSM CRS units)."""
    files: List[str] = field(default_factory=list)
    rois: List[str] = field(default_factory=list)
    indices: List[int] = field(default_factory=list)
    photos: List[str] = field(default_factory=list)
    visible: List[float] = field(default_factory=list)
    occluded: List[float] = field(default_factory=list)
    gsd: List[float] = field(default_factory=list)
    skipped: Dict[str, str] = field(default_factory=dict)


def _metres_per_unit(surface: RaySurface) -> float:
    crs = surface.crs
    if crs is not None and crs.is_geographic:
        return 111_320.0
    if crs is not None and crs.axis_info and crs.axis_info[0].unit_conversion_factor:
        return float(crs.axis_info[0].unit_conversion_factor)
    return 1.0


def _native_gsd(recon, cam, x, y, z, crs) -> float:
    """Ground size (DSM CRS units) of one photo pixel at (x, y, z): the square root of the
    area of the map patch one pixel covers there."""
    d = 1e-6 if crs is not None and crs.is_geographic else 0.05
    pts = np.array([[x, y, z], [x + d, y, z], [x, y + d, z]])
    uv = recon.project_points(pts, crs, cameras=[cam]).pixels[0]
    J = np.column_stack([uv[1] - uv[0], uv[2] - uv[0]]) / d
    det = abs(np.linalg.det(J))
    if not np.isfinite(det) or det == 0:
        return float("nan")
    return float(1.0 / np.sqrt(det))


@renamed_parameters(dsm_crs="source_crs")
def orthorectify_rois(rois: ROISet, recon, dsm, output_folder, *, selection: str = "best",
                      photo=None, photos_folder=None, gsd: Optional[float] = None,
                      occlusion: bool = True, occlusion_tolerance: Optional[float] = None,
                      source_crs=None, overwrite: bool = False, progress=None,
                      is_cancelled=None, values: str = "stored",
                      value_options: Optional[dict] = None) -> OrthoResult:
    """Orthorectify every ROI from raw photos (see the module docstring).

    Files are named ``<roi>.tif`` (``best``, ``photo``) or ``<roi>_<photo>.tif`` (``all``); the
    folder is guarded as every output folder is (:class:`..files.OutputFolder`). Photos
    missing or not of the camera's size are skipped, with the reason in ``skipped``.

    Parameters
    ----------
    rois : ROISet
        The ROIs.
    recon : Reconstruction
        The opened project.
    dsm : DSM, GeoTiff or path
        The DSM the photos are draped on.
    output_folder : str or path
        The folder the GeoTIFFs are written into.
    selection : {"best", "all", "photo"}
        The best photo of each ROI, every photo that sees it, or the one named ``photo``.
    photo : str, optional
        The camera label, for ``selection="photo"``.
    photos_folder : str or path, optional
        The folder the photos are in now (default: the paths stored in the project).
    gsd : float, optional
        The output pixel size in DSM CRS units (default: the photo's native one at the ROI).
    occlusion : bool
        Leave out the DSM cells the photo does not see.
    occlusion_tolerance : float, optional
        Metres (default: one DSM pixel).
    source_crs : CRS, optional
        The CRS to assume for the DSM, instead of the one its GeoKeys give.
    overwrite : bool
        Replace this run's earlier outputs.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    values : {"stored", "temperature", "reflectance"}
        The photo's values as stored (its bands and data type), or in physical units: float32
        in °C or reflectance (see the module docstring; a photo that holds no such values is
        skipped, with why).
    value_options : dict, optional
        The options of ``values`` (object parameters, temperature TIFF scale:
        :func:`..radiometry.read_photo_values`).

    Returns
    -------
    OrthoResult
        The files written and the ROIs or photos skipped with the reason.
    """
    if selection not in SELECTIONS:
        raise EasyIDPError(f"selection must be one of {SELECTIONS}, not {selection!r}.")
    if selection == "photo" and not photo:
        raise InputError("Orthorectify from a named photo: give the photo's label.")
    if gsd is not None and not gsd > 0:
        raise InputError(f"The output pixel size (GSD) must be positive, not {gsd}.")
    decoding = (values, photo_decoder(values, value_options))
    prog = as_progress(progress, is_cancelled)
    dsm = as_dsm(dsm, source_crs)
    surface = dsm.ray_surface()
    tif = dsm.tif
    local = rois_in_raster_crs(rois, tif)
    result = OrthoResult()
    # which photos for which ROI
    pairs: List[tuple] = []
    if selection == "photo":
        cam = recon.select_cameras([photo])[0]
        pairs = [(r, cam) for r in range(len(rois))]
    else:
        bp = back_project(rois, recon, heights=dsm, min_visible=0.0,
                          max_views=1 if selection == "best" else 0,
                          progress=prog.sub(0, 10))
        cams = {c.label: c for c in recon.cameras}
        for i in range(len(bp)):
            pairs.append((int(bp.roi[i]), cams[str(bp.photo[i])]))
        for name, why in bp.unseen.items():
            result.skipped[name] = why
    names = [r.name for r in rois]
    stems = unique_names([names[r] if selection != "all" else f"{names[r]}_{os.path.splitext(c.label)[0]}"
                          for r, c in pairs])
    tol = occlusion_tolerance if occlusion_tolerance is not None else \
        abs(tif.geotransform[1]) * _metres_per_unit(surface)
    by_photo: Dict[str, list] = {}
    for k, (r, cam) in enumerate(pairs):
        by_photo.setdefault(cam.label, []).append(k)
    cams = {cam.label: cam for _, cam in pairs}
    found, missing = resolve_photos(list(by_photo), [cams[lab].photo_path for lab in by_photo],
                                    photos_folder)
    with OutputFolder(output_folder, overwrite=overwrite, inputs=[tif.path]) as out:
        paths = [str(p) for p in out.claim(s + ".tif" for s in stems)]
        _render_all(by_photo, found, missing, pairs, cams, paths, local, names, recon, surface,
                    gsd, occlusion, tol, result, prog, decoding)
    if not result.files and result.skipped:
        what, why = next(iter(result.skipped.items()))
        raise InputError(f"No ROI image was written: {what}: {why}"
                         + (f" (and {len(result.skipped) - 1} more)" if len(result.skipped) > 1 else "")
                         + ".")
    return result


def _render_all(by_photo, found, missing, pairs, cams, paths, local, names, recon, surface, gsd,
                occlusion, tol, result, prog, decoding=("stored", None)) -> None:
    """Decode each photo once (:class:`.photos.DecodedPhotos`, the pass every consumer of
    pixels shares; ``decoding``: (values, decoder of :func:`..radiometry.photo_decoder`)) and
    write the images of the ROIs it was chosen for."""
    done = 0
    labels = list(by_photo)
    sensors = [recon.sensors[cams[label].sensor_id] for label in labels]
    with DecodedPhotos([found.get(label) for label in labels],
                       [(s.width, s.height) for s in sensors],
                       missing=[missing.get(label, "") for label in labels],
                       decode=decoding[1]) as decoded:
        for i, image, why in decoded:
            prog.check()
            physical = None
            if isinstance(image, PhotoValues):          # physical values: NaN where invalid
                physical, image = (decoding[0], image), image.masked()
            label = labels[i]
            ks = by_photo[label]
            whys = [why] * len(ks) if why else _render(
                [(local[pairs[k][0]], paths[k]) for k in ks], recon, cams[label],
                image[..., None] if image.ndim == 2 else image, surface, gsd, occlusion, tol,
                result, physical)
            for k, why_k in zip(ks, whys):
                r = pairs[k][0]
                if why_k:
                    result.skipped[f"{names[r]} / {label}"] = why_k
                else:
                    result.rois.append(names[r])
                    result.indices.append(r)
                    result.photos.append(label)
            done += len(ks)
            prog.set(10 + 90.0 * done / max(len(pairs), 1))


def line_of_sight(recon, cam, surface: RaySurface, p: np.ndarray, tol: float) -> np.ndarray:
    """True where the straight line from the camera centre to model point ``p`` meets the DSM
    no earlier than ``tol`` before the point (or not at all)."""
    d = p - cam.C
    dist = np.linalg.norm(d, axis=1)
    hits = first_hits(surface, recon.frame, cam.C, d / dist[:, None], max_distance=dist + tol)
    return ((hits.status == HIT) & (hits.distance >= dist - tol)) | (hits.status == MISS)


def line_of_sight_coarse_first(recon, cam, surface, p, tol, job, row, col, step) -> np.ndarray:
    """:func:`line_of_sight` for output pixels (job, row, col), coarse grid first: rays are
    cast to every ``step``-th row and column; a pixel whose four surrounding coarse nodes were
    all cast and agree takes their answer, every other pixel (near an edge of the hidden
    ground, of the frame or of the ROI) gets its own ray. ``step`` (one number, or one per
    pixel, the same for all the pixels of a job) is at most half a DSM cell in output pixels,
    so hidden ground narrower than that between agreeing nodes is the only thing that can be
    missed (measured on the real survey: see ARCHITECTURE.md); pixels with step 1 get a ray each."""
    n = len(p)
    step = np.broadcast_to(np.asarray(step, np.int64), (n,))
    if n < 64 or not (step > 1).any():
        return line_of_sight(recon, cam, surface, p, tol)
    seen = np.zeros(n, bool)
    is_coarse = (step > 1) & (row % step == 0) & (col % step == 0)
    coarse = np.flatnonzero(is_coarse)
    seen[coarse] = line_of_sight(recon, cam, surface, p[coarse], tol)
    # each job's coarse nodes on a grid of their own (-1: not cast), all the grids in one array
    job = np.asarray(job, np.int64)
    nj = int(job.max()) + 1
    sj = np.ones(nj, np.int64)
    sj[job] = step
    rmax, cmax = np.zeros(nj, np.int64), np.zeros(nj, np.int64)
    np.maximum.at(rmax, job, row)
    np.maximum.at(cmax, job, col)
    gw = cmax // sj + 2
    off = np.concatenate([[0], np.cumsum((rmax // sj + 2) * gw)])
    grid = np.full(int(off[-1]), -1, np.int8)
    grid[off[job[coarse]] + (row[coarse] // step[coarse]) * gw[job[coarse]]
         + col[coarse] // step[coarse]] = seen[coarse]
    rest = np.flatnonzero(~is_coarse)
    st, jr = step[rest], job[rest]
    at = off[jr] + (row[rest] // st) * gw[jr] + col[rest] // st
    votes = np.zeros(len(rest), np.int64)
    known = st > 1
    for d in (0, 1, gw[jr], gw[jr] + 1):
        g = grid[at + d]
        known &= g >= 0
        votes += g
    decided = known & ((votes == 0) | (votes == 4))
    seen[rest[decided]] = votes[decided] == 4
    todo = rest[~decided]
    if todo.size:
        seen[todo] = line_of_sight(recon, cam, surface, p[todo], tol)
    return seen


def _render(jobs, recon, cam, image, surface: RaySurface, gsd, occlusion, tol, result,
            physical=None):
    """Write the images of ``jobs`` [(ROI in the DSM CRS, output path)] from one photo (all
    their pixels projected and ray-tested at once); returns why not, per job (None: written).
    ``physical``: (values, :class:`..radiometry.PhotoValues`) when ``image`` holds them (NaN
    where not valid)."""
    from scipy.ndimage import map_coordinates
    tif, crs = surface.tif, surface.crs
    whys: List[Optional[str]] = [None] * len(jobs)
    grids, xs, ys, owner, cell = [], [], [], [], []
    for j, (roi, out) in enumerate(jobs):
        x0, y0, x1, y1 = roi.bounds
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        if gsd is None:
            zc = float(surface.heights(np.array([cx]), np.array([cy]))[0])
            if not np.isfinite(zc):
                ring = np.asarray(roi.rings[0])
                zc = float(np.nanmedian(surface.heights(ring[:, 0], ring[:, 1])))
            g = _native_gsd(recon, cam, cx, cy, zc, crs) if np.isfinite(zc) else float("nan")
            if not np.isfinite(g):
                whys[j] = "the photo does not see the ROI's centre (no native resolution there)"
                grids.append(None)
                continue
        else:
            g = float(gsd)
        ox, oy = np.floor(x0 / g) * g, np.ceil(y1 / g) * g
        ncol, nrow = int(np.ceil((x1 - ox) / g)), int(np.ceil((oy - y0) / g))
        if ncol * nrow > MAX_PIXELS:
            raise InputError(f"ROI {roi.name!r} at a pixel size of {g:g} would be {ncol}×{nrow} "
                             "px; give a larger GSD.")
        # the output pixels whose centre is inside the ROI: a scanline fill of the grid
        rings_px = [np.column_stack([(np.asarray(r)[:, 0] - ox) / g, (oy - np.asarray(r)[:, 1]) / g])
                    for r in roi.rings]
        inside = np.flatnonzero(rasterize(rings_px, (nrow, ncol)))
        if not inside.size:
            whys[j] = "the ROI is smaller than one output pixel"
            grids.append(None)
            continue
        grids.append((ox, oy, g, ncol, nrow, inside.size))
        xs.append(ox + (inside % ncol + 0.5) * g)
        ys.append(oy - (inside // ncol + 0.5) * g)
        owner.append(np.full(inside.size, j))
        cell.append(inside)
    if not xs:
        return whys
    x, y, owner, cell = (np.concatenate(a) for a in (xs, ys, owner, cell))
    z = surface.heights(x, y)
    keep = np.flatnonzero(np.isfinite(z))
    xyz = np.column_stack([x[keep], y[keep], z[keep]])
    proj = recon.project_points(xyz, crs, cameras=[cam])
    inside = proj.status[0] == 0
    keep, xyz, uv = keep[inside], xyz[inside], proj.pixels[0][inside]
    occluded = np.zeros(len(jobs))
    if occlusion and keep.size:
        p = recon.to_model(xyz, crs)
        ncols = np.array([gr[3] if gr is not None else 1 for gr in grids], np.int64)
        own = owner[keep]
        half_cell = 0.5 * abs(tif.geotransform[1])     # each ROI's step: its own pixel size
        steps = np.array([max(1, int(half_cell / gr[2])) if gr is not None else 1 for gr in grids],
                         np.int64)
        seen = line_of_sight_coarse_first(recon, cam, surface, p, tol, own, cell[keep] // ncols[own],
                                          cell[keep] % ncols[own], steps[own])
        n_in = np.bincount(owner[keep], minlength=len(jobs))
        n_hidden = np.bincount(owner[keep][~seen], minlength=len(jobs))
        occluded = n_hidden / np.maximum(n_in, 1)
        keep, uv = keep[seen], uv[seen]
    bands = image.shape[2]
    values = np.empty((len(keep), bands), image.dtype)
    coords = np.vstack([uv[:, 1] - 0.5, uv[:, 0] - 0.5])      # (row, col) of pixel centres
    for b in range(bands):
        v = map_coordinates(image[..., b], coords, order=1, mode="nearest")
        if image.dtype.kind in "ui":
            v = np.clip(np.rint(v), np.iinfo(image.dtype).min, np.iinfo(image.dtype).max)
        values[:, b] = v.astype(image.dtype)
    top = np.iinfo(image.dtype).max if image.dtype.kind in "ui" else 1.0
    rgb = bands == 3 and image.dtype == np.uint8
    geokeys = {k: v for k, v in tif.geo_tags.items() if k != TAG_GDAL_METADATA}
    nodata = None
    if physical is not None:         # float32 in units: NaN (nodata, alpha 0) where no value
        geokeys[TAG_GDAL_METADATA], nodata = gdal_metadata(*physical, ("alpha",)), NODATA_TEXT
    order = np.argsort(owner[keep], kind="stable")
    bounds = np.searchsorted(owner[keep][order], np.arange(len(jobs) + 1))
    for j, (roi, out) in enumerate(jobs):
        if grids[j] is None:
            continue
        sel = order[bounds[j]:bounds[j + 1]]
        if not sel.size:
            whys[j] = "the photo shows none of the ROI (outside its frame, occluded or on DSM nodata)"
            continue
        ox, oy, g, ncol, nrow, n_roi = grids[j]
        data = np.zeros((nrow * ncol, bands + 1), dtype=image.dtype)
        if nodata is not None:
            data[:, :bands] = np.nan
        at = cell[keep[sel]]
        data[at, :bands] = values[sel]
        data[at, bands] = top if nodata is None else np.where(
            np.isnan(values[sel]).any(axis=1), 0.0, top)
        write_geotiff(out, data.reshape(nrow, ncol, bands + 1), (ox, g, 0.0, oy, 0.0, -g),
                      geokeys, nodata, rgb=rgb, extrasamples=(EXTRASAMPLE_ALPHA,) if rgb
                      else (0,) * (bands - 1) + (EXTRASAMPLE_ALPHA,))
        result.files.append(out)
        result.visible.append(sel.size / n_roi)
        result.occluded.append(float(occluded[j]))
        result.gsd.append(g)
    return whys
