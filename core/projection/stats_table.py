"""The result of :func:`.photo_stats.photo_statistics`: the statistics of every ROI × photo and
their across-view summary per ROI, as tables and CSV."""
import csv
import io
import math
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..files import write_bytes


@dataclass
class PhotoStatistics:
    """The statistics of every ROI × photo and their across-view summary per ROI.

    Views (one row per record of the back-projection, in its order): ``record`` (its index),
    ``roi`` (index into ``roi_names``), ``photo``, ``values`` (k, len(columns)),
    ``polygon_pixels`` (pixel centres in the polygon), ``pixels`` (measured: not occluded, not
    masked), ``occluded_share`` (share of the polygon's pixels left out as occluded; NaN when not
    tested), ``undecided_share`` (lines of sight that met no DSM data), ``visible_share``,
    ``used`` and ``why`` (why a view is not used), ``deviation`` (see the module docstring), and
    from the back-projection ``rank``, ``score``, ``view_angle``, ``gsd``, ``visible_fraction``.

    Each view's time and sun: ``acquired`` (ISO 8601, with the UTC offset when the photo gives
    it; "" unknown), ``sun_zenith``, ``sun_azimuth`` (degrees, clockwise from north) and
    ``phase_angle`` (sun–ROI–camera, degrees; NaN unknown). ``values_kind``: ``stored``,
    ``temperature`` or ``reflectance`` (the unit is in the column names: ``temp_c_mean``,
    ``nir_refl_median``).

    Per ROI: ``median``/``mad``/``minimum``/``maximum`` (n_rois, len(columns)), ``views``
    (views used) and ``disagreement``.
    """
    roi_names: List[str]
    bands: List[str]
    indices: List[str]
    columns: List[str]
    record: np.ndarray
    roi: np.ndarray
    photo: np.ndarray
    rank: np.ndarray
    score: np.ndarray
    view_angle: np.ndarray
    gsd: np.ndarray
    visible_fraction: np.ndarray
    values: np.ndarray
    polygon_pixels: np.ndarray
    pixels: np.ndarray
    occluded_share: np.ndarray
    undecided_share: np.ndarray
    visible_share: np.ndarray
    used: np.ndarray
    why: List[str]
    deviation: np.ndarray
    median: np.ndarray
    mad: np.ndarray
    minimum: np.ndarray
    maximum: np.ndarray
    views: np.ndarray
    disagreement: np.ndarray
    cover_index: Optional[str] = None
    cover_threshold: Optional[float] = None
    threshold_source: str = ""
    weighted: bool = False
    skipped_photos: Dict[str, str] = field(default_factory=dict)
    previews: List[str] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    warnings: List[str] = field(default_factory=list)
    photos_decoded: int = 0
    rays: int = 0
    values_kind: str = "stored"
    acquired: List[str] = field(default_factory=list)
    sun_zenith: Optional[np.ndarray] = None
    sun_azimuth: Optional[np.ndarray] = None
    phase_angle: Optional[np.ndarray] = None

    def column(self, name: str) -> np.ndarray:
        """One statistic of every view."""
        return self.values[:, self.columns.index(name)]

    def roi_value(self, name: str) -> np.ndarray:
        """One statistic's across-view value of every ROI."""
        return self.median[:, self.columns.index(name)]

    VIEW_FIELDS = ("roi", "photo", "rank", "score", "view_angle", "gsd", "visible_fraction",
                   "polygon_pixels", "pixels", "occluded_share", "undecided_share",
                   "visible_share", "used", "why", "deviation", "acquired", "sun_zenith",
                   "sun_azimuth", "phase_angle")

    def view_rows(self) -> List[dict]:
        rows = []
        for k in range(len(self.record)):
            row = {"roi": self.roi_names[int(self.roi[k])], "photo": str(self.photo[k]),
                   "rank": int(self.rank[k]), "score": _num(self.score[k]),
                   "view_angle": _num(self.view_angle[k]), "gsd": _num(self.gsd[k]),
                   "visible_fraction": _num(self.visible_fraction[k]),
                   "polygon_pixels": int(self.polygon_pixels[k]), "pixels": int(self.pixels[k]),
                   "occluded_share": _num(self.occluded_share[k]),
                   "undecided_share": _num(self.undecided_share[k]),
                   "visible_share": _num(self.visible_share[k]), "used": bool(self.used[k]),
                   "why": self.why[k], "deviation": _num(self.deviation[k]),
                   "acquired": self.acquired[k] if k < len(self.acquired) else "",
                   "sun_zenith": _opt(self.sun_zenith, k), "sun_azimuth": _opt(self.sun_azimuth, k),
                   "phase_angle": _opt(self.phase_angle, k)}
            row.update({c: _num(v) for c, v in zip(self.columns, self.values[k])})
            rows.append(row)
        return rows

    def roi_fields(self) -> List[str]:
        """Names of the per-ROI values: each statistic (its across-view median), then its
        ``_mad``, ``_min`` and ``_max``, then ``views`` and ``disagreement``."""
        out = list(self.columns)
        for suffix in ("mad", "min", "max"):
            out += [f"{c}_{suffix}" for c in self.columns]
        return out + ["views", "disagreement"]

    def roi_rows(self) -> List[dict]:
        rows = []
        for r, name in enumerate(self.roi_names):
            vals = list(self.median[r]) + list(self.mad[r]) + list(self.minimum[r]) \
                + list(self.maximum[r])
            row = {"roi": name}
            row.update({f: _num(v) for f, v in zip(self.roi_fields(), vals)})
            row["views"] = int(self.views[r])
            row["disagreement"] = _num(self.disagreement[r])
            rows.append(row)
        return rows

    def write_csv(self, views_path=None, rois_path=None) -> List[str]:
        """The views table and/or the per-ROI table as CSV (atomically); returns the paths."""
        out = []
        for path, rows in ((views_path, self.view_rows), (rois_path, self.roi_rows)):
            if path is None:
                continue
            data = rows()
            buf = io.StringIO()
            if data:
                w = csv.DictWriter(buf, fieldnames=list(data[0]), lineterminator="\n")
                w.writeheader()
                w.writerows({k: ("" if v is None else v) for k, v in row.items()} for row in data)
            write_bytes(path, buf.getvalue().encode("utf-8"))
            out.append(os.fspath(path))
        return out

    def summary(self) -> str:
        used = int(self.used.sum())
        seen = int((self.views > 0).sum())
        out = (f"{len(self.record)} views measured, {used} used, for {seen} of "
               f"{len(self.roi_names)} ROIs")
        if self.cover_index:
            out += (f"; cover: {self.cover_index.upper()} ≥ {self.cover_threshold:.4f} "
                    f"({self.threshold_source})") if self.cover_threshold is not None else \
                f"; cover: no threshold ({self.threshold_source})"
        if self.skipped_photos:
            out += f"; {len(self.skipped_photos)} photo(s) skipped"
        return out


def _num(v):
    v = float(v)
    return None if not math.isfinite(v) else v


def _opt(arr, k):
    return None if arr is None else _num(arr[k])
