"""A GeoPackage writer (OGC 12-128r18) with the standard library: attribute tables and
(multi)polygon layers in one file, written atomically.

Each :class:`GpkgTable` becomes a table registered in ``gpkg_contents``: ``attributes`` when it
has no geometries, else ``features`` with a ``MULTIPOLYGON`` column ``geom`` (GeoPackage binary:
a header with the xy envelope, then little-endian WKB) in the table's CRS. No spatial index:
GDAL and QGIS read such files as they are. Values None and NaN are written as NULL.
"""
import math
import sqlite3
import struct
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .crs import as_crs
from .files import atomic_output

LAST_CHANGE = "2024-06-01T12:00:00.000Z"   # fixed: the same data gives the same file
CUSTOM_SRS_ID = 100000                      # first id for CRSs without an EPSG code
SQL_TYPES = ("TEXT", "INTEGER", "REAL")

_WGS84_WKT = ('GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,'
              'AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,'
              'AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],'
              'AXIS["Latitude",NORTH],AXIS["Longitude",EAST],AUTHORITY["EPSG","4326"]]')


@dataclass
class GpkgTable:
    """``fields``: (name, SQL type TEXT/INTEGER/REAL); ``rows``: one tuple per feature;
    ``geometries``: None (an attribute table) or one multipolygon per row: a list of polygons,
    each a list of rings ((n, 2) arrays, exterior first; closed or not); ``crs``: anything
    pyproj accepts, or None (undefined)."""
    name: str
    fields: Sequence[Tuple[str, str]]
    rows: Sequence[Sequence[object]]
    geometries: Optional[Sequence[List[List[np.ndarray]]]] = None
    crs: object = None


def quote_identifier(name: str) -> str:
    """A table or column name for an SQL statement: in double quotes, each ``"`` in it doubled
    (SQLite binds values, not names, so this is how a name from a user's file enters SQL)."""
    return '"' + str(name).replace('"', '""') + '"'


def field_type(values) -> str:
    """INTEGER, REAL or TEXT for a column of Python values (None ignored)."""
    kinds = {type(v) for v in values if v is not None}
    if kinds and kinds <= {int, bool}:
        return "INTEGER"
    if kinds and kinds <= {int, bool, float}:
        return "REAL"
    return "TEXT"


def write_geopackage(path: str, tables: Sequence[GpkgTable]) -> str:
    """Write ``tables`` into a new GeoPackage at ``path`` (atomically; replaces the file)."""
    for t in tables:
        bad = [ty for _, ty in t.fields if ty not in SQL_TYPES]
        if bad:
            raise ValueError(f"GeoPackage table {t.name}: unsupported field types {bad}")
    with atomic_output(path) as tmp:
        con = sqlite3.connect(tmp)
        try:
            _write(con, tables)
            con.commit()
        finally:
            con.close()
    return path


