"""``make demo``: create the demo survey and run every EasyIDP tool on it through qgis_process.

Prints what was produced, how long each step took, and the errors against the survey's truth,
each line marked [independent] (the truth is not made by the code it checks: pixels by
``tests/support/independent_camera.py``, OpenCV and the Metashape manual's formulas; heights,
colours and plot layouts from the generator's parameters and closed-form models; other
software) or [consistency only] (our code against our code: the generator computes that truth
with the production camera model); writes an overview picture (orthomosaic, plots, camera
footprints) drawn by QGIS.
Usage: python -m easyidp_toolbox.scripts.demo OUTPUT_FOLDER
"""
import json
import os
import shutil
import subprocess
import sys
import time

import numpy as np

from .demo_multispectral import run_multispectral_demo
from .demo_photo_folder import run_photo_folder_demo
from .demo_photo_statistics import run_photo_statistics_demo
from .demo_plot_grid import run_plot_grid_demo
from .demo_round_trip import run_round_trip_demo
from .demo_season import SEASON_DATES, run_season_demo
from .demo_thermal import run_thermal_demo
from .qgis_process import qgis_process_env, run_algorithm
from ..tests.support.independent_camera import observation_lookup, observation_pixels, photo_pixels

IND, CONS = "[independent]", "[consistency only]"


class Steps:
    """Runs algorithms through qgis_process and keeps their wall times."""

    def __init__(self):
        self.env = qgis_process_env()
        self.times = []

    def run(self, label, alg, params):
        t = time.time()
        res = run_algorithm(alg, params, self.env)
        self.times.append((label, time.time() - t))
        print(f"  {self.times[-1][1]:6.1f} s  {label}", flush=True)
        return res


def _features(path: str, layer: int = 0):
    from osgeo import ogr
    ds = ogr.Open(path)  # keep the dataset alive while its layer is read
    return [{**f.items(), "_geom": f.GetGeometryRef() and f.GetGeometryRef().Clone()}
            for f in ds.GetLayer(layer)]


MARKER = ".easyidp-demo"   # the demo's own output folder: cleared by the next demo run


def _fresh_folder(out: str) -> None:
    """Empty ``out`` when an earlier demo made it; refuse a folder that holds anything else."""
    if os.path.isdir(out) and os.listdir(out):
        if not os.path.exists(os.path.join(out, MARKER)):
            raise SystemExit(f"{out} is not empty and was not made by the demo: give another folder "
                             "(make demo DEMO_DIR=…).")
        shutil.rmtree(out)
    os.makedirs(out, exist_ok=True)
    open(os.path.join(out, MARKER), "w").close()


