"""The field book: a table of plots (genotype, treatment, replicate…) joined to a plot grid by
plot id or by row and column.

Rows are dicts (a CSV read by :func:`read_field_book`, or a table layer's features). Keys are
compared as text with surrounding spaces removed, and numbers by value ("7" = "7.0"). Rows that
match no plot and plots that match no row are reported by name in :attr:`JoinReport`; a key
that appears twice in the book is an error naming it.
"""
import csv
import io
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

from ..errors import InputError
from .layout import PlotGrid, PlotGridError

GRID_FIELDS = ("plot_id", "plot_no", "row", "col", "block")


@dataclass
class JoinReport:
    """``unmatched_rows``: book keys that match no plot; ``plots_without_row``: plot ids with
    no book row; ``fields``: the columns added."""
    unmatched_rows: List[str] = field(default_factory=list)
    plots_without_row: List[str] = field(default_factory=list)
    fields: List[str] = field(default_factory=list)

    def messages(self, limit: int = 20) -> List[str]:
        out = []
        for items, what in ((self.unmatched_rows, "Field-book rows that match no plot"),
                            (self.plots_without_row, "Plots with no field-book row")):
            if items:
                more = f" and {len(items) - limit} more" if len(items) > limit else ""
                out.append(f"{what} ({len(items)}): {', '.join(items[:limit])}{more}.")
        return out


