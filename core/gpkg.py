"""A GeoPackage writer (OGC 12-128r18) with the standard library: attribute tables and
(multi)polygon layers in one file, written atomically.

Each :class:`GpkgTable` becomes a table registered in ``gpkg_contents``: ``attributes`` when it
has no geometries, else ``features`` with a ``MULTIPOLYGON`` column ``geom`` (GeoPackage binary:
a header with the xy envelope, then little-endian WKB) in the table's CRS. No spatial index:
GDAL and QGIS read such files as they are. Values None and NaN are written as NULL.

Many records at once: :func:`encoded_multipolygons` encodes a ``core.geometry.FlatPolygons``
in one numpy pass (``core.wkb``), envelopes included, for ``GpkgTable.geometries`` (47,477
back-projection features: about 0.2 s of CPU for the whole file, where QGIS's feature sink
took about 0.8 s with its spatial index).
"""
import math
import sqlite3
import struct
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple, Union

import numpy as np

from .crs import as_crs
from .files import atomic_output
from .wkb import flat_multipolygons_wkb

LAST_CHANGE = "2024-06-01T12:00:00.000Z"   # fixed: the same data gives the same file
CUSTOM_SRS_ID = 100000                      # first id for CRSs without an EPSG code
SQL_TYPES = ("TEXT", "INTEGER", "REAL", "MEDIUMINT", "BOOLEAN")
"""Field types: GDAL reads MEDIUMINT as a 32-bit integer and BOOLEAN as a boolean (what QGIS
writes for its Int and Bool fields), INTEGER as a 64-bit integer."""

_WGS84_WKT = ('GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,'
              'AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,'
              'AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],'
              'AXIS["Latitude",NORTH],AXIS["Longitude",EAST],AUTHORITY["EPSG","4326"]]')


@dataclass
class EncodedMultipolygons:
    """Multipolygons already encoded, one per row: ``wkb`` (ISO WKB MultiPolygon, little-endian)
    and ``envelopes`` (n, 4) float64 ``(min_x, max_x, min_y, max_y)``, NaN for an empty one.
    Made by :func:`encoded_multipolygons`."""
    wkb: Sequence[bytes]
    envelopes: np.ndarray

    def __len__(self) -> int:
        return len(self.wkb)


@dataclass
class GpkgTable:
    """``fields``: (name, SQL type, one of :data:`SQL_TYPES`); ``rows``: one tuple per feature;
    ``geometries``: None (an attribute table), one multipolygon per row (a list of polygons,
    each a list of rings ((n, 2) arrays, exterior first; closed or not)), or
    :class:`EncodedMultipolygons`; ``crs``: anything pyproj accepts, or None (undefined)."""
    name: str
    fields: Sequence[Tuple[str, str]]
    rows: Sequence[Sequence[object]]
    geometries: Optional[Union[Sequence[List[List[np.ndarray]]], EncodedMultipolygons]] = None
    crs: object = None


