"""Regions of interest: named polygons or multipolygons in one CRS.

``ROI.parts`` is a list of polygons, each a list of rings ``[exterior, hole, ...]``; a ring is an
open (n, 2) float64 array of map coordinates (x, y) = (easting, northing) or (lon, lat).
``ROI.z`` is None, or the vertex heights of a 3-D geometry (PolygonZ), nested like ``parts``:
one (n,) float64 array per ring, in the vertical reference of the source.
"""
from dataclasses import dataclass, field
from typing import Callable, Iterator, List, Optional, Sequence, Tuple

import numpy as np
from pyproj import CRS

from .. import geometry
from ..crs import as_crs, same_crs, transform_xy
from ..errors import ROIError
from ..ragged import offsets


@dataclass
class ROI:
    name: str
    parts: List[List[np.ndarray]]
    attributes: dict = field(default_factory=dict)
    z: Optional[List[List[np.ndarray]]] = None

    @property
    def rings(self) -> List[np.ndarray]:
        """All rings of all parts (even-odd inside-ness over them is the polygon)."""
        return [ring for part in self.parts for ring in part]

    @property
    def bounds(self) -> Tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax)."""
        allxy = np.concatenate(self.rings)
        return (float(allxy[:, 0].min()), float(allxy[:, 1].min()),
                float(allxy[:, 0].max()), float(allxy[:, 1].max()))

    @property
    def area(self) -> float:
        return geometry.area(self.rings)

    @property
    def ring_z(self) -> Optional[List[np.ndarray]]:
        """Vertex heights of all rings (aligned with :attr:`rings`), or None for a 2-D ROI."""
        return None if self.z is None else [z for part in self.z for z in part]

    def map_xy(self, fn: Callable[[np.ndarray], np.ndarray]) -> "ROI":
        """A copy with ``fn`` ((n, 2) → (n, 2)) applied to every ring (heights kept)."""
        return ROI(self.name, [[fn(r) for r in part] for part in self.parts], dict(self.attributes),
                   self.z)

    def validate(self) -> "ROI":
        """Raise :class:`ROIError` naming this ROI if it is empty or not a valid polygon."""
        if not self.parts or not any(len(p) for p in self.parts):
            raise ROIError(f"ROI {self.name!r} has an empty geometry: remove the feature or draw it.")
        for ring in self.rings:
            if not np.all(np.isfinite(ring)):
                raise ROIError(f"ROI {self.name!r} has non-finite coordinates.")
        bad = geometry.self_intersections(self.rings) if all(len(r) >= 3 for r in self.rings) else []
        if bad:
            x, y = bad[0]
            raise ROIError(f"ROI {self.name!r} is not a valid polygon: its boundary crosses itself "
                           f"near ({x:.6g}, {y:.6g}). Repair it (QGIS: Vector geometry ▸ Fix "
                           "geometries) and run again.")
        for ring in self.rings:
            if len(ring) < 3 or abs(geometry.ring_area(ring)) == 0.0:
                raise ROIError(f"ROI {self.name!r} has a ring with no area (fewer than 3 distinct "
                               "vertices or all on one line): fix or remove the feature.")
        return self


def roi_from_coordinates(name: str, geom_type: str, coordinates, attributes=None) -> ROI:
    """An ROI from GeoJSON-style ``Polygon`` or ``MultiPolygon`` coordinates.

    A third coordinate is kept as the ROI's vertex heights (:attr:`ROI.z`) when every vertex
    has one; a repeated closing vertex and consecutive duplicates are dropped.

    Parameters
    ----------
    name : str
        The ROI's name.
    geom_type : {"Polygon", "MultiPolygon"}
        The GeoJSON geometry type of ``coordinates``.
    coordinates : nested sequences
        GeoJSON-style rings: ``[[(x, y), …], …]`` for a polygon (outer ring first, then holes),
        a list of those for a multipolygon; (x, y, z) vertices keep their z.
    attributes : dict, optional
        The ROI's attributes.

    Returns
    -------
    ROI
        The ROI (not yet validated: :meth:`ROI.validate`).
    """
    if geom_type == "Polygon":
        polys = [coordinates]
    elif geom_type == "MultiPolygon":
        polys = coordinates
    else:
        raise ROIError(f"ROI {name!r} is a {geom_type}, not a polygon: ROIs must be polygons or "
                       "multipolygons (buffer points or lines first).")
    if coordinates is None:                                 # an empty geometry
        polys = []
    if not _is_list(polys) or not all(_is_list(p) and all(_is_list(r) for r in p)
                                      for p in polys):
        raise ROIError(f"ROI {name!r}: its {geom_type} coordinates are not nested lists of "
                       f"rings: {str(coordinates)[:80]}.")
    parts, heights = [], []
    for poly in polys:
        rings = [_ring_xyz(name, r) for r in poly if len(r)]
        if rings:
            parts.append([geometry.close_ring(r[:, :2], keep=keep) for r, keep in rings])
            heights.append([r[keep, 2] if r.shape[1] > 2 else None for r, keep in rings])
    has_z = bool(parts) and all(z is not None for zs in heights for z in zs)
    return ROI(str(name), parts, dict(attributes or {}), heights if has_z else None)


def _is_list(value) -> bool:
    """A GeoJSON array (a list or tuple, or an array from a reader), not a string or number."""
    return isinstance(value, (list, tuple, np.ndarray))


def _ring_xyz(name: str, ring):
    """(ring as an (n, 2 or 3) float array, indices of the vertices :func:`close_ring` keeps)."""
    try:
        arr = np.asarray([tuple(v) for v in ring], dtype=np.float64)
    except (TypeError, ValueError):
        raise ROIError(f"ROI {name!r}: a ring's coordinates are not numbers: "
                       f"{str(ring)[:80]}.") from None
    if arr.ndim != 2 or arr.shape[1] < 2:
        raise ROIError(f"ROI {name!r}: a ring's coordinates are not (x, y[, z]) pairs.")
    if arr.shape[1] > 3:
        arr = arr[:, :3]                                    # x, y, z; an M value is dropped
    return arr, geometry.ring_keep(arr[:, :2])


class ROISet(Sequence[ROI]):
    """An ordered collection of ROIs sharing one CRS (None when unknown)."""

    def __init__(self, rois: Sequence[ROI], crs=None):
        self.rois: List[ROI] = list(rois)
        self.crs: Optional[CRS] = as_crs(crs, "ROI CRS")

    def __getitem__(self, i):
        return self.rois[i]

    def __len__(self) -> int:
        return len(self.rois)

    def __iter__(self) -> Iterator[ROI]:
        return iter(self.rois)

    @property
    def names(self) -> List[str]:
        return [r.name for r in self.rois]

    def to_crs(self, crs) -> "ROISet":
        """The ROIs reprojected vertex by vertex into ``crs``."""
        crs = as_crs(crs)
        if self.crs is None:
            raise ROIError.of("rois_no_crs")
        if same_crs(self.crs, crs):
            return ROISet(self.rois, crs)
        return ROISet([r.map_xy(lambda xy: transform_xy(self.crs, crs, xy)) for r in self.rois], crs)

    def validate(self) -> "ROISet":
        """Raise :class:`ROIError` for an empty set or the first invalid ROI; the set as it was
        validated is remembered (a tool validates, then the core function it calls again)."""
        if not self.rois:
            raise ROIError.of("rois_no_features")
        key = tuple(map(id, self.rois))
        if getattr(self, "_validated", None) == key:
            return self
        for r in _not_plainly_valid(self.rois):
            r.validate()
        self._validated = key
        return self


def _not_plainly_valid(rois: Sequence[ROI]) -> List[ROI]:
    """The ROIs :meth:`ROI.validate` has to look at one by one: all but those of one finite,
    strictly convex ring (valid by :func:`geometry.convex_simple_rings`, checked for all at
    once: the per-ROI cost of validating thousands of plots)."""
    single = [r for r in rois if len(r.parts) == 1 and len(r.parts[0]) == 1
              and len(r.parts[0][0]) >= 3]
    if not single:
        return list(rois)
    rings = [r.parts[0][0] for r in single]
    xy = np.concatenate(rings)
    offs = offsets([len(r) for r in rings])
    finite = np.logical_and.reduceat(np.isfinite(xy).all(axis=1), offs[:-1])
    ok = geometry.convex_simple_rings(np.where(np.isfinite(xy), xy, 0.0), offs) & finite
    plain = {id(r) for r, good in zip(single, ok) if good}
    return [r for r in rois if id(r) not in plain]
