"""Plot statistics from the raw photos: every view of every ROI measured, and one robust value
per ROI across its views.

:func:`photo_statistics` takes a :class:`BackProjection` (every ROI × photo that sees it) and
the photos. In **one pass** over the photos (:class:`.photos.DecodedPhotos`, the pass the photo
crops use: each photo decoded once, threads ahead), every record of the photo is measured:

* **Pixels**: the photo pixels whose centre is inside the record's (frame-clipped) polygon, the
  raster rule (:func:`core.geometry.rasterize`). With a DSM, the pixels whose line of sight meets
  the surface outside the ROI are left out (:mod:`.pixel_occlusion`) and their share is
  ``occluded_share``. A band named ``alpha`` masks (alpha 0 is left out) and is not measured.
* **Per band** (the photo's values as decoded: 8-bit, 16-bit or float, never rescaled): mean,
  median, population standard deviation and chosen percentiles (numpy's linear rule).
* **Vegetation indices** (:mod:`core.indices`: ExG, ExGR, VARI, GLI for red/green/blue; NDVI,
  NDRE for named red, rededge and nir bands), per pixel, with the same statistics over the
  pixels where they are defined.
* **Canopy cover**: the share of the pixels whose cover index (NDVI when red and nir are
  named, else ExG) is at or above a threshold: the one given, or Otsu's over the pooled
  histogram of every measured view (one threshold for the run; ExG and NDVI do not change
  with brightness).
* The pixel count, and the record's GSD, score, view angle and visible fraction.

**Across views**, per ROI, over its *used* views (measured, with a visible share
``visible_fraction × (1 − occluded_share)`` ≥ ``min_visible``, the ``max_images`` best by rank):
the median of each statistic (``weighted``: the score-weighted median), its median absolute
deviation (MAD, unscaled), minimum and maximum, and the number of views used. **Disagreement**:
for each "mean" statistic and the cover, the field's typical spread ``σ`` is the median over the
ROIs with three or more views of 1.4826·MAD; a view's ``deviation`` is the mean over those
statistics of |value − its ROI's value| / σ, and a ROI's ``disagreement`` the largest deviation
of its views. About 1 is typical for the field; several times that flags a view that disagrees
(a shadow, wind, a bad pose, or tall canopy seen from a very different angle; the MAD itself
ignores a single outlying view). NaN with fewer than two views.

Photos are measured as stored unless ``values`` asks for temperature or reflectance
(:mod:`..radiometry`: the one place where pixels become physical values; invalid pixels such as
saturated ones are left out, never averaged).

**Band files of multispectral captures** (MicaSense, DJI; as stored or reflectance) are one view
per ROI × capture (:mod:`.capture_stats`): each band measured through its own camera and
polygon, indices from the band means and medians of the same ROI, no cover.
"""
import math
import os
from contextlib import ExitStack
from typing import Dict, List, Optional, Sequence

import numpy as np

from .. import indices as ix
from ..deprecation import renamed_parameters
from ..errors import EasyIDPError, InputError
from ..files import OutputFolder
from ..geometry import rasterize
from ..photos import DecodedPhotos, photo_notes, resolve_photos
from ..progress import as_progress
from ..radiometry import VALUES, PhotoValues, photo_decoder
from .across_views import aggregate_views
from .capture_stats import band_columns, band_layout, capture_views, combine_bands
from .result import BackProjection
from .stat_previews import StatSheets
from .stats_table import PhotoStatistics
from .view_measure import STATISTICS, ViewMeasure, band_names_for, percentile_name
from .view_occlusion import PhotoOcclusion
from .view_sun import view_sun


