"""Where backward projection takes the heights of ROI vertices: a ROI must be 3-D before it is
projected.

Four sources, one of them required (:func:`height_source`):

* :class:`GeometryZ` — the Z of 3-D geometries (PolygonZ, e.g. the output of *ROI heights from
  DSM*), linearly interpolated along the edges when they are densified;
* a :class:`~core.raster.DSM` — sampled bilinearly (between pixel centres,
  :meth:`~core.raster.DSM.heights`) at every vertex, including the vertices added by
  densification, so long edges follow the terrain (an opened ``GeoTiff`` is accepted for it);
* :class:`PerROIHeights` — one height per ROI: a sequence aligned with the ROIs, or the name of
  a numeric ROI attribute (e.g. a plot's mean DSM height);
* :class:`ConstantHeight` — one height for every vertex (a number is accepted for it).

Heights are in the vertical reference of the ROIs' CRS as the photogrammetry project reads it
(:mod:`core.reconstruction.geodesy`: ellipsoidal for 2-D CRSs of a georeferenced Metashape
chunk; the project's output heights for Pix4D).
"""
from dataclasses import dataclass
from typing import List, Optional, Sequence, Union

import numpy as np

from ..errors import EasyIDPError, ROIError
from ..raster import DSM, GeoTiff


class HeightSource:
    """Base class of the sources that are not a DSM; ``describe()`` says what gives the heights
    (a :class:`~core.raster.DSM` describes itself the same way)."""

    def describe(self) -> str:
        raise NotImplementedError


@dataclass(frozen=True)
class GeometryZ(HeightSource):
    def describe(self) -> str:
        return "geometry Z"


@dataclass(frozen=True)
class PerROIHeights(HeightSource):
    """``values``: one height per ROI (sequence aligned with the ROIs) or an attribute name."""
    values: Union[str, Sequence[float]]

    def describe(self) -> str:
        return (f"attribute {self.values!r}" if isinstance(self.values, str)
                else "one height per ROI")


@dataclass(frozen=True)
class ConstantHeight(HeightSource):
    height: float

    def describe(self) -> str:
        return f"constant {self.height:g}"


HEIGHTS_HELP = ("Give the ROI vertex heights: heights='geometry' (3-D ROIs, e.g. from ROI heights "
                "from DSM), DSM(dsm_path), PerROIHeights(values or attribute name) or a "
                "constant ground height (a number).")


def height_source(heights):
    """A :class:`HeightSource` or a :class:`~core.raster.DSM` from one of them, an opened
    ``GeoTiff`` (a DSM), ``"geometry"``/``"z"``, or a number (constant)."""
    if isinstance(heights, (HeightSource, DSM)):
        return heights
    if heights is None:
        raise EasyIDPError(f"No height source: a ROI must be 3-D to be projected into photos. "
                           f"{HEIGHTS_HELP}")
    if isinstance(heights, str) and heights.lower() in ("geometry", "z"):
        return GeometryZ()
    if isinstance(heights, (int, float, np.integer, np.floating)) and not isinstance(heights, bool):
        if not np.isfinite(heights):
            raise EasyIDPError(f"The constant height {heights} is not a finite number.")
        return ConstantHeight(float(heights))
    if isinstance(heights, GeoTiff):
        return DSM(heights)
    raise EasyIDPError(f"Height source {heights!r} not understood. {HEIGHTS_HELP}")


def per_roi_values(source: PerROIHeights, rois) -> np.ndarray:
    """(n_rois,) heights of a :class:`PerROIHeights`; a missing value names its ROI."""
    if isinstance(source.values, str):
        name = source.values
        vals = []
        for r in rois:
            if name not in r.attributes:
                raise ROIError(f"ROI {r.name!r} has no attribute {name!r} to take its height from.")
            vals.append(r.attributes[name])
    else:
        vals = list(source.values)
        if len(vals) != len(rois):
            raise EasyIDPError(f"{len(vals)} heights given for {len(rois)} ROIs: give one per ROI.")
    out = np.empty(len(rois))
    for i, (r, v) in enumerate(zip(rois, vals)):
        try:
            out[i] = float(v)
        except (TypeError, ValueError):
            out[i] = np.nan
        if not np.isfinite(out[i]):
            raise ROIError(f"ROI {r.name!r} has no height ({v!r}): fill the value, or choose "
                           "another height source.")
    return out


def check_geometry_z(rois) -> None:
    missing = [r.name for r in rois if r.z is None]
    if missing:
        more = f" and {len(missing) - 5} more" if len(missing) > 5 else ""
        raise ROIError(f"{len(missing)} ROI(s) have no Z ({', '.join(map(repr, missing[:5]))}{more}), "
                       "so their heights cannot come from the geometry. Give 3-D polygons (e.g. "
                       "from ROI heights from DSM), a DSM, an attribute or a constant height.")
    for r in rois:
        for z in r.ring_z:
            if not np.all(np.isfinite(z)):
                raise ROIError(f"ROI {r.name!r} has vertices without a valid Z (NaN).")


def missing_heights_error(names: List[str], what: Optional[str] = None) -> ROIError:
    more = f" and {len(names) - 5} more" if len(names) > 5 else ""
    return ROIError(f"The DSM has no data under some vertices of {len(names)} ROI(s) "
                    f"({', '.join(map(repr, names[:5]))}{more}): they lie outside the DSM or on "
                    f"nodata. Use a DSM that covers them, or another height source.")