def main(out: str) -> int:
    out = os.path.abspath(out)
    _fresh_folder(out)
    print(f"EasyIDP demo: every tool on a generated survey, through qgis_process → {out}", flush=True)
    steps = Steps()
    s = steps.run("create demo survey (ortho, DSM, 40 plots, 36 photos, 4 projects, cloud; "
                  f"a {SEASON_DATES}-date growth season)", "easyidp:createdemosurvey",
                  {"OUTPUT_FOLDER": os.path.join(out, "survey"), "SEASON_DATES": SEASON_DATES})
    truth = json.load(open(s["TRUTH"]))
    plots, dsm = s["PLOTS"], s["DSM"]

    dom = steps.run("crop orthomosaic by plots", "easyidp:croprasterbyrois",
                    {"INPUT": s["ORTHOMOSAIC"], "ROIS": plots, "NAME_FIELD": "plot_id",
                     "OUTPUT_FOLDER": os.path.join(out, "crops_orthomosaic")})
    steps.run("crop DSM by plots", "easyidp:croprasterbyrois",
              {"INPUT": dsm, "ROIS": plots, "NAME_FIELD": "plot_id",
               "OUTPUT_FOLDER": os.path.join(out, "crops_dsm")})
    top = steps.run("plot canopy top from DSM (95th percentile)", "easyidp:roiheightsfromdsm",
                    {"ROIS": plots, "DSM": dsm, "MODE": 0, "STATISTIC": 4, "PERCENTILE": 95,
                     "OUTPUT": os.path.join(out, "plots_top.gpkg")})
    ground = steps.run("plot ground from DSM (2nd percentile, 0.3 m around)", "easyidp:roiheightsfromdsm",
                       {"ROIS": plots, "DSM": dsm, "MODE": 0, "STATISTIC": 4, "PERCENTILE": 2,
                        "BUFFER": 0.3, "OUTPUT": os.path.join(out, "plots_ground.gpkg")})
    ms = steps.run("camera footprints on the DSM, Metashape project", "easyidp:camerafootprints",
                   {"PROJECT": s["METASHAPE_PROJECT"], "DSM": dsm,
                    "OUTPUT_CAMERAS": os.path.join(out, "metashape_cameras.gpkg"),
                    "OUTPUT_FOOTPRINTS": os.path.join(out, "metashape_footprints.gpkg")})
    steps.run("camera footprints on the DSM, Pix4D project", "easyidp:camerafootprints",
              {"PROJECT": s["PIX4D_PROJECT"], "DSM": dsm,
               "OUTPUT_CAMERAS": os.path.join(out, "pix4d_cameras.gpkg"),
               "OUTPUT_FOOTPRINTS": os.path.join(out, "pix4d_footprints.gpkg")})
    steps.run("camera footprints on the DSM, OpenDroneMap project", "easyidp:camerafootprints",
              {"PROJECT": os.path.join(s["ODM_PROJECT"], "opensfm", "reconstruction.json"),
               "DSM": dsm, "OUTPUT_CAMERAS": os.path.join(out, "odm_cameras.gpkg"),
               "OUTPUT_FOOTPRINTS": os.path.join(out, "odm_footprints.gpkg")})
    opf = steps.run("camera footprints on the DSM, OPF project (PIX4Dmatic)", "easyidp:camerafootprints",
                    {"PROJECT": s["OPF_PROJECT"], "DSM": dsm,
                     "OUTPUT_CAMERAS": os.path.join(out, "opf_cameras.gpkg"),
                     "OUTPUT_FOOTPRINTS": os.path.join(out, "opf_footprints.gpkg")})
    pc = steps.run("crop point cloud by plots (LAZ)", "easyidp:croppointcloudbyrois",
                   {"INPUT": s["POINT_CLOUD"], "ROIS": plots, "NAME_FIELD": "plot_id",
                    "OUTPUT_FOLDER": os.path.join(out, "crops_pointcloud")})
    stats = steps.run("point cloud statistics per plot", "easyidp:pointcloudroistatistics",
                      {"INPUT": s["POINT_CLOUD"], "ROIS": plots, "PERCENTILES": "50,95,99",
                       "OUTPUT": os.path.join(out, "plots_pointcloud_stats.gpkg")})
    forward = _forward_projection(steps, s, truth, out)

    back = _backward_projection(steps, s, out)
    photo_folder = run_photo_folder_demo(steps, s, truth, out, _features)
    photo_stats = run_photo_statistics_demo(steps, s, truth, out, _features)
    photo_stats += run_round_trip_demo(steps, out)
    multispectral = run_multispectral_demo(steps, s, out, _features)
    thermal = run_thermal_demo(steps, s, out, _features)

    # ---- checks against the truth ----------------------------------------------------------
    crop_h = {k: v["crop_height"] for k, v in truth["plots"].items()}
    t = {f["plot_id"]: f["height"] for f in _features(top["OUTPUT"])}
    g = {f["plot_id"]: f["height"] for f in _features(ground["OUTPUT"])}
    dsm_err = np.array([(t[k] - g[k]) - crop_h[k] for k in crop_h])
    pc_err = np.array([f["h_p99"] - crop_h[f["plot_id"]] for f in _features(stats["OUTPUT"])])
    truth_check = float(np.abs(observation_pixels(truth)
                               - np.array(truth["observations"]["pixel"])).max())
    proj = _projection_errors(s, truth)
    plots_apart = _plots_apart(s, truth)
    inside = _footprint_coverage(ms["OUTPUT_FOOTPRINTS"], truth)
    inside_opf = _footprint_coverage(opf["OUTPUT_FOOTPRINTS"], truth)
    season = run_season_demo(steps, s["SEASON_SURVEYS"], out)
    plot_grid = run_plot_grid_demo(steps, out)

    png = _overview(os.path.join(out, "overview.png"), s["ORTHOMOSAIC"],
                    [plots, ms["OUTPUT_FOOTPRINTS"]])

    print("\nResults")
    print(f"  survey:      {s['OUTPUT_FOLDER']}")
    print(f"  crops:       {dom['CROPPED']} orthomosaic + DSM GeoTIFFs, {pc['CROPPED']} LAZ "
          f"in {out}/crops_*")
    print("  layers:      plots_top.gpkg, plots_ground.gpkg, plots_pointcloud_stats.gpkg, "
          "metashape_/pix4d_/odm_/opf_ cameras and footprints (.gpkg)")
    print(f"  picture:     {png}")
    feats = [p["field"] for p in truth["plots"].values()]
    print(f"  field:       {sum(f['empty'] for f in feats)} empty plots, {sum(f['weeds'] > 0 for f in feats)} "
          f"with weeds, {sum(f['gaps'] > 0 for f in feats)} with missing row segments, "
          f"{sum(f['lodged'] for f in feats)} lodged, {sum(f['no_alley'] for f in feats)} without "
          f"alleys; margin grass, alley weeds, shadows, soil gradient (truth.json field_mess)")
    print("  raw photos:  plots_in_photos.gpkg (photo pixels: x = column, y = -row), "
          "plots_best_photo.gpkg, back2raw.json, crops_photos/, previews/")
    print("  statistics:  plots_photo_statistics.gpkg (per plot, across views), "
          "plots_photo_views.gpkg (every plot × photo), previews_statistics/")
    print("Errors against the truth ([independent]: the truth is not made by the code it checks; "
          "[consistency only]: our code against our code)")
    print(f"  {IND} plot crop height, DSM p95 − ground:   mean {100 * np.mean(np.abs(dsm_err)):.1f} cm, "
          f"max {100 * np.max(np.abs(dsm_err)):.1f} cm over {len(dsm_err)} plots")
    print(f"  {IND} plot crop height, cloud p99 − ground: mean {100 * np.mean(np.abs(pc_err)):.1f} cm, "
          f"max {100 * np.max(np.abs(pc_err)):.1f} cm")
    print(f"  {IND} the generator's truth pixels (production camera model) vs the independent "
          f"camera (OpenCV + the Metashape terms): max {truth_check:.1e} px")
    for name, err in proj.items():
        print(f"  {IND} truth points → photo pixels, {name}: max {err:.1e} px from the independent "
              f"camera over {len(truth['observations']['point'])} observations")
    print(f"  {CONS} plot corners back-projected through Metashape, Pix4D and ODM: at most "
          f"{plots_apart:.2f} px apart")
    print(f"  {CONS} truth points inside the footprint of each photo that sees them (seen pairs "
          f"by the generator's camera): {100 * inside:.1f} % (Metashape), {100 * inside_opf:.1f} % "
          f"(OPF)")
    print(f"  {IND} season, {SEASON_DATES} dates × 40 plots: height max {100 * season['height']:.1f} cm "
          f"(DSM), {100 * season['cloud']:.1f} cm (cloud); cover max {100 * season['cover']:.1f} %")
    for line in _backward_errors(back, s, truth):
        print(f"  {line}")
    for line in photo_folder:
        print(line)
    for line in forward:
        print(line)
    print(f"  {IND} plot colour truth from the generator's closed-form model "
          f"(next lines); the round trip's object visibility: {CONS} (generator's camera):")
    for line in photo_stats:
        print(line)
    for line in multispectral:
        print(line)
    for line in thermal:
        print(line)
    print(f"  {IND} plot grid against the generator's plot layout:")
    for line in plot_grid:
        print(line)
    total = sum(sec for _, sec in steps.times)
    print(f"Summary: {len(steps.times)} tool runs in {total:.0f} s; {dom['CROPPED']} plots cropped "
          f"from orthomosaic, DSM and point cloud; projections agree with the independent truth "
          f"to {max(proj.values()):.0e} px; plot heights within {100 * np.mean(np.abs(dsm_err)):.0f} "
          f"cm (mean; independent).")
    return 0


