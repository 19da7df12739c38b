"""Decoding a photo file as stored: the one decoder of raw photos.

Photos are decoded with tifffile (TIFF: 16-bit and multiband, e.g. multispectral) or imagecodecs
(JPEG, PNG and the rest), as stored: pixel (0, 0) is the first stored row and column (the EXIF
orientation tag is not applied, as Metashape and Pix4D do not apply it to their pixel
coordinates either).
"""
import os

import numpy as np

from ..errors import InputError


def read_photo(path) -> np.ndarray:
    """Decode a photo to (rows, cols) or (rows, cols, bands); :class:`InputError` naming the
    file when it cannot be decoded."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(4)
        if head[:2] == b"\xff\xd8":                      # JPEG: libjpeg-turbo, straight
            import imagecodecs
            with open(path, "rb") as fh:
                arr = imagecodecs.jpeg_decode(fh.read())
        elif head[:4] in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
            import tifffile
            with tifffile.TiffFile(path) as tif:
                page = tif.pages.first
                arr = page.asarray()
                if page.planarconfig == 2 and arr.ndim == 3:   # separate planes → bands last
                    arr = np.moveaxis(arr, 0, -1)
        else:
            import imagecodecs
            arr = imagecodecs.imread(path)
    except (OSError, ValueError, RuntimeError, Exception) as exc:  # codec errors vary
        if isinstance(exc, MemoryError):
            raise
        raise InputError(f"The photo {path} cannot be decoded ({type(exc).__name__}: "
                         f"{str(exc)[:120]}).") from None
    arr = np.asarray(arr)
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = arr[..., 0]
    if arr.ndim not in (2, 3):
        raise InputError(f"The photo {path} has {arr.ndim} dimensions; expected an image.")
    return arr
