"""What hides an object in a photo, not counting the object itself: the training-set rule.

**Rule.** Sample points are spread over the object's outline as in :mod:`.occlusion` (about
``samples`` cells of a regular grid, in the DSM's CRS) and placed on the object's **top
surface**: all at the height of the highest DSM point among a denser grid of the object (four
times ``samples``; bilinear between pixel centres). A sample inside the photo's frame is
*hidden* when its line of sight from the camera centre meets the DSM surface more than
``tolerance`` (default one DSM pixel) before it, at a point **outside** the object's outline. A
hit inside the outline is the object's own canopy (tall rows hiding the soil between them, a
plant's own leaves) and does not count. ``hidden`` share = hidden / in-frame samples.

So a plot that is in the frame and hidden by nothing outside itself is 0 % hidden, whatever its
rows hide of its own soil; a neighbour, a tree or a building in front of it hides it. The top
surface is flat: on ground that slopes inside one object the low end is sampled above its canopy
(a plot of a few metres on a slope of a few per cent: centimetres). Lines of sight that meet
DSM nodata before their sample count as not hidden (reported).
"""
from typing import List, Tuple

import numpy as np

from ..crs import as_crs, same_crs, transform_xy
from ..geometry import points_in_rings
from ..progress import as_progress
from ..raster import HIT, NODATA, as_dsm, first_hits
from ..reconstruction import INSIDE
from .occlusion import RAYS_AT_ONCE, _tolerance, sample_grid


def outside_hidden_fractions(rois, rec_roi: np.ndarray, cams_of_rec: np.ndarray, recon, cams,
                             dsm, samples: int = 256, tolerance=None,
                             progress=None) -> Tuple[np.ndarray, List[str]]:
    """Share of each record (ROI ``rec_roi[i]`` in camera ``cams[cams_of_rec[i]]``) hidden by the
    surface outside the ROI (the module's rule); NaN where no sample is in the frame. Returns
    (fractions, notes)."""
    prog = as_progress(progress)
    dsm = as_dsm(dsm)
    surface = dsm.ray_surface()
    dcrs = dsm.crs
    rcrs = as_crs(rois.crs)
    notes: List[str] = []
    n_rec = len(rec_roi)
    if not n_rec:
        return np.full(0, np.nan), notes
    tol = _tolerance(recon, dsm.tif, dcrs) if tolerance is None else float(tolerance)
    C = np.array([c.C for c in cams])
    # samples of each ROI on its top surface, in the DSM's CRS and in the model frame
    need = np.unique(rec_roi)
    rings_of, grids, dense = {}, [], []
    box = np.full((len(rois), 4), np.nan)        # x0, y0, x1, y1 of each ROI, in the DSM's CRS
    for r in need:
        r = int(r)
        rings = rois[r].rings
        if dcrs is not None and rcrs is not None and not same_crs(rcrs, dcrs):
            rings = [transform_xy(rcrs, dcrs, ring) for ring in rings]
        rings_of[r] = rings
        allxy = np.concatenate(rings)
        box[r] = np.concatenate([allxy.min(axis=0), allxy.max(axis=0)])
        grids.append(sample_grid(rings, samples))
        dense.append(sample_grid(rings, 4 * samples))
    # every height in one DSM read: the samples and the denser grid, per ROI
    both = [np.concatenate([g, d]) for g, d in zip(grids, dense)]
    allxy = np.concatenate(both) if both else np.zeros((0, 2))
    z = dsm.heights(allxy[:, 0], allxy[:, 1]) if len(allxy) else np.zeros(0)
    cut = np.cumsum([0] + [len(b) for b in both])
    starts, xyz_all, no_dsm, k = {}, [], [], 0
    for n, r in enumerate(need):
        r = int(r)
        zr = z[cut[n]:cut[n + 1]]
        pts = grids[n]
        if not np.isfinite(zr).any():
            no_dsm.append(rois[r].name)
            pts = pts[:0]
        xyz_all.append(np.column_stack([pts, np.full(len(pts), np.nanmax(zr) if len(pts) else 0.0)]))
        starts[r] = (k, k + len(pts))
        k += len(pts)
    xyz = np.concatenate(xyz_all) if xyz_all else np.zeros((0, 3))
    model = recon.to_model(xyz, dcrs) if len(xyz) else np.zeros((0, 3))
    prog.set(10)
    n_in = np.zeros(n_rec, np.int64)
    hidden = np.zeros(n_rec, np.int64)
    undecided = 0
    pending: List[Tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    queued = 0

    def cast():
        nonlocal undecided, queued
        owner = np.concatenate([p[0] for p in pending])
        target = np.concatenate([p[1] for p in pending])
        cam_of = np.concatenate([p[2] for p in pending])
        pending.clear()
        queued = 0
        o = C[cam_of]
        d = model[target] - o
        dist = np.linalg.norm(d, axis=1)
        hits = first_hits(surface, recon.frame, o, d / dist[:, None],
                          max_distance=np.maximum(dist - tol, 0.0), is_cancelled=prog.cancelled)
        undecided += int((hits.status == NODATA).sum())
        hit = np.flatnonzero(hits.status == HIT)
        if not len(hit):
            return
        roi_of = rec_roi[owner[hit]]
        p = hits.xyz[hit]
        b = box[roi_of]                           # outside the object's box: outside it
        near = (p[:, 0] >= b[:, 0]) & (p[:, 0] <= b[:, 2]) & (p[:, 1] >= b[:, 1]) & (p[:, 1] <= b[:, 3])
        np.add.at(hidden, owner[hit[~near]], 1)
        for r in np.unique(roi_of[near]):         # a hit inside the object's outline: itself
            sel = hit[near][roi_of[near] == r]
            q = hits.xyz[sel]
            outside = ~points_in_rings(q[:, 0], q[:, 1], rings_of[int(r)])
            np.add.at(hidden, owner[sel[outside]], 1)

    order = np.argsort(cams_of_rec, kind="stable")
    groups = np.split(order, np.flatnonzero(np.diff(cams_of_rec[order])) + 1)
    for g_i, grp in enumerate(groups):
        prog.check()
        cam_i = int(cams_of_rec[grp[0]])
        idx = [np.arange(*starts[int(rec_roi[i])]) for i in grp]
        owner = np.concatenate([np.full(len(a), i) for a, i in zip(idx, grp)])
        idx = np.concatenate(idx)
        if len(idx):
            seen = recon.project_points(xyz[idx], dcrs, cameras=[cams[cam_i]]).status[0] == INSIDE
            np.add.at(n_in, owner[seen], 1)
            pending.append((owner[seen], idx[seen], np.full(int(seen.sum()), cam_i)))
            queued += int(seen.sum())
            if queued >= RAYS_AT_ONCE:
                cast()
        prog.set(10 + 90.0 * (g_i + 1) / len(groups))
    if pending:
        cast()
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(n_in > 0, hidden / np.maximum(n_in, 1), np.nan)
    if no_dsm:
        notes.append(f"hiding not tested for {len(no_dsm)} object(s) without DSM data inside: "
                     + ", ".join(map(repr, no_dsm[:10])) + (" …" if len(no_dsm) > 10 else ""))
    if undecided:
        notes.append(f"{undecided} line(s) of sight crossed DSM nodata before their sample point "
                     "and were counted as not hidden")
    return out, notes
