"""The ROIs of a back-projection as flat ring arrays, with a height at every vertex.

:class:`ROIRings` holds every ring of every ROI end to end (the even-odd vocabulary of
:mod:`core.geometry`, with ring → part → ROI indices); :func:`ring_arrays` builds it from a
:class:`ROISet`, :func:`vertex_heights` gives its vertices their heights from a height source
(:mod:`.height_sources`).
"""
from dataclasses import dataclass

import numpy as np

from ..errors import EasyIDPError
from ..geometry import FlatPolygons
from ..ragged import offsets, ranges, run_of
from ..raster import DSM
from ..roi import ROISet
from .height_sources import (ConstantHeight, GeometryZ, PerROIHeights, check_geometry_z,
                             missing_heights_error, per_roi_values)

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

    def flat(self, xy: np.ndarray) -> FlatPolygons:
        """The ROIs as flat polygons (one record per ROI) with vertices ``xy`` (V, 2)."""
        return FlatPolygons(xy, self.ring_offsets, self.ring_part, self.ring_hole, self.roi_rings)

    def take(self, r: np.ndarray):
        """ROIs ``r`` (indices, repeats allowed) as one record each: (``vidx`` (M,) the indices
        of their vertices in ``xy``, ``record`` (M,) the record of each, the records' flat
        polygons without vertices: give them with :meth:`FlatPolygons.with_xy`)."""
        rr0, rr1 = self.roi_rings[r], self.roi_rings[r + 1]
        ring_idx = ranges(rr0, rr1)
        vs, ve = self.ring_offsets[ring_idx], self.ring_offsets[ring_idx + 1]
        record = np.repeat(np.repeat(np.arange(len(rr0)), rr1 - rr0), ve - vs)
        return ranges(vs, ve), record, FlatPolygons(None, offsets(ve - vs), self.ring_part[ring_idx],
                                                    self.ring_hole[ring_idx], offsets(rr1 - rr0))

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
    return ROIRings(xy, np.zeros(len(xy)), offsets(np.array(lens, np.int64)),
                    np.array(ring_roi, np.int64), np.array(ring_part, np.int32),
                    np.array(ring_hole, bool), offsets(np.array(per_roi, np.int64)),
                    np.ones(len(xy), bool))


def vertex_heights(source, rois, rings: ROIRings, xy: np.ndarray, crs, ring_index) -> np.ndarray:
    """Heights at ``xy`` (the original vertices when ``ring_index`` is None; otherwise new
    vertices, with ``ring_index`` their ring)."""
    roi_of = rings.ring_roi[ring_index] if ring_index is not None else \
        rings.ring_roi[run_of(rings.ring_offsets)]
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
