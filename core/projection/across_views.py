"""Robust aggregation across views: per ROI, the (weighted) median, MAD, minimum and maximum of
each statistic over its used views, and each view's deviation from the field's typical spread
(see :mod:`.photo_stats`)."""
from typing import Dict

import numpy as np

from .result import BackProjection

MAD_SCALE = 1.4826          # MAD → standard deviation of a normal distribution
MIN_VIEWS_FOR_SPREAD = 3    # ROIs with at least this many views define the typical spread


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


def aggregate_views(res: BackProjection, values: np.ndarray, used: np.ndarray, columns, weighted):
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
