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
from typing import List, Optional, Sequence

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError, ROIError
from ..progress import as_progress
from ..roi import ROISet
from .densify import densify_rings
from .height_sources import height_source
from .occlusion import occluded_fractions
from .ranking import rank_records
from .record_clip import project_and_clip
from .result import BackProjection
from .roi_geometry import candidate_pairs, roi_geometry
from .roi_rings import ring_arrays, vertex_heights
from .sensor_geometry import SensorGeometry


@renamed_parameters(max_images="max_views")
def back_project(rois: ROISet, recon, *, heights, cameras: Optional[Sequence] = None,
                 distortion: bool = True, clip: bool = True, occlusion_dsm=None,
                 min_visible: float = 0.5, max_views: int = 0,
                 densify_tolerance: float = 0.1, occlusion_samples: int = 256,
                 occlusion_tolerance: Optional[float] = None,
                 progress=None, is_cancelled=None) -> BackProjection:
    """Project ROIs into the raw photos of a photogrammetry project.

    Pixels follow the [Conventions](../background/conventions.md); each ROI × photo record is
    ranked by its score (view angle, ground resolution, distance from the photo centre,
    visible share).

    Parameters
    ----------
    rois : ROISet
        The ROIs, in any CRS the project can be related to (a local project takes ROIs without
        a CRS as local coordinates).
    recon : Reconstruction
        The opened project (:func:`open_reconstruction`).
    heights : str, float, DSM or PerROIHeights
        The vertex heights (:mod:`.height_sources`): ``"geometry"`` (the ROIs' Z), one number
        (the project's vertical reference), a :class:`~core.raster.DSM` sampled at every
        vertex, or :class:`PerROIHeights`.
    cameras : sequence of str, optional
        Camera labels to use (default: every aligned, enabled camera).
    distortion : bool
        False for photos the photogrammetry software has undistorted.
    clip : bool
        True: clip each ROI to the photo frame; False: keep only photos that hold the whole ROI.
    occlusion_dsm : DSM, GeoTiff or path, optional
        A DSM to test lines of sight against (:mod:`.occlusion`); None: no occlusion test.
    min_visible : float
        Photos whose visible, unoccluded share of the ROI (0–1) is below this are dropped (and
        counted).
    max_views : int
        Keep the best k photos per ROI (0: all).
    densify_tolerance : float
        Edges are densified until the projected curve is within this many pixels of the
        straight edge.
    occlusion_samples : int
        About this many sample points per ROI for the occlusion test.
    occlusion_tolerance : float, optional
        A surface closer than this to a sample does not hide it (model units; default one DSM
        pixel).
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    BackProjection
        One record per ROI × photo (rings in photo pixels, rank, score, view angle, GSD,
        visible and occluded share), with counts of the photos dropped and the run's notes.
    """
    if not 0.0 <= float(min_visible) <= 1.0:
        raise EasyIDPError(f"min_visible must be between 0 and 1, not {min_visible}.")
    if int(max_views) < 0:
        raise EasyIDPError(f"max_views must be 0 (all) or more, not {max_views}.")
    if not densify_tolerance > 0:
        raise EasyIDPError(f"densify_tolerance must be positive, not {densify_tolerance}.")
    prog = as_progress(progress, is_cancelled)
    source = height_source(heights)
    rois = _checked_rois(rois, recon)
    cams = _cameras(recon, cameras)
    crs = rois.crs
    _check_transform(rois, recon)

    rings = ring_arrays(rois)
    rings.z = vertex_heights(source, rois, rings, rings.xy, crs, ring_index=None)
    prog.set(2)
    sensors = {c.sensor_id: recon.calibrated_sensor(c) for c in cams}
    geo = {sid: SensorGeometry(s, distortion, densify_tolerance) for sid, s in sensors.items()}
    rings = densify_rings(rings, rois, source, recon, cams, geo, distortion, prog.sub(2, 15))
    prog.check()

    X = recon.to_model(np.column_stack([rings.xy, rings.z]), crs)   # model frame, once
    per_roi = roi_geometry(rings, X, len(rois), recon)
    cand = candidate_pairs(per_roi, cams, geo)                              # (n_rois, m) bool

    recs = project_and_clip(rois, rings, X, per_roi, cand, recon, cams, geo, distortion, clip,
                             prog.sub(15, 75))
    occluded = np.full(len(recs["roi"]), np.nan)
    notes: List[str] = []
    if occlusion_dsm is not None and len(recs["roi"]):
        occluded, occ_notes = occluded_fractions(
            rois, recs["roi"], recs["cam"], recon, cams, occlusion_dsm, occlusion_samples,
            occlusion_tolerance, prog.sub(75, 95))
        notes += occ_notes
    prog.set(95)
    result = rank_records(rois, recon, cams, geo, per_roi, recs, occluded, float(min_visible),
                     int(max_views), clip)
    result.settings = {"heights": source.describe(), "distortion": bool(distortion),
                       "clip": bool(clip), "occlusion": occlusion_dsm is not None,
                       "min_visible": float(min_visible), "max_images": int(max_views),
                       "densify_tolerance_px": float(densify_tolerance),
                       "segment_px": {s.label: g.segment_px for s, g in
                                      ((sensors[k], geo[k]) for k in geo)},
                       "vertices": {"input": int(rings.original.sum()), "densified": len(rings.xy)}}
    result.notes = list(recon.notes) + notes
    result.uncertainty_px = {c.label: recon.uncertainty_px[c.label] for c in cams
                             if c.label in recon.uncertainty_px}
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
