"""GeoPackage polygon layers (OGC 12-128r18, QGIS's default vector format) with the standard
library's sqlite3: the CRS from ``gpkg_spatial_ref_sys``, geometries from GeoPackage binary
blobs (a header, then WKB: Polygon or MultiPolygon, ISO or extended Z/M codes; Z kept, M
dropped), attributes as feature properties, the feature id (``fid``) as the default name.
"""
import os
import sqlite3
import struct
from pathlib import Path
from typing import List, Optional, Tuple

from pyproj import CRS

from ..errors import InputError
from ..gpkg import quote_identifier
from .features import rois_from_features
from .model import ROISet

ENVELOPE_DOUBLES = {0: 0, 1: 4, 2: 6, 3: 6, 4: 8}     # header envelope code → doubles
WKB_POLYGON, WKB_MULTIPOLYGON = 3, 6


def read_geopackage(path, name_field: Optional[str] = None, crs=None,
                    layer: Optional[str] = None) -> ROISet:
    """ROIs from a polygon layer of a GeoPackage (``layer``: its table name; needed only when
    the file holds several feature layers). The CRS is ``crs`` when given, else the layer's."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"ROI file not found: {path}")
    try:
        # read-only, through a URI (percent-encoded: names with '#', '?' or spaces open too)
        con = sqlite3.connect(Path(path).resolve().as_uri() + "?mode=ro", uri=True)
    except sqlite3.Error as exc:
        raise InputError(f"{path} cannot be opened as a GeoPackage ({exc}).") from None
    try:
        table, column, srs_id = _layer(con, path, layer)
        layer_crs = _crs(con, path, srs_id)
        cur = con.execute(f"SELECT * FROM {quote_identifier(table)}")  # nosec B608 -- quoted name
        names = [d[0] for d in cur.description]
        pk = _primary_key(con, table)
        features = []
        for row in cur:
            props = dict(zip(names, row))
            blob = props.pop(column)
            fid = props.pop(pk, None) if pk else None
            where = f"{path}, layer {table!r}, feature {fid}"
            features.append({"id": fid if fid is not None else len(features),
                             "geometry": None if blob is None else geometry(bytes(blob), where),
                             "properties": props})
    except sqlite3.Error as exc:
        raise InputError(f"{path}: the GeoPackage cannot be read ({exc}); it may be damaged. "
                         "Open it in QGIS and save the layer again.") from None
    finally:
        con.close()
    if crs is None and layer_crs is None:
        raise InputError(f"{path}, layer {table!r}: its CRS is undefined. Give the CRS "
                         "(crs='EPSG:…'), or set the layer's CRS in QGIS and save it again.")
    return rois_from_features(features, crs if crs is not None else layer_crs, name_field,
                              f"{path}, layer {table!r}")


def _layer(con, path: str, layer: Optional[str]) -> Tuple[str, str, int]:
    """(table, geometry column, srs_id) of the polygon layer to read."""
    try:
        rows = con.execute("SELECT c.table_name, g.column_name, g.srs_id, g.geometry_type_name "
                           "FROM gpkg_contents c JOIN gpkg_geometry_columns g "
                           "ON c.table_name = g.table_name "
                           "WHERE c.data_type = 'features' ORDER BY c.table_name").fetchall()
    except sqlite3.DatabaseError:
        raise InputError(f"{path} is not a GeoPackage (no gpkg_contents and "
                         "gpkg_geometry_columns tables).") from None
    if not rows:
        raise InputError(f"{path} holds no feature layer (no geometries).")
    if layer is None:
        if len(rows) > 1:
            raise InputError(f"{path} holds {len(rows)} feature layers "
                             f"({', '.join(r[0] for r in rows)}): say which (layer='…').")
        found = rows[0]
    else:
        found = next((r for r in rows if r[0] == layer), None)
        if found is None:
            raise InputError(f"{path} has no feature layer {layer!r}; its layers are "
                             f"{', '.join(r[0] for r in rows)}.")
    table, column, srs_id, kind = found
    if kind.upper() not in ("POLYGON", "MULTIPOLYGON", "GEOMETRY", "MULTISURFACE",
                            "CURVEPOLYGON"):
        raise InputError(f"{path}, layer {table!r} holds {kind} geometries, not polygons: ROIs "
                         "must be polygons (buffer points or lines first).")
    return table, column, srs_id


def _crs(con, path: str, srs_id: int) -> Optional[CRS]:
    """The layer's CRS: its EPSG code, else its WKT; None for the undefined systems."""
    row = con.execute("SELECT organization, organization_coordsys_id, definition "
                      "FROM gpkg_spatial_ref_sys WHERE srs_id = ?", (srs_id,)).fetchone()
    if row is None or srs_id in (0, -1) or (row[2] or "").strip().lower() == "undefined":
        return None
    org, code, definition = row
    try:
        if (org or "").upper() == "EPSG":
            return CRS.from_epsg(int(code))
        return CRS.from_wkt(definition)
    except Exception:                     # pyproj: an unknown code or WKT
        raise InputError(f"{path}: the layer's CRS (srs_id {srs_id}, {org}:{code}) cannot be "
                         "understood. Give the CRS (crs='EPSG:…').") from None


