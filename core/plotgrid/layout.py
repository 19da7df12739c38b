"""Plot grids from a field layout: the anchor (four corners, a boundary, or an origin and a
bearing), the layout (rows × columns, sizes, gaps, blocks, a buffer) and the numbering.

**The grid frame.** Every anchor becomes a rectangle with four corners in the order
*upper-left, upper-right, lower-right, lower-left*: clockwise on the map, starting at the corner
whose edge to the next one points closest to east (within ±45°) — FIELDimageR's clicking order.
Its *top edge* (upper-left → upper-right) is the x axis of the grid: the columns (passes) are
counted along it; its *left edge* (upper-left → lower-left) is the y axis: the rows (ranges) are
counted down it. Geometry is laid out from the upper-left corner; the numbering can start at
any corner.

**Along one axis** (x: across the columns, y: down the rows) plot ``i`` (0-based) starts at
``margin + i·size + (i − k)·gap + k·block_gap``, where ``k = i // per_block`` is the number of
block boundaries before it. Sizes, gaps and margins are in metres of the map CRS, which must be
projected in metres (a geographic CRS is refused with the UTM zone to use).

With corners or a boundary the field's extent is known, so one unknown per axis may be left
None and is solved: the gap (plots of ``size`` spread over the field), or the size (plots fill
the field between gaps). With both given, the plots are centred in the field (equal margins).
An origin and bearing needs the size and gap (or the spacing) of both axes.

Names: ``pattern.format(...)`` with ``plot_no`` (start id + position in the numbering order),
``row``, ``col`` (1-based from the start corner), ``block``, ``block_row``, ``block_col``,
``row_letter`` (A, B, …, Z, AA, …), ``range`` (= row) and ``pass`` (= col).
"""
import math
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from pyproj import CRS

from ..crs import as_crs, transformer
from ..errors import EasyIDPError
from ..roi import ROI, ROISet

CORNER_ORDER = ("upper-left", "upper-right", "lower-right", "lower-left")
START_CORNERS = ("top-left", "top-right", "bottom-left", "bottom-right")
ORDERS = ("row-major", "serpentine", "column-major", "serpentine-columns")
DEFAULT_PATTERN = "{plot_no}"
DEFAULT_TOLERANCE = 0.25      # m: how far four corners may be from a rectangle
MAX_PLOTS = 1_000_000         # plots in one grid (checked before anything is allocated)


class PlotGridError(EasyIDPError):
    """A layout that cannot be built: the message names the input and what to change."""


# ---- the frame -----------------------------------------------------------------------------

@dataclass(frozen=True)
class GridFrame:
    """The field rectangle: ``origin`` (upper-left corner, map x, y), unit vectors ``ux`` (along
    the top edge) and ``uy`` (down the left edge, ``ux`` turned 90° clockwise), and the
    ``extent`` (length of the top edge, of the left edge) in metres, or None (origin + bearing)."""
    origin: Tuple[float, float]
    ux: Tuple[float, float]
    uy: Tuple[float, float]
    extent: Optional[Tuple[float, float]] = None

    @property
    def bearing(self) -> float:
        """Compass bearing of the top edge (degrees clockwise from grid north)."""
        return math.degrees(math.atan2(self.ux[0], self.ux[1])) % 360.0

    def to_map(self, a, b) -> np.ndarray:
        """Map (x, y) of grid coordinates (a along x, b down y): (..., 2)."""
        a, b = np.asarray(a, float), np.asarray(b, float)
        ox, oy = self.origin
        return np.stack([ox + a * self.ux[0] + b * self.uy[0],
                         oy + a * self.ux[1] + b * self.uy[1]], axis=-1)

    def corners(self) -> np.ndarray:
        """(4, 2): upper-left, upper-right, lower-right, lower-left (needs the extent)."""
        w, h = self.extent
        return self.to_map([0, w, w, 0], [0, 0, h, h])


def frame_from_bearing(origin, bearing_deg: float) -> GridFrame:
    """``origin``: the field's upper-left corner; ``bearing_deg``: compass bearing of the top
    edge (90 = east). The rows run down from it, 90° clockwise."""
    t = math.radians(bearing_deg)
    ux = (math.sin(t), math.cos(t))
    return GridFrame((float(origin[0]), float(origin[1])), ux, (ux[1], -ux[0]), None)


