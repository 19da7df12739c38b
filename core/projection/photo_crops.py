"""Crops of the raw photos for a :class:`BackProjection`, and preview sheets per ROI.

One pass over the photos (:class:`..photos.DecodedPhotos`, shared with the plot statistics):
each photo is decoded **once** (a pool of threads decodes ahead) and every ROI the result keeps
in it is cut out; the files are encoded and written by a second pool, atomically. Memory holds at most ``workers + 1`` decoded photos, the crops waiting to be
written, and the preview tiles of ROIs whose best views are not all decoded yet (spilled to
disk beyond ``PREVIEW_CACHE_BYTES``).

Each crop is the bounding box of the clipped polygon (plus ``margin`` px, inside the frame),
with the polygon as alpha (a pixel is inside when its centre is, as for raster crops):

* 8-bit photos with 1 or 3 bands (or RGBA): PNG, grey+alpha or RGBA;
* 16-bit, floating-point or multiband photos (e.g. multispectral TIFFs): TIFF, the photo's
  bands plus an alpha band (ExtraSamples = unassociated alpha; 0 / the type's maximum, 1.0
  for floats).
* ``values`` temperature or reflectance (:func:`..radiometry.read_photo_values`, the one place
  where pixels become physical values): float32 TIFF of those values plus the alpha band, the
  unit and what was applied in GDAL's metadata (:mod:`..radiometry.output_tags`), NaN (the
  nodata) where a pixel is not valid (saturated, unreadable); the sidecar's ``values`` says the
  same.

Files are ``<roi>/<photo>.png|tif`` with a sidecar ``<roi>/<photo>.json``: the crop's offset
in the photo, the polygons in crop and photo pixels, score and fractions, the camera and the
pixel convention. Previews are ``<roi>.png``: the ROI's best views left to right (rank 1
first), each with the polygon drawn in red and the outside dimmed (EasyIDP's
``draw_backward_one_roi``).
"""
import os
import shutil
import tempfile
from concurrent.futures import ThreadPoolExecutor
from contextlib import ExitStack
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import InputError
from ..files import OutputFolder, atomic_output, write_bytes, write_json
from ..geometry import densify, rasterize
from ..naming import unique_names
from ..photos import DecodedPhotos, photo_stems, resolve_photos
from ..progress import as_progress
from ..radiometry import PhotoValues, photo_decoder, tiff_extratags
from .result import PIXEL_CONVENTION, BackProjection

MAX_PENDING_WRITES = 64
PREVIEW_CACHE_BYTES = 128 << 20
PREVIEW_HEIGHT = 256     # px, height of one view in a preview sheet
PREVIEW_PAD = 40         # px of photo around the ROI in a preview view (EasyIDP's buffer)
PREVIEW_GAP = 6          # px between views
PNG_FAST = {"level": 1, "strategy": 3, "filter": 16}
"""PNG settings of OpenCV's encoder (zlib level 1, RLE, SUB filter): on photo crops about 8×
faster than zlib level 6 for files about 1.5× larger."""
TIFF_LEVEL = 1


@dataclass
class PhotoCropResult:
    """``files``: crop images written (``sidecars`` their JSON, same order); ``previews``:
    preview sheets; ``skipped_photos``: {photo label: why} (missing, undecodable, wrong size);
    ``empty``: ROI × photo pairs whose polygon holds no pixel centre (nothing written)."""
    files: List[str] = field(default_factory=list)
    sidecars: List[str] = field(default_factory=list)
    previews: List[str] = field(default_factory=list)
    skipped_photos: Dict[str, str] = field(default_factory=dict)
    empty: int = 0

    def summary(self) -> str:
        out = f"{len(self.files)} crops, {len(self.previews)} previews"
        if self.skipped_photos:
            out += f"; {len(self.skipped_photos)} photo(s) skipped"
        return out


