"""Trait names and the per-ROI computations on pixels and points.

Traits (names in the long table; heights in the units of the DSM or cloud, usually metres):

* from a DSM: ``height_pNN``: the NN-th percentile of the ROI's DSM pixels above the ground;
* from an orthomosaic: ``mean_<band>`` (e.g. ``mean_red``; ``mean_b1``… for unnamed bands) in
  the raster's values; ``exg`` (mean excess green 2g − r − b of the chromatic coordinates, RGB)
  or ``ndvi`` (mean (nir − red)/(nir + red), when the bands are named); ``cover``: the share of
  the ROI's pixels whose index (ExG or NDVI) is above the threshold (0–1), the threshold being
  given or Otsu's over the histogram of all ROIs' pixels of that raster (scikit-image);
* from a point cloud: ``cloud_height_pNN`` and ``cloud_points`` (the count).

A pixel counts when its centre is inside the ROI and it is valid (not nodata, alpha > 0).
"""
import re
import xml.etree.ElementTree as ET
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..errors import EasyIDPError
from ..raster.geotiff import TAG_GDAL_METADATA, GeoTiff

TRAIT_GROUPS = ("height", "cover", "bands", "index", "cloud")
"""What can be asked for: DSM heights, canopy cover, band means, the vegetation index (ExG or
NDVI), point-cloud heights."""
DEFAULT_PERCENTILES = (50.0, 95.0, 99.0)
INDEX_RANGE = {"exg": (-1.0, 2.0), "ndvi": (-1.0, 1.0)}
INDEX_BINS = 3000     # histogram bins over the index range (ExG: 0.001 per bin)
RGB_NAMES = ("red", "green", "blue")


def check_traits(traits: Optional[Sequence[str]]) -> Tuple[str, ...]:
    if traits is None:
        return TRAIT_GROUPS
    out = tuple(dict.fromkeys(str(t).strip().lower() for t in traits))
    bad = [t for t in out if t not in TRAIT_GROUPS]
    if bad or not out:
        raise EasyIDPError(f"Unknown trait(s) {', '.join(bad) or '(none)'}: choose from "
                           f"{', '.join(TRAIT_GROUPS)}.")
    return out


def check_percentiles(percentiles: Sequence[float]) -> Tuple[float, ...]:
    out = tuple(dict.fromkeys(float(q) for q in percentiles))
    if not out or any(not 0 <= q <= 100 for q in out):
        raise EasyIDPError(f"Height percentiles must be numbers from 0 to 100 (got "
                           f"{list(percentiles)}).")
    return out


def percentile_name(prefix: str, q: float) -> str:
    """'height_p95', 'height_p99_5'."""
    return f"{prefix}_p{q:g}".replace(".", "_")


# ---- orthomosaic bands ------------------------------------------------------------------------

def band_names(tif: GeoTiff, given: Optional[Sequence[str]] = None) -> List[str]:
    """Names of the colour/data bands (alpha excluded), lower case: ``given`` (the table's
    ``bands`` column), else GDAL's band descriptions, else red/green/blue for RGB(A), else
    b1, b2, …"""
    n = tif.bands - (1 if tif.alpha_band is not None else 0)
    if given:
        names = [str(b).strip().lower() for b in given]
        if len(names) != n:
            raise EasyIDPError(f"{tif.path} has {n} bands but the survey table names "
                               f"{len(names)} ({', '.join(names)}); give one name per band.")
        return names
    described = _gdal_descriptions(tif)
    if described and len(described) >= n and all(described[:n]):
        return [re.sub(r"\W+", "_", d.strip().lower()) for d in described[:n]]
    if tif.kind in ("rgb", "rgba") and n == 3:
        return list(RGB_NAMES)
    return [f"b{k + 1}" for k in range(n)]


