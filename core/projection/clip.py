"""Exact clipping of polygons (holes and multipart) to a convex region.

The region is the intersection of K half-spaces F_k(p) >= 0 whose functions are *affine* along
the straight edges of the subject, in whatever space the subject lives (2-D pixels for the photo
frame, 3-D camera coordinates for the lens model's valid cone). An edge crossing is therefore
exact (linear interpolation of F), and the pieces are joined Weiler–Atherton style: after a
piece leaves the region, the boundary of the region is followed (in its positive direction)
to the next piece that enters it. Unlike Sutherland–Hodgman this never leaves zero-width
bridges along the boundary: a concave ROI cut by the frame into two pieces gives two polygons.

Polygons are those of :mod:`core.geometry` (lists of open rings, exterior first), the rings
(n, d) arrays in the subject space, oriented (:func:`core.geometry.orient`: exteriors positive,
shoelace > 0 in the 2-D output space, i.e. the interior on the left of each edge; holes
negative); the region is given by its 2-D boundary polygon, positively oriented, whose edge k
is the zero set of F_k.
"""
from typing import Callable, List, Optional, Sequence

import numpy as np

from ..geometry import Polygons, points_in_rings, ring_area
from ..ragged import cyclic_next, run_of
from ..ragged import offsets as ragged_offsets

_EPS_T = 1e-12


def _following(a: np.ndarray) -> np.ndarray:
    """The next element of a closed sequence (a[1], ..., a[n-1], a[0]); faster than np.roll."""
    return np.concatenate((a[1:], a[:1]))


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
    Fa, Fb = F, _following(F)
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
    b = _following(ring)
    # a segment continues the chain of the previous one when both meet at the shared vertex
    end = ins & (t1 == 1.0)
    cont = ins & (t0 == 0.0) & np.concatenate((end[-1:], end[:-1]))
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
    chains, inner_ext, inner_holes, rings_2d, around = [], [], [], [], []
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
                around.append(ring)
            else:
                rings_2d.append(None)
                for pts, e_in, e_out in res:
                    q = region.to_plane(pts)
                    if len(q) >= 2:
                        chains.append((q, region.perimeter(q[0], e_in),
                                       region.perimeter(q[-1], e_out)))
    if chains and not _alternate(chains):
        return _clip_each_ring(polys, region)
    exteriors: List[np.ndarray] = _walk(chains, region) if chains else []
    if not chains and rings_2d:
        v = region.vertices
        probe = v[0] + 1e-7 * (v[2 % region.K] - v[0])   # just inside a corner
        # whether the region lies inside the rings that stay outside it: the rings wholly
        # inside it are parts of the result already, and one with a vertex on the probed
        # corner would otherwise add the whole region
        if probe_inside is None:
            rings = [region.to_plane(r) for r in around]
            inside = bool(points_in_rings(probe[:1], probe[1:], rings)[0]) if rings else False
        else:                                   # even-odd: the inner rings' parity taken out
            inner = inner_ext + inner_holes
            inside = bool(probe_inside(probe)) != (
                bool(points_in_rings(probe[:1], probe[1:], inner)[0]) if inner else False)
        if inside:
            exteriors.append(v.copy())
    result = [[e] for e in exteriors + inner_ext if abs(ring_area(e)) > 0]
    for h in inner_holes:
        owner = _smallest_container(h, [p[0] for p in result])
        if owner is not None:
            result[owner].append(h)
    return result


def _alternate(chains) -> bool:
    """Whether the chains' exits and entries alternate along the region's boundary, as they do
    for any polygon whose rings cross neither themselves nor each other (after an exit the
    boundary runs inside the polygon up to the next entry). A ring that folds on the boundary
    (a DSM-height ROI seen obliquely can fold by a fraction of a pixel) breaks it, and the walk
    would then go round the whole region."""
    s = np.array([c[2] for c in chains] + [c[1] for c in chains])
    kind = np.repeat([0, 1], len(chains))             # exits first where they meet an entry
    order = np.lexsort((kind, s))
    return bool(np.all(np.diff(kind[order]) != 0))


def _clip_each_ring(polys, region: ConvexRegion) -> Polygons:
    """Each ring clipped by the region's half-spaces one after the other (Sutherland–Hodgman),
    the polygons' structure kept: the fallback for rings that cross themselves or each other.
    The area is then that of the winding number, and a concave piece that leaves the region and
    comes back is joined to the rest along the boundary by a zero-width bridge."""
    out = []
    for p in polys:
        rings = [region.to_plane(r) for r in (_half_spaces(np.asarray(r, np.float64), region)
                                               for r in p if len(r) >= 3) if len(r) >= 3]
        if rings and abs(ring_area(rings[0])) > 0:
            out.append(rings)
    return out


