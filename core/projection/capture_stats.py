"""The band files of one capture as one view of *Plot statistics from photos*.

A multispectral camera (MicaSense ``IMG_0001_1.tif … _5.tif``, DJI ``…_MS_G.TIF … _MS_NIR.TIF``)
takes one capture as one file per band, each through its own lens; the project (Metashape,
Pix4D, OPF) solves each band file as its own camera. Each band is measured through its own
camera: the ROI is back-projected into each band file separately, and that band's statistics come
from the pixels inside its own polygon. The rows of one ROI × capture are then one view:

* per band (named by the photo's band tag, :func:`core.indices.canonical_band`: ``red``,
  ``nir``, ``rededge`` …) its statistics, from its own photo's pixels;
* the vegetation indices from the same ROI in every band, never from pixels of different
  places: the bands' pixels are not registered to each other (each lens sees the ROI at other
  pixels), so an index is formed from the band statistics of the ROI, ``ndvi_mean`` from the
  band means and ``ndvi_median`` from the band medians (no per-pixel index, so no index
  standard deviation or percentiles and no canopy cover);
* the view's geometry: score, view angle and GSD the mean over its bands, visible share the
  smallest, the pixel count the smallest band's; its photo is the capture's name (the band files'
  common name); its rank, 1 = best, by the best rank among its bands.

A capture missing a band the ROI has elsewhere (that band's photo does not see the ROI, or could
not be read) is kept as a row but not used across views.
"""
import os
from dataclasses import dataclass
from typing import Dict, List, Optional, Tuple

import numpy as np

from .. import indices as ix
from ..errors import InputError
from ..radiometry import capture_key, read_photo_tags

BAND_ORDER = ("blue", "green", "red", "rededge", "nir", "panchro", "lwir")
TIFF_SUFFIXES = (".tif", ".tiff")


@dataclass
class BandLayout:
    """The band files among the photos: ``capture`` and ``band`` (canonical name) by photo
    label, and ``names`` the capture's name by capture key."""

    capture: Dict[str, str]
    band: Dict[str, str]
    names: Dict[str, str]


def band_layout(found: Dict[str, str]) -> Optional[BandLayout]:
    """The band files among ``found`` (photo label → file), grouped into captures by the vendors'
    tags (:func:`..radiometry.capture_key`); None when no photo is a band file (a TIFF with a
    ``Camera:BandName`` tag). InputError naming both files when a capture has a band twice."""
    capture: Dict[str, str] = {}
    band: Dict[str, str] = {}
    seen: Dict[Tuple[str, str], str] = {}
    files: Dict[str, List[str]] = {}
    for label, path in found.items():
        if not str(path).lower().endswith(TIFF_SUFFIXES):
            continue
        try:
            tags = read_photo_tags(path)
        except InputError:
            continue                       # not readable here: the decoding says why
        name = tags.xmp.get("Camera:BandName")
        if not name or isinstance(name, list):
            continue
        key, b = capture_key(tags), ix.canonical_band(name)
        if (key, b) in seen:
            raise InputError(f"{path}: band {name!r} of capture {key} is also in "
                             f"{seen[(key, b)]}; give each capture's band files once")
        seen[(key, b)] = path
        capture[label], band[label] = key, b
        files.setdefault(key, []).append(label)
    if not capture:
        return None
    return BandLayout(capture, band, {k: _capture_name(v, k) for k, v in files.items()})


def _capture_name(labels: List[str], key: str) -> str:
    """The band files' common name without its band suffix (``IMG_0001_1``, ``IMG_0001_2`` →
    ``IMG_0001``), else the capture key."""
    stems = [os.path.splitext(os.path.basename(lab))[0] for lab in labels]
    common = os.path.commonprefix(stems).rstrip("_-. ")
    if len(stems) == 1:
        common = stems[0].rsplit("_", 1)[0] if "_" in stems[0] else stems[0]
    return common or key