def _primary_key(con, table: str) -> Optional[str]:
    return next((r[1] for r in con.execute("SELECT * FROM pragma_table_info(?)", (table,))
                 if r[5]), None)


def geometry(blob: bytes, where: str) -> Optional[dict]:
    """A GeoPackage geometry blob → a GeoJSON-like Polygon/MultiPolygon dict (None if empty)."""
    if len(blob) < 8 or blob[:2] != b"GP":
        raise InputError(f"{where}: the geometry is not a GeoPackage geometry blob.")
    flags = blob[3]
    if flags & 0b100000:
        raise InputError(f"{where}: the geometry uses an extended GeoPackage geometry type, "
                         "which I do not read. Save the layer again from QGIS.")
    if flags & 0b10000:
        return None                                       # the empty flag
    envelope = ENVELOPE_DOUBLES.get((flags >> 1) & 0b111)
    if envelope is None:
        raise InputError(f"{where}: the geometry header is damaged (envelope code).")
    kind, payload = _WKB(blob, 8 + 8 * envelope, where).geometry()
    if kind == WKB_POLYGON:
        return {"type": "Polygon", "coordinates": payload}
    return {"type": "MultiPolygon", "coordinates": payload}


class _WKB:
    """A reader of WKB polygons and multipolygons from ``offset`` of ``data``."""

    def __init__(self, data: bytes, offset: int, where: str):
        self.data, self.pos, self.where = data, offset, where

    def _take(self, fmt: str):
        size = struct.calcsize(fmt)
        if self.pos + size > len(self.data):
            raise InputError(f"{self.where}: the geometry is truncated.")
        out = struct.unpack_from(fmt, self.data, self.pos)
        self.pos += size
        return out

    def _header(self) -> Tuple[str, int, int, bool]:
        (order,) = self._take("B")
        if order not in (0, 1):
            raise InputError(f"{self.where}: the geometry is damaged (WKB byte order {order}).")
        e = "<" if order == 1 else ">"
        (code,) = self._take(e + "I")
        has_z = bool(code & 0x80000000) or (code % 10000) // 1000 in (1, 3)
        has_m = bool(code & 0x40000000) or (code % 10000) // 1000 in (2, 3)
        base = (code & 0x0FFFFFFF) % 1000
        return e, base, 2 + has_z + has_m, has_z

    def geometry(self):
        e, base, dims, has_z = self._header()
        if base == WKB_POLYGON:
            return base, self._polygon(e, dims, has_z)
        if base == WKB_MULTIPOLYGON:
            (n,) = self._take(e + "I")
            parts = []
            for _ in range(n):
                pe, pbase, pdims, pz = self._header()
                if pbase != WKB_POLYGON:
                    raise InputError(f"{self.where}: a multipolygon holds a geometry of WKB "
                                     f"type {pbase}, not a polygon.")
                parts.append(self._polygon(pe, pdims, pz))
            return base, parts
        names = {1: "a point", 2: "a line", 4: "a multipoint", 5: "a multiline",
                 7: "a geometry collection", 10: "a curved polygon", 15: "a polyhedral surface"}
        raise InputError(f"{self.where} is {names.get(base, f'WKB type {base}')}, not a polygon: "
                         "ROIs must be polygons (QGIS: Vector geometry ▸ Buffer, or Segmentize "
                         "for curves).")

    def _polygon(self, e: str, dims: int, has_z: bool) -> List[list]:
        (rings,) = self._take(e + "I")
        out = []
        for _ in range(rings):
            (n,) = self._take(e + "I")
            flat = self._take(e + "d" * (n * dims))
            keep = 3 if has_z else 2
            out.append([list(flat[i * dims:i * dims + keep]) for i in range(n)])
        return out
