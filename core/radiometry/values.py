"""Photo pixels as physical values: the record every radiometric reader returns.

:class:`PhotoValues` is what a photo becomes once a vendor's radiometric model is applied
(thermal: °C; multispectral: reflectance). Tools that read photo pixels take these arrays in
place of the stored digital numbers.
"""
from dataclasses import dataclass
from typing import Tuple

import numpy as np

__all__ = ["PhotoValues"]


@dataclass
class PhotoValues:
    """One photo in physical units.

    Attributes
    ----------
    values : numpy.ndarray
        float32, (rows, cols) or (rows, cols, bands), in ``unit``; pixel (0, 0) is the first
        stored row and column (conventions: ``docs/background/conventions.md``).
    valid : numpy.ndarray
        bool, (rows, cols): False where a value must not be used (saturated pixels).
    unit : str
        the unit of ``values``, e.g. ``"reflectance"`` (a fraction, 1 = a white Lambertian
        surface).
    bands : tuple of str
        the band names, one per band of ``values``, as the photo's band tag gives them.
    note : str
        what was applied, in words (the vendor model, the irradiance source, the masks).
    """

    values: np.ndarray
    valid: np.ndarray
    unit: str
    bands: Tuple[str, ...]
    note: str
