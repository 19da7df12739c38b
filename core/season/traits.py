"""Trait names and the per-ROI computations on pixels and points.

Traits (names in the long table; heights in the units of the DSM or cloud, usually metres):

* from a DSM: ``height_pNN``: the NN-th percentile of the ROI's DSM pixels above the ground;
* from an orthomosaic: ``mean_<band>`` (e.g. ``mean_red``; ``mean_b1``… for unnamed bands) in
  the raster's values; ``exg`` (mean excess green 2g − r − b of the chromatic coordinates, RGB)
  or ``ndvi`` (mean (nir − red)/(nir + red), when the bands are named); ``cover``: the share of
  the ROI's pixels whose index (ExG or NDVI) is at or above the threshold (0–1), the threshold
  being given or Otsu's over the histogram of all ROIs' pixels of that raster (the indices,
  histograms and Otsu's threshold are :mod:`core.indices`, shared with the photo statistics);
* from a point cloud: ``cloud_height_pNN`` and ``cloud_points`` (the count).

A pixel counts when its centre is inside the ROI and it is valid (not nodata, alpha > 0).
"""
import re
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..errors import EasyIDPError
from ..indices import RGB_NAMES
from ..raster import TAG_GDAL_METADATA, GeoTiff
from ..safe_xml import XMLError, parse_xml

TRAIT_GROUPS = ("height", "cover", "bands", "index", "cloud")
"""What can be asked for: DSM heights, canopy cover, band means, the vegetation index (ExG or
NDVI), point-cloud heights."""
DEFAULT_PERCENTILES = (50.0, 95.0, 99.0)


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
        root = parse_xml(xml)
    except XMLError:
        return []
    out: Dict[int, str] = {}
    for item in root.iter("Item"):
        if item.get("role") == "description" and item.get("sample") is not None:
            out[int(item.get("sample"))] = (item.text or "").strip()
    return [out.get(k, "") for k in range(max(out) + 1)] if out else []


# ---- heights ----------------------------------------------------------------------------------

def height_percentiles(h: np.ndarray, percentiles: Sequence[float], prefix: str) -> Dict[str, float]:
    """{prefix_pNN: NN-th percentile of the finite heights} (NaN when there is none)."""
    h = h[np.isfinite(h)]
    if not len(h):
        return {percentile_name(prefix, q): float("nan") for q in percentiles}
    values = np.percentile(h, list(percentiles))
    return {percentile_name(prefix, q): float(v) for q, v in zip(percentiles, values)}
