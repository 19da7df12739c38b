"""A Metashape chunk in CH1903+ / LV95 (issue 24), shared by the core and QGIS tests of the
project CRS: Metashape's WKT of it, one 500 m off, and a cameras XML with one nadir camera."""
import numpy as np
from pyproj import CRS, Transformer

# as Metashape writes it (sic: "recitified"), from a real CH1903+/LV95 project
LV95_METASHAPE = (
    'PROJCS["CH1903+ / LV95",GEOGCS["CH1903+",DATUM["CH1903+",SPHEROID["Bessel 1841",6377397.155,'
    '299.1528128,AUTHORITY["EPSG","7004"]],TOWGS84[674.374,15.056,405.346,0,0,0,0],AUTHORITY['
    '"EPSG","6150"]],PRIMEM["Greenwich",0,AUTHORITY["EPSG","8901"]],UNIT["degree",'
    '0.01745329251994328,AUTHORITY["EPSG","9102"]],AUTHORITY["EPSG","4150"]],PROJECTION['
    '"Oblique_Mercator",AUTHORITY["EPSG","9815"]],PARAMETER["latitude_of_center",'
    '46.95240555555561],PARAMETER["longitude_of_center",7.439583333333329],PARAMETER["azimuth",'
    '90],PARAMETER["recitified_grid_angle",90],PARAMETER["scale_factor",1],PARAMETER['
    '"false_easting",2600000],PARAMETER["false_northing",1200000],UNIT["metre",1,AUTHORITY['
    '"EPSG","9001"]],AUTHORITY["EPSG","2056"]]')
LV95_NO_AUTHORITY = LV95_METASHAPE[:LV95_METASHAPE.rindex(',AUTHORITY["EPSG","2056"]]')] + "]"
# the Metashape LV95 with a false easting 500 m off: PROJ cannot use it, no EPSG code agrees
LV95_SHIFTED = LV95_NO_AUTHORITY.replace("2600000", "2600500")

W, H, F = 1000, 800, 1000.0
CENTRE_LV95 = (2600100.0, 1200200.0, 600.0)       # camera centre, LV95 + ellipsoidal height (m)


def _enu(lon, lat):
    lo, la = np.radians(lon), np.radians(lat)
    return np.array([[-np.sin(lo), np.cos(lo), 0.0],
                     [-np.sin(la) * np.cos(lo), -np.sin(la) * np.sin(lo), np.cos(la)],
                     [np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)]])


def chunk_xml(tmp_path, reference):
    """A cameras XML with one nadir camera (x east, y south) over Bern; the chunk frame is the
    CH1903+ geocentric frame (Bessel), as Metashape's chunk transform gives it."""
    lv95 = CRS.from_epsg(2056)
    ecef = CRS.from_proj4("+proj=geocent +ellps=bessel +units=m +no_defs")  # CH1903+ geocentric
    to_ecef = Transformer.from_crs(lv95, ecef, always_xy=True)
    C = np.array(to_ecef.transform(*CENTRE_LV95))
    lon, lat = Transformer.from_crs(lv95, lv95.geodetic_crs, always_xy=True).transform(*CENTRE_LV95[:2])
    E = _enu(lon, lat)
    R = np.column_stack([E[0], -E[1], -E[2]])               # camera axes in the chunk frame
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, C
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<document version="1.4.0"><chunk label="LV95" enabled="true">
  <sensors><sensor id="0" label="thermal" type="frame"><resolution width="{W}" height="{H}"/>
    <calibration type="frame" class="adjusted"><resolution width="{W}" height="{H}"/>
    <f>{F}</f></calibration></sensor></sensors>
  <cameras><camera id="0" sensor_id="0" label="IMG_0001"><transform>{' '.join(repr(float(v)) for v in T.ravel())}</transform></camera></cameras>
  <reference>{reference}</reference>
</chunk></document>"""
    p = tmp_path / "cameras.xml"
    p.write_text(xml)
    return p, to_ecef
