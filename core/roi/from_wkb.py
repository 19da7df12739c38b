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
from typing import List, NamedTuple, Optional, Sequence, Tuple

import numpy as np

from ..errors import ROIError
from ..gc_pause import paused_gc
from ..ragged import offsets, ranges
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
    with paused_gc():
        return _rois(names, _read_rings(names, blobs), crs)


def _rois(names: Sequence[str], rings: "_Rings", crs) -> ROISet:
    lens = rings.lens
    keep = _kept(rings.xyz[:, :2], offsets(lens))
    kept_lens = np.add.reduceat(keep.astype(np.int64), offsets(lens)[:-1]) if len(lens) \
        else lens            # every ring read has vertices (empty rings are left out)
    xyz = rings.xyz[keep]
    xy = np.ascontiguousarray(xyz[:, :2])
    z = np.ascontiguousarray(xyz[:, 2])
    cuts = offsets(kept_lens).tolist()
    xy_rings = [xy[i:j] for i, j in zip(cuts[:-1], cuts[1:])]
    z_rings = [z[i:j] for i, j in zip(cuts[:-1], cuts[1:])]
    if rings.single:                         # one ring per ROI, the ROIs with a geometry
        out = [ROI(str(name), [], {}, None) for name in names]
        for k, r_xy, r_z, zk in zip(rings.roi.tolist(), xy_rings, z_rings, rings.has_z.tolist()):
            out[k].parts = [[r_xy]]
            out[k].z = [[r_z]] if zk else None
        return ROISet(out, crs)
    parts: List[list] = [[] for _ in names]
    heights: List[list] = [[] for _ in names]
    z_ok = [True] * len(names)
    last = (-1, -1)
    for roi, poly, z_flag, r_xy, r_z in zip(rings.roi.tolist(), rings.poly.tolist(),
                                            rings.has_z.tolist(), xy_rings, z_rings):
        if (roi, poly) != last:
            parts[roi].append([])
            heights[roi].append([])
            last = (roi, poly)
        parts[roi][-1].append(r_xy)
        heights[roi][-1].append(r_z)
        z_ok[roi] = z_ok[roi] and z_flag
    return ROISet([ROI(str(name), p, {}, h if p and ok else None)
                   for name, p, h, ok in zip(names, parts, heights, z_ok)], crs)


class _Rings(NamedTuple):
    """The rings of many WKB geometries, in order: each ring's ROI, polygon (within its ROI),
    vertex count and Z flag, and all vertices as stored (V, 3) float64 (Z NaN without Z).
    ``single``: every geometry read has one ring (then ``roi`` is increasing)."""
    roi: np.ndarray
    poly: np.ndarray
    lens: np.ndarray
    has_z: np.ndarray
    xyz: np.ndarray
    single: bool


def _read_rings(names: Sequence[str], blobs: Sequence[Optional[bytes]]) -> _Rings:
    """The rings of ``blobs``: one numpy pass when every geometry is a little-endian Polygon,
    or MultiPolygon of one polygon, of one ring, 2-D or Z (plots, mostly); else geometry by
    geometry."""
    fast = _single_rings(blobs)
    if fast is not None:
        return fast
    rings: List[Tuple[int, int, bytes, int, int, int, bool, str]] = []
    # per ring: (roi, polygon, blob, byte offset, vertices, doubles per vertex, z, byte order)
    for k, (name, blob) in enumerate(zip(names, blobs)):
        if blob:
            _parse(k, str(name), bytes(blob), rings)
    lens = np.array([r[4] for r in rings], np.int64)
    has_z = np.array([r[6] for r in rings], bool)
    xyz = np.full((int(lens.sum()), 3), np.nan)
    at = 0
    for _, _, blob, pos, n, dims, z, e in rings:
        c = np.frombuffer(blob, f"{e}f8", n * dims, pos).reshape(n, dims)
        xyz[at:at + n, :2 + z] = c[:, :2 + z]
        at += n
    return _Rings(np.array([r[0] for r in rings], np.int64), np.array([r[1] for r in rings],
                  np.int64), lens, has_z, xyz, False)


_CODES = {3: (False, False), 1003: (True, False), 0x80000003: (True, False),
          6: (False, True), 1006: (True, True), 0x80000006: (True, True)}
"""WKB type code → (Z, multi) of the codes the one-pass reader takes."""


