"""Backward projection: every ROI in every raw photo that sees it (EasyIDP's ``back2raw``).

:func:`back_project` gives the ROIs their vertex heights (:mod:`.heights`), densifies their
edges, projects them with :meth:`Reconstruction.project_points` (block-wise, vectorised over
ROIs × photos), clips them to the photo frame, tests occlusion against a DSM when one is given,
and ranks the photos of each ROI by a score. Pixels follow the project convention (origin at
the top-left image corner, centre of the top-left pixel at (0.5, 0.5)).

Rules (ARCHITECTURE.md, "Backward projection", has the reasons):

* **Densification**: an edge is split so that its image is at most ``L`` px long in every photo
  where both ends are in front of the camera and inside the lens model's valid radius, where
  ``L = sqrt(8·tol/κ)`` and κ is the largest curvature (1/px) the sensor's distortion gives a
  straight line inside the frame: the chord then departs from the true, bent image of the edge
  by at most ``tol`` px (``densify_tolerance``, default 0.1 px).
* **Visibility**: a vertex behind the camera or beyond the valid radius never folds back into
  the frame. A ROI wholly inside the frame is kept as is; one partly inside is clipped exactly
  to the frame (``clip=True``) or dropped (``clip=False``, EasyIDP's all-vertices rule). When
  some vertices are behind the camera or beyond the valid radius, the ROI is first clipped to
  the lens model's valid cone in camera space (exact: the cone's faces are planes through the
  camera centre), then distorted and clipped to the frame.
* ``visible_fraction``: the ground area of the clipped polygon (its pixels cast back as rays
  onto the ROI's best-fit plane) over the ROI's area on that plane.
* ``gsd``: sqrt(visible ground area / visible pixel area), map units per pixel.
"""
import math
from dataclasses import dataclass
from typing import List, Optional, Sequence

import numpy as np

from ..errors import EasyIDPError, ROIError
from ..geometry import points_in_rings
from ..progress import as_progress
from ..reconstruction import INSIDE, border_pixels
from ..roi import ROISet
from .clip import (ConvexRegion, clip_convex, clip_convex_rings_to_frames, convex_rings, orient,
                   rectangle, signed_area)
from .heights import (ConstantHeight, DSMHeights, GeometryZ, PerROIHeights, check_geometry_z,
                      height_source, missing_heights_error, per_roi_values, sample_dsm)
from .result import BackProjection, FlatPolygons, _offsets, _ranges

BLOCK_PAIRS = 1 << 21
"""Camera × vertex pairs projected at once (about 40 MB of pixels and statuses)."""
MAX_SUBDIVISIONS = 4096
"""Most pieces one edge is cut into (an edge seen from a few metres by a fisheye)."""


@dataclass
class _Rings:
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


def back_project(rois: ROISet, recon, *, heights, cameras: Optional[Sequence] = None,
                 distortion: bool = True, clip: bool = True, occlusion_dsm=None,
                 min_visible: float = 0.5, max_images: int = 0,
                 densify_tolerance: float = 0.1, occlusion_samples: int = 256,
                 occlusion_tolerance: Optional[float] = None,
                 progress=None, is_cancelled=None) -> BackProjection:
    """Project ROIs into the raw photos of a photogrammetry project.

    ``rois``: a :class:`ROISet` in any CRS the project can be related to (a local project
    takes ROIs without a CRS as local coordinates). ``heights``: the vertex heights, see
    :mod:`.heights` (``"geometry"``, a number, :class:`DSMHeights`, :class:`PerROIHeights`).
    ``cameras``: labels (default: every aligned, enabled camera). ``distortion``: False for
    photos undistorted by the photogrammetry software. ``clip``: clip ROIs to the frame (True)
    or keep only photos that hold the whole ROI (False). ``occlusion_dsm``: a DSM (path or
    :class:`DSMHeights`) to test lines of sight against (see :mod:`.occlusion`).
    ``min_visible``: photos whose visible, unoccluded share of the ROI is below this are
    dropped (and counted); ``max_images``: keep the best k photos per ROI (0 = all).
    """
    if not 0.0 <= float(min_visible) <= 1.0:
        raise EasyIDPError(f"min_visible must be between 0 and 1, not {min_visible}.")
    if int(max_images) < 0:
        raise EasyIDPError(f"max_images must be 0 (all) or more, not {max_images}.")
    if not densify_tolerance > 0:
        raise EasyIDPError(f"densify_tolerance must be positive, not {densify_tolerance}.")
    prog = as_progress(progress, is_cancelled)
    source = height_source(heights)
    rois = _checked_rois(rois, recon)
    cams = _cameras(recon, cameras)
    crs = rois.crs
    _check_transform(rois, recon)

    rings = _ring_arrays(rois)
    rings.z = _vertex_heights(source, rois, rings, rings.xy, crs, ring_index=None)
    prog.set(2)
    sensors = {c.sensor_id: recon.calibrated_sensor(c) for c in cams}
    geo = {sid: _SensorGeometry(s, distortion, densify_tolerance) for sid, s in sensors.items()}
    rings = _densify(rings, rois, source, recon, cams, geo, distortion, prog.sub(2, 15))
    prog.check()

    X = recon.to_model(np.column_stack([rings.xy, rings.z]), crs)   # model frame, once
    per_roi = _roi_geometry(rings, X, len(rois), recon)
    cand = _candidates(per_roi, cams, geo)                              # (n_rois, m) bool

    recs = _project_and_clip(rois, rings, X, per_roi, cand, recon, cams, geo, distortion, clip,
                             prog.sub(15, 75))
    occluded = np.full(len(recs["roi"]), np.nan)
    notes: List[str] = []
    if occlusion_dsm is not None and len(recs["roi"]):
        from .occlusion import occluded_fractions
        occluded, occ_notes = occluded_fractions(
            rois, recs["roi"], recs["cam"], recon, cams, occlusion_dsm, occlusion_samples,
            occlusion_tolerance, prog.sub(75, 95))
        notes += occ_notes
    prog.set(95)
    result = _finish(rois, recon, cams, geo, per_roi, recs, occluded, float(min_visible),
                     int(max_images), clip)
    result.settings = {"heights": source.describe(), "distortion": bool(distortion),
                       "clip": bool(clip), "occlusion": occlusion_dsm is not None,
                       "min_visible": float(min_visible), "max_images": int(max_images),
                       "densify_tolerance_px": float(densify_tolerance),
                       "segment_px": {s.label: g.segment_px for s, g in
                                      ((sensors[k], geo[k]) for k in geo)},
                       "vertices": {"input": int(rings.original.sum()), "densified": len(rings.xy)}}
    result.notes = list(recon.notes) + notes
    prog.set(100)
    return result


