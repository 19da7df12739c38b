"""The raster engine: GeoTIFF metadata, block decoding and writing, one sweep for many windows,
ROIs on the pixel grid, cropping and DSM heights.

* :mod:`.geotiff` reads a GeoTIFF's metadata and decodes single tiles or strips (tifffile).
* :mod:`.geotiff_write` writes GeoTIFFs with the source's georeferencing, atomically.
* :mod:`.sweep` reads many pixel windows in one top-to-bottom pass, each block decoded once.
* :mod:`.roi_pixels` places ROIs on a raster's grid (windows, masks).
* :mod:`.crop` crops ROIs out of a raster; :mod:`.dsm_heights` gives ROIs their heights.
"""
from .crop import CropResult, crop_raster_by_rois
from .dsm_heights import HeightResult, roi_heights, sample_points, vertex_heights
from .geotiff import TAG_GDAL_METADATA, GeoTiff, open_geotiff
from .geotiff_write import epsg_geo_tags, write_geotiff
from .roi_pixels import NO_PIXEL, place_rois, require_overlap, rois_in_raster_crs
from .sweep import Window, sweep_windows, thread_pool

__all__ = ["GeoTiff", "open_geotiff", "TAG_GDAL_METADATA", "write_geotiff", "epsg_geo_tags",
           "Window", "sweep_windows", "thread_pool", "place_rois", "rois_in_raster_crs",
           "require_overlap", "NO_PIXEL", "CropResult", "crop_raster_by_rois", "HeightResult",
           "roi_heights", "sample_points", "vertex_heights"]
