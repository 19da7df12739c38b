"""FLIR radiometric JPEGs written in FLIR's published record format (exiftool's FLIR tag notes):
the demo's thermal camera, and the test photos of the thermal reader.

:func:`write_flir_jpeg` writes a JPEG whose image is a grey rendering of the raw values and
whose APP1 segments hold an FFF file with a RawData record (the raw image as a byte-swapped
16-bit **PNG**, as FLIR cameras write it, or as a **TIFF**, as the DJI Zenmuse XT2 writes it)
and a CameraInfo record (the Planck constants and object parameters, little-endian, kelvin),
plus EXIF Make, Model and the acquisition time (DateTimeOriginal, SubSecTimeOriginal,
OffsetTimeOriginal).
"""
import io
import os
import struct
from typing import Optional

import numpy as np

from ..files import write_bytes
from ..radiometry import KELVIN, ThermalParameters

SEGMENT = 65535 - 2 - 8            # FFF bytes per APP1 segment


def _camera_info(p: ThermalParameters, model: str, raw_range) -> bytes:
    rec = bytearray(0x400)
    struct.pack_into("<H", rec, 0, 2)
    struct.pack_into("<6f", rec, 0x20, p.emissivity, p.object_distance,
                     p.reflected_temperature + KELVIN, p.atmospheric_temperature + KELVIN,
                     p.ir_window_temperature + KELVIN, p.ir_window_transmission)
    struct.pack_into("<f", rec, 0x3C, p.relative_humidity)
    struct.pack_into("<3f", rec, 0x58, p.r1, p.b, p.f)
    struct.pack_into("<5f", rec, 0x70, p.alpha1, p.alpha2, p.beta1, p.beta2, p.x)
    struct.pack_into("<2f", rec, 0x90, 150.0 + KELVIN, -20.0 + KELVIN)
    name = model.encode("latin-1")[:31]
    rec[0xD4:0xD4 + len(name)] = name
    struct.pack_into("<i", rec, 0x308, int(round(p.o)))
    struct.pack_into("<f", rec, 0x30C, p.r2)
    struct.pack_into("<HH", rec, 0x310, *raw_range)
    return bytes(rec)


def _raw_data(raw: np.ndarray, encoding: str) -> bytes:
    h, w = raw.shape
    head = bytearray(32)
    struct.pack_into("<HHH", head, 0, 2, w, h)
    if encoding == "png":
        import imagecodecs
        body = imagecodecs.png_encode(raw.astype(np.uint16).byteswap())
    elif encoding == "tiff":
        import tifffile
        buf = io.BytesIO()
        tifffile.imwrite(buf, raw.astype("<u2"), byteorder="<", photometric="minisblack")
        body = buf.getvalue()
    else:
        raise ValueError(f"raw encoding {encoding!r}: png or tiff")
    return bytes(head) + body


def fff_file(raw: np.ndarray, p: ThermalParameters, *, encoding: str = "png",
             model: str = "FLIR Vue Pro R", raw_range=(1, 65534)) -> bytes:
    """The FFF file: header, directory (two records, then two empty entries, as cameras leave
    spare ones) and records."""
    records = [(0x0001, 3 if encoding == "png" else 2, _raw_data(raw, encoding)),
               (0x0020, 1, _camera_info(p, model, raw_range))]
    n = len(records) + 2
    offset = 64 + 32 * n
    head = bytearray(64)
    head[0:4] = b"FFF\x00"
    head[4:11] = b"EasyIDP"
    struct.pack_into(">III", head, 0x14, 100, 64, n)
    struct.pack_into(">I", head, 0x20, len(records) + 1)
    dir_ = bytearray(32 * n)
    body = b""
    for k, (typ, sub, data) in enumerate(records):
        struct.pack_into(">HHIIII", dir_, 32 * k, typ, sub, 100, 1, offset + len(body), len(data))
        body += data
    return bytes(head) + bytes(dir_) + body


def _exif(model: str, when: Optional[str], subsec: str, utc_offset: str) -> bytes:
    from PIL import Image
    ex = Image.Exif()
    ex[0x010F] = "FLIR"
    ex[0x0110] = model
    if when:
        ifd = {0x9003: when}
        if subsec:
            ifd[0x9291] = subsec
        if utc_offset:
            ifd[0x9011] = utc_offset
        ex[0x8769] = ifd
    return ex.tobytes()


def write_flir_jpeg(path, raw: np.ndarray, p: ThermalParameters, *, encoding: str = "png",
                    model: str = "FLIR Vue Pro R", when: Optional[str] = None, subsec: str = "",
                    utc_offset: str = "", raw_range=(1, 65534), quality: int = 90) -> str:
    """Write a FLIR radiometric JPEG at ``path`` (atomically): ``raw`` uint16 rows × cols,
    ``p`` its Planck constants and object parameters, ``encoding`` ``png`` or ``tiff`` (the
    raw image inside the RawData record), ``when`` the EXIF DateTimeOriginal
    (``YYYY:MM:DD HH:MM:SS``) with ``subsec`` and ``utc_offset`` (``+09:00``)."""
    from PIL import Image
    raw = np.asarray(raw)
    lo, hi = float(raw.min()), float(raw.max())
    grey = ((raw - lo) * (255.0 / max(hi - lo, 1.0))).astype(np.uint8)
    buf = io.BytesIO()
    Image.fromarray(grey).save(buf, "JPEG", quality=quality,
                               exif=_exif(model, when, subsec, utc_offset))
    jpeg = buf.getvalue()
    fff = fff_file(raw, p, encoding=encoding, model=model, raw_range=raw_range)
    chunks = [fff[k:k + SEGMENT] for k in range(0, len(fff), SEGMENT)]
    if len(chunks) > 256:
        raise ValueError("raw image too large for 256 FLIR segments")
    app1 = b"".join(b"\xff\xe1" + struct.pack(">H", len(c) + 10) + b"FLIR\x00\x01"
                    + bytes([k, len(chunks) - 1]) + c for k, c in enumerate(chunks))
    # after SOI and the EXIF APP1 (FLIR cameras put theirs after EXIF too)
    (n,) = struct.unpack(">H", jpeg[4:6])
    at = 4 + n if jpeg[2:4] == b"\xff\xe1" else 2
    path = os.fspath(path)
    write_bytes(path, jpeg[:at] + app1 + jpeg[at:])
    return path