@renamed_parameters(out_folder="output_folder", photos="photos_folder")
def crop_photos(result: BackProjection, output_folder, photos_folder=None, *, margin: int = 0,
                previews_folder=None, preview_views: int = 4, workers: Optional[int] = None,
                overwrite: bool = False, progress=None, is_cancelled=None,
                values: str = "stored", value_options: Optional[dict] = None) -> PhotoCropResult:
    """Cut every ROI × photo of ``result`` out of the raw photos.

    Each photo is decoded once. Missing or undecodable photos are reported in
    ``skipped_photos`` and skipped. Both folders are guarded as every output folder is
    (:class:`..files.OutputFolder`): an ROI's folder or preview that already exists stops the
    run before anything is written, unless ``overwrite``.

    Parameters
    ----------
    result : BackProjection
        The ROI × photo pairs (:func:`back_project`).
    output_folder : str or path or None
        The folder of the crops, one subfolder per ROI (None: previews only).
    photos_folder : str or path, optional
        The folder the photos are in now, when they moved (matched by file name).
    margin : int
        Pixels added around each ROI's box.
    previews_folder : str or path, optional
        Also draw one preview sheet per ROI with its ``preview_views`` best photos.
    preview_views : int
        The most photos on a preview sheet.
    workers : int, optional
        Decoding and writing threads (default: the CPU count, at most 4).
    overwrite : bool
        Replace this run's earlier outputs.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    values : {"stored", "temperature", "reflectance"}
        The pixels as stored (the photo's data type), or in physical units: float32 TIFFs in
        °C or reflectance, NaN where a pixel is not valid (:func:`..radiometry.read_photo_values`;
        a photo that holds no such values is skipped, with why).
    value_options : dict, optional
        The options of ``values`` (object parameters, temperature TIFF scale:
        :func:`..radiometry.read_photo_values`).

    Returns
    -------
    PhotoCropResult
        The crops, their sidecars and the previews written, sorted, and the photos skipped.
    """
    decode = photo_decoder(values, value_options)
    if output_folder is None and previews_folder is None:
        raise InputError.of("nothing_to_write")
    if margin < 0:
        raise InputError(f"The crop margin must be 0 or more pixels, not {margin}.")
    prog = as_progress(progress, is_cancelled)
    out = PhotoCropResult()
    if not len(result):
        return out
    used = sorted(set(result.photo_index.tolist()), key=lambda j: result.photo_labels[j])
    labels = [result.photo_labels[j] for j in used]
    found, missing = resolve_photos(labels, [result.photo_paths[j] for j in used],
                                    photos_folder)
    out.skipped_photos.update(missing)
    if not found:
        raise InputError(f"None of the {len(labels)} photos is available: "
                         f"{'; '.join(list(missing.values())[:3])}. Give the photos folder.")
    roi_dirs = unique_names(result.roi_names)
    with ExitStack() as stack:    # both folders checked, locked and claimed before any decode
        if output_folder is not None:
            stack.enter_context(OutputFolder(output_folder, overwrite=overwrite,
                                             what="Crops folder")).claim(roi_dirs)
        if previews_folder is not None:
            stack.enter_context(OutputFolder(previews_folder, overwrite=overwrite,
                                             what="Previews folder")).claim(d + ".png" for d in roi_dirs)
        _crop_all(result, out, used, found, roi_dirs, output_folder, previews_folder, preview_views,
                  margin, workers, prog, (values, decode))
    out.files.sort()
    out.sidecars.sort()
    out.previews.sort()
    return out


