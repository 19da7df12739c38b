"""LAS/LAZ reading and writing with laspy (LAZ through the lazrs backend).

Coordinates are ``X * scale + offset`` in float64; the raw point records (every standard
dimension, RGB at 16 bits, GPS time, extra bytes) are kept as they are, so a LAS → LAS crop copies
records bit for bit with the source header (scale, offset, version, point format, VLRs). The CRS
is read from the WKT VLR or the GeoTIFF-keys VLRs and written back the same way.
Uncompressed LAS is memory-mapped read-only; LAZ is decompressed into memory.
"""
import copy
import io
import os
import struct
from pathlib import Path
from typing import Dict, Optional, Tuple

import numpy as np
from pyproj import CRS

from ..crs import as_crs, same_crs
from ..errors import InputError, reads_file
from .cloud import PointCloud, gather_records
from ..files import atomic_output, check_not_inputs

_COLOUR = ("red", "green", "blue")


def _laspy():
    import laspy
    return laspy


def las_crs(header) -> Tuple[Optional[CRS], Optional[str]]:
    """(CRS stored in a LAS header (WKT VLR preferred, else GeoTIFF keys) or None, why a CRS
    record that is there could not be read, or None)."""
    try:
        return header.parse_crs(), None
    except Exception as exc:  # unparseable or user-defined GeoTIFF keys
        return None, f"its CRS record cannot be read ({type(exc).__name__}: {exc})"


@reads_file("Export or copy the point cloud again.")
def read_las(path, crs=None) -> PointCloud:
    """Read a .las or .laz file.

    ``crs`` overrides the CRS of the file; without it the file's CRS VLR is used (None if absent).
    """
    laspy = _laspy()
    path = Path(path)
    if not path.is_file():
        raise InputError(f"Point cloud {str(path)!r} does not exist: check the path.")
    _check_las_header(path)
    try:
        with laspy.open(str(path)) as reader:
            header = reader.header
            compressed = header.are_points_compressed
            n = int(header.point_count)
            if compressed:
                _check_laz_layout(path, header)
                records = reader.read_points(n).array if n else np.zeros(0, header.point_format.dtype())
            else:
                records = None
    except InputError:
        raise
    except Exception as exc:
        raise InputError(f"Point cloud {path.name!r} cannot be read as LAS/LAZ ({exc}). Check that "
                         "the file is complete and really a LAS or LAZ file.") from None
    dtype = header.point_format.dtype()
    if not compressed:
        need = header.offset_to_point_data + n * dtype.itemsize
        size = os.path.getsize(path)
        if size < need:
            raise InputError(f"Point cloud {path.name!r} is truncated: its header announces {n} "
                             f"points ({need} bytes) but the file has {size} bytes. Export or "
                             "copy it again.")
        records = (np.memmap(path, dtype=dtype, mode="r", offset=header.offset_to_point_data,
                             shape=(n,)) if n else np.zeros(0, dtype))
    elif len(records) != n:
        raise InputError(f"Point cloud {path.name!r} is truncated: {len(records)} of {n} points "
                         "could be decompressed. Export or copy it again.")
    fmt = "laz" if compressed else "las"
    file_crs, problem = las_crs(header)
    cloud = PointCloud(records, fmt, header, as_crs(crs, f"CRS of {path.name}") or file_crs, path)
    cloud.file_crs = file_crs
    if problem:
        cloud.notes.append(f"{path.name}: {problem}; " + (
            "the CRS given is used." if crs is not None else
            "it is treated as having no CRS. Give the point cloud's CRS."))
    return cloud


