"""The point-cloud type: double-precision coordinates plus every per-point attribute of the source.

A :class:`PointCloud` keeps the source's own per-point records untouched, row-aligned with the
points, so a crop copies whole records and loses nothing:

- LAS/LAZ: ``records`` is the raw LAS point array (numpy structured, integer X/Y/Z, packed bit
  fields, RGB of any bit depth, GPS time, extra bytes…), memory-mapped read-only for
  uncompressed LAS; ``header`` is the ``laspy.LasHeader`` (scale, offset, VLRs, version).
- PLY: ``records`` is the vertex element's structured array (every property, original dtypes,
  memory-mapped copy-on-write for binary files); ``header`` is a :class:`PlyHeader`.
- Arrays (:meth:`PointCloud.from_arrays`): a structured array with float64 x/y/z fields.

Coordinates (``xyz``) are float64 map units of ``crs`` in (x, y, z) = (easting, northing, height)
order; for LAS they are ``X * scale + offset`` computed in float64.
"""
import mmap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np

from ..crs import as_crs

LAS_FORMATS = ("las", "laz")
XYZ_PLY = ("x", "y", "z")


@dataclass
class PlyHeader:
    """What a PLY file says besides its vertices: encoding, comments, other elements.

    ``text``: ASCII file; ``byte_order``: '<', '>' or '='; ``other_elements``: names of
    non-vertex elements (faces…), which a crop drops because their vertex indices change.
    """
    text: bool = False
    byte_order: str = "<"
    comments: List[str] = field(default_factory=list)
    obj_info: List[str] = field(default_factory=list)
    other_elements: List[str] = field(default_factory=list)


