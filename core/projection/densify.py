"""Densification of the ROIs' edges: each edge split so that its image is at most the sensor's
``segment_px`` long in every photo (:class:`.sensor_geometry.SensorGeometry`)."""
import numpy as np

from ..geometry import split_edges
from ..ragged import cyclic_next, run_of
from .height_sources import GeometryZ
from .roi_rings import BLOCK_PAIRS, ROIRings, vertex_heights
from .sensor_geometry import MAX_SUBDIVISIONS


def densify_rings(rings: ROIRings, rois, source, recon, cams, geo, distortion, prog) -> ROIRings:
    """Split edges so that no projected segment exceeds its sensor's ``segment_px``."""
    seg = np.array([geo[c.sensor_id].segment_px for c in cams])
    if not np.isfinite(seg).any():
        return rings
    V = len(rings.xy)
    nxt = cyclic_next(rings.ring_offsets)
    need = np.zeros(V)                              # edge length / allowed length, max over photos
    xyz = np.column_stack([rings.xy, rings.z])
    inv_seg = np.where(np.isfinite(seg), 1.0 / seg, 0.0)
    step = max(1, BLOCK_PAIRS // max(len(cams), 1))
    # blocks of whole rings, so both ends of every edge are in the block
    cut = [0]
    for r in range(len(rings.ring_roi)):
        if rings.ring_offsets[r + 1] - cut[-1] > step and rings.ring_offsets[r] > cut[-1]:
            cut.append(int(rings.ring_offsets[r]))
    cut.append(V)
    for b0, b1 in zip(cut[:-1], cut[1:]):
        prog.check()
        p = recon.project_points(xyz[b0:b1], rois.crs, cameras=cams, distortion=distortion)
        uv = p.pixels
        nb = nxt[b0:b1] - b0
        d = np.linalg.norm(uv[:, nb] - uv, axis=2) * inv_seg[:, None]
        need[b0:b1] = np.nanmax(np.where(np.isfinite(d), d, 0.0), axis=0)
        prog.set(100.0 * b1 / V)
    nsub = np.clip(np.ceil(need), 1, MAX_SUBDIVISIONS).astype(np.int64)
    if (nsub == 1).all():
        return rings
    # new vertex list: each vertex followed by its edge's interior points
    src, dst, t, new_offsets = split_edges(rings.ring_offsets, nsub)
    xy = rings.xy[src] + t[:, None] * (rings.xy[dst] - rings.xy[src])
    original = t == 0
    new_ring = run_of(rings.ring_offsets)[src]
    if isinstance(source, GeometryZ):
        z = rings.z[src] + t * (rings.z[dst] - rings.z[src])
    else:
        z = np.empty(len(src))
        z[original] = rings.z[src[original]]
        if (~original).any():
            z[~original] = vertex_heights(source, rois, rings, xy[~original], rois.crs,
                                           ring_index=new_ring[~original])
    return ROIRings(xy, z, new_offsets, rings.ring_roi, rings.ring_part, rings.ring_hole,
                    rings.roi_rings, original)
