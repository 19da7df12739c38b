"""A minimal ESRI shapefile reader for polygons (shape types 5, 15, 25), no dependencies.

Reads the ``.shp`` geometry (x, y only; z/m ignored), the ``.prj`` WKT next to it, and the
``.dbf`` attributes (dBASE III: character, numeric, float, logical, date fields as strings or
numbers). Rings are returned as (k, 2) arrays as stored (the first vertex repeated at the end).
"""
import struct
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

from ..errors import InputError

POLYGON_TYPES = {5, 15, 25}


def read_polygons(path) -> Tuple[List[List[np.ndarray]], Optional[str], List[Dict]]:
    """(polygons as lists of rings, .prj WKT or None, attribute records) of a polygon .shp."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the shapefile ({exc}).") from None
    if len(data) < 100 or struct.unpack(">i", data[:4])[0] != 9994:
        raise InputError(f"{path}: not an ESRI shapefile (bad header).")
    shape_type = struct.unpack("<i", data[32:36])[0]
    if shape_type not in POLYGON_TYPES:
        raise InputError(f"{path}: shape type {shape_type} is not a polygon type (5, 15, 25).")
    polys, pos = [], 100
    while pos + 8 <= len(data):
        _, length = struct.unpack(">ii", data[pos:pos + 8])
        rec = data[pos + 8:pos + 8 + 2 * length]
        pos += 8 + 2 * length
        if len(rec) < 4:
            raise InputError(f"{path}: truncated record at byte {pos}.")
        st = struct.unpack("<i", rec[:4])[0]
        if st == 0:
            polys.append([])
            continue
        nparts, npoints = struct.unpack("<ii", rec[36:44])
        parts = list(struct.unpack(f"<{nparts}i", rec[44:44 + 4 * nparts])) + [npoints]
        off = 44 + 4 * nparts
        if len(rec) < off + 16 * npoints:
            raise InputError(f"{path}: truncated polygon record at byte {pos}.")
        xy = np.frombuffer(rec[off:off + 16 * npoints], dtype="<f8").reshape(npoints, 2)
        polys.append([xy[parts[k]:parts[k + 1]].copy() for k in range(nparts)])
    prj = path.with_suffix(".prj")
    wkt = prj.read_text(errors="replace").strip() if prj.is_file() else None
    return polys, wkt, _read_dbf(path.with_suffix(".dbf"))


def _read_dbf(path: Path) -> List[Dict]:
    if not path.is_file():
        return []
    data = path.read_bytes()
    nrec, hlen, rlen = struct.unpack("<IHH", data[4:12])
    fields, pos = [], 32
    while pos < hlen - 1 and data[pos] != 0x0D:
        name = data[pos:pos + 11].split(b"\0", 1)[0].decode("latin-1")
        fields.append((name, chr(data[pos + 11]), data[pos + 16]))
        pos += 32
    out = []
    for i in range(nrec):
        rec = data[hlen + i * rlen: hlen + (i + 1) * rlen]
        if not rec or rec[:1] == b"*":
            continue
        vals, off = {}, 1
        for name, typ, size in fields:
            raw = rec[off:off + size].decode("latin-1").strip()
            off += size
            if typ in "NF":
                try:
                    vals[name] = int(raw) if raw.lstrip("-").isdigit() else float(raw)
                except ValueError:
                    vals[name] = None
            else:
                vals[name] = raw
        out.append(vals)
    return out