def _half_spaces(ring: np.ndarray, region: ConvexRegion) -> np.ndarray:
    """``ring`` (subject space) clipped by each half-space F_k >= 0 in turn."""
    for k in range(region.K):
        if len(ring) < 3:
            return ring[:0]
        F = region.values(ring)[:, k]
        Fn, nxt = _following(F), _following(ring)
        ins = F >= 0
        cross = np.flatnonzero(ins != (Fn >= 0))
        emit = ins.astype(np.int64)
        emit[cross] += 1
        slot = np.cumsum(emit) - emit
        new = np.empty((int(emit.sum()), ring.shape[1]))
        new[slot[ins]] = ring[ins]
        t = F[cross] / (F[cross] - Fn[cross])
        new[slot[cross] + ins[cross]] = ring[cross] + t[:, None] * (nxt[cross] - ring[cross])
        ring = new
    return ring


def _smallest_container(ring: np.ndarray, exteriors: List[np.ndarray]) -> Optional[int]:
    """The smallest exterior that holds ``ring``: most of the points a third of the way along
    its edges are inside it (a vertex may lie on the exterior, e.g. at the region's corner)."""
    best, best_a = None, np.inf
    q = ring + (_following(ring) - ring) / 3.0
    x, y = q[:, 0], q[:, 1]
    for i, e in enumerate(exteriors):
        if points_in_rings(x, y, [e]).mean() > 0.5:
            a = abs(ring_area(e))
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


def clip_convex_rings_to_frames(xy: np.ndarray, offsets: np.ndarray, width: np.ndarray,
                                height: np.ndarray):
    """Many *convex* rings, each clipped to its own frame [0, w] × [0, h], vectorised.

    ``xy`` (V, 2) all vertices, ring i = ``xy[offsets[i]:offsets[i + 1]]``; ``width``/``height``
    (R,). For a convex ring, clipping by the frame's four half-planes one after the other
    (Sutherland–Hodgman) is exact. Returns (xy, offsets) of the clipped rings, consecutive
    duplicate vertices removed; a ring wholly outside comes back with fewer than 3 vertices.
    """
    xy = np.asarray(xy, np.float64)
    offsets = np.asarray(offsets, np.int64)
    for axis, side in ((1, 0), (0, 1), (1, 1), (0, 0)):       # edges in the frame's order
        n = np.diff(offsets)
        ring = run_of(offsets)
        if side:
            limit = (width if axis == 0 else height)[ring]
            F = limit - xy[:, axis]
        else:
            F = xy[:, axis]
        nxt = cyclic_next(offsets)
        ins = F >= 0
        cross = ins != ins[nxt]
        emit = ins.astype(np.int64) + cross
        slot = np.cumsum(emit) - emit
        out = np.empty((int(emit.sum()), 2))
        out[slot[ins]] = xy[ins]
        c = np.flatnonzero(cross)
        Fa, Fb = F[c], F[nxt[c]]
        t = Fa / (Fa - Fb)
        p = xy[c] + t[:, None] * (xy[nxt[c]] - xy[c])
        p[:, axis] = (width if axis == 0 else height)[ring[c]] if side else 0.0  # exactly on it
        out[slot[c] + ins[c]] = p
        offsets = ragged_offsets(np.bincount(ring, emit, minlength=len(n)).astype(np.int64))
        xy = out
    # drop consecutive duplicates (corners met exactly)
    ring = run_of(offsets)
    keep = np.any(xy != xy[cyclic_next(offsets)], axis=1) if len(xy) else np.zeros(0, bool)
    counts = np.bincount(ring[keep], minlength=len(offsets) - 1).astype(np.int64)
    return xy[keep], ragged_offsets(counts)


def convex_rings(xy: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(R,) bool: each ring's turns all go the same way (a convex, simple ring)."""
    n = np.diff(offsets)
    if not len(xy):
        return np.zeros(len(n), bool)
    nxt = cyclic_next(offsets)
    e = xy[nxt] - xy
    turn = e[:, 0] * e[nxt, 1] - e[:, 1] * e[nxt, 0]
    starts = offsets[:-1]
    lo = np.minimum.reduceat(turn, starts)
    hi = np.maximum.reduceat(turn, starts)
    total = np.add.reduceat(np.arctan2(turn, np.einsum("ij,ij->i", e, e[nxt])), starts)
    # one full turn (not a star that winds twice) and no turn against the others
    return (n >= 3) & ((lo >= 0) | (hi <= 0)) & (np.abs(np.abs(total) - 2 * np.pi) < 1e-6)