class PointCloud:
    """Points with float64 coordinates and every attribute of their source file.

    ``fmt`` is 'las', 'laz', 'ply' or 'array'. Use :func:`read_point_cloud` to make one from a file.
    """

    def __init__(self, records: np.ndarray, fmt: str, header: Any = None, crs=None,
                 path: Optional[Path] = None):
        self.records = records
        self.fmt = fmt
        self.header = header
        self.crs = as_crs(crs, "point cloud CRS")
        self.path = Path(path) if path is not None else None
        self._xyz: Optional[np.ndarray] = None
        self.file_crs = self.crs  # the CRS the file itself declares (LAS VLRs), if any
        self.notes: List[str] = []  # problems met while reading (e.g. an unreadable CRS record)

    # ---- construction -----------------------------------------------------------------------
    @classmethod
    def from_arrays(cls, xyz: np.ndarray, attributes: Optional[Dict[str, np.ndarray]] = None,
                    crs=None) -> "PointCloud":
        """A cloud from an (n, 3) coordinate array and optional per-point arrays (1-D)."""
        xyz = np.asarray(xyz, dtype=np.float64)
        if xyz.ndim != 2 or xyz.shape[1] != 3:
            raise ValueError(f"xyz must be an (n, 3) array, got shape {xyz.shape}.")
        attributes = {k: np.asarray(v) for k, v in (attributes or {}).items()}
        for k, v in attributes.items():
            if v.shape[:1] != (len(xyz),):
                raise ValueError(f"attribute {k!r} has {v.shape[:1]} values for {len(xyz)} points.")
        dtype = [(n, np.float64) for n in XYZ_PLY] + [(k, v.dtype, v.shape[1:])
                                                      for k, v in attributes.items()]
        rec = np.empty(len(xyz), dtype=dtype)
        for i, n in enumerate(XYZ_PLY):
            rec[n] = xyz[:, i]
        for k, v in attributes.items():
            rec[k] = v
        return cls(rec, "array", None, crs)

    # ---- coordinates ------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.records)

    @property
    def is_las(self) -> bool:
        return self.fmt in LAS_FORMATS

    def xyz_slice(self, start: int, stop: int, dims: int = 3) -> np.ndarray:
        """Coordinates of points ``start:stop`` as a new (m, dims) float64 array: x, y, z, or
        x, y with ``dims=2``."""
        if self._xyz is not None:
            return self._xyz[start:stop, :dims]
        rec = self._rows(start, stop)
        out = np.empty((len(rec), dims), dtype=np.float64)
        if self.is_las:
            for i, (n, s, o) in enumerate(zip("XYZ"[:dims], self.header.scales,
                                              self.header.offsets)):
                np.multiply(rec[n], s, out=out[:, i], casting="unsafe")
                out[:, i] += o
        else:
            for i, n in enumerate(XYZ_PLY[:dims]):
                out[:, i] = rec[n]
        return out

    def _rows(self, start: int, stop: int) -> np.ndarray:
        """Records ``start:stop``; from a memory-mapped file they are read with ordinary file
        reads, so scanning the whole cloud does not make the mapped file resident."""
        rec = self.records
        if isinstance(rec, np.memmap) and isinstance(rec.base, mmap.mmap) and rec.filename:
            size = rec.dtype.itemsize
            with open(rec.filename, "rb") as f:
                f.seek(rec.offset + start * size)
                out = np.fromfile(f, dtype=rec.dtype, count=stop - start)
            if len(out) == stop - start:
                return out
        return rec[start:stop]

    def iter_xyz(self, chunk_size: int = 2_000_000, dims: int = 3
                 ) -> Iterator[Tuple[int, np.ndarray]]:
        """(start, xyz of points start:start+chunk) for the whole cloud, without caching it all
        (``dims=2``: x and y only)."""
        for start in range(0, len(self), chunk_size):
            yield start, self.xyz_slice(start, min(start + chunk_size, len(self)), dims)

    @property
    def xyz(self) -> np.ndarray:
        """All coordinates, (n, 3) float64 (computed once and cached: 24 bytes per point)."""
        if self._xyz is None:
            xyz = np.empty((len(self), 3), dtype=np.float64)
            for start, chunk in self.iter_xyz():  # chunked: never all records in memory at once
                xyz[start:start + len(chunk)] = chunk
            self._xyz = xyz
        return self._xyz

    def bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """(mins, maxs) of x, y, z computed from the points (not from a file header)."""
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        for _, xyz in self.iter_xyz():
            if len(xyz):
                lo = np.minimum(lo, xyz.min(axis=0))
                hi = np.maximum(hi, xyz.max(axis=0))
        return lo, hi

    # ---- attributes -------------------------------------------------------------------------
    @property
    def attribute_names(self) -> List[str]:
        """Every per-point attribute except the coordinates (LAS: laspy dimension names)."""
        if self.is_las:
            return [n for n in self.header.point_format.dimension_names if n not in ("X", "Y", "Z")]
        return [n for n in self.records.dtype.names if n not in XYZ_PLY]

    def attribute(self, name: str) -> np.ndarray:
        """One attribute as a numpy array (LAS bit fields unpacked, e.g. ``return_number``)."""
        if self.is_las:
            import laspy
            return np.asarray(laspy.PackedPointRecord(self.records, self.header.point_format)[name])
        return np.asarray(self.records[name])

    def take(self, index: np.ndarray) -> "PointCloud":
        """A new in-memory cloud of the points at ``index`` (same format, header and CRS)."""
        sub = PointCloud(self.records[np.asarray(index)], self.fmt, self.header, self.crs, self.path)
        sub.file_crs, sub.notes = self.file_crs, list(self.notes)
        if self._xyz is not None:
            sub._xyz = self._xyz[index]
        return sub

    def take_sorted(self, index: np.ndarray, chunk_size: int = 4_000_000) -> "PointCloud":
        """Like :meth:`take` for ascending ``index``, reading the records chunk by chunk in
        file order (fast and without making a memory-mapped file resident)."""
        index = np.asarray(index, dtype=np.int64)
        parts = []
        for start in range(0, len(self), chunk_size):
            a, b = np.searchsorted(index, [start, start + chunk_size])
            if b > a:
                rows = self._rows(start, min(start + chunk_size, len(self)))
                parts.append(gather_records(rows, index[a:b] - start))
        rec = np.concatenate(parts) if parts else self.records[:0].copy()
        sub = PointCloud(np.asarray(rec), self.fmt, self.header, self.crs, self.path)
        sub.file_crs, sub.notes = self.file_crs, list(self.notes)
        if self._xyz is not None:
            sub._xyz = self._xyz[index]
        if getattr(self, "_las_template", None) is not None:
            sub._las_template = self._las_template
        return sub

    def __repr__(self) -> str:
        crs = self.crs.name if self.crs is not None else "no CRS"
        src = f" from {self.path.name}" if self.path else ""
        return f"<PointCloud {len(self)} points, {self.fmt}{src}, {crs}>"


def gather_records(records: np.ndarray, index) -> np.ndarray:
    """``records[index]``, gathered as opaque items when the records are in memory and
    contiguous: a structured dtype's fancy indexing copies field by field, 6× slower on LAS
    records."""
    index = np.asarray(index)
    if isinstance(records, np.memmap) or not records.flags.c_contiguous or records.ndim != 1 \
            or index.dtype == bool:
        return records[index]
    return np.take(records.view(f"V{records.dtype.itemsize}"), index).view(records.dtype)
