"""CRS helpers around pyproj. Map coordinates are always (easting, northing) / (lon, lat):
every transformer is built with ``always_xy=True``."""
import re
from functools import lru_cache
from typing import Any, List, Optional, Tuple

import numpy as np
from pyproj import CRS, Transformer

from .errors import EasyIDPError, InputError


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


def transform_columns(t: Transformer, *columns) -> Tuple[np.ndarray, ...]:
    """``t.transform`` of equal-length 1-d coordinate arrays, as float64 arrays. pyproj 3.7
    takes one-element arrays for a point and warns under numpy ≥ 1.25, so those go as floats."""
    cols = [np.asarray(c, np.float64).reshape(-1) for c in columns]
    if cols[0].size == 1:
        return tuple(np.array([v], np.float64) for v in t.transform(*(float(c[0]) for c in cols)))
    return tuple(np.asarray(v, np.float64) for v in t.transform(*cols))


def transform_xy(src: CRS, dst: CRS, xy: np.ndarray) -> np.ndarray:
    """Transform an (n, 2) array of map coordinates; returns a new (n, 2) array."""
    xy = np.asarray(xy, dtype=np.float64)
    if src == dst:
        return xy.copy()
    x, y = transform_columns(transformer(src, dst), xy[:, 0], xy[:, 1])
    out = np.column_stack([x, y])
    if not np.all(np.isfinite(out)):
        raise EasyIDPError(f"Coordinates could not be transformed from {src.name} to {dst.name}: "
                           "they lie outside the area where that transformation is defined.")
    return out


def same_crs(a: Optional[CRS], b: Optional[CRS]) -> bool:
    if a is None or b is None:
        return a is b
    return a == b or a.equals(b, ignore_axis_order=True)


# --- a project's CRS as the photogrammetry software wrote it ------------------------------------
def _wkt_name(text: str) -> str:
    """The name of the outermost WKT object (``PROJCS["CH1903+ / LV95",…`` → ``CH1903+ / LV95``)."""
    m = re.match(r'\s*\w+\s*\[\s*"([^"]*)"', text)
    return m.group(1) if m else text[:60]


def wkt_top_authority(text: str) -> Optional[Tuple[str, str]]:
    """(authority, code) of the outermost object's own ``AUTHORITY[…]`` / ``ID[…]`` (the last
    one at nesting depth 1), or None. Nested ones (datum, ellipsoid, unit) are not looked at."""
    depth, quoted, found = 0, False, None
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif ch in "[(":
            depth += 1
            if depth == 2:
                m = re.search(r'(AUTHORITY|ID)\s*$', text[max(0, i - 12):i])
                if m:
                    a = re.match(r'\[\s*"([^"]+)"\s*,\s*"?([^",\]]+)"?', text[i:])
                    if a:
                        found = (a.group(1).strip(), a.group(2).strip())
        elif ch in "])":
            depth -= 1
    return found


def _params(crs: CRS) -> List[Tuple[str, float]]:
    """(unit category, value in radians / metres / unity) of the map projection's parameters."""
    op = crs.coordinate_operation
    return [(p.unit_category, float(p.value) * (p.unit_conversion_factor or 1.0))
            for p in (op.params if op is not None else [])]


def _close(category: str, a: float, b: float) -> bool:
    tol = 1e-3 if category == "linear" else 1e-9     # 1 mm; 1e-9 rad (6 mm on the Earth) / unity
    return abs(a - b) <= tol + 1e-12 * abs(b)


def same_definition(custom: CRS, candidate: CRS) -> bool:
    """True when ``candidate`` (an EPSG CRS) defines the same coordinates as ``custom``, judged
    by numbers only, not by names (which WKT dialects spell differently, or wrongly): the same
    kind of CRS, ellipsoid (a to 1 mm, 1/f to 1e-6), prime meridian, axis unit and map
    projection parameter values. Every parameter of ``custom`` must match one of
    ``candidate``'s; a parameter of ``candidate`` left over must be 0 or equal to a matched one
    (WKT1 dialects omit zero parameters, and ESRI's Hotine "azimuth centre" omits the rectified
    grid angle, which then equals the azimuth)."""
    custom, candidate = unbound(custom), unbound(candidate)
    if custom.is_compound or candidate.is_compound:
        a, b = custom.sub_crs_list, candidate.sub_crs_list
        if len(a) != len(b) or not a:
            return False
        if not same_definition(a[0], b[0]):
            return False
        norm = lambda c: "".join(ch for ch in (c.name or "").lower() if ch.isalnum())
        return all(norm(x) == norm(y) for x, y in zip(a[1:], b[1:]))
    if (custom.is_projected, custom.is_geographic, custom.is_geocentric) != \
            (candidate.is_projected, candidate.is_geographic, candidate.is_geocentric):
        return False
    ea, eb = custom.ellipsoid, candidate.ellipsoid
    if ea is None or eb is None:
        return False
    if abs(ea.semi_major_metre - eb.semi_major_metre) > 1e-3 or \
            abs((ea.inverse_flattening or 0.0) - (eb.inverse_flattening or 0.0)) > 1e-6:
        return False
    pa, pb = custom.prime_meridian, candidate.prime_meridian
    if pa is not None and pb is not None and abs(
            pa.longitude * (pa.unit_conversion_factor or 1) -
            pb.longitude * (pb.unit_conversion_factor or 1)) > 1e-9:
        return False
    ua = [a.unit_conversion_factor for a in custom.axis_info[:2]]
    ub = [a.unit_conversion_factor for a in candidate.axis_info[:2]]
    if ua and ub and abs(ua[0] - ub[0]) > 1e-12:
        return False
    if not custom.is_projected:
        return True
    left = _params(candidate)
    matched = []
    for cat, v in _params(custom):
        hit = next((k for k, (c2, v2) in enumerate(left) if c2 == cat and _close(cat, v, v2)), None)
        if hit is None:
            if abs(v) <= 1e-12:               # a zero the candidate leaves out
                continue
            return False
        matched.append(left.pop(hit))
    return all(abs(v) <= 1e-12 or any(c == cat and _close(cat, v, v2) for c, v2 in matched)
               for cat, v in left)


