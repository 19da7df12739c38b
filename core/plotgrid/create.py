"""One call from an anchor, a layout and a field book to a plot grid (what the
``easyidp:createplotgrid`` tool runs), and a GeoPackage writer for it."""
from typing import Optional, Sequence, Tuple

import numpy as np

from ..gpkg import GpkgTable, field_type, write_geopackage
from .fieldbook import JoinReport, join_field_book
from .layout import (DEFAULT_TOLERANCE, Axis, Numbering, PlotGrid, PlotGridError,
                     check_metric_crs, frame_from_bearing, frame_from_boundary,
                     frame_from_corners, make_plot_grid)


def create_plot_grid(crs, rows: int, cols: int, *, corners=None, boundary=None, origin=None,
                     bearing: float = 90.0,
                     size_x: Optional[float] = None, size_y: Optional[float] = None,
                     gap_x: Optional[float] = None, gap_y: Optional[float] = None,
                     spacing_x: Optional[float] = None, spacing_y: Optional[float] = None,
                     blocks_x: int = 1, blocks_y: int = 1,
                     block_gap_x: Optional[float] = None, block_gap_y: Optional[float] = None,
                     buffer: float = 0.0, order: str = "row-major", start: str = "top-left",
                     start_id: int = 1, pattern: str = "{plot_no}",
                     tolerance: float = DEFAULT_TOLERANCE,
                     field_book: Optional[Sequence[dict]] = None, join_by: str = "plot_id",
                     book_id: Optional[str] = None, book_row: Optional[str] = None,
                     book_col: Optional[str] = None) -> Tuple[PlotGrid, Optional[JoinReport]]:
    """A plot grid of ``rows`` × ``cols`` plots (see :mod:`.layout` for the frame and the
    layout), anchored on exactly one of ``corners`` ((4, 2) points in any order),
    ``boundary`` (polygon rings) or ``origin`` (the upper-left corner) with ``bearing`` (of the
    top edge, degrees clockwise from north). ``x``: along the top edge (columns, passes);
    ``y``: down the left edge (rows, ranges). Coordinates in ``crs``, projected in metres.
    ``field_book``: rows (dicts) joined by ``join_by`` (plot_id, plot_no or row_col)."""
    given = [k for k, v in (("corners", corners), ("boundary", boundary), ("origin", origin))
             if v is not None]
    if len(given) != 1:
        raise PlotGridError("Anchor: give exactly one of four field corners, a field boundary "
                            f"polygon, or an origin and a bearing (given: {', '.join(given) or 'none'}).")
    if given[0] == "corners":
        pts = np.asarray(corners, float)
        check_metric_crs(crs, pts.mean(axis=0) if pts.ndim == 2 and len(pts) else (0, 0),
                         "Field corners")
        frame, note = frame_from_corners(pts, tolerance)
    elif given[0] == "boundary":
        rings = [np.asarray(r, float) for r in boundary]
        check_metric_crs(crs, rings[0].mean(axis=0), "Field boundary")
        frame, note = frame_from_boundary(rings)
    else:
        check_metric_crs(crs, origin, "Origin point")
        frame = frame_from_bearing(origin, bearing)
        note = (f"Origin ({origin[0]:.2f}, {origin[1]:.2f}) is the upper-left corner; top edge "
                f"bearing {bearing:g}°, rows run down it at {(bearing + 90) % 360:g}°.")
    grid = make_plot_grid(
        frame,
        Axis(cols, size_x, gap_x, spacing_x, blocks_x, block_gap_x),
        Axis(rows, size_y, gap_y, spacing_y, blocks_y, block_gap_y),
        Numbering(order, start, start_id, pattern), buffer, crs, [note])
    report = None
    if field_book is not None:
        report = join_field_book(grid, field_book, join_by, book_id, book_row, book_col)
    return grid, report


def write_plot_grid(path: str, grid: PlotGrid, layer: str = "plots") -> str:
    """The grid as a GeoPackage polygon layer (written atomically)."""
    names = grid.field_names()
    rows = [tuple(grid.attributes(i)[k] for k in names) for i in range(len(grid))]
    types = [field_type([r[j] for r in rows]) for j in range(len(names))]
    table = GpkgTable(layer, list(zip(names, types)), rows,
                      [[[grid.corners[i]]] for i in range(len(grid))], grid.crs)
    return write_geopackage(path, [table])
