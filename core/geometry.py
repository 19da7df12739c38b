"""Planar polygons on numpy arrays: rings, area, centroid, orientation, densification,
point-in-polygon, rasterisation, distances, validity.

The one vocabulary of polygons in the core:

* A **ring** is an (n, 2) float64 array of (x, y), open (the first vertex is not repeated).
* A **polygon** is a list of rings, exterior first, then its holes; **polygons** (a
  multipolygon, :attr:`ROI.parts`, what clipping takes and gives) a list of polygons
  (:data:`Polygons`). Oriented polygons (:func:`orient`) have exteriors positive (shoelace > 0:
  counter-clockwise in a y-up frame, the interior on the left of each edge) and holes negative.
* A **ring list** (:data:`Rings`) is the rings of polygons concatenated (:func:`ring_list`);
  inside-ness over it uses the even-odd rule, which honours holes and multipart polygons at once.
* **Flat polygons** (:class:`FlatPolygons`) hold the polygons of many records in ragged arrays
  (:mod:`core.ragged`) for vectorised work; :meth:`FlatPolygons.from_lists` and
  :meth:`FlatPolygons.polygons` convert to and from polygons.

Rasterisation works in *pixel coordinates*: x = column, y = row, origin at the top-left corner of
the top-left pixel, so the centre of pixel (row r, col c) is (c + 0.5, r + 0.5).
"""
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

from .ragged import cyclic_next, offsets, position_in_run, ranges, run_of

Ring = np.ndarray
"""(n, 2) float64, open."""
Polygons = List[List[np.ndarray]]
"""[[exterior, hole, ...], ...]: polygons, each a list of rings."""
Rings = Sequence[np.ndarray]
"""A ring list: the rings of polygons concatenated (roles by the even-odd rule)."""


def ring_list(polys: Polygons) -> List[np.ndarray]:
    """The ring list of polygons: every ring, exteriors and holes, in order."""
    return [r for p in polys for r in p]


def ring_keep(ring: np.ndarray) -> np.ndarray:
    """Indices of the vertices :func:`close_ring` keeps: consecutive duplicates and a repeated
    closing vertex are dropped."""
    ring = np.asarray(ring, dtype=np.float64)[:, :2]
    keep = np.ones(len(ring), bool)
    if len(ring) > 1:
        keep[1:] = np.any(ring[1:] != ring[:-1], axis=1)
    idx = np.flatnonzero(keep)
    if len(idx) > 1 and np.all(ring[idx[0]] == ring[idx[-1]]):
        idx = idx[:-1]
    return idx


def close_ring(ring: np.ndarray, keep: np.ndarray = None) -> np.ndarray:
    """Drop a repeated closing vertex and consecutive duplicates; returns an open (n, 2) ring.
    ``keep``: the indices from :func:`ring_keep`, when already computed."""
    ring = np.asarray(ring, dtype=np.float64)[:, :2]
    return ring[ring_keep(ring) if keep is None else keep]


def _edges(rings: Rings) -> Tuple[np.ndarray, np.ndarray]:
    """All edges of all rings as start points (E, 2) and end points (E, 2)."""
    if len(rings) == 1:
        r = np.asarray(rings[0])
        return r, np.concatenate([r[1:], r[:1]])
    starts = np.concatenate([r for r in rings])
    ends = np.concatenate([np.concatenate([r[1:], r[:1]]) for r in rings])
    return starts, ends


def ring_area(ring: np.ndarray) -> float:
    """Signed area (shoelace) of one ring; positive for counter-clockwise rings in a y-up frame,
    0 for fewer than 3 vertices. Relative to the first vertex, so UTM-size coordinates keep
    their precision. Many rings at once: :func:`ring_moments`."""
    if len(ring) < 3:
        return 0.0
    x, y = ring[1:, 0] - ring[0, 0], ring[1:, 1] - ring[0, 1]
    return 0.5 * float(np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1]))