def _backward_projection(steps, s, out):
    """Plots → raw photos (issue 9): best 4 photos per plot with crops and previews (DSM heights,
    occlusion on); and EasyIDP's whole-plots-only rule, to compare with the truth."""
    best = steps.run("back-project plots to raw photos (DSM heights, occlusion, crops, previews)",
                     "easyidp:backprojectrois",
                     {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["METASHAPE_PROJECT"],
                      "HEIGHT_SOURCE": 1, "DSM": s["DSM"], "MAX_IMAGES": 4,
                      "OUTPUT": os.path.join(out, "plots_in_photos.gpkg"),
                      "OUTPUT_SUMMARY": os.path.join(out, "plots_best_photo.gpkg"),
                      "OUTPUT_JSON": os.path.join(out, "back2raw.json"),
                      "CROPS_FOLDER": os.path.join(out, "crops_photos"),
                      "PREVIEW_FOLDER": os.path.join(out, "previews")})
    whole = steps.run("back-project plots, whole plots only (EasyIDP's rule), Pix4D project",
                      "easyidp:backprojectrois",
                      {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["PIX4D_PROJECT"],
                       "HEIGHT_SOURCE": 1, "DSM": s["DSM"], "CLIP": 1, "MIN_VISIBLE": 0,
                       "OCCLUSION": False, "OUTPUT": os.path.join(out, "plots_in_photos_whole.gpkg"),
                       "OUTPUT_SUMMARY": "TEMPORARY_OUTPUT"})
    clipped = steps.run("back-project plots, clipped to the frame, every photo",
                        "easyidp:backprojectrois",
                        {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["METASHAPE_PROJECT"],
                         "HEIGHT_SOURCE": 1, "DSM": s["DSM"], "MIN_VISIBLE": 0, "OCCLUSION": False,
                         "OUTPUT": os.path.join(out, "plots_in_photos_clipped.gpkg"),
                         "OUTPUT_SUMMARY": "TEMPORARY_OUTPUT"})
    whole_opf = steps.run("back-project plots, whole plots only, OPF project (PIX4Dmatic)",
                          "easyidp:backprojectrois",
                          {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["OPF_PROJECT"],
                           "HEIGHT_SOURCE": 1, "DSM": s["DSM"], "CLIP": 1, "MIN_VISIBLE": 0,
                           "OCCLUSION": False,
                           "OUTPUT": os.path.join(out, "plots_in_photos_whole_opf.gpkg"),
                           "OUTPUT_SUMMARY": "TEMPORARY_OUTPUT"})
    return {"best": best, "whole": whole, "clipped": clipped, "whole_opf": whole_opf}