def _check_las_header(path: Path) -> None:
    """Refuse a LAS/LAZ whose header's counts and offsets cannot be true for its size, before
    laspy reads it (it would loop over billions of VLRs a damaged header announces)."""
    size = os.path.getsize(path)
    with open(path, "rb") as fh:
        head = fh.read(375)
    if len(head) < 227 or head[:4] != b"LASF":
        raise InputError(f"Point cloud {path.name!r} is not a LAS/LAZ file (no LASF header); check "
                         "that the file is complete.")
    minor = head[25]
    header_size, offset_points, n_vlr = struct.unpack_from("<HII", head, 94)
    bad = None
    if not 227 <= header_size <= offset_points <= size:
        bad = (f"its header ({header_size} bytes) and point data (at byte {offset_points:,}) do "
               f"not fit a file of {size:,} bytes")
    elif n_vlr * 54 > offset_points - header_size:
        bad = f"it announces {n_vlr:,} VLRs in {offset_points - header_size:,} bytes"
    elif minor >= 4 and header_size >= 247 and len(head) >= 247:
        evlr_start, n_evlr = struct.unpack_from("<QI", head, 235)
        if n_evlr and (evlr_start > size or n_evlr * 60 > size - evlr_start):
            bad = f"it announces {n_evlr:,} extended VLRs past its end"
    if bad:
        raise InputError(f"Point cloud {path.name!r} is damaged: {bad}. Export or copy it again.")


MAX_LAZ_RATIO = 1000
"""Points decoded per compressed byte beyond which a LAZ header is taken to be damaged."""


def _check_laz_layout(path: Path, header) -> None:
    """Refuse a LAZ whose chunk table or point count cannot be true for its size, before the
    decompressor (which aborts the whole process on an impossible allocation) sees it."""
    size = os.path.getsize(path)
    start = int(header.offset_to_point_data)
    n = int(header.point_count)
    with open(path, "rb") as fh:
        fh.seek(start)
        raw = fh.read(8)
        if len(raw) < 8:
            raise InputError(f"Point cloud {path.name!r} is truncated: it ends before its points.")
        table = struct.unpack("<q", raw)[0]
        if table == -1:                    # no chunk table (streamed): sizes known from the data
            data = size - start - 8
        elif not start + 8 <= table <= size - 8:
            raise InputError(f"Point cloud {path.name!r} is damaged or truncated: its LAZ chunk "
                             f"table is said to be at byte {table:,} of a {size:,}-byte file.")
        else:
            fh.seek(table)
            version, chunks = struct.unpack("<II", fh.read(8))
            data = table - start - 8
            if version != 0 or chunks > min(n + 1, max(data, 1)):
                raise InputError(f"Point cloud {path.name!r} is damaged: its LAZ chunk table "
                                 f"(version {version}, {chunks:,} chunks) does not fit "
                                 f"{n:,} points in {data:,} bytes.")
    if n * header.point_format.size > MAX_LAZ_RATIO * max(data, 1) + 2**20:
        raise InputError(f"Point cloud {path.name!r} is damaged: its header announces {n:,} points, "
                         f"far more than its {data:,} bytes of compressed data can hold.")


def _set_crs(header, crs: Optional[CRS]) -> None:
    """Write ``crs`` into the header: GeoTIFF keys where LAS < 1.4 readers expect them (when the
    CRS has an EPSG code) plus a WKT VLR; LAS 1.4 / point formats ≥ 6 get the WKT VLR."""
    if crs is None or same_crs(las_crs(header)[0], crs):
        return
    laspy = _laspy()
    try:
        header.add_crs(crs)
    except Exception:
        for name in ("GeoKeyDirectoryVlr", "GeoAsciiParamsVlr", "GeoDoubleParamsVlr"):
            try:
                header.vlrs.extract(name)
            except IndexError:
                pass
    if not header.vlrs.get("WktCoordinateSystemVlr"):
        header.vlrs.append(laspy.vlrs.known.WktCoordinateSystemVlr(crs.to_wkt("WKT1_GDAL")))
        if header.version.minor >= 4 or header.point_format.id >= 6:
            header.global_encoding.wkt = True


