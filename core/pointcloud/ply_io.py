"""PLY reading and writing with plyfile (ASCII, binary little- and big-endian).

The vertex element is kept as its structured array: every property with its own dtype (colours
of any dtype untouched, normals, scalar fields, list properties). Coordinates are the x/y/z
properties converted to float64 (float64 PLY coordinates stay exact). PLY has no CRS: the
caller gives it. Other elements (faces…) are not carried through a crop (their indices change).
"""
from pathlib import Path
from typing import Optional

import numpy as np

from ..crs import as_crs
from ..errors import InputError, reads_file
from .cloud import XYZ_PLY, PlyHeader, PointCloud
from ..files import atomic_output, check_not_inputs

# numpy kinds plyfile can write; 64-bit integers (e.g. from LAS extra bytes) go to float64
_PLY_OK = {"i1", "u1", "i2", "u2", "i4", "u4", "f4", "f8"}


@reads_file("Export or copy the point cloud again.")
def read_ply(path, crs=None) -> PointCloud:
    """Read the vertex element of a PLY file (binary files are memory-mapped copy-on-write)."""
    from plyfile import PlyData
    path = Path(path)
    if not path.is_file():
        raise InputError(f"Point cloud {str(path)!r} does not exist: check the path.")
    try:
        ply = PlyData.read(str(path))
    except Exception as exc:
        raise InputError(f"Point cloud {path.name!r} cannot be read as PLY ({exc}). Check that the "
                         "file is complete and really a PLY file.") from None
    names = [e.name for e in ply.elements]
    if "vertex" not in names:
        raise InputError(f"PLY file {path.name!r} has no 'vertex' element (it has "
                         f"{names or 'no elements'}): it holds no points.")
    vertex = ply["vertex"]
    props = [p.name for p in vertex.properties]
    missing = [c for c in XYZ_PLY if c not in props]
    if missing:
        raise InputError(f"PLY file {path.name!r} has no {'/'.join(missing)} vertex properties "
                         f"(it has {', '.join(props) or 'none'}): a point cloud needs x, y and z.")
    header = PlyHeader(text=ply.text, byte_order=ply.byte_order, comments=list(ply.comments),
                       obj_info=list(ply.obj_info), other_elements=[n for n in names if n != "vertex"])
    return PointCloud(vertex.data, "ply", header, as_crs(crs, f"CRS of {path.name}"), path)


def _ply_records(cloud: PointCloud) -> np.ndarray:
    """A structured array plyfile can write: x/y/z float64 first, then every attribute
    (bool → uint8, 64-bit integers → float64, fixed-size array fields split into name_0…)."""
    if cloud.fmt in ("ply", "array") and all(
            _ok(cloud.records.dtype[n]) for n in cloud.records.dtype.names):
        return np.asarray(cloud.records)
    xyz = cloud.xyz
    cols = [(n, xyz[:, i]) for i, n in enumerate(XYZ_PLY)]
    for name in cloud.attribute_names:
        v = np.asarray(cloud.attribute(name))
        parts = [(name, v)] if v.ndim == 1 else [(f"{name}_{k}", v[:, k]) for k in range(v.shape[1])]
        for pname, pv in parts:
            if pv.dtype.kind == "b":
                pv = pv.astype(np.uint8)
            elif pv.dtype.kind != "O" and pv.dtype.str[1:] not in _PLY_OK:
                pv = pv.astype(np.float64)
            cols.append((pname, pv))
    out = np.empty(len(xyz), dtype=[(n, v.dtype) for n, v in cols])
    for n, v in cols:
        out[n] = v
    return out


def _ok(dt: np.dtype) -> bool:
    return dt.kind == "O" or (not dt.shape and dt.str[1:] in _PLY_OK)


def write_ply(cloud: PointCloud, path, text: Optional[bool] = None,
              index: Optional[np.ndarray] = None) -> Path:
    """Write ``cloud`` (or its points at ``index``) as a PLY vertex element; atomic.

    ``text``: ASCII when True, binary when False; default: the source PLY's encoding, else binary
    little-endian. A PLY source keeps its property dtypes, byte order, comments and obj_info; the
    CRS is recorded as a ``comment crs <AUTH:code or WKT1>`` line for information only (PLY has no CRS).
    """
    from plyfile import PlyData, PlyElement
    path = Path(path)
    check_not_inputs(path, [cloud.path])
    if index is not None:
        cloud = cloud.take(index)
    src = cloud.header if isinstance(cloud.header, PlyHeader) else PlyHeader()
    text = src.text if text is None else bool(text)
    records = _ply_records(cloud)
    comments = [c for c in src.comments if not c.startswith("crs ")]
    if cloud.crs is not None:
        auth = cloud.crs.to_authority()
        text_crs = ":".join(auth) if auth else cloud.crs.to_wkt("WKT1_GDAL").replace("\n", " ")
        comments.append("crs " + text_crs.encode("ascii", "replace").decode("ascii"))
    byte_order = src.byte_order if src.byte_order in "<>" else "<"
    el = PlyElement.describe(np.ascontiguousarray(records), "vertex")
    ply = PlyData([el], text=text, byte_order=byte_order, comments=comments,
                  obj_info=list(src.obj_info))
    with atomic_output(path) as tmp:
        ply.write(str(tmp))
    return path