def sort_corners(points) -> np.ndarray:
    """Four points in :data:`CORNER_ORDER`: clockwise about their centroid, starting at the
    corner whose edge to the next points closest to east."""
    p = np.asarray(points, float)[:, :2]
    if p.shape != (4, 2) or not np.all(np.isfinite(p)):
        raise PlotGridError(f"Field corners: exactly four points are needed, {len(p)} were given. "
                            "Give one point per corner of the field.")
    c = p.mean(axis=0)
    ang = np.arctan2(p[:, 1] - c[1], p[:, 0] - c[0])
    cw = p[np.argsort(-ang, kind="stable")]                  # clockwise on the map (y up)
    d = np.roll(cw, -1, axis=0) - cw
    edge_angle = np.abs(np.arctan2(d[:, 1], d[:, 0]))        # 0 = east
    start = int(np.argmin(edge_angle))
    return np.roll(cw, -start, axis=0)


def frame_from_corners(points, tolerance: float = DEFAULT_TOLERANCE) -> Tuple[GridFrame, str]:
    """The rectangle nearest four corners (any order); raises when a corner is more than
    ``tolerance`` m from it, saying by how much. Returns (frame, note on the order used)."""
    q = sort_corners(points)
    d = np.roll(q, -1, axis=0) - q                           # top, right, bottom, left edges
    lengths = np.hypot(d[:, 0], d[:, 1])
    if lengths.min() <= 0:
        raise PlotGridError("Field corners: two of the four points are the same point. "
                            "Give the four distinct corners of the field.")
    # the direction of the top edge: circular mean of the four edges, each turned onto it
    ang = np.arctan2(d[:, 1], d[:, 0]) + np.array([0, 0.5, 1.0, 1.5]) * math.pi
    t = math.atan2(np.sum(lengths * np.sin(ang)), np.sum(lengths * np.cos(ang)))
    ux = np.array([math.cos(t), math.sin(t)])
    uy = np.array([ux[1], -ux[0]])
    centre = q.mean(axis=0)
    a = (q - centre) @ ux
    b = (q - centre) @ uy
    w = (a[1] + a[2] - a[0] - a[3]) / 2
    h = (b[2] + b[3] - b[0] - b[1]) / 2
    if w <= 0 or h <= 0:
        raise PlotGridError("Field corners: the four points do not enclose an area (they lie on "
                            "one line). Give the four corners of the field.")
    fit = centre + np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2],
                             [-w / 2, h / 2]]) @ np.array([ux, uy])
    off = np.hypot(*(q - fit).T)
    worst = int(np.argmax(off))
    if off[worst] > tolerance:
        angles = [math.degrees(math.acos(np.clip(-(d[i - 1] @ d[i]) / (lengths[i - 1] * lengths[i]),
                                                 -1, 1))) for i in range(4)]
        raise PlotGridError(
            f"Field corners: the four points are not a rectangle: the {CORNER_ORDER[worst]} corner "
            f"is {off[worst]:.3f} m from the nearest rectangle (tolerance {tolerance:g} m; edges "
            f"{lengths[0]:.2f}, {lengths[1]:.2f}, {lengths[2]:.2f}, {lengths[3]:.2f} m, corner "
            f"angles {', '.join(f'{x:.1f}°' for x in angles)}). Check the corner points (one "
            "per corner), or raise the tolerance.")
    frame = GridFrame(tuple(fit[0]), tuple(ux), tuple(uy), (float(w), float(h)))
    note = ("Corners used as " + ", ".join(f"{n} ({x:.2f}, {y:.2f})" for n, (x, y)
                                            in zip(CORNER_ORDER, q))
            + f"; top edge bearing {frame.bearing:.2f}°, field {w:.3f} × {h:.3f} m, corners at "
            f"most {off.max():.3f} m from the rectangle.")
    return frame, note


def convex_hull(points) -> np.ndarray:
    """Convex hull (counter-clockwise, open) of (n, 2) points: Andrew's monotone chain."""
    p = np.unique(np.asarray(points, float)[:, :2], axis=0)
    if len(p) < 3:
        return p

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for pt in p:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], pt) <= 0:
            lower.pop()
        lower.append(pt)
    for pt in p[::-1]:
        while len(upper) >= 2 and cross(upper[-2], upper[-1], pt) <= 0:
            upper.pop()
        upper.append(pt)
    return np.array(lower[:-1] + upper[:-1])


