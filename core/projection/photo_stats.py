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

Photos are measured as stored: no vignetting or radiometric correction is applied (correct the
photos first when the study needs reflectance).
"""
import csv
import io
import math
import os
from contextlib import ExitStack
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from .. import indices as ix
from ..errors import EasyIDPError, InputError
from ..files import OutputFolder, write_bytes
from ..geometry import rasterize
from ..progress import as_progress
from ..photo_files import photo_notes
from .photos import DecodedPhotos, resolve_photos
from .result import BackProjection

STATISTICS = ("mean", "median", "std")
"""Statistics of every band and index (plus percentiles, ``p5``, ``p95``…)."""
MAD_SCALE = 1.4826          # MAD → standard deviation of a normal distribution
MIN_VIEWS_FOR_SPREAD = 3    # ROIs with at least this many views define the typical spread


def percentile_name(q: float) -> str:
    """'p5', 'p97_5'."""
    return f"p{q:g}".replace(".", "_")


@dataclass
class PhotoStatistics:
    """The statistics of every ROI × photo and their across-view summary per ROI.

    Views (one row per record of the back-projection, in its order): ``record`` (its index),
    ``roi`` (index into ``roi_names``), ``photo``, ``values`` (k, len(columns)),
    ``polygon_pixels`` (pixel centres in the polygon), ``pixels`` (measured: not occluded, not
    masked), ``occluded_share`` (share of the polygon's pixels left out as occluded; NaN when not
    tested), ``undecided_share`` (lines of sight that met no DSM data), ``visible_share``,
    ``used`` and ``why`` (why a view is not used), ``deviation`` (see the module docstring), and
    from the back-projection ``rank``, ``score``, ``view_angle``, ``gsd``, ``visible_fraction``.

    Per ROI: ``median``/``mad``/``minimum``/``maximum`` (n_rois, len(columns)), ``views``
    (views used) and ``disagreement``.
    """
    roi_names: List[str]
    bands: List[str]
    indices: List[str]
    columns: List[str]
    record: np.ndarray
    roi: np.ndarray
    photo: np.ndarray
    rank: np.ndarray
    score: np.ndarray
    view_angle: np.ndarray
    gsd: np.ndarray
    visible_fraction: np.ndarray
    values: np.ndarray
    polygon_pixels: np.ndarray
    pixels: np.ndarray
    occluded_share: np.ndarray
    undecided_share: np.ndarray
    visible_share: np.ndarray
    used: np.ndarray
    why: List[str]
    deviation: np.ndarray
    median: np.ndarray
    mad: np.ndarray
    minimum: np.ndarray
    maximum: np.ndarray
    views: np.ndarray
    disagreement: np.ndarray
    cover_index: Optional[str] = None
    cover_threshold: Optional[float] = None
    threshold_source: str = ""
    weighted: bool = False
    skipped_photos: Dict[str, str] = field(default_factory=dict)
    previews: List[str] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    photos_decoded: int = 0
    rays: int = 0

    def column(self, name: str) -> np.ndarray:
        """One statistic of every view."""
        return self.values[:, self.columns.index(name)]

    def roi_value(self, name: str) -> np.ndarray:
        """One statistic's across-view value of every ROI."""
        return self.median[:, self.columns.index(name)]

    VIEW_FIELDS = ("roi", "photo", "rank", "score", "view_angle", "gsd", "visible_fraction",
                   "polygon_pixels", "pixels", "occluded_share", "undecided_share",
                   "visible_share", "used", "why", "deviation")

    def view_rows(self) -> List[dict]:
        rows = []
        for k in range(len(self.record)):
            row = {"roi": self.roi_names[int(self.roi[k])], "photo": str(self.photo[k]),
                   "rank": int(self.rank[k]), "score": _num(self.score[k]),
                   "view_angle": _num(self.view_angle[k]), "gsd": _num(self.gsd[k]),
                   "visible_fraction": _num(self.visible_fraction[k]),
                   "polygon_pixels": int(self.polygon_pixels[k]), "pixels": int(self.pixels[k]),
                   "occluded_share": _num(self.occluded_share[k]),
                   "undecided_share": _num(self.undecided_share[k]),
                   "visible_share": _num(self.visible_share[k]), "used": bool(self.used[k]),
                   "why": self.why[k], "deviation": _num(self.deviation[k])}
            row.update({c: _num(v) for c, v in zip(self.columns, self.values[k])})
            rows.append(row)
        return rows

    def roi_fields(self) -> List[str]:
        """Names of the per-ROI values: each statistic (its across-view median), then its
        ``_mad``, ``_min`` and ``_max``, then ``views`` and ``disagreement``."""
        out = list(self.columns)
        for suffix in ("mad", "min", "max"):
            out += [f"{c}_{suffix}" for c in self.columns]
        return out + ["views", "disagreement"]

    def roi_rows(self) -> List[dict]:
        rows = []
        for r, name in enumerate(self.roi_names):
            vals = list(self.median[r]) + list(self.mad[r]) + list(self.minimum[r]) \
                + list(self.maximum[r])
            row = {"roi": name}
            row.update({f: _num(v) for f, v in zip(self.roi_fields(), vals)})
            row["views"] = int(self.views[r])
            row["disagreement"] = _num(self.disagreement[r])
            rows.append(row)
        return rows

    def write_csv(self, views_path=None, rois_path=None) -> List[str]:
        """The views table and/or the per-ROI table as CSV (atomically); returns the paths."""
        out = []
        for path, rows in ((views_path, self.view_rows), (rois_path, self.roi_rows)):
            if path is None:
                continue
            data = rows()
            buf = io.StringIO()
            if data:
                w = csv.DictWriter(buf, fieldnames=list(data[0]), lineterminator="\n")
                w.writeheader()
                w.writerows({k: ("" if v is None else v) for k, v in row.items()} for row in data)
            write_bytes(path, buf.getvalue().encode("utf-8"))
            out.append(os.fspath(path))
        return out

    def summary(self) -> str:
        used = int(self.used.sum())
        seen = int((self.views > 0).sum())
        out = (f"{len(self.record)} views measured, {used} used, for {seen} of "
               f"{len(self.roi_names)} ROIs")
        if self.cover_index:
            out += (f"; cover: {self.cover_index.upper()} ≥ {self.cover_threshold:.4f} "
                    f"({self.threshold_source})") if self.cover_threshold is not None else \
                f"; cover: no threshold ({self.threshold_source})"
        if self.skipped_photos:
            out += f"; {len(self.skipped_photos)} photo(s) skipped"
        return out


