"""The ground under each ROI, as a plane: z = a + bx·(x − x0) + by·(y − y0).

Heights above ground are measured against one plane per ROI, in the ROIs' CRS (so DSMs, point
clouds and the DTM of a season may come in different CRSs and grids), with (x0, y0) the centre
of the ROI's bounding box. The plane comes from either

* a bare-soil DSM or DTM of the season: the least-squares plane through its valid pixels
  inside the ROI (:func:`fit_plane`); it follows slopes exactly and smooths furrows and clods;
* or, without one, the ROI's own low points: the ``q``-th percentile of the heights in each
  cell of a 3 × 3 grid over the ROI, and the plane through those, refined on the heights above
  it (:func:`low_plane`). This follows a slope across the plot (a single low percentile would
  put the ground at the plot's lowest corner: 4 cm too low on a 4 m plot at 2 %), but needs bare
  soil in most cells: on a closed canopy, use a DTM.
"""
from typing import NamedTuple, Optional

import numpy as np

LOW_GRID = 3          # cells per side of the grid of low points
LOW_MIN_COUNT = 8     # values a cell needs to give a low point
LOW_PASSES = 2        # the plane through the cells' low points, then once on the heights above it
LOW_SAMPLE = 20000    # values used at most (every k-th of a larger ROI)


class Plane(NamedTuple):
    x0: float
    y0: float
    a: float
    bx: float
    by: float

    def at(self, x, y) -> np.ndarray:
        """Ground height at map points (x, y) in the ROIs' CRS."""
        return self.a + self.bx * (np.asarray(x) - self.x0) + self.by * (np.asarray(y) - self.y0)


def fit_plane(x: np.ndarray, y: np.ndarray, z: np.ndarray, centre) -> Optional[Plane]:
    """Least-squares plane through points; flat (their mean) when they do not span a plane;
    None without points."""
    x0, y0 = centre
    if not len(z):
        return None
    dx, dy = np.asarray(x, np.float64) - x0, np.asarray(y, np.float64) - y0
    z = np.asarray(z, np.float64)
    a = np.column_stack([np.ones_like(dx), dx, dy])
    coef, _, rank, _ = np.linalg.lstsq(a, z, rcond=None)
    if rank < 3:
        return Plane(x0, y0, float(z.mean()), 0.0, 0.0)
    return Plane(x0, y0, float(coef[0]), float(coef[1]), float(coef[2]))


def low_plane(x: np.ndarray, y: np.ndarray, z: np.ndarray, q: float, centre) -> Optional[Plane]:
    """The plane through the ``q``-th percentile heights (nearest rank) of the cells of a 3 × 3
    grid over the points' extent (each at its cell's mean position), refined on the heights
    above that plane, so that a slope across a cell does not pull the ground
    down to the cell's lowest corner. With fewer than 3 cells of :data:`LOW_MIN_COUNT` values,
    flat at the ``q``-th percentile of all. Large ROIs are sampled (every k-th value, at most
    :data:`LOW_SAMPLE`). None without points."""
    if not len(z):
        return None
    step = -(-len(z) // LOW_SAMPLE)
    x, y, z = (np.asarray(v, np.float64)[::step] for v in (x, y, z))
    cells = []
    for axis in (x, y):
        lo, hi = axis.min(), axis.max()
        k = np.floor((axis - lo) / max(hi - lo, 1e-12) * LOW_GRID).astype(np.int64)
        cells.append(np.clip(k, 0, LOW_GRID - 1))
    cell = cells[1] * LOW_GRID + cells[0]
    order = np.argsort(cell, kind="stable")            # the values of each cell contiguous
    x, y, z = x[order], y[order], z[order]
    ends = np.cumsum(np.bincount(cell, minlength=LOW_GRID * LOW_GRID))
    spans = [(b - n, b) for n, b in zip(np.diff(ends, prepend=0), ends) if n >= LOW_MIN_COUNT]
    if len(spans) < 3:
        return Plane(centre[0], centre[1], _low(z, q), 0.0, 0.0)
    px = np.array([x[a:b].mean() for a, b in spans])
    py = np.array([y[a:b].mean() for a, b in spans])
    plane = Plane(centre[0], centre[1], 0.0, 0.0, 0.0)
    for _ in range(LOW_PASSES):
        r = z - plane.at(x, y)
        fix = fit_plane(px, py, np.array([_low(r[a:b], q) for a, b in spans]), centre)
        plane = Plane(centre[0], centre[1], plane.a + fix.a, plane.bx + fix.bx, plane.by + fix.by)
    return plane


def _low(v: np.ndarray, q: float) -> float:
    """The ``q``-th percentile of ``v`` by nearest rank (one partition)."""
    k = int(round(q / 100.0 * (len(v) - 1)))
    return float(np.partition(v, k)[k])
