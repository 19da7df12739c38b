"""Raster layers as the core reads them: the local GeoTIFF behind a layer, a DSM sampled at
points, and the DSM parameter of the projection tools."""
import os

from qgis.core import QgsProcessingException

from .crs import crs_string
from .layer_files import layer_file


def geotiff_source(layer, label: str) -> str:
    """The GeoTIFF file behind a raster layer; refuses layers that are not a local GeoTIFF."""
    if layer is None:
        raise QgsProcessingException(f"{label}: no raster layer given, or it could not be loaded.")
    path = layer_file(layer)
    if layer.providerType() != "gdal" or not os.path.isfile(path):
        raise QgsProcessingException(
            f"{label}: layer '{layer.name()}' is not a local raster file ({layer.source()}). "
            "EasyIDP reads GeoTIFF files: save it as GeoTIFF first (Export ▸ Save As…).")
    with open(path, "rb") as fh:
        magic = fh.read(4)
    if magic not in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):  # classic and BigTIFF
        raise QgsProcessingException(
            f"{label}: {path} is not a GeoTIFF. Convert it to GeoTIFF first (Raster ▸ Conversion "
            "▸ Translate).")
    return path


def dsm_ground(layer, label: str, points_crs=None):
    """``ground(x, y) -> z``: bilinear heights of a DSM/DTM raster layer (NaN outside it or on
    nodata) at points given in ``points_crs`` (a pyproj CRS), transformed to the DSM's CRS when
    they differ; ``points_crs=None`` takes the points to be in the DSM's own frame."""
    from ..core.raster import DSM

    dsm = DSM(geotiff_source(layer, label), crs=crs_string(layer.crs()))
    return lambda x, y: dsm.heights(x, y, crs=points_crs)


def dsm_parameter(alg, parameters, context):
    """The DSM parameter as the core's :class:`DSM` (None when not given)."""
    from ..core.raster import DSM
    layer = alg.parameterAsRasterLayer(parameters, alg.DSM, context)
    if layer is None:
        return None
    return DSM(geotiff_source(layer, alg.tr("DSM")), crs=crs_string(layer.crs()))
