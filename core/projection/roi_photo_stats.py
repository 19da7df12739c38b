"""Plot statistics of ROIs from the raw photos in one call: back-projection (or one given),
then the measurement of every view (what *Plot statistics from photos* runs)."""
from ..deprecation import renamed_parameters
from ..errors import ROIError
from ..progress import as_progress
from .backward import back_project
from .photo_stats import photo_statistics
from .stats_table import PhotoStatistics


@renamed_parameters(photos="photos_folder")
def roi_photo_statistics(rois, recon, photos_folder=None, *, backprojection=None, heights=None,
                         distortion: bool = True, occlusion_dsm=None, occlusion: bool = True,
                         progress=None, is_cancelled=None, **measure) -> PhotoStatistics:
    """:func:`photo_statistics` of ``rois`` in the photos of ``recon``.

    Progress: 5–30 % projecting, 30–95 % measuring.

    Parameters
    ----------
    rois : ROISet
        The ROIs.
    recon : Reconstruction
        The opened project.
    photos_folder : str or path, optional
        The folder the photos are in now, when they moved (matched by file name).
    backprojection : BackProjection, optional
        The ROI × photo pairs (e.g. read back from a layer); when None, :func:`back_project`
        with ``heights``, ``distortion`` and the occlusion test on ``occlusion_dsm`` (every pair
        kept, ``min_visible=0``: the measurement decides); its notes come back as
        ``warnings``.
    heights : str, float, DSM or PerROIHeights, optional
        The vertex heights for :func:`back_project` (:mod:`.height_sources`).
    distortion : bool
        False for photos undistorted by the photogrammetry software.
    occlusion_dsm : DSM, GeoTiff or path, optional
        A DSM to test lines of sight against.
    occlusion : bool
        Leave the pixels hidden on ``occlusion_dsm`` out of the statistics.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    **measure
        The other arguments of :func:`photo_statistics` (bands, statistics, indices, …).

    Returns
    -------
    PhotoStatistics
        One row per ROI, with every view's measurements.

    Raises
    ------
    ROIError
        When no ROI is seen by any photo.
    """
    prog = as_progress(progress, is_cancelled)
    result, warnings = backprojection, []
    if result is None:
        result = back_project(rois, recon, heights=heights, distortion=distortion,
                              occlusion_dsm=occlusion_dsm, min_visible=0.0,
                              progress=prog.sub(5, 30))
        warnings = list(result.notes)
    if not len(result):
        raise ROIError.of("no_roi_seen")
    stats = photo_statistics(result, photos_folder, recon=recon, rois=rois, distortion=distortion,
                             occlusion_dsm=occlusion_dsm if occlusion else None,
                             progress=prog.sub(30, 95), **measure)
    stats.warnings = warnings + stats.warnings
    return stats