def _check_args(statistics, percentiles, min_visible, max_images, cover_threshold):
    stats = tuple(dict.fromkeys(str(s).strip().lower() for s in statistics if str(s).strip()))
    bad = [s for s in stats if s not in STATISTICS]
    if bad:
        raise EasyIDPError(f"Unknown statistic {', '.join(bad)}: choose from "
                           f"{', '.join(STATISTICS)} (percentiles are given apart).")
    qs = []
    for q in percentiles or ():
        try:
            q = float(q)
        except (TypeError, ValueError):
            raise EasyIDPError(f"Percentile {q!r} is not a number: give numbers from 0 to "
                               "100, e.g. 5, 95.") from None
        if not 0.0 <= q <= 100.0:
            raise EasyIDPError(f"Percentile {q:g} is outside 0–100.")
        qs.append(q)
    qs = tuple(dict.fromkeys(qs))
    if not stats and not qs:
        raise EasyIDPError("No statistic chosen: choose mean, median, std or percentiles.")
    if not 0.0 <= float(min_visible) <= 1.0:
        raise EasyIDPError(f"The minimum visible share must be between 0 and 1, not {min_visible}.")
    if int(max_images) < 0:
        raise EasyIDPError(f"The number of views per ROI must be 0 (all) or more, not {max_images}.")
    if cover_threshold is not None and not math.isfinite(float(cover_threshold)):
        raise EasyIDPError(f"The cover threshold must be a number, not {cover_threshold}.")
    return stats, qs