def encoded_multipolygons(polygons, flip_y: bool = False) -> EncodedMultipolygons:
    """Every record of ``polygons`` (a ``core.geometry.FlatPolygons``) as a MultiPolygon for
    :class:`GpkgTable`, encoded in one pass (``core.wkb.flat_multipolygons_wkb``); ``flip_y``:
    y written as −y (photo pixels, as QGIS places a photo opened without georeference)."""
    xy = np.asarray(polygons.xy, np.float64).reshape(-1, 2)
    vert = np.asarray(polygons.ring_offsets, np.int64)[np.asarray(polygons.record_rings, np.int64)]
    env = np.full((len(vert) - 1, 4), np.nan)
    has = np.flatnonzero(np.diff(vert) > 0)
    if len(has):
        starts = vert[:-1][has]
        x, y = xy[:, 0], (-xy[:, 1] if flip_y else xy[:, 1])
        env[has] = np.column_stack([np.minimum.reduceat(x, starts), np.maximum.reduceat(x, starts),
                                    np.minimum.reduceat(y, starts), np.maximum.reduceat(y, starts)])
    return EncodedMultipolygons(flat_multipolygons_wkb(polygons, flip_y=flip_y), env)


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
        columns = [_sql_column(col) for col in zip(*t.rows)] if t.fields else []
        if t.geometries is None:
            c.execute(f"CREATE TABLE {table} (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL{cols})")
            c.execute("INSERT INTO gpkg_contents (table_name, data_type, identifier, last_change) "
                      "VALUES (?,?,?,?)", (t.name, "attributes", t.name, LAST_CHANGE))
            if t.fields:
                marks = ",".join("?" * len(t.fields))
                sql = f"INSERT INTO {table} ({names[2:]}) VALUES ({marks})"  # nosec B608 -- quoted names
                c.executemany(sql, zip(*columns))
            continue
        srs_id = _srs(t.crs, srs)
        c.execute(f"CREATE TABLE {table} (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
                  f"geom MULTIPOLYGON{cols})")
        if isinstance(t.geometries, EncodedMultipolygons):
            blobs = _encoded_blobs(t.geometries, srs_id)
            env = t.geometries.envelopes
            box = (np.nanmin(env[:, 0]), np.nanmin(env[:, 2]), np.nanmax(env[:, 1]),
                   np.nanmax(env[:, 3])) if np.isfinite(env[:, 0]).any() else (0.0,) * 4
        else:
            blobs = [_blob(g, srs_id) for g in t.geometries]
            pts = [ring for g in t.geometries for part in g for ring in part]
            allxy = np.vstack(pts)[:, :2] if pts else np.zeros((1, 2))
            box = (allxy[:, 0].min(), allxy[:, 1].min(), allxy[:, 0].max(), allxy[:, 1].max())
        if len(blobs) != len(t.rows):
            raise ValueError(f"GeoPackage table {t.name}: {len(blobs)} geometries for "
                             f"{len(t.rows)} rows")
        c.execute("INSERT INTO gpkg_contents VALUES (?,?,?,?,?,?,?,?,?,?)",
                  (t.name, "features", t.name, "", LAST_CHANGE, *map(float, box), srs_id))
        c.execute("INSERT INTO gpkg_geometry_columns VALUES (?,?,?,?,?,?)",
                  (t.name, "geom", "MULTIPOLYGON", srs_id, 0, 0))
        marks = ",".join("?" * (len(t.fields) + 1))
        sql = f"INSERT INTO {table} (geom{names}) VALUES ({marks})"  # nosec B608 -- quoted names
        c.executemany(sql, zip(blobs, *columns))
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


def _sql_column(values) -> Sequence[object]:
    """:func:`_sql` of a column of values, the column itself when it needs nothing: no numpy
    scalar, and no NaN or infinity, which one sum over a numeric column tells (in C: 47,477
    values in 1 ms; a sum that overflows only costs the pass value by value)."""
    kinds = set(map(type, values))
    if float not in kinds and not any(issubclass(k, np.generic) for k in kinds):
        return values
    if kinds <= {float, int, bool, type(None)} and math.isfinite(sum(filter(None, values))):
        return values
    return [_sql(v) for v in values]


def _encoded_blobs(geoms: EncodedMultipolygons, srs_id: int) -> List[bytes]:
    """GeoPackage geometry blobs of encoded multipolygons: each a header (magic, version 0,
    flags: little-endian, xy envelope; or empty without envelope) and its WKB."""
    env = np.asarray(geoms.envelopes, np.float64).reshape(-1, 4)
    empty = ~np.isfinite(env).all(axis=1)
    head = np.zeros(len(env), np.dtype([("magic", "S2"), ("version", "u1"), ("flags", "u1"),
                                        ("srs", "<i4"), ("env", "<f8", (4,))]))
    head["magic"] = b"GP"
    head["flags"] = np.where(empty, 0b00010001, 0b00000011)
    head["srs"] = srs_id
    head["env"] = np.where(empty[:, None], 0.0, env)
    raw = head.tobytes()
    size = head.itemsize
    return [raw[k * size:k * size + (8 if e else size)] + w
            for k, (e, w) in enumerate(zip(empty.tolist(), geoms.wkb))]


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
