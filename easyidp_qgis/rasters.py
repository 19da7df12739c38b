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
    import numpy as np
    from ..core.crs import same_crs, transform_xy
    from ..core.raster.dsm_heights import sample_points
    from ..core.raster.geotiff import open_geotiff

    dsm = open_geotiff(geotiff_source(layer, label), crs=crs_string(layer.crs()))
    if dsm.crs is None or points_crs is None or same_crs(dsm.crs, points_crs):
        return lambda x, y: sample_points(dsm, x, y)

    def ground(x, y):
        xy = transform_xy(points_crs, dsm.crs, np.column_stack([np.ravel(x), np.ravel(y)]))
        return sample_points(dsm, xy[:, 0], xy[:, 1]).reshape(np.shape(x))
    return ground


def dsm_parameter(alg, parameters, context):
    """The DSM parameter as the core's :class:`DSMHeights` (None when not given)."""
    from ..core.projection import DSMHeights
    layer = alg.parameterAsRasterLayer(parameters, alg.DSM, context)
    if layer is None:
        return None
    return DSMHeights(geotiff_source(layer, alg.tr("DSM")), crs_string(layer.crs()))