@renamed_parameters(photos="photos_folder", max_images="max_views")
def photo_statistics(result: BackProjection, photos_folder=None, *, bands: Optional[Sequence[str]] = None,
                     statistics: Sequence[str] = STATISTICS, percentiles: Sequence[float] = (),
                     indices: Optional[Sequence[str]] = None,
                     cover_threshold: Optional[float] = None, min_visible: float = 0.0,
                     max_views: int = 0, weighted: bool = False, recon=None, rois=None,
                     occlusion_dsm=None, distortion: Optional[bool] = None,
                     occlusion_samples: int = 256, previews_folder=None, preview_views: int = 4,
                     overwrite: bool = False, workers: Optional[int] = None, progress=None,
                     is_cancelled=None, values: str = "stored",
                     value_options: Optional[dict] = None,
                     utc_offset: Optional[float] = None) -> PhotoStatistics:
    """Measure every ROI × photo of ``result`` in the raw photos, and summarise each ROI across
    its views (see the module docstring).

    Invalid pixels (saturated, unreadable) are left out. Each view also gets its photo's
    acquisition time (``acquired``, EXIF) and, with ``recon`` and ``rois``, the sun's zenith
    and azimuth at its ROI and the phase angle sun–ROI–camera (:mod:`.view_sun`).

    Parameters
    ----------
    result : BackProjection
        The ROIs in the photos (:func:`back_project`).
    photos_folder : str or path, optional
        Where the photos are when they moved (matched by file name).
    bands : sequence of str, optional
        The photos' band names (default red, green, blue for 3 bands, else b1…; name
        multispectral bands ``blue, green, red, rededge, nir`` for NDVI/NDRE; a band named
        ``alpha`` masks).
    statistics : sequence of str
        Of :data:`STATISTICS`.
    percentiles : sequence of float
        Percentiles, 0–100.
    indices : sequence of str, optional
        Of :data:`core.indices.INDICES` (default: all that the bands allow).
    cover_threshold : float, optional
        The vegetation-index threshold of cover (None: Otsu's per view).
    min_visible : float
        Views with a smaller visible share (0–1) are not used across views.
    max_views : int
        Use the best k views per ROI across views (0: all).
    weighted : bool
        Score-weighted medians across views.
    recon : Reconstruction, optional
        The project: with ``rois``, for the occlusion test and the sun angles.
    rois : ROISet, optional
        The ROI set the back-projection was made from.
    occlusion_dsm : DSM, GeoTiff or path, optional
        Leave out the pixels whose line of sight meets this DSM outside the ROI
        (:mod:`.pixel_occlusion`).
    distortion : bool, optional
        As the back-projection (default: its setting).
    occlusion_samples : int
        Coarse rays per view for the occlusion test.
    previews_folder : str or path, optional
        One PNG per ROI with its used views side by side, each with its values.
    preview_views : int
        At most this many views per preview.
    overwrite : bool
        Replace this run's earlier previews.
    workers : int, optional
        Decoding threads (the measuring runs on the calling thread).
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    values : {"stored", "temperature", "reflectance"}
        ``"stored"``: the photos as stored (columns ``red_mean``, …); ``"temperature"``: °C
        (:func:`..radiometry.read_photo_values`; columns ``temp_c_mean``, …);
        ``"reflectance"``: reflectance 0–1 (columns ``nir_refl_median``, …; indices on
        reflectance). Band files of multispectral captures (as stored or reflectance) give one
        view per ROI × capture, named by their band tags (:mod:`.capture_stats`).
    value_options : dict, optional
        The options of ``values`` (object parameters, temperature scale:
        :func:`..radiometry.read_photo_values`).
    utc_offset : float, optional
        Hours, for photos whose time states no offset (the sun's angles need UTC).

    Returns
    -------
    PhotoStatistics
        The table of every ROI × photo and the table across views, with the notes.
    """
    if values not in VALUES:
        raise EasyIDPError(f"Unknown values {values!r}: choose from {', '.join(VALUES)}.")
    stats, qs = _check_args(statistics, percentiles, min_visible, max_views, cover_threshold)
    wanted = ix.check_indices(indices)
    prog = as_progress(progress, is_cancelled)
    if distortion is None:
        distortion = bool(result.settings.get("distortion", True))
    occ = None
    if occlusion_dsm is not None:
        occ = PhotoOcclusion(result, recon, rois, occlusion_dsm, distortion, occlusion_samples)
    k = len(result)
    used_photos = sorted(set(result.photo_index.tolist()), key=lambda j: result.photo_labels[j])
    labels = [result.photo_labels[j] for j in used_photos]
    found, missing = resolve_photos(labels, [result.photo_paths[j] for j in used_photos],
                                    photos_folder)
    if k and not found:
        raise InputError(f"None of the {len(labels)} photos is available: "
                         f"{'; '.join(list(missing.values())[:3])}. Give the photos folder.")
    layout = band_layout(found) if values in ("stored", "reflectance") else None
    if layout is None:
        state = _Pass(result, stats, qs, wanted, cover_threshold, bands, k, values)
    else:
        state = _CapturePass(result, layout, stats, qs, wanted, cover_threshold, bands, k, values)
    state.skipped.update(missing)
    state.notes += photo_notes(list(found.values()))
    sheets = None
    if previews_folder is not None and layout is not None:
        state.notes.append("no previews: they are not drawn yet for the band files of "
                           "multispectral captures")
    elif previews_folder is not None:
        sheets = StatSheets(result, previews_folder, preview_views, min_visible, max_views)
    by_photo: Dict[int, List[int]] = {}
    for i, j in enumerate(result.photo_index.tolist()):
        by_photo.setdefault(j, []).append(i)
    todo = [j for j in used_photos if result.photo_labels[j] in found]
    workers = max(1, workers or min(4, os.cpu_count() or 1))
    with ExitStack() as stack:
        if sheets is not None:
            stack.callback(sheets.cleanup)
            stack.enter_context(OutputFolder(previews_folder, overwrite=overwrite,
                                             what="Previews folder")).claim(
                d + ".png" for d in sheets.names)
        # the decoding runs ahead in threads; the measuring stays on this thread: its many
        # small numpy calls hold the GIL (two measuring threads were 1.4× slower than one)
        decode = photo_decoder(values, value_options)
        with DecodedPhotos([found[result.photo_labels[j]] for j in todo],
                           result.image_sizes[todo], workers, decode=decode) as decoded:
            for n, img, why in decoded:
                prog.check()
                j = todo[n]
                if img is None:
                    state.skipped[result.photo_labels[j]] = why
                    continue
                valid = value_bands = None
                if isinstance(img, PhotoValues):
                    state.value_note(img.note)
                    value_bands = img.bands
                    img, valid = img.values, (None if img.valid.all() else img.valid)
                if not state.ready(img, result.photo_labels[j], value_bands):
                    continue
                img = np.ascontiguousarray(img)      # pixels are gathered by flat index
                state.photos_decoded += 1
                recs = by_photo[j]
                windows = [window_mask(result, i) for i in recs]
                occluded = [None] * len(recs)
                if occ is not None:
                    occluded = occ.photo(j, recs, windows, prog)
                for i, w, o in zip(recs, windows, occluded):
                    state.measure(i, img, w, o, valid)
                if sheets is not None:
                    for i in recs:
                        sheets.add(i, img)
                del img
                prog.set(95.0 * (n + 1) / max(len(todo), 1))
        out = state.finish(min_visible, max_views, weighted)
        sun = view_sun(result, rois, recon, found, utc_offset)
        pick = out.record                  # a capture view: its first band's record
        out.acquired = [sun["acquired"][i] for i in pick]
        out.sun_zenith, out.sun_azimuth = sun["sun_zenith"][pick], sun["sun_azimuth"][pick]
        out.phase_angle = sun["phase_angle"][pick]
        out.notes += sun["notes"]
        out.notes += occ.notes() if occ is not None else []
        out.rays = occ.rays if occ is not None else 0
        if sheets is not None:
            out.previews = sheets.write(out)
    prog.set(100)
    return out


