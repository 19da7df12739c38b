"""The demo survey's thermal camera: FLIR radiometric JPEGs of a known temperature field, taken
from the poses of the survey's photos (a thermal camera registered to the RGB one, as a
Zenmuse XT2's pairs are), so the survey's Metashape project measures them by file name.

The field: each plot's canopy and soil at one temperature (``plot_temperatures``: 22–32 °C,
cooler where plants transpire more), the alleys and margins at :data:`SOIL_C`. Each pixel takes
the temperature of the point of the surface it sees (the renderer's ray–surface hit), plus the
camera's noise (0.05 °C); the raw values follow from the Planck curve with
:data:`THERMAL_CAMERA`'s constants and object parameters (the photo states them), rounded to
whole counts. ``thermal_truth.json``: the plot temperatures and what the photos state.
"""
import json
import os
from typing import Dict, Optional

import numpy as np

from ..files import write_bytes
from ..radiometry import ThermalParameters, celsius_to_raw
from .field import FieldMess, plot_corners
from .flight import make_camera, plan_flight
from .flir_writer import write_flir_jpeg
from .render import pixel_rays, surface_hits
from .scene import make_scene

# a Vue Pro R-like camera 25 m over the field on a warm morning
THERMAL_CAMERA = ThermalParameters(r1=17096.453, r2=0.046642166, b=1428.0, f=1.0, o=-342.0,
                                   emissivity=0.97, object_distance=25.0,
                                   reflected_temperature=12.0, atmospheric_temperature=24.0,
                                   relative_humidity=0.55)
SOIL_C = 38.0
NOISE_C = 0.05
UTC_OFFSET = "+09:00"          # the survey field is in Japan (EPSG:32654)


def plot_temperatures(scene, seed: int) -> Dict[str, float]:
    """The canopy temperature (°C) of every plot: 22–32 °C, lower for taller (transpiring)
    crops, plus a random part."""
    rng = np.random.default_rng([seed, 34])
    out = {}
    for p in scene.plots:
        out[p["plot_id"]] = round(float(30.0 - 8.0 * (p["height"] - 0.25) / 0.45
                                        + rng.uniform(-2.0, 2.0)), 3)
    return out


def temperature_at(scene, temps: Dict[str, float], x_map, y_map) -> np.ndarray:
    """The field's temperature (°C) at map points (1-D): its plot's, else the soil's."""
    x_map, y_map = np.asarray(x_map, float), np.asarray(y_map, float)
    order = np.argsort(x_map)
    xs = x_map[order]
    t = np.full(x_map.shape, SOIL_C)
    for p in scene.plots:
        c = plot_corners(p)
        lo, hi = np.searchsorted(xs, [c[:, 0].min(), c[:, 0].max()], side="left")
        idx = order[lo:hi + 1]
        e1, e2 = c[1] - c[0], c[3] - c[0]
        dx, dy = x_map[idx] - c[0][0], y_map[idx] - c[0][1]
        u = (dx * e1[0] + dy * e1[1]) / (e1 @ e1)
        v = (dx * e2[0] + dy * e2[1]) / (e2 @ e2)
        t[idx[(u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)]] = temps[p["plot_id"]]
    return t


def write_thermal_photos(survey_folder: str, seed: int = 0, size: str = "small",
                         mess=None, encoding: str = "png",
                         limit: Optional[int] = None) -> Dict[str, object]:
    """Write ``survey_folder/thermal/`` (one FLIR JPEG per photo of the survey, same file
    names) and ``survey_folder/thermal_truth.json``; the survey must have been made with the
    same ``seed``, ``size`` and field ``mess`` (default: the demo survey's). ``limit``: only
    the first photos (tests). Returns {folder, truth, plots, photos}."""
    scene = make_scene(seed, mess=FieldMess() if mess is None else mess)
    camera = make_camera(size)
    shots = plan_flight(scene, np.random.default_rng([seed, 1]))
    temps = plot_temperatures(scene, seed)
    folder = os.path.join(survey_folder, "thermal")
    os.makedirs(folder, exist_ok=True)
    rays = pixel_rays(camera)
    rng = np.random.default_rng([seed, 35])
    written = []
    for shot in shots[:limit]:
        hits = surface_hits(scene, shot.C, rays @ shot.R.astype(np.float32)).astype(np.float64)
        t = temperature_at(scene, temps, hits[:, 0] + scene.offset[0], hits[:, 1] + scene.offset[1])
        t = t.reshape(camera.height, camera.width) + rng.normal(0.0, NOISE_C, (camera.height,
                                                                            camera.width))
        raw = np.round(celsius_to_raw(t, THERMAL_CAMERA)).astype(np.uint16)
        path = os.path.join(folder, shot.filename)
        write_flir_jpeg(path, raw, THERMAL_CAMERA, encoding=encoding, when=shot.time,
                        subsec="00", utc_offset=UTC_OFFSET)
        written.append(path)
    truth = os.path.join(survey_folder, "thermal_truth.json")
    doc = {"plots_c": temps, "soil_c": SOIL_C, "noise_c": NOISE_C,
           "camera": {k: float(v) for k, v in THERMAL_CAMERA.as_dict().items()},
           "utc_offset": UTC_OFFSET,
           "description": "each plot's canopy and soil at one temperature, the rest soil; "
                          "pixels: the temperature of the surface point they see + noise"}
    write_bytes(truth, json.dumps(doc, indent=1).encode("utf-8"))
    return {"folder": folder, "truth": truth, "plots": temps, "photos": written}
