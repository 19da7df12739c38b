"""What a raw photo's header says, read without decoding its pixels.

:func:`photo_size` (the size as stored), :func:`jpeg_facts` (EXIF Make and Orientation, DJI
thermal R-JPEGs) and :func:`photo_notes` (what a tool tells about them). JPEG and PNG headers
are read with Pillow, lazily (``PIL.Image.open`` reads the header, not the pixels: its markers
up to the start of scan, with the EXIF block and the APPn segments); TIFF headers with
tifffile's first page, as the TIFF tags of camera and GDAL-written photos are read
(:mod:`.tags`). Pillow is optional for the plugin: where it is missing, these functions raise
an :class:`~..errors.EasyIDPError` saying what to install.
"""
import os
import struct
from typing import Dict, List, Optional, Sequence, Tuple

from ..errors import EasyIDPError

JPEG_MAGIC = b"\xff\xd8"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
TIFF_MAGIC = (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+")
HEADER_ERRORS = (OSError, SyntaxError, ValueError, EOFError, struct.error)
"""What Pillow raises on a damaged header: ``UnidentifiedImageError`` and other ``OSError``
from ``Image.open``, ``SyntaxError`` from an EXIF block that is not TIFF data, ``ValueError``,
``EOFError`` and ``struct.error`` from truncated segments."""
PILLOW_MISSING = ("{path}: reading a photo's header needs the Python package Pillow, which is "
                  "not installed ({exc}). Install it (pip install pillow; Debian/Ubuntu: apt "
                  "install python3-pil) and run again.")
EXIF_MAKE, EXIF_ORIENTATION = 0x010F, 0x0112
XMP_NS = b"http://ns.adobe.com/xap/1.0/\x00"
"""The prefix of a JPEG's XMP APP1 segment."""


def open_header(path, formats: Sequence[str] = ("JPEG", "PNG")):
    """``PIL.Image.open(path)`` for its header (the pixels are not decoded; close it, e.g. in a
    ``with`` block). Raises :class:`~..errors.EasyIDPError` naming the photo when Pillow is not
    installed, and what Pillow raises for a file it cannot read (:data:`HEADER_ERRORS`)."""
    try:
        from PIL import Image
    except ImportError as exc:
        raise EasyIDPError(PILLOW_MISSING.format(path=os.fspath(path), exc=exc)) from None
    try:
        return Image.open(path, formats=list(formats))
    except Image.DecompressionBombError as exc:   # over 2 × MAX_IMAGE_PIXELS: not a photo
        raise OSError(str(exc)) from None


def jpeg_segments(image, marker: str) -> List[bytes]:
    """The payloads of the ``marker`` segments (``"APP1"``, ``"APP3"`` …) of a JPEG opened by
    :func:`open_header`, in file order."""
    return [data for name, data in getattr(image, "applist", []) if name == marker]


def jpeg_xmp(image) -> bytes:
    """The XMP packet of a JPEG opened by :func:`open_header` (its first APP1 segment with the
    XMP prefix), b"" when it has none."""
    for data in jpeg_segments(image, "APP1"):
        if data.startswith(XMP_NS):
            return data[len(XMP_NS):]
    return b""


def _magic(path) -> bytes:
    with open(path, "rb") as fh:
        return fh.read(8)


def photo_size(path) -> Optional[Tuple[int, int]]:
    """(width, height) in pixels as stored (EXIF orientation not applied) from the file's
    header (JPEG SOF, PNG IHDR, TIFF first page), or None when it cannot be told cheaply
    (another format, a damaged header)."""
    try:
        head = _magic(path)
        if head[:2] == JPEG_MAGIC or head == PNG_MAGIC:
            with open_header(path) as im:
                return int(im.size[0]), int(im.size[1])
        if head[:4] in TIFF_MAGIC:
            import tifffile
            try:
                with tifffile.TiffFile(path) as tif:
                    page = tif.pages.first
                    return int(page.imagewidth), int(page.imagelength)
            except (tifffile.TiffFileError, IndexError, KeyError):   # damaged IFDs
                return None
    except HEADER_ERRORS:                                             # a damaged header: unknown
        return None
    return None


def scale_to(sensor_size: Tuple[int, int], photo: Tuple[int, int]) -> Optional[float]:
    """The factor s of a photo stored at ``photo`` (w, h) from a sensor of ``sensor_size``:
    1 for the same size; s when both sides are the sensor's times s, rounded to whole pixels
    (a resized copy, same aspect); None for another aspect ratio."""
    (W, H), (w, h) = sensor_size, photo
    if (w, h) == (W, H):
        return 1.0
    s = w / W
    return s if abs(round(H * s) - h) <= 1 and abs(round(W * (h / H)) - w) <= 1 else None


def jpeg_facts(path) -> Dict[str, object]:
    """What a JPEG's header says that changes how its pixels read: ``make`` (EXIF Make),
    ``orientation`` (EXIF Orientation, 1 when absent) and ``thermal`` (DJI R-JPEG: a DJI
    photo carrying APP3 segments, where DJI keeps the raw thermal data; the image itself is a
    false-colour palette rendering). {} for a file that is not a JPEG or cannot be read."""
    try:
        if _magic(path)[:2] != JPEG_MAGIC:
            return {}
        with open_header(path, ("JPEG",)) as im:
            app1 = jpeg_segments(im, "APP1")
            app3 = bool(jpeg_segments(im, "APP3"))
            try:
                exif = im.getexif()
            except HEADER_ERRORS:                       # a damaged EXIF block: as none
                exif = {}
            make, orientation = exif.get(EXIF_MAKE), exif.get(EXIF_ORIENTATION)
    except HEADER_ERRORS:
        return {}
    make = make.split("\x00")[0].strip() if isinstance(make, str) else ""
    if not make and any(b"drone-dji" in d for d in app1 if not d.startswith(b"Exif\x00\x00")):
        make = "DJI"                                    # DJI's XMP, no EXIF Make
    return {"make": make, "orientation": orientation if isinstance(orientation, int) else 1,
            "thermal": app3 and make.upper().startswith("DJI")}


THERMAL_NOTE = ("{names}: DJI thermal R-JPEG; its stored image is a false-colour palette "
                "rendering, not temperatures, so values measured on it are palette colours. "
                "Convert the photos to temperature TIFFs first (DJI Thermal SDK, dji_irp) and "
                "give those as the photos.")
ORIENTATION_NOTE = ("{names}: EXIF orientation {values}: pixels are read as stored, not turned "
                    "upright, as Metashape and Pix4D measure them (an OpenDroneMap project works "
                    "on upright photos: see its notes)")


def photo_notes(paths: Sequence[str]) -> List[str]:
    """What to tell about a set of photo files before their pixels are used: DJI thermal
    R-JPEGs (palette, not temperatures) and EXIF-rotated photos (read as stored)."""
    thermal, rotated = [], {}
    for p in paths:
        facts = jpeg_facts(p) if p else {}
        if facts.get("thermal"):
            thermal.append(os.path.basename(p))
        if facts.get("orientation", 1) not in (1, 0):
            rotated[os.path.basename(p)] = facts["orientation"]
    notes = []
    short = lambda names: ", ".join(names[:3]) + (f" and {len(names) - 3} more" if len(names) > 3 else "")
    if thermal:
        notes.append(THERMAL_NOTE.format(names=short(thermal)))
    if rotated:
        notes.append(ORIENTATION_NOTE.format(names=short(list(rotated)),
                                             values=sorted(set(rotated.values()))))
    return notes
