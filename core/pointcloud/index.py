"""One pass over a cloud, testing each point only against the few regions near it.

Regions are given by their bounding boxes (k, 4) = (xmin, ymin, xmax, ymax) plus an exact test
``test(k, x, y) -> bool mask``. A uniform grid over the boxes (cell ≈ the median box size) maps
each cell to the boxes touching it; for every chunk of points, each point gets the candidate
boxes of its cell, the boxes' own extents filter those pairs, and the exact test runs once per
box on its candidate points. Memory: one chunk of coordinates plus the kept indices.
"""
from typing import Callable, List, Optional, Tuple

import numpy as np

from ..progress import Progress
from ..ragged import position_in_run
from .cloud import PointCloud

MAX_CELLS = 4_000_000
CELLS_PER_BOX = 6
"""Grid cells across the median box: finer cells give fewer candidate pairs outside the boxes
(cells of a third of a box gave 2.2 candidates per point in a box on the benchmark's plots,
a sixth 1.6) for more cell entries."""


class BoxGrid:
    """Uniform grid mapping cells to the boxes whose extent touches them (CSR layout)."""

    def __init__(self, boxes: np.ndarray):
        boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
        self.boxes = boxes
        self.bx0, self.by0, self.bx1, self.by1 = (np.ascontiguousarray(c) for c in boxes.T)
        self.x0, self.y0 = boxes[:, 0].min(), boxes[:, 1].min()
        w = boxes[:, 2] - boxes[:, 0]
        h = boxes[:, 3] - boxes[:, 1]
        span_x = boxes[:, 2].max() - self.x0
        span_y = boxes[:, 3].max() - self.y0
        size = float(np.median(np.maximum(w, h))) / CELLS_PER_BOX  # few boxes per cell
        if not size > 0:
            size = max(span_x, span_y, 1e-9) / 64 or 1.0
        while (span_x / size + 1) * (span_y / size + 1) > MAX_CELLS:
            size *= 2
        self.size = size
        self.nx = int(span_x // size) + 1
        self.ny = int(span_y // size) + 1
        c0x, c0y = self._cell_xy(boxes[:, 0], boxes[:, 1])
        c1x, c1y = self._cell_xy(boxes[:, 2], boxes[:, 3])
        wx, wy = c1x - c0x + 1, c1y - c0y + 1
        n = wx * wy
        box = np.repeat(np.arange(len(boxes)), n)
        k = position_in_run(n)
        cell = (c0y[box] + k // wx[box]) * self.nx + c0x[box] + k % wx[box]
        order = np.argsort(cell, kind="stable")
        self.items = box[order]
        self.start = np.zeros(self.nx * self.ny + 1, dtype=np.int64)
        np.cumsum(np.bincount(cell, minlength=self.nx * self.ny), out=self.start[1:])

    def _cell_xy(self, x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        cx = np.clip(np.floor((x - self.x0) / self.size), 0, self.nx - 1).astype(np.int64)
        cy = np.clip(np.floor((y - self.y0) / self.size), 0, self.ny - 1).astype(np.int64)
        return cx, cy

    def pairs(self, x: np.ndarray, y: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """(point, box) index pairs with the point inside the box's extent (edges included),
        by point, then box, ascending."""
        fx = (x - self.x0) / self.size        # cell = floor(fx): the truncation of fx ≥ 0
        fy = (y - self.y0) / self.size
        pts = np.flatnonzero((fx >= 0) & (fx < self.nx) & (fy >= 0) & (fy < self.ny))
        cell = fy[pts].astype(np.int64)
        cell *= self.nx
        cell += fx[pts].astype(np.int64)
        s = self.start[cell]
        cnt = self.start[cell + 1] - s        # cells without a box repeat nothing below
        pt = np.repeat(pts, cnt)
        box = self.items[np.repeat(s, cnt) + position_in_run(cnt)]
        px, py = x[pt], y[pt]
        inb = (px >= self.bx0[box]) & (px <= self.bx1[box]) & \
            (py >= self.by0[box]) & (py <= self.by1[box])
        return pt[inb], box[inb]


def one_pass(cloud: PointCloud, boxes: np.ndarray, test: Callable[[int, np.ndarray, np.ndarray],
             np.ndarray], z_range: Tuple[Optional[float], Optional[float]] = (None, None),
             progress: Optional[Progress] = None, chunk_size: int = 2_000_000
             ) -> Tuple[List[np.ndarray], np.ndarray]:
    """Indices (ascending, int64) of the cloud's points passing ``test`` for each box, and the
    xy bounds of all points (xmin, ymin, xmax, ymax; NaN for an empty cloud).

    ``z_range`` (zmin, zmax), either may be None: only points with zmin ≤ z ≤ zmax count.
    ``progress`` is checked for cancellation after every chunk.
    """
    progress = progress or Progress()
    k = len(boxes)
    found: List[List[np.ndarray]] = [[] for _ in range(k)]
    lo = np.array([np.inf, np.inf])
    hi = -lo
    n = len(cloud)
    grid = BoxGrid(boxes) if k else None
    zmin, zmax = z_range
    with_z = zmin is not None or zmax is not None
    for start, xyz in cloud.iter_xyz(chunk_size, 3 if with_z else 2):
        progress.check()
        x, y = xyz[:, 0], xyz[:, 1]
        z = xyz[:, 2] if with_z else None
        if len(x):
            lo = np.minimum(lo, [x.min(), y.min()])
            hi = np.maximum(hi, [x.max(), y.max()])
        if grid is not None and len(x):
            if with_z:
                zok = np.ones(len(z), bool)
                if zmin is not None:
                    zok &= z >= zmin
                if zmax is not None:
                    zok &= z <= zmax
                sel = np.flatnonzero(zok)
                pt, box = grid.pairs(x[sel], y[sel])
                pt = sel[pt]
            else:
                pt, box = grid.pairs(x, y)
            # stable radix sort on small integers keeps each box's points in ascending order
            order = np.argsort(box.astype(np.int16 if k < 2**15 else np.int32), kind="stable")
            pt, box = pt[order], box[order]
            edges = np.flatnonzero(np.diff(box)) + 1
            starts = np.concatenate([[0], edges]) if len(pt) else np.zeros(0, np.int64)
            stops = np.concatenate([edges, [len(pt)]]) if len(pt) else np.zeros(0, np.int64)
            for a, e in zip(starts, stops):
                b = int(box[a])
                p = pt[a:e]
                keep = test(b, x[p], y[p])
                if keep.any():
                    found[b].append(p[keep] + start)
        progress.set(100.0 * min(start + chunk_size, n) / max(n, 1))
    bounds = np.array([*lo, *hi]) if n else np.full(4, np.nan)
    out = [np.concatenate(f).astype(np.int64, copy=False) if f else np.zeros(0, np.int64)
           for f in found]
    return out, bounds