def _crop_all(result, out, used, found, roi_dirs, out_folder, previews_folder, preview_views,
              margin, workers, prog, decoding=("stored", None)) -> None:
    """One pass over the photos (:class:`..photos.DecodedPhotos`: each decoded once, threads
    ahead of the cutting) writing each photo's crops and previews; ``decoding``: (values,
    decoder of :func:`..radiometry.photo_decoder`)."""
    stems = dict(zip(result.photo_labels, photo_stems(result.photo_labels)))
    by_photo: Dict[int, List[int]] = {}
    for i, j in enumerate(result.photo_index.tolist()):
        by_photo.setdefault(j, []).append(i)
    sheets = PreviewSheets(result, previews_folder, preview_views, roi_dirs) if previews_folder else None
    todo = [j for j in used if result.photo_labels[j] in found]
    early = []
    if sheets is not None:
        for j in used:
            if result.photo_labels[j] not in found:
                early += sheets.photo_unavailable(by_photo[j])
    workers = max(1, workers or min(4, os.cpu_count() or 1))
    pending = []

    def collect(item):
        kind, fut = item
        path, side = fut.result()
        if kind == "crop":
            out.files.append(path)
            out.sidecars.append(side)
        else:
            out.previews.append(path)

    paths = [found[result.photo_labels[j]] for j in todo]
    with DecodedPhotos(paths, result.image_sizes[todo], workers, decode=decoding[1]) as photos, \
            ThreadPoolExecutor(workers, thread_name_prefix="easyidp-write") as writers:
        try:
            pending += [("preview", writers.submit(*sheet)) for sheet in early]
            for k, img, why in photos:
                prog.check()
                j = todo[k]
                if img is None:
                    out.skipped_photos[result.photo_labels[j]] = why
                    if sheets is not None:
                        pending += [("preview", writers.submit(*sheet))
                                    for sheet in sheets.photo_unavailable(by_photo[j])]
                    continue
                physical = None
                if isinstance(img, PhotoValues):        # physical values: NaN where invalid
                    physical, img = (decoding[0], img), img.masked()
                for i in by_photo[j]:
                    if out_folder is not None:
                        job = _crop_job(result, i, img, margin, out_folder, roi_dirs, stems,
                                        paths[k], physical)
                        if job is None:
                            out.empty += 1
                        else:
                            pending.append(("crop", writers.submit(*job)))
                    if sheets is not None:
                        for sheet in sheets.add(i, img):
                            pending.append(("preview", writers.submit(*sheet)))
                    while len(pending) > MAX_PENDING_WRITES:
                        collect(pending.pop(0))
                del img
                prog.set(100.0 * (k + 1) / len(todo))
            if sheets is not None:
                for sheet in sheets.finish():
                    pending.append(("preview", writers.submit(*sheet)))
            for item in pending:
                collect(item)
        except BaseException:
            for _, fut in pending:
                fut.cancel()
            for _, fut in pending:
                if not fut.cancelled():
                    try:
                        fut.result()
                    except Exception:  # nosec B110 -- the error being raised is the first one
                        pass
            raise
        finally:
            if sheets is not None:
                sheets.cleanup()


@renamed_parameters(folder="output_folder", views="max_views", photos="photos_folder")
def draw_previews(result: BackProjection, output_folder, photos_folder=None, *,
                  max_views: int = 4, workers: Optional[int] = None, overwrite: bool = False,
                  progress=None, is_cancelled=None) -> PhotoCropResult:
    """Only the preview sheets of :func:`crop_photos`: one PNG per ROI with its best photos.

    Parameters
    ----------
    result : BackProjection
        The ROI × photo pairs (:func:`back_project`).
    output_folder : str or path
        The folder of the previews.
    photos_folder : str or path, optional
        The folder the photos are in now, when they moved (matched by file name).
    max_views : int
        The most photos on a preview sheet.
    workers : int, optional
        Decoding and writing threads.
    overwrite : bool
        Replace this run's earlier outputs.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    PhotoCropResult
        The previews written.
    """
    return crop_photos(result, None, photos_folder, previews_folder=output_folder,
                       preview_views=max_views, workers=workers, overwrite=overwrite,
                       progress=progress, is_cancelled=is_cancelled)