def _backward_errors(back, s, truth):
    """Back-projection against the truth: photo sets (whole plots), corner pixels, visible
    fractions of clipped plots (dense ground sampling), occlusion of the kept pairs."""
    from ..core import open_reconstruction
    from ..core.reconstruction import INSIDE
    pix = observation_lookup(truth)             # the independent truth
    same, worst = _whole_against_truth(back["whole"], truth, pix)
    # OPF has one focal length: the demo camera's affinity b1 is mapped out of the truth exactly
    cal, b1 = _opf_calibration(s, truth)
    same_opf, raw_opf = _whole_against_truth(back["whole_opf"], truth, pix)
    no_b1 = {k: (cal.cx + (uv[0] - cal.cx) * cal.f / (cal.f + b1), uv[1]) for k, uv in pix.items()}
    _, worst_opf = _whole_against_truth(back["whole_opf"], truth, no_b1)
    recon = open_reconstruction(s["METASHAPE_PROJECT"])
    g = (np.arange(120) + 0.5) / 120
    u, v = [a.ravel()[:, None] for a in np.meshgrid(g, g)]
    vis_err = []
    clipped = [f for f in _features(back["clipped"]["OUTPUT"]) if f["clipped"]]
    by_plot = {}
    for f in clipped:
        by_plot.setdefault(f["roi"], []).append(f)
    for pid, feats in by_plot.items():
        c = np.array(truth["plots"][pid]["corners"])
        pts = c[0] * (1 - u) * (1 - v) + c[1] * u * (1 - v) + c[2] * u * v + c[3] * (1 - u) * v
        p = recon.project_points(pts, truth["crs"])
        frac = dict(zip(p.camera_labels, (p.status == INSIDE).mean(axis=1)))
        vis_err += [abs(f["visible_fraction"] - frac[f["photo"]]) for f in feats]
    best = _features(back["best"]["OUTPUT"])
    occ = np.array([f["occluded_fraction"] for f in best])
    crops = sum(len(files) for _, _, files in os.walk(back["best"]["CROPS_FOLDER"]))
    return [f"{CONS} plots → photos, whole plots only (Pix4D): photo sets equal the generator's "
            f"for {same} of {len(truth['plots'])} plots",
            f"{IND} plots → photos, whole plots only (Pix4D): corners within {worst:.1e} px",
            f"{CONS} plots → photos, whole plots only (OPF): photo sets equal the generator's for "
            f"{same_opf} of {len(truth['plots'])} plots",
            f"{IND} plots → photos, whole plots only (OPF): corners within {worst_opf:.1e} px of the "
            f"truth without the affinity b1 = {b1:g} px OPF cannot hold ({raw_opf:.2f} px of the "
            f"truth itself)",
            f"{CONS} plots → photos, clipped (Metashape): visible fraction within "
            f"{max(vis_err):.4f} of a dense ground count (projected by our reader) over "
            f"{len(vis_err)} clipped plot × photo pairs",
            f"[no truth] best 4 photos per plot: {len(best)} pairs, occluded share of the plot "
            f"surface median "
            f"{np.median(occ):.2f}, max {occ.max():.2f} (soil between crop rows); "
            f"{crops // 2} crops and their JSON written"]

