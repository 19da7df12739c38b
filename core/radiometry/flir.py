"""FLIR radiometric JPEGs: the raw sensor image and the camera's constants from the FLIR APP1
records (the "FFF" format, as exiftool's FLIR tag notes publish it).

Written by the FLIR Vue Pro R, Duo Pro R, the DJI Zenmuse XT and XT2 and many handhelds. The
JPEG carries APP1 segments that start ``FLIR\\0``, a version byte, the segment's number and the
last number; joined in order they are one FFF file: a 64-byte header (``FFF\\0``, creator,
version, the offset and length of the record directory) and a directory of 32-byte entries
(type, subtype, version, id, offset, length, …). Two records matter here:

* **RawData** (type 1): a 32-byte header (the int16 ``2`` in the record's byte order, width,
  height) and the raw image, as a **PNG** (16-bit, its bytes swapped: FLIR writes little-endian
  values into a big-endian format), a **TIFF** (the Zenmuse XT2) or bare uint16 values.
* **CameraInfo** (type 0x20): emissivity, object distance, reflected, atmospheric and IR window
  temperatures (kelvin), window transmission, relative humidity, the Planck constants R1, B, F
  (float32 at 0x58), O (int32 at 0x308), R2 (float32 at 0x30C), the atmospheric transmission
  constants, the raw value range and the camera model.
"""
import io
import struct
from dataclasses import dataclass
from typing import Dict, List, Tuple

import numpy as np

from ..errors import InputError
from .planck import KELVIN, ThermalParameters

RAW_DATA, CAMERA_INFO = 0x0001, 0x0020
FLIR_MAGIC = b"FLIR\x00"


@dataclass
class FlirPhoto:
    """The raw image (uint16, rows × cols), the photo's :class:`ThermalParameters`, the raw
    image's encoding (``png``, ``tiff``, ``raw``), the camera model and the usable raw range
    (values outside are saturated)."""

    raw: np.ndarray
    parameters: ThermalParameters
    encoding: str
    model: str
    raw_range: Tuple[int, int]


def jpeg_segments(data: bytes) -> List[Tuple[int, bytes]]:
    """(marker, payload) of a JPEG's header segments, up to the start of scan."""
    if data[:2] != b"\xff\xd8":
        raise ValueError("not a JPEG")
    out, pos = [], 2
    while pos + 4 <= len(data):
        if data[pos] != 0xFF:
            raise ValueError(f"no JPEG marker at byte {pos}")
        marker = data[pos + 1]
        if marker == 0xFF:
            pos += 1
            continue
        if marker in (0xD8, 0x01) or 0xD0 <= marker <= 0xD7:
            pos += 2
            continue
        if marker in (0xDA, 0xD9):
            break
        (n,) = struct.unpack(">H", data[pos + 2:pos + 4])
        out.append((marker, data[pos + 4:pos + 2 + n]))
        pos += 2 + n
    return out


def fff_block(data: bytes) -> bytes:
    """The FFF file joined from a JPEG's FLIR APP1 segments; b"" when it has none."""
    parts: Dict[int, bytes] = {}
    for marker, payload in jpeg_segments(data):
        if marker == 0xE1 and payload[:5] == FLIR_MAGIC and len(payload) >= 8:
            parts[payload[6]] = payload[8:]
    if not parts:
        return b""
    missing = [k for k in range(max(parts) + 1) if k not in parts]
    if missing:
        raise ValueError(f"FLIR segment(s) {missing} missing")
    return b"".join(parts[k] for k in sorted(parts))


def fff_records(fff: bytes) -> Dict[int, Tuple[int, int, bytes]]:
    """{record type: (subtype, version, bytes)} of an FFF file (the first of each type)."""
    if fff[:4] not in (b"FFF\x00", b"AFF\x00"):
        raise ValueError("the FLIR data does not start with FFF")
    order = ">"
    (version,) = struct.unpack(">I", fff[0x14:0x18])
    if not 100 <= version < 200:
        order = "<"
    offset, count = struct.unpack(order + "II", fff[0x18:0x20])
    out: Dict[int, Tuple[int, int, bytes]] = {}
    for k in range(count):
        e = fff[offset + 32 * k: offset + 32 * (k + 1)]
        if len(e) < 32:
            raise ValueError("the FLIR record directory is truncated")
        typ, sub, ver, _id, off, length = struct.unpack(order + "HHIIII", e[:20])
        if typ == 0 or typ in out:
            continue
        if off + length > len(fff):
            raise ValueError(f"FLIR record {typ:#x} runs past the data")
        out[typ] = (sub, ver, fff[off:off + length])
    return out


