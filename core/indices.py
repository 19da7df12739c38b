"""Vegetation indices and canopy cover: one implementation for every tool (orthomosaic traits of
a season, statistics of the raw photos).

Bands are named in lower case: ``red``, ``green``, ``blue`` for RGB; multispectral bands
``blue``, ``green``, ``red``, ``rededge``, ``nir`` (aliases in :data:`BAND_ALIASES`). Indices
work on the band values as stored (8-bit, 16-bit or reflectance: the ratios do not depend on a
common scale), per pixel, in float64; NaN where the denominator is zero:

* ``exg``  excess green, 2g − r − b of the chromatic coordinates r = R/(R+G+B) …
  = (2G − R − B)/(R + G + B) (Woebbecke et al. 1995); range [−1, 2];
* ``exgr`` excess green minus excess red, ExG − (1.4r − g) = (3G − 2.4R − B)/(R + G + B)
  (Meyer & Neto 2008); range [−2.4, 3];
* ``vari`` visible atmospherically resistant index, (G − R)/(G + R − B) (Gitelson et al. 2002);
  unbounded where G + R ≈ B: prefer its median;
* ``gli``  green leaf index, (2G − R − B)/(2G + R + B) (Louhaichi et al. 2001); range [−1, 1];
* ``ndvi`` (NIR − Red)/(NIR + Red); ``ndre`` (NIR − RedEdge)/(NIR + RedEdge); range [−1, 1].

**Cover** is the share of pixels whose index is **at or above** a threshold: a given one, or
Otsu's (scikit-image ``threshold_otsu``) over a histogram of :data:`INDEX_BINS` equal bins over
the index range. Pooled histograms let one threshold serve many ROIs (Otsu per ROI splits the
noise of an all-soil or all-canopy plot). Values are binned exactly (a value is in bin k when
``edges[k] ≤ value < edges[k + 1]``), and Otsu's threshold is the upper edge of the bin
scikit-image returns, so a cover from a histogram equals the share of the raw values ≥ the
threshold, with no rounding at the bin boundaries.
"""
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .errors import EasyIDPError

RGB_INDICES = ("exg", "exgr", "vari", "gli")
MULTISPECTRAL_INDICES = ("ndvi", "ndre")
INDICES = RGB_INDICES + MULTISPECTRAL_INDICES
"""Every index by name."""
INDEX_BANDS = {"exg": ("red", "green", "blue"), "exgr": ("red", "green", "blue"),
               "vari": ("red", "green", "blue"), "gli": ("red", "green", "blue"),
               "ndvi": ("red", "nir"), "ndre": ("rededge", "nir")}
"""The bands each index needs."""
INDEX_RANGE = {"exg": (-1.0, 2.0), "exgr": (-2.4, 3.0), "gli": (-1.0, 1.0),
               "ndvi": (-1.0, 1.0), "ndre": (-1.0, 1.0)}
"""Value range of the indices a cover can be computed on (VARI is unbounded: none)."""
INDEX_BINS = 3000     # histogram bins over an index range (ExG: 0.001 per bin)
RGB_NAMES = ("red", "green", "blue")
BAND_ALIASES = {"r": "red", "g": "green", "b": "blue", "near_infrared": "nir", "nir1": "nir",
                "red_edge": "rededge", "re": "rededge", "edge": "rededge", "rededge1": "rededge"}


def canonical_band(name: str) -> str:
    """A band name in lower case with its alias resolved ('Red Edge' → 'rededge')."""
    n = "_".join(str(name).strip().lower().replace("-", " ").split())
    return BAND_ALIASES.get(n, BAND_ALIASES.get(n.replace("_", ""), n.replace("red_edge", "rededge")))


def available(names: Sequence[str]) -> List[str]:
    """The indices whose bands are all among ``names`` (canonical names)."""
    have = set(names)
    return [k for k in INDICES if all(b in have for b in INDEX_BANDS[k])]


def check_indices(wanted: Optional[Sequence[str]]) -> Tuple[str, ...]:
    """Index names, lower case and known (None: every index)."""
    if wanted is None:
        return INDICES
    out = tuple(dict.fromkeys(str(k).strip().lower() for k in wanted if str(k).strip()))
    bad = [k for k in out if k not in INDICES]
    if bad:
        raise EasyIDPError(f"Unknown vegetation index {', '.join(bad)}: choose from "
                           f"{', '.join(INDICES)}.")
    return out


def cover_kind(names: Sequence[str]) -> Optional[str]:
    """The index canopy cover is measured on by default: 'ndvi' when red and nir are named,
    'exg' when red, green and blue are, else None."""
    if "red" in names and "nir" in names:
        return "ndvi"
    if all(n in names for n in RGB_NAMES):
        return "exg"
    return None


