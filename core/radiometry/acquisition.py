"""When a photo was taken: EXIF ``DateTimeOriginal`` with ``SubSecTimeOriginal`` and
``OffsetTimeOriginal`` (EXIF 2.31), from a JPEG's APP1 block or a TIFF's own tags."""
import os
import struct
from datetime import datetime, timedelta, timezone
from typing import Dict, Optional

from .flir import jpeg_segments

_TAGS = {0x9003: "original", 0x9291: "subsec", 0x9011: "offset"}


def _ifd_entries(tiff: bytes, at: int, order: str) -> Dict[int, object]:
    (count,) = struct.unpack(order + "H", tiff[at:at + 2])
    out: Dict[int, object] = {}
    for k in range(count):
        e = tiff[at + 2 + 12 * k: at + 14 + 12 * k]
        tag, typ, num = struct.unpack(order + "HHI", e[:8])
        if typ == 2:                                            # ASCII
            raw = e[8:8 + num] if num <= 4 else \
                tiff[struct.unpack(order + "I", e[8:12])[0]:][:num]
            out[tag] = raw.split(b"\x00")[0].decode("latin-1").strip()
        elif typ in (4, 13) and num == 1:                       # LONG, IFD
            out[tag] = struct.unpack(order + "I", e[8:12])[0]
    return out


def exif_time_tags(tiff: bytes) -> Dict[str, str]:
    """{original, subsec, offset} of an EXIF TIFF block (those present)."""
    order = "<" if tiff[:2] == b"II" else ">"
    (ifd0,) = struct.unpack(order + "I", tiff[4:8])
    exif_at = _ifd_entries(tiff, ifd0, order).get(0x8769)
    if not isinstance(exif_at, int):
        return {}
    tags = _ifd_entries(tiff, exif_at, order)
    return {name: tags[t] for t, name in _TAGS.items() if isinstance(tags.get(t), str) and tags[t]}


def acquisition_time(path) -> Optional[datetime]:
    """The photo's time of acquisition: aware when the photo states its UTC offset, naive
    (local time of the camera) when not; None when it has no ``DateTimeOriginal`` or cannot
    be read."""
    try:
        with open(os.fspath(path), "rb") as fh:
            head = fh.read(4)
            fh.seek(0)
            data = fh.read(1 << 20) if head[:2] == b"\xff\xd8" else fh.read()
        tags: Dict[str, str] = {}
        if head[:2] == b"\xff\xd8":
            for marker, payload in jpeg_segments(data):
                if marker == 0xE1 and payload[:6] == b"Exif\x00\x00":
                    tags = exif_time_tags(payload[6:])
                    break
        elif head in (b"II*\x00", b"MM\x00*"):
            tags = exif_time_tags(data)
        if "original" not in tags:
            return None
        when = datetime.strptime(tags["original"][:19], "%Y:%m:%d %H:%M:%S")
        sub = "".join(ch for ch in tags.get("subsec", "") if ch.isdigit())
        if sub:
            when += timedelta(seconds=float("0." + sub))
        off = tags.get("offset", "")
        if len(off) >= 6 and off[0] in "+-" and off[3] == ":":
            sign = 1 if off[0] == "+" else -1
            when = when.replace(tzinfo=timezone(sign * timedelta(hours=int(off[1:3]),
                                                                  minutes=int(off[4:6]))))
        return when
    except (OSError, ValueError, struct.error, IndexError):
        return None
