"""The ground under each ROI, as a plane: z = a + bx·(x − x0) + by·(y − y0).

Heights above ground are measured against one plane per ROI, in the ROIs' CRS (so DSMs, point
clouds and the DTM of a season may come in different CRSs and grids), with (x0, y0) the centre
of the ROI's bounding box. The plane comes from either

* a bare-soil DSM or DTM of the season: the least-squares plane through its valid pixels
  inside the ROI (:func:`fit_plane`); it follows slopes exactly and smooths furrows and clods;
* or, without one, the ROI's own low points: the ``q``-th percentile of the heights in each
  cell of a 3 × 3 grid over the ROI, and the plane through those (:func:`low_plane`). This
  follows a slope across the plot (a single low percentile would put the ground at the plot's
  lowest corner) but needs bare soil in most cells: on a closed canopy, use a DTM.
"""
from typing import NamedTuple, Optional

import numpy as np

LOW_GRID = 3          # cells per side of the grid of low points
LOW_MIN_COUNT = 8     # values a cell needs to give a low point


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
    """The plane through the ``q``-th percentile of z in each cell of a 3 × 3 grid over the
    points' extent (at the cell's mean position); with fewer than 3 such cells, flat at the
    ``q``-th percentile of all. None without points."""
    if not len(z):
        return None
    x, y, z = (np.asarray(v, np.float64) for v in (x, y, z))
    cells = []
    for axis in (x, y):
        lo, hi = axis.min(), axis.max()
        k = np.floor((axis - lo) / max(hi - lo, 1e-12) * LOW_GRID).astype(np.int64)
        cells.append(np.clip(k, 0, LOW_GRID - 1))
    cell = cells[1] * LOW_GRID + cells[0]
    px, py, pz = [], [], []
    for c in range(LOW_GRID * LOW_GRID):
        sel = cell == c
        if np.count_nonzero(sel) >= LOW_MIN_COUNT:
            px.append(x[sel].mean())
            py.append(y[sel].mean())
            pz.append(np.percentile(z[sel], q))
    if len(pz) >= 3:
        plane = fit_plane(np.array(px), np.array(py), np.array(pz), centre)
        if plane is not None and (plane.bx or plane.by):
            return plane
    return Plane(centre[0], centre[1], float(np.percentile(z, q)), 0.0, 0.0)
