"""The core's errors in the user's language.

An error of the engine that carries a message id (``core.errors.MESSAGES``: a missing input, no
CRS, nothing to do) is shown translated; every other one in the engine's English. The English
texts here are the core's, word for word (tests/qgis/test_i18n.py keeps them so).
"""
from qgis.PyQt.QtCore import QCoreApplication


def tr(text: str) -> str:
    return QCoreApplication.translate("EasyIDP", text)


def texts() -> dict:
    """{message id: the message, translated}; built when asked (the translator is installed
    after import). Without a translator, the core's English (``core.errors.MESSAGES``)."""
    return {
        "roi_file_not_found": tr("ROI file not found: {path}"),
        "project_not_found": tr("{path}: file not found."),
        "rois_no_crs": tr("The ROIs have no CRS: set one on the layer before using it."),
        "rois_no_features": tr("The ROI layer has no features."),
        "rois_miss_raster": tr(
            "None of the {count} ROIs overlaps the raster {raster}. Raster extent "
            "{raster_extent}, ROI extent {roi_extent} (both in {crs}). Check that the ROI layer "
            "and the raster cover the same area and that the ROI layer's CRS is set correctly."),
        "no_roi_seen": tr("No ROI is seen by any photo: check that the ROIs lie in the surveyed "
                          "area and in the right CRS."),
        "nothing_to_write": tr("Nothing to write: give a crops folder, a previews folder or "
                               "both."),
    }


def error_message(exc) -> str:
    """The message of a core error ``exc``, translated when it has a message id."""
    text = texts().get(getattr(exc, "key", None))
    if text is None:
        return str(exc)
    try:
        return text.format(**exc.fields)
    except (KeyError, IndexError, ValueError):   # a translation that lost a placeholder
        return str(exc)