def minimum_area_rectangle(points) -> np.ndarray:
    """(4, 2) corners of the minimum-area rectangle around ``points`` (one side on a hull
    edge, as rotating calipers prove)."""
    hull = convex_hull(points)
    if len(hull) < 3:
        raise PlotGridError("Field boundary: the polygon has no area. Draw the field's outline.")
    e = np.roll(hull, -1, axis=0) - hull
    ang = np.unique(np.mod(np.arctan2(e[:, 1], e[:, 0]), math.pi / 2))
    best = None
    for t in ang:
        ux, uy = np.array([math.cos(t), math.sin(t)]), np.array([-math.sin(t), math.cos(t)])
        a, b = hull @ ux, hull @ uy
        area = (a.max() - a.min()) * (b.max() - b.min())
        if best is None or area < best[0]:
            best = (area, ux, uy, a.min(), a.max(), b.min(), b.max())
    _, ux, uy, a0, a1, b0, b1 = best
    return np.array([a0 * ux + b0 * uy, a1 * ux + b0 * uy, a1 * ux + b1 * uy, a0 * ux + b1 * uy])


def frame_from_boundary(rings) -> Tuple[GridFrame, str]:
    """The frame of a field-boundary polygon (rings: exterior first): its minimum-area
    rectangle."""
    pts = np.concatenate([np.asarray(r, float)[:, :2] for r in rings])
    rect = minimum_area_rectangle(pts)
    frame, note = frame_from_corners(rect, tolerance=1e-6 * (1 + np.abs(pts).max()))
    return frame, "Boundary: its minimum-area rectangle. " + note


# ---- the CRS -------------------------------------------------------------------------------

def utm_zone(lon: float, lat: float) -> Tuple[int, str]:
    """(EPSG code, name) of the WGS 84 / UTM zone at a longitude and latitude."""
    zone = int(math.floor((lon + 180.0) / 6.0)) % 60 + 1
    north = lat >= 0
    return (32600 if north else 32700) + zone, f"WGS 84 / UTM zone {zone}{'N' if north else 'S'}"


def check_metric_crs(crs, xy, what: str = "Field corners") -> None:
    """Raise when ``crs`` is not projected in metres, naming the UTM zone of ``xy`` (a point
    in that CRS) to reproject to."""
    crs = as_crs(crs, what)
    if crs is None:
        raise PlotGridError(f"{what}: the layer has no CRS. Set its CRS (a projected CRS in "
                            "metres, e.g. the UTM zone of the field).")
    unit = crs.axis_info[0].unit_name if crs.axis_info else ""
    lon = lat = None
    try:
        lon, lat = transformer(crs, CRS.from_epsg(4326)).transform(float(xy[0]), float(xy[1]))
        code, name = utm_zone(lon, lat)
        hint = f"reproject it to {name} (EPSG:{code})"
    except Exception:
        hint = "reproject it to the UTM zone of the field"
    if crs.is_projected and unit in ("metre", "meter", "m"):
        scale = _scale_factor(crs, lon, lat)
        if scale is None or abs(scale - 1) <= MAX_SCALE_ERROR:
            return
        raise PlotGridError(
            f"{what}: the CRS {crs.name} stretches distances by {scale:.3f} at the field, so "
            f"plots laid out in its metres would be {abs(scale - 1) * 100:.0f} % off: {hint} "
            "and run again.")
    kind = "geographic (degrees)" if crs.is_geographic else f"in {unit or 'unknown units'}"
    raise PlotGridError(f"{what}: the CRS {crs.name} is {kind}, but plot sizes are in metres: "
                        f"{hint} and run again.")


MAX_SCALE_ERROR = 0.01
"""A projected CRS whose point scale at the field is off 1 by more than this (Web Mercator:
1/cos(latitude)) is refused: its metres are not metres on the ground."""


def _scale_factor(crs, lon, lat):
    """The point scale (mean of the meridional and parallel scales) of ``crs`` at (lon, lat),
    or None when it cannot be computed."""
    if lon is None:
        return None
    try:
        from pyproj import Proj
        f = Proj(crs).get_factors(lon, lat)
        return float((f.meridional_scale + f.parallel_scale) / 2)
    except Exception:
        return None


