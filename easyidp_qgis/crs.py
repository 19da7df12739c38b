"""CRSs between QGIS and the core: QGIS CRS → the core's CRS text, pyproj CRS → QGIS CRS."""
from qgis.core import QgsCoordinateReferenceSystem

from .compat import CrsWktVariant


def crs_string(crs: QgsCoordinateReferenceSystem):
    """An EPSG code when QGIS knows one, else WKT; None for an invalid CRS."""
    if crs is None or not crs.isValid():
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
