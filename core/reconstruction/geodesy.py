"""Map CRS ↔ the Cartesian *model frame* in which camera poses are kept.

Every :class:`~.model.Reconstruction` keeps its cameras in one right-handed Cartesian frame in
metres (or the local unit), chosen so coordinates stay small:

* :class:`GeocentricFrame` (Metashape, georeferenced chunk): the geocentric frame of the chunk
  CRS *datum* (not always WGS 84), shifted to an origin near the scene and rotated to east,
  north, up there. Heights given in a 2-D or 3-D geographic/projected CRS are ellipsoidal;
  a compound CRS with a geoid height is converted with its geoid model (an error is raised if
  the geoid grid is not installed, rather than silently using ellipsoidal heights).
* :class:`OffsetFrame` (Pix4D): project CRS coordinates minus ``offset.xyz``; heights are those
  of the project output CRS.
* :class:`LocalFrame` (local/engineering CRS, or no CRS): the local coordinates themselves.
"""
from typing import Optional

import numpy as np
from pyproj import CRS
from pyproj.transformer import TransformerGroup

from ..crs import as_crs, same_crs, transform_columns, transformer, unbound
from ..errors import EasyIDPError

_ECEF_CS = {"subtype": "Cartesian", "axis": [
    {"name": "Geocentric X", "abbreviation": "X", "direction": "geocentricX", "unit": "metre"},
    {"name": "Geocentric Y", "abbreviation": "Y", "direction": "geocentricY", "unit": "metre"},
    {"name": "Geocentric Z", "abbreviation": "Z", "direction": "geocentricZ", "unit": "metre"}]}


def is_local(crs: Optional[CRS]) -> bool:
    """True for no CRS or a local/engineering CRS (no geodetic datum)."""
    return crs is None or crs.geodetic_crs is None


def geocentric_of(crs: CRS) -> CRS:
    """The geocentric (ECEF) CRS on the same datum as ``crs`` (e.g. JGD2011 → EPSG:6666)."""
    geodetic = unbound(crs).geodetic_crs
    if geodetic is None:
        raise EasyIDPError(f"{crs.name} has no geodetic datum, so it has no geocentric frame.")
    j = geodetic.to_json_dict()
    j["type"] = "GeodeticCRS"
    j.pop("id", None)
    j["coordinate_system"] = _ECEF_CS
    j["name"] = f"{geodetic.name} (geocentric)"
    out = CRS.from_json_dict(j)
    code = out.to_epsg(min_confidence=90)
    return CRS.from_epsg(code) if code else out


def enu_rotation(lon_deg: float, lat_deg: float) -> np.ndarray:
    """(3, 3) rotation whose rows are east, north, up at (lon, lat), in geocentric coordinates:
    ``enu = R · (ecef − origin)`` for a local east-north-up frame at that place."""
    lo, la = np.radians(lon_deg), np.radians(lat_deg)
    return np.array([[-np.sin(lo), np.cos(lo), 0.0],
                     [-np.sin(la) * np.cos(lo), -np.sin(la) * np.sin(lo), np.cos(la)],
                     [np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)]])


def _check_vertical(src: CRS, dst: CRS) -> None:
    """Refuse a transformation that would silently drop a geoid model (grid not installed)."""
    if not any(s.is_vertical for s in (src.sub_crs_list or [])) and not src.is_vertical:
        return
    group = TransformerGroup(src, dst, always_xy=True)
    if not group.best_available:
        raise EasyIDPError(
            f"Heights in {src.name} need a geoid grid that is not installed, so they cannot be "
            "converted to ellipsoidal heights exactly. Install the PROJ grid (projsync, or the "
            "proj-data package), enable PROJ_NETWORK=ON, or give points in a CRS with "
            "ellipsoidal heights.")


def _transform3(src: CRS, dst: CRS, xyz: np.ndarray) -> np.ndarray:
    if same_crs(src, dst):
        return np.array(xyz, dtype=np.float64, copy=True)
    _check_vertical(src, dst)
    x, y, z = transform_columns(transformer(src, dst), xyz[:, 0], xyz[:, 1], xyz[:, 2])
    out = np.column_stack([x, y, z])
    bad = ~np.all(np.isfinite(out), axis=1) & np.all(np.isfinite(xyz), axis=1)
    if bad.any():
        raise EasyIDPError(f"{int(bad.sum())} point(s) could not be transformed from {src.name} "
                           f"to {dst.name}: they lie outside its area of use.")
    return out


def _as_points(xyz) -> np.ndarray:
    a = np.asarray(xyz, dtype=np.float64)
    if a.ndim == 1:
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] != 3:
        raise EasyIDPError(f"Points must be an (n, 3) array of x, y, z; got shape {a.shape}.")
    return a