def _order(rec: bytes) -> str:
    """The byte order of a record whose first int16 is 2."""
    if struct.unpack("<H", rec[:2])[0] == 2:
        return "<"
    if struct.unpack(">H", rec[:2])[0] == 2:
        return ">"
    raise ValueError("unknown byte order of a FLIR record")


def raw_image(rec: bytes, subtype: int) -> Tuple[np.ndarray, str]:
    """(uint16 rows × cols, encoding) of a RawData record."""
    order = _order(rec)
    w, h = struct.unpack(order + "HH", rec[2:6])
    body = rec[32:]
    if body[:8] == b"\x89PNG\r\n\x1a\n":
        import imagecodecs
        arr = np.asarray(imagecodecs.png_decode(body)).astype(np.uint16).byteswap()
        enc = "png"
    elif body[:4] in (b"II*\x00", b"MM\x00*"):
        import tifffile
        arr = np.asarray(tifffile.imread(io.BytesIO(body))).astype(np.uint16)
        enc = "tiff"
    else:
        dt = np.dtype(">u2" if subtype == 1 else "<u2")
        arr = np.frombuffer(body[:2 * w * h], dt).astype(np.uint16)
        if arr.size != w * h:
            raise ValueError(f"raw data has {arr.size} values for {w}×{h}")
        arr = arr.reshape(h, w)
        enc = "raw"
    if arr.ndim == 3 and arr.shape[2] == 1:
        arr = arr[..., 0]
    if arr.shape != (h, w):
        raise ValueError(f"the raw image is {arr.shape[1]}×{arr.shape[0]}, its record says {w}×{h}")
    return arr, enc


def camera_info(rec: bytes) -> Tuple[ThermalParameters, str, Tuple[int, int]]:
    """(parameters, camera model, raw range) of a CameraInfo record."""
    o = _order(rec)
    f = lambda at: struct.unpack(o + "f", rec[at:at + 4])[0]    # noqa: E731
    emissivity, distance, refl, atm, win, win_t = (f(0x20 + 4 * k) for k in range(6))
    rh = f(0x3C)
    r1, b, ff = f(0x58), f(0x5C), f(0x60)
    a1, a2, b1, b2, x = (f(0x70 + 4 * k) for k in range(5))
    (po,) = struct.unpack(o + "i", rec[0x308:0x30C])
    r2 = f(0x30C)
    lo, hi = struct.unpack(o + "HH", rec[0x310:0x314])
    model = rec[0xD4:0xF4].split(b"\x00")[0].decode("latin-1").strip()
    atmos = dict(alpha1=a1, alpha2=a2, beta1=b1, beta2=b2, x=x) if x else {}
    p = ThermalParameters(
        r1=r1, r2=r2, b=b, f=ff, o=float(po), emissivity=emissivity, object_distance=distance,
        reflected_temperature=refl - KELVIN, atmospheric_temperature=atm - KELVIN,
        relative_humidity=rh / 100.0 if rh > 2 else rh, ir_window_temperature=win - KELVIN,
        ir_window_transmission=win_t or 1.0, **atmos)
    raw_range = (int(lo), int(hi)) if hi > lo else (0, 65535)
    return p, model, raw_range


def read_flir(path, data: bytes) -> FlirPhoto:
    """The :class:`FlirPhoto` of a FLIR radiometric JPEG (``data``: the file's bytes);
    :class:`InputError` naming the photo when its FLIR records cannot be read."""
    try:
        recs = fff_records(fff_block(data))
        if RAW_DATA not in recs:
            raise ValueError("no RawData record")
        if CAMERA_INFO not in recs:
            raise ValueError("no CameraInfo record (no Planck constants)")
        raw, enc = raw_image(recs[RAW_DATA][2], recs[RAW_DATA][0])
        params, model, rng = camera_info(recs[CAMERA_INFO][2])
    except (ValueError, struct.error, IndexError, RuntimeError, Exception) as exc:
        if isinstance(exc, (MemoryError, InputError)):
            raise
        raise InputError(f"The thermal photo {path}: its FLIR raw data cannot be read "
                         f"({str(exc)[:120]}). Check the file is an unedited radiometric JPEG "
                         "from the camera, or convert it to a temperature TIFF.") from None
    return FlirPhoto(raw, params, enc, model, rng)
