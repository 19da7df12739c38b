"""A map polygon: an object on the map made from forward-projected shapes (:mod:`.merge`,
:mod:`.fuse`), and the shapely polygon of a forward-projected shape (the geometry both use)."""
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from .forward import ForwardShape


@dataclass
class MapPolygon:
    """One object on the map. ``parts``: list of polygons, each a list of (k, 3) rings
    (exterior first, open). ``photos``: the photos it was found in (the chosen one first)."""
    label: str
    parts: List[List[np.ndarray]]
    photos: List[str]
    views: int
    complete: bool
    area_m2: float
    perimeter_m: float
    score: Optional[float] = None
    members: List[ForwardShape] = field(default_factory=list)


def shapely_polygon(f: ForwardShape):
    """The shapely (Multi)Polygon of a forward-projected polygon on the map x, y (made valid
    where its rings fold), or None without a ring of 3 vertices or more."""
    import shapely
    rings = [r for r in f.rings if len(r) >= 3]
    if not rings or len(f.rings[0]) < 3:
        return None
    g = shapely.Polygon(rings[0][:, :2], [r[:, :2] for r in rings[1:]])
    if not g.is_valid:                 # folds at occlusion edges: the area it covers
        g = shapely.make_valid(g)
        polys = [p for p in getattr(g, "geoms", [g]) if p.geom_type == "Polygon"] \
            if g.geom_type != "Polygon" else [g]
        g = shapely.MultiPolygon(polys) if len(polys) != 1 else polys[0]
    return g if not g.is_empty else None


def shapely_polygons(shapes: List[ForwardShape]) -> list:
    """:func:`shapely_polygon` of each shape, the single-ring ones built at once (shapely's
    vectorised constructors); the same geometries."""
    import shapely
    import numpy as np
    out: list = [None] * len(shapes)
    simple = []
    for i, f in enumerate(shapes):
        rings = f.rings
        if len(rings) == 1 and len(rings[0]) >= 3:
            simple.append(i)
        else:
            out[i] = shapely_polygon(f)
    if simple:
        xy = [shapes[i].rings[0][:, :2] for i in simple]
        n = np.array([len(r) for r in xy])
        closed = np.concatenate([np.vstack([r, r[:1]]) for r in xy])
        try:
            lr = shapely.linearrings(closed, indices=np.repeat(np.arange(len(xy)), n + 1))
        except (ValueError, shapely.errors.GEOSException):   # a degenerate ring: one by one
            for i in simple:
                out[i] = shapely_polygon(shapes[i])
            return out
        polys = shapely.polygons(lr)
        ok = shapely.is_valid(polys)
        for i, g, good in zip(simple, polys.tolist(), ok.tolist()):
            out[i] = g if good and not g.is_empty else shapely_polygon(shapes[i])
    return out