class ModelFrame:
    """Base class: ``to_model(xyz, crs)`` and ``from_model(xyz, crs)`` for (n, 3) arrays."""
    crs: Optional[CRS] = None

    def to_model(self, xyz, crs=None) -> np.ndarray:
        raise NotImplementedError

    def from_model(self, xyz, crs=None) -> np.ndarray:
        raise NotImplementedError

    def up(self, xyz_model: np.ndarray) -> np.ndarray:
        """Unit "up" vectors (n, 3) at model points (normal of the CRS's height axis)."""
        xyz_model = _as_points(xyz_model)
        m = self.from_model(xyz_model)
        m[:, 2] += 1.0
        d = self.to_model(m) - xyz_model
        return d / np.linalg.norm(d, axis=1, keepdims=True)


class GeocentricFrame(ModelFrame):
    """East-north-up frame at ``origin`` (geocentric, datum of ``crs``): X_model = E·(X_ecef − O)."""

    def __init__(self, crs: CRS, origin_ecef: np.ndarray):
        self.crs = unbound(crs)
        self.ecef = geocentric_of(self.crs)
        self.origin = np.asarray(origin_ecef, dtype=np.float64)
        geog = self.crs.geodetic_crs                        # geographic, same datum
        lon, lat, _ = transformer(self.ecef, geog).transform(*self.origin)
        self.rotation = enu_rotation(lon, lat)

    def ecef_to_model(self, ecef: np.ndarray) -> np.ndarray:
        return (ecef - self.origin) @ self.rotation.T

    def to_model(self, xyz, crs=None) -> np.ndarray:
        src = unbound(as_crs(crs)) if crs is not None else self.crs
        if is_local(src):
            raise EasyIDPError(f"Points in the local CRS {src.name if src else '(none)'} cannot "
                               f"be placed in a chunk georeferenced in {self.crs.name}.")
        return self.ecef_to_model(_transform3(src, self.ecef, _as_points(xyz)))

    def from_model(self, xyz, crs=None) -> np.ndarray:
        dst = unbound(as_crs(crs)) if crs is not None else self.crs
        ecef = _as_points(xyz) @ self.rotation + self.origin
        return _transform3(self.ecef, dst, ecef)


class OffsetFrame(ModelFrame):
    """Project CRS coordinates minus an offset (Pix4D ``offset.xyz``): model = scale·xyz − offset,
    per axis in (x, y, z) = (east, north, up) order; ``scale`` 1 but for OPF projects whose CRS
    axes have different units (OPF's base → canonical scale)."""

    def __init__(self, crs: Optional[CRS], offset, scale=(1.0, 1.0, 1.0)):
        self.crs = crs
        self.offset = np.asarray(offset, dtype=np.float64)
        self.scale = np.asarray(scale, dtype=np.float64)

    def to_model(self, xyz, crs=None) -> np.ndarray:
        xyz = _as_points(xyz)
        src = as_crs(crs)
        if src is not None and self.crs is None:
            raise EasyIDPError(f"The project's CRS is unknown (no *_wkt.prj), so points in "
                               f"{src.name} cannot be placed in it. Pass crs= to "
                               "open_reconstruction, or give points in the project CRS with crs=None.")
        if src is not None and not same_crs(src, self.crs):
            xyz = _transform3(src, self.crs, xyz)
        return xyz * self.scale - self.offset

    def from_model(self, xyz, crs=None) -> np.ndarray:
        out = (_as_points(xyz) + self.offset) / self.scale
        dst = as_crs(crs)
        if dst is not None and self.crs is not None and not same_crs(dst, self.crs):
            out = _transform3(self.crs, dst, out)
        return out


class LocalFrame(ModelFrame):
    """Local/engineering coordinates (e.g. Metashape LOCAL_CS): no CRS conversion possible."""

    def __init__(self, crs: Optional[CRS] = None):
        self.crs = crs

    def _check(self, crs):
        c = as_crs(crs)
        if c is not None and not (self.crs is not None and same_crs(c, self.crs)):
            raise EasyIDPError(f"This project uses a local coordinate system "
                               f"({self.crs.name if self.crs else 'none'}); points in {c.name} "
                               "cannot be converted to it. Give local coordinates with crs=None.")

    def to_model(self, xyz, crs=None) -> np.ndarray:
        self._check(crs)
        return _as_points(xyz).copy()

    def from_model(self, xyz, crs=None) -> np.ndarray:
        self._check(crs)
        return _as_points(xyz).copy()