def _header_from(cloud: PointCloud):
    """A new LAS 1.2 header for a non-LAS cloud: point format 0–3 from the attributes present,
    scale fine enough for the extent (1e-4 map units, 1e-8 for geographic CRSs), offset at the
    floor of the minimum; colours and intensity in the standard fields, the rest as extra bytes."""
    laspy = _laspy()
    names = cloud.attribute_names
    has_rgb = all(c in names for c in _COLOUR)
    has_time = "gps_time" in names
    pf = (2 if has_rgb else 0) + (1 if has_time else 0)
    header = laspy.LasHeader(version="1.2", point_format=pf)
    lo, hi = cloud.bounds()
    if not len(cloud):
        lo = hi = np.zeros(3)
    geographic = cloud.crs is not None and cloud.crs.is_geographic
    scale = np.full(3, 1e-8 if geographic else 1e-4)
    span = np.maximum(np.abs(hi - np.floor(lo)), np.abs(lo - np.floor(lo)))
    while np.any(span / scale > 2**31 - 2):
        scale = np.where(span / scale > 2**31 - 2, scale * 10, scale)
    header.scales = scale
    header.offsets = np.floor(lo)
    std = set(header.point_format.dimension_names)
    mapped = _standard_names(cloud, header.point_format)
    extra = []
    for name in names:
        if name in mapped:
            continue
        dt = cloud.records.dtype[name]
        base = dt.base if dt.subdtype else dt
        shape = dt.shape
        if base.kind == "b":
            base = np.dtype(np.uint8)
        tname = f"{shape[0]}{base.str[1:]}" if shape else base.str[1:]
        extra.append(laspy.ExtraBytesParams(name=_las_name(name, std), type=tname))
    if extra:
        header.add_extra_dims(extra)
    return header


def _standard_names(cloud: PointCloud, point_format) -> set:
    """Attributes that map onto a LAS standard field of the same name: colours (any numeric
    dtype, rescaled to 16 bits), GPS time (floats), and integer fields whose values fit."""
    out = set()
    std = {d.name: d for d in point_format.dimensions if d.name not in ("X", "Y", "Z")}
    for name in cloud.attribute_names:
        dt = cloud.records.dtype[name]
        if name not in std or dt.shape:
            continue
        if name in _COLOUR or name == "gps_time":
            if dt.kind in "uif":
                out.add(name)
        elif dt.kind in "uib":
            v = cloud.attribute(name)
            if not len(v) or (int(v.min()) >= std[name].min and int(v.max()) <= std[name].max):
                out.add(name)
    return out


def _las_name(name: str, std) -> str:
    out = name[:32]
    return out if out not in std else ("ply_" + name)[:32]


def _colour16(v: np.ndarray) -> np.ndarray:
    """Colour channel → LAS 16-bit: uint8 × 257 (255 → 65535), 16-bit unchanged, floats in [0, 1]
    × 65535, larger floats clipped as 16-bit values."""
    if v.dtype.kind == "f":
        scale = 65535.0 if (len(v) == 0 or np.nanmax(v) <= 1.0) else 1.0
        return np.clip(np.rint(v * scale), 0, 65535).astype(np.uint16)
    if v.dtype.itemsize == 1:
        return v.astype(np.uint16) * 257
    return np.clip(v, 0, 65535).astype(np.uint16)


def _records_from(cloud: PointCloud, header) -> "np.ndarray":
    laspy = _laspy()
    las = laspy.LasData(header)
    las.points = laspy.ScaleAwarePointRecord.zeros(len(cloud), header=header)
    xyz = cloud.xyz
    las.x, las.y, las.z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    std = set(laspy.PointFormat(header.point_format.id).dimension_names)
    mapped = _standard_names(cloud, laspy.PointFormat(header.point_format.id))
    for name in cloud.attribute_names:
        v = cloud.attribute(name)
        if name in mapped:
            las[name] = _colour16(v) if name in _COLOUR else v
        else:
            las[_las_name(name, std)] = v
    return las.points.array


