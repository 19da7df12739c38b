"""The band tags of one multispectral photo (MicaSense, DJI): its XMP packet and its TIFF/EXIF
tags, read once (radiometry's reflectance reads them).

XMP is parsed with :func:`..safe_xml.parse_xml` (no DTD, no entity). Properties are keyed
``"prefix:Name"`` with the vendors' usual prefixes, found by namespace URI (not by the prefix the
file declares): ``Camera`` (``http://pix4d.com/camera/1.0/``, MicaSense and DJI band tags),
``DLS`` (MicaSense's downwelling light sensor), ``MicaCamera`` and ``drone-dji``. A property may
be an attribute or an element; a ``rdf:Seq``/``rdf:Bag``/``rdf:Alt`` becomes a list of strings.

TIFF tags come from tifffile: the first page's tags and its EXIF sub-IFD, by name
(``ExposureTime``, ``ISOSpeed``, ``BlackLevel``, ``BitsPerSample``, ``DateTimeOriginal`` …).
"""
import os
import re
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Union

from ..errors import InputError
from ..safe_xml import XMLError, parse_xml

__all__ = ["BandTags", "read_band_tags", "xmp_properties"]

NAMESPACES = {
    "http://pix4d.com/camera/1.0/": "Camera",
    "http://micasense.com/DLS/1.0/": "DLS",
    "http://micasense.com/MicaCamera/1.0/": "MicaCamera",
    "http://www.dji.com/drone-dji/1.0/": "drone-dji",
}
_RDF = "http://www.w3.org/1999/02/22-rdf-syntax-ns#"
_XMP_PACKET = re.compile(rb"<x:xmpmeta.*?</x:xmpmeta>", re.S)


@dataclass
class BandTags:
    """The tags of one photo file (``path``): ``xmp`` by ``"prefix:Name"``, ``tiff`` by tag name
    (EXIF sub-IFD included)."""

    path: str
    xmp: Dict[str, Union[str, List[str]]] = field(default_factory=dict)
    tiff: Dict[str, Any] = field(default_factory=dict)

    def number(self, key: str) -> Optional[float]:
        """An XMP property as a float (None when absent); InputError naming the photo when it is
        not a number."""
        raw = self.xmp.get(key)
        if raw is None:
            return None
        try:
            return float(raw[0] if isinstance(raw, list) else raw)
        except (TypeError, ValueError):
            raise InputError(f"{self.path}: the tag {key} is {raw!r}, not a number; the photo's "
                             f"metadata is damaged (use the camera's original file)") from None

    def numbers(self, key: str) -> Optional[List[float]]:
        """An XMP list property (a ``rdf:Seq`` or a comma/space separated string) as floats."""
        raw = self.xmp.get(key)
        if raw is None:
            return None
        items = raw if isinstance(raw, list) else re.split(r"[,\s]+", raw.strip())
        try:
            return [float(v) for v in items if v != ""]
        except ValueError:
            raise InputError(f"{self.path}: the tag {key} is {raw!r}, not a list of numbers; the "
                             f"photo's metadata is damaged (use the camera's original file)") from None


def _rational(value) -> Any:
    if isinstance(value, tuple) and len(value) == 2 and all(isinstance(v, int) for v in value):
        return value[0] / value[1] if value[1] else float("nan")
    return value


def xmp_properties(packet: Union[bytes, str]) -> Dict[str, Union[str, List[str]]]:
    """The known vendors' properties of an XMP packet, ``{"prefix:Name": value}``."""
    root = parse_xml(packet)
    out: Dict[str, Union[str, List[str]]] = {}
    for desc in root.iter(f"{{{_RDF}}}Description"):
        for key, value in desc.attrib.items():
            name = _known(key)
            if name:
                out[name] = value
        for child in desc:
            name = _known(child.tag)
            if not name:
                continue
            items = [li.text or "" for li in child.iter(f"{{{_RDF}}}li")]
            out[name] = items if items else (child.text or "").strip()
    return out


def _known(tag: str) -> Optional[str]:
    if not tag.startswith("{"):
        return None
    uri, _, local = tag[1:].partition("}")
    prefix = NAMESPACES.get(uri)
    return f"{prefix}:{local}" if prefix else None


def read_band_tags(path) -> BandTags:
    """Read the XMP and TIFF/EXIF tags of a TIFF photo; :class:`InputError` naming the photo when
    it is not a TIFF or its XMP is not well-formed."""
    import tifffile
    path = os.fspath(path)
    try:
        with tifffile.TiffFile(path) as tif:
            page = tif.pages[0]
            tiff = {}
            for tag in page.tags.values():
                if tag.name == "ExifTag" and isinstance(tag.value, dict):
                    tiff.update({k: _rational(v) for k, v in tag.value.items()})
                elif tag.name != "XMP":
                    tiff[tag.name] = _rational(tag.value)
            xmp_tag = page.tags.get("XMP")
            xmp_raw = xmp_tag.value if xmp_tag is not None else b""
    except (OSError, ValueError, tifffile.TiffFileError) as exc:
        raise InputError(f"{path}: not a readable TIFF photo ({exc}); multispectral reflectance "
                         f"reads the camera's 16-bit TIFF band files") from None
    if isinstance(xmp_raw, str):
        xmp_raw = xmp_raw.encode("utf-8")
    match = _XMP_PACKET.search(bytes(xmp_raw))
    try:
        xmp = xmp_properties(match.group(0)) if match else {}
    except XMLError as exc:
        raise InputError(f"{path}: its XMP metadata is not readable ({exc}); use the camera's "
                         f"original file") from None
    return BandTags(path, xmp, tiff)
