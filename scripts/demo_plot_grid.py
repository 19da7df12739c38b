"""The plot-grid part of ``make demo``: the demo trial (``core.demo.trial``), its grid made from
the four field corners and the layout, then the grid turned by 2°, shifted by 0.30 m and with its
spacing 2 % off fitted to the crop rows; both through qgis_process, with the errors against the
trial's truth."""
import json
import os

import numpy as np


def _rings(path):
    from osgeo import ogr
    ds = ogr.Open(path)
    out = {}
    for f in ds.GetLayer(0):
        g = f.GetGeometryRef()
        ring = (g.GetGeometryRef(0).GetGeometryRef(0) if g.GetGeometryCount() and
                g.GetGeometryRef(0).GetGeometryName() == "POLYGON" else g.GetGeometryRef(0))
        out[f.GetField("plot_id")] = (np.array(ring.GetPoints())[:-1, :2], f.items())
    return out


def run_plot_grid_demo(steps, out: str) -> list:
    """Returns the lines to print."""
    from ..core.demo.trial import TRIAL, make_demo_trial, perturbed_start
    from ..core.plotgrid import write_plot_grid
    trial = make_demo_trial(os.path.join(out, "trial"))
    with open(trial.truth, encoding="utf-8") as fh:
        truth = json.load(fh)["plots"]
    made = steps.run("plot grid from the trial's four corners, layout and field book",
                     "easyidp:createplotgrid",
                     {"ANCHOR": 0, "CORNERS": trial.corners, "ROWS": TRIAL["rows"],
                      "COLS": TRIAL["cols"], "SIZE_X": TRIAL["size_x"], "SIZE_Y": TRIAL["size_y"],
                      "GAP_X": TRIAL["gap_x"], "GAP_Y": TRIAL["gap_y"],
                      "BLOCKS_X": TRIAL["blocks_x"], "BLOCK_GAP_X": TRIAL["block_gap_x"],
                      "ORDER": 1, "START_ID": TRIAL["start_id"], "PATTERN": TRIAL["pattern"],
                      "FIELD_BOOK": trial.field_book,
                      "OUTPUT": os.path.join(out, "trial_grid.gpkg")})
    grid = _rings(made["OUTPUT"])
    made_err = max(float(np.abs(r - np.array(truth[p]["layout"])).max()) for p, (r, _) in grid.items())
    # the start of the fit: the layout with its spacing 2 % off, turned by 2°, shifted 0.30 m
    g, start = perturbed_start()
    g.corners = np.array(start)
    start = write_plot_grid(os.path.join(out, "trial_grid_off.gpkg"), g)
    fitted = steps.run("fit the grid (turned 2°, shifted 0.30 m, spacing 2 % off) to the crop rows",
                       "easyidp:fitplotgrid",
                       {"GRID": start, "ORTHOMOSAIC": trial.orthomosaic,
                        "OUTPUT": os.path.join(out, "trial_grid_fitted.gpkg")})
    fit = _rings(fitted["OUTPUT"])
    err = np.concatenate([np.hypot(*(r - np.array(truth[p]["planted"])).T) for p, (r, _) in fit.items()])
    before = np.concatenate([np.hypot(*(g.corners[i] - np.array(truth[p]["planted"])).T)
                             for i, p in enumerate(g.plot_id)])
    left = sorted(p for p, (_, a) in fit.items() if not a["moved"])
    return [f"  plot grid from 4 corners: {len(grid)} plots, vertices within "
            f"{made_err * 1000:.3f} mm of the layout",
            f"  plot grid fitted to the crop rows: vertex error median {100 * np.median(err):.2f} cm, "
            f"max {100 * err.max():.2f} cm (start: median {100 * np.median(before):.0f} cm); "
            f"left in place: {', '.join(left)} (the empty plots)"]
