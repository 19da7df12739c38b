"""The ROIs of a back-projection as flat ring arrays, with a height at every vertex.

:class:`ROIRings` holds every ring of every ROI end to end (the even-odd vocabulary of
:mod:`core.geometry`, with ring → part → ROI indices); :func:`ring_arrays` builds it from a
:class:`ROISet`, :func:`vertex_heights` gives its vertices their heights from a height source
(:mod:`.height_sources`).
"""
from dataclasses import dataclass

import numpy as np

from ..errors import EasyIDPError
from ..raster import DSM
from ..roi import ROISet
from .height_sources import (ConstantHeight, GeometryZ, PerROIHeights, check_geometry_z,
                             missing_heights_error, per_roi_values)
from .result import _offsets

BLOCK_PAIRS = 1 << 21
"""Camera × vertex pairs projected at once (about 40 MB of pixels and statuses)."""


@dataclass
class ROIRings:
    """The ROIs' rings, flat: ``xy`` (V, 2) map coordinates in the ROIs' CRS, ``z`` (V,)
    heights, ``ring_offsets`` (R+1,), ``ring_roi``/``ring_part``/``ring_hole`` (R,),
    ``roi_rings`` (n+1,) offsets of each ROI's rings, ``original`` (V,) the input vertices."""
    xy: np.ndarray
    z: np.ndarray
    ring_offsets: np.ndarray
    ring_roi: np.ndarray
    ring_part: np.ndarray
    ring_hole: np.ndarray
    roi_rings: np.ndarray
    original: np.ndarray

    def roi_vertex_range(self, r: int):
        return (int(self.ring_offsets[self.roi_rings[r]]),
                int(self.ring_offsets[self.roi_rings[r + 1]]))


def ring_arrays(rois: ROISet) -> ROIRings:
    xy, ring_roi, ring_part, ring_hole, lens, per_roi = [], [], [], [], [], []
    for i, roi in enumerate(rois):
        n = 0
        for j, part in enumerate(roi.parts):
            for k, ring in enumerate(part):
                xy.append(ring)
                lens.append(len(ring))
                ring_roi.append(i)
                ring_part.append(j)
                ring_hole.append(k > 0)
                n += 1
        per_roi.append(n)
    xy = np.concatenate(xy).astype(np.float64)
    return ROIRings(xy, np.zeros(len(xy)), _offsets(np.array(lens, np.int64)),
                  np.array(ring_roi, np.int64), np.array(ring_part, np.int32),
                  np.array(ring_hole, bool), _offsets(np.array(per_roi, np.int64)),
                  np.ones(len(xy), bool))


def vertex_heights(source, rois, rings: ROIRings, xy: np.ndarray, crs, ring_index) -> np.ndarray:
    """Heights at ``xy`` (the original vertices when ``ring_index`` is None; otherwise new
    vertices, with ``ring_index`` their ring)."""
    roi_of = rings.ring_roi[ring_index] if ring_index is not None else \
        np.repeat(rings.ring_roi, np.diff(rings.ring_offsets))
    if isinstance(source, ConstantHeight):
        return np.full(len(xy), source.height)
    if isinstance(source, PerROIHeights):
        return per_roi_values(source, rois)[roi_of]
    if isinstance(source, DSM):
        z = source.heights(xy[:, 0], xy[:, 1], crs=crs)
        bad = ~np.isfinite(z)
        if bad.any():
            raise missing_heights_error(sorted({rois[i].name for i in roi_of[bad]}))
        return z
    if isinstance(source, GeometryZ):
        if ring_index is None:
            check_geometry_z(rois)
            return np.concatenate([z for r in rois for z in r.ring_z]).astype(np.float64)
        raise AssertionError("geometry Z is interpolated, not sampled")
    raise EasyIDPError(f"Unknown height source {source!r}.")