# ---- the layout ----------------------------------------------------------------------------

@dataclass
class Axis:
    """One axis of the layout: ``count`` plots of ``size`` m separated by ``gap`` m, in
    ``blocks`` blocks separated by ``block_gap`` m, starting ``margin`` m from the field edge.
    ``spacing`` (centre to centre) may be given instead of the gap. None: solved from the
    field extent (see the module docstring)."""
    count: int
    size: Optional[float] = None
    gap: Optional[float] = None
    spacing: Optional[float] = None
    blocks: int = 1
    block_gap: Optional[float] = None
    margin: Optional[float] = None

    def resolved(self, extent: Optional[float], name: str) -> "Axis":
        """A copy with size, gap, block gap and margin all set."""
        n, nb = int(self.count), int(self.blocks)
        if n < 1:
            raise PlotGridError(f"Number of {name}s: {n}; give at least 1.")
        if nb < 1 or n % nb:
            raise PlotGridError(f"Blocks along the {name}s: {nb} does not divide the {n} {name}s "
                                "into equal blocks; give a divisor of the number of "
                                f"{name}s.")
        size, gap = self.size, self.gap
        if self.spacing is not None:
            if gap is not None and size is not None and abs(size + gap - self.spacing) > 1e-9:
                raise PlotGridError(f"{name.capitalize()}s: give the gap or the spacing, not both "
                                    f"(size {size:g} + gap {gap:g} ≠ spacing {self.spacing:g} m).")
            if size is None and gap is None:
                size = self.spacing
            if gap is None:
                gap = self.spacing - size
            elif size is None:
                size = self.spacing - gap
        bgap = self.block_gap
        margin = self.margin
        n_gap = n - nb                          # plot gaps inside blocks
        n_bgap = nb - 1
        if bgap is None and gap is not None:
            bgap = gap
        if extent is None:
            if size is None or gap is None:
                raise PlotGridError(f"{name.capitalize()}s: with an origin and a bearing the plot "
                                    f"size and the gap (or the spacing) along the {name}s are "
                                    "needed; give them, or anchor the grid on four corners.")
            margin = margin or 0.0
        else:
            avail = extent - 2 * (margin or 0.0)
            if size is None and gap is None:
                gap = 0.0
            if size is None:
                bgap = gap if bgap is None else bgap
                size = (avail - n_gap * gap - n_bgap * bgap) / n
            elif gap is None:
                if bgap is not None:
                    gap = (avail - n * size - n_bgap * bgap) / n_gap if n_gap else 0.0
                else:
                    gap = (avail - n * size) / (n_gap + n_bgap) if n_gap + n_bgap else 0.0
                    bgap = gap
            bgap = gap if bgap is None else bgap
            if margin is None:
                margin = (extent - (n * size + n_gap * gap + n_bgap * bgap)) / 2
        if size <= 0:
            raise PlotGridError(f"Plot size along the {name}s: {size:.3f} m; the plots collapse "
                                "to a line. Give a positive plot size, or fewer plots, smaller "
                                "gaps or a larger field.")
        return Axis(n, float(size), float(gap), None, nb, float(bgap), float(margin))

    def starts(self) -> np.ndarray:
        """(count,) offsets of the plots' near edges from the field edge."""
        i = np.arange(self.count)
        k = i // (self.count // self.blocks)
        return self.margin + i * self.size + (i - k) * self.gap + k * self.block_gap

    @property
    def length(self) -> float:
        """From the field edge to the far edge of the last plot, plus the margin."""
        n, nb = self.count, self.blocks
        return 2 * self.margin + n * self.size + (n - nb) * self.gap + (nb - 1) * self.block_gap


@dataclass
class Numbering:
    """``order``: one of :data:`ORDERS`; ``start``: one of :data:`START_CORNERS`; ``start_id``:
    the first ``plot_no``; ``pattern``: the name (see the module docstring)."""
    order: str = "row-major"
    start: str = "top-left"
    start_id: int = 1
    pattern: str = DEFAULT_PATTERN

    def check(self) -> None:
        if self.order not in ORDERS:
            raise PlotGridError(f"Numbering order {self.order!r}: choose one of {', '.join(ORDERS)}.")
        if self.start not in START_CORNERS:
            raise PlotGridError(f"Start corner {self.start!r}: choose one of "
                                f"{', '.join(START_CORNERS)}.")
        try:
            self.pattern.format(**_name_keys(1, 1, 1, 1, 1, 1))
        except Exception as exc:        # any error of str.format: KeyError, AttributeError, …
            raise pattern_error(self.pattern, exc) from None