# --- inputs --------------------------------------------------------------------------------------
def _checked_rois(rois, recon) -> ROISet:
    if not isinstance(rois, ROISet):
        rois = ROISet(list(rois))
    if not len(rois):
        raise ROIError("No ROIs given: the ROI layer has no features.")
    rois.validate()
    if rois.crs is None and not recon.is_local:
        raise ROIError(f"The ROIs have no CRS, so they cannot be placed in the project "
                       f"({recon.crs.name if recon.crs is not None else 'no CRS'}). Set the "
                       "layer's CRS and run again.")
    return rois


def _cameras(recon, cameras):
    if cameras is None:
        cams = recon.aligned_cameras
        if not cams:
            raise EasyIDPError(f"{recon.source}: no aligned, enabled camera in the project "
                               f"({len(recon.cameras)} camera(s), {len(recon.unaligned_cameras)} "
                               "not aligned): align the photos in the photogrammetry software first.")
        return cams
    cams = recon.select_cameras(cameras)
    if not cams:
        raise EasyIDPError("The list of cameras to project into is empty.")
    return cams


def _check_transform(rois: ROISet, recon) -> None:
    """Fail early, naming the CRSs, when the ROIs cannot be placed in the project."""
    xy = rois[0].rings[0][:1]
    try:
        m = recon.to_model(np.column_stack([xy, [0.0]]), rois.crs)
    except EasyIDPError as exc:
        raise EasyIDPError(f"The ROIs (CRS {rois.crs.name if rois.crs else 'none'}) cannot be "
                           f"placed in the project {recon.source}: {exc}") from None
    if not np.all(np.isfinite(m)):
        raise EasyIDPError(f"The ROIs (CRS {rois.crs.name if rois.crs else 'none'}) cannot be "
                           f"transformed to the project's CRS ({recon.crs.name if recon.crs else 'none'}).")


def _ring_arrays(rois: ROISet) -> _Rings:
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
    return _Rings(xy, np.zeros(len(xy)), _offsets(np.array(lens, np.int64)),
                  np.array(ring_roi, np.int64), np.array(ring_part, np.int32),
                  np.array(ring_hole, bool), _offsets(np.array(per_roi, np.int64)),
                  np.ones(len(xy), bool))


def _vertex_heights(source, rois, rings: _Rings, xy: np.ndarray, crs, ring_index) -> np.ndarray:
    """Heights at ``xy`` (the original vertices when ``ring_index`` is None; otherwise new
    vertices, with ``ring_index`` their ring)."""
    roi_of = rings.ring_roi[ring_index] if ring_index is not None else \
        np.repeat(rings.ring_roi, np.diff(rings.ring_offsets))
    if isinstance(source, ConstantHeight):
        return np.full(len(xy), source.height)
    if isinstance(source, PerROIHeights):
        return per_roi_values(source, rois)[roi_of]
    if isinstance(source, DSMHeights):
        z = sample_dsm(source, xy, crs)
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


