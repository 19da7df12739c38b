"""easyidp_toolbox.core: the GUI-free engine of EasyIDP for QGIS, and its documented facade.

Plain data in (numpy arrays, file paths, CRS as pyproj.CRS / EPSG / WKT), plain data out.
Never imports qgis or PyQt. Progress and cancellation come in as callables
(``progress(percent)``, ``is_cancelled()``).

This module holds every tool's entry point (the function its QGIS tool runs) and
``__version__``; each subpackage's ``__init__`` is that subpackage's whole public API. Pixels,
CRS axis order and heights follow the one set of
[Conventions](../background/conventions.md); the names follow the
[Glossary](../developer/glossary.md).
"""
# The one version source: metadata.txt (make changelog) and the wheel (pyproject.toml) read it.
__version__ = "0.3.0"

import os
from typing import TYPE_CHECKING, Optional

from .errors import Cancelled, EasyIDPError, InputError, ROIError
from .deprecation import renamed_parameters
from .progress import Progress
from .projection import (back_project, camera_footprints, crop_photos, draw_previews,
                         export_training_set, forward_project, forward_project_photos,
                         fuse_views, orthorectify_rois, photo_statistics, roi_photo_statistics)
from .raster import RasterCropResult, crop_raster_by_rois, dsm_roi_heights, open_geotiff
from .reconstruction import Reconstruction, open_reconstruction
from .roi import ROI, ROISet, read_geojson, roi_from_coordinates
from .roi import open_rois as _open_rois

if TYPE_CHECKING:
    from .plotgrid import (FieldBookJoin, GridAnchor, GridLayout, Numbering, PlotGrid,
                           create_plot_grid, fit_plot_grid)
    from .pointcloud import (CloudCropResult, PointCloud, canopy_summary, cloud_roi_heights,
                             crop_point_cloud, read_point_cloud, write_point_cloud)
    from .season import run_season

_ON_FIRST_USE = {name: package for package, names in (
    ("pointcloud", ("CloudCropResult", "PointCloud", "canopy_summary", "cloud_roi_heights",
                    "crop_point_cloud", "read_point_cloud", "write_point_cloud")),
    ("plotgrid", ("FieldBookJoin", "GridAnchor", "GridLayout", "Numbering", "PlotGrid",
                  "create_plot_grid", "fit_plot_grid")),
    ("season", ("run_season",))) for name in names}
"""The facade's names whose package is imported when one is first used (PEP 562), not with
the facade: every QGIS tool imports the facade when QGIS loads the plugin (``qgis_process``
too, at each run), and these packages are the ones the other tools do not need (0.05 s of
CPU at each start)."""


def __getattr__(name: str):
    package = _ON_FIRST_USE.get(name)
    if package is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib
    value = getattr(importlib.import_module(f".{package}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_ON_FIRST_USE))


__all__ = [
    "__version__", "Cancelled", "EasyIDPError", "InputError", "ROIError", "Progress",
    "ROI", "ROISet", "roi_from_coordinates", "open_rois", "read_geojson",
    "crop_raster_by_rois", "RasterCropResult", "dsm_roi_heights",
    "PointCloud", "read_point_cloud", "write_point_cloud", "crop_point_cloud", "CloudCropResult",
    "canopy_summary", "cloud_roi_heights",
    "Reconstruction", "open_reconstruction",
    "camera_footprints", "back_project", "crop_photos", "draw_previews", "photo_statistics",
    "roi_photo_statistics", "forward_project", "forward_project_photos", "fuse_views",
    "orthorectify_rois", "export_training_set",
    "PlotGrid", "create_plot_grid", "GridAnchor", "GridLayout", "Numbering", "FieldBookJoin",
    "fit_plot_grid",
    "run_season",
]


@renamed_parameters(crs="source_crs")
def open_rois(source, name_field: Optional[str] = None, source_crs=None, raster=None,
              layer: Optional[str] = None) -> ROISet:
    """ROIs from a file or an object, with their CRS.

    The facade's :func:`core.roi.open_rois`, which also takes the LabelMe ``raster`` as a path.

    Parameters
    ----------
    source : str, path or object
        * ``.shp`` / ``.zip``: ESRI shapefile (CRS from ``.prj``, encoding from ``.cpg``);
        * ``.gpkg``: a polygon layer of a GeoPackage;
        * ``.geojson`` / ``.json``: GeoJSON, or a LabelMe file (recognised by its ``shapes``),
          whose pixel polygons are placed on the georeferenced ``raster`` they were drawn on;
        * ``.txt`` / ``.csv``: a CloudCompare point list (one polygon; ``source_crs``
          required);
        * any object with ``__geo_interface__`` (shapely, geopandas) or a GeoJSON-like dict.
    name_field : str, optional
        The attribute that names each ROI (default: the feature id or index).
    source_crs : CRS, optional
        Overrides (or, where the source has none, supplies) the CRS.
    raster : str, path or GeoTiff, optional
        LabelMe only: the georeferenced raster (orthomosaic or DSM) the polygons were drawn on,
        a GeoTIFF path or opened (``core.raster.open_geotiff``).
    layer : str, optional
        GeoPackage only: the layer's name, when it has several.

    Returns
    -------
    ROISet
        The ROIs with their CRS.
    """
    if isinstance(raster, (str, os.PathLike)):
        if not os.path.isfile(raster):
            raise InputError(f"Raster not found: {os.fspath(raster)} (the GeoTIFF the LabelMe "
                             "polygons were drawn on). Check the path.")
        raster = open_geotiff(os.fspath(raster))
    return _open_rois(source, name_field=name_field, source_crs=source_crs, raster=raster,
                      layer=layer)
