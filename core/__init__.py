"""easyidp_toolbox.core: the GUI-free engine of EasyIDP for QGIS.

Plain data in (numpy arrays, file paths, CRS as pyproj.CRS / EPSG / WKT), plain data out.
Never imports qgis or PyQt. Progress and cancellation come in as callables
(``progress(percent)``, ``is_cancelled()``).

Plot grids from a field layout, and their fit to the crop rows of an orthomosaic:
``core.plotgrid`` (``create_plot_grid``, ``fit_plot_grid``).

ROI heights: ``core.raster.roi_heights`` (from a DSM) and ``core.pointcloud.roi_heights``
(from a point cloud).

Conventions (see ARCHITECTURE.md): map coordinates are (x, y) = (easting, northing) or
(lon, lat); image pixels have their origin at the top-left *corner*, x right, y down, so the
centre of the top-left pixel is (0.5, 0.5).
"""
# The one version source: metadata.txt (make changelog) and the wheel (pyproject.toml) read it.
__version__ = "0.3.0"

from .errors import Cancelled, EasyIDPError, InputError, ROIError
from .pointcloud import PointCloud, canopy_summary, crop_point_cloud, read_point_cloud, write_point_cloud
from .plotgrid import PlotGrid, create_plot_grid, fit_plot_grid
from .progress import Progress
from .reconstruction import Reconstruction, open_reconstruction
from .roi import ROI, ROISet, open_rois, read_geojson, roi_from_coordinates

__all__ = [
    "Cancelled", "EasyIDPError", "InputError", "ROIError", "Progress",
    "ROI", "ROISet", "roi_from_coordinates", "open_rois", "read_geojson",
    "PointCloud", "read_point_cloud", "write_point_cloud", "crop_point_cloud", "canopy_summary",
    "Reconstruction", "open_reconstruction",
    "PlotGrid", "create_plot_grid", "fit_plot_grid",
]
