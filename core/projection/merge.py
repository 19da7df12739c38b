"""Multi-view merge: the same object found in several photos becomes one map polygon.

Forward-projected polygons with the same label whose map footprints overlap (by more than
``min_overlap`` of the smaller one) are one object; ``views`` counts its photos. Modes:
``none`` (every polygon kept, views 1), ``union`` (the union of the views; a vertex's height
is that of the nearest input vertex) and ``best`` (the polygon of the best view: complete
first, then the highest score, then the most nadir view, then the largest in pixels);
``fuse`` (:mod:`.fuse`: NMS within each photo, groups by IoU and distance, a majority
consensus outline, scores, DSM height and a confidence from the views that could see it).
Geometry work is done by shapely on the map x, y.
"""
from typing import List

import numpy as np

from ..errors import EasyIDPError
from .forward import ForwardShape
from .fuse import fuse_views
from .map_polygon import MapPolygon, shapely_polygon

MERGE_MODES = ("none", "union", "best", "fuse")


def _single(f: ForwardShape, views: int = 1, photos=None) -> MapPolygon:
    return MapPolygon(f.label, [[r for r in f.rings if len(r)]], photos or [f.photo], views,
                      f.complete, f.area_m2, f.perimeter_m, f.score, [f])


def merge_views(shapes: List[ForwardShape], mode: str = "union",
                min_overlap: float = 0.1, *, recon=None, dsm=None,
                **fuse_options) -> List[MapPolygon]:
    """Merge forward-projected polygons of several photos (see the module docstring).
    ``fuse`` needs the project ``recon`` and the ``dsm`` (GeoTIFF path) the shapes were
    projected on; ``fuse_options`` go to :func:`.fuse.fuse_views`."""
    if mode not in MERGE_MODES:
        raise EasyIDPError(f"merge mode must be one of {MERGE_MODES}, not {mode!r}")
    if mode == "fuse":
        if recon is None or dsm is None:
            raise EasyIDPError("merge mode 'fuse' needs the project and the DSM (recon=, dsm=).")
        return fuse_views(shapes, recon, dsm, **fuse_options)
    polys = [f for f in shapes if f.kind == "polygon"]
    if mode == "none":
        return [_single(f) for f in polys]
    import shapely
    geoms = [shapely_polygon(f) for f in polys]
    keep = [i for i, g in enumerate(geoms) if g is not None]
    parent = list(range(len(polys)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    if keep:
        tree = shapely.STRtree([geoms[i] for i in keep])
        a, b = tree.query([geoms[i] for i in keep], predicate="intersects")
        for x, y in zip(a.tolist(), b.tolist()):
            i, j = keep[x], keep[y]
            if i >= j or polys[i].label != polys[j].label:
                continue
            inter = geoms[i].intersection(geoms[j]).area
            if inter > min_overlap * min(geoms[i].area, geoms[j].area):
                parent[root(i)] = root(j)
    groups = {}
    for i in range(len(polys)):
        groups.setdefault(root(i), []).append(i)
    out = []
    for members in groups.values():
        fs = [polys[i] for i in members]
        photos = list(dict.fromkeys(f.photo for f in fs))
        if len(fs) == 1 or any(geoms[i] is None for i in members):
            out.extend(_single(f, 1) for f in fs) if len(fs) > 1 else out.append(_single(fs[0]))
            continue
        if mode == "best":
            best = min(fs, key=lambda f: (not f.complete, -(f.score if f.score is not None else -np.inf),
                                          f.view_angle if np.isfinite(f.view_angle) else 90.0,
                                          -(f.pixel_area if np.isfinite(f.pixel_area) else 0)))
            m = _single(best, len(photos), [best.photo] + [p for p in photos if p != best.photo])
            m.members = fs
            out.append(m)
            continue
        union = shapely.unary_union([geoms[i] for i in members])
        verts = np.vstack([r for f in fs for r in f.rings if len(r)])
        from scipy.spatial import cKDTree
        nearest = cKDTree(verts[:, :2])        # memory: linear, not the (ring, vertices) table
        parts = []
        for p in getattr(union, "geoms", [union]):
            if p.geom_type != "Polygon" or p.is_empty:
                continue
            rings = []
            for ring in [p.exterior, *p.interiors]:
                xy = np.asarray(ring.coords)[:-1]
                near = nearest.query(xy)[1]
                rings.append(np.column_stack([xy, verts[near, 2]]))
            parts.append(rings)
        # planimetric metres from map units, by the members' own ratio
        a_scale = np.nanmean([f.area_m2 / geoms[i].area for f, i in zip(fs, members)
                              if geoms[i].area > 0])
        p_scale = np.nanmean([f.perimeter_m / geoms[i].length for f, i in zip(fs, members)
                              if geoms[i].length > 0])
        scores = [f.score for f in fs if f.score is not None]
        out.append(MapPolygon(fs[0].label, parts, photos, len(photos),
                              all(f.complete for f in fs), float(union.area * a_scale),
                              float(union.length * p_scale), max(scores) if scores else None, fs))
    return out