# --- crops -------------------------------------------------------------------------------------------
def _window(rings, w: int, h: int, margin: int):
    allxy = np.concatenate(rings)
    c0 = max(int(np.floor(allxy[:, 0].min())) - margin, 0)
    r0 = max(int(np.floor(allxy[:, 1].min())) - margin, 0)
    c1 = min(int(np.ceil(allxy[:, 0].max())) + margin, w)
    r1 = min(int(np.ceil(allxy[:, 1].max())) + margin, h)
    return r0, r1, c0, c1


def _crop_job(result, i, img, margin, out_folder, roi_dirs, stems, photo_path, physical=None):
    """(function, args...) writing record ``i``'s crop and sidecar, or None when empty;
    ``physical``: (values, :class:`..radiometry.PhotoValues`) when ``img`` holds them."""
    j = int(result.photo_index[i])
    w, h = (int(v) for v in result.image_sizes[j])
    polys = result.polygons_of(i)
    rings = [r for p in polys for r in p]
    r0, r1, c0, c1 = _window(rings, w, h, margin)
    if r1 <= r0 or c1 <= c0:
        return None
    off = np.array([c0, r0], float)
    mask = rasterize([r - off for r in rings], (r1 - r0, c1 - c0))
    if not mask.any():
        return None
    crop = img[r0:r1, c0:c1]
    folder = os.path.join(out_folder, roi_dirs[int(result.roi[i])])
    stem = stems[str(result.photo[i])]
    meta = _sidecar(result, i, polys, off, (c1 - c0, r1 - r0), margin, photo_path)
    tags = None
    if physical is not None:
        kind, pv = physical
        meta["values"] = {"values": kind, "unit": pv.unit, "bands": list(pv.bands),
                          "note": pv.note, "nodata": "NaN where a pixel is not valid "
                                                    "(saturated, unreadable)"}
        tags = tiff_extratags(kind, pv, ("alpha",))
    return (_write_crop, folder, stem, crop, mask, meta, tags)


def _write_crop(folder, stem, crop, mask, meta, tags=None):
    os.makedirs(folder, exist_ok=True)
    if tags is None and crop.dtype == np.uint8 and (crop.ndim == 2 or crop.shape[2] in (3, 4)):
        import imagecodecs
        if crop.ndim == 2:
            arr = np.dstack([crop, mask.astype(np.uint8) * 255])
        else:
            arr = np.empty(crop.shape[:2] + (4,), np.uint8)
            arr[..., :3] = crop[..., :3]
            arr[..., 3] = mask.astype(np.uint8) * 255
            if crop.shape[2] == 4:
                arr[..., 3] &= crop[..., 3]
        path = os.path.join(folder, stem + ".png")
        write_bytes(path, imagecodecs.png_encode(arr, **PNG_FAST))
    else:
        import tifffile
        data = crop if crop.ndim == 3 else crop[..., None]
        top = 1.0 if data.dtype.kind == "f" else np.iinfo(data.dtype).max
        arr = np.concatenate([data, (mask * top).astype(data.dtype)[..., None]], axis=2)
        rgb = data.shape[2] == 3
        extras = (0,) * (arr.shape[2] - (3 if rgb else 1) - 1) + (2,)   # the last: alpha
        path = os.path.join(folder, stem + ".tif")
        with atomic_output(path) as tmp:
            tifffile.imwrite(tmp, arr, photometric="rgb" if rgb else "minisblack",
                             planarconfig="contig", extrasamples=extras, compression="zlib",
                             compressionargs={"level": TIFF_LEVEL}, metadata=None,
                             **({"extratags": tags} if tags else {}))
    meta["file"] = os.path.basename(path)
    side = os.path.join(folder, stem + ".json")
    write_json(side, meta, separators=(",", ":"))
    return path, side


def _num(v):
    v = float(v)
    return None if not np.isfinite(v) else v


