"""The measurement of one view: the column layout (bands, indices, statistics, percentiles,
cover) and the statistics of the view's pixels."""
from typing import List, Optional, Sequence

import numpy as np

from .. import indices as ix
from ..errors import InputError
from .order_stats import order_stats_float, order_stats_int

STATISTICS = ("mean", "median", "std")
"""Statistics of every band and index (plus percentiles, ``p5``, ``p95``…)."""


def percentile_name(q: float) -> str:
    """'p5', 'p97_5'."""
    return f"p{q:g}".replace(".", "_")



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
class ViewMeasure:
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
                med, pct = order_stats_int(v, bool(need), self.qs)
            else:
                med, pct = order_stats_float(v, bool(need), self.qs)
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
