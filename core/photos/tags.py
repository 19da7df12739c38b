"""The metadata a raw photo carries: EXIF and XMP tags, read the same way from every file kind.

:func:`read_photo_tags` reads

* camera JPEGs: EXIF (IFD0, the EXIF and GPS IFDs) with Pillow, XMP from the JPEG's APP1
  ``http://ns.adobe.com/xap/1.0/`` segment;
* TIFFs written by a camera (DJI multispectral and thermal TIFFs): the EXIF and GPS IFDs and
  XMP (TIFF tag 700) with tifffile;
* TIFFs re-saved by GDAL (OpenDroneMap's and Orthority's downscaled test photos): EXIF as
  ``EXIF_*`` items of GDAL's metadata (TIFF tag 42112, ``GDAL_METADATA``) and XMP in tag 700,
  where GDAL writes it after a non-standard ``xml:XMP=`` prefix.

EXIF values are keyed by their EXIF tag name (``FocalLength``, ``GPSLatitude``…): rationals
as floats, GPS degrees/minutes/seconds as a tuple of floats. XMP values are keyed
``(namespace URI, local name)``, from attributes of ``rdf:Description`` and from simple child
elements alike. XMP is parsed with :func:`~..safe_xml.parse_xml` (no DTD, no entity
expansion): photos come from the user's disk.
"""
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, Optional, Tuple

from ..errors import InputError
from ..safe_xml import XMLError, parse_xml
from .headers import HEADER_ERRORS, XMP_NS, jpeg_xmp, open_header

__all__ = ["PhotoTags", "read_photo_tags", "DJI", "CAMERA_NS", "SENSEFLY", "XMP_NS"]

DJI = "http://www.dji.com/drone-dji/1.0/"
"""DJI's XMP namespace (``drone-dji:``)."""
CAMERA_NS = "http://pix4d.com/camera/1.0/"
"""The ``Camera:`` namespace of MicaSense, Sentera and Parrot XMP (Pix4D's)."""
SENSEFLY = "http://ns.sensefly.com/Camera/1.0/"
"""senseFly's camera namespace."""
_RDF = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"

_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


@dataclass
class PhotoTags:
    """The tags of one photo. ``size``: (width, height) in pixels as stored; ``exif``: EXIF
    name → value; ``xmp``: (namespace URI, name) → text; ``kind``: how they were read
    (``jpeg``, ``tiff``, ``gdal-tiff``)."""
    path: str
    size: Tuple[int, int]
    kind: str
    exif: Dict[str, object] = field(default_factory=dict)
    xmp: Dict[Tuple[str, str], str] = field(default_factory=dict)

    def xmp_float(self, ns: str, name: str) -> Optional[float]:
        """An XMP value as a float (``+186.57`` → 186.57), None when absent or not a number."""
        text = self.xmp.get((ns, name))
        try:
            return float(str(text).strip()) if text is not None else None
        except ValueError:
            return None

    def exif_float(self, name: str) -> Optional[float]:
        """An EXIF value as a float (the first of a tuple), None when absent or unusable."""
        v = self.exif.get(name)
        if isinstance(v, (tuple, list)):
            v = v[0] if v else None
        try:
            return float(v) if v is not None else None
        except (TypeError, ValueError):
            return None


def read_photo_tags(path) -> PhotoTags:
    """The EXIF and XMP tags of the photo at ``path`` (JPEG or TIFF). Raises
    :class:`~..errors.InputError` naming the file when it is neither or cannot be read."""
    p = Path(path)
    try:
        with open(p, "rb") as fh:
            head = fh.read(4)
    except OSError as exc:
        raise InputError(f"{p}: the photo cannot be read ({exc.strerror or exc}).") from None
    if head[:2] == b"\xff\xd8":
        return _read_jpeg(p)
    if head in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
        return _read_tiff(p)
    raise InputError(f"{p}: not a JPEG or TIFF photo; camera tags are read from those only.")


# --- JPEG ------------------------------------------------------------------------------------
def _read_jpeg(p: Path) -> PhotoTags:
    try:
        with open_header(p, ("JPEG",)) as im:
            from PIL import ExifTags                    # there: open_header imported Pillow
            size = im.size
            exif = im.getexif()
            out: Dict[str, object] = {}
            for ifd in (None, 0x8769, 0x8825):          # IFD0, EXIF IFD, GPS IFD
                block = exif if ifd is None else exif.get_ifd(ifd)
                names = ExifTags.GPSTAGS if ifd == 0x8825 else ExifTags.TAGS
                for tag, value in block.items():
                    name = names.get(tag)
                    if name and not isinstance(value, dict):
                        out[name] = _exif_value(value)
            xmp = jpeg_xmp(im)
    except HEADER_ERRORS as exc:
        raise InputError(f"{p}: the JPEG cannot be read ({exc}).") from None
    return PhotoTags(str(p), (int(size[0]), int(size[1])), "jpeg", out, _parse_xmp(xmp, p))