def ring_moments(xy: np.ndarray, offs: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(signed area (R,), first moment (R, 2) about the origin) of every ring of the ragged
    vertices ``xy`` (V, 2), ring i = ``xy[offs[i]:offs[i + 1]]`` (empty rings: 0); the centroid
    of ring i is ``moment[i] / area[i]``. Computed relative to each ring's first vertex, as
    :func:`ring_area`."""
    R = len(offs) - 1
    area, moment = np.zeros(R), np.zeros((R, 2))
    full = np.diff(offs) > 0
    if not full.any():
        return area, moment
    if not full.all():                           # empty rings: area and moment 0
        sub = np.flatnonzero(full)
        area[sub], moment[sub] = ring_moments(xy, np.r_[offs[sub], offs[-1]])
        return area, moment
    starts = offs[:-1]
    o = xy[starts][run_of(offs)]
    a = xy - o
    b = xy[cyclic_next(offs)] - o
    cross = a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]
    area = 0.5 * np.add.reduceat(cross, starts)
    mx = np.add.reduceat((a[:, 0] + b[:, 0]) * cross, starts) / 6.0 + area * xy[starts, 0]
    my = np.add.reduceat((a[:, 1] + b[:, 1]) * cross, starts) / 6.0 + area * xy[starts, 1]
    return area, np.column_stack([mx, my])


def polygons_area(polys: Polygons) -> float:
    """Area of polygons (exteriors minus holes), whatever their orientation."""
    return sum(abs(ring_area(p[0])) - sum(abs(ring_area(h)) for h in p[1:]) for p in polys)


def area_centroid(polys: Polygons) -> Tuple[float, np.ndarray]:
    """(area, centroid (2,)) of polygons (exteriors minus holes); centroid NaN for zero area."""
    a, c = FlatPolygons.from_lists([polys]).areas_centroids()
    return (float(a[0]), c[0]) if a[0] > 0 else (0.0, np.full(2, np.nan))


def orient(polys: Polygons) -> Polygons:
    """The polygons with exteriors positive and holes negative (rings reversed as needed)."""
    out = []
    for p in polys:
        rings = []
        for k, r in enumerate(p):
            positive = ring_area(r) > 0
            rings.append(r if positive == (k == 0) else r[::-1])
        out.append(rings)
    return out


def split_edges(offs: np.ndarray, pieces: np.ndarray):
    """Densification of ragged rings by index: edge v (vertex v to the next of its ring) cut
    into ``pieces[v]`` (≥ 1) equal pieces. Returns (src, dst, t, new offsets): new vertex m is
    ``p[src[m]] + t[m] · (p[dst[m]] − p[src[m]])`` for any per-vertex quantity p (t = 0 for the
    original vertices)."""
    pieces = np.asarray(pieces, np.int64)
    src = np.repeat(np.arange(len(pieces)), pieces)
    t = position_in_run(pieces) / np.repeat(pieces, pieces)
    lens = np.bincount(run_of(offs)[src], minlength=len(offs) - 1)
    return src, cyclic_next(offs)[src], t, offsets(lens)


def densify(xy: np.ndarray, offs: np.ndarray, step: Union[float, np.ndarray],
            closed: bool = True, max_pieces: Optional[int] = None):
    """Ragged rings (``closed``; else open lines) with vertices inserted so that no edge is
    longer than ``step`` (a number, or one per ring (R,); inf leaves a ring as it is), each
    edge cut in at most ``max_pieces``. Returns (xy (M, 2), offsets, original (M,) bool)."""
    xy = np.asarray(xy, np.float64)
    offs = np.asarray(offs, np.int64)
    seg = np.linalg.norm(xy[cyclic_next(offs)] - xy, axis=1)
    st = np.repeat(step, np.diff(offs)) if np.ndim(step) else step
    with np.errstate(invalid="ignore", divide="ignore"):
        n = np.ceil(np.where(np.isfinite(st), seg / st, 1.0))
    n = np.clip(n, 1, max_pieces if max_pieces is not None else None).astype(np.int64)
    if not closed:
        n[offs[1:][np.diff(offs) > 0] - 1] = 1
    src, dst, t, new_offs = split_edges(offs, n)
    return xy[src] + t[:, None] * (xy[dst] - xy[src]), new_offs, t == 0


@dataclass
class FlatPolygons:
    """The polygons of many records in ragged arrays: all vertices in ``xy`` (V, 2), rings
    delimited by ``ring_offsets`` (R + 1,), each ring tagged with its polygon
    (``ring_polygon`` (R,), numbered within its record) and whether it is a hole
    (``ring_hole`` (R,)); record i's rings are ``record_rings[i]:record_rings[i + 1]``."""
    xy: np.ndarray                 # (V, 2) float64
    ring_offsets: np.ndarray       # (R + 1,) int64
    ring_polygon: np.ndarray       # (R,) int32, polygon number within the record
    ring_hole: np.ndarray          # (R,) bool
    record_rings: np.ndarray       # (k + 1,) int64

    @classmethod
    def empty(cls) -> "FlatPolygons":
        return cls(np.zeros((0, 2)), np.zeros(1, np.int64), np.zeros(0, np.int32),
                   np.zeros(0, bool), np.zeros(1, np.int64))

    @classmethod
    def from_lists(cls, records: List[Polygons]) -> "FlatPolygons":
        """From per-record polygons ``[[exterior, hole, ...], ...]``."""
        rings, poly, hole, per_rec = [], [], [], []
        for polys in records:
            n = 0
            for j, p in enumerate(polys):
                for k, r in enumerate(p):
                    rings.append(np.asarray(r, np.float64).reshape(-1, 2))
                    poly.append(j)
                    hole.append(k > 0)
                    n += 1
            per_rec.append(n)
        if not rings:
            out = cls.empty()
            out.record_rings = np.zeros(len(records) + 1, np.int64)
            return out
        lens = np.array([len(r) for r in rings], np.int64)
        return cls(np.concatenate(rings), offsets(lens), np.array(poly, np.int32),
                   np.array(hole, bool), offsets(np.array(per_rec, np.int64)))

    @staticmethod
    def concat(parts: List["FlatPolygons"]) -> "FlatPolygons":
        parts = [p for p in parts if p is not None]
        if not parts:
            return FlatPolygons.empty()
        xy = np.concatenate([p.xy for p in parts])
        ring_lens = np.concatenate([np.diff(p.ring_offsets) for p in parts])
        rec_lens = np.concatenate([np.diff(p.record_rings) for p in parts])
        return FlatPolygons(xy, offsets(ring_lens), np.concatenate([p.ring_polygon for p in parts]),
                            np.concatenate([p.ring_hole for p in parts]), offsets(rec_lens))

    def __len__(self) -> int:
        return len(self.record_rings) - 1

    def polygons(self, i: int) -> Polygons:
        """Record ``i`` as ``[[exterior, hole, ...], ...]`` (open rings, views into ``xy``)."""
        out: Polygons = []
        for j in range(self.record_rings[i], self.record_rings[i + 1]):
            ring = self.xy[self.ring_offsets[j]:self.ring_offsets[j + 1]]
            if not self.ring_hole[j] or not out:
                out.append([ring])
            else:
                out[-1].append(ring)
        return out

    def with_xy(self, xy: np.ndarray) -> "FlatPolygons":
        """The same rings with other vertex coordinates (the same count)."""
        return FlatPolygons(xy, self.ring_offsets, self.ring_polygon, self.ring_hole,
                            self.record_rings)

    def take(self, order: np.ndarray) -> "FlatPolygons":
        """The records ``order`` (indices), in that order."""
        order = np.asarray(order, np.int64)
        rr0, rr1 = self.record_rings[order], self.record_rings[order + 1]
        ring_idx = ranges(rr0, rr1)
        v0, v1 = self.ring_offsets[ring_idx], self.ring_offsets[ring_idx + 1]
        return FlatPolygons(self.xy[ranges(v0, v1)], offsets(v1 - v0),
                            self.ring_polygon[ring_idx], self.ring_hole[ring_idx],
                            offsets(rr1 - rr0))

    def areas_centroids(self):
        """(area (k,), centroid (k, 2)) of every record (exteriors minus holes, whatever their
        orientation); centroid NaN for zero area."""
        k = len(self)
        if len(self.xy) == 0:
            return np.zeros(k), np.full((k, 2), np.nan)
        ring_a, moment = ring_moments(self.xy, self.ring_offsets)
        eff = np.where(self.ring_hole, -np.abs(ring_a), np.abs(ring_a))
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(ring_a != 0, eff / ring_a, 0.0)
        rec_of_ring = run_of(self.record_rings)
        area = np.bincount(rec_of_ring, eff, minlength=k)
        cx = np.bincount(rec_of_ring, moment[:, 0] * scale, minlength=k)
        cy = np.bincount(rec_of_ring, moment[:, 1] * scale, minlength=k)
        with np.errstate(invalid="ignore", divide="ignore"):
            cen = np.column_stack([cx, cy]) / area[:, None]
        cen[area <= 0] = np.nan
        return area, cen


def area(rings: Rings) -> float:
    """Area of a valid polygon or multipolygon given as rings: exteriors minus holes.

    Ring roles follow from nesting depth (a ring inside an odd number of others is a hole).
    """
    total = 0.0
    for i, ring in enumerate(rings):
        others = [r for j, r in enumerate(rings) if j != i]
        is_hole = bool(others) and bool(points_in_rings(ring[:1, 0], ring[:1, 1], others)[0])
        total += -abs(ring_area(ring)) if is_hole else abs(ring_area(ring))
    return total


def points_in_rings(x: np.ndarray, y: np.ndarray, rings: Rings) -> np.ndarray:
    """Even-odd point-in-polygon test, vectorised over points; returns a bool array."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    inside = np.zeros(x.shape, dtype=bool)
    for ring in rings:
        x0, y0 = ring[:, 0], ring[:, 1]
        x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
        for ax, ay, bx, by in zip(x0, y0, x1, y1):
            if ay == by:
                continue
            crosses = (ay <= y) != (by <= y)
            if not crosses.any():
                continue
            xc = ax + (y - ay) * (bx - ax) / (by - ay)
            inside ^= crosses & (x < xc)
    return inside


def rasterize(rings_px: Rings, shape: Tuple[int, int], all_touched: bool = False) -> np.ndarray:
    """Burn a (multi)polygon given in pixel coordinates into a bool mask of ``shape`` (rows, cols).

    Default: a pixel is inside when its centre is inside (GDAL's scanline rule: crossings at
    y = row + 0.5 on half-open edges, filled columns ``floor(xa + 0.5) <= c < floor(xb + 0.5)``).
    ``all_touched``: also every pixel that any edge passes through, i.e. every pixel the polygon
    intersects.
    """
    rows, cols = shape
    mask = np.zeros(shape, dtype=bool)
    if rows == 0 or cols == 0 or not len(rings_px):
        return mask
    a, b = _edges(rings_px)
    ylo = np.minimum(a[:, 1], b[:, 1])
    yhi = np.maximum(a[:, 1], b[:, 1])
    # rows whose centre line y = r + 0.5 lies in [ylo, yhi)
    r0 = np.maximum(np.ceil(ylo - 0.5), 0).astype(np.int64)
    r1 = np.minimum(np.ceil(yhi - 0.5), rows).astype(np.int64)  # exclusive
    n = np.maximum(r1 - r0, 0)
    if n.sum():
        edge = np.repeat(np.arange(len(a)), n)
        row = position_in_run(n) + r0[edge]
        yc = row + 0.5
        ax, ay, bx, by = a[edge, 0], a[edge, 1], b[edge, 0], b[edge, 1]
        xc = ax + (yc - ay) * (bx - ax) / (by - ay)
        order = np.lexsort((xc, row))
        row, xc = row[order], xc[order]
        # crossings come in pairs per row for closed rings
        start = np.floor(xc[0::2] + 0.5).astype(np.int64)
        stop = np.floor(xc[1::2] + 0.5).astype(np.int64)
        prow = row[0::2]
        start = np.clip(start, 0, cols)
        stop = np.clip(stop, 0, cols)
        ok = stop > start
        if prow.size < 2 or (prow[1:] != prow[:-1]).all():    # one span per row (convex)
            s_row = np.zeros(rows, np.int64)
            e_row = np.zeros(rows, np.int64)
            s_row[prow], e_row[prow] = start, stop
            c = np.arange(cols)
            return _touch(rings_px, (c >= s_row[:, None]) & (c < e_row[:, None]), all_touched)
        # spans of a row are disjoint: toggle at each start and stop, then the running parity
        flat = np.concatenate([prow[ok] * (cols + 1) + start[ok], prow[ok] * (cols + 1) + stop[ok]])
        toggle = np.bincount(flat, minlength=rows * (cols + 1)).reshape(rows, cols + 1)
        mask = (np.cumsum(toggle[:, :cols], axis=1, dtype=np.int32) & 1).astype(bool)
    return _touch(rings_px, mask, all_touched)


def row_spans(rings: Sequence[np.ndarray], shapes: Sequence[Tuple[int, int]]) -> list:
    """:func:`rasterize` (pixel centres) of many one-ring polygons at once, for those whose
    every row holds one span (convex ones, among others): per polygon, ``(start, stop)`` column
    arrays over its rows (mask: ``start[r] <= c < stop[r]``), or None where a row holds more
    than one span (then call :func:`rasterize`). ``rings[k]`` is in pixel coordinates of a
    grid of ``shapes[k]`` (rows, cols). One vectorised pass: the per-polygon cost of
    :func:`rasterize` (its fixed numpy calls) is what many small ROIs pay."""
    m = len(rings)
    out: list = [None] * m
    if not m:
        return out
    lens = np.array([len(r) for r in rings], np.int64)
    a = np.concatenate([np.asarray(r, np.float64)[:, :2] for r in rings])
    offs = offsets(lens)
    nxt = np.arange(len(a)) + 1
    nxt[offs[1:] - 1] = offs[:-1]
    b = a[nxt]
    owner = np.repeat(np.arange(m), lens)
    rows_of = np.array([sh[0] for sh in shapes], np.int64)
    cols_of = np.array([sh[1] for sh in shapes], np.int64)
    ylo, yhi = np.minimum(a[:, 1], b[:, 1]), np.maximum(a[:, 1], b[:, 1])
    r0 = np.maximum(np.ceil(ylo - 0.5), 0).astype(np.int64)
    r1 = np.minimum(np.ceil(yhi - 0.5), rows_of[owner]).astype(np.int64)
    n = np.maximum(r1 - r0, 0)
    edge = np.repeat(np.arange(len(a)), n)
    row = position_in_run(n) + r0[edge]
    own = owner[edge]
    ax, ay, bx, by = a[edge, 0], a[edge, 1], b[edge, 0], b[edge, 1]
    xc = ax + (row + 0.5 - ay) * (bx - ax) / (by - ay)
    order = np.lexsort((xc, row, own))
    own, row, xc = own[order], row[order], xc[order]
    # a closed ring crosses each row an even number of times: pairs never straddle polygons
    pown, prow = own[0::2], row[0::2]
    start = np.clip(np.floor(xc[0::2] + 0.5).astype(np.int64), 0, cols_of[pown])
    stop = np.clip(np.floor(xc[1::2] + 0.5).astype(np.int64), 0, cols_of[pown])
    more = np.zeros(m, bool)
    dup = (pown[1:] == pown[:-1]) & (prow[1:] == prow[:-1])
    more[pown[1:][dup]] = True
    # every polygon's rows in two arrays (rows without a crossing: the empty span 0, 0)
    base = offsets(rows_of)
    s_all = np.zeros(int(base[-1]), np.int64)
    e_all = np.zeros(int(base[-1]), np.int64)
    s_all[base[pown] + prow], e_all[base[pown] + prow] = start, stop
    b = base.tolist()
    for k in np.flatnonzero(~more).tolist():
        out[k] = (s_all[b[k]:b[k + 1]], e_all[b[k]:b[k + 1]])
    return out


def _touch(rings_px: Rings, mask: np.ndarray, all_touched: bool) -> np.ndarray:
    """``mask`` with, for ``all_touched``, every pixel an edge of the rings passes through."""
    rows, cols = mask.shape
    if all_touched:
        for ring in rings_px:
            for (x0, y0), (x1, y1) in zip(ring, np.roll(ring, -1, axis=0)):
                rr, cc = _segment_cells(x0, y0, x1, y1)
                ok = (rr >= 0) & (rr < rows) & (cc >= 0) & (cc < cols)
                mask[rr[ok], cc[ok]] = True
    return mask


def _segment_cells(x0: float, y0: float, x1: float, y1: float) -> Tuple[np.ndarray, np.ndarray]:
    """Rows and columns of every cell a segment passes through (supercover)."""
    ts = [np.array([0.0, 1.0])]
    dx, dy = x1 - x0, y1 - y0
    if dx != 0:
        gx = np.arange(np.ceil(min(x0, x1)), np.floor(max(x0, x1)) + 1)
        ts.append((gx - x0) / dx)
    if dy != 0:
        gy = np.arange(np.ceil(min(y0, y1)), np.floor(max(y0, y1)) + 1)
        ts.append((gy - y0) / dy)
    t = np.unique(np.clip(np.concatenate(ts), 0.0, 1.0))
    mid = (t[:-1] + t[1:]) / 2 if len(t) > 1 else t
    cc = np.floor(x0 + mid * dx).astype(np.int64)
    rr = np.floor(y0 + mid * dy).astype(np.int64)
    return rr, cc


def distance_to_rings(x: np.ndarray, y: np.ndarray, rings: Rings) -> np.ndarray:
    """Euclidean distance from each point to the nearest edge of any ring."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    best = np.full(x.shape, np.inf)
    a, b = _edges(rings)
    for (ax, ay), (bx, by) in zip(a, b):
        ex, ey = bx - ax, by - ay
        L2 = ex * ex + ey * ey
        t = np.zeros_like(x) if L2 == 0 else np.clip(((x - ax) * ex + (y - ay) * ey) / L2, 0, 1)
        d = np.hypot(x - (ax + t * ex), y - (ay + t * ey))
        np.minimum(best, d, out=best)
    return best


def _convex_simple(ring: np.ndarray) -> bool:
    """True when the ring (open, (n, 2)) is a strictly convex polygon: every turn strictly to
    the same side and the turns add up to one full turn (a star's add up to more), so no two
    of its edges can meet except adjacent ones at their shared vertex."""
    if len(ring) < 3:
        return False
    e = np.concatenate([ring[1:], ring[:1]]) - ring[:, :2]
    f = np.concatenate([e[1:], e[:1]])
    cross = e[:, 0] * f[:, 1] - e[:, 1] * f[:, 0]
    if not ((cross > 0).all() or (cross < 0).all()):
        return False
    turn = np.arctan2(cross, e[:, 0] * f[:, 0] + e[:, 1] * f[:, 1])
    return bool(abs(abs(turn.sum()) - 2 * np.pi) < 1e-6)


def convex_simple_rings(xy: np.ndarray, offs: np.ndarray) -> np.ndarray:
    """(R,) bool: :func:`_convex_simple` of every ring of the ragged vertices ``xy`` (V, 2),
    ring i = ``xy[offs[i]:offs[i + 1]]``, in one pass (rings of fewer than 3 vertices: False).
    What validating many plots costs when they are convex (most are)."""
    lens = np.diff(offs)
    out = np.zeros(len(lens), bool)
    full = np.flatnonzero(lens >= 3)
    if not len(full):
        return out
    sub = np.concatenate([np.arange(offs[i], offs[i + 1]) for i in full]) \
        if len(full) < len(lens) else np.arange(len(xy))
    o = offsets(lens[full])
    p = np.asarray(xy, np.float64)[sub, :2]
    nxt = cyclic_next(o)
    e = p[nxt] - p
    f = e[nxt]
    cross = e[:, 0] * f[:, 1] - e[:, 1] * f[:, 0]
    starts = o[:-1]
    lo, hi = np.minimum.reduceat(cross, starts), np.maximum.reduceat(cross, starts)
    turn = np.add.reduceat(np.arctan2(cross, e[:, 0] * f[:, 0] + e[:, 1] * f[:, 1]), starts)
    out[full] = ((lo > 0) | (hi < 0)) & (np.abs(np.abs(turn) - 2 * np.pi) < 1e-6)
    return out


def self_intersections(rings: Rings, max_report: int = 1) -> List[Tuple[float, float]]:
    """Points where edges of the rings cross or touch other than at shared ring vertices.

    An empty list means the rings form a simple (valid) polygon boundary.
    """
    if len(rings) == 1 and _convex_simple(np.asarray(rings[0], np.float64)):
        return []                   # a strictly convex ring turning once: simple
    a, b = _edges(rings)
    ring_id = np.concatenate([np.full(len(r), i) for i, r in enumerate(rings)])
    idx = np.concatenate([np.arange(len(r)) for r in rings])
    size = np.concatenate([np.full(len(r), len(r)) for r in rings])
    found: List[Tuple[float, float]] = []
    E = len(a)
    step = max(1, 4_000_000 // max(E, 1))
    for s in range(0, E, step):
        i = np.arange(s, min(E, s + step))[:, None]
        j = np.arange(E)[None, :]
        p, r = a[i], b[i] - a[i]
        q, sv = a[j], b[j] - a[j]
        rxs = r[..., 0] * sv[..., 1] - r[..., 1] * sv[..., 0]
        qp = q - p
        t_num = qp[..., 0] * sv[..., 1] - qp[..., 1] * sv[..., 0]
        u_num = qp[..., 0] * r[..., 1] - qp[..., 1] * r[..., 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = t_num / rxs
            u = u_num / rxs
        same_ring = ring_id[i] == ring_id[j]
        k = size[i]
        adjacent = same_ring & (((idx[i] + 1) % k == idx[j]) | ((idx[j] + 1) % k == idx[i]))
        hit = (j > i) & ~adjacent & (rxs != 0) & (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
        # collinear overlapping edges
        coll = (j > i) & ~adjacent & (rxs == 0) & (t_num == 0)
        if coll.any():
            rr = np.einsum("...k,...k", r, r)
            with np.errstate(divide="ignore", invalid="ignore"):
                t0 = np.einsum("...k,...k", qp, r) / rr
                t1 = t0 + np.einsum("...k,...k", sv, r) / rr
            coll &= (np.maximum(t0, t1) > 0) & (np.minimum(t0, t1) < 1)
            hit |= coll
        ii, jj = np.nonzero(hit)
        for m in range(min(len(ii), max_report - len(found))):
            pi = p[ii[m], 0]
            tt = t[ii[m], jj[m]]
            tt = 0.0 if not np.isfinite(tt) else tt
            pt = pi + tt * r[ii[m], 0]
            found.append((float(pt[0]), float(pt[1])))
        if len(found) >= max_report:
            break
    return found