def _single_rings(blobs: Sequence[Optional[bytes]]) -> Optional[_Rings]:
    """:func:`_read_rings` for the one-ring case in one numpy pass; None when any geometry is
    another kind."""
    sizes = np.array([len(b) if b else 0 for b in blobs], np.int64)
    have = np.flatnonzero(sizes)
    if not len(have) or sizes[have].min() < 13:
        return None
    buf = np.frombuffer(b"".join(bytes(b) for b in blobs if b), np.uint8)
    start = offsets(sizes[have])[:-1]

    def u32(pos):
        pos = np.minimum(pos, len(buf) - 4)
        return (buf[pos].astype(np.int64) | buf[pos + 1].astype(np.int64) << 8
                | buf[pos + 2].astype(np.int64) << 16 | buf[pos + 3].astype(np.int64) << 24)
    code = u32(start + 1)
    kinds = set(np.unique(code).tolist())
    if not kinds <= set(_CODES) or (buf[start] != 1).any():
        return None
    z = np.array([_CODES[c][0] for c in code.tolist()], bool)
    multi = np.array([_CODES[c][1] for c in code.tolist()], bool)
    ring = start + np.where(multi, 14, 5)           # the ring count
    if multi.any():
        m = start[multi]
        inner = u32(m + 10)
        if (u32(m + 5) != 1).any() or (buf[m + 9] != 1).any() or \
                not set(inner.tolist()) <= {3, 1003, 0x80000003} or \
                ((inner != 3) != z[multi]).any():
            return None
    if (u32(ring) != 1).any():
        return None
    n = u32(ring + 4)
    dims = 2 + z
    first = ring + 8
    if not (first + 8 * dims * n == start + sizes[have]).all() or (n == 0).any():
        return None
    xyz = np.full((int(n.sum()), 3), np.nan)
    for d in (2, 3):                                # 2-D and Z rings
        sel = dims == d
        if sel.any():
            rows = np.repeat(sel, n)
            at = ranges(first[sel] // 8, first[sel] // 8 + d * n[sel]) * 8 + \
                np.repeat(first[sel] % 8, d * n[sel])
            xyz[rows, :d] = _doubles(buf, at).reshape(-1, d)
    return _Rings(have, np.zeros(len(have), np.int64), n, z, xyz, True)


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
    the same rings and vertices and one height at every vertex: how the heights tool writes
    its features' geometries, all at once.

    Parameters
    ----------
    blobs : sequence of bytes or None
        WKB Polygons or MultiPolygons (as :func:`rois_from_wkb` reads them); None or empty
        bytes for a null geometry.
    heights : sequence of float
        One height per geometry (NaN stays NaN).

    Returns
    -------
    list of bytes
        One MultiPolygonZ per geometry: its rings and vertices as stored (closing vertices
        and duplicates kept, M dropped), Z = its height; a null or empty geometry gives an
        empty MultiPolygonZ.
    """
    rings = _read_rings([f"#{k}" for k in range(len(blobs))], blobs)
    h = np.asarray(heights, np.float64)
    lens, roi = rings.lens, rings.roi
    # polygons: runs of rings with the same (ROI, polygon); sizes in bytes, then positions
    new_poly = np.ones(len(lens), bool)
    new_poly[1:] = (roi[1:] != roi[:-1]) | (rings.poly[1:] != rings.poly[:-1])
    poly_of_ring = np.cumsum(new_poly) - 1
    poly_roi = roi[new_poly]
    ring_size = 4 + 24 * lens
    poly_size = 9 + np.bincount(poly_of_ring, ring_size, len(poly_roi)).astype(np.int64)
    polys_per_rec = np.bincount(poly_roi, minlength=len(blobs))
    rec_size = 9 + np.bincount(poly_roi, poly_size, len(blobs)).astype(np.int64)
    rec_start = offsets(rec_size)
    poly_start = rec_start[poly_roi] + 9 + _before_in_run(poly_size, poly_roi)
    ring_start = poly_start[poly_of_ring] + 9 + _before_in_run(ring_size, poly_of_ring)
    buf = np.zeros(int(rec_start[-1]), np.uint8)
    _put(buf, rec_start[:-1], 1, MULTIPOLYGON + 1000, polys_per_rec)
    _put(buf, poly_start, 1, POLYGON + 1000, np.bincount(poly_of_ring, minlength=len(poly_roi)))
    _put(buf, ring_start - 5, None, None, lens)
    xyz = np.column_stack([rings.xyz[:, :2], np.repeat(h[roi], lens)])
    first = ring_start + 4
    at = ranges(first // 8, first // 8 + 3 * lens) * 8 + np.repeat(first % 8, 3 * lens)
    _doubles(buf, at, xyz.ravel())
    data = buf.tobytes()
    cuts = rec_start.tolist()
    return [data[i:j] for i, j in zip(cuts[:-1], cuts[1:])]


def _before_in_run(size: np.ndarray, run: np.ndarray) -> np.ndarray:
    """For items in runs (``run``: non-decreasing run ids), the total ``size`` of the items
    before each in its run."""
    before = np.cumsum(size) - size
    first = np.ones(len(run), bool)
    first[1:] = run[1:] != run[:-1]
    return before - before[first][np.cumsum(first) - 1]


def _put(buf: np.ndarray, at: np.ndarray, order, code, count: np.ndarray) -> None:
    """Write a WKB header (byte order, type code, a count) at each position ``at`` (only the
    count, at ``at + 5``, when ``order`` is None)."""
    if order is not None:
        head = np.empty((len(at), 5), np.uint8)
        head[:, 0] = order
        head[:, 1:5] = np.frombuffer(struct.pack("<I", code), np.uint8)
        buf[(at[:, None] + np.arange(5)).ravel()] = head.ravel()
    c = np.asarray(count, "<u4").view(np.uint8).reshape(-1, 4)
    buf[(at[:, None] + np.arange(5, 9)).ravel()] = c.ravel()


def _doubles(buf: np.ndarray, at: np.ndarray, values: Optional[np.ndarray] = None):
    """The little-endian doubles at the byte positions ``at`` of ``buf`` (uint8), or, with
    ``values``, write them there: through eight float64 views, one per byte alignment, so the
    gather is per double, not per byte."""
    out = np.empty(len(at)) if values is None else None
    shift = at % 8
    for o in range(8):
        sel = np.flatnonzero(shift == o)
        if not len(sel):
            continue
        view = buf[o:o + (len(buf) - o) // 8 * 8].view("<f8")
        if values is None:
            out[sel] = view[(at[sel] - o) // 8]
        else:
            view[(at[sel] - o) // 8] = values[sel]
    return out
