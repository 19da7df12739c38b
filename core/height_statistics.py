"""The vocabulary of ROI height statistics: the modes, the statistics and the result type shared
by the DSM (:mod:`.raster.roi_heights`) and the point cloud (:mod:`.pointcloud.stats`).

``mode``: ``"polygon"`` (one value per ROI, from the pixels or points inside it) or ``"vertex"``
(one value per vertex of every ring). ``statistic`` (with ``percentile``, 0–100):

* ``mean``, ``median``, ``min``, ``max``, ``std``;
* ``percentile``: the ``percentile``-th percentile (numpy's linear interpolation);
* ``pmin`` / ``pmax``: EasyIDP's kernels, the mean of the values at or below the
  ``percentile``-th percentile / at or above the (100 − ``percentile``)-th.

Non-finite values are ignored; a statistic of no value is NaN, never 0.
"""
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

from .errors import EasyIDPError

STATISTICS = ("mean", "median", "min", "max", "std", "percentile", "pmin", "pmax")
MODES = ("polygon", "vertex")
_ALIASES = {"face": "polygon", "point": "vertex"}   # EasyIDP's names


def check_heights_args(mode: str, statistic: str, percentile: float) -> str:
    """Validate the shared arguments; returns the mode with EasyIDP's aliases resolved."""
    m = _ALIASES.get(str(mode), str(mode))
    if m not in MODES:
        raise EasyIDPError(f"Unknown mode {mode!r}: use 'polygon' (EasyIDP: face) or 'vertex' "
                           "(EasyIDP: point).")
    if statistic not in STATISTICS:
        raise EasyIDPError(f"Unknown statistic {statistic!r}: use one of {', '.join(STATISTICS)}.")
    if not 0 <= float(percentile) <= 100:
        raise EasyIDPError(f"The percentile must be between 0 and 100, not {percentile}.")
    return m


def statistic_of(values, statistic: str, percentile: float = 50.0) -> float:
    """One statistic of ``values`` (non-finite values ignored); NaN when none is left."""
    v = np.asarray(values, dtype=np.float64).ravel()
    v = v[np.isfinite(v)]
    if not len(v):
        return float("nan")
    if statistic in ("mean", "median", "min", "max", "std"):
        return float(getattr(np, statistic)(v))
    if statistic == "percentile":
        return float(np.percentile(v, percentile))
    if statistic == "pmin":
        return float(v[v <= np.percentile(v, percentile)].mean())
    if statistic == "pmax":
        return float(v[v >= np.percentile(v, 100.0 - percentile)].mean())
    raise EasyIDPError(f"Unknown statistic {statistic!r}: use one of {', '.join(STATISTICS)}.")


def statistics_of(groups: List[np.ndarray], statistic: str, percentile: float = 50.0) -> np.ndarray:
    """:func:`statistic_of` of every array of ``groups`` (the values of many ROIs): mean, min,
    max and std in one pass over all values (numpy's reductions, run by run), the others group
    by group. NaN for a group without a finite value."""
    if statistic not in ("mean", "min", "max", "std"):
        return np.array([statistic_of(g, statistic, percentile) for g in groups], np.float64)
    out = np.full(len(groups), np.nan)
    v = np.concatenate([np.asarray(g).ravel() for g in groups]) if groups else np.zeros(0)
    counts = np.array([np.asarray(g).size for g in groups], np.int64)
    finite = np.isfinite(v)
    if not finite.all():
        owner = np.repeat(np.arange(len(groups)), counts)
        v, counts = v[finite], np.bincount(owner[finite], minlength=len(groups))
    v = v.astype(np.float64)
    has = np.flatnonzero(counts)
    if not len(has):
        return out
    starts = (np.cumsum(counts) - counts)[has]
    n = counts[has]
    if statistic == "min":
        out[has] = np.minimum.reduceat(v, starts)
    elif statistic == "max":
        out[has] = np.maximum.reduceat(v, starts)
    else:
        mean = np.add.reduceat(v, starts) / n
        if statistic == "mean":
            out[has] = mean
        else:
            d = v - np.repeat(mean, n)
            out[has] = np.sqrt(np.add.reduceat(d * d, starts) / n)
    return out


@dataclass
class HeightResult:
    """Heights of an :class:`~.roi.ROISet`, aligned with its order (duplicate names are safe).

    ``values[i]``: polygon mode, a float (NaN: no height); vertex mode, a list (per part) of
    lists (per ring) of (n,) arrays, aligned with ``rois[i].parts``. ``missing``: ROI index →
    why (some of) its heights are NaN. ``notes``: problems met reading the inputs (e.g. a CRS
    that could not be read), for the caller to show.
    """
    mode: str
    values: List[object]
    missing: Dict[int, str] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)


def split_by_ring(values: np.ndarray, rois) -> list:
    """Per-vertex values (all rings of all ROIs, in order) → [roi][part][ring] arrays."""
    out, k = [], 0
    for roi in rois:
        parts = []
        for part in roi.parts:
            rings = []
            for ring in part:
                rings.append(values[k:k + len(ring)])
                k += len(ring)
            parts.append(rings)
        out.append(parts)
    return out


def vertex_result(values: np.ndarray, rois, why: str) -> HeightResult:
    """A vertex-mode :class:`HeightResult` from per-vertex values; ROIs with a NaN get ``why``."""
    nested = split_by_ring(values, rois)
    missing = {i: why for i, parts in enumerate(nested)
               if np.isnan(np.concatenate([r for p in parts for r in p])).any()}
    return HeightResult("vertex", nested, missing)
