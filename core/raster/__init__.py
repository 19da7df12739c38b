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
from .geotiff import GeoTiff, open_geotiff
from .geotiff_write import write_geotiff
from .sweep import Window, sweep_windows

__all__ = ["GeoTiff", "open_geotiff", "write_geotiff", "Window", "sweep_windows", "CropResult",
           "crop_raster_by_rois", "HeightResult", "roi_heights", "sample_points", "vertex_heights"]
