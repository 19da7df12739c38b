"""A minimal GeoPackage writer for one polygon layer (OGC 12-128r18), with the standard library.

Writes the required tables (``gpkg_spatial_ref_sys``, ``gpkg_contents``,
``gpkg_geometry_columns``) and one feature table whose geometries are GeoPackage binary blobs
(header with an xy envelope, then little-endian WKB). No spatial index; readers (GDAL, QGIS)
do not need one for a few dozen features. The file is written atomically.
"""
import sqlite3
import struct
from typing import Dict, List, Sequence

import numpy as np

from ..files import atomic_output

LAST_CHANGE = "2024-06-01T12:00:00.000Z"   # fixed, so the same input gives the same bytes


def _blob(rings: Sequence[np.ndarray], srs_id: int) -> bytes:
    """GeoPackage geometry blob of a polygon (closed rings, exterior first)."""
    allpts = np.vstack(rings)
    env = (allpts[:, 0].min(), allpts[:, 0].max(), allpts[:, 1].min(), allpts[:, 1].max())
    head = b"GP" + bytes([0, 0b00000011]) + struct.pack("<i4d", srs_id, *env)
    wkb = struct.pack("<BII", 1, 3, len(rings))
    for r in rings:
        wkb += struct.pack("<I", len(r)) + np.ascontiguousarray(r, "<f8").tobytes()
    return head + wkb


def write_gpkg_polygons(path: str, layer: str, polygons: List[np.ndarray],
                        attributes: List[Dict], fields: Dict[str, str], epsg: int,
                        srs_name: str, srs_wkt: str) -> str:
    """Write ``polygons`` (each an (n, 2) closed exterior ring) with ``attributes`` (dicts with
    the keys of ``fields``: name → SQL type, TEXT/INTEGER/REAL) as layer ``layer``."""
    with atomic_output(path) as tmp:
        con = sqlite3.connect(tmp)
        try:
            _fill(con, layer, polygons, attributes, fields, epsg, srs_name, srs_wkt)
            con.commit()
        finally:
            con.close()
    return path


def _fill(con, layer, polygons, attributes, fields, epsg, srs_name, srs_wkt) -> None:
    """The GeoPackage tables and the features, through the connection ``con``."""
    c = con.cursor()
    c.execute("PRAGMA application_id = 1196444487")      # 'GPKG'
    c.execute("PRAGMA user_version = 10200")
    c.execute("""CREATE TABLE gpkg_spatial_ref_sys (srs_name TEXT NOT NULL,
        srs_id INTEGER NOT NULL PRIMARY KEY, organization TEXT NOT NULL,
        organization_coordsys_id INTEGER NOT NULL, definition TEXT NOT NULL, description TEXT)""")
    c.executemany("INSERT INTO gpkg_spatial_ref_sys VALUES (?,?,?,?,?,?)", [
        ("Undefined cartesian SRS", -1, "NONE", -1, "undefined", "undefined cartesian coordinate reference system"),
        ("Undefined geographic SRS", 0, "NONE", 0, "undefined", "undefined geographic coordinate reference system"),
        ("WGS 84 geodetic", 4326, "EPSG", 4326,
         'GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,298.257223563,'
         'AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,'
         'AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],'
         'AXIS["Latitude",NORTH],AXIS["Longitude",EAST],AUTHORITY["EPSG","4326"]]',
         "longitude/latitude coordinates in decimal degrees on the WGS 84 spheroid"),
        (srs_name, epsg, "EPSG", epsg, srs_wkt, None)])
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
    cols = "".join(f', "{k}" {v}' for k, v in fields.items())
    c.execute(f'CREATE TABLE "{layer}" (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, '
              f'geom POLYGON{cols})')
    allpts = np.vstack(polygons)
    c.execute("INSERT INTO gpkg_contents VALUES (?,?,?,?,?,?,?,?,?,?)",
              (layer, "features", layer, "", LAST_CHANGE, float(allpts[:, 0].min()),
               float(allpts[:, 1].min()), float(allpts[:, 0].max()), float(allpts[:, 1].max()), epsg))
    c.execute("INSERT INTO gpkg_geometry_columns VALUES (?,?,?,?,?,?)",
              (layer, "geom", "POLYGON", epsg, 0, 0))
    names = list(fields)
    columns = "".join(f', "{n}"' for n in names)
    marks = ",".join("?" * (len(names) + 1))
    c.executemany(f'INSERT INTO "{layer}" (geom{columns}) VALUES ({marks})',
                  [(_blob([p], epsg), *(a[n] for n in names)) for p, a in zip(polygons, attributes)])