def pattern_error(pattern: str, exc: Exception) -> PlotGridError:
    """The one message for a name pattern that cannot be formatted: the pattern, the error and
    the keys."""
    keys = ", ".join("{" + k + "}" for k in _name_keys(1, 1, 1, 1, 1, 1))
    return PlotGridError(f"Name pattern {pattern!r} cannot be formatted ({type(exc).__name__}: "
                         f"{exc}); use the keys {keys} with format specs such as :02d, e.g. "
                         "'{block}-{row:02d}-{col:02d}'.")


def row_letter(row: int) -> str:
    """1 → A, 26 → Z, 27 → AA (spreadsheet column letters)."""
    s = ""
    while row > 0:
        row, r = divmod(row - 1, 26)
        s = chr(ord("A") + r) + s
    return s


def _name_keys(no, row, col, block, brow, bcol) -> dict:
    return {"plot_no": no, "row": row, "col": col, "block": block, "block_row": brow,
            "block_col": bcol, "row_letter": row_letter(row), "range": row, "pass": col}


@dataclass
class PlotGrid:
    """The plots of a grid, in the numbering order.

    ``corners``: (n, 4, 2) map corners of every plot, clockwise from its upper-left corner
    (in the grid frame); ``plot_id`` (names), ``plot_no``, ``row``, ``col``, ``block``:
    per plot; ``fields``: the joined field-book columns ({name: list}); ``crs``; ``frame``;
    ``axes`` (x, y) as resolved; ``notes``: what was decided (corner order, solved sizes).
    """
    corners: np.ndarray
    plot_id: List[str]
    plot_no: np.ndarray
    row: np.ndarray
    col: np.ndarray
    block: np.ndarray
    crs: object
    frame: GridFrame
    axes: Tuple[Axis, Axis]
    buffer: float = 0.0
    fields: Dict[str, list] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.plot_id)

    def attributes(self, i: int) -> dict:
        out = {"plot_id": self.plot_id[i], "plot_no": int(self.plot_no[i]),
               "row": int(self.row[i]), "col": int(self.col[i]), "block": int(self.block[i])}
        for k, v in self.fields.items():
            out[k] = v[i]
        return out

    def field_names(self) -> List[str]:
        return ["plot_id", "plot_no", "row", "col", "block"] + list(self.fields)

    def to_rois(self):
        """The plots as an :class:`ROISet` (name = plot_id, the attributes as fields)."""
        return ROISet([ROI(self.plot_id[i], [[self.corners[i].copy()]], self.attributes(i))
                       for i in range(len(self))], self.crs)


