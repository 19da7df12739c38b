"""One call from an anchor, a layout and a field book to a plot grid (what the
``easyidp:createplotgrid`` tool runs), and a GeoPackage writer for it."""
from typing import Optional, Tuple

import numpy as np

from ..gpkg import GpkgTable, field_type, write_geopackage
from .fieldbook import JoinReport, join_field_book
from .layout import (Axis, Numbering, PlotGrid, PlotGridError, check_metric_crs,
                     frame_from_bearing, frame_from_boundary, frame_from_corners, make_plot_grid)
from .options import FieldBookJoin, GridAnchor, GridLayout, grid_keywords


@grid_keywords
def create_plot_grid(crs, rows: int, cols: int, *, anchor: Optional[GridAnchor] = None,
                     layout: Optional[GridLayout] = None, numbering: Optional[Numbering] = None,
                     field_book: Optional[FieldBookJoin] = None
                     ) -> Tuple[PlotGrid, Optional[JoinReport]]:
    """A plot grid of ``rows`` × ``cols`` plots from a field layout (see :mod:`.layout`).

    ``x`` runs along the top edge (columns, passes), ``y`` down the left edge (rows, ranges).
    The 0.2 keywords (``origin=…, size_x=…, join_by=…``) still work until 0.4, with a
    ``DeprecationWarning``.

    Parameters
    ----------
    crs : CRS
        The CRS of the grid and its anchor: projected, in metres.
    rows, cols : int
        The number of plots down and across.
    anchor : GridAnchor
        Where the grid sits: four field corners, a field boundary, or an origin and a bearing.
    layout : GridLayout, optional
        Plot sizes, gaps, blocks and buffer (default: derived from the anchor's extent).
    numbering : Numbering, optional
        The order, starting corner, first number and id pattern of the plots.
    field_book : FieldBookJoin, optional
        A field book's rows joined to the plots.

    Returns
    -------
    PlotGrid
        The plots, numbered, with the field book's fields.
    JoinReport or None
        How the field book joined, when one was given.

    Examples
    --------
    >>> from easyidp_toolbox.core import GridAnchor, GridLayout, create_plot_grid
    >>> grid, _ = create_plot_grid("EPSG:32654", 2, 3,
    ...                            anchor=GridAnchor(origin=(500000, 4000000), bearing=90),
    ...                            layout=GridLayout(size_x=2, size_y=1, gap_x=0.5, gap_y=1))
    >>> len(grid)
    6
    """
    anchor = anchor if anchor is not None else GridAnchor()
    lay = layout if layout is not None else GridLayout()
    numbering = numbering if numbering is not None else Numbering()
    corners, boundary, origin = anchor.corners, anchor.boundary, anchor.origin
    bearing, tolerance = anchor.bearing, anchor.tolerance
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
        Axis(cols, lay.size_x, lay.gap_x, lay.spacing_x, lay.blocks_x, lay.block_gap_x),
        Axis(rows, lay.size_y, lay.gap_y, lay.spacing_y, lay.blocks_y, lay.block_gap_y),
        numbering, lay.buffer, crs, [note])
    report = None
    if field_book is not None:
        report = join_field_book(grid, field_book.rows, field_book.join_by, field_book.book_id,
                                 field_book.book_row, field_book.book_col)
    return grid, report


def write_plot_grid(path: str, grid: PlotGrid, layer: str = "plots") -> str:
    """The grid as a GeoPackage polygon layer (written atomically)."""
    names = grid.field_names()
    rows = [tuple(grid.attributes(i)[k] for k in names) for i in range(len(grid))]
    types = [field_type([r[j] for r in rows]) for j in range(len(names))]
    table = GpkgTable(layer, list(zip(names, types)), rows,
                      [[[grid.corners[i]]] for i in range(len(grid))], grid.crs)
    return write_geopackage(path, [table])
