"""Exact clipping of polygons (holes and multipart) to a convex region, and polygon areas.

The region is the intersection of K half-spaces F_k(p) >= 0 whose functions are *affine* along
the straight edges of the subject, in whatever space the subject lives (2-D pixels for the photo
frame, 3-D camera coordinates for the lens model's valid cone). An edge crossing is therefore
exact (linear interpolation of F), and the pieces are joined Weiler–Atherton style: after a
piece leaves the region, the boundary of the region is followed (in its positive direction)
to the next piece that enters it. Unlike Sutherland–Hodgman this never leaves zero-width
bridges along the boundary: a concave ROI cut by the frame into two pieces gives two polygons.

Rings are open (n, d) arrays. Exterior rings must be positively oriented (shoelace > 0 in the
2-D output space, i.e. the interior on the left of each edge) and holes negatively; the region
is given by its 2-D boundary polygon, positively oriented, whose edge k is the zero set of F_k.
"""
from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np

from ..geometry import points_in_rings

Polygons = List[List[np.ndarray]]      # [[exterior, hole, ...], ...], 2-D open rings
_EPS_T = 1e-12


def signed_area(ring: np.ndarray) -> float:
    """Shoelace area of an open 2-D ring, relative to its first vertex (precise far from 0)."""
    if len(ring) < 3:
        return 0.0
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polygons_area(polys: Polygons) -> float:
    """Area of polygons given as [exterior, holes...] (exteriors minus holes)."""
    return sum(abs(signed_area(p[0])) - sum(abs(signed_area(h)) for h in p[1:]) for p in polys)


def area_centroid(polys: Polygons) -> Tuple[float, np.ndarray]:
    """(area, centroid (2,)) of polygons [exterior, holes...]; centroid NaN for zero area."""
    total, moment = 0.0, np.zeros(2)
    for p in polys:
        for k, ring in enumerate(p):
            if len(ring) < 3:
                continue
            o = ring[0]
            x, y = ring[:, 0] - o[0], ring[:, 1] - o[1]
            xn, yn = np.roll(x, -1), np.roll(y, -1)
            cross = x * yn - xn * y
            a = 0.5 * float(cross.sum())
            c = np.array([float(((x + xn) * cross).sum()), float(((y + yn) * cross).sum())])
            sign = 1.0 if (a > 0) == (k == 0) else -1.0      # exteriors add, holes subtract
            if a == 0:
                continue
            total += sign * abs(a)
            moment += sign * abs(a) * (c / (6.0 * a) + o)
    if total <= 0:
        return 0.0, np.full(2, np.nan)
    return total, moment / total


def orient(polys: Polygons) -> Polygons:
    """Exteriors positive, holes negative (as :func:`clip_convex` expects)."""
    out = []
    for p in polys:
        rings = []
        for k, r in enumerate(p):
            positive = signed_area(r) > 0
            rings.append(r if positive == (k == 0) else r[::-1])
        out.append(rings)
    return out


class ConvexRegion:
    """A convex region: ``values(points) -> (n, K)`` half-space functions (>= 0 inside),
    ``to_plane(points) -> (n, 2)`` the output space, and its 2-D boundary polygon
    ``vertices`` (K, 2), positively oriented, edge k = V_k → V_{k+1} being F_k = 0."""

    def __init__(self, vertices: np.ndarray, values: Callable[[np.ndarray], np.ndarray],
                 to_plane: Callable[[np.ndarray], np.ndarray] = lambda p: p):
        self.vertices = np.asarray(vertices, np.float64)
        self.values = values
        self.to_plane = to_plane
        self.K = len(self.vertices)

    def perimeter(self, q: np.ndarray, edge: int) -> float:
        """Boundary parameter in [0, K) of a 2-D point ``q`` on edge ``edge``."""
        a, b = self.vertices[edge], self.vertices[(edge + 1) % self.K]
        d = b - a
        s = float(np.dot(q - a, d) / np.dot(d, d))
        return edge + min(max(s, 0.0), 1.0 - 1e-12)


def rectangle(width: float, height: float) -> ConvexRegion:
    """The photo frame [0, w] × [0, h] in pixel coordinates (x right, y down)."""
    w, h = float(width), float(height)

    def values(p):
        return np.column_stack([p[:, 1], w - p[:, 0], h - p[:, 1], p[:, 0]])
    return ConvexRegion(np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]]), values)


