"""CRSs between QGIS and the core: QGIS CRS → the core's CRS text, pyproj CRS → QGIS CRS."""
from qgis.core import QgsCoordinateReferenceSystem

from .compat import CrsWktVariant


UNDEFINED_NAMES = ("undefined geographic srs", "undefined cartesian srs", "undefined srs")
"""What QGIS shows for a GeoPackage layer without a CRS: GDAL writes such a layer with
``srs_id`` 0 ("Undefined geographic SRS") or -1 ("Undefined Cartesian SRS"), and QGIS reads
each as a valid CRS of that name (OGC 12-128r18, 1.1.2.1.1); newer GDAL (3.10 in Debian 13)
writes ``srs_id`` 99999 ("Undefined SRS") instead."""


def has_crs(crs: QgsCoordinateReferenceSystem) -> bool:
    """Whether a layer CRS says where the layer is: valid, and not one of the GeoPackage's
    undefined SRSs (:data:`UNDEFINED_NAMES`). Photo-pixel layers, written with the undefined
    Cartesian CRS on purpose, have none either."""
    if crs is None or not crs.isValid():
        return False
    return bool(crs.authid()) or crs.description().lower() not in UNDEFINED_NAMES


def crs_string(crs: QgsCoordinateReferenceSystem):
    """An EPSG code when QGIS knows one, else WKT; None for an invalid CRS or a GeoPackage's
    undefined one (:func:`has_crs`)."""
    if not has_crs(crs):
        return None
    if crs.authid().upper().startswith("EPSG:"):
        return crs.authid()
    return crs.toWkt(CrsWktVariant.Preferred)


def pixel_crs() -> QgsCoordinateReferenceSystem:
    """The CRS photo-pixel layers are written with: an undefined engineering (Cartesian) CRS
    (GeoPackage srs_id −1), see ``core.projection.PIXEL_CRS_WKT``."""
    from ..core.projection import PIXEL_CRS_WKT
    return QgsCoordinateReferenceSystem.fromWkt(PIXEL_CRS_WKT)


def qgis_crs(crs) -> QgsCoordinateReferenceSystem:
    """A QgsCoordinateReferenceSystem from a pyproj CRS (by EPSG code when it has one), or an
    invalid one for None."""
    if crs is None:
        return QgsCoordinateReferenceSystem()
    code = crs.to_epsg(min_confidence=100)
    if code:
        return QgsCoordinateReferenceSystem(f"EPSG:{code}")
    return QgsCoordinateReferenceSystem.fromWkt(crs.to_wkt())
