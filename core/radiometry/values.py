"""Photo pixels as physical values: :class:`PhotoValues`, the record every radiometric reader
returns (thermal: °C; multispectral: reflectance; or the values as stored)."""
from dataclasses import dataclass
from typing import Tuple

import numpy as np


@dataclass
class PhotoValues:
    """A photo's pixels in stated units.

    Attributes
    ----------
    values : numpy.ndarray
        float32, (rows, cols) or (rows, cols, bands), in ``unit``; row 0 is the first stored row
        (conventions: ``docs/background/conventions.md``).
    valid : numpy.ndarray
        bool, (rows, cols): False where a pixel cannot be trusted (saturated, outside the
        camera's range, unreadable); those pixels are left out of every statistic, never
        averaged.
    unit : str
        ``"degC"``, ``"reflectance"`` (a fraction, 1 = a white Lambertian surface) or
        ``"stored"`` (the values as the file stores them).
    bands : tuple of str
        one name per band of ``values`` (for multispectral photos, the photo's band tag).
    note : str
        what was applied, in one sentence, for the run's notes.
    """

    values: np.ndarray
    valid: np.ndarray
    unit: str
    bands: Tuple[str, ...]
    note: str = ""

    def __post_init__(self):
        self.values = np.asarray(self.values, dtype=np.float32)
        self.valid = np.asarray(self.valid, dtype=bool)
        if self.valid.shape != self.values.shape[:2]:
            raise ValueError(f"valid has shape {self.valid.shape}, values {self.values.shape}")
        self.bands = tuple(self.bands)
        n = 1 if self.values.ndim == 2 else self.values.shape[2]
        if len(self.bands) != n:
            raise ValueError(f"{len(self.bands)} band names for {n} band(s)")

    def masked(self) -> np.ndarray:
        """``values`` with NaN where a pixel is not valid (a copy only when some are not)."""
        if self.valid.all():
            return self.values
        out = self.values.copy()
        out[~self.valid] = np.nan
        return out
