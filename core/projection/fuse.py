"""Fusion of detections across views: one map object per real object (merge mode ``fuse``).

Input: forward-projected polygons (:func:`.forward.forward_project`) of detections, with
scores, from several photos. Steps:

1. **NMS within a photo**: per photo and label, by decreasing score, a polygon whose map IoU
   with a kept one exceeds ``nms_iou`` is suppressed (tiles of one photo count as one photo).
2. **Grouping**: polygons of one label from *different* photos are linked when their map IoU
   is at least ``group_iou`` and their centroids are at most ``max_distance`` apart (default:
   half the median equivalent diameter, sqrt(area)); a group is a connected component.
3. **One object per group**: the *consensus* outline is the region covered by more than half of
   the group's photos (a vote on a grid of ``VOTE_CELLS`` cells across the group, contoured
   between cells; the outermost ring of the largest piece), not their union, so a misplaced
   view neither grows nor moves it. ``position`` is the outline's centroid, its height the DSM
   there (bilinear); ``views`` the number of photos in the group; ``mean_score``/``max_score``.
4. **Confidence**: the outline is back-projected (:func:`.backward.back_project`, DSM heights,
   occlusion tested, ``min_visible``) into the photos that were searched; ``expected_views`` is
   the number of those that could have seen it. ``confidence = mean score (1 when there are no
   scores) × views / max(expected_views, views)``: an object found in 1 of 9 photos that could
   see it gets 1/9 of its score.

Map coordinates: those of the shapes (the DSM's CRS unless forward projection was given
another); areas in m² by the members' own planimetric ratio, as :mod:`.merge` does.
"""
from dataclasses import dataclass
from typing import List, Optional, Sequence

import numpy as np

from ..errors import EasyIDPError
from ..geometry import rasterize
from ..progress import as_progress
from ..raster import as_dsm
from ..roi import ROI, ROISet
from .backward import back_project
from .forward import ForwardShape
from .map_polygon import MapPolygon, shapely_polygon

VOTE_CELLS = 48          # vote grid cells across a group's extent (longer side)


@dataclass
class FusedObject(MapPolygon):
    """A :class:`MapPolygon` with the fusion's figures: ``position`` (x, y, z) map units and DSM
    height; ``expected_views`` photos searched that could see it; ``mean_score``,
    ``max_score`` (None without scores); ``confidence`` in [0, 1]."""
    position: tuple = (float("nan"),) * 3
    expected_views: int = 0
    mean_score: Optional[float] = None
    max_score: Optional[float] = None
    confidence: float = 0.0


def _nms(idx: List[int], geoms, scores, iou: float) -> List[int]:
    import shapely
    order = sorted(idx, key=lambda i: -scores[i])
    kept: List[int] = []
    if not order:
        return kept
    tree = shapely.STRtree([geoms[i] for i in order])
    suppressed = np.zeros(len(order), bool)
    for k, i in enumerate(order):
        if suppressed[k]:
            continue
        kept.append(i)
        cand = tree.query(geoms[i], predicate="intersects")
        cand = cand[(cand > k) & ~suppressed[cand]]
        if len(cand):
            others = [geoms[order[c]] for c in cand]
            inter = shapely.area(shapely.intersection(geoms[i], others))
            union = geoms[i].area + shapely.area(others) - inter
            suppressed[cand[inter > iou * union]] = True
    return kept


def _consensus(members, n_photos: int):
    """(exterior ring (k, 2) map units, shapely polygon) covered by more than half the photos."""
    import shapely
    from skimage.measure import find_contours
    x0, y0, x1, y1 = shapely.total_bounds(members)
    cell = max(x1 - x0, y1 - y0) / VOTE_CELLS
    if not cell > 0:
        return None, None
    cols, rows = int(np.ceil((x1 - x0) / cell)) + 2, int(np.ceil((y1 - y0) / cell)) + 2
    ox, oy = x0 - cell, y1 + cell            # grid corner: x right, rows down (north up)
    votes = np.zeros((rows, cols), np.int32)
    for g in members:
        rings = []
        for p in getattr(g, "geoms", [g]):
            for ring in [p.exterior, *p.interiors]:
                xy = np.asarray(ring.coords)[:-1]
                rings.append(np.column_stack([(xy[:, 0] - ox) / cell, (oy - xy[:, 1]) / cell]))
        votes += rasterize(rings, (rows, cols))
    # photos, not polygons: a photo with two overlapping pieces votes once
    votes = np.minimum(votes, n_photos)
    level = n_photos / 2.0
    if not (votes > level).any():
        return None, None
    contours = find_contours(votes.astype(np.float64), level)
    polys = []
    for c in contours:
        if len(c) < 4:
            continue
        xy = np.column_stack([ox + (c[:, 1] + 0.5) * cell, oy - (c[:, 0] + 0.5) * cell])
        p = shapely.Polygon(xy)
        if not p.is_valid:
            p = shapely.make_valid(p)
        polys += _flat_polygons(p)
    if not polys:
        return None, None
    best = max(polys, key=lambda p: p.area).simplify(0.25 * cell)
    if best.geom_type != "Polygon" or best.is_empty:
        return None, None
    ring = np.asarray(best.exterior.coords)[:-1]
    return ring, shapely.Polygon(ring)


