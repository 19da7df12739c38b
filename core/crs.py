"""CRS helpers around pyproj. Map coordinates are always (easting, northing) / (lon, lat):
every transformer is built with ``always_xy=True``."""
from functools import lru_cache
from typing import Any, Optional

import numpy as np
from pyproj import CRS, Transformer

from .errors import EasyIDPError


def as_crs(value: Any, what: str = "CRS") -> Optional[CRS]:
    """A pyproj CRS from a CRS, an EPSG code (int or 'EPSG:n'), WKT, PROJ string; None stays None."""
    if value is None or isinstance(value, CRS):
        return value
    try:
        return CRS.from_user_input(value)
    except Exception as exc:  # pyproj raises CRSError with a terse message
        raise EasyIDPError(f"{what}: cannot understand {str(value)[:80]!r} as a coordinate "
                           f"reference system ({exc}). Give an EPSG code or WKT.") from None


@lru_cache(maxsize=64)
def _transformer(src_wkt: str, dst_wkt: str) -> Transformer:
    return Transformer.from_crs(CRS.from_wkt(src_wkt), CRS.from_wkt(dst_wkt), always_xy=True)


def transformer(src: CRS, dst: CRS) -> Transformer:
    """A cached (x, y[, z]) → (x, y[, z]) transformer in traditional GIS axis order."""
    return _transformer(src.to_wkt(), dst.to_wkt())


def transform_xy(src: CRS, dst: CRS, xy: np.ndarray) -> np.ndarray:
    """Transform an (n, 2) array of map coordinates; returns a new (n, 2) array."""
    xy = np.asarray(xy, dtype=np.float64)
    if src == dst:
        return xy.copy()
    x, y = transformer(src, dst).transform(xy[:, 0], xy[:, 1])
    out = np.column_stack([x, y])
    if not np.all(np.isfinite(out)):
        raise EasyIDPError(f"Coordinates could not be transformed from {src.name} to {dst.name}: "
                           "they lie outside the area where that transformation is defined.")
    return out


def same_crs(a: Optional[CRS], b: Optional[CRS]) -> bool:
    if a is None or b is None:
        return a is b
    return a == b or a.equals(b, ignore_axis_order=True)