def _opf_calibration(s, truth):
    """(the OPF project's calibration, the demo camera's affinity b1 in px): OPF has one focal
    length, so its pixels are the truth's with u → cx + (u − cx)·f/(f + b1)."""
    from ..core import open_reconstruction
    from ..core.demo.flight import SIZES, make_camera
    size = next(k for k, v in SIZES.items() if list(v) == list(truth["image_size"]))
    recon = open_reconstruction(s["OPF_PROJECT"])
    return next(iter(recon.sensors.values())).calibration, make_camera(size).calibration.b1


def _whole_against_truth(run, truth, pix):
    """(plots whose photo set is the truth's, worst corner distance in px) of a whole-plots-only
    back-projection layer against the truth pixels ``pix`` {(point id, photo stem): (u, v)}."""
    whole = _features(run["OUTPUT"])
    sets = {}
    for f in whole:
        sets.setdefault(f["roi"], set()).add(os.path.splitext(f["photo"])[0])
    same = sum(sets.get(k, set()) == set(v["photos_whole"]) for k, v in truth["plots"].items())
    worst = 0.0
    for f in whole:
        ring = np.array(f["_geom"].GetGeometryRef(0).GetGeometryRef(0).GetPoints())[:, :2] * [1, -1]
        for k in range(4):
            uv = pix.get((f"{f['roi']}_c{k + 1}", os.path.splitext(f["photo"])[0]))
            if uv is not None:
                worst = max(worst, float(np.min(np.linalg.norm(ring - np.asarray(uv), axis=1))))
    return same, worst