# --- sensor geometry and densification --------------------------------------------------------------
class _SensorGeometry:
    """Per sensor: the largest normalised radius of the frame (``r_frame``), the valid radius,
    the cone that holds the frame, and the longest image segment ``segment_px`` whose chord
    stays within ``tol`` px of the true image of a straight edge."""

    def __init__(self, sensor, distortion: bool, tol: float):
        cal = sensor.calibration
        self.sensor = sensor
        self.cal = cal
        self.distortion = distortion
        b = border_pixels(sensor.width, sensor.height, 64)
        x, y = cal.pixel_to_normalised(b[:, 0], b[:, 1], distortion)
        self.r_frame = float(np.sqrt(np.max(x * x + y * y)))
        self.r_valid = float(np.sqrt(sensor.r2_limit)) if distortion else 4.0 * self.r_frame
        self.cos_cone = 1.0 / math.sqrt(1.0 + (self.r_frame * 1.01) ** 2)
        self.sin_cone = (self.r_frame * 1.01) * self.cos_cone
        self.segment_px = self._segment(tol)
        self._ngon = None

    def _segment(self, tol: float) -> float:
        """sqrt(8·tol/κ) px for the largest line curvature κ inside the frame (inf: none)."""
        if not (self.distortion and self.cal.has_distortion):
            return math.inf
        s = self.sensor
        u, v = np.meshgrid(np.linspace(0, s.width, 13), np.linspace(0, s.height, 11))
        x, y = self.cal.pixel_to_normalised(u.ravel(), v.ravel(), True)
        h = 8.0 / self.cal.f                                 # ±8 px steps, normalised
        kappa = 0.0
        for ang in np.radians([0.0, 45.0, 90.0, 135.0]):
            dx, dy = h * math.cos(ang), h * math.sin(ang)
            pa = np.column_stack(self.cal.project_normalised(x - dx, y - dy))
            pm = np.column_stack(self.cal.project_normalised(x, y))
            pb = np.column_stack(self.cal.project_normalised(x + dx, y + dy))
            dev = np.linalg.norm(pm - (pa + pb) / 2, axis=1)
            length = np.linalg.norm(pb - pa, axis=1)
            kappa = max(kappa, float(np.max(8.0 * dev / length ** 2)))
        return math.inf if kappa <= 0 else max(1.0, math.sqrt(8.0 * tol / kappa))

    def ngon(self):
        """(inradius ρ, circumradius, n) of the polygonal cone used for the valid radius."""
        if self._ngon is None:
            rf, rv = self.r_frame, self.r_valid
            if rv > rf * 1.0005:
                rho = rf + 0.5 * (rv - rf)
                n = int(np.clip(math.ceil(math.pi / math.acos(rho / rv)), 8, 1440))
            else:                                  # lens model barely covers the frame
                n = 1440
                rho = rv * math.cos(math.pi / n)
            self._ngon = (rho, rho / math.cos(math.pi / n), n)
        return self._ngon


def _densify(rings: _Rings, rois, source, recon, cams, geo, distortion, prog) -> _Rings:
    """Split edges so that no projected segment exceeds its sensor's ``segment_px``."""
    seg = np.array([geo[c.sensor_id].segment_px for c in cams])
    if not np.isfinite(seg).any():
        return rings
    V = len(rings.xy)
    ring_of_v = np.repeat(np.arange(len(rings.ring_roi)), np.diff(rings.ring_offsets))
    nxt = np.arange(V) + 1
    nxt[rings.ring_offsets[1:] - 1] = rings.ring_offsets[:-1]
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
    total = int(nsub.sum())
    src = np.repeat(np.arange(V), nsub)
    t = (np.arange(total) - np.repeat(_offsets(nsub)[:-1], nsub)) / np.repeat(nsub, nsub)
    a, b = rings.xy[src], rings.xy[nxt[src]]
    xy = a + t[:, None] * (b - a)
    original = t == 0
    new_ring = ring_of_v[src]
    if isinstance(source, GeometryZ):
        z = rings.z[src] + t * (rings.z[nxt[src]] - rings.z[src])
    else:
        z = np.empty(total)
        z[original] = rings.z[src[original]]
        if (~original).any():
            z[~original] = _vertex_heights(source, rois, rings, xy[~original], rois.crs,
                                           ring_index=new_ring[~original])
    lens = np.bincount(new_ring, minlength=len(rings.ring_roi))
    return _Rings(xy, z, _offsets(lens), rings.ring_roi, rings.ring_part, rings.ring_hole,
                  rings.roi_rings, original)


# --- per-ROI 3-D geometry ----------------------------------------------------------------------------
@dataclass
class _ROIGeometry:
    centre: np.ndarray     # (n, 3) model-frame area centroid on the ROI's plane
    radius: np.ndarray     # (n,) bounding-sphere radius about ``centre``
    plane: np.ndarray      # (n, 3) z = a + b·x + c·y in the model frame
    area: np.ndarray       # (n,) horizontal area in the model frame
    up: np.ndarray         # (n, 3) "up" at the centre


