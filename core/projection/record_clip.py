"""Projection of the ROIs into their candidate photos and clipping of each (ROI, photo) record
to the frame: whole ROIs as they are, convex one-ring ROIs all at once, the rest one by one
(first to the lens model's valid cone in camera space when some vertices are behind the camera
or beyond the valid radius)."""
from typing import List

import numpy as np

from ..geometry import FlatPolygons, densify, orient, points_in_rings, ring_area
from ..reconstruction import INSIDE
from .clip import ConvexRegion, clip_convex, clip_convex_rings_to_frames, convex_rings, rectangle
from .roi_geometry import ROIGeometry
from .roi_rings import BLOCK_PAIRS, ROIRings
from .sensor_geometry import MAX_SUBDIVISIONS
from .visibility import visible_fractions


def project_and_clip(rois, rings: ROIRings, X, g: ROIGeometry, cand, recon, cams, geo,
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
    vis = visible_fractions(flat, roi_i, cam_i, rings, X, g, cams, geo, recon, distortion)
    keep = np.flatnonzero(vis > 0)
    out["roi"].append(roi_i[keep])
    out["cam"].append(cam_i[keep])
    out["vis"].append(np.minimum(vis[keep], 1.0))
    out["clipped"].append(np.ones(len(keep), bool))
    out["polys"].append(flat.take(keep))


def _gather_whole(rings: ROIRings, uv, ci, r, a) -> FlatPolygons:
    """Flat polygons of ROIs wholly inside photos: their projected rings, as they are."""
    vidx, rec, layout = rings.take(r)
    return layout.with_xy(uv[ci[rec], vidx - a])


def _roi_structure(rings: ROIRings, r: int, arrays: np.ndarray) -> List[List[np.ndarray]]:
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
            positive = (ring_area(r2) > 0) == (sigma > 0)
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
            dense = densify(ring, np.array([0, len(ring)]), step, max_pieces=MAX_SUBDIVISIONS)[0]
            u, v = sg.cal.project_normalised(dense[:, 0], dense[:, 1], distortion)
            rs.append(np.column_stack([u, v]))
        pixel_polys.append(rs)
    return clip_convex(orient(pixel_polys), frame)


def _image_orientation(g: ROIGeometry, r: int, Xr: np.ndarray, cam) -> int:
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
    s = ring_area(q)
    return 1 if s > 0 else (-1 if s < 0 else 0)
