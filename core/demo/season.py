"""The demo season: the demo survey's field flown on N dates while the crop grows along known
curves, each date with its orthomosaic, DSM and point cloud, and the truth per plot and date.

``make_demo_season(folder, dates=4, seed=0)`` writes, into ``folder``::

    surveys.csv             date, orthomosaic, dsm, point_cloud, project (paths relative to it)
    plots.geojson           the survey's plots (same seed, same rectangles) with plot_id, row,
                            col and variety (V1–V4, one per column modulo 4)
    bare_soil_dsm.tif       the ground before emergence: float32, 5 cm (another grid than the
                            DSMs), nodata -9999, the season's DTM
    YYYY-MM-DD/orthomosaic.tif   RGB, 1 cm, tiled 256, deflate
    YYYY-MM-DD/dsm.tif           float32, 2 cm, nodata -9999 (the survey's nodata strip in the west)
    YYYY-MM-DD/pointcloud.laz    100 points/m² on the surface, coloured, CRS in the file
    season_truth.json       per plot and date: canopy height (m) and cover (0–1); the curves

The crop grows in rows 0.5 m apart along each plot's long axis, with a 0.1 m bare edge inside
the plot. On a date at day t after sowing, a row is a band of canopy ``w(t)`` wide whose height
across the band is a dome ``H(t)·√(1 − (2d/w)²)`` (d: distance to the row centre), slightly
modulated along the row (plants 0.15 m apart, ±3 %); ``H`` and ``w`` are logistic in t, per
variety and plot. Truth, by construction and independent of the engine:

* height = ``H(t)``, the canopy top (m);
* cover = the share of the plot rectangle's area under canopy, analytically: the sum over rows
  of their band's overlap with the inner rectangle, times its length, over the plot area.

Heights are ellipsoidal (WGS 84) above the ground plane of the survey's field, in metres, map
CRS EPSG:32654. Same seed → same files.
"""
import csv
import datetime as dt
import io
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..errors import InputError
from ..files import write_bytes, write_json
from ..pointcloud import PointCloud, write_point_cloud
from ..progress import as_progress
from ..raster import epsg_geo_tags, write_geotiff
from .field import DOM_PIXEL, DSM_PIXEL, EDGE, NODATA, PLANT_SPACING, ROW_SPACING, FieldLayout, \
    make_plots, plot_corners, plot_window
from .scene import SURVEY_FIELD
from .survey import LAS_DATE

SOWING = dt.date(2024, 5, 1)
FIRST_DAY, LAST_DAY = 21, 63          # days after sowing of the first and last flights
DTM_PIXEL = 0.05
CLOUD_DENSITY = 100.0                 # points per m²
DSM_NOISE, CLOUD_NOISE, DTM_NOISE = 0.003, 0.004, 0.003   # m, standard deviations
PLANT_RIPPLE = 0.03                   # relative height modulation along a row
VARIETIES = {                         # final height (m), day of half height, final row width (m)
    "V1": (0.55, 33.0, 0.36), "V2": (0.75, 36.0, 0.42),
    "V3": (0.95, 40.0, 0.44), "V4": (0.65, 30.0, 0.30)}
HEIGHT_RATE, WIDTH_RATE = 6.5, 8.0    # days: logistic scale of height and row width
SOIL_RGB = np.array([122, 96, 72], np.float32)
LEAF_RGB = np.array([58, 132, 46], np.float32)
COLOUR_NOISE = 5.0                    # per-channel noise of the orthomosaic (grey levels, sd)
BAND_ROWS = 512                       # orthomosaic rows painted at once
TRUTH_FORMAT = "easyidp-demo-season-truth"


@dataclass
class DemoSeason:
    """Absolute paths of what :func:`make_demo_season` wrote."""
    folder: str
    surveys: str
    plots: str
    ground: str
    truth: str
    dates: List[str]
    orthomosaics: List[str] = field(default_factory=list)
    dsms: List[str] = field(default_factory=list)
    point_clouds: List[str] = field(default_factory=list)
    plot_ids: List[str] = field(default_factory=list)


def season_days(n: int) -> List[int]:
    """Days after sowing of ``n`` flights, evenly from FIRST_DAY to LAST_DAY."""
    if n == 1:
        return [FIRST_DAY]
    return [int(round(FIRST_DAY + k * (LAST_DAY - FIRST_DAY) / (n - 1))) for k in range(n)]


