"""The season part of ``make demo``: plot traits over the demo's growth season through
qgis_process, printed against the season's truth (height and cover per plot and date)."""
import csv
import json
import os

import numpy as np

SEASON_DATES = 4


def run_season_demo(steps, surveys: str, out: str) -> dict:
    """Run easyidp:seasontraits on the demo season (``surveys``: its surveys.csv) into ``out``
    and print the traits against the truth; returns the errors (m and cover fraction)."""
    folder = os.path.dirname(surveys)
    res = steps.run(f"plot traits over a {SEASON_DATES}-date season (2 worker processes)",
                    "easyidp:seasontraits",
                    {"SURVEYS": surveys, "ROIS": os.path.join(folder, "plots.geojson"),
                     "NAME_FIELD": "plot_id", "GROUP_FIELD": "variety",
                     "GROUND": os.path.join(folder, "bare_soil_dsm.tif"), "WORKERS": 2,
                     "OUTPUT_TABLE": os.path.join(out, "season_traits.csv"),
                     "OUTPUT_LAYER": os.path.join(out, "season_latest.gpkg"),
                     "OUTPUT_CURVES": os.path.join(out, "season_curves.png")})
    with open(os.path.join(folder, "season_truth.json")) as fh:
        truth = json.load(fh)
    values = {}
    with open(res["OUTPUT_TABLE"], newline="") as fh:
        for row in csv.DictReader(fh):
            values[(row["roi"], row["date"], row["trait"])] = float(row["value"])
    dates = truth["dates"]
    print(f"\nSeason: {len(truth['plots'])} plots × {len(dates)} dates "
          f"({', '.join(dates)}), measured − truth")
    print(f"  {'date':<11} {'height_p99 (DSM)':>20} {'cloud_height_p99':>20} {'cover':>18}")
    errors = {"height": [], "cloud": [], "cover": []}
    for k, d in enumerate(dates):
        e = {key: [] for key in errors}
        for pid, t in truth["plots"].items():
            e["height"].append(values[(pid, d, "height_p99")] - t["height"][k])
            e["cloud"].append(values[(pid, d, "cloud_height_p99")] - t["height"][k])
            e["cover"].append(values[(pid, d, "cover")] - t["cover"][k])
        for key in errors:
            errors[key] += e[key]
        mean_h = np.mean([t["height"][k] for t in truth["plots"].values()])
        mean_c = np.mean([t["cover"][k] for t in truth["plots"].values()])
        print(f"  {d:<11} {_cm(e['height']):>20} {_cm(e['cloud']):>20} {_pc(e['cover']):>18}"
              f"   (truth: mean height {100 * mean_h:.0f} cm, cover {100 * mean_c:.0f} %)")
    pid = sorted(truth["plots"])[0]
    t = truth["plots"][pid]
    print(f"  plot {pid} ({t['variety']}): "
          + "; ".join(f"{d}: {100 * values[(pid, d, 'height_p99')]:.1f} cm "
                      f"(truth {100 * t['height'][k]:.1f}), cover "
                      f"{100 * values[(pid, d, 'cover')]:.1f} % ({100 * t['cover'][k]:.1f})"
                      for k, d in enumerate(dates)))
    print(f"  tables and curves: {res['OUTPUT_TABLE']}, {res['OUTPUT_LAYER']}, "
          f"{res['OUTPUT_CURVES']}")
    return {k: float(np.max(np.abs(v))) for k, v in errors.items()}


def _cm(e) -> str:
    e = np.asarray(e)
    return f"max {100 * np.max(np.abs(e)):.1f} cm"


def _pc(e) -> str:
    e = np.asarray(e)
    return f"max {100 * np.max(np.abs(e)):.1f} %"
