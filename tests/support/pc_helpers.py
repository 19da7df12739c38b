"""Helpers for the point-cloud tests: an independent point-in-polygon count and ROI builders."""
import numpy as np

from easyidp_toolbox.core import ROI, ROISet


def winding_inside(x, y, rings):
    """Independent inside test: per ring, the winding number by angle summation (inside when
    non-zero); a point is in the polygon when an odd number of rings contain it."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    parity = np.zeros(len(x), dtype=np.int64)
    for ring in rings:
        near = np.flatnonzero((x >= ring[:, 0].min()) & (x <= ring[:, 0].max())
                              & (y >= ring[:, 1].min()) & (y <= ring[:, 1].max()))
        px, py = x[near], y[near]
        total = np.zeros(len(near))
        for (ax, ay), (bx, by) in zip(ring, np.roll(ring, -1, axis=0)):
            a = np.arctan2(ay - py, ax - px)
            b = np.arctan2(by - py, bx - px)
            d = b - a
            d = (d + np.pi) % (2 * np.pi) - np.pi
            total += d
        parity[near] += np.rint(np.abs(total) / (2 * np.pi)).astype(np.int64) != 0
    return parity % 2 == 1


def polygon(cx, cy, r, n=7, phase=0.3):
    t = phase + np.linspace(0, 2 * np.pi, n + 1)[:-1]
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def random_rois(lo, hi, k, rng, crs=None, rmin=10.0, rmax=60.0):
    """``k`` irregular polygons inside the xy extent; every third one with a hole, every
    fifth one a two-part multipolygon. Vertex coordinates are non-round so no LAS point
    (0.01 grid) falls on an edge."""
    rois = []
    for i in range(k):
        cx, cy = rng.uniform(lo[:2] + rmax, hi[:2] - rmax)
        r = rng.uniform(rmin, rmax)
        ext = polygon(cx + 0.00317, cy + 0.00731, r, n=int(rng.integers(4, 9)))
        part = [ext]
        if i % 3 == 0:
            part.append(polygon(cx + 0.00317, cy + 0.00731, r / 3, n=5, phase=1.1))
        parts = [part]
        if i % 5 == 0:
            parts.append([polygon(cx + 2.4 * r + 0.0011, cy + 0.0023, r / 2, n=6)])
        rois.append(ROI(f"plot {i}", parts))
    return ROISet(rois, crs)