def growth(p: dict, day: float):
    """(canopy height H, row width w) of plot ``p`` on ``day`` after sowing, in metres."""
    h = p["h_max"] / (1.0 + np.exp(-(day - p["t_half"]) / HEIGHT_RATE))
    w = p["w_max"] / (1.0 + np.exp(-(day - p["t_half"] + 3.0) / WIDTH_RATE))
    return float(h), float(w)


def row_centres(p: dict) -> np.ndarray:
    """Across-plot offsets (m) of the rows inside the plot's inner rectangle."""
    a = p["size"][1] / 2 - EDGE
    k = np.arange(-np.floor(a / ROW_SPACING), np.floor(a / ROW_SPACING) + 1)
    return k * ROW_SPACING


def true_cover(p: dict, w: float) -> float:
    """Share of the plot rectangle under canopy (analytic): each row's band [v − w/2, v + w/2]
    clipped to the inner rectangle, times the inner length, over the plot area."""
    length, width = p["size"]
    a = width / 2 - EDGE
    across = sum(max(0.0, min(v + w / 2, a) - max(v - w / 2, -a)) for v in row_centres(p))
    return across * (length - 2 * EDGE) / (length * width)


def canopy_at(p: dict, day: float, x: np.ndarray, y: np.ndarray):
    """(leaf: bool, height: m) of plot ``p``'s canopy at map points (x, y) on ``day``."""
    h, w = growth(p, day)
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    dx, dy = x - p["centre"][0], y - p["centre"][1]
    u = dx * ca + dy * sa
    v = -dx * sa + dy * ca
    a = p["size"][1] / 2 - EDGE
    inner = (np.abs(u) < p["size"][0] / 2 - EDGE) & (np.abs(v) < a)
    d = np.abs(v - np.clip(np.round(v / ROW_SPACING), -np.floor(a / ROW_SPACING),
                           np.floor(a / ROW_SPACING)) * ROW_SPACING)
    leaf = inner & (d < w / 2)
    dome = np.sqrt(np.clip(1.0 - (2.0 * d / max(w, 1e-9)) ** 2, 0.0, 1.0))
    ripple = 1.0 - PLANT_RIPPLE * 0.5 * (1.0 - np.cos(2 * np.pi * u / PLANT_SPACING))
    return leaf, np.where(leaf, h * dome * ripple, 0.0)


def make_plots_with_varieties(layout: FieldLayout, seed: int) -> List[dict]:
    """The survey's plots (same seed → same rectangles) with a variety and growth parameters."""
    plots = make_plots(layout, np.random.default_rng(seed))
    rng = np.random.default_rng([seed, 23])
    names = sorted(VARIETIES)
    for p in plots:
        v = names[(p["col"] - 1) % len(names)]
        h, t, w = VARIETIES[v]
        p.update(variety=v, h_max=h * rng.uniform(0.9, 1.1), t_half=t + rng.uniform(-2, 2),
                 w_max=w * rng.uniform(0.95, 1.05))
        p.pop("height", None)
    return plots


def _grid(layout: FieldLayout, pixel: float, rows: slice):
    ny, nx = layout.grid_shape(pixel)
    r = np.arange(rows.start, min(rows.stop, ny))
    y = layout.origin[1] - (r + 0.5) * pixel
    x = layout.origin[0] + (np.arange(nx) + 0.5) * pixel
    return x, y


def canopy_grid(layout: FieldLayout, plots: List[dict], day: float, pixel: float):
    """(leaf, height) on the ``pixel`` grid of the field, each plot evaluated in its window."""
    ny, nx = layout.grid_shape(pixel)
    leaf = np.zeros((ny, nx), bool)
    height = np.zeros((ny, nx), np.float32)
    for p in plots:
        win = plot_window(layout, p, pixel)
        if win is None:
            continue
        (i0, i1, j0, j1), x, y = win
        lf, h = canopy_at(p, day, x, y)
        leaf[i0:i1, j0:j1] |= lf
        height[i0:i1, j0:j1] = np.maximum(height[i0:i1, j0:j1], h)
    return leaf, height


