"""Decoding raw photos as stored, and the one pass over them that every consumer shares.

Photos are decoded with tifffile (TIFF: 16-bit and multiband, e.g. multispectral) or imagecodecs
(JPEG, PNG and the rest), as stored: pixel (0, 0) is the first stored row and column (the EXIF
orientation tag is not applied, as Metashape and Pix4D do not apply it to their pixel
coordinates either). :func:`read_photo` is the one decoder of raw photos; physical units
(temperature, reflectance) are radiometry's (:func:`..radiometry.read_photo_values`), given to
:class:`DecodedPhotos` as its ``decode``.

:class:`DecodedPhotos` is the one pass over the photos that every consumer of pixels shares
(crops and previews, plot statistics): each photo decoded once, by threads running ahead.
"""
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Optional, Sequence

import numpy as np

from ..errors import InputError
from .headers import JPEG_MAGIC, TIFF_MAGIC, scale_to
from .lookup import file_name


def read_photo(path) -> np.ndarray:
    """Decode a photo to (rows, cols) or (rows, cols, bands); :class:`InputError` naming the
    file when it cannot be decoded."""
    path = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            head = fh.read(4)
        if head[:2] == JPEG_MAGIC:                       # JPEG: libjpeg-turbo, straight
            import imagecodecs
            with open(path, "rb") as fh:
                arr = imagecodecs.jpeg_decode(fh.read())
        elif head[:4] in TIFF_MAGIC:
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


def read_raw_band(path) -> np.ndarray:
    """The stored digital numbers of a single-band photo, (rows, cols), as stored."""
    import tifffile
    try:
        arr = tifffile.imread(os.fspath(path))
    except (OSError, ValueError, tifffile.TiffFileError) as exc:
        raise InputError(f"{path}: its pixels cannot be decoded ({exc})") from None
    if arr.ndim != 2:
        raise InputError(f"{path}: {arr.shape} pixels, not one band; a multispectral band file "
                         f"holds one band (give the camera's band files, not a stacked image)")
    return arr


def check_size(arr: np.ndarray, width: int, height: int, path) -> Optional[str]:
    """None if the decoded photo has the camera's size, else why it is not usable: another
    aspect ratio (not the photo the project was built from), or a resized copy that was not
    there when the project was opened (``open_reconstruction`` scales the calibration of the
    resized photos it finds, :func:`..reconstruction.model.fit_sensors_to_photos`)."""
    if arr.shape[1] == width and arr.shape[0] == height:
        return None
    size = f"{file_name(os.fspath(path))} is {arr.shape[1]}×{arr.shape[0]} px but the camera's " \
           f"sensor is {width}×{height}"
    if scale_to((width, height), (arr.shape[1], arr.shape[0])) is None:
        return f"{size}, another aspect ratio: not the photo the project was built from"
    return (f"{size}: a resized copy, found only now; put the photos where the project finds "
            "them (its calibration is then scaled to them when it is opened)")


class DecodedPhotos:
    """Each photo decoded **once**, in order, by a pool of threads running ``workers`` photos
    ahead of the consumer (at most ``workers + 1`` decoded photos in memory)::

        with DecodedPhotos(paths, sizes) as photos:
            for k, img, why in photos:      # img None: why it cannot be used

    ``paths[k]``: the file (None: unavailable, ``why`` given by ``missing[k]``); ``sizes[k]``:
    (width, height) the camera expects, checked (:func:`check_size`). Leaving the ``with``
    block (also by an error or a cancel) cancels the decodes not started and waits for the
    running ones. ``decode``: path → array (None: :func:`read_photo`, as stored) or
    :class:`..radiometry.PhotoValues` (its ``values`` are size-checked).
    """

    def __init__(self, paths: Sequence[Optional[str]], sizes, workers: Optional[int] = None,
                 missing: Optional[Sequence[str]] = None, decode=None):
        self.paths = list(paths)
        self.sizes = [(int(w), int(h)) for w, h in sizes]
        self.missing = list(missing) if missing is not None else [""] * len(self.paths)
        self.workers = max(1, workers or min(4, os.cpu_count() or 1))
        self._pool = None
        self._ahead = {}
        self.decode = decode

    def __enter__(self) -> "DecodedPhotos":
        self._pool = ThreadPoolExecutor(self.workers, thread_name_prefix="easyidp-decode")
        return self

    def __exit__(self, *exc) -> None:
        for fut in self._ahead.values():
            fut.cancel()
        self._ahead.clear()
        self._pool.shutdown(wait=True)

    def _submit(self, k: int) -> None:
        if k < len(self.paths) and k not in self._ahead and self.paths[k] is not None:
            self._ahead[k] = self._pool.submit(self.decode or read_photo, self.paths[k])

    def __iter__(self):
        for k in range(min(self.workers + 1, len(self.paths))):
            self._submit(k)
        for k, path in enumerate(self.paths):
            self._submit(k)
            fut = self._ahead.pop(k, None)
            self._submit(k + self.workers + 1)
            if fut is None:
                yield k, None, self.missing[k] or "not available"
                continue
            try:
                img = fut.result()
            except InputError as exc:
                yield k, None, str(exc)
                continue
            why = check_size(getattr(img, "values", img), *self.sizes[k], path)
            if why:
                yield k, None, why
                continue
            yield k, img, ""
            del img
