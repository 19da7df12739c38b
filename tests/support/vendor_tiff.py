"""16-bit band files as MicaSense and DJI cameras write them, built byte by byte in the tests.

A small TIFF writer of its own (struct only, no imaging library): IFD0 with the image, the
EXIF sub-IFD (``ExposureTime``, ``ISOSpeed``, ``DateTimeOriginal``, ``SubSecTimeOriginal``), the
GPS sub-IFD, ``BlackLevel`` (DNG tag 50714) and the XMP packet (tag 700) with the vendors'
namespaces and property names, as their cameras write them. The product reads these files with
tifffile and its own XMP parsing, so these bytes are an independent truth of the layout.
"""
import struct
from fractions import Fraction

import numpy as np

BYTE, ASCII, SHORT, LONG, RATIONAL = 1, 2, 3, 4, 5
_SIZE = {BYTE: 1, ASCII: 1, SHORT: 2, LONG: 4, RATIONAL: 8}

MICASENSE_NS = {"Camera": "http://pix4d.com/camera/1.0/", "DLS": "http://micasense.com/DLS/1.0/",
                "MicaCamera": "http://micasense.com/MicaCamera/1.0/"}
DJI_NS = {"drone-dji": "http://www.dji.com/drone-dji/1.0/", "Camera": "http://pix4d.com/camera/1.0/"}


def xmp_packet(props, namespaces, *, as_elements=()) -> bytes:
    """An XMP packet: ``props`` {"prefix:Name": value}; lists become rdf:Seq elements, names in
    ``as_elements`` become elements, the rest attributes (cameras write both forms)."""
    attrs, elems = [], []
    for key, value in props.items():
        if isinstance(value, (list, tuple)):
            items = "".join(f"<rdf:li>{v}</rdf:li>" for v in value)
            elems.append(f"<{key}><rdf:Seq>{items}</rdf:Seq></{key}>")
        elif key in as_elements:
            elems.append(f"<{key}>{value}</{key}>")
        else:
            attrs.append(f'{key}="{value}"')
    ns = " ".join(f'xmlns:{p}="{u}"' for p, u in namespaces.items())
    return ('<?xpacket begin="\ufeff" id="W5M0MpCehiHzreSzNTczkc9d"?>'
            '<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
            'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#">'
            f'<rdf:Description rdf:about="" {ns} {" ".join(attrs)}>{"".join(elems)}'
            '</rdf:Description></rdf:RDF></x:xmpmeta><?xpacket end="w"?>').encode("utf-8")


def rational(value, limit=1_000_000):
    f = Fraction(value).limit_denominator(limit)
    return (f.numerator, f.denominator)


def _encode(kind, values) -> bytes:
    if kind == ASCII:
        return values.encode("ascii") + b"\0"
    if kind == BYTE:
        return bytes(values)
    if kind == RATIONAL:
        return b"".join(struct.pack("<II", *v) for v in values)
    return struct.pack(f"<{len(values)}{'H' if kind == SHORT else 'I'}", *values)


def _ifd(entries, start) -> bytes:
    """IFD bytes at file offset ``start``: entries [(tag, kind, values)], out-of-line data after."""
    entries = sorted(entries)
    data_at = start + 2 + 12 * len(entries) + 4
    head, tail = [struct.pack("<H", len(entries))], []
    for tag, kind, values in entries:
        raw = _encode(kind, values)
        count = len(raw) // _SIZE[kind]
        if len(raw) <= 4:
            head.append(struct.pack("<HHI", tag, kind, count) + raw.ljust(4, b"\0"))
        else:
            head.append(struct.pack("<HHII", tag, kind, count, data_at))
            raw += b"\0" * (len(raw) % 2)
            tail.append(raw)
            data_at += len(raw)
    head.append(struct.pack("<I", 0))
    return b"".join(head) + b"".join(tail)


def write_band_tiff(path, pixels, *, xmp: bytes, make: str, model: str, software: str = "v1.0.0",
                    black_level=None, exposure_s=None, iso=None, when=None, subsec=None,
                    latlon=None) -> None:
    """Write a 16-bit single-band TIFF with the given camera tags (None: tag left out)."""
    pixels = np.ascontiguousarray(pixels, dtype="<u2")
    rows, cols = pixels.shape
    image = pixels.tobytes()
    exif = []
    if exposure_s is not None:
        exif.append((33434, RATIONAL, [rational(exposure_s)]))
    if iso is not None:
        exif += [(34855, SHORT, [int(iso)]), (34864, SHORT, [3]), (34867, LONG, [int(iso)])]
    if when is not None:
        exif.append((36867, ASCII, when))
    if subsec is not None:
        exif.append((37521, ASCII, subsec))
    gps = []
    if latlon is not None:
        lat, lon = latlon

        def dms(v):
            v = abs(v)
            d = int(v)
            m = int((v - d) * 60)
            s = (v - d - m / 60) * 3600
            return [(d, 1), (m, 1), (int(round(s * 10000)), 10000)]
        gps = [(0, BYTE, [2, 3, 0, 0]), (1, ASCII, "N" if lat >= 0 else "S"), (2, RATIONAL, dms(lat)),
               (3, ASCII, "E" if lon >= 0 else "W"), (4, RATIONAL, dms(lon))]

    def ifd0(exif_at, gps_at, strip_at):
        e = [(256, LONG, [cols]), (257, LONG, [rows]), (258, SHORT, [16]), (259, SHORT, [1]),
             (262, SHORT, [1]), (271, ASCII, make), (272, ASCII, model), (273, LONG, [strip_at]),
             (277, SHORT, [1]), (278, LONG, [rows]), (279, LONG, [len(image)]),
             (284, SHORT, [1]), (305, ASCII, software), (700, BYTE, list(xmp))]
        if black_level is not None:
            e.append((50714, SHORT, [int(b) for b in np.atleast_1d(black_level)]))
        if exif:
            e.append((34665, LONG, [exif_at]))
        if gps:
            e.append((34853, LONG, [gps_at]))
        return e

    strip_at = 8
    ifd0_at = strip_at + len(image) + len(image) % 2
    size0 = len(_ifd(ifd0(0, 0, strip_at), ifd0_at))
    exif_at = ifd0_at + size0
    exif_bytes = _ifd(exif, exif_at) if exif else b""
    gps_at = exif_at + len(exif_bytes)
    gps_bytes = _ifd(gps, gps_at) if gps else b""
    out = (b"II*\0" + struct.pack("<I", ifd0_at) + image + b"\0" * (len(image) % 2)
           + _ifd(ifd0(exif_at, gps_at, strip_at), ifd0_at) + exif_bytes + gps_bytes)
    with open(path, "wb") as fh:
        fh.write(out)
