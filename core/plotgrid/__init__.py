"""Plot grids: make the plot polygons of a trial from its field layout
(:func:`create_plot_grid`), join its field book, and fit the grid to the crop rows of an
orthomosaic (:func:`fit_plot_grid`, in :mod:`.fit`).
"""
from .create import create_plot_grid, write_plot_grid
from .fieldbook import JoinReport, field_book_problem, join_field_book, read_field_book
from .fit import FitResult, fit_plot_grid
from .options import FieldBookJoin, GridAnchor, GridLayout, grid_options
from .layout import (CORNER_ORDER, MAX_PLOTS, ORDERS, START_CORNERS, Axis, GridFrame, Numbering, PlotGrid,
                     PlotGridError, check_metric_crs, frame_from_bearing, frame_from_boundary, frame_from_corners,
                     make_plot_grid, minimum_area_rectangle, sort_corners, utm_zone)

__all__ = ["create_plot_grid", "GridAnchor", "GridLayout", "FieldBookJoin", "grid_options", "write_plot_grid", "join_field_book", "read_field_book",
           "JoinReport", "fit_plot_grid", "FitResult", "Axis", "GridFrame", "Numbering",
           "PlotGrid", "PlotGridError", "frame_from_bearing", "frame_from_boundary",
           "frame_from_corners", "make_plot_grid", "minimum_area_rectangle", "sort_corners",
           "utm_zone", "check_metric_crs", "CORNER_ORDER", "ORDERS", "START_CORNERS",
           "field_book_problem", "MAX_PLOTS"]