def _exif_value(value):
    """Pillow's EXIF value as plain Python: rationals → float, tuples of them → tuple."""
    if isinstance(value, tuple):
        return tuple(_exif_value(v) for v in value)
    if isinstance(value, bytes):
        return value
    if isinstance(value, (int, str)):
        return value.strip("\x00 ") if isinstance(value, str) else value
    try:
        return float(value)
    except (TypeError, ValueError, ZeroDivisionError):
        return None


# --- TIFF ------------------------------------------------------------------------------------
def _read_tiff(p: Path) -> PhotoTags:
    import tifffile

    try:
        with tifffile.TiffFile(p) as tif:
            page = tif.pages.first
            size = (int(page.imagewidth), int(page.imagelength))
            tags = {t.code: t.value for t in page.tags.values()}
    except Exception as exc:                          # tifffile raises many kinds on damage
        raise InputError(f"{p}: the TIFF cannot be read ({exc}).") from None
    exif: Dict[str, object] = {}
    kind = "tiff"
    for code, name in ((271, "Make"), (272, "Model"), (274, "Orientation")):
        if code in tags:
            exif[name] = _exif_value(_plain(tags[code]))
    for code in (34665, 34853):                       # EXIF IFD, GPS IFD (tifffile: dicts)
        if isinstance(tags.get(code), dict):
            exif.update({k: _exif_value(_plain(v)) for k, v in tags[code].items()})
    if 42112 in tags:                                 # GDAL's metadata: EXIF_* items
        items = _gdal_exif(tags[42112], p)
        if items:
            kind = "gdal-tiff"
            exif.update(items)
    xmp = tags.get(700, b"")
    if isinstance(xmp, str):
        xmp = xmp.encode("utf-8")
    start = bytes(xmp).find(b"<")                     # GDAL writes "xml:XMP=" before it
    return PhotoTags(str(p), size, kind, exif, _parse_xmp(bytes(xmp)[max(start, 0):], p))


def _plain(value):
    """tifffile's value as EXIF-like Python: a (numerator, denominator) pair is a rational."""
    if isinstance(value, tuple) and len(value) == 2 and all(isinstance(v, int) for v in value):
        return value[0] / value[1] if value[1] else None
    if isinstance(value, tuple) and len(value) in (6, 8) and all(isinstance(v, int) for v in value):
        return tuple(value[i] / value[i + 1] if value[i + 1] else 0.0
                     for i in range(0, len(value), 2))         # GPS degrees, minutes, seconds
    return value


def _gdal_exif(text, p: Path) -> Dict[str, object]:
    """The ``EXIF_*`` items of a GDAL_METADATA document, by EXIF name: ``(8.8)`` → 8.8,
    ``(24) (40) (49.0009)`` → (24.0, 40.0, 49.0009), ``24`` → 24, text as text."""
    try:
        root = parse_xml(text.encode("utf-8") if isinstance(text, str) else bytes(text))
    except XMLError as exc:
        raise InputError(f"{p}: GDAL's metadata tag (42112) is not readable XML ({exc}).") from None
    out: Dict[str, object] = {}
    for item in root.iter("Item"):
        name = item.get("name", "")
        if not name.startswith("EXIF_") or item.get("domain") not in (None, ""):
            continue
        raw = (item.text or "").strip()
        parts = re.findall(r"\(([^)]*)\)", raw)
        if parts and re.sub(r"\([^)]*\)", "", raw).strip() == "":
            try:
                nums = tuple(float(v) for v in parts)
            except ValueError:
                nums = None
            out[name[5:]] = nums[0] if nums and len(nums) == 1 else (nums or raw)
        elif _NUMBER.match(raw) and "." not in raw:
            out[name[5:]] = int(raw)
        else:
            out[name[5:]] = raw
    return out


# --- XMP -------------------------------------------------------------------------------------
def _parse_xmp(data: bytes, p: Path) -> Dict[Tuple[str, str], str]:
    """(namespace, name) → text of an XMP packet: rdf:Description attributes and simple
    child elements. {} for no packet; an unreadable one is an error naming the photo."""
    data = data.rstrip(b"\x00 \n\r\t")
    if not data.strip():
        return {}
    try:
        root = parse_xml(data)
    except XMLError as exc:
        raise InputError(f"{p}: its XMP metadata is not readable XML ({exc}).") from None
    out: Dict[Tuple[str, str], str] = {}
    for desc in root.iter(f"{{{_RDF}}}Description"):
        for key, value in desc.attrib.items():
            if key.startswith("{") and not key.startswith(f"{{{_RDF}}}"):
                ns, name = key[1:].split("}", 1)
                out[(ns, name)] = value
        for child in desc:
            if child.tag.startswith("{") and len(child) == 0 and (child.text or "").strip():
                ns, name = child.tag[1:].split("}", 1)
                out.setdefault((ns, name), child.text.strip())
    return out