def _gdal_descriptions(tif: GeoTiff) -> List[str]:
    """Band descriptions from GDAL's metadata tag, by band (empty strings where none)."""
    xml = tif.geo_tags.get(TAG_GDAL_METADATA)
    if not xml:
        return []
    try:
        root = ET.fromstring(xml)
    except ET.ParseError:
        return []
    out: Dict[int, str] = {}
    for item in root.iter("Item"):
        if item.get("role") == "description" and item.get("sample") is not None:
            out[int(item.get("sample"))] = (item.text or "").strip()
    return [out.get(k, "") for k in range(max(out) + 1)] if out else []


def index_kind(names: Sequence[str], tif: GeoTiff) -> Optional[str]:
    """'ndvi' when red and nir are named, 'exg' when red, green and blue are, else None."""
    if "red" in names and "nir" in names:
        return "ndvi"
    if all(n in names for n in RGB_NAMES):
        return "exg"
    return None


def vegetation_index(kind: str, bands: np.ndarray, names: Sequence[str]) -> np.ndarray:
    """ExG or NDVI of the values ``bands`` (bands, n), float64; NaN where undefined (zero
    sum)."""
    v = np.asarray(bands, np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        if kind == "ndvi":
            red, nir = v[names.index("red")], v[names.index("nir")]
            return (nir - red) / (nir + red)
        r, g, b = (v[names.index(n)] for n in RGB_NAMES)
        return (2 * g - r - b) / (r + g + b)


def index_histogram(kind: str, values: np.ndarray) -> Tuple[int, np.ndarray]:
    """Counts of the finite index values in :data:`INDEX_BINS` equal bins over the index range,
    trimmed to the occupied bins: (first bin, counts)."""
    lo, hi = INDEX_RANGE[kind]
    v = values[np.isfinite(values)]
    if not len(v):
        return 0, np.zeros(0, np.int64)
    k = np.clip(((v - lo) * (INDEX_BINS / (hi - lo))).astype(np.int64), 0, INDEX_BINS - 1)
    start = int(k.min())
    return start, np.bincount(k - start)


def add_histogram(total: np.ndarray, hist: Tuple[int, np.ndarray]) -> None:
    """Add a trimmed histogram into a full one (in place)."""
    start, counts = hist
    total[start:start + len(counts)] += counts


def bin_centres(kind: str) -> np.ndarray:
    lo, hi = INDEX_RANGE[kind]
    return lo + (np.arange(INDEX_BINS) + 0.5) * ((hi - lo) / INDEX_BINS)


def otsu_threshold(kind: str, counts: np.ndarray) -> Optional[float]:
    """Otsu's threshold (scikit-image) of a full histogram of :data:`INDEX_BINS` bins; None
    when the values do not fill two bins."""
    from skimage.filters import threshold_otsu
    nz = np.flatnonzero(counts)
    if len(nz) < 2:
        return None
    sl = slice(nz[0], nz[-1] + 1)   # skimage wants no empty bins at the ends
    return float(threshold_otsu(hist=(counts[sl], bin_centres(kind)[sl])))


def cover_from_histogram(kind: str, hist: Tuple[int, np.ndarray], threshold: float) -> float:
    """Share of the values above ``threshold`` (the bins whose centre is above it) in a
    trimmed histogram; NaN when it is empty."""
    start, counts = hist
    total = counts.sum()
    if not total:
        return float("nan")
    centres = bin_centres(kind)[start:start + len(counts)]
    return float(counts[centres > threshold].sum() / total)


# ---- heights ----------------------------------------------------------------------------------

def height_percentiles(h: np.ndarray, percentiles: Sequence[float], prefix: str) -> Dict[str, float]:
    """{prefix_pNN: NN-th percentile of the finite heights} (NaN when there is none)."""
    h = h[np.isfinite(h)]
    if not len(h):
        return {percentile_name(prefix, q): float("nan") for q in percentiles}
    values = np.percentile(h, list(percentiles))
    return {percentile_name(prefix, q): float(v) for q, v in zip(percentiles, values)}