def _roi_geometry(rings: _Rings, X: np.ndarray, n: int, recon) -> _ROIGeometry:
    v0 = rings.ring_offsets[rings.roi_rings[:-1]]
    v1 = rings.ring_offsets[rings.roi_rings[1:]]
    roi_of_v = np.repeat(np.arange(n), v1 - v0)
    # horizontal areas and centroids (model xy), per ring then per ROI
    flat = FlatPolygons(X[:, :2], rings.ring_offsets, rings.ring_part, rings.ring_hole,
                        rings.roi_rings)
    area, cen = flat.areas_centroids()
    # least-squares plane per ROI about its vertex mean
    cnt = np.bincount(roi_of_v, minlength=n).astype(float)
    mean = np.column_stack([np.bincount(roi_of_v, X[:, k], minlength=n) for k in range(3)]) / cnt[:, None]
    d = X - mean[roi_of_v]
    sxx = np.bincount(roi_of_v, d[:, 0] * d[:, 0], minlength=n)
    sxy = np.bincount(roi_of_v, d[:, 0] * d[:, 1], minlength=n)
    syy = np.bincount(roi_of_v, d[:, 1] * d[:, 1], minlength=n)
    sxz = np.bincount(roi_of_v, d[:, 0] * d[:, 2], minlength=n)
    syz = np.bincount(roi_of_v, d[:, 1] * d[:, 2], minlength=n)
    det = sxx * syy - sxy * sxy
    ok = det > 1e-12 * (sxx + syy) ** 2
    with np.errstate(invalid="ignore", divide="ignore"):
        b = np.where(ok, (sxz * syy - syz * sxy) / det, 0.0)
        c = np.where(ok, (syz * sxx - sxz * sxy) / det, 0.0)
    a = mean[:, 2] - b * mean[:, 0] - c * mean[:, 1]
    bad = ~np.isfinite(cen).all(axis=1)
    cen[bad] = mean[bad, :2]
    centre = np.column_stack([cen, a + b * cen[:, 0] + c * cen[:, 1]])
    radius = np.zeros(n)
    np.maximum.at(radius, roi_of_v, np.linalg.norm(X - centre[roi_of_v], axis=1))
    return _ROIGeometry(centre, radius, np.column_stack([a, b, c]), np.abs(area),
                        recon.frame.up(centre))


def _candidates(g: _ROIGeometry, cams, geo) -> np.ndarray:
    """(n_rois, m): the ROI's bounding sphere meets the cone that holds the photo's frame."""
    out = np.zeros((len(g.centre), len(cams)), bool)
    for j, cam in enumerate(cams):
        sg = geo[cam.sensor_id]
        d = g.centre - cam.C
        t = d @ cam.R[2]                                     # along the optical axis
        p = np.sqrt(np.maximum(np.einsum("ij,ij->i", d, d) - t * t, 0.0))
        dist = p * sg.cos_cone - t * sg.sin_cone             # signed distance to the cone
        apex_side = t * sg.cos_cone + p * sg.sin_cone < 0
        near = np.where(apex_side, np.linalg.norm(d, axis=1) <= g.radius, dist <= g.radius)
        out[:, j] = near
    return out