def field_book_problem(path: str) -> Optional[str]:
    """What is wrong with a field-book file as a text table, or None: missing, empty, binary
    (NUL bytes, as in a spreadsheet workbook or a damaged file) or not text at all."""
    if not os.path.isfile(path):
        return f"Field book {path!r}: no such file."
    with open(path, "rb") as fh:
        head = fh.read(65536)
    if not head.strip():
        return (f"Field book {path!r} is empty ({os.path.getsize(path)} bytes): export the sheet "
                "again as CSV, with a header line and one row per plot.")
    kind = ("an Excel workbook (.xlsx)" if head.startswith(b"PK\x03\x04") else
            "an Excel 97 workbook (.xls)" if head.startswith(b"\xd0\xcf\x11\xe0") else
            "binary or damaged")
    nul = head.find(b"\x00")
    if nul >= 0 and not head.startswith((b"\xff\xfe", b"\xfe\xff")):
        return (f"Field book {path!r} is not a text table: it is {kind} (NUL bytes from byte "
                f"{nul}). Save the sheet as CSV (UTF-8, comma-separated) and "
                "give that file.")
    control = sum(1 for b in head if b < 32 and b not in (9, 10, 13))
    if control > max(8, len(head) // 100):
        return (f"Field book {path!r} is not a text table: {control} control bytes in its first "
                f"{len(head)} bytes (binary or damaged). Save the sheet as CSV (UTF-8) and give "
                "that file.")
    return None


def read_field_book(path: str) -> List[dict]:
    """The rows of a CSV field book (UTF-8, a BOM allowed; comma, semicolon or tab)."""
    problem = field_book_problem(path)
    if problem:
        raise InputError(problem)
    with open(path, "rb") as fh:
        raw = fh.read()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    try:
        dialect = csv.Sniffer().sniff(text[:4096], delimiters=",;\t")
    except csv.Error:
        dialect = csv.excel
    rows = list(csv.DictReader(io.StringIO(text), dialect=dialect))
    if not rows:
        raise InputError(f"Field book {path!r} has no rows under its header line.")
    return [{(k or "").strip(): (v.strip() if isinstance(v, str) else v) for k, v in r.items()
             if k is not None} for r in rows]


def _key(v) -> str:
    if v is None:
        return ""
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    s = str(v).strip()
    try:
        f = float(s)
        if f.is_integer() and s.lstrip("+-").replace(".", "", 1).isdigit():
            return str(int(f))
    except ValueError:
        pass
    return s


def _as_int(v) -> int:
    if isinstance(v, float):
        if not v.is_integer():
            raise ValueError(v)
        return int(v)
    return v if isinstance(v, int) else int(str(v).strip())


def _typed(values: Sequence) -> list:
    """A column as ints, floats or text (whichever all its non-empty values are)."""
    vals = [None if v is None or (isinstance(v, str) and v.strip() == "") else v for v in values]
    for cast in (_as_int, float):
        try:
            return [None if v is None else cast(v) for v in vals]
        except (TypeError, ValueError):
            continue
    return [None if v is None else str(v) for v in vals]


def join_field_book(grid: PlotGrid, rows: Sequence[dict], by: str = "plot_id",
                    book_id: Optional[str] = None, book_row: Optional[str] = None,
                    book_col: Optional[str] = None) -> JoinReport:
    """Join ``rows`` to ``grid`` in place (its :attr:`PlotGrid.fields`).

    ``by="plot_id"``: the book column ``book_id`` (default ``plot_id``) matches the plot ids;
    ``by="plot_no"``: it matches the plot numbers; ``by="row_col"``: the book columns
    ``book_row`` and ``book_col`` (default ``row``, ``col``) match the plots' row and column.
    """
    rows = list(rows)
    if not rows:
        raise PlotGridError("Field book: it has no rows.")
    columns = list(dict.fromkeys(k for r in rows for k in r))
    if by in ("plot_id", "plot_no"):
        keys = [book_id or by]
        plot_keys = [_key(v) for v in (grid.plot_id if by == "plot_id" else grid.plot_no)]
    elif by == "row_col":
        keys = [book_row or "row", book_col or "col"]
        plot_keys = [f"{int(r)}/{int(c)}" for r, c in zip(grid.row, grid.col)]
    else:
        raise PlotGridError(f"Field book join {by!r}: choose plot_id, plot_no or row_col.")
    missing = [k for k in keys if k not in columns]
    if missing:
        raise PlotGridError(f"Field book: no column {', '.join(map(repr, missing))} (its columns: "
                            f"{', '.join(columns)}). Name the column that holds the "
                            + ("plot id." if by != "row_col" else "row and the column."))
    # rows with nothing in them (blank lines of a spreadsheet) are not rows of the book
    numbered = [(i, r) for i, r in enumerate(rows)
                if any(v is not None and str(v).strip() != "" for v in r.values())]
    empty = [i + 2 for i, r in numbered if any(_key(r.get(k)) == "" for k in keys)]
    if empty:
        shown = ", ".join(map(str, empty[:10])) + (" …" if len(empty) > 10 else "")
        raise PlotGridError(f"Field book: {len(empty)} row(s) have no {' or '.join(keys)} (empty; "
                            f"rows {shown} of the file, the header being row 1). Fill them in or "
                            "remove those rows.")
    positions = [i for i, _ in numbered]
    rows = [r for _, r in numbered]
    book_keys = ["/".join(_key(r.get(k)) for k in keys) for r in rows]
    index: Dict[str, int] = {}
    for i, k in enumerate(book_keys):
        if k in index:
            raise PlotGridError(f"Field book: the key {k!r} ({'/'.join(keys)}) is on two rows "
                                f"({positions[index[k]] + 2} and {positions[i] + 2} of the file). "
                                "Each plot needs one row.")
        index[k] = i
    plot_index = {k: i for i, k in enumerate(plot_keys)}
    report = JoinReport()
    report.unmatched_rows = [k for k in book_keys if k not in plot_index]
    report.plots_without_row = [grid.plot_id[i] for i, k in enumerate(plot_keys) if k not in index]
    taken = set(GRID_FIELDS) | set(grid.fields)
    for col in columns:
        if col in keys or col == "":
            continue
        name = col if col not in taken else f"book_{col}"
        values = [rows[index[k]].get(col) if k in index else None for k in plot_keys]
        grid.fields[name] = _typed(values)
        taken.add(name)
        report.fields.append(name)
    return report
