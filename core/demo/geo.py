"""Map ↔ geocentric for the writers, and the CRS texts they write.

The demo map CRS is WGS 84 / UTM 54N (EPSG:32654) with ellipsoidal heights; the Metashape
chunk is referenced in WGS 84 (EPSG:4326) and its transform goes to WGS 84 geocentric
(EPSG:4978). The WKT texts are fixed strings, so files do not change with the PROJ version.
"""
from functools import lru_cache

import numpy as np
from pyproj import CRS

from ..crs import transform_columns, transformer
from ..reconstruction import enu_rotation

MAP_EPSG = 32654
# WGS 84 / UTM 54N as GDAL writes WKT1 (Pix4D *_wkt.prj, GeoPackage, LAS).
UTM54_WKT = (
    'PROJCS["WGS 84 / UTM zone 54N",GEOGCS["WGS 84",DATUM["WGS_1984",SPHEROID["WGS 84",6378137,'
    '298.257223563,AUTHORITY["EPSG","7030"]],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,'
    'AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],'
    'AUTHORITY["EPSG","4326"]],PROJECTION["Transverse_Mercator"],PARAMETER["latitude_of_origin",0],'
    'PARAMETER["central_meridian",141],PARAMETER["scale_factor",0.9996],'
    'PARAMETER["false_easting",500000],PARAMETER["false_northing",0],UNIT["metre",1,'
    'AUTHORITY["EPSG","9001"]],AXIS["Easting",EAST],AXIS["Northing",NORTH],AUTHORITY["EPSG","32654"]]')
# WGS 84 as Metashape 1.x writes the chunk <reference>.
METASHAPE_WGS84_WKT = (
    'GEOGCS["WGS 84",DATUM["World Geodetic System 1984",SPHEROID["WGS 84",6378137,298.257223563,'
    'AUTHORITY["EPSG","7030"]],TOWGS84[0,0,0,0,0,0,0],AUTHORITY["EPSG","6326"]],PRIMEM["Greenwich",0,'
    'AUTHORITY["EPSG","8901"]],UNIT["degree",0.01745329251994328,AUTHORITY["EPSG","9102"]],'
    'AUTHORITY["EPSG","4326"]]')


@lru_cache(maxsize=8)
def _t(src: int, dst: int):
    return transformer(CRS.from_epsg(src), CRS.from_epsg(dst))


def map_to_ecef(xyz: np.ndarray) -> np.ndarray:
    """(n, 3) EPSG:32654 + ellipsoidal height → (n, 3) WGS 84 geocentric (m)."""
    x, y, z = transform_columns(_t(MAP_EPSG, 4978), xyz[:, 0], xyz[:, 1], xyz[:, 2])
    return np.column_stack([x, y, z])


def map_to_lonlat(xyz: np.ndarray) -> np.ndarray:
    """(n, 3) EPSG:32654 → (n, 3) longitude, latitude (degrees), ellipsoidal height."""
    x, y, z = transform_columns(_t(MAP_EPSG, 4326), xyz[:, 0], xyz[:, 1], xyz[:, 2])
    return np.column_stack([x, y, z])


class ENUFrame:
    """A Cartesian east-north-up frame at the local origin (the map ``offset``), for fitting the
    geocentric camera poses: ``enu(local)`` maps local points (map − offset) exactly."""

    def __init__(self, offset: np.ndarray):
        self.offset = np.asarray(offset, dtype=np.float64)
        self.origin = map_to_ecef(self.offset[None])[0]
        lon, lat, _ = map_to_lonlat(self.offset[None])[0]
        self.rotation = enu_rotation(lon, lat)

    def enu(self, local: np.ndarray) -> np.ndarray:
        return (map_to_ecef(local + self.offset) - self.origin) @ self.rotation.T

    def to_ecef(self, enu: np.ndarray) -> np.ndarray:
        return enu @ self.rotation + self.origin
