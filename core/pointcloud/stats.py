"""ROI heights and canopy summaries from a point cloud (heights in the cloud's z units/reference).

:func:`cloud_roi_heights` speaks the vocabulary of the DSM version (:mod:`..height_statistics`: ``mode``,
``statistic``, ``percentile``, a :class:`~..height_statistics.HeightResult` aligned with the ROI order):
``polygon`` (EasyIDP: ``face``): one value per ROI from the points inside it; ``vertex``
(EasyIDP: ``point``): one value per vertex of every ring, from the points within ``buffer``
(xy distance, cloud CRS units) of the vertex, or with ``buffer=0`` the z of the nearest point
in xy.
"""
from pathlib import Path
from typing import Callable, Dict, List, Optional, Sequence, Union

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError, InputError
from ..height_statistics import HeightResult, check_heights_args, statistic_of, vertex_result
from ..progress import as_progress
from ..roi import ROISet
from .cloud import PointCloud
from .crop import as_cloud, cloud_name, crop_indices, rois_in_cloud_crs
from .index import one_pass

Ground = Union[None, float, np.ndarray, Callable[[np.ndarray, np.ndarray], np.ndarray]]


@renamed_parameters(crs="source_crs")
def cloud_roi_heights(cloud: Union[PointCloud, str, Path], rois: ROISet, mode: str = "polygon",
                      statistic: str = "mean", percentile: float = 50.0, buffer: float = 0.0,
                      z_min: Optional[float] = None, z_max: Optional[float] = None,
                      source_crs=None, progress=None, is_cancelled=None) -> HeightResult:
    """Heights of ROIs from the cloud's z (in the cloud's z units and vertical reference).

    Parameters
    ----------
    cloud : PointCloud or path
        The point cloud, or a .las/.laz/.ply path.
    rois : ROISet
        The ROIs.
    mode : {"polygon", "vertex"}
        ``"polygon"`` (EasyIDP: ``face``): one value per ROI from the points inside it;
        ``"vertex"`` (EasyIDP: ``point``): one value per vertex of every ring, from the points
        within ``buffer`` of the vertex, or with ``buffer=0`` the z of the nearest point in xy.
    statistic : str
        ``mean``, ``median``, ``min``, ``max``, ``std``, ``percentile``, ``pmin`` or ``pmax``
        (:mod:`core.height_statistics`).
    percentile : float
        The percentile (0–100) for ``statistic="percentile"``.
    buffer : float
        xy distance in the cloud CRS's units (vertex mode only).
    z_min, z_max : float, optional
        Only the points in this Z range count.
    source_crs : CRS, optional
        The cloud's CRS when it is a path (required for PLY; overrides the LAS record).
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    HeightResult
        Values in the ROI order; NaN where no point counts, with the reason in ``missing``.
    """
    mode = check_heights_args(mode, statistic, percentile)
    prog = as_progress(progress, is_cancelled)
    cloud = as_cloud(cloud, source_crs)
    if mode == "polygon":
        if buffer:
            raise EasyIDPError("buffer applies to the vertex mode only; buffer the ROIs first "
                               "for a polygon statistic over a larger area.")
        idx, _, _ = crop_indices(cloud, rois, z_min, z_max, prog)
        values = [statistic_of(_z(cloud, ii), statistic, percentile) for ii in idx]
        return HeightResult("polygon", values, {i: "no point of the cloud inside it"
                                                for i, v in enumerate(values) if np.isnan(v)})
    if buffer < 0:
        raise EasyIDPError(f"buffer must be ≥ 0 (got {buffer}).")
    local = rois_in_cloud_crs(cloud, rois)
    allv = np.concatenate([r for roi in local for r in roi.rings])
    vz = (_disc_stat(cloud, allv, buffer, statistic, percentile, (z_min, z_max), prog)
          if buffer > 0 else _nearest_z(cloud, allv, (z_min, z_max), prog))
    return vertex_result(vz, local, "no point of the cloud near some vertices")


def _z(cloud: PointCloud, idx: np.ndarray) -> np.ndarray:
    return cloud.take(idx).xyz[:, 2] if len(idx) else np.zeros(0)


def _discs(cloud, v, r, z_range, prog):
    boxes = np.column_stack([v[:, 0] - r, v[:, 1] - r, v[:, 0] + r, v[:, 1] + r])
    test = lambda k, x, y: (x - v[k, 0]) ** 2 + (y - v[k, 1]) ** 2 <= r * r  # noqa: E731
    return one_pass(cloud, boxes, test, z_range, prog)


def _disc_stat(cloud, v, r, statistic, percentile, z_range, prog) -> np.ndarray:
    idx, _ = _discs(cloud, v, float(r), z_range, prog)
    return np.array([statistic_of(_z(cloud, ii), statistic, percentile) for ii in idx])