def _num(v):
    v = float(v)
    return None if not math.isfinite(v) else v


# --- checks of the inputs ------------------------------------------------------------------------
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


def band_names_for(n: int, given: Optional[Sequence[str]]) -> List[str]:
    """Names of a photo's ``n`` bands: ``given`` (canonical, :func:`core.indices.canonical_band`),
    else red/green/blue for 3 bands, else b1…bn."""
    if given:
        names = [ix.canonical_band(b) for b in given]
        if len(names) != n:
            raise InputError(f"The photos have {n} band(s) but {len(names)} band name(s) were "
                             f"given ({', '.join(names)}): give one name per band.")
        if len(set(names)) != len(names):
            raise InputError(f"Band names must differ: {', '.join(names)}.")
        return names
    if n == 3:
        return list(ix.RGB_NAMES)
    return [f"b{k + 1}" for k in range(n)]


# --- the measurement of one view -------------------------------------------------------------------
class _Measure:
    """Column layout and the statistics of one view's pixels."""

    def __init__(self, names: List[str], stats, qs, wanted_indices, cover_kind, threshold):
        self.names = names
        self.alpha = names.index("alpha") if "alpha" in names else None
        self.band_idx = [k for k, n in enumerate(names) if n != "alpha"]
        self.bands = [names[k] for k in self.band_idx]
        self.stats, self.qs = stats, qs
        self.indices = [k for k in wanted_indices if k in ix.available(self.bands)]
        self.cover_kind = cover_kind
        self.threshold = threshold
        per = list(stats) + [percentile_name(q) for q in qs]
        self.columns = [f"{b}_{s}" for b in self.bands for s in per] + \
            [f"{k}_{s}" for k in self.indices for s in per] + (["cover"] if cover_kind else [])

    def stats_of(self, v: np.ndarray, out: np.ndarray, integer: bool) -> None:
        """Statistics of the 1-D float64 ``v`` into ``out`` (len: stats + percentiles)."""
        k = 0
        n = len(v)
        if n == 0:
            out[:] = np.nan
            return
        for s in self.stats:
            if s == "mean":
                out[k] = np.mean(v)
            elif s == "std":
                out[k] = np.std(v)
            k += 1
        need = [s for s in self.stats if s == "median"]
        if need or self.qs:
            if integer:
                med, pct = _order_stats_int(v, bool(need), self.qs)
            else:
                med, pct = _order_stats_float(v, bool(need), self.qs)
            if need:
                out[self.stats.index("median")] = med
            for j, p in enumerate(pct):
                out[len(self.stats) + j] = p

    def view(self, img: np.ndarray, r0: int, c0: int, keep: np.ndarray):
        """(values (len(columns),), pixel count, cover histogram or None) of the pixels
        ``keep`` (a window whose top-left pixel is (r0, c0)) of the photo ``img``."""
        out = np.full(len(self.columns), np.nan)
        rr, cc = np.nonzero(keep)
        flat = (rr + r0) * img.shape[1] + (cc + c0)
        px = np.take(img.reshape(img.shape[0] * img.shape[1], -1), flat, axis=0)  # (n, bands)
        if self.alpha is not None:
            px = px[px[:, self.alpha] > 0]
        n = len(px)
        if n == 0:
            return out, 0, None
        integer = px.dtype.kind == "u" and px.dtype.itemsize <= 2
        v = np.ascontiguousarray(px[:, self.band_idx].T, dtype=np.float64)   # (bands, n)
        per = len(self.stats) + len(self.qs)
        k = 0
        for b in range(len(self.bands)):
            self.stats_of(v[b], out[k:k + per], integer)
            k += per
        hist = None
        for kind in self.indices:
            idx = ix.compute(kind, v, self.bands)
            fin = idx[np.isfinite(idx)]
            self.stats_of(fin, out[k:k + per], False)
            k += per
            if kind == self.cover_kind:
                if self.threshold is not None:
                    out[-1] = ix.cover(fin, self.threshold)
                else:
                    hist = ix.index_histogram(kind, fin)
        if self.cover_kind and self.cover_kind not in self.indices:
            idx = ix.compute(self.cover_kind, v, self.bands)
            fin = idx[np.isfinite(idx)]
            if self.threshold is not None:
                out[-1] = ix.cover(fin, self.threshold)
            else:
                hist = ix.index_histogram(self.cover_kind, fin)
        return out, n, hist