def _sidecar(result, i, polys, off, size, margin, photo_path) -> dict:
    j = int(result.photo_index[i])
    return {
        "roi": result.roi_names[int(result.roi[i])], "photo": str(result.photo[i]),
        "photo_path": photo_path, "camera": result.photo_labels[j],
        "image_size": [int(v) for v in result.image_sizes[j]],
        "offset": [int(off[0]), int(off[1])], "crop_size": [int(size[0]), int(size[1])],
        "margin": int(margin),
        "polygons_photo": [[np.round(r, 6).tolist() for r in p] for p in polys],
        "polygons_crop": [[np.round(r - off, 6).tolist() for r in p] for p in polys],
        "rank": int(result.rank[i]), "score": _num(result.score[i]),
        "visible_fraction": _num(result.visible_fraction[i]),
        "occluded_fraction": _num(result.occluded_fraction[i]),
        "view_angle": _num(result.view_angle[i]), "gsd": _num(result.gsd[i]),
        "centre_distance": _num(result.centre_distance[i]), "clipped": bool(result.clipped[i]),
        "pixels": PIXEL_CONVENTION + "; offset = photo pixel of the crop's top-left corner "
                  "(x = column, y = row); polygons are open rings, exterior first",
        "alpha": "opaque where the pixel centre is inside the ROI",
    }


# --- previews -----------------------------------------------------------------------------------------
class PreviewSheets:
    """Tiles of the best views per ROI, composed into a sheet once all have been seen."""

    def __init__(self, result: BackProjection, folder, views: int, roi_dirs):
        self.result = result
        self.folder = folder
        self.roi_dirs = roi_dirs
        self.wanted: Dict[int, set] = {}
        for i in np.flatnonzero(result.rank <= max(1, views)):
            self.wanted.setdefault(int(result.roi[i]), set()).add(int(i))
        self.tiles: Dict[int, Dict[int, object]] = {}
        self.bytes = 0
        self.spill_dir = None

    def photo_unavailable(self, records):
        """Forget the views of a photo that cannot be read; sheets now complete."""
        out = []
        for i in records:
            r = int(self.result.roi[i])
            if r in self.wanted and int(i) in self.wanted[r]:
                self.wanted[r].discard(int(i))
                out += self._ready(r)
        return out

    def add(self, i: int, img: np.ndarray):
        r = int(self.result.roi[i])
        if r not in self.wanted or i not in self.wanted[r]:
            return []
        tile = _tile(self.result, i, img)
        self.tiles.setdefault(r, {})[i] = tile
        self.bytes += tile.nbytes
        if self.bytes > PREVIEW_CACHE_BYTES:
            self._spill()
        return self._ready(r)

    def _ready(self, r: int):
        have = self.tiles.get(r, {})
        if not self.wanted[r] or not self.wanted[r] <= set(have):
            return []
        return [self._sheet(r)]

    def _sheet(self, r: int):
        tiles = self.tiles.pop(r, {})
        order = sorted(tiles, key=lambda i: self.result.rank[i])
        arrays = []
        for i in order:
            t = tiles[i]
            if isinstance(t, str):
                t = np.load(t)
            else:
                self.bytes -= t.nbytes
            arrays.append(t)
        del self.wanted[r]
        path = os.path.join(self.folder, self.roi_dirs[r] + ".png")
        return (_write_sheet, path, arrays)

    def _spill(self) -> None:
        if self.spill_dir is None:
            self.spill_dir = tempfile.mkdtemp(prefix=".easyidp-previews-", dir=self.folder)
        for r, tiles in self.tiles.items():
            for i, t in tiles.items():
                if not isinstance(t, str):
                    p = os.path.join(self.spill_dir, f"{i}.npy")
                    np.save(p, t)
                    tiles[i] = p
        self.bytes = 0

    def finish(self):
        out = []
        for r in list(self.wanted):
            if self.tiles.get(r):
                out.append(self._sheet(r))
        return out

    def cleanup(self) -> None:
        if self.spill_dir is not None:
            shutil.rmtree(self.spill_dir, ignore_errors=True)


