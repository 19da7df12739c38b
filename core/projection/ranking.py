"""Ranking of the photos of each ROI (:func:`score`) and the :class:`BackProjection` made from
the clipped records."""
import numpy as np

from .result import BackProjection
from .roi_geometry import ROIGeometry


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


def rank_records(rois, recon, cams, geo, g: ROIGeometry, recs, occluded, min_visible,
                 max_images, clip) -> BackProjection:
    """The :class:`BackProjection` of the clipped records ``recs``: scored, ranked per ROI,
    those below ``min_visible`` or beyond ``max_images`` dropped (and counted)."""
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