def _order_stats_int(v: np.ndarray, median: bool, qs):
    """(median, percentiles) of non-negative integer values (as float64) from their histogram,
    as numpy's ``median`` and ``percentile`` (linear rule) compute them."""
    counts = np.bincount(v.astype(np.int64))
    cum = np.cumsum(counts)

    def kth(k):                       # the k-th smallest value (0-based)
        return float(np.searchsorted(cum, k, side="right"))
    return _interpolate(kth, len(v), median, qs)


SELECT_BINS = 1024


def _order_stats_float(v: np.ndarray, median: bool, qs):
    """(median, percentiles) of finite float64 values, exactly as numpy's ``median`` and
    ``percentile`` (linear rule): the order statistics needed are found by a histogram of
    :data:`SELECT_BINS` bins (monotone in the value), then selected among the values of their
    bin only (about twice as fast as ``np.percentile``'s partition of all values)."""
    n = len(v)
    lo, hi = float(v.min()), float(v.max())
    if n < 4 * SELECT_BINS or not hi > lo:
        s = np.sort(v) if n < 4 * SELECT_BINS else None
        return _interpolate((lambda k: float(s[k])) if s is not None else (lambda k: lo), n,
                            median, qs)
    scale = (SELECT_BINS - 1) / (hi - lo)
    b = ((v - lo) * scale).astype(np.int64)          # monotone in v: order is kept across bins
    cum = np.cumsum(np.bincount(b, minlength=SELECT_BINS))
    cache = {}

    def kth(k):
        if k not in cache:
            j = int(np.searchsorted(cum, k, side="right"))
            inside = np.sort(v[b == j])
            cache[k] = float(inside[k - (cum[j - 1] if j else 0)])
        return cache[k]
    return _interpolate(kth, n, median, qs)