def _ground_grid(layout: FieldLayout, pixel: float) -> np.ndarray:
    ny, nx = layout.grid_shape(pixel)
    x, y = _grid(layout, pixel, slice(0, ny))
    return layout.ground_height(x[None, :], y[:, None])


def _dsm(layout, plots, day, rng) -> np.ndarray:
    _, h = canopy_grid(layout, plots, day, DSM_PIXEL)
    z = _ground_grid(layout, DSM_PIXEL) + h + rng.normal(0.0, DSM_NOISE, h.shape)
    z = z.astype(np.float32)
    z[:, :layout.nodata_cols] = NODATA
    return z


def _orthomosaic(layout, plots, day, seed, k) -> np.ndarray:
    """RGB at 1 cm: soil (smooth moisture on 1 m, grain, colour noise) and leaves shaded by
    their height."""
    ny, nx = layout.grid_shape(DOM_PIXEL)
    leaf, height = canopy_grid(layout, plots, day, DOM_PIXEL)
    top = max(float(height.max()), 1e-6)
    rng = np.random.default_rng([seed, 31, k])
    moist = rng.standard_normal((ny // 100 + 2, nx // 100 + 2)).astype(np.float32)
    sun = np.float32(1.0 + 0.06 * np.sin(1.7 * k))           # brightness changes by date
    out = np.empty((ny, nx, 3), np.uint8)
    for b0 in range(0, ny, BAND_ROWS):
        b1 = min(b0 + BAND_ROWS, ny)
        rows = (np.arange(b0, b1) // 100)[:, None]
        cols = (np.arange(nx) // 100)[None, :]
        shade = sun * (1.0 + 0.06 * moist[rows, cols])
        grain = rng.integers(-9, 10, (b1 - b0, nx)).astype(np.float32)
        lf, h = leaf[b0:b1], height[b0:b1] / top
        for c in range(3):
            tint = rng.normal(0.0, COLOUR_NOISE, (b1 - b0, nx)).astype(np.float32)
            soil = SOIL_RGB[c] * shade + grain + tint
            green = LEAF_RGB[c] * sun * (0.8 + 0.35 * h) + 1.3 * grain + 2 * tint
            out[b0:b1, :, c] = np.clip(np.where(lf, green, soil), 0, 255).astype(np.uint8)
    return out


def _cloud(layout, plots, day, rng, ortho):
    """Points uniformly over the field with data, z = ground + canopy + noise, coloured."""
    w, h = layout.size
    n = int(CLOUD_DENSITY * w * h)
    x = layout.origin[0] + layout.nodata_cols * DSM_PIXEL + rng.uniform(0, 1, n) * (
        w - layout.nodata_cols * DSM_PIXEL)
    y = layout.origin[1] - rng.uniform(0, 1, n) * h
    z = layout.ground_height(x, y) + rng.normal(0.0, CLOUD_NOISE, n)
    canopy = np.zeros(n)
    for p in plots:
        c = plot_corners(p)
        sel = np.flatnonzero((x >= c[:, 0].min()) & (x <= c[:, 0].max()) &
                             (y >= c[:, 1].min()) & (y <= c[:, 1].max()))
        _, hh = canopy_at(p, day, x[sel], y[sel])
        canopy[sel] = np.maximum(canopy[sel], hh)
    col = np.clip(((x - layout.origin[0]) / DOM_PIXEL).astype(np.intp), 0, ortho.shape[1] - 1)
    row = np.clip(((layout.origin[1] - y) / DOM_PIXEL).astype(np.intp), 0, ortho.shape[0] - 1)
    return np.column_stack([x, y, z + canopy]), ortho[row, col]


def make_demo_season(folder: str, dates: int = 4, seed: int = 0,
                     layout: Optional[FieldLayout] = None, progress=None,
                     is_cancelled=None) -> DemoSeason:
    """Write the demo season (see the module docstring) into ``folder`` and return its paths.

    ``layout``: the field (default: the demo survey's); tests pass a smaller one.
    """
    if not 1 <= int(dates) <= 30:
        raise InputError(f"Demo season: {dates} dates; choose 1 to 30.")
    prog = as_progress(progress, is_cancelled)
    layout = layout or SURVEY_FIELD
    folder = os.path.abspath(folder)
    os.makedirs(folder, exist_ok=True)
    plots = make_plots_with_varieties(layout, seed)
    tags = epsg_geo_tags(layout.epsg)
    days = season_days(int(dates))
    labels = [(SOWING + dt.timedelta(days=d)).isoformat() for d in days]
    season = DemoSeason(folder, os.path.join(folder, "surveys.csv"),
                        os.path.join(folder, "plots.geojson"),
                        os.path.join(folder, "bare_soil_dsm.tif"),
                        os.path.join(folder, "season_truth.json"), labels,
                        plot_ids=[p["plot_id"] for p in plots])
    _write_plots(season.plots, plots, layout.epsg)
    rng = np.random.default_rng([seed, 29])
    dtm = (_ground_grid(layout, DTM_PIXEL) + rng.normal(0.0, DTM_NOISE, layout.grid_shape(DTM_PIXEL)))
    write_geotiff(season.ground, dtm.astype(np.float32), layout.geotransform(DTM_PIXEL), tags,
                  nodata_text="-9999", tile=256)
    for k, (day, label) in enumerate(zip(days, labels)):
        prog.check()
        sub = os.path.join(folder, label)
        os.makedirs(sub, exist_ok=True)
        r = np.random.default_rng([seed, 37, k])
        ortho = _orthomosaic(layout, plots, day, seed, k)
        season.orthomosaics.append(write_geotiff(
            os.path.join(sub, "orthomosaic.tif"), ortho, layout.geotransform(DOM_PIXEL), tags,
            rgb=True, tile=256))
        season.dsms.append(write_geotiff(
            os.path.join(sub, "dsm.tif"), _dsm(layout, plots, day, r),
            layout.geotransform(DSM_PIXEL), tags, nodata_text="-9999", tile=256))
        xyz, rgb = _cloud(layout, plots, day, r, ortho)
        cloud = PointCloud.from_arrays(xyz, {"red": rgb[:, 0], "green": rgb[:, 1],
                                             "blue": rgb[:, 2]}, crs=f"EPSG:{layout.epsg}")
        laz = str(write_point_cloud(cloud, os.path.join(sub, "pointcloud.laz")))
        with open(laz, "r+b") as fh:                 # LAS header: creation day and year, fixed
            fh.seek(90)
            fh.write(np.array(LAS_DATE, "<u2").tobytes())
        season.point_clouds.append(laz)
        prog.set(100.0 * (k + 1) / len(days))
    _write_table(season)
    _write_truth(season, plots, days, layout)
    return season


def _write_plots(path: str, plots: List[dict], epsg: int) -> None:
    features = [{"type": "Feature",
                 "properties": {k: p[k] for k in ("plot_id", "row", "col", "variety")},
                 "geometry": {"type": "Polygon", "coordinates": [
                     np.vstack([plot_corners(p), plot_corners(p)[:1]]).tolist()]}}
                for p in plots]
    write_json(path, {"type": "FeatureCollection", "name": "plots",
                      "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{epsg}"}},
                      "features": features})


def _write_table(season: DemoSeason) -> None:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["date", "orthomosaic", "dsm", "point_cloud", "project"])
    for label in season.dates:
        w.writerow([label, f"{label}/orthomosaic.tif", f"{label}/dsm.tif",
                    f"{label}/pointcloud.laz", ""])
    write_bytes(season.surveys, buf.getvalue().encode())


def _write_truth(season: DemoSeason, plots: List[dict], days: List[int], layout) -> None:
    truth: Dict[str, dict] = {}
    for p in plots:
        hw = [growth(p, d) for d in days]
        truth[p["plot_id"]] = {
            "variety": p["variety"], "h_max": p["h_max"], "t_half": p["t_half"],
            "w_max": p["w_max"], "height": [h for h, _ in hw],
            "cover": [true_cover(p, w) for _, w in hw], "row_width": [w for _, w in hw]}
    write_json(season.truth, {
        "format": TRUTH_FORMAT, "version": 1, "crs": f"EPSG:{layout.epsg}",
        "sowing": SOWING.isoformat(), "dates": season.dates, "days_after_sowing": days,
        "height": "canopy top above the ground plane, metres (H(t), logistic)",
        "cover": "share of the plot rectangle's area under canopy (analytic, 0-1)",
        "ground": "the field's ground plane; bare_soil_dsm.tif samples it with noise",
        "plots": truth}, indent=1)