def make_plot_grid(frame: GridFrame, x: Axis, y: Axis, numbering: Numbering = None,
                   buffer: float = 0.0, crs=None, notes: Sequence[str] = ()) -> PlotGrid:
    """The plots of a layout in a frame (see the module docstring). ``x``: the columns (along
    the top edge), ``y``: the rows (down the left edge); ``buffer`` grows (> 0) or shrinks
    (< 0) every plot on each side, keeping it a rectangle."""
    numbering = numbering or Numbering()
    numbering.check()
    ext = frame.extent or (None, None)
    ax = x.resolved(ext[0], "column")
    ay = y.resolved(ext[1], "row")
    notes = list(notes)
    for a, name, orig in ((ax, "column", x), (ay, "row", y)):
        _check_overlap(a, name, buffer)
        solved = [k for k in ("size", "gap") if getattr(orig, k) is None and orig.spacing is None]
        if solved or (orig.margin is None and frame.extent is not None):
            notes.append(f"Along the {name}s: {a.count} plots of {a.size:.3f} m, gap {a.gap:.3f} m"
                         + (f", {a.blocks} blocks {a.block_gap:.3f} m apart" if a.blocks > 1 else "")
                         + f", margin {a.margin:.3f} m"
                         + (f" (solved: {', '.join(solved)})" if solved else "") + ".")
    if frame.extent is not None:
        for a, name, e in ((ax, "column", ext[0]), (ay, "row", ext[1])):
            if a.margin < -1e-6:
                raise PlotGridError(
                    f"The {name}s do not fit in the field: {a.count} plots of {a.size:.3f} m with "
                    f"gaps take {a.length - 2 * a.margin:.3f} m but the field is {e:.3f} m "
                    f"({-2 * a.margin:.3f} m too long). Lower the plot size or the gaps.")
    nc, nr = ax.count, ay.count
    if nc * nr > MAX_PLOTS:
        raise PlotGridError(f"{nr:,} rows × {nc:,} columns make {nc * nr:,} plots; a grid holds at "
                            f"most {MAX_PLOTS:,}. Check the numbers of rows and columns, or make "
                            "the field in parts.")
    a0 = ax.starts() - buffer
    b0 = ay.starts() - buffer
    wa, hb = ax.size + 2 * buffer, ay.size + 2 * buffer
    # geometry rows/cols (0-based, from the upper-left), every plot
    gr, gc = np.meshgrid(np.arange(nr), np.arange(nc), indexing="ij")
    gr, gc = gr.ravel(), gc.ravel()
    # numbering: rows and columns counted from the start corner
    flip_r = numbering.start.startswith("bottom")
    flip_c = numbering.start.endswith("right")
    r = (nr - 1 - gr) if flip_r else gr
    c = (nc - 1 - gc) if flip_c else gc
    if numbering.order.startswith("serpentine"):
        if numbering.order == "serpentine":
            c_seq = np.where(r % 2 == 1, nc - 1 - c, c)
            seq = r * nc + c_seq
        else:
            r_seq = np.where(c % 2 == 1, nr - 1 - r, r)
            seq = c * nr + r_seq
    elif numbering.order == "row-major":
        seq = r * nc + c
    else:
        seq = c * nr + r
    order = np.argsort(seq, kind="stable")
    gr, gc, r, c = gr[order], gc[order], r[order], c[order]
    per_r, per_c = nr // ay.blocks, nc // ax.blocks
    brow, bcol = r // per_r, c // per_c
    block = brow * ax.blocks + bcol + 1
    A = a0[gc][:, None] + np.array([0.0, wa, wa, 0.0])[None, :]
    B = b0[gr][:, None] + np.array([0.0, 0.0, hb, hb])[None, :]
    corners = frame.to_map(A, B)
    no = numbering.start_id + np.arange(len(order))
    pattern = numbering.pattern
    try:
        names = [pattern.format(**_name_keys(int(n), int(rr) + 1, int(cc) + 1, int(bb),
                                             int(br) + 1, int(bc) + 1))
                 for n, rr, cc, bb, br, bc in zip(no, r, c, block, brow, bcol)]
    except Exception as exc:            # a pattern that formats for plot 1 but not for all
        raise pattern_error(pattern, exc) from None
    dup = _duplicates(names)
    if dup:
        raise PlotGridError(f"Name pattern {pattern!r} gives the same name to several plots "
                            f"({', '.join(dup[:5])}): include {{plot_no}}, or {{row}} and "
                            "{col} (and {block} when the blocks restart the numbering).")
    return PlotGrid(corners, names, no, r + 1, c + 1, block, as_crs(crs), frame, (ax, ay),
                    float(buffer), {}, notes)


def _check_overlap(a: Axis, name: str, buffer: float) -> None:
    for gap, what in ((a.gap, "gap between plots"), (a.block_gap, "gap between blocks")):
        if (what.endswith("blocks") and a.blocks < 2) or (what.endswith("plots") and a.count == a.blocks):
            continue
        over = 2 * buffer - gap
        if over > 1e-9:
            raise PlotGridError(
                f"Plots would overlap by {over:.3f} m along the {name}s: the {what} is "
                f"{gap:.3f} m" + (f" and the buffer adds {buffer:g} m on each side" if buffer else "")
                + ". Lower the plot size or the buffer, or widen the gaps (spacing).")
    if a.size + 2 * buffer <= 0:
        raise PlotGridError(f"Buffer {buffer:g} m: the plots are {a.size:.3f} m along the "
                            f"{name}s, so they collapse to a line; use a buffer above "
                            f"{-a.size / 2:.3f} m.")


def _duplicates(names: Sequence[str]) -> List[str]:
    seen, dup = set(), []
    for n in names:
        if n in seen:
            dup.append(n)
        seen.add(n)
    return dup