def compute(kind: str, bands: np.ndarray, names: Sequence[str], *,
            dtype=np.float64) -> np.ndarray:
    """Index ``kind`` of the values ``bands`` (bands, n) whose rows are ``names``; of
    ``dtype`` (float64, or float32 for half the memory traffic), NaN where undefined."""
    v = np.asarray(bands, dtype)

    def b(name):
        return v[list(names).index(name)]
    with np.errstate(invalid="ignore", divide="ignore"):
        if kind == "ndvi":
            out = (b("nir") - b("red")) / (b("nir") + b("red"))
        elif kind == "ndre":
            out = (b("nir") - b("rededge")) / (b("nir") + b("rededge"))
        else:
            r, g, bl = b("red"), b("green"), b("blue")
            if kind == "exg":
                out = (2 * g - r - bl) / (r + g + bl)
            elif kind == "exgr":
                out = (3 * g - 2.4 * r - bl) / (r + g + bl)
            elif kind == "vari":
                out = (g - r) / (g + r - bl)
            elif kind == "gli":
                out = (2 * g - r - bl) / (2 * g + r + bl)
            else:
                raise EasyIDPError(f"Unknown vegetation index {kind!r}.")
    out[~np.isfinite(out)] = np.nan
    return out


# ---- histograms and Otsu's threshold --------------------------------------------------------------
_EDGES: Dict[str, np.ndarray] = {}


def bin_edges(kind: str) -> np.ndarray:
    """The :data:`INDEX_BINS` + 1 bin edges over the range of ``kind``."""
    if kind not in _EDGES:
        if kind not in INDEX_RANGE:
            raise EasyIDPError(f"Canopy cover cannot be measured on {kind!r}: choose one of "
                               f"{', '.join(INDEX_RANGE)}.")
        lo, hi = INDEX_RANGE[kind]
        _EDGES[kind] = lo + np.arange(INDEX_BINS + 1) * ((hi - lo) / INDEX_BINS)
    return _EDGES[kind]


def bin_centres(kind: str) -> np.ndarray:
    e = bin_edges(kind)
    return 0.5 * (e[:-1] + e[1:])


def bins_of(kind: str, values: np.ndarray) -> np.ndarray:
    """Bin of each (finite) value: ``edges[k] ≤ v < edges[k + 1]`` exactly; values beyond the
    range go to the first or last bin."""
    e = bin_edges(kind)
    lo, hi = e[0], e[-1]
    v = np.asarray(values, np.float64)
    k = np.clip(np.floor((v - lo) * (INDEX_BINS / (hi - lo))), 0, INDEX_BINS - 1).astype(np.int64)
    k -= (v < e[k]) & (k > 0)                                # the float product's rounding
    k += (v >= e[k + 1]) & (k < INDEX_BINS - 1)
    return k


def index_histogram(kind: str, values: np.ndarray) -> Tuple[int, np.ndarray]:
    """Counts of the finite values of ``kind`` per bin, trimmed to the occupied bins:
    (first bin, counts)."""
    v = np.asarray(values)
    v = v[np.isfinite(v)]
    if not len(v):
        return 0, np.zeros(0, np.int64)
    k = bins_of(kind, v)
    start = int(k.min())
    return start, np.bincount(k - start)


def add_histogram(total: np.ndarray, hist: Tuple[int, np.ndarray]) -> None:
    """Add a trimmed histogram into a full one (in place)."""
    start, counts = hist
    total[start:start + len(counts)] += counts


def otsu_threshold(kind: str, counts: np.ndarray) -> Optional[float]:
    """Otsu's threshold (scikit-image) of a full histogram of :data:`INDEX_BINS` bins, as the
    upper edge of the bin it returns (vegetation: index ≥ threshold); None when the values do
    not fill two bins."""
    from skimage.filters import threshold_otsu
    nz = np.flatnonzero(counts)
    if len(nz) < 2:
        return None
    sl = slice(nz[0], nz[-1] + 1)   # skimage wants no empty bins at the ends (issue 5496)
    centre = float(threshold_otsu(hist=(counts[sl], bin_centres(kind)[sl])))
    k = int(np.argmin(np.abs(bin_centres(kind) - centre)))
    return float(bin_edges(kind)[k + 1])


def cover_from_histogram(kind: str, hist: Tuple[int, np.ndarray], threshold: float) -> float:
    """Share of the values ≥ ``threshold`` in a trimmed histogram, for a threshold on a bin
    edge (as :func:`otsu_threshold` gives); NaN when the histogram is empty."""
    start, counts = hist
    total = counts.sum()
    if not total:
        return float("nan")
    first = int(np.searchsorted(bin_edges(kind), threshold, side="left"))   # first bin above
    return float(counts[max(first - start, 0):].sum() / total)


def cover(values: np.ndarray, threshold: float) -> float:
    """Share of the finite ``values`` ≥ ``threshold``; NaN when there is none."""
    v = np.asarray(values)
    v = v[np.isfinite(v)]
    return float(np.count_nonzero(v >= threshold) / len(v)) if len(v) else float("nan")