def band_columns(bands: List[str], per: List[str], wanted) -> Tuple[List[str], List[str],
                                                                      List[str]]:
    """(bands in the usual order, indices, columns) of capture views: each band's statistics
    ``per``, then each index of the band means and medians."""
    bands = sorted(bands, key=lambda b: (BAND_ORDER.index(b) if b in BAND_ORDER else 99, b))
    indices = [k for k in wanted if k in ix.available(bands)]
    columns = [f"{b}_{s}" for b in bands for s in per]
    columns += [f"{k}_{s}" for k in indices for s in per if s in ("mean", "median")]
    return bands, indices, columns


@dataclass
class CaptureViews:
    """The capture views of a back-projection: ``records[v]`` the records (one per band) of
    view ``v``, and per view ``roi``, ``photo`` (the capture's name), ``rank``, ``score``,
    ``view_angle``, ``gsd``, ``visible_fraction``, ``occluded_fraction``; ``roi_names`` as the
    back-projection's. It stands in for the back-projection where views are summarised."""

    records: List[List[int]]
    roi_names: List[str]
    roi: np.ndarray
    photo: np.ndarray
    rank: np.ndarray
    score: np.ndarray
    view_angle: np.ndarray
    gsd: np.ndarray
    visible_fraction: np.ndarray
    occluded_fraction: np.ndarray

    def __len__(self) -> int:
        return len(self.records)


def capture_views(result, layout: BandLayout) -> CaptureViews:
    """Group the records of ``result`` (a BackProjection) whose photos are band files into one
    view per ROI × capture, in the order of their first record."""
    groups: Dict[Tuple[int, str], List[int]] = {}
    for i in range(len(result)):
        label = result.photo_labels[int(result.photo_index[i])]
        if label in layout.capture:
            groups.setdefault((int(result.roi[i]), layout.capture[label]), []).append(i)
    keys = list(groups)
    recs = [groups[k] for k in keys]

    def agg(arr, how):
        return np.array([how(np.asarray(arr)[r]) for r in recs], float) if recs else np.zeros(0)

    roi = np.array([k[0] for k in keys], np.int64)
    best = agg(result.rank, np.min)
    rank = np.zeros(len(keys), np.int64)
    for r in np.unique(roi):                # 1 = best capture of the ROI
        at = np.flatnonzero(roi == r)
        rank[at[np.argsort(best[at], kind="stable")]] = np.arange(1, len(at) + 1)
    with np.errstate(invalid="ignore"):
        occluded = agg(result.occluded_fraction, lambda a: np.nan if np.isnan(a).all()
                       else np.nanmax(a))
    return CaptureViews(recs, list(result.roi_names), roi,
                        np.array([layout.names[k[1]] for k in keys], dtype=object), rank,
                        agg(result.score, np.mean), agg(result.view_angle, np.mean),
                        agg(result.gsd, np.mean), agg(result.visible_fraction, np.min), occluded)


def combine_bands(views: CaptureViews, band_of: List[Optional[str]], rec_values: np.ndarray,
                  per: List[str], bands: List[str], indices: List[str], columns: List[str],
                  measured: np.ndarray) -> Tuple[np.ndarray, np.ndarray, List[str]]:
    """(values (views, columns), all bands measured (views,), why not) of the capture views,
    from each record's band statistics ``rec_values`` (records, len(per))."""
    n = len(views)
    out = np.full((n, len(columns)), np.nan)
    complete = np.zeros(n, bool)
    why = [""] * n
    at = {c: q for q, c in enumerate(columns)}
    for v, recs in enumerate(views.records):
        have = {}
        for i in recs:
            if measured[i] and band_of[i] is not None:
                have[band_of[i]] = i
                for q, s in enumerate(per):
                    out[v, at[f"{band_of[i]}_{s}"]] = rec_values[i, q]
        missing = [b for b in bands if b not in have]
        complete[v] = bool(have) and not missing
        if missing:
            why[v] = f"no {', '.join(missing)} view (that band's photo does not see the ROI " \
                     "or was not read)"
        for s in ("mean", "median"):
            if s not in per:
                continue
            v_b = np.array([[out[v, at[f"{b}_{s}"]]] for b in bands])
            for kind in indices:
                out[v, at[f"{kind}_{s}"]] = float(ix.compute(kind, v_b, bands)[0])
    return out, complete, why


__all__ = ["BandLayout", "band_layout", "band_columns", "CaptureViews", "capture_views",
           "combine_bands"]
