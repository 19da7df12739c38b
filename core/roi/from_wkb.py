"""ROIs from the WKB of many polygon geometries at once (what a GIS hands over in bulk, e.g.
``QgsGeometry.asWkb()`` of every feature of a layer).

The same ROIs as :func:`~.model.roi_from_coordinates` on each geometry's MultiPolygon
coordinates: Z kept as the vertex heights, M dropped, the repeated closing vertex and
consecutive duplicates dropped, empty rings and polygons left out, an empty or null geometry
an ROI without parts (its validation says so). The vertices of all ROIs are read into one array
and cleaned in one numpy pass; the per-ROI cost that is left is slicing (10,000 plots: a few
hundredths of a second, against 0.8 s ring by ring).
"""
import struct
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..errors import ROIError
from ..ragged import offsets
from .model import ROI, ROISet

POLYGON, MULTIPOLYGON = 3, 6


def rois_from_wkb(names: Sequence[str], blobs: Sequence[Optional[bytes]], crs=None) -> ROISet:
    """An :class:`ROISet` from one WKB Polygon or MultiPolygon (ISO or extended Z/M codes,
    either byte order) per ROI.

    Parameters
    ----------
    names : sequence of str
        The ROIs' names, one per geometry.
    blobs : sequence of bytes or None
        The geometries as WKB; None or empty bytes for a null geometry.
    crs : CRS, optional
        The CRS of the coordinates (anything pyproj accepts).

    Returns
    -------
    ROISet
        The ROIs in the order of ``names`` (not yet validated: :meth:`ROISet.validate`).
    """
    rings: List[Tuple[int, int, bytes, int, int, int, bool, str]] = []
    # per ring: (roi, polygon, blob, byte offset, vertices, doubles per vertex, z, byte order)
    for k, (name, blob) in enumerate(zip(names, blobs)):
        if blob:
            _parse(k, str(name), bytes(blob), rings)
    lens = np.array([r[4] for r in rings], np.int64)
    has_z = np.array([r[6] for r in rings], bool)
    coords = [np.frombuffer(blob, f"{e}f8", n * dims, pos).reshape(n, dims)
              for _, _, blob, pos, n, dims, _, e in rings]
    xyz = np.concatenate([c[:, :3] if z else np.column_stack([c[:, :2], np.full(n, np.nan)])
                          for c, z, n in zip(coords, has_z, lens)]) if rings else np.zeros((0, 3))
    keep = _kept(xyz[:, :2], offsets(lens))
    kept_lens = np.add.reduceat(keep.astype(np.int64), offsets(lens)[:-1]) if len(lens) \
        else lens            # every ring read has vertices (empty rings are left out)
    xyz = xyz[keep].astype(np.float64)
    xy = np.ascontiguousarray(xyz[:, :2])
    z = np.ascontiguousarray(xyz[:, 2])
    cuts = offsets(kept_lens)
    xy_rings, z_rings = np.split(xy, cuts[1:-1]), np.split(z, cuts[1:-1])
    parts: List[list] = [[] for _ in names]
    heights: List[list] = [[] for _ in names]
    z_ok = [True] * len(names)
    last = (-1, -1)
    for (roi, poly, *_), z_flag, r_xy, r_z in zip(rings, has_z, xy_rings, z_rings):
        if (roi, poly) != last:
            parts[roi].append([])
            heights[roi].append([])
            last = (roi, poly)
        parts[roi][-1].append(r_xy)
        heights[roi][-1].append(r_z)
        z_ok[roi] = z_ok[roi] and bool(z_flag)
    return ROISet([ROI(str(name), p, {}, h if p and ok else None)
                   for name, p, h, ok in zip(names, parts, heights, z_ok)], crs)


def _kept(xy: np.ndarray, offs: np.ndarray) -> np.ndarray:
    """(V,) bool: the vertices :func:`core.geometry.ring_keep` keeps, ring by ring of the
    ragged ``xy``: consecutive duplicates and a repeated closing vertex dropped."""
    keep = np.ones(len(xy), bool)
    if not len(xy):
        return keep
    keep[1:] = np.any(xy[1:] != xy[:-1], axis=1)
    starts = offs[:-1][np.diff(offs) > 0]
    keep[starts] = True
    # the last kept vertex of each ring, dropped when it repeats the first (and is not it)
    idx = np.where(keep, np.arange(len(xy)), -1)
    last = np.maximum.reduceat(idx, starts)
    closing = (last != starts) & np.all(xy[last] == xy[starts], axis=1)
    keep[last[closing]] = False
    return keep


