"""The season's outputs as files: the long table (CSV and GeoPackage) and the wide layer.

* Long table: ``roi, date, trait, value``, one row per value (tidy), in ROI order, then date,
  then trait. CSV: UTF-8, comma separated, values with 10 significant digits.
* Wide layer (GeoPackage layer ``latest``): the ROIs (multipolygons in their CRS) with their
  own attributes, ``date`` (the ROI's latest date with values) and one field per trait at that
  date (NULL where the trait has no value then).
"""
import csv
import io
from typing import List, Optional, Tuple

from ..files import check_not_inputs, write_bytes
from ..gpkg import GpkgTable, field_type, write_geopackage
from .season import SeasonResult

LONG_FIELDS = ("roi", "date", "trait", "value")


def long_csv_text(result: SeasonResult) -> str:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(LONG_FIELDS)
    for roi, date, trait, value in result.rows:
        w.writerow((roi, date, trait, f"{value:.10g}"))
    return buf.getvalue()


def write_long_csv(result: SeasonResult, path: str) -> str:
    """The long table as CSV, written atomically (never over an input of the season)."""
    check_not_inputs(path, result.inputs)
    write_bytes(path, long_csv_text(result).encode("utf-8"))
    return path


def wide_fields(result: SeasonResult) -> Tuple[List[Tuple[str, str]], List[list]]:
    """(fields, rows) of the wide layer's attributes: the ROIs' own attributes (those whose
    names clash with the new fields are dropped), ``date``, then one REAL field per trait."""
    new = {"date", *result.traits}
    own = []
    for r in result.rois:
        for k in r.attributes:
            if k not in own and k.lower() not in {n.lower() for n in new} and k.lower() != "fid":
                own.append(k)
    fields = [(k, field_type([r.attributes.get(k) for r in result.rois])) for k in own]
    fields += [("date", "TEXT")] + [(t, "REAL") for t in result.traits]
    rows = []
    for roi, (date, values) in zip(result.rois, result.latest()):
        rows.append([_attr(roi.attributes.get(k)) for k in own] + [date]
                    + [values.get(t) for t in result.traits])
    return fields, rows


def _attr(v):
    return v if v is None or isinstance(v, (int, float, str, bool)) else str(v)


def write_season_geopackage(result: SeasonResult, path: str, long_layer: Optional[str] = "traits",
                            wide_layer: Optional[str] = "latest") -> str:
    """One GeoPackage with the long table (attribute table ``long_layer``) and the wide layer
    (``wide_layer``); either may be None to leave it out. Never written over an input."""
    check_not_inputs(path, result.inputs)
    tables = []
    if long_layer:
        tables.append(GpkgTable(long_layer, [("roi", "TEXT"), ("date", "TEXT"), ("trait", "TEXT"),
                                             ("value", "REAL")], result.rows))
    if wide_layer:
        fields, rows = wide_fields(result)
        tables.append(GpkgTable(wide_layer, fields, rows, [r.parts for r in result.rois],
                                result.rois.crs))
    return write_geopackage(path, tables)


