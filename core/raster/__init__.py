"""The raster engine: GeoTIFF metadata, block decoding and writing, one sweep for many windows,
ROIs on the pixel grid, cropping, the DSM and its heights.

* :mod:`.geotiff` reads a GeoTIFF's metadata and decodes single tiles or strips (tifffile).
* :mod:`.geotiff_write` writes GeoTIFFs with the source's georeferencing, atomically.
* :mod:`.sweep` reads many pixel windows in one top-to-bottom pass, each block decoded once.
* :mod:`.roi_pixels` places ROIs on a raster's grid (windows, masks).
* :mod:`.crop` crops ROIs out of a raster.
* :mod:`.dsm`: the :class:`DSM` (opens and checks a DSM, samples its heights at points in any
  CRS, gives its ray surface); :mod:`.ray_surface`: the exact first hits of rays on it.
* :mod:`.dsm_heights` gives ROIs their heights from a DSM (per vertex or per polygon).
"""
from ..deprecation import moved_names
from .crop import RasterCropResult, crop_raster_by_rois
from .dsm import DSM, SAMPLING, as_dsm, valid_heights
from .geotiff import TAG_GDAL_METADATA, GeoTiff, open_geotiff
from .geotiff_write import epsg_geo_tags, write_geotiff
from .ray_surface import HIT, LEFT, MISS, NODATA, STATUS_NAMES, RayHits, RaySurface, first_hits
from .dsm_heights import HeightResult, dsm_roi_heights, vertex_heights
from .roi_pixels import NO_PIXEL, place_rois, require_overlap, rois_in_raster_crs
from .sweep import Window, sweep_windows, thread_pool

__all__ = ["GeoTiff", "open_geotiff", "TAG_GDAL_METADATA", "write_geotiff", "epsg_geo_tags",
           "Window", "sweep_windows", "thread_pool", "place_rois", "rois_in_raster_crs",
           "require_overlap", "NO_PIXEL", "RasterCropResult", "crop_raster_by_rois", "DSM", "SAMPLING",
           "as_dsm", "valid_heights", "RaySurface", "RayHits", "first_hits", "HIT", "MISS", "LEFT",
           "NODATA", "STATUS_NAMES", "HeightResult", "dsm_roi_heights", "vertex_heights"]

# the names before the glossary's renames, for one release (core.deprecation)
__getattr__ = moved_names(__name__, globals(), CropResult="RasterCropResult",
                          roi_heights="dsm_roi_heights")