def unit_columns(columns: List[str], bands: Sequence[str], values: str) -> List[str]:
    """The column names with the unit of ``values`` after each band's name (reflectance:
    ``nir_median`` → ``nir_refl_median``; temperature bands are named ``temp_c`` already;
    indices and cover are unitless)."""
    if values != "reflectance":
        return list(columns)
    out = []
    for c in columns:
        b = next((b for b in bands if c.startswith(b + "_")), None)
        out.append(f"{b}_refl_{c[len(b) + 1:]}" if b else c)
    return out


def window_mask(result: BackProjection, i: int):
    """(r0, c0, mask) of record ``i``: the pixels whose centre is inside its polygon, over
    the polygon's bounding box inside the frame."""
    j = int(result.photo_index[i])
    w, h = (int(v) for v in result.image_sizes[j])
    rings = result.rings_of(i)
    allxy = np.concatenate(rings)
    c0 = min(max(int(np.floor(allxy[:, 0].min())), 0), w)
    r0 = min(max(int(np.floor(allxy[:, 1].min())), 0), h)
    c1 = max(min(int(np.ceil(allxy[:, 0].max())), w), c0)
    r1 = max(min(int(np.ceil(allxy[:, 1].max())), h), r0)
    off = np.array([c0, r0], float)
    mask = rasterize([r - off for r in rings], (r1 - r0, c1 - c0))
    return r0, c0, mask


