"""Visible fractions of clipped records: the ground area of a record's pixel polygons, cast back
as rays onto the ROI's best-fit plane, over the ROI's area on that plane."""
import numpy as np

from ..geometry import FlatPolygons, densify
from ..ragged import run_of
from .roi_geometry import ROIGeometry
from .roi_rings import ROIRings
from .sensor_geometry import MAX_SUBDIVISIONS


def visible_fractions(flat: FlatPolygons, roi_i, cam_i, rings: ROIRings, X, g: ROIGeometry,
                      cams, geo, recon, distortion) -> np.ndarray:
    """Per clipped record: the ground area of its pixel polygons (densified, cast as rays onto
    the ROI's best-fit plane) over the ROI's area on that plane (its vertices cast from the
    camera centre onto the plane). Vectorised over records; one ray call per photo."""
    k = len(flat)
    step = np.array([geo[cams[j].sensor_id].segment_px for j in cam_i])
    dense = _densify_flat(flat, np.where(np.isfinite(step), step, np.inf))
    rec_of_v = run_of(dense.record_rings)[run_of(dense.ring_offsets)]
    dirs = np.empty((len(dense.xy), 3))
    cam_of_v = cam_i[rec_of_v]
    for j in np.unique(cam_i):
        sel = cam_of_v == j
        _, dirs[sel] = recon.pixel_to_ray(cams[j], dense.xy[sel], distortion)
    C = np.array([cams[j].C for j in cam_i])
    ground, ok = _on_plane(C[rec_of_v], dirs, g.plane[roi_i[rec_of_v]])
    area_vis, _ = dense.with_xy(ground).areas_centroids()
    bad = np.bincount(rec_of_v, ~ok, minlength=k) > 0
    # the whole ROI on the same plane, cast from the same camera centre
    vidx, rec_of_rv, layout = rings.take(roi_i)
    full, ok_full = _on_plane(C[rec_of_rv], X[vidx] - C[rec_of_rv], g.plane[roi_i[rec_of_rv]])
    area_full, _ = layout.with_xy(full).areas_centroids()
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
    xy, offs, _ = densify(flat.xy, flat.ring_offsets, step[run_of(flat.record_rings)],
                          max_pieces=MAX_SUBDIVISIONS)
    return FlatPolygons(xy, offs, flat.ring_polygon, flat.ring_hole, flat.record_rings)