def usable(crs: CRS) -> bool:
    """True when PROJ can transform coordinates of ``crs`` (to its geographic CRS and back)."""
    geog = unbound(crs).geodetic_crs
    if geog is None:
        return True
    try:
        t = Transformer.from_crs(geog, crs, always_xy=True)
        Transformer.from_crs(crs, geog, always_xy=True)
        t.transform(0.0, 0.0)
        return True
    except Exception:                           # pyproj.exceptions.ProjError, CRSError
        return False


def unbound(crs: CRS) -> CRS:
    """Drop a WKT1 TOWGS84 wrapper (BoundCRS), as Metashape and Pix4D write it."""
    return crs.source_crs if crs.is_bound else crs


def project_crs(text: str, where: str, given: Any = None) -> Tuple[Optional[CRS], str]:
    """(CRS, how it was resolved) of a CRS a photogrammetry project wrote (Metashape chunk
    ``<reference>``, Pix4D ``*_wkt.prj``), in this order:

    1. the WKT's own top-level ``AUTHORITY`` (e.g. EPSG:2056), if its parameters agree
       (:func:`same_definition`);
    2. an EPSG match that PROJ finds, at any confidence, if its parameters agree;
    3. the custom CRS as written, if PROJ can transform it (:func:`usable`);
    4. ``given`` (the user's CRS) when the text cannot be used; else :class:`InputError`
       naming the CRS and asking for its EPSG code.

    A local (engineering) CRS is returned as it is. ``given`` with a usable CRS in the text is
    refused when the two differ. The note is "" when the text is an EPSG CRS as it stands.
    """
    text = (text or "").strip()
    name = _wkt_name(text)
    ask = (f"{where}: the project CRS {name!r} is not one PROJ can use as written, and it "
           "matches no EPSG code. Give its EPSG code as the project CRS (the 'Project CRS' "
           "parameter, or crs= in Python), e.g. EPSG:2056 for CH1903+ / LV95.")
    user = as_crs(given, "The project CRS") if given is not None else None
    try:
        crs = unbound(CRS.from_user_input(text))
    except Exception:                           # pyproj.exceptions.CRSError
        if user is not None:
            return user, f"the project CRS {name!r} cannot be read; using the one given, {user.name}"
        raise InputError(ask) from None
    resolved, how = None, ""
    if crs.geodetic_crs is None:                # local / engineering
        resolved = crs
    else:
        top = wkt_top_authority(text)
        if top is not None:
            try:
                own = CRS.from_authority(*top)
            except Exception:
                own = None
            if own is not None and same_definition(crs, own):
                resolved = own
                if crs.to_epsg(min_confidence=90) != own.to_epsg(min_confidence=90):
                    how = f"read as {top[0]}:{top[1]} ({own.name}), its own AUTHORITY"
            else:
                how = f"its AUTHORITY {top[0]}:{top[1]} disagrees with its parameters; "
        if resolved is None:
            try:
                matches = crs.list_authority(min_confidence=1)
            except Exception:                   # pyproj.exceptions.CRSError: nothing to match
                matches = []
            for match in matches:
                if match.auth_name != "EPSG":
                    continue
                cand = CRS.from_epsg(int(match.code))
                if same_definition(crs, cand):
                    resolved = cand
                    if match.confidence < 90 or how:
                        how += (f"matched to EPSG:{match.code} ({cand.name}; PROJ's confidence "
                                f"{match.confidence} %, the parameters agree)")
                    break
        if resolved is None and usable(crs):
            resolved = crs
            how += "kept as written (a custom CRS with no EPSG code; PROJ can use it)"
    if resolved is None:
        if user is not None:
            return user, f"the project CRS {name!r} cannot be used; using the one given, {user.name}"
        raise InputError(ask + (f" ({how.rstrip('; ')})" if how else ""))
    if user is not None and not same_crs(user, resolved):
        raise InputError(f"{where}: the project is georeferenced in {resolved.name}; do not "
                         f"pass another project CRS ({user.name}). Choose the output CRS instead.")
    return resolved, (f"project CRS {name!r}: {how}" if how else "")
