"""A small synthetic field, written from a seed: orthomosaic, DSM and plot polygons.

The field is 40 m × 30 m in WGS 84 / UTM 54N (EPSG:32654): gently sloped bare soil with 24
slightly rotated plots (4 rows × 6 columns, 4 m × 2.5 m) of crop rows some decimetres tall.
The orthomosaic is RGB at 1 cm, tiled 256, deflate; the DSM is float32 at 2 cm with nodata
-9999 (heights in metres above the ellipsoid, the truth being ``ground + canopy``).
"""
import json
import os
from dataclasses import dataclass
from typing import List

import numpy as np

from .geotiff_write import epsg_geo_tags, write_geotiff

EPSG = 32654
ORIGIN = (368000.0, 3956030.0)  # top-left corner (x, y)
SIZE = (40.0, 30.0)             # metres (x, y)
DOM_PIXEL, DSM_PIXEL = 0.01, 0.02
PLOT_SIZE = (4.0, 2.5)
ROWS, COLS = 4, 6


@dataclass
class DemoField:
    folder: str
    orthomosaic: str
    dsm: str
    plots: str
    plot_ids: List[str]
    canopy_height: dict   # plot_id -> maximum crop height above the ground (m)


def _ground(x, y):
    return 95.0 + 0.02 * (x - ORIGIN[0]) + 0.01 * (y - ORIGIN[1] + SIZE[1])


def _plots(rng):
    plots = []
    for r in range(ROWS):
        for c in range(COLS):
            cx = ORIGIN[0] + 4.0 + c * 6.4
            cy = ORIGIN[1] - 4.5 - r * 7.0
            angle = np.deg2rad(rng.uniform(-4, 4))
            plots.append({"plot_id": f"{'ABCD'[r]}{c + 1}", "row": r + 1, "col": c + 1,
                          "centre": (cx, cy), "angle": angle, "height": rng.uniform(0.25, 0.7)})
    return plots


def _corners(p):
    w, h = PLOT_SIZE
    local = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
    ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
    rot = np.array([[ca, -sa], [sa, ca]])
    return local @ rot.T + p["centre"]


def _canopy(x, y, plots):
    """Crop height (m) at map points: rows 0.5 m apart along each plot's long axis."""
    h = np.zeros(x.shape)
    for p in plots:
        ca, sa = np.cos(p["angle"]), np.sin(p["angle"])
        u = (x - p["centre"][0]) * ca + (y - p["centre"][1]) * sa
        v = -(x - p["centre"][0]) * sa + (y - p["centre"][1]) * ca
        inside = (np.abs(u) < PLOT_SIZE[0] / 2 - 0.1) & (np.abs(v) < PLOT_SIZE[1] / 2 - 0.1)
        rows = np.clip(np.cos(2 * np.pi * v / 0.5), 0, None) ** 2
        plants = 0.75 + 0.25 * np.cos(2 * np.pi * u / 0.15)
        h = np.where(inside, np.maximum(h, p["height"] * rows * plants), h)
    return h


def make_demo_field(folder: str, seed: int = 0) -> DemoField:
    """Write ``orthomosaic.tif``, ``dsm.tif`` and ``plots.geojson`` into ``folder``."""
    os.makedirs(folder, exist_ok=True)
    rng = np.random.default_rng(seed)
    plots = _plots(rng)

    # DSM at 2 cm
    ny, nx = round(SIZE[1] / DSM_PIXEL), round(SIZE[0] / DSM_PIXEL)
    y = ORIGIN[1] - (np.arange(ny) + 0.5)[:, None] * DSM_PIXEL
    x = ORIGIN[0] + (np.arange(nx) + 0.5)[None, :] * DSM_PIXEL
    x, y = np.broadcast_to(x, (ny, nx)), np.broadcast_to(y, (ny, nx))
    canopy = _canopy(x, y, plots)
    dsm = (_ground(x, y) + canopy + rng.normal(0, 0.004, (ny, nx))).astype(np.float32)
    dsm[:, :40] = -9999  # a strip without data along the western edge, as real DSMs have
    dsm_path = write_geotiff(os.path.join(folder, "dsm.tif"), dsm,
                             (ORIGIN[0], DSM_PIXEL, 0.0, ORIGIN[1], 0.0, -DSM_PIXEL),
                             epsg_geo_tags(EPSG), nodata_text="-9999", tile=256)

    # orthomosaic at 1 cm: canopy upsampled from the DSM grid, soil and leaves textured
    up = np.repeat(np.repeat(canopy, 2, axis=0), 2, axis=1)
    noise = rng.normal(0, 1, up.shape).astype(np.float32)
    leaf = np.clip(up / 0.15, 0, 1)[..., None]
    soil = np.array([120, 95, 70], np.float32) + 12 * noise[..., None]
    green = np.array([60, 140, 50], np.float32) * (0.8 + 0.4 * np.clip(up / 0.7, 0, 1))[..., None] \
        + 10 * noise[..., None]
    dom = np.clip(soil * (1 - leaf) + green * leaf, 0, 255).astype(np.uint8)
    dom_path = write_geotiff(os.path.join(folder, "orthomosaic.tif"), dom,
                             (ORIGIN[0], DOM_PIXEL, 0.0, ORIGIN[1], 0.0, -DOM_PIXEL),
                             epsg_geo_tags(EPSG), rgb=True, tile=256)

    features = [{"type": "Feature",
                 "properties": {k: p[k] for k in ("plot_id", "row", "col")},
                 "geometry": {"type": "Polygon",
                              "coordinates": [np.vstack([_corners(p), _corners(p)[:1]]).tolist()]}}
                for p in plots]
    plots_path = os.path.join(folder, "plots.geojson")
    with open(plots_path, "w") as fh:
        json.dump({"type": "FeatureCollection", "name": "plots",
                   "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{EPSG}"}},
                   "features": features}, fh)
    return DemoField(folder, dom_path, dsm_path, plots_path, [p["plot_id"] for p in plots],
                     {p["plot_id"]: p["height"] for p in plots})