def _pieces(ring: np.ndarray, region: ConvexRegion):
    """Chains of ``ring`` inside ``region``: (points in the subject space, entry edge, exit edge)
    per chain; or "inside" / "outside" for a ring that never crosses the boundary."""
    n = len(ring)
    F = region.values(ring)                                  # (n, K)
    Fa, Fb = F, np.roll(F, -1, axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        tc = Fa / (Fa - Fb)                                  # crossing parameter per half-space
    lo = np.where((Fa < 0) & (Fb >= 0), tc, 0.0)
    hi = np.where((Fa >= 0) & (Fb < 0), tc, 1.0)
    never = (Fa < 0) & (Fb < 0)
    lo = np.where(never, 2.0, lo)
    hi = np.where(never, -1.0, hi)
    t0, k0 = lo.max(axis=1), lo.argmax(axis=1)
    t1, k1 = hi.min(axis=1), hi.argmin(axis=1)
    ins = t1 - t0 > _EPS_T
    if not ins.any():
        return "outside"
    full = ins & (t0 == 0.0) & (t1 == 1.0)
    if full.all():
        return "inside"
    b = np.roll(ring, -1, axis=0)
    # a segment continues the chain of the previous one when both meet at the shared vertex
    cont = ins & (t0 == 0.0) & np.roll(ins & (t1 == 1.0), 1)
    starts = np.flatnonzero(ins & ~cont)
    chains = []
    for s in starts:
        pts = [ring[s] + t0[s] * (b[s] - ring[s])]
        entry = int(k0[s]) if t0[s] > 0 else _on_edge(F[s])
        i = s
        while True:
            if t1[i] < 1.0:
                pts.append(ring[i] + t1[i] * (b[i] - ring[i]))
                exit_ = int(k1[i])
                break
            j = (i + 1) % n
            pts.append(b[i])
            if not cont[j]:                                 # ends on a boundary vertex
                exit_ = _on_edge(F[j])
                break
            i = j
        chains.append((np.array(pts), entry, exit_))
    return chains


def _on_edge(f: np.ndarray) -> int:
    return int(np.argmin(np.abs(f)))


def clip_convex(polys: Sequence[Sequence[np.ndarray]], region: ConvexRegion,
                probe_inside: Optional[Callable[[np.ndarray], bool]] = None) -> Polygons:
    """``polys`` ([exterior, holes...] in the subject space, oriented as the module says) ∩
    ``region``, as 2-D polygons in the region's output space (exteriors positive).

    ``probe_inside(point)``: whether a 2-D point of the region lies inside ``polys``; asked only
    when no ring crosses the region's boundary (then one point decides for the whole region).
    Default: the even-odd test on the rings mapped by ``region.to_plane``.
    """
    chains, inner_ext, inner_holes, rings_2d = [], [], [], []
    for p in polys:
        for k, ring in enumerate(p):
            if len(ring) < 3:
                continue
            ring = np.asarray(ring, np.float64)
            res = _pieces(ring, region)
            if res == "inside":
                q = region.to_plane(ring)
                (inner_ext if k == 0 else inner_holes).append(q)
                rings_2d.append(q)
            elif res == "outside":
                rings_2d.append(None)
            else:
                rings_2d.append(None)
                for pts, e_in, e_out in res:
                    q = region.to_plane(pts)
                    if len(q) >= 2:
                        chains.append((q, region.perimeter(q[0], e_in),
                                       region.perimeter(q[-1], e_out)))
    exteriors: List[np.ndarray] = _walk(chains, region) if chains else []
    if not chains and rings_2d:
        v = region.vertices
        probe = v[0] + 1e-7 * (v[2 % region.K] - v[0])   # just inside a corner
        if probe_inside is None:
            rings = [region.to_plane(np.asarray(r, np.float64)) for p in polys for r in p
                     if len(r) >= 3]
            inside = bool(points_in_rings(probe[:1], probe[1:], rings)[0])
        else:
            inside = bool(probe_inside(probe))
        if inside:
            exteriors.append(v.copy())
    result = [[e] for e in exteriors + inner_ext if abs(signed_area(e)) > 0]
    for h in inner_holes:
        owner = _smallest_container(h, [p[0] for p in result])
        if owner is not None:
            result[owner].append(h)
    return result


def _smallest_container(ring: np.ndarray, exteriors: List[np.ndarray]) -> Optional[int]:
    best, best_a = None, np.inf
    x, y = ring[:1, 0], ring[:1, 1]
    for i, e in enumerate(exteriors):
        if points_in_rings(x, y, [e])[0]:
            a = abs(signed_area(e))
            if a < best_a:
                best, best_a = i, a
    return best


def _walk(chains, region: ConvexRegion) -> List[np.ndarray]:
    """Join chains (2-D points, entry parameter, exit parameter) into rings: from a chain's exit,
    follow the boundary in its positive direction to the nearest entry, passing its vertices."""
    K = region.K
    entries = np.array([c[1] for c in chains])
    used = np.zeros(len(chains), bool)
    rings = []
    for first in range(len(chains)):
        if used[first]:
            continue
        parts, cur = [], first
        while True:
            used[cur] = True
            q, _, s_out = chains[cur]
            parts.append(q)
            travel_all = (entries - s_out) % K
            nxt = int(np.argmin(travel_all))
            travel = float(travel_all[nxt])
            m0 = int(np.floor(s_out))
            steps = int(np.floor(s_out + travel)) - m0
            if steps > 0:
                parts.append(region.vertices[[(m0 + j) % K for j in range(1, steps + 1)]])
            if used[nxt]:
                break
            cur = nxt
        ring = np.concatenate(parts)
        keep = np.ones(len(ring), bool)
        keep[1:] = np.any(np.abs(np.diff(ring, axis=0)) > 1e-12, axis=1)
        ring = ring[keep]
        while len(ring) > 1 and np.all(np.abs(ring[0] - ring[-1]) <= 1e-12):
            ring = ring[:-1]
        if len(ring) >= 3:
            rings.append(ring)
    return rings
