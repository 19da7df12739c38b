"""Planar polygon primitives on numpy arrays: point-in-polygon, rasterisation, distances, validity.

A polygon is a list of rings (exterior first, then holes); a multipolygon is the concatenation of
its parts' rings. Rings are (n, 2) float64 arrays of (x, y), open (the first vertex is not
repeated). Inside-ness uses the even-odd rule over all rings, which honours holes and multipart
polygons at once.

Rasterisation works in *pixel coordinates*: x = column, y = row, origin at the top-left corner of
the top-left pixel, so the centre of pixel (row r, col c) is (c + 0.5, r + 0.5).
"""
from typing import List, Sequence, Tuple

import numpy as np

Rings = Sequence[np.ndarray]


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
    starts = np.concatenate([r for r in rings])
    ends = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    return starts, ends


def ring_area(ring: np.ndarray) -> float:
    """Signed area (shoelace); positive for counter-clockwise rings in a y-up frame.

    Computed relative to the first vertex, so UTM-size coordinates keep their precision.
    """
    x, y = ring[:, 0] - ring[0, 0], ring[:, 1] - ring[0, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


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
        row = np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n) + r0[edge]
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
        # spans of a row are disjoint: toggle at each start and stop, then XOR-accumulate
        toggle = np.zeros((rows, cols + 1), dtype=bool)
        np.logical_xor.at(toggle, (prow[ok], start[ok]), True)
        np.logical_xor.at(toggle, (prow[ok], stop[ok]), True)
        mask = np.logical_xor.accumulate(toggle[:, :cols], axis=1)
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


def self_intersections(rings: Rings, max_report: int = 1) -> List[Tuple[float, float]]:
    """Points where edges of the rings cross or touch other than at shared ring vertices.

    An empty list means the rings form a simple (valid) polygon boundary.
    """
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