class _Pass:
    """What the pass over the photos accumulates."""

    def __init__(self, result, stats, qs, wanted, threshold, bands, k, values="stored"):
        self.result = result
        self.values_kind = values
        self.value_notes: Dict[str, int] = {}
        self.stats, self.qs, self.wanted = stats, qs, wanted
        self.threshold = None if threshold is None else float(threshold)
        self.given_bands = bands
        self.m: Optional[ViewMeasure] = None
        self.n_bands = None
        self.values = None
        self.k = k
        self.polygon_pixels = np.zeros(k, np.int64)
        self.pixels = np.zeros(k, np.int64)
        self.occluded = np.full(k, np.nan)
        self.undecided = np.full(k, np.nan)
        self.measured = np.zeros(k, bool)
        self.hists: Dict[int, tuple] = {}
        self.skipped: Dict[str, str] = {}
        self.photos_decoded = 0
        self.notes: List[str] = []

    def ready(self, img: np.ndarray, label: str, value_bands=None) -> bool:
        """Set the band layout from the first photo (``value_bands``: the band names of its
        physical values); False for a photo with another one."""
        n = 1 if img.ndim == 2 else img.shape[2]
        if self.m is None:
            names = band_names_for(n, value_bands or self.given_bands)
            kind = ix.cover_kind([b for b in names if b != "alpha"])
            self.m = ViewMeasure(names, self.stats, self.qs, self.wanted, kind, self.threshold)
            self.n_bands = n
            self.values = np.full((self.k, len(self.m.columns)), np.nan)
            missing = [x for x in self.wanted if x not in self.m.indices]
            if missing and self.wanted != ix.INDICES:
                self.notes.append(f"{', '.join(missing).upper()}: the bands "
                                  f"({', '.join(self.m.bands)}) lack what they need; name the "
                                  "bands (e.g. blue, green, red, rededge, nir)")
            if kind is None:
                self.notes.append(f"no canopy cover: the bands ({', '.join(self.m.bands)}) are "
                                  "not named red, green, blue or red and nir")
            return True
        if n != self.n_bands:
            self.skipped[label] = (f"it has {n} band(s) where the first photo has "
                                   f"{self.n_bands}: measure one camera at a time")
            return False
        return True

    def view_measure(self, i: int) -> ViewMeasure:
        """The measurement of record ``i``."""
        return self.m

    def value_note(self, note: str) -> None:
        """Count a photo's note of what was applied (reported once per kind)."""
        self.value_notes[note] = self.value_notes.get(note, 0) + 1

    def measure(self, i: int, img: np.ndarray, wm, occluded, valid=None) -> None:
        """Measure record ``i`` in ``img``; ``wm``: its (r0, c0, mask); ``valid``: the photo's
        valid pixels (None: all)."""
        r0, c0, mask = wm
        keep = mask if occluded is None else mask & ~occluded[0]
        if valid is not None:
            keep = keep & valid[r0:r0 + mask.shape[0], c0:c0 + mask.shape[1]]
        vals, n, hist = self.view_measure(i).view(img, r0, c0, keep)
        self.values[i] = vals
        npoly = int(mask.sum())
        self.polygon_pixels[i] = npoly
        self.pixels[i] = n
        self.measured[i] = True
        if occluded is not None and npoly:
            self.occluded[i] = float(occluded[0].sum()) / npoly
            self.undecided[i] = occluded[1] / npoly
        if hist is not None:              # int32: a run of 50,000 views keeps ~150 MB
            self.hists[i] = (hist[0], hist[1].astype(np.int32))

    def finish(self, min_visible, max_images, weighted) -> PhotoStatistics:
        res = self.result
        k = self.k
        if self.m is None:                 # no photo could be read
            self.m = ViewMeasure(band_names_for(3, None) if not self.given_bands else
                              band_names_for(len(self.given_bands), self.given_bands),
                              self.stats, self.qs, self.wanted, None, self.threshold)
            self.values = np.full((k, len(self.m.columns)), np.nan)
        m = self.m
        threshold, source = self.threshold, "given"
        if m.cover_kind and threshold is None:
            total = np.zeros(ix.INDEX_BINS, np.int64)
            for h in self.hists.values():
                ix.add_histogram(total, h)
            threshold = ix.otsu_threshold(m.cover_kind, total) if total.any() else None
            source = (f"Otsu over {int(total.sum()):,} pixels of {len(self.hists)} views"
                      if threshold is not None else "Otsu undefined: the index values are all "
                                                    "alike; give a threshold")
            if threshold is not None:
                for i, h in self.hists.items():
                    self.values[i, -1] = ix.cover_from_histogram(m.cover_kind, h, threshold)
        occ = np.where(np.isfinite(self.occluded), self.occluded,
                       np.nan_to_num(res.occluded_fraction, nan=0.0))
        visible = res.visible_fraction * (1.0 - occ)
        used = self.measured & (self.pixels > 0) & (visible >= min_visible)
        why = [""] * k
        for i in range(k):
            if not self.measured[i]:
                why[i] = "photo not available"
            elif self.pixels[i] == 0:
                why[i] = "no pixel to measure"
            elif visible[i] < min_visible:
                why[i] = "below the minimum visible share"
        if max_images > 0:                 # the best by rank among the usable views
            order = np.lexsort((res.rank, res.roi))
            count = np.zeros(len(res.roi_names), np.int64)
            for i in order:
                if used[i]:
                    count[res.roi[i]] += 1
                    if count[res.roi[i]] > max_images:
                        used[i] = False
                        why[i] = "beyond the views per ROI"
        agg = aggregate_views(res, self.values, used, m.columns, weighted)
        notes = list(self.notes) + [f"{note} ({n} photo(s))" for note, n in
                                    list(self.value_notes.items())[:5]]
        if len(self.value_notes) > 5:
            notes.append(f"… and {len(self.value_notes) - 5} more settings of the conversion")
        return PhotoStatistics(
            roi_names=list(res.roi_names), bands=m.bands, indices=m.indices,
            columns=unit_columns(m.columns, m.bands, self.values_kind),
            record=np.arange(k), roi=res.roi.copy(), photo=res.photo.copy(), rank=res.rank.copy(),
            score=res.score.copy(), view_angle=res.view_angle.copy(), gsd=res.gsd.copy(),
            visible_fraction=res.visible_fraction.copy(), values=self.values,
            polygon_pixels=self.polygon_pixels, pixels=self.pixels, occluded_share=self.occluded,
            undecided_share=self.undecided, visible_share=visible, used=used, why=why,
            deviation=agg["deviation"], median=agg["median"], mad=agg["mad"],
            minimum=agg["min"], maximum=agg["max"], views=agg["views"],
            disagreement=agg["disagreement"], cover_index=m.cover_kind,
            cover_threshold=threshold, threshold_source=source if m.cover_kind else "",
            weighted=bool(weighted), skipped_photos=dict(self.skipped),
            photos_decoded=self.photos_decoded, notes=notes, values_kind=self.values_kind)