def _forward_projection(steps, s, truth, out) -> list:
    """Forward projection of the survey's LabelMe polygons through both projects (vertices
    only, so they compare with the truth's), a merged layer, and easyidp 2.0.4's homography
    side by side; returns the lines to print."""
    from .homography_comparison import compare, report
    labelme = os.path.join(s["OUTPUT_FOLDER"], "labelme")
    lines = []
    for name, project in (("Metashape", s["METASHAPE_PROJECT"]), ("Pix4D", s["PIX4D_PROJECT"])):
        res = steps.run(f"forward-project LabelMe polygons to the map, {name} project",
                        "easyidp:forwardprojectpolygons",
                        {"INPUT_FOLDER": labelme, "PROJECT": project, "DSM": s["DSM"], "DENSIFY": 0,
                         "OUTPUT": os.path.join(out, f"labelme_on_map_{name.lower()}.gpkg")})
        errors, area = [], []
        for f in _features(res["OUTPUT"]):
            key = f"labelme/{os.path.splitext(f['photo'])[0]}.json"
            shape = next(t for t in truth["labelme"][key]["shapes"] if t["label"] == f["label"])
            ring = f["_geom"].GetGeometryRef(0).GetGeometryRef(0)
            got = np.array(ring.GetPoints())[:-1]
            true = np.array(shape["map"])
            errors.append(np.linalg.norm(got - true, axis=1))
            x, y = true[:, 0] - true[0, 0], true[:, 1] - true[0, 1]
            true_area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
            area.append(abs(f["area_m2"] - true_area) / true_area)
        e = np.concatenate(errors)
        lines.append(f"  {IND} LabelMe vertices on the map, {name}: median {np.median(e) * 1000:.3f} mm, "
                     f"max {e.max() * 1000:.3f} mm over {len(e)} vertices (DSM cell 20 mm); "
                     f"areas within {100 * max(area):.3f} %")
    steps.run("forward-project LabelMe polygons, merged across photos (union)",
              "easyidp:forwardprojectpolygons",
              {"INPUT_FOLDER": labelme, "PROJECT": s["METASHAPE_PROJECT"], "DSM": s["DSM"],
               "MERGE": 1, "OUTPUT": os.path.join(out, "labelme_on_map_merged.gpkg")})
    lines.append(f"  {IND} LabelMe truth (map points cast by the generator) → the clicks by the "
                 f"independent camera: max {_labelme_truth_check(truth):.1e} px")
    lines.append(f"  {IND} raw → map, ray–DSM vs easyidp 2.0.4 homography, truth points in plots "
                 f"(at their independent pixels):")
    lines.append(report(compare(s["OUTPUT_FOLDER"])))
    best = steps.run("orthorectify plots from their best raw photo (native resolution)",
                     "easyidp:orthorectifyrois",
                     {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["METASHAPE_PROJECT"],
                      "DSM": s["DSM"], "OUTPUT_FOLDER": os.path.join(out, "ortho_best")})
    check = steps.run("orthorectify plots at 2 cm (for the check against the orthomosaic)",
                      "easyidp:orthorectifyrois",
                      {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": s["PIX4D_PROJECT"],
                       "DSM": s["DSM"], "GSD": 0.02, "OUTPUT_FOLDER": os.path.join(out, "ortho_2cm")})
    off = np.array([_ncc_offset(f, s["ORTHOMOSAIC"]) for f in check["OUTPUT_FILES"]])
    lines.append(f"  {CONS} orthorectified plots (the photos are rendered with our camera model): "
                 f"{best['WRITTEN']} images from the best photos; against "
                 f"the orthomosaic (NCC peak, 2 cm images): offset mean "
                 f"{np.hypot(*off.T).mean():.2f}, max {np.hypot(*off.T).max():.2f} DSM cells")
    return lines


def _ncc_offset(path: str, ortho: str):
    """Sub-cell (rows, cols) offset of the normalised cross-correlation peak between an
    orthorectified image (alpha > 0 pixels) and the orthomosaic averaged onto its grid."""
    import tifffile
    from ..core.raster import open_geotiff
    img = tifffile.imread(path)
    info = open_geotiff(path)
    c, a, _, f, _, e = info.geotransform
    X, Y = np.meshgrid(c + a * (np.arange(info.width) + 0.5), f + e * (np.arange(info.height) + 0.5))
    o = tifffile.imread(ortho).astype(np.float64).mean(axis=2)
    oi = open_geotiff(ortho)
    k = max(int(round(a / oi.geotransform[1])), 1)          # orthomosaic pixels per image pixel
    col, row = oi.map_to_pixel(X, Y)
    c0 = np.clip(np.floor(col - k / 2).astype(int), 0, o.shape[1] - k)
    r0 = np.clip(np.floor(row - k / 2).astype(int), 0, o.shape[0] - k)
    ref = sum(o[r0 + i, c0 + j] for i in range(k) for j in range(k)) / (k * k)
    ours = img[..., :3].astype(np.float64).mean(axis=2)
    ok = img[..., -1] > 0
    m = 3
    sc = np.zeros((3, 3))
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            aa = ours[m:-m, m:-m][ok[m:-m, m:-m]]
            bb = ref[m + dy:ref.shape[0] - m + dy, m + dx:ref.shape[1] - m + dx][ok[m:-m, m:-m]]
            aa, bb = aa - aa.mean(), bb - bb.mean()
            sc[dy + 1, dx + 1] = (aa * bb).sum() / np.sqrt((aa * aa).sum() * (bb * bb).sum())
    dy = 0.5 * (sc[0, 1] - sc[2, 1]) / (sc[0, 1] - 2 * sc[1, 1] + sc[2, 1])
    dx = 0.5 * (sc[1, 0] - sc[1, 2]) / (sc[1, 0] - 2 * sc[1, 1] + sc[1, 2])
    return dy, dx