def _nearest_z(cloud, v, z_range, prog) -> np.ndarray:
    """z of the nearest point (xy) to each vertex: search discs growing ×4 until found."""
    out = np.full(len(v), np.nan)
    if not len(cloud):
        return out
    lo, hi = cloud.bounds()
    span = float(max(hi[0] - lo[0], hi[1] - lo[1], 1e-9))
    r = 3.0 * np.sqrt(max((hi[0] - lo[0]) * (hi[1] - lo[1]), span * 1e-9) / len(cloud))
    # every point lies within ``far`` of every vertex (distance to the farthest extent corner)
    far = float(np.hypot(np.maximum(np.abs(v[:, 0] - lo[0]), np.abs(v[:, 0] - hi[0])),
                         np.maximum(np.abs(v[:, 1] - lo[1]), np.abs(v[:, 1] - hi[1]))).max()) * 1.001
    r = min(r, far)
    todo = np.arange(len(v))
    while len(todo):
        idx, _ = _discs(cloud, v[todo], r, z_range, prog)
        found = np.zeros(len(todo), bool)
        for n, (j, ii) in enumerate(zip(todo, idx)):
            if len(ii):
                xyz = cloud.take(ii).xyz
                d = (xyz[:, 0] - v[j, 0]) ** 2 + (xyz[:, 1] - v[j, 1]) ** 2
                out[j] = xyz[np.argmin(d), 2]
                found[n] = True
        todo = todo[~found]
        if r >= far:
            break  # no point at any distance: only possible when a Z range keeps none
        r = min(r * 4, far)
    return out


@renamed_parameters(crs="source_crs")
def canopy_summary(cloud: Union[PointCloud, str, Path], rois: ROISet, ground: Ground = None,
                   percentiles: Sequence[float] = (5, 50, 95, 99), ground_percentile: float = 1.0,
                   z_min: Optional[float] = None, z_max: Optional[float] = None, source_crs=None,
                   progress=None, is_cancelled=None) -> List[Dict[str, float]]:
    """Per-ROI point count and height statistics above a ground.

    Parameters
    ----------
    cloud : PointCloud or path
        The point cloud, or a .las/.laz/.ply path.
    rois : ROISet
        The ROIs.
    ground : float, ndarray, callable or None
        A number (z of the ground, cloud z units); an array of one ground z per cloud point; a
        callable ``ground(x, y) -> z`` on arrays in the cloud CRS (e.g. a DTM sampler; NaN = no
        ground there, those points get no height); or None: the ROI's own
        ``ground_percentile``-th percentile of z.
    percentiles : sequence of float
        The height percentiles (0–100) of each row (``h_pNN``).
    ground_percentile : float
        The percentile of an ROI's z taken as its ground when ``ground`` is None.
    z_min, z_max : float, optional
        Only the points in this Z range count.
    source_crs : CRS, optional
        The cloud's CRS when it is a path (required for PLY; overrides the LAS record).
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    list of dict
        One row per ROI, in the ROI order: count, density (points per CRS unit², using the ROI
        area), z_min, z_mean, z_max, ground (mean ground z used), h_mean, h_max and h_pNN for
        each NN in ``percentiles``; NaN values when no point counts.
    """
    prog = as_progress(progress, is_cancelled)
    cloud = as_cloud(cloud, source_crs)
    if isinstance(ground, np.ndarray) and ground.shape != (len(cloud),):
        raise InputError(f"The ground array has shape {ground.shape}, but {cloud_name(cloud)} "
                         f"has {len(cloud)} points: give one ground height per point.")
    for q in list(percentiles) + [ground_percentile]:
        if not 0 <= float(q) <= 100:
            raise EasyIDPError(f"Percentile {q} is outside 0–100.")
    idx, _, rois = crop_indices(cloud, rois, z_min, z_max, prog.sub(0, 80))
    out: List[Dict[str, float]] = []
    for roi, ii in zip(rois, idx):
        prog.check()
        xyz = cloud.take(ii).xyz if len(ii) else np.zeros((0, 3))
        z = xyz[:, 2]
        if ground is None:
            g = np.full(len(z), np.percentile(z, ground_percentile) if len(z) else np.nan)
        elif callable(ground):
            g = np.broadcast_to(np.asarray(ground(xyz[:, 0], xyz[:, 1]), np.float64), z.shape)
        elif isinstance(ground, np.ndarray):
            g = ground[ii].astype(np.float64)
        else:
            g = np.full(len(z), float(ground))
        h = z - g
        h = h[np.isfinite(h)]
        area = roi.area
        row = {"count": len(z), "density": len(z) / area if area > 0 else float("nan"),
               "z_min": statistic_of(z, "min"), "z_mean": statistic_of(z, "mean"),
               "z_max": statistic_of(z, "max"), "ground": statistic_of(g, "mean"),
               "h_mean": statistic_of(h, "mean"), "h_max": statistic_of(h, "max")}
        for q in percentiles:
            row[f"h_p{q:g}"] = statistic_of(h, "percentile", float(q))
        out.append(row)
    prog.set(100)
    return out