class _CapturePass(_Pass):
    """The pass over the band files of multispectral captures (:mod:`.capture_stats`): each
    record measured in its own band file through its own polygon, then one view per ROI ×
    capture."""

    def __init__(self, result, layout, stats, qs, wanted, threshold, bands, k, values):
        super().__init__(result, stats, qs, wanted, threshold, bands, k, values)
        self.layout = layout
        self.per = list(stats) + [percentile_name(q) for q in qs]
        self.band_of = [layout.band.get(result.photo_labels[j])
                        for j in result.photo_index.tolist()]
        self.measures: Dict[str, ViewMeasure] = {}
        self.values = np.full((k, len(self.per)), np.nan)
        if bands:
            self.notes.append("the band names given are not used: band files are named by "
                              "their band tags")

    def ready(self, img: np.ndarray, label: str, value_bands=None) -> bool:
        if label not in self.layout.band:
            self.skipped[label] = ("not a band file, where the other photos are band files of a "
                                   "multispectral camera: measure one camera at a time")
            return False
        if img.ndim == 3 and img.shape[2] > 1:
            self.skipped[label] = f"it has {img.shape[2]} bands where a band file has one"
            return False
        return True

    def view_measure(self, i: int) -> ViewMeasure:
        band = self.band_of[i]
        if band not in self.measures:
            self.measures[band] = ViewMeasure([band], self.stats, self.qs, (), None, None)
        return self.measures[band]

    def finish(self, min_visible, max_images, weighted) -> PhotoStatistics:
        views = capture_views(self.result, self.layout)
        bands, indices, columns = band_columns(list(self.measures), self.per, self.wanted)
        values, complete, missing = combine_bands(views, self.band_of, self.values, self.per,
                                                  bands, indices, columns, self.measured)
        recs = views.records

        def per_view(arr, how):
            with np.errstate(invalid="ignore"):
                return np.array([how(arr[r]) for r in recs], float) if recs else np.zeros(0)

        def most(a):
            return np.nan if np.isnan(a).all() else np.nanmax(a)
        self.pixels = np.where(complete, per_view(self.pixels, np.min), 0).astype(np.int64)
        self.polygon_pixels = per_view(self.polygon_pixels, np.min).astype(np.int64)
        self.occluded = per_view(self.occluded, most)
        self.undecided = per_view(self.undecided, most)
        self.result, self.k, self.values, self.measured = views, len(views), values, complete
        self.m = ViewMeasure(bands, self.stats, self.qs, (), None, None)
        self.m.indices, self.m.columns = indices, columns
        self.hists = {}
        self.notes.append(f"{len(set(self.layout.capture.values()))} multispectral capture(s) of "
                          f"{len(self.layout.band)} band files: one view per ROI × capture, each "
                          "band measured through its own camera; indices from the band means "
                          "and medians of the same ROI; no canopy cover")
        out = super().finish(min_visible, max_images, weighted)
        out.record = np.array([r[0] for r in recs], np.int64)
        for v, why in enumerate(missing):
            if why and not out.used[v]:
                out.why[v] = why
        return out


__all__ = ["photo_statistics", "window_mask"]