def _overview(png: str, raster: str, vectors) -> str:
    """The overview picture, drawn by QGIS in a process of its own (a QgsApplication must not
    start in a process that has already used GDAL's Python bindings)."""
    proc = subprocess.run([sys.executable, "-m", f"{__package__}.overview", png, raster, *vectors],
                          capture_output=True, text=True, env=dict(os.environ, QT_QPA_PLATFORM="offscreen"))
    if proc.returncode != 0:
        raise RuntimeError(f"the overview picture failed:\n{proc.stderr[-2000:]}")
    return png


def _labelme_truth_check(truth) -> float:
    """Max distance (px) between the LabelMe clicks and their true map points projected by the
    independent camera: the forward-projection truth checked without core code."""
    worst = 0.0
    for doc in truth["labelme"].values():
        for shape in doc["shapes"]:
            uv = photo_pixels(truth, doc["photo"], np.array(shape["map"]))[0]
            worst = max(worst, float(np.abs(uv - np.array(shape["pixels"])).max()))
    return worst


def _projection_errors(s, truth) -> dict:
    """Max pixel error of the truth points projected through the four projects (core) against
    the independent truth (``tests/support/independent_camera.py``)."""
    from ..core import open_reconstruction
    xyz = np.array(truth["points"]["xyz"])
    obs = truth["observations"]
    want_all = observation_pixels(truth)
    out = {}
    for name, path, suffix in (("Metashape", s["METASHAPE_PROJECT"], ""),
                               ("Pix4D", s["PIX4D_PROJECT"], ".JPG"),
                               ("ODM", s["ODM_PROJECT"], ".JPG")):
        p = open_reconstruction(path).project_points(xyz, truth["crs"])
        index = {lab: i for i, lab in enumerate(p.camera_labels)}
        cam = np.array([index[lab + suffix] for lab in obs["photo"]])
        uv = p.pixels[cam, np.array(obs["point"])]
        out[name] = float(np.abs(uv - want_all).max())
    cal, b1 = _opf_calibration(s, truth)
    p = open_reconstruction(s["OPF_PROJECT"]).project_points(xyz, truth["crs"])
    index = {lab: i for i, lab in enumerate(p.camera_labels)}
    uv = p.pixels[np.array([index[lab + ".JPG"] for lab in obs["photo"]]), np.array(obs["point"])]
    want = want_all.copy()
    want[:, 0] = cal.cx + (want[:, 0] - cal.cx) * cal.f / (cal.f + b1)
    out["OPF (the truth without b1)"] = float(np.abs(uv - want).max())
    return out


def _plots_apart(s, truth) -> float:
    """How far apart (px) the plot corners land through the Metashape, Pix4D and ODM projects."""
    from ..core import open_reconstruction
    corners = np.array([c for plot in truth["plots"].values() for c in plot["corners"]])
    px = []
    for path in (s["METASHAPE_PROJECT"], s["PIX4D_PROJECT"], s["ODM_PROJECT"]):
        pr = open_reconstruction(path).project_points(corners, truth["crs"])
        order = np.argsort([lab.split(".")[0] for lab in pr.camera_labels])
        px.append(np.where(pr.status[order, :, None] == 0, pr.pixels[order], np.nan))
    return max(float(np.nanmax(np.abs(a - px[0]))) for a in px[1:])


def _footprint_coverage(footprints: str, truth) -> float:
    """Share of (point, photo) truth observations whose point lies in that photo's footprint."""
    from osgeo import ogr, osr
    feats = {os.path.splitext(f["label"])[0]: f["_geom"] for f in _features(footprints)}
    src = osr.SpatialReference()
    src.SetFromUserInput(truth["crs"])
    src.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    xyz = truth["points"]["xyz"]
    hits = 0
    obs = truth["observations"]
    for k, label in zip(obs["point"], obs["photo"]):
        geom = feats[label]
        dst = geom.GetSpatialReference()
        dst.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
        pt = ogr.Geometry(ogr.wkbPoint)
        pt.AddPoint_2D(*xyz[k][:2])
        pt.AssignSpatialReference(src)
        pt.TransformTo(dst)
        hits += geom.Contains(pt)
    return hits / len(obs["point"])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "demo_output"))