# --- projection and clipping ----------------------------------------------------------------------
def _project_and_clip(rois, rings: _Rings, X, g: _ROIGeometry, cand, recon, cams, geo,
                      distortion, clip, prog) -> dict:
    """Records (ROI, camera) with their pixel polygons, visible fraction and clipped flag."""
    n, m = len(rois), len(cams)
    xyz = np.column_stack([rings.xy, rings.z])
    v0 = rings.ring_offsets[rings.roi_rings[:-1]]
    v1 = rings.ring_offsets[rings.roi_rings[1:]]
    nv = v1 - v0
    budget = max(1, BLOCK_PAIRS // m)
    out = {"roi": [], "cam": [], "vis": [], "clipped": [], "polys": [], "partial": 0}
    r0 = 0
    while r0 < n:
        r1 = r0 + 1
        while r1 < n and v1[r1] - v0[r0] <= budget:
            r1 += 1
        prog.check()
        a, b = int(v0[r0]), int(v1[r1 - 1])
        sub_cams = np.flatnonzero(cand[r0:r1].any(axis=0))
        if len(sub_cams):
            p = recon.project_points(xyz[a:b], rois.crs, cameras=[cams[j] for j in sub_cams],
                                     distortion=distortion)
            _block_records(rings, X, g, cand, recon, cams, geo, distortion, clip, p.pixels,
                           p.status, sub_cams, r0, r1, a, nv, out)
        prog.set(100.0 * r1 / n)
        r0 = r1
    return {"roi": np.concatenate(out["roi"]) if out["roi"] else np.zeros(0, np.int64),
            "cam": np.concatenate(out["cam"]) if out["cam"] else np.zeros(0, np.int64),
            "vis": np.concatenate(out["vis"]) if out["vis"] else np.zeros(0),
            "clipped": np.concatenate(out["clipped"]) if out["clipped"] else np.zeros(0, bool),
            "polys": FlatPolygons.concat(out["polys"]), "partial": out["partial"]}


def _block_records(rings, X, g, cand, recon, cams, geo, distortion, clip, uv, st, sub_cams,
                   r0, r1, a, nv, out) -> None:
    starts = (rings.ring_offsets[rings.roi_rings[r0:r1]] - a).astype(np.int64)
    inside = (st == INSIDE).astype(np.int32)
    n_in = np.add.reduceat(inside, starts, axis=1)           # (m_sub, n_block)
    finite = np.isfinite(uv[..., 0]).astype(np.int32)
    n_fin = np.add.reduceat(finite, starts, axis=1)
    nvb = nv[r0:r1]
    cand_b = cand[r0:r1][:, sub_cams].T                       # (m_sub, n_block)
    whole = n_in == nvb[None, :]
    some = (n_in > 0) & ~whole
    # whole ROIs: gather their pixels in one go
    ci, ri = np.nonzero(whole)
    if len(ci):
        polys = _gather_whole(rings, uv, ci, ri + r0, a)
        out["roi"].append(ri + r0)
        out["cam"].append(sub_cams[ci])
        out["vis"].append(np.ones(len(ci)))
        out["clipped"].append(np.zeros(len(ci), bool))
        out["polys"].append(polys)
    if not clip:
        out["partial"] += int(some.sum())
        return
    # partial ROIs, and candidates with no vertex inside that the quick test cannot reject
    outside_all = (n_in == 0) & cand_b
    if outside_all.any():
        u, v = uv[..., 0], uv[..., 1]
        w = np.array([geo[cams[j].sensor_id].sensor.width for j in sub_cams])[:, None]
        h = np.array([geo[cams[j].sensor_id].sensor.height for j in sub_cams])[:, None]
        one_side = ((np.add.reduceat((u < 0).astype(np.int32), starts, axis=1) == nvb)
                    | (np.add.reduceat((u > w).astype(np.int32), starts, axis=1) == nvb)
                    | (np.add.reduceat((v < 0).astype(np.int32), starts, axis=1) == nvb)
                    | (np.add.reduceat((v > h).astype(np.int32), starts, axis=1) == nvb))
        outside_all &= ~(one_side & (n_fin == nvb[None, :]))
    todo_c, todo_r = np.nonzero(some | outside_all)
    if not len(todo_c):
        return
    # fast path: one-ring ROIs, every vertex valid, convex in the photo: clipped all at once
    single = (rings.roi_rings[r0 + todo_r + 1] - rings.roi_rings[r0 + todo_r]) == 1
    valid = n_fin[todo_c, todo_r] == nvb[todo_r]
    fast = np.flatnonzero(single & valid)
    res_roi, res_cam, res_flat = [], [], []
    if len(fast):
        ci, ri = todo_c[fast], todo_r[fast]
        whole_rings = _gather_whole(rings, uv, ci, ri + r0, a)
        convex = convex_rings(whole_rings.xy, whole_rings.ring_offsets)
        f = np.flatnonzero(convex)
        if len(f):
            src = whole_rings.take(f)
            wh = np.array([[geo[cams[sub_cams[c]].sensor_id].sensor.width,
                            geo[cams[sub_cams[c]].sensor_id].sensor.height] for c in ci[f]], float)
            cxy, coff = clip_convex_rings_to_frames(src.xy, src.ring_offsets, wh[:, 0], wh[:, 1])
            n_out = np.diff(coff)
            flat = FlatPolygons(cxy, coff, np.zeros(len(f), np.int32), np.zeros(len(f), bool),
                                np.arange(len(f) + 1, dtype=np.int64))
            ok = np.flatnonzero(n_out >= 3)
            res_roi.append(ri[f][ok] + r0)
            res_cam.append(sub_cams[ci[f][ok]])
            res_flat.append(flat.take(ok))
        slow = np.setdiff1d(np.arange(len(todo_c)), fast[f])
    else:
        slow = np.arange(len(todo_c))
    lists_roi, lists_cam, lists_polys = [], [], []
    for c, rr in zip(todo_c[slow], todo_r[slow]):
        r = rr + r0
        cam = cams[sub_cams[c]]
        sg = geo[cam.sensor_id]
        va, vb = rings.roi_vertex_range(r)
        polys = _clip_record(rings, r, X[va:vb], uv[c, va - a:vb - a], n_fin[c, rr] == nvb[rr],
                             cam, sg, g, distortion, recon)
        if polys:
            lists_roi.append(r)
            lists_cam.append(sub_cams[c])
            lists_polys.append(polys)
    if lists_roi:
        res_roi.append(np.array(lists_roi, np.int64))
        res_cam.append(np.array(lists_cam, np.int64))
        res_flat.append(FlatPolygons.from_lists(lists_polys))
    if not res_roi:
        return
    roi_i, cam_i = np.concatenate(res_roi), np.concatenate(res_cam)
    flat = FlatPolygons.concat(res_flat)
    if not len(flat):
        return
    vis = _visible_fractions(flat, roi_i, cam_i, rings, X, g, cams, geo, recon, distortion)
    keep = np.flatnonzero(vis > 0)
    out["roi"].append(roi_i[keep])
    out["cam"].append(cam_i[keep])
    out["vis"].append(np.minimum(vis[keep], 1.0))
    out["clipped"].append(np.ones(len(keep), bool))
    out["polys"].append(flat.take(keep))


def _gather_whole(rings: _Rings, uv, ci, r, a) -> FlatPolygons:
    """Flat polygons of ROIs wholly inside photos: their projected rings, as they are."""
    rr0, rr1 = rings.roi_rings[r], rings.roi_rings[r + 1]
    ring_idx = _ranges(rr0, rr1)
    vs, ve = rings.ring_offsets[ring_idx], rings.ring_offsets[ring_idx + 1]
    vidx = _ranges(vs, ve)
    cam_of_v = np.repeat(np.repeat(ci, rr1 - rr0), ve - vs)
    return FlatPolygons(uv[cam_of_v, vidx - a], _offsets(ve - vs), rings.ring_part[ring_idx],
                        rings.ring_hole[ring_idx], _offsets(rr1 - rr0))


def _roi_structure(rings: _Rings, r: int, arrays: np.ndarray) -> List[List[np.ndarray]]:
    """``arrays`` (the ROI's vertices, any dimension) split into [[exterior, holes], ...]."""
    va = rings.ring_offsets[rings.roi_rings[r]]
    polys: List[List[np.ndarray]] = []
    for j in range(rings.roi_rings[r], rings.roi_rings[r + 1]):
        ring = arrays[rings.ring_offsets[j] - va:rings.ring_offsets[j + 1] - va]
        if not rings.ring_hole[j] or not polys:
            polys.append([ring])
        else:
            polys[-1].append(ring)
    return polys


def _clip_record(rings, r, Xr, uvr, all_valid, cam, sg, g, distortion, recon):
    """Pixel polygons of ROI ``r`` in photo ``cam``, clipped to the frame (may be empty)."""
    s = sg.sensor
    frame = rectangle(s.width, s.height)
    if all_valid:
        return clip_convex(orient(_roi_structure(rings, r, uvr)), frame)
    # some vertices behind the camera or beyond the valid radius: clip to the valid cone first
    Xc = (Xr - cam.C) @ cam.R.T
    rho, rcirc, n = sg.ngon()
    th = 2 * np.pi * np.arange(n) / n
    phi = th + np.pi / n
    cphi, sphi = np.cos(phi), np.sin(phi)
    ngon = np.column_stack([rcirc * np.cos(th), rcirc * np.sin(th)])

    def values(p):
        return rho * p[:, 2:3] - p[:, 0:1] * cphi[None, :] - p[:, 1:2] * sphi[None, :]

    def to_plane(p):
        return p[:, :2] / p[:, 2:3]

    cone = ConvexRegion(ngon, values, to_plane)
    sigma = _image_orientation(g, r, Xr, cam)
    if sigma == 0:
        return []
    structure = _roi_structure(rings, r, Xc)
    ground = _roi_structure(rings, r, Xr[:, :2])
    oriented = []
    for p3, p2 in zip(structure, ground):
        rs = []
        for k, (r3, r2) in enumerate(zip(p3, p2)):
            positive = (signed_area(r2) > 0) == (sigma > 0)
            rs.append(r3 if positive == (k == 0) else r3[::-1])
        oriented.append(rs)

    def probe_inside(q):                          # the cone's cross-section inside the ROI?
        d = np.array([q[0], q[1], 1.0]) @ cam.R    # model-frame direction
        a, b, c = g.plane[r]
        denom = d[2] - b * d[0] - c * d[1]
        if abs(denom) < 1e-15:
            return False
        t = (a + b * cam.C[0] + c * cam.C[1] - cam.C[2]) / denom
        if t <= 0:
            return False
        P = cam.C + t * d
        return bool(points_in_rings(P[:1], P[1:2], [rr for pp in ground for rr in pp])[0])

    normalised = clip_convex(oriented, cone, probe_inside)
    if not normalised:
        return []
    step = (sg.segment_px if np.isfinite(sg.segment_px) else 16.0) / sg.cal.f
    pixel_polys = []
    for p in normalised:
        rs = []
        for ring in p:
            dense = _densify_ring(ring, step)
            u, v = sg.cal.project_normalised(dense[:, 0], dense[:, 1], distortion)
            rs.append(np.column_stack([u, v]))
        pixel_polys.append(rs)
    return clip_convex(orient(pixel_polys), frame)


def _densify_ring(ring: np.ndarray, step: float) -> np.ndarray:
    b = np.concatenate((ring[1:], ring[:1]))
    k = np.clip(np.ceil(np.linalg.norm(b - ring, axis=1) / step), 1, MAX_SUBDIVISIONS).astype(np.int64)
    src = np.repeat(np.arange(len(ring)), k)
    t = (np.arange(int(k.sum())) - np.repeat(_offsets(k)[:-1], k)) / np.repeat(k, k)
    return ring[src] + t[:, None] * (b[src] - ring[src])


def _image_orientation(g: _ROIGeometry, r: int, Xr: np.ndarray, cam) -> int:
    """+1 when a positively oriented ground polygon (model x, y) stays positive in the
    camera's normalised plane, −1 when it flips, 0 when no vertex is in front."""
    zc = (Xr - cam.C) @ cam.R[2]
    i = int(np.argmax(zc))
    if zc[i] <= 0:
        return 0
    a, b, c = g.plane[r]
    eps = max(float(g.radius[r]), 1e-6) * 1e-4
    P = Xr[i].copy()
    P[2] = a + b * P[0] + c * P[1]
    tri = np.array([P, P + eps * np.array([1.0, 0.0, b]), P + eps * np.array([0.0, 1.0, c])])
    q = (tri - cam.C) @ cam.R.T
    q = q[:, :2] / q[:, 2:3]
    s = signed_area(q)
    return 1 if s > 0 else (-1 if s < 0 else 0)


def _visible_fractions(flat: FlatPolygons, roi_i, cam_i, rings: _Rings, X, g: _ROIGeometry,
                       cams, geo, recon, distortion) -> np.ndarray:
    """Per clipped record: the ground area of its pixel polygons (densified, cast as rays onto
    the ROI's best-fit plane) over the ROI's area on that plane (its vertices cast from the
    camera centre onto the plane). Vectorised over records; one ray call per photo."""
    k = len(flat)
    step = np.array([geo[cams[j].sensor_id].segment_px for j in cam_i])
    dense = _densify_flat(flat, np.where(np.isfinite(step), step, np.inf))
    rec_of_ring = np.repeat(np.arange(k), np.diff(dense.record_rings))
    rec_of_v = np.repeat(rec_of_ring, np.diff(dense.ring_offsets))
    dirs = np.empty((len(dense.xy), 3))
    cam_of_v = cam_i[rec_of_v]
    for j in np.unique(cam_i):
        sel = cam_of_v == j
        _, dirs[sel] = recon.pixel_to_ray(cams[j], dense.xy[sel], distortion)
    C = np.array([cams[j].C for j in cam_i])
    ground, ok = _on_plane(C[rec_of_v], dirs, g.plane[roi_i[rec_of_v]])
    area_vis, _ = FlatPolygons(ground, dense.ring_offsets, dense.ring_polygon, dense.ring_hole,
                               dense.record_rings).areas_centroids()
    bad = np.bincount(rec_of_v, ~ok, minlength=k) > 0
    # the whole ROI on the same plane, cast from the same camera centre
    rr0, rr1 = rings.roi_rings[roi_i], rings.roi_rings[roi_i + 1]
    ring_idx = _ranges(rr0, rr1)
    vs, ve = rings.ring_offsets[ring_idx], rings.ring_offsets[ring_idx + 1]
    vidx = _ranges(vs, ve)
    rec_of_rv = np.repeat(np.repeat(np.arange(k), rr1 - rr0), ve - vs)
    full, ok_full = _on_plane(C[rec_of_rv], X[vidx] - C[rec_of_rv], g.plane[roi_i[rec_of_rv]])
    area_full, _ = FlatPolygons(full, _offsets(ve - vs), rings.ring_part[ring_idx],
                                rings.ring_hole[ring_idx], _offsets(rr1 - rr0)).areas_centroids()
    behind = np.bincount(rec_of_rv, ~ok_full, minlength=k) > 0
    # vertices beyond the camera's horizon have no image on the plane: the ROI's own area
    area_full = np.where(behind | ~(area_full > 0), g.area[roi_i], area_full)
    with np.errstate(invalid="ignore", divide="ignore"):
        vis = np.where(bad, 0.0, area_vis / area_full)
    return np.nan_to_num(vis, nan=0.0)


def _on_plane(C, d, plane):
    """Horizontal (x, y) of C + t·d on z = a + b·x + c·y per row, and whether t > 0."""
    a, b, c = plane[:, 0], plane[:, 1], plane[:, 2]
    denom = d[:, 2] - b * d[:, 0] - c * d[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a + b * C[:, 0] + c * C[:, 1] - C[:, 2]) / denom
    ok = np.isfinite(t) & (t > 0)
    xy = C[:, :2] + np.where(ok, t, 0.0)[:, None] * d[:, :2]
    return xy, ok


def _densify_flat(flat: FlatPolygons, step: np.ndarray) -> FlatPolygons:
    """Every ring edge of record i split into pieces of at most ``step[i]`` px."""
    if not np.isfinite(step).any() or not len(flat.xy):
        return flat
    lens = np.diff(flat.ring_offsets)
    starts = flat.ring_offsets[:-1]
    nxt = np.arange(len(flat.xy)) + 1
    nxt[flat.ring_offsets[1:] - 1] = starts
    rec_of_ring = np.repeat(np.arange(len(flat)), np.diff(flat.record_rings))
    st = np.repeat(step[rec_of_ring], lens)
    seg = np.linalg.norm(flat.xy[nxt] - flat.xy, axis=1)
    n = np.clip(np.ceil(np.where(np.isfinite(st), seg / st, 1.0)), 1, MAX_SUBDIVISIONS).astype(np.int64)
    src = np.repeat(np.arange(len(flat.xy)), n)
    t = (np.arange(int(n.sum())) - np.repeat(_offsets(n)[:-1], n)) / np.repeat(n, n)
    xy = flat.xy[src] + t[:, None] * (flat.xy[nxt[src]] - flat.xy[src])
    ring_of_v = np.repeat(np.arange(len(lens)), lens)
    new_lens = np.bincount(ring_of_v[src], minlength=len(lens))
    return FlatPolygons(xy, _offsets(new_lens), flat.ring_polygon, flat.ring_hole,
                        flat.record_rings)


# --- ranking and the result ------------------------------------------------------------------------
def score(share, view_angle_deg, gsd, gsd_best, centre_distance):
    """The rank of a photo for a ROI, in [0, 1] (0 when the DSM hides the whole ROI): the
    product of

    * ``share`` = visible_fraction × (1 − occluded_fraction): how much of the ROI it shows;
    * cos(view angle off nadir): oblique views foreshorten and hide more;
    * ``gsd_best / gsd``: resolution relative to the ROI's sharpest photo;
    * 1 − ½·centre_distance²: distortion and vignetting grow towards the corners (½ there).
    """
    return (np.asarray(share) * np.cos(np.radians(view_angle_deg)) * (gsd_best / gsd)
            * (1.0 - 0.5 * np.minimum(np.asarray(centre_distance), 1.5) ** 2))


def _finish(rois, recon, cams, geo, g: _ROIGeometry, recs, occluded, min_visible, max_images,
            clip) -> BackProjection:
    names = rois.names
    labels = [c.label for c in cams]
    sizes = np.array([[geo[c.sensor_id].sensor.width, geo[c.sensor_id].sensor.height] for c in cams])
    pp = np.array([[geo[c.sensor_id].cal.cx, geo[c.sensor_id].cal.cy] for c in cams], float)
    roi, cam, vis, clipped, polys = (recs[k] for k in ("roi", "cam", "vis", "clipped", "polys"))
    area_px, cen_px = polys.areas_centroids()
    Cs = np.array([c.C for c in cams]) if cams else np.zeros((0, 3))
    to_cam = Cs[cam] - g.centre[roi]
    cosang = np.einsum("ij,ij->i", to_cam, g.up[roi]) / np.linalg.norm(to_cam, axis=1)
    angle = np.degrees(np.arccos(np.clip(cosang, -1.0, 1.0)))
    with np.errstate(invalid="ignore", divide="ignore"):
        gsd = np.sqrt(vis * g.area[roi] / area_px)
        half_diag = 0.5 * np.hypot(sizes[cam, 0], sizes[cam, 1])
        cdist = np.linalg.norm(cen_px - pp[cam], axis=1) / half_diag
    share = vis * (1.0 - np.nan_to_num(occluded, nan=0.0))
    dropped = {"partly_outside": int(recs["partial"])}
    keep = share >= min_visible
    dropped["below_min_visible"] = int((~keep).sum())
    by_roi_dropped = np.bincount(roi[~keep], minlength=len(names))
    idx = np.flatnonzero(keep)
    best_gsd = np.full(len(names), np.inf)
    np.minimum.at(best_gsd, roi[idx], gsd[idx])
    sc = np.zeros(len(roi))
    sc[idx] = score(share[idx], angle[idx], gsd[idx], best_gsd[roi[idx]], cdist[idx])
    order = idx[np.lexsort((cam[idx], -sc[idx], roi[idx]))]
    first = np.ones(len(order), bool)
    first[1:] = roi[order][1:] != roi[order][:-1]
    start = np.maximum.accumulate(np.where(first, np.arange(len(order)), 0))
    rank = np.arange(len(order)) - start + 1
    if max_images > 0:
        over = rank > max_images
        dropped["beyond_max_images"] = int(over.sum())
        order, rank = order[~over], rank[~over]
    counts = np.bincount(roi[order], minlength=len(names))
    unseen = {}
    partial_note = "" if clip else " whole (it is partly outside every photo that sees it)"
    for i in np.flatnonzero(counts == 0):
        if by_roi_dropped[i]:
            unseen[names[i]] = (f"seen by {by_roi_dropped[i]} photo(s), but less than "
                                f"{min_visible:g} of it visible and unoccluded in each")
        else:
            unseen[names[i]] = f"no photo sees it{partial_note}"
    return BackProjection(
        roi_names=names, photo_labels=labels, photo_paths=[c.photo_path for c in cams],
        image_sizes=sizes, principal_points=pp, roi=roi[order],
        photo=np.array(labels, dtype=str)[cam[order]] if len(order) else np.zeros(0, str),
        photo_index=cam[order], polygons=polys.take(order), visible_fraction=vis[order],
        occluded_fraction=occluded[order], score=sc[order], view_angle=angle[order],
        gsd=gsd[order], centre_distance=cdist[order], rank=rank.astype(np.int32),
        clipped=clipped[order], unseen=unseen, dropped=dropped)