def _interpolate(kth, n: int, median: bool, qs):
    """(median, percentiles) from ``kth(k)``, the k-th smallest of ``n`` values, with numpy's
    rules: the median of an even count is the mean of the middle two; percentiles are linear
    between order statistics, with numpy's ``_lerp``."""
    med = None
    if median:
        med = kth(n // 2) if n % 2 else (kth(n // 2 - 1) + kth(n // 2)) / 2.0
    pct = []
    for q in qs:
        virtual = (n - 1) * (q / 100.0)
        if virtual >= n - 1:
            pct.append(kth(n - 1))
            continue
        lo = int(math.floor(virtual))
        a, b, t = kth(lo), kth(lo + 1), virtual - lo
        diff = b - a                  # numpy's _lerp, both branches
        pct.append(b - diff * (1 - t) if t >= 0.5 else a + diff * t)
    return med, pct


# --- the pass over the photos ----------------------------------------------------------------------
def photo_statistics(result: BackProjection, photos=None, *, bands: Optional[Sequence[str]] = None,
                     statistics: Sequence[str] = STATISTICS, percentiles: Sequence[float] = (),
                     indices: Optional[Sequence[str]] = None,
                     cover_threshold: Optional[float] = None, min_visible: float = 0.0,
                     max_images: int = 0, weighted: bool = False, recon=None, rois=None,
                     occlusion_dsm=None, distortion: Optional[bool] = None,
                     occlusion_samples: int = 256, previews_folder=None, preview_views: int = 4,
                     overwrite: bool = False, workers: Optional[int] = None, progress=None,
                     is_cancelled=None) -> PhotoStatistics:
    """Measure every ROI × photo of ``result`` in the raw photos, and summarise each ROI across
    its views (see the module docstring).

    ``photos``: folder of the photos when they moved (matched by file name). ``bands``: the
    photos' band names (default red, green, blue for 3 bands, else b1…; name multispectral bands
    ``blue, green, red, rededge, nir`` for NDVI/NDRE; a band named ``alpha`` masks).
    ``statistics``: of :data:`STATISTICS`; ``percentiles``: numbers 0–100; ``indices``: of
    :data:`core.indices.INDICES` (default all that the bands allow). ``cover_threshold``: None
    for Otsu's. ``min_visible``/``max_images``: which views are used across views;
    ``weighted``: score-weighted medians. ``occlusion_dsm`` (with ``recon``, the project, and
    ``rois``, the ROI set the back-projection was made from): leave out the pixels whose line of
    sight meets the DSM outside the ROI (:mod:`.pixel_occlusion`; ``occlusion_samples`` coarse
    rays per view). ``previews_folder``: one PNG per ROI with its used views (at most
    ``preview_views``) side by side, each with its values. ``workers``: decoding threads (the
    measuring runs on the calling thread).
    """
    stats, qs = _check_args(statistics, percentiles, min_visible, max_images, cover_threshold)
    wanted = ix.check_indices(indices)
    prog = as_progress(progress, is_cancelled)
    if distortion is None:
        distortion = bool(result.settings.get("distortion", True))
    occ = None
    if occlusion_dsm is not None:
        occ = _Occlusion(result, recon, rois, occlusion_dsm, distortion, occlusion_samples)
    k = len(result)
    used_photos = sorted(set(result.photo_index.tolist()), key=lambda j: result.photo_labels[j])
    labels = [result.photo_labels[j] for j in used_photos]
    found, missing = resolve_photos(labels, [result.photo_paths[j] for j in used_photos], photos)
    if k and not found:
        raise InputError(f"None of the {len(labels)} photos is available: "
                         f"{'; '.join(list(missing.values())[:3])}. Give the photos folder.")
    state = _Pass(result, stats, qs, wanted, cover_threshold, bands, k)
    state.skipped.update(missing)
    state.notes += photo_notes(list(found.values()))
    sheets = None
    if previews_folder is not None:
        from .stat_previews import StatSheets
        sheets = StatSheets(result, previews_folder, preview_views, min_visible, max_images)
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
        with DecodedPhotos([found[result.photo_labels[j]] for j in todo],
                           result.image_sizes[todo], workers) as decoded:
            for n, img, why in decoded:
                prog.check()
                j = todo[n]
                if img is None:
                    state.skipped[result.photo_labels[j]] = why
                    continue
                if not state.ready(img, result.photo_labels[j]):
                    continue
                img = np.ascontiguousarray(img)      # pixels are gathered by flat index
                state.photos_decoded += 1
                recs = by_photo[j]
                windows = [_window_mask(result, i) for i in recs]
                occluded = [None] * len(recs)
                if occ is not None:
                    occluded = occ.photo(j, recs, windows, prog)
                for i, w, o in zip(recs, windows, occluded):
                    state.measure(i, img, w, o)
                if sheets is not None:
                    for i in recs:
                        sheets.add(i, img)
                del img
                prog.set(95.0 * (n + 1) / max(len(todo), 1))
        out = state.finish(min_visible, max_images, weighted)
        out.notes += occ.notes() if occ is not None else []
        out.rays = occ.rays if occ is not None else 0
        if sheets is not None:
            out.previews = sheets.write(out)
    prog.set(100)
    return out


def _window_mask(result: BackProjection, i: int):
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

    def __init__(self, result, stats, qs, wanted, threshold, bands, k):
        self.result = result
        self.stats, self.qs, self.wanted = stats, qs, wanted
        self.threshold = None if threshold is None else float(threshold)
        self.given_bands = bands
        self.m: Optional[_Measure] = None
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

    def ready(self, img: np.ndarray, label: str) -> bool:
        """Set the band layout from the first photo; False for a photo with another one."""
        n = 1 if img.ndim == 2 else img.shape[2]
        if self.m is None:
            names = band_names_for(n, self.given_bands)
            kind = ix.cover_kind([b for b in names if b != "alpha"])
            self.m = _Measure(names, self.stats, self.qs, self.wanted, kind, self.threshold)
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

    def measure(self, i: int, img: np.ndarray, wm, occluded) -> None:
        """Measure record ``i`` in ``img``; ``wm``: its (r0, c0, mask)."""
        r0, c0, mask = wm
        keep = mask if occluded is None else mask & ~occluded[0]
        vals, n, hist = self.m.view(img, r0, c0, keep)
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
            self.m = _Measure(band_names_for(3, None) if not self.given_bands else
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
        agg = _aggregate(res, self.values, used, m.columns, weighted)
        return PhotoStatistics(
            roi_names=list(res.roi_names), bands=m.bands, indices=m.indices, columns=m.columns,
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
            photos_decoded=self.photos_decoded, notes=list(self.notes))


# --- across views ----------------------------------------------------------------------------------
def weighted_median(x: np.ndarray, w: np.ndarray) -> float:
    """The weighted median of ``x``: the smallest value whose cumulative weight reaches half the
    total, or the midpoint of two values when it lands exactly on half (so equal weights give
    numpy's median). NaN for no positive weight."""
    ok = np.isfinite(x) & (w > 0)
    x, w = x[ok], w[ok]
    if not len(x):
        return float("nan")
    o = np.argsort(x, kind="stable")
    x, w = x[o], w[o]
    cum = np.cumsum(w)
    half = 0.5 * cum[-1]
    i = int(np.searchsorted(cum, half * (1 - 1e-12)))
    if abs(cum[i] - half) <= 1e-12 * cum[-1] and i + 1 < len(x):
        return float(0.5 * (x[i] + x[i + 1]))
    return float(x[i])


def _aggregate(res: BackProjection, values: np.ndarray, used: np.ndarray, columns, weighted):
    n, c = len(res.roi_names), len(columns)
    med = np.full((n, c), np.nan)
    mad, lo, hi = med.copy(), med.copy(), med.copy()
    views = np.bincount(res.roi[used], minlength=n)
    order = np.flatnonzero(used)
    groups: Dict[int, np.ndarray] = {}
    if len(order):
        by = order[np.argsort(res.roi[order], kind="stable")]
        cuts = np.flatnonzero(np.diff(res.roi[by])) + 1
        for g in np.split(by, cuts):
            groups[int(res.roi[g[0]])] = g
    with np.errstate(invalid="ignore"):
        for r, g in groups.items():
            X = values[g]
            if weighted:
                wts = np.clip(np.nan_to_num(res.score[g], nan=0.0), 0, None)
                if not (wts > 0).any():
                    wts = np.ones(len(g))
                med[r] = [weighted_median(X[:, q], wts) for q in range(c)]
                mad[r] = [weighted_median(np.abs(X[:, q] - med[r, q]), wts) for q in range(c)]
            else:
                med[r] = _nanmedian(X)
                mad[r] = _nanmedian(np.abs(X - med[r]))
            fin = np.isfinite(X)
            lo[r] = np.where(fin.any(axis=0), np.nanmin(np.where(fin, X, np.inf), axis=0), np.nan)
            hi[r] = np.where(fin.any(axis=0), np.nanmax(np.where(fin, X, -np.inf), axis=0), np.nan)
    # disagreement: the "mean" statistics and the cover, against the field's typical spread
    key = [q for q, name in enumerate(columns) if name.endswith("_mean") or name == "cover"]
    spread = MAD_SCALE * mad[:, key]
    many = views >= MIN_VIEWS_FOR_SPREAD
    if not many.any():
        many = views >= 2
    typical = np.array([np.nanmedian(spread[many, q]) if np.isfinite(spread[many, q]).any()
                        else np.nan for q in range(len(key))]) if many.any() else \
        np.full(len(key), np.nan)
    typical = np.where(typical > 0, typical, np.nan)
    with np.errstate(invalid="ignore", divide="ignore"):
        dev = np.full(len(res.roi), np.nan)
        if len(key):
            z = _mean_finite(np.abs(values[:, key] - med[res.roi][:, key]) / typical)
            ok = used & (views[res.roi] >= 2) & np.isfinite(z)
            dev[ok] = z[ok]
    dis = np.full(n, np.nan)
    ok = np.flatnonzero(np.isfinite(dev))
    if len(ok):
        np.fmax.at(dis, res.roi[ok], dev[ok])
    return {"median": med, "mad": mad, "min": lo, "max": hi, "views": views,
            "disagreement": dis, "deviation": dev}


def _mean_finite(a: np.ndarray) -> np.ndarray:
    """Row means over the finite values (NaN for a row without any)."""
    fin = np.isfinite(a)
    n = fin.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, np.where(fin, a, 0.0).sum(axis=1) / np.maximum(n, 1), np.nan)


def _nanmedian(X: np.ndarray) -> np.ndarray:
    """Column medians ignoring NaN (NaN for an all-NaN column), without numpy's warning."""
    fin = np.isfinite(X)
    if fin.all():
        return np.median(X, axis=0)
    out = np.full(X.shape[1], np.nan)
    for q in range(X.shape[1]):
        v = X[fin[:, q], q]
        if len(v):
            out[q] = np.median(v)
    return out


# --- occlusion per pixel ---------------------------------------------------------------------------
class _Occlusion:
    """The per-pixel occlusion test of each photo's records (:mod:`.pixel_occlusion`)."""

    def __init__(self, result, recon, rois, dsm, distortion, samples):
        from .occlusion import _surface
        from .pixel_occlusion import rings_in_dsm_crs
        if recon is None or rois is None:
            raise EasyIDPError("The occlusion test of the photo pixels needs the photogrammetry "
                               "project and the ROIs as well as the DSM.")
        names = list(rois.names)
        if names != list(result.roi_names):
            raise EasyIDPError("The ROIs given are not those of the back-projection (names or "
                               "order differ): give the ROI set it was made from.")
        self.recon, self.distortion, self.samples = recon, distortion, int(samples)
        self.surface = _surface(dsm)
        self.rings = rings_in_dsm_crs(rois, self.surface, sorted(set(result.roi.tolist())))
        self.cams = {}
        for label in result.photo_labels:
            try:
                self.cams[label] = recon.camera(label)
            except EasyIDPError:
                raise EasyIDPError(f"Photo {label} of the back-projection is not a camera of "
                                   f"{recon.source}: give the project it was made with.") from None
        self.result = result
        self.rays = 0
        self.undecided = 0

    def photo(self, j, recs, windows, prog):
        from .pixel_occlusion import PixelJob, test_pixels
        jobs = [PixelJob(int(self.result.roi[i]), r0, c0, mask) for i, (r0, c0, mask) in
                zip(recs, windows)]
        test_pixels(jobs, self.recon, self.cams[self.result.photo_labels[j]], self.surface,
                    self.rings, distortion=self.distortion, coarse=self.samples,
                    is_cancelled=prog.cancelled)
        self.rays += sum(jb.rays for jb in jobs)
        self.undecided += sum(jb.undecided for jb in jobs)
        return [(jb.occluded, jb.undecided) for jb in jobs]

    def notes(self) -> List[str]:
        out = [f"occlusion per pixel: {self.rays:,} lines of sight cast"]
        if self.undecided:
            out.append(f"{self.undecided:,} pixel(s) whose line of sight met no DSM data were "
                       "kept (undecided)")
        return out


__all__ = ["photo_statistics", "PhotoStatistics", "STATISTICS", "band_names_for",
           "weighted_median", "percentile_name"]
