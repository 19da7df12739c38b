"""The options of :func:`.create.create_plot_grid`, grouped as keyword-only objects.

:class:`GridAnchor` (where the grid sits), :class:`GridLayout` (plot sizes, gaps, blocks) and
:class:`FieldBookJoin` (the field book and how it joins), with :class:`.layout.Numbering` (how the
plots are numbered). The 25 keywords of 0.2 (``origin=…, size_x=…, join_by=…``) still work for
one release, with a ``DeprecationWarning`` (:func:`grid_keywords`); :func:`grid_options` groups
flat keywords without one.
"""
import functools
import warnings
from dataclasses import dataclass, fields
from typing import Optional, Sequence

from ..deprecation import REMOVED_IN
from .layout import DEFAULT_TOLERANCE, Numbering


@dataclass(frozen=True)
class GridAnchor:
    """Where a plot grid sits: exactly one of ``corners``, ``boundary`` or ``origin``.

    Parameters
    ----------
    corners : array_like, optional
        The four field corners, (4, 2) points in any order.
    boundary : sequence of array_like, optional
        A field boundary polygon (rings); the grid fills its minimum-area rectangle.
    origin : tuple of float, optional
        The upper-left corner of the grid, with ``bearing``.
    bearing : float
        With ``origin``: the bearing of the top edge, degrees clockwise from north.
    tolerance : float
        With ``corners``: how far (m) the four corners may be from a rectangle.
    """
    corners: object = None
    boundary: object = None
    origin: object = None
    bearing: float = 90.0
    tolerance: float = DEFAULT_TOLERANCE


@dataclass(frozen=True)
class GridLayout:
    """The plots' sizes and gaps, metres; ``x`` runs along the top edge (columns), ``y`` down the
    left edge (rows). Per axis, give what the trial's plan says of size, gap and spacing; what is
    missing is derived from the anchor's extent (:mod:`.layout`).

    Parameters
    ----------
    size_x, size_y : float, optional
        A plot's width and length.
    gap_x, gap_y : float, optional
        The gap between neighbouring plots.
    spacing_x, spacing_y : float, optional
        The distance from one plot's start to the next one's.
    blocks_x, blocks_y : int
        Blocks (replicates) along each axis, separated by a wider gap.
    block_gap_x, block_gap_y : float, optional
        The gap between blocks.
    buffer : float
        Grow (> 0) or shrink (< 0) every plot, metres.
    """
    size_x: Optional[float] = None
    size_y: Optional[float] = None
    gap_x: Optional[float] = None
    gap_y: Optional[float] = None
    spacing_x: Optional[float] = None
    spacing_y: Optional[float] = None
    blocks_x: int = 1
    blocks_y: int = 1
    block_gap_x: Optional[float] = None
    block_gap_y: Optional[float] = None
    buffer: float = 0.0


@dataclass(frozen=True)
class FieldBookJoin:
    """A field book and how its rows join the plots.

    Parameters
    ----------
    rows : sequence of dict
        The field book's rows (``read_field_book``).
    join_by : {"plot_id", "plot_no", "row_col"}
        The key the rows and the plots share.
    book_id, book_row, book_col : str, optional
        The field book's columns of the plot id, row and column (default: found by name).
    """
    rows: Sequence[dict]
    join_by: str = "plot_id"
    book_id: Optional[str] = None
    book_row: Optional[str] = None
    book_col: Optional[str] = None


def _names(cls, skip=()):
    return [f.name for f in fields(cls) if f.name not in skip]


GROUPS = (("anchor", GridAnchor, _names(GridAnchor)), ("layout", GridLayout, _names(GridLayout)),
          ("numbering", Numbering, _names(Numbering)))
BOOK_KEYS = _names(FieldBookJoin, ("rows",))


def grid_options(**keywords) -> dict:
    """The keywords of :func:`create_plot_grid` from flat ones (``origin=…, size_x=…,
    order=…, field_book=rows, join_by=…``, as a layout table such as the demo trial's holds
    them): each group becomes its options object; other keywords pass as they are.

    Parameters
    ----------
    **keywords
        Flat keywords: the fields of :class:`GridAnchor`, :class:`GridLayout`,
        :class:`Numbering` and :class:`FieldBookJoin` (``field_book`` for its rows), and any
        other keyword of :func:`create_plot_grid`.

    Returns
    -------
    dict
        ``anchor``, ``layout``, ``numbering``, ``field_book`` where given, and the rest.
    """
    out = dict(keywords)
    for group, cls, names in GROUPS:
        given = {k: out.pop(k) for k in names if k in out}
        if given:
            if out.get(group) is not None:
                raise TypeError(f"create_plot_grid() got {group}= and its fields "
                                f"{', '.join(given)}: give {group}= only.")
            out[group] = cls(**given)
    join = {k: out.pop(k) for k in BOOK_KEYS if k in out}
    book = out.get("field_book")
    if book is not None and not isinstance(book, FieldBookJoin):
        out["field_book"] = FieldBookJoin(book, **join)
    elif join:
        raise TypeError(f"create_plot_grid(): {', '.join(join)} without field book rows.")
    return out


def grid_keywords(fn):
    """Decorate :func:`create_plot_grid`: the 0.2 keywords (``origin=…, size_x=…``, a field book
    as rows) become the options objects (:func:`grid_options`), with a ``DeprecationWarning``."""
    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        old = sorted(k for _, _, names in GROUPS for k in names if k in kwargs)
        old += sorted(k for k in BOOK_KEYS if k in kwargs)
        book = kwargs.get("field_book")
        if book is not None and not isinstance(book, FieldBookJoin):
            old.append("field_book (rows)")
        if old:
            warnings.warn(f"create_plot_grid(): the keywords {', '.join(old)} are deprecated: "
                          "give anchor=GridAnchor(…), layout=GridLayout(…), "
                          "numbering=Numbering(…), field_book=FieldBookJoin(rows, …) (the old "
                          f"keywords go in {REMOVED_IN}).", DeprecationWarning, stacklevel=2)
            kwargs = grid_options(**kwargs)
        return fn(*args, **kwargs)
    return wrapper
