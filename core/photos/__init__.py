"""Raw photos as files: finding them, reading their headers and tags, decoding their pixels.

* :mod:`.lookup`: a photo's key (:func:`photo_key`, the file name, any case, photo extension
  dropped) and :func:`resolve_photos`, the one lookup of a project's photos on disk
  (:class:`PhotoFiles`: a photos folder with its subfolders);
* :mod:`.headers`: what a header says without decoding the pixels (Pillow for JPEG and PNG,
  tifffile for TIFF): :func:`photo_size`, :func:`jpeg_facts` (EXIF Make and Orientation, DJI
  thermal R-JPEGs) and :func:`photo_notes`;
* :mod:`.tags`: a camera's EXIF and XMP tags (:func:`read_photo_tags`: GPS, gimbal, focal
  length; camera JPEGs, camera TIFFs and GDAL-written TIFFs, tags 42112 and 700);
* :mod:`.band_tags`: the vendors' band tags of multispectral TIFFs (:func:`read_band_tags`:
  MicaSense, DJI);
* :mod:`.decode`: :func:`read_photo`, the one decoder of raw photos (as stored), and
  :class:`DecodedPhotos`, the one pass over them every consumer of pixels shares.

Physical units (temperature, reflectance) are not here: they are :mod:`..radiometry`'s, which
decodes with :func:`read_photo` and gives :class:`DecodedPhotos` its ``decode``.
"""
from .band_tags import BandTags, read_band_tags, xmp_properties
from .decode import DecodedPhotos, check_size, read_photo, read_raw_band
from .headers import (ORIENTATION_NOTE, THERMAL_NOTE, jpeg_facts, open_header, photo_notes,
                      photo_size, scale_to)
from .lookup import (PHOTO_EXTENSIONS, PhotoFiles, file_name, is_windows_path, photo_key,
                     photo_stems, resolve_photos)
from .tags import CAMERA_NS, DJI, SENSEFLY, XMP_NS, PhotoTags, read_photo_tags

__all__ = ["PHOTO_EXTENSIONS", "PhotoFiles", "file_name", "is_windows_path", "photo_key",
           "photo_stems", "resolve_photos", "photo_size", "scale_to", "jpeg_facts",
           "photo_notes", "open_header", "THERMAL_NOTE", "ORIENTATION_NOTE", "PhotoTags",
           "read_photo_tags", "DJI", "CAMERA_NS", "SENSEFLY", "XMP_NS", "BandTags",
           "read_band_tags", "xmp_properties", "read_photo", "read_raw_band", "DecodedPhotos",
           "check_size"]
