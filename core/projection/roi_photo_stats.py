"""Plot statistics of ROIs from the raw photos in one call: back-projection (or one given),
then the measurement of every view (what *Plot statistics from photos* runs)."""
from ..errors import ROIError
from ..progress import as_progress
from .backward import back_project
from .photo_stats import photo_statistics
from .stats_table import PhotoStatistics


def roi_photo_statistics(rois, recon, photos=None, *, backprojection=None, heights=None,
                         distortion: bool = True, occlusion_dsm=None, occlusion: bool = True,
                         progress=None, is_cancelled=None, **measure) -> PhotoStatistics:
    """:func:`photo_statistics` of ``rois`` in the photos of ``recon``.

    The ROI × photo pairs are ``backprojection`` (a :class:`BackProjection`, e.g. read back from
    a layer) or, when None, :func:`back_project` with ``heights``, ``distortion`` and the
    occlusion test on ``occlusion_dsm`` (every pair kept, ``min_visible=0``: the measurement
    decides); its notes come back as ``warnings``. ``occlusion``: leave the pixels hidden on
    ``occlusion_dsm`` out of the statistics. ``measure``: the other arguments of
    :func:`photo_statistics` (bands, statistics, indices, …). Progress: 5–30 % projecting,
    30–95 % measuring. Raises :class:`ROIError` when no ROI is seen by any photo.
    """
    prog = as_progress(progress, is_cancelled)
    result, warnings = backprojection, []
    if result is None:
        result = back_project(rois, recon, heights=heights, distortion=distortion,
                              occlusion_dsm=occlusion_dsm, min_visible=0.0,
                              progress=prog.sub(5, 30))
        warnings = list(result.notes)
    if not len(result):
        raise ROIError("No ROI is seen by any photo: check that the ROIs lie in the surveyed "
                       "area and in the right CRS.")
    stats = photo_statistics(result, photos, recon=recon, rois=rois, distortion=distortion,
                             occlusion_dsm=occlusion_dsm if occlusion else None,
                             progress=prog.sub(30, 95), **measure)
    stats.warnings = warnings + stats.warnings
    return stats
