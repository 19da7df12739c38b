"""Per-ROI 3-D geometry in the model frame: area centroid, bounding sphere, best-fit plane,
horizontal area and "up"; and the candidate photos of each ROI (its bounding sphere meets the
cone that holds the photo's frame)."""
from dataclasses import dataclass

import numpy as np

from .roi_rings import ROIRings


@dataclass
class ROIGeometry:
    centre: np.ndarray     # (n, 3) model-frame area centroid on the ROI's plane
    radius: np.ndarray     # (n,) bounding-sphere radius about ``centre``
    plane: np.ndarray      # (n, 3) z = a + b·x + c·y in the model frame
    area: np.ndarray       # (n,) horizontal area in the model frame
    up: np.ndarray         # (n, 3) "up" at the centre


def roi_geometry(rings: ROIRings, X: np.ndarray, n: int, recon) -> ROIGeometry:
    v0 = rings.ring_offsets[rings.roi_rings[:-1]]
    v1 = rings.ring_offsets[rings.roi_rings[1:]]
    roi_of_v = np.repeat(np.arange(n), v1 - v0)
    # horizontal areas and centroids (model xy), per ring then per ROI
    area, cen = rings.flat(X[:, :2]).areas_centroids()
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
    return ROIGeometry(centre, radius, np.column_stack([a, b, c]), np.abs(area),
                       recon.frame.up(centre))


def candidate_pairs(g: ROIGeometry, cams, geo) -> np.ndarray:
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
