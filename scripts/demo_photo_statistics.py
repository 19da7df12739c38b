"""The plot-statistics part of ``make demo``: ExG and canopy cover of every plot from the raw
photos (easyidp:photostatistics through qgis_process), printed per plot against the survey's
colour truth; and, on a copy of the survey whose orthomosaic shows ghosting and blur (the
photos are the same files), the same statistics from the orthomosaic crops
(easyidp:seasontraits), to show where the photos are closer to the truth."""
import csv
import os
import time

import numpy as np


def run_photo_statistics_demo(steps, s, truth, out, features) -> list:
    """Run the tools into ``out``; ``features(path)`` reads a layer's features as dicts.
    Returns the summary lines to print."""
    res = steps.run("plot statistics from the raw photos (3 best views per plot, hidden pixels "
                    "left out, previews)", "easyidp:photostatistics",
                    {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id",
                     "PROJECT": s["METASHAPE_PROJECT"], "HEIGHT_SOURCE": 1, "DSM": s["DSM"],
                     "OUTPUT_VIEWS": os.path.join(out, "plots_photo_views.gpkg"),
                     "OUTPUT": os.path.join(out, "plots_photo_statistics.gpkg"),
                     "PREVIEW_FOLDER": os.path.join(out, "previews_statistics")})
    photo = {f["plot_id"]: f for f in features(res["OUTPUT"])}
    views = features(res["OUTPUT_VIEWS"])

    # the same survey with ghosting and blur in its orthomosaic (the core generator; the
    # photos, projects and DSM are byte-identical), and the orthomosaic crops' statistics
    from ..core.demo import make_demo_survey
    t0 = time.time()
    bad = make_demo_survey(os.path.join(out, "survey_ortho_defects"), seed=0, ortho_defects=True)
    print(f"  {time.time() - t0:6.1f} s  demo survey with ghosting and blur in its orthomosaic "
          "(core generator, not a tool run)", flush=True)
    import json
    with open(bad.truth) as fh:
        defects = json.load(fh)["ortho_defects"]
    table = os.path.join(out, "ortho_defects_survey.csv")
    with open(table, "w", newline="") as fh:
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(["date", "orthomosaic"])
        w.writerow(["2024-06-01", bad.orthomosaic])
    ortho_res = steps.run("ExG and cover of the orthomosaic crops (orthomosaic with ghosting "
                          "and blur)", "easyidp:seasontraits",
                          {"SURVEYS": table, "ROIS": bad.plots_geojson, "NAME_FIELD": "plot_id",
                           "TRAITS": "1,3", "WORKERS": 1,
                           "OUTPUT_TABLE": os.path.join(out, "ortho_defects_traits.csv"),
                           "OUTPUT_LAYER": "TEMPORARY_OUTPUT",
                           "OUTPUT_CURVES": os.path.join(out, "ortho_defects_traits.png")})
    ortho = {}
    with open(ortho_res["OUTPUT_TABLE"], newline="") as fh:
        for row in csv.DictReader(fh):
            ortho.setdefault(row["roi"], {})[row["trait"]] = float(row["value"])

    plots = truth["plots"]
    kind = {n: k for k in ("ghosting", "blur") for n in defects[k]}
    print("\nPlot statistics from the raw photos, per plot: measured − truth (ExG; cover in %)")
    print(f"  {'plot':<5} {'ExG':>7} {'truth':>7} {'error':>8}   {'cover':>6} {'truth':>6} "
          f"{'error':>6}   {'orthomosaic with defects: ExG, cover error':<44}")
    e_exg, e_cov, o_exg, o_cov = [], [], [], []
    for pid in sorted(plots):
        t, f = plots[pid], photo[pid]
        ee, ec = f["exg_mean"] - t["exg"], f["cover"] - t["cover"]
        e_exg.append(ee)
        e_cov.append(ec)
        extra = ""
        if pid in kind:
            oe, oc = ortho[pid]["exg"] - t["exg"], ortho[pid]["cover"] - t["cover"]
            o_exg.append((abs(ee), abs(oe)))
            o_cov.append((abs(ec), abs(oc)))
            extra = f"{kind[pid]:<9} {oe:+.4f}, {100 * oc:+6.1f} %"
        print(f"  {pid:<5} {f['exg_mean']:7.4f} {t['exg']:7.4f} {ee:+8.4f}   "
              f"{100 * f['cover']:6.1f} {100 * t['cover']:6.1f} {100 * ec:+6.1f}   {extra}")
    e_exg, e_cov = np.abs(e_exg), np.abs(e_cov)
    used = [v for v in views if v["used"]]
    closer = sum(a < b for a, b in o_exg) + sum(a < b for a, b in o_cov)
    return [f"  plot statistics from the raw photos: ExG within {e_exg.max():.4f} (mean "
            f"{e_exg.mean():.4f}), cover within {100 * e_cov.max():.1f} % (mean "
            f"{100 * e_cov.mean():.1f} %) of the truth over {len(plots)} plots; {len(views)} "
            f"plot × photo views measured, {len(used)} used (3 best per plot)",
            f"  on the {len(o_exg)} plots whose orthomosaic shows ghosting or blur: photos ExG "
            f"error max {max(a for a, _ in o_exg):.4f} vs orthomosaic "
            f"{min(b for _, b in o_exg):.4f}–{max(b for _, b in o_exg):.4f}, cover error max "
            f"{100 * max(a for a, _ in o_cov):.1f} % vs orthomosaic "
            f"{100 * min(b for _, b in o_cov):.1f}–{100 * max(b for _, b in o_cov):.1f} %; "
            f"the photos are closer in {closer} of {2 * len(o_exg)} comparisons"]