def fuse_views(shapes: List[ForwardShape], recon, dsm, *, photos: Optional[Sequence[str]] = None,
               nms_iou: float = 0.5, group_iou: float = 0.3, max_distance: Optional[float] = None,
               min_visible: float = 0.5, occlusion: bool = True, dsm_crs=None,
               progress=None) -> List[FusedObject]:
    """Fuse forward-projected detections (see the module docstring). ``dsm``: the DSM the
    shapes were projected on (a :class:`~core.raster.DSM`, a GeoTIFF path or an opened
    ``GeoTiff``; heights and the expected-views test; its CRS must be that of the shapes,
    ``dsm_crs`` overriding its GeoKeys); ``photos``: labels of every photo
    searched, also those without a detection (default: the photos of ``shapes``)."""
    import shapely
    for name, v in (("nms_iou", nms_iou), ("group_iou", group_iou)):
        if not 0.0 < v <= 1.0:
            raise EasyIDPError(f"{name} must be in (0, 1], not {v}.")
    prog = as_progress(progress)
    dsm = as_dsm(dsm, dsm_crs)
    polys = [f for f in shapes if f.kind == "polygon"]
    geoms = [shapely_polygon(f) for f in polys]
    ok = [i for i, g in enumerate(geoms) if g is not None and g.area > 0]
    scores = [f.score if f.score is not None else 1.0 for f in polys]
    by = {}
    for i in ok:
        by.setdefault((polys[i].photo, polys[i].label), []).append(i)
    kept = sorted(i for idx in by.values() for i in _nms(idx, geoms, scores, nms_iou))
    prog.set(15)
    if not kept:
        return []
    kg = [geoms[i] for i in kept]
    areas = shapely.area(kg)
    cent = shapely.get_coordinates(shapely.centroid(kg))
    gate = float(max_distance) if max_distance else 0.5 * float(np.median(np.sqrt(areas)))
    tree = shapely.STRtree(kg)
    a, b = tree.query(kg, predicate="intersects")
    sel = a < b
    a, b = a[sel], b[sel]
    same = np.array([polys[kept[x]].label == polys[kept[y]].label and
                     polys[kept[x]].photo != polys[kept[y]].photo for x, y in zip(a, b)], bool)
    a, b = a[same] if len(a) else a, b[same] if len(b) else b
    if len(a):
        inter = shapely.area(shapely.intersection(np.array(kg, object)[a], np.array(kg, object)[b]))
        iou = inter / (areas[a] + areas[b] - inter)
        near = np.hypot(*(cent[a] - cent[b]).T) <= gate
        link = (iou >= group_iou) & near
        a, b = a[link], b[link]
    comp = _components(len(kept), a, b)
    prog.set(30)
    groups = {}
    for k, c in enumerate(comp.tolist()):
        groups.setdefault(c, []).append(k)
    out: List[FusedObject] = []
    rings = []
    for members in groups.values():
        fs = [polys[kept[k]] for k in members]
        photos_g = list(dict.fromkeys(f.photo for f in fs))
        ring, outline = _consensus([kg[k] for k in members], len(photos_g))
        if ring is None:                      # no majority region: the best-scored view
            best = max(members, key=lambda k: scores[kept[k]])
            outline = max(_flat_polygons(kg[best]), key=lambda p: p.area)
            ring = np.asarray(outline.exterior.coords)[:-1]
        a_scale = _mean([f.area_m2 / kg[k].area for f, k in zip(fs, members)])
        p_scale = _mean([f.perimeter_m / kg[k].length for f, k in zip(fs, members)])
        sc = [f.score for f in fs if f.score is not None]
        c = outline.centroid
        out.append(FusedObject(
            fs[0].label, [[ring]], photos_g, len(photos_g), all(f.complete for f in fs),
            float(outline.area * a_scale), float(outline.length * p_scale),
            float(np.mean(sc)) if sc else None, fs, position=(c.x, c.y, float("nan")),
            mean_score=float(np.mean(sc)) if sc else None,
            max_score=float(np.max(sc)) if sc else None))
        rings.append(ring)
    prog.set(60)
    # heights from the DSM: outline vertices and the position
    allxy = np.vstack(rings + [np.array([o.position[:2] for o in out])])
    z = dsm.heights(allxy[:, 0], allxy[:, 1])
    k = 0
    for o, r in zip(out, rings):
        o.parts = [[np.column_stack([r, z[k:k + len(r)]])]]
        k += len(r)
    for o, zz in zip(out, z[k:]):
        o.position = (float(o.position[0]), float(o.position[1]), float(zz))
    # expected views: the photos searched that could have seen each object
    searched = list(dict.fromkeys(photos if photos is not None else [f.photo for f in polys]))
    rois = ROISet([ROI(str(j), [[r]]) for j, r in enumerate(rings)], crs=dsm.crs)
    bp = back_project(rois, recon, heights=dsm, cameras=searched,
                      occlusion_dsm=dsm if occlusion else None, min_visible=min_visible,
                      progress=prog.sub(60, 100))
    expected = bp.photos_per_roi()
    for o, e in zip(out, expected.tolist()):
        o.expected_views = int(e)
        o.confidence = float((o.mean_score if o.mean_score is not None else 1.0)
                             * o.views / max(e, o.views))
    prog.set(100)
    return out


def _mean(values) -> float:
    """Mean of the finite values; NaN when there is none."""
    v = np.asarray(values, np.float64)
    v = v[np.isfinite(v)]
    return float(v.mean()) if len(v) else float("nan")


def _flat_polygons(g) -> list:
    """The polygons inside any shapely geometry (collections and multi-parts flattened)."""
    import shapely
    return [p for p in shapely.get_parts(shapely.get_parts(g)) if p.geom_type == "Polygon"
            and not p.is_empty]


def _components(n: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected-component label of each of ``n`` nodes linked by edges (a, b)."""
    parent = np.arange(n)

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    for x, y in zip(a.tolist(), b.tolist()):
        rx, ry = root(x), root(y)
        if rx != ry:
            parent[rx] = ry
    return np.array([root(i) for i in range(n)], np.int64)


__all__ = ["fuse_views", "FusedObject"]