def _write(con, tables) -> None:
    c = con.cursor()
    c.execute("PRAGMA application_id = 1196444487")      # 'GPKG'
    c.execute("PRAGMA user_version = 10200")
    c.execute("""CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL,
        srs_id INTEGER NOT NULL PRIMARY KEY, organization TEXT NOT NULL,
        organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT NULL, description TEXT)""")
    srs = {-1: ("Undefined cartesian SRS", "NONE", -1, "undefined",
                "undefined cartesian coordinate reference system"),
           0: ("Undefined geographic SRS", "NONE", 0, "undefined",
               "undefined geographic coordinate reference system"),
           4326: ("WGS 84 geodetic", "EPSG", 4326, _WGS84_WKT,
                  "longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid")}
    c.execute("""CREATE TABLE gpkg_contents (table_name TEXT NOT NULL PRIMARY KEY,
        data_type TEXT NOT NULL, identifier TEXT UNIQUE, description TEXT DEFAULT '',
        last_change DATETIME NOT NULL, min_x DOUBLE, min_y DOUBLE, max_x DOUBLE, max_y DOUBLE,
        srs_id INTEGER, CONSTRAINT fk_gc_r_srs_id FOREIGN KEY (srs_id)
        REFERENCES gpkg_spatial_ref_sys(srs_id))""")
    c.execute("""CREATE TABLE gpkg_geometry_columns (table_name TEXT NOT NULL,
        column_name TEXT NOT NULL, geometry_type_name TEXT NOT NULL, srs_id INTEGER NOT NULL,
        z TINYINT NOT NULL, m TINYINT NOT NULL,
        CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),
        CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),
        CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id))""")
    for t in tables:
        # SQL below (B608 reviewed): names only through quote_identifier, types from SQL_TYPES,
        # values bound
        table = quote_identifier(t.name)
        cols = "".join(f", {quote_identifier(n)} {ty}" for n, ty in t.fields)
        names = "".join(f", {quote_identifier(n)}" for n, _ in t.fields)
        values = [tuple(_sql(v) for v in row) for row in t.rows]
        if t.geometries is None:
            c.execute(f"CREATE TABLE {table} (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL{cols})")
            c.execute("INSERT INTO gpkg_contents (table_name, data_type, identifier, last_change) "
                      "VALUES (?,?,?,?)", (t.name, "attributes", t.name, LAST_CHANGE))
            if t.fields:
                marks = ",".join("?" * len(t.fields))
                sql = f"INSERT INTO {table} ({names[2:]}) VALUES ({marks})"  # nosec B608 -- quoted names
                c.executemany(sql, values)
            continue
        srs_id = _srs(t.crs, srs)
        c.execute(f"CREATE TABLE {table} (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
                  f"geom MULTIPOLYGON{cols})")
        pts = [ring for g in t.geometries for part in g for ring in part]
        allxy = np.vstack(pts) if pts else np.zeros((1, 2))
        c.execute("INSERT INTO gpkg_contents VALUES (?,?,?,?,?,?,?,?,?,?)",
                  (t.name, "features", t.name, "", LAST_CHANGE, float(allxy[:, 0].min()),
                   float(allxy[:, 1].min()), float(allxy[:, 0].max()), float(allxy[:, 1].max()),
                   srs_id))
        c.execute("INSERT INTO gpkg_geometry_columns VALUES (?,?,?,?,?,?)",
                  (t.name, "geom", "MULTIPOLYGON", srs_id, 0, 0))
        marks = ",".join("?" * (len(t.fields) + 1))
        sql = f"INSERT INTO {table} (geom{names}) VALUES ({marks})"  # nosec B608 -- quoted names
        c.executemany(sql, [(_blob(g, srs_id), *row) for g, row in zip(t.geometries, values)])
    c.executemany("INSERT INTO gpkg_spatial_ref_sys VALUES (?,?,?,?,?,?)",
                  [(v[0], k, v[1], v[2], v[3], v[4]) for k, v in sorted(srs.items())])


def _srs(crs, srs: dict) -> int:
    """The srs_id of ``crs`` in ``srs`` (added when new): its EPSG code, or a custom id."""
    crs = as_crs(crs, "GeoPackage CRS")
    if crs is None:
        return -1
    code = crs.to_epsg()
    try:
        from pyproj.enums import WktVersion
        wkt = crs.to_wkt(WktVersion.WKT1_GDAL)
    except Exception:  # a CRS that WKT1 cannot express
        wkt = crs.to_wkt()
    if code is not None:
        srs.setdefault(code, (crs.name, "EPSG", code, wkt, None))
        return code
    for k, v in srs.items():
        if v[3] == wkt:
            return k
    k = max(CUSTOM_SRS_ID - 1, *srs) + 1
    srs[k] = (crs.name, "NONE", k, wkt, None)
    return k


def _sql(v):
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.generic):
        return _sql(v.item())
    return v


def _ring(r: np.ndarray) -> bytes:
    r = np.asarray(r, np.float64)[:, :2]
    if len(r) and not np.array_equal(r[0], r[-1]):
        r = np.vstack([r, r[:1]])
    return struct.pack("<I", len(r)) + np.ascontiguousarray(r, "<f8").tobytes()


def _blob(parts: List[List[np.ndarray]], srs_id: int) -> bytes:
    """GeoPackage geometry blob of a multipolygon (little-endian WKB with an xy envelope)."""
    pts = [np.asarray(r)[:, :2] for p in parts for r in p]
    if not pts:
        return b"GP" + bytes([0, 0b00010001]) + struct.pack("<i", srs_id) + \
            struct.pack("<BII", 1, 6, 0)        # empty flag set, no envelope
    allxy = np.vstack(pts)
    env = (allxy[:, 0].min(), allxy[:, 0].max(), allxy[:, 1].min(), allxy[:, 1].max())
    head = b"GP" + bytes([0, 0b00000011]) + struct.pack("<i4d", srs_id, *env)
    wkb = struct.pack("<BII", 1, 6, len(parts))
    for p in parts:
        wkb += struct.pack("<BII", 1, 3, len(p)) + b"".join(_ring(r) for r in p)
    return head + wkb