def _parse(k: int, name: str, blob: bytes, out: list) -> None:
    """Append the rings of one WKB Polygon or MultiPolygon to ``out`` (see :func:`rois_from_wkb`)."""
    try:
        e, base, dims, z, pos = _header(blob, 0)
        if base == POLYGON:
            _polygon(k, 0, blob, pos, e, dims, z, out)
        elif base == MULTIPOLYGON:
            (n,) = struct.unpack_from(e + "I", blob, pos)
            pos += 4
            for j in range(n):
                pe, pbase, pdims, pz, pos = _header(blob, pos)
                if pbase != POLYGON:
                    raise ROIError(f"ROI {name!r}: its multipolygon holds a geometry of WKB "
                                   f"type {pbase}, not a polygon.")
                pos = _polygon(k, j, blob, pos, pe, pdims, pz, out)
        else:
            raise ROIError(f"ROI {name!r} is a geometry of WKB type {base}, not a polygon: ROIs "
                           "must be polygons or multipolygons (buffer points or lines first, "
                           "segmentize curves).")
    except struct.error:
        raise ROIError(f"ROI {name!r}: its geometry (WKB) is truncated.") from None


def _header(blob: bytes, pos: int):
    """(byte order, base type, doubles per vertex, has Z, position after the header)."""
    order = blob[pos]
    if order not in (0, 1):
        raise struct.error
    e = "<" if order == 1 else ">"
    (code,) = struct.unpack_from(e + "I", blob, pos + 1)
    iso = (code & 0x0FFFFFFF) // 1000              # ISO: 1000 Z, 2000 M, 3000 ZM
    has_z = bool(code & 0x80000000) or iso in (1, 3)   # extended: flags in the high bits
    has_m = bool(code & 0x40000000) or iso in (2, 3)
    return e, (code & 0x0FFFFFFF) % 1000, 2 + has_z + has_m, has_z, pos + 5


def _polygon(k: int, j: int, blob: bytes, pos: int, e: str, dims: int, z: bool,
             out: list) -> int:
    (n_rings,) = struct.unpack_from(e + "I", blob, pos)
    pos += 4
    for _ in range(n_rings):
        (n,) = struct.unpack_from(e + "I", blob, pos)
        pos += 4
        if pos + 8 * n * dims > len(blob):
            raise struct.error
        if n:
            out.append((k, j, blob, pos, n, dims, z, e))
        pos += 8 * n * dims
    return pos


def wkb_with_height(blobs: Sequence[Optional[bytes]], heights: Sequence[float]) -> List[bytes]:
    """Each WKB Polygon or MultiPolygon of ``blobs`` as an ISO little-endian MultiPolygonZ with
    the same rings and vertices (as stored: closing vertices and duplicates kept, M dropped)
    and Z = ``heights[i]`` at every vertex (NaN stays NaN); a null or empty geometry gives an
    empty MultiPolygonZ. How the heights tool writes its features' geometries, all at once."""
    rings: list = []
    for k, blob in enumerate(blobs):
        if blob:
            _parse(k, f"#{k}", bytes(blob), rings)
    h = np.asarray(heights, np.float64)
    coords = [np.frombuffer(blob, f"{e}f8", n * dims, pos).reshape(n, dims)[:, :2]
              for _, _, blob, pos, n, dims, _, e in rings]
    lens = np.array([len(c) for c in coords], np.int64)
    data = np.column_stack([np.concatenate(coords), np.repeat(h[[r[0] for r in rings]], lens)]
                           ).astype("<f8").tobytes() if rings else b""
    cuts = (24 * offsets(lens)).tolist()
    out: List[list] = [[] for _ in blobs]            # per record: per polygon, its ring bytes
    last = (-1, -1)
    for j, (roi, poly, *_) in enumerate(rings):
        if (roi, poly) != last:
            out[roi].append([])
            last = (roi, poly)
        out[roi][-1].append(struct.pack("<I", int(lens[j])) + data[cuts[j]:cuts[j + 1]])
    head_z = struct.pack("<BI", 1, POLYGON + 1000)
    return [struct.pack("<BII", 1, MULTIPOLYGON + 1000, len(polys)) + b"".join(
        head_z + struct.pack("<I", len(p)) + b"".join(p) for p in polys) for polys in out]
