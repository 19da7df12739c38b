"""Raw photos in physical units: one place where a photo's pixels become physical values.

Multispectral band files become reflectance (:func:`reflectance_values`, MicaSense and DJI);
each reader returns a :class:`PhotoValues`. Band files of one capture are grouped by
:func:`group_captures`.
"""
from .multispectral import (SUPPORTED_CAMERAS, Capture, ReflectanceOptions, band_key,
                            group_captures, reflectance_values)
from .sun import sun_position
from .values import PhotoValues

__all__ = ["PhotoValues", "reflectance_values", "ReflectanceOptions", "Capture", "group_captures",
           "band_key", "SUPPORTED_CAMERAS", "sun_position"]