def _display(a: np.ndarray) -> np.ndarray:
    """Any photo window → RGB uint8 (first three bands; others stretched to 2–98 %)."""
    if a.ndim == 2:
        a = a[..., None]
    a = a[..., :3] if a.shape[2] >= 3 else np.repeat(a[..., :1], 3, axis=2)
    if a.dtype == np.uint8:
        return np.ascontiguousarray(a)
    f = a.astype(np.float32)
    lo, hi = np.nanpercentile(f, 2), np.nanpercentile(f, 98)
    f = (f - lo) * (255.0 / max(hi - lo, 1e-12))
    return np.clip(np.nan_to_num(f, nan=0.0), 0, 255).astype(np.uint8)   # NaN: not valid


def _resize(a: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """Box-average by the integer part of the reduction, then nearest to the exact size."""
    k = int(min(a.shape[0] // max(rows, 1), a.shape[1] // max(cols, 1)))
    if k >= 2:
        r, c = a.shape[0] // k * k, a.shape[1] // k * k
        a = a[:r, :c].reshape(r // k, k, c // k, k, -1).mean(axis=(1, 3)).astype(np.uint8)
    ri = np.minimum(((np.arange(rows) + 0.5) * a.shape[0] / rows).astype(np.int64), a.shape[0] - 1)
    ci = np.minimum(((np.arange(cols) + 0.5) * a.shape[1] / cols).astype(np.int64), a.shape[1] - 1)
    return a[ri][:, ci]


def _tile(result: BackProjection, i: int, img: np.ndarray) -> np.ndarray:
    j = int(result.photo_index[i])
    w, h = (int(v) for v in result.image_sizes[j])
    rings = result.rings_of(i)
    r0, r1, c0, c1 = _window(rings, w, h, PREVIEW_PAD)
    view = _display(img[r0:r1, c0:c1])
    scale = PREVIEW_HEIGHT / max(r1 - r0, 1)
    cols = max(1, int(round((c1 - c0) * scale)))
    if cols > 3 * PREVIEW_HEIGHT:
        scale *= 3 * PREVIEW_HEIGHT / cols
        cols = 3 * PREVIEW_HEIGHT
    rows = max(1, int(round((r1 - r0) * scale)))
    tile = _resize(view, rows, cols)
    local = [(r - [c0, r0]) * [cols / (c1 - c0), rows / (r1 - r0)] for r in rings]
    inside = rasterize(local, (rows, cols))
    np.right_shift(tile, 1, out=tile, where=~inside[..., None])    # dim the outside
    for ring in local:
        _draw_ring(tile, ring, (255, 40, 40))
    return tile


def _draw_ring(img: np.ndarray, ring: np.ndarray, colour) -> None:
    """A closed polyline, 2 px wide, burnt into ``img`` (rows, cols, 3)."""
    p = densify(ring, np.array([0, len(ring)]), 0.5)[0]          # a point every ½ px
    for dx in (-0.5, 0.5):
        for dy in (-0.5, 0.5):
            c = np.floor(p[:, 0] + dx).astype(np.int64)
            r = np.floor(p[:, 1] + dy).astype(np.int64)
            ok = (r >= 0) & (r < img.shape[0]) & (c >= 0) & (c < img.shape[1])
            img[r[ok], c[ok]] = colour


def _write_sheet(path, tiles):
    import imagecodecs
    height = max(t.shape[0] for t in tiles)
    width = sum(t.shape[1] for t in tiles) + PREVIEW_GAP * (len(tiles) + 1)
    sheet = np.full((height + 2 * PREVIEW_GAP, width, 3), 32, np.uint8)
    x = PREVIEW_GAP
    for t in tiles:
        sheet[PREVIEW_GAP:PREVIEW_GAP + t.shape[0], x:x + t.shape[1]] = t
        x += t.shape[1] + PREVIEW_GAP
    write_bytes(path, imagecodecs.png_encode(sheet, **PNG_FAST))
    return path, None
