"""The plot-grid part of ``make demo``: the hard demo trial (``core.demo.trial``: margin grass,
weeds, uneven vigour, missing row segments, lodging, shadows, plots touching across the rows),
its grid made from the four field corners and the layout, then the grid turned by 2°, shifted by
0.30 m and with its spacing 2 % off fitted to the crop rows, both through qgis_process; then
issue 32's done-when figures from 9 start grids spread over 3 trial seeds and from the true grid
of each (in process).

The truth is independent of the code it checks: the trial's generator writes the layout plots
with its own loops and the planted offsets and empty plots from its own random stream, not with
``core.plotgrid``, and renders the crop from them."""
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
    from ..core.demo.trial import EMPTY, TRIAL, make_demo_trial, perturbed_start
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
    lines = [f"  plot grid from 4 corners: {len(grid)} plots, vertices within "
             f"{made_err * 1000:.3f} mm of the layout (independent truth: the generator's loops)",
             f"  plot grid fitted to the crop rows: vertex error median {100 * np.median(err):.2f} cm, "
             f"max {100 * err.max():.2f} cm (start: median {100 * np.median(before):.0f} cm); "
             f"left in place: {', '.join(left)} (the empty plots: {', '.join(sorted(EMPTY))})"]
    return lines + done_when(trial, out)


def done_when(trial, out: str) -> list:
    """Issue 32's checks of the fit on the hard trial, in process: 9 start grids (rotation up to
    ±3°, shift up to 0.5 m, spacing ±3 %) spread over the trial seeds 0, 1 and 2, and the true
    grid of each seed, against the planted plots."""
    from ..core.demo.trial import EMPTY, FIT_SEEDS, make_demo_trial, start_grids_over_seeds
    from ..core.plotgrid import fit_plot_grid
    trials = {seed: trial if seed == 0 else
              make_demo_trial(os.path.join(out, f"trial_seed{seed}"), seed=seed)
              for seed in FIT_SEEDS}
    truths = {}
    for seed, t in trials.items():
        with open(t.truth, encoding="utf-8") as fh:
            truths[seed] = json.load(fh)["plots"]
    meds, maxes, only_empty = [], [], True
    for seed, _, (g, start) in start_grids_over_seeds(FIT_SEEDS):
        res = fit_plot_grid(start, trials[seed].orthomosaic)
        e = np.concatenate([np.hypot(*(r - np.array(truths[seed][p]["planted"])).T)
                            for r, p in zip(res.rings, g.plot_id)])
        meds.append(np.median(e))
        maxes.append(e.max())
        only_empty &= sorted(p for p, f in zip(g.plot_id, res.flag) if f) == sorted(EMPTY)
    moved = 0.0
    for seed, t in trials.items():
        ids = list(truths[seed])
        planted = [np.array(truths[seed][p]["planted"]) for p in ids]
        res = fit_plot_grid(planted, t.orthomosaic)
        moved = max(moved, max(np.hypot(*(r - q).T).max() for r, q in zip(res.rings, planted)))
        only_empty &= sorted(p for p, f in zip(ids, res.flag) if f) == sorted(EMPTY)
    ok = max(meds) <= 0.01 and max(maxes) <= 0.03 and moved <= 0.01 and only_empty
    return [f"  fit from {len(meds)} start grids (±3°, 0.5 m, ±3 %) over trial seeds "
            f"{', '.join(map(str, FIT_SEEDS))}: vertex error median "
            f"{100 * min(meds):.2f}–{100 * max(meds):.2f} cm (target ≤ 1), max "
            f"{100 * min(maxes):.2f}–{100 * max(maxes):.2f} cm (≤ 3); only the empty plots "
            f"flagged: {'yes' if only_empty else 'NO'}; the true grids moved ≤ "
            f"{100 * moved:.2f} cm (≤ 1): {'all met' if ok else 'NOT MET'} "
            "(independent truth: the generator's planted plots)"]