def _template(cloud: PointCloud) -> Optional[bytes]:
    """Header + VLR bytes of an uncompressed LAS like ``cloud``'s (counts and bounds to be
    patched), cached on the cloud; None when the fast path does not apply (EVLRs, extra bytes)."""
    cached = getattr(cloud, "_las_template", None)
    if cached is not None and cached[0] is cloud.crs:
        return cached[1]
    laspy = _laspy()
    header = copy.deepcopy(cloud.header)
    if header.evlrs or list(header.point_format.extra_dimension_names):
        # EVLRs follow the points; laspy fills extra-bytes statistics: let laspy write those
        cloud._las_template = (cloud.crs, None)
        return None
    _set_crs(header, cloud.crs)
    buf = io.BytesIO()
    empty = laspy.PackedPointRecord(np.zeros(0, cloud.records.dtype), header.point_format)
    laspy.LasData(header, empty).write(buf, do_compress=False)
    cloud._las_template = (cloud.crs, buf.getvalue())
    return cloud._las_template[1]


def _fast_write_las(cloud: PointCloud, records: np.ndarray, path: Path, template: bytes) -> None:
    """Write an uncompressed LAS: the template header with point counts, per-return counts and
    bounds patched at their LAS-specification offsets, then the raw records."""
    laspy = _laspy()
    h = bytearray(template)
    n = len(records)
    pf = cloud.header.point_format
    minor = cloud.header.version.minor
    ret = np.asarray(laspy.PackedPointRecord(records, pf)["return_number"]) if n else np.zeros(0)
    by_ret = np.bincount(ret.astype(np.int64), minlength=16)[1:16] if n else np.zeros(15, int)
    legacy = pf.id < 6 and n < 2**32
    struct.pack_into("<I", h, 107, n if legacy else 0)
    struct.pack_into("<5I", h, 111, *[int(c) if legacy else 0 for c in by_ret[:5]])
    if n:
        s, o = cloud.header.scales, cloud.header.offsets
        mm = []
        for i, d in enumerate("XYZ"):
            v = records[d]
            mm += [float(v.max() * s[i] + o[i]), float(v.min() * s[i] + o[i])]
    else:
        mm = [0.0] * 6
    struct.pack_into("<6d", h, 179, *mm)
    if minor >= 4:
        struct.pack_into("<Q", h, 247, n)
        struct.pack_into("<15Q", h, 255, *[int(c) for c in by_ret])
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(h)
            f.write(np.ascontiguousarray(records).tobytes())


def write_las(cloud: PointCloud, path, compress: Optional[bool] = None,
              index: Optional[np.ndarray] = None) -> Path:
    """Write ``cloud`` (or its points at ``index``) to ``path`` as LAS, or LAZ when ``compress``
    (default: from the suffix). Atomic; refuses to overwrite the cloud's own file.

    A LAS/LAZ cloud keeps its header and raw records (bit-exact points). Any other cloud gets a
    LAS 1.2 header (see :func:`_header_from`); its coordinates are then quantised to the scale.
    Header counts, bounds and per-return counts are recomputed from the written points.
    """
    laspy = _laspy()
    path = Path(path)
    check_not_inputs(path, [cloud.path])
    if compress is None:
        compress = path.suffix.lower() == ".laz"
    if cloud.is_las and not compress:
        template = _template(cloud)
        if template is not None:
            records = cloud.records if index is None else gather_records(cloud.records, index)
            _fast_write_las(cloud, records, path, template)
            return path
    if index is not None:
        cloud = cloud.take(index)
    if cloud.is_las:
        header = copy.deepcopy(cloud.header)
        records = np.asarray(cloud.records)
    else:
        header = _header_from(cloud)
        records = _records_from(cloud, header)
    _set_crs(header, cloud.crs)
    header.point_count = len(records)
    points = laspy.PackedPointRecord(np.ascontiguousarray(records), header.point_format)
    data = laspy.LasData(header, points)
    with atomic_output(path) as tmp:
        with open(tmp, "wb") as f:
            data.write(f, do_compress=compress, laz_backend=laspy.LazBackend.Lazrs)
    return path


def dimension_arrays(cloud: PointCloud) -> Dict[str, np.ndarray]:
    """Every attribute of a LAS cloud as named arrays (bit fields unpacked)."""
    return {n: cloud.attribute(n) for n in cloud.attribute_names}
