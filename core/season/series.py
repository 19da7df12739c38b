"""A season's table of surveys: one row per flight, with its date and its files.

Columns (names case-insensitive, in any order; extra columns are ignored):

* ``date`` (required): ISO date ``YYYY-MM-DD`` (a time after it, ``T10:30`` or `` 10:30``, is
  kept: two flights on one day stay apart);
* ``orthomosaic``, ``dsm``, ``point_cloud``, ``project``: file paths, absolute or relative to
  the table's folder; empty cells allowed (at least one of the first three per row);
* ``bands`` (optional): names of the orthomosaic's bands in order, e.g. ``blue,green,red,
  rededge,nir`` (NDVI needs ``red`` and ``nir``); else GDAL's band descriptions, else RGB;
* ``crs`` (optional): the CRS of files that carry none (a PLY cloud), EPSG code or WKT.

Rows are numbered from 1, the header not counted. A bad row or a missing file is reported as a
:class:`RowProblem` and left out; it never stops the season.
"""
import csv
import datetime as dt
import os
import re
from dataclasses import dataclass, field
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

from ..errors import InputError

FILE_COLUMNS = ("orthomosaic", "dsm", "point_cloud", "project")
DATA_COLUMNS = ("orthomosaic", "dsm", "point_cloud")      # the files traits are computed from
OPTIONAL_COLUMNS = ("bands", "crs")
_TIME = re.compile(r"^(\d{4}-\d{2}-\d{2})(?:[T ](\d{2}):(\d{2})(?::(\d{2}))?)?$")


@dataclass
class Survey:
    """One flight of the season. Paths are absolute; None where the table gives none (or the
    file is missing, which is then a :class:`RowProblem`)."""
    row: int
    date: str
    orthomosaic: Optional[str] = None
    dsm: Optional[str] = None
    point_cloud: Optional[str] = None
    project: Optional[str] = None
    bands: Optional[Tuple[str, ...]] = None
    crs: Optional[str] = None

    def files(self) -> Dict[str, str]:
        """{column: path} of the data files this survey has (orthomosaic, dsm, point_cloud)."""
        return {c: getattr(self, c) for c in DATA_COLUMNS if getattr(self, c)}


@dataclass
class RowProblem:
    """Why a row, or one file of it, is left out of the season."""
    row: int
    date: str
    column: str      # '' for the whole row
    message: str

    def __str__(self) -> str:
        where = f"row {self.row}" + (f" ({self.date})" if self.date else "")
        return f"{where}, {self.column}: {self.message}" if self.column else f"{where}: {self.message}"


@dataclass
class SurveyTable:
    surveys: List[Survey]
    problems: List[RowProblem] = field(default_factory=list)
    source: Optional[str] = None


def parse_date(text: str) -> str:
    """'2024-06-01' (or with a time, '2024-06-01T10:30') normalised; ValueError otherwise."""
    s = str(text or "").strip()
    m = _TIME.match(s)
    if not m:
        raise ValueError(s)
    day = dt.date.fromisoformat(m.group(1)).isoformat()
    if m.group(2) is None:
        return day
    t = dt.time(int(m.group(2)), int(m.group(3)), int(m.group(4) or 0))
    return f"{day}T{t.strftime('%H:%M:%S' if m.group(4) else '%H:%M')}"


def read_survey_table(path: str) -> SurveyTable:
    """Read a CSV table of surveys (comma, semicolon or tab separated; UTF-8, BOM allowed).

    Paths in it are relative to the table's folder. Raises :class:`InputError` when the file
    cannot be read or has no ``date`` column or no file column; row problems are returned.
    """
    if not os.path.isfile(path):
        raise InputError(f"Survey table not found: {path}")
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"The survey table {path} cannot be read ({exc}); save it as UTF-8 "
                         "CSV.") from None
    first = text.splitlines()[0] if text.strip() else ""
    delimiter = max((",", ";", "\t"), key=first.count)
    rows = list(csv.DictReader(text.splitlines(), delimiter=delimiter))
    table = surveys_from_rows(rows, os.path.dirname(os.path.abspath(path)), label=path)
    table.source = path
    return table


def surveys_from_rows(rows: Iterable[Dict[str, object]], base_dir: str,
                      label: str = "the survey table") -> SurveyTable:
    """Surveys from rows (dicts of column → value, e.g. a CSV or the features of a QGIS table).

    Relative paths are taken from ``base_dir``. Values may be None (empty cells).
    """
    rows = [{str(k).strip().lower(): v for k, v in r.items() if k is not None} for r in rows]
    columns = set().union(*rows) if rows else set()
    if rows and "date" not in columns:
        raise InputError(f"{label} has no 'date' column (it has {', '.join(sorted(columns))}). "
                         "Name the columns date, orthomosaic, dsm, point_cloud, project.")
    if rows and not columns & set(DATA_COLUMNS):
        raise InputError(f"{label} has none of the columns {', '.join(DATA_COLUMNS)}: there is "
                         "nothing to compute traits from.")
    if not rows:
        raise InputError(f"{label} has no survey rows.")
    surveys, problems = [], []
    for n, raw in enumerate(rows, start=1):
        value = {k: _text(v) for k, v in raw.items()}
        try:
            date = parse_date(value.get("date", ""))
        except ValueError:
            problems.append(RowProblem(n, "", "date", f"{value.get('date', '')!r} is not a date; "
                                       "write it as YYYY-MM-DD. The row is left out."))
            continue
        s = Survey(n, date)
        for col in FILE_COLUMNS:
            p = value.get(col, "")
            if not p:
                continue
            p = os.path.expanduser(p)
            p = p if os.path.isabs(p) else os.path.join(base_dir, p)
            p = os.path.normpath(p)
            if not os.path.exists(p):
                problems.append(RowProblem(n, date, col, f"file not found: {p}"))
                continue
            setattr(s, col, p)
        if value.get("bands"):
            s.bands = tuple(b.strip().lower() for b in re.split(r"[,;\s]+", value["bands"])
                            if b.strip())
        s.crs = value.get("crs") or None
        if not s.files():
            if not any(value.get(c) for c in DATA_COLUMNS):
                problems.append(RowProblem(n, date, "", "no orthomosaic, DSM or point cloud "
                                           "given; the row is left out."))
            continue
        surveys.append(s)
    return SurveyTable(surveys, problems)


def _text(v) -> str:
    if v is None:
        return ""
    s = str(v).strip()
    return "" if s.upper() == "NULL" else s


def season_dates(surveys: Sequence[Survey]) -> List[str]:
    """The distinct dates, in order."""
    return sorted({s.date for s in surveys})
