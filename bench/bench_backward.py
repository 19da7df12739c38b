"""Benchmark: backward projection (issue 9) against easyidp 2.0.4's ``back2raw``.

    python -m easyidp_toolbox.bench.bench_backward [--quick] [--no-ref]

1. **Projection**: 1,600 plots (a 40 × 40 grid of 0.8 m × 1.2 m rectangles, 3-D) × the 138
   cameras of the real wheat_tanashi project: ROI × photo pairs examined per second, ours with
   clipping on and off and with the occlusion test against a synthetic 2 cm DSM of the field
   (hedges 1.5 m tall), easyidp's ``Metashape.back2raw`` on the same 3-D polygons.
2. **Raw-photo crops**: ours (``back_project`` + ``crop_photos``) against easyidp's
   ``back2raw(roi, save_folder=...)``, both projecting and writing the PNG crops, on
   (a) the 40 plots of the demo survey (medium: 36 photos of 1600 × 1200) and
   (b) a synthetic set of 400 plots × 100 photos of 4000 × 3000 (JPEG, written one at a time).
   Both keep the photos that hold the whole plot (EasyIDP's rule), so they write the same crops.

Each tool runs in its own child process (peak memory is its own). Inputs are generated once,
deterministically, into bench_output/backward/ and reused. Figures are printed with the ratios
and PASS/MISS per target (a miss does not fail the run).
"""
import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

from .common import REF_PYTHON, print_targets, ratio, reference_env, run_json_child, table, target

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output" / "backward"
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))
WHEAT = REALDATA / "easyidp" / "metashape" / "wheat_tanashi.psx"
GEN_VERSION = 1
TIMEOUT = 6 * 3600

# --- child programs ---------------------------------------------------------------------------------
_LOAD_ROIS = r"""
def load_rois(path):
    import json
    import numpy as np
    from easyidp_toolbox.core.roi import ROI, ROISet
    d = json.load(open(path))
    rois = [ROI(k, [[np.array(v)[:-1, :2]]], {}, [[np.array(v)[:-1, 2]]]) for k, v in d["rois"].items()]
    return ROISet(rois, d["crs"])
"""

OURS_PROJECT = _LOAD_ROIS + r"""
import json, sys, time
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.projection import back_project
project, rois_path, mode, dsm = sys.argv[1:5]
rois = load_rois(rois_path)
recon = open_reconstruction(project)
t0 = time.perf_counter()
kw = dict(clip=mode != "whole", min_visible=0.0)
if mode == "occlusion":
    from easyidp_toolbox.core.raster import DSM
    kw["occlusion_dsm"] = DSM(dsm)
res = back_project(rois, recon, heights="geometry", **kw)
t1 = time.perf_counter()
print(json.dumps({"seconds": t1 - t0, "examined": len(rois) * len(recon.aligned_cameras),
                  "kept": len(res)}))
"""

REF_ROIS = r"""
import json, logging, os, sys, time, warnings
warnings.filterwarnings("ignore")
logging.disable(logging.CRITICAL)
import numpy as np, pyproj
import easyidp as idp
project, rois_path = sys.argv[1:3]
d = json.load(open(rois_path))
roi = idp.ROI()
for k, v in d["rois"].items():
    roi[k] = np.array(v, dtype=float)
roi.crs = pyproj.CRS.from_user_input(d["crs"])
"""
"""The start of every easyidp 2.0.4 child: argv PROJECT ROIS_JSON; the ROIs read into ``roi``."""

REF_PROJECT = REF_ROIS + r"""
ms = idp.Metashape(project, chunk_id=0, check_img_existance=False)
t0 = time.perf_counter()
out = ms.back2raw(roi)
t1 = time.perf_counter()
print(json.dumps({"seconds": t1 - t0, "examined": len(d["rois"]) * len(ms.photos),
                  "kept": sum(len(v) for v in out.values())}))
"""

OURS_CROPS = _LOAD_ROIS + r"""
import json, sys, time
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.projection import back_project, crop_photos
project, rois_path, folder = sys.argv[1:4]
rois = load_rois(rois_path)
t0 = time.perf_counter()
recon = open_reconstruction(project)
res = back_project(rois, recon, heights="geometry", clip=False, min_visible=0.0)
t1 = time.perf_counter()
out = crop_photos(res, folder)
t2 = time.perf_counter()
print(json.dumps({"seconds": t2 - t0, "project_s": t1 - t0, "crop_s": t2 - t1,
                  "crops": len(out.files), "skipped": len(out.skipped_photos)}))
"""

REF_CROPS = REF_ROIS + r"""
folder = sys.argv[3]
t0 = time.perf_counter()
ms = idp.Metashape(project, chunk_id=0)
out = ms.back2raw(roi, save_folder=folder)
t1 = time.perf_counter()
n = sum(1 for _, _, files in os.walk(folder) for f in files if f.endswith(".png"))
print(json.dumps({"seconds": t1 - t0, "crops": n}))
"""


# --- inputs -----------------------------------------------------------------------------------------
def _grid_plots(x0, y0, x1, y1, rows, cols, size, z_of, seed):
    """{name: closed (5, 3) ring} of slightly rotated rectangles on a grid over a box."""
    rng = np.random.default_rng(seed)
    out = {}
    w, h = size
    local = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
    for i in range(rows):
        for j in range(cols):
            cx = x0 + (x1 - x0) * (j + 0.5) / cols
            cy = y0 + (y1 - y0) * (i + 0.5) / rows
            a = np.radians(rng.uniform(-4, 4))
            ring = local @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]]) + [cx, cy]
            ring = np.vstack([ring, ring[:1]])
            out[f"R{i:02d}C{j:02d}"] = np.column_stack([ring, z_of(ring[:, 0], ring[:, 1])]).tolist()
    return out


def wheat_inputs(quick: bool) -> dict:
    """1,600 plots over the wheat_tanashi field (UTM 54N, ellipsoidal heights ~96.8 m) and a
    2 cm DSM of the field (flat ground with hedges 1.5 m tall across it, for occlusion)."""
    from pyproj import Transformer
    n = 20 if quick else 40
    path = OUT / f"wheat_rois_{n}.json"
    dsm = OUT / "wheat_dsm.tif"
    to_utm = Transformer.from_crs(4326, 32654, always_xy=True)
    x0, y0 = to_utm.transform(139.54015, 35.73754)
    x1, y1 = to_utm.transform(139.54062, 35.73810)
    if not path.exists():
        rois = _grid_plots(x0, y0, x1, y1, n, n, (0.8, 1.2), lambda x, y: np.full(len(x), 96.8), 1)
        path.write_text(json.dumps({"crs": "EPSG:32654", "rois": rois}))
    if not dsm.exists():
        from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, write_geotiff
        px = 0.02
        ox, oy = x0 - 5, y1 + 5
        rows, cols = int((y1 - y0 + 10) / px), int((x1 - x0 + 10) / px)
        z = np.full((rows, cols), 96.8, np.float32)
        for k in range(6):                                     # hedges every ~10 m, east-west
            r = int((5 + 10 * k) / px)
            z[r:r + int(0.4 / px)] = 98.3
        write_geotiff(str(dsm), z, (ox, px, 0.0, oy, 0.0, -px), epsg_geo_tags(32654), tile=256)
    return {"rois": path, "dsm": dsm}


def demo_inputs(size: str) -> dict:
    """The demo survey (seed 0) and its 40 plots with DSM heights at the corners."""
    from easyidp_toolbox.core.demo import make_demo_survey
    from easyidp_toolbox.core.raster import DSM
    from easyidp_toolbox.core.roi import read_geojson
    folder = OUT / f"demo_{size}"
    truth = folder / "truth.json"
    if not truth.exists():
        make_demo_survey(str(folder), seed=0, size=size)
    path = OUT / f"demo_{size}_rois.json"
    if not path.exists():
        rois = read_geojson(str(folder / "plots.geojson"), name_field="plot_id")
        d = {}
        dsm = DSM(str(folder / "dsm.tif"))
        for r in rois:
            ring = np.vstack([r.rings[0], r.rings[0][:1]])
            d[r.name] = np.column_stack([ring, dsm.heights(ring[:, 0], ring[:, 1])]).tolist()
        path.write_text(json.dumps({"crs": "EPSG:32654", "rois": d}))
    return {"project": folder / "metashape" / "demo_survey.psx", "rois": path}


def synthetic_inputs(quick: bool) -> dict:
    """A Metashape project of 100 nadir photos of 4000 × 3000 (10 × 10 grid, 25 m up) over the
    demo field, the photos as JPEG (one in memory at a time), and 400 plots (20 × 20 grid)."""
    from easyidp_toolbox.core.demo.flight import CameraModel, Shot, nadir_rotation
    from easyidp_toolbox.core.demo.metashape_writer import write_metashape
    from easyidp_toolbox.core.demo.scene import make_scene
    from easyidp_toolbox.core.files import write_bytes
    from easyidp_toolbox.core.reconstruction import Calibration
    import imagecodecs
    n_side, r_side = (5, 10) if quick else (10, 20)
    folder = OUT / f"synthetic_{n_side}x{n_side}_v{GEN_VERSION}"
    psx = folder / "metashape" / "synthetic.psx"
    rois_path = folder / "rois.json"
    if psx.exists() and rois_path.exists():
        return {"project": psx, "rois": rois_path}
    scene = make_scene(0)
    lay, off = scene.layout, scene.offset
    w, h = 4000, 3000
    cal = Calibration(f=3400.0, cx=2016.0, cy=1489.5, b1=3.1, b2=-1.35, k1=-0.062, k2=0.041,
                      k3=-0.012, p1=0.0009, p2=-0.0006)
    cam = CameraModel("SynthCam (11.22mm)", "SynthCam", w, h, cal, 13.2 / w)
    shots, photos = [], []
    (folder / "photos").mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(7)
    xs = np.linspace(lay.origin[0] + 8, lay.origin[0] + lay.size[0] - 8, n_side) - off[0]
    ys = np.linspace(lay.origin[1] - 6, lay.origin[1] - lay.size[1] + 6, n_side) - off[1]
    row = np.arange(h, dtype=np.float32)[:, None]
    col = np.arange(w, dtype=np.float32)[None, :]
    for k, (y, x) in enumerate((y, x) for y in ys for x in xs):
        C = np.array([x, y, float(scene.ground_local(x, y)) + 25.0])
        R = nadir_rotation(0.0)
        label = f"IMG_{k + 1:04d}"
        shots.append(Shot(label, label + ".JPG", R, C, 1 + k // n_side, 90.0, C + off,
                          "2024:06:01 10:00:00"))
        path = folder / "photos" / (label + ".JPG")
        photos.append(str(path))
        g = (96 + 60 * np.sin(row / 37.0 + k) * np.cos(col / 53.0)).astype(np.uint8)
        img = np.dstack([g, (g // 2 + 64), (255 - g) // 2])
        img += rng.integers(0, 12, img.shape, dtype=np.uint8)
        write_bytes(path, imagecodecs.jpeg8_encode(img, level=90))
        del img, g
    write_metashape(folder / "metashape", "synthetic", scene, cam, shots, photos, [], rng)
    rois = _grid_plots(lay.origin[0] + 2, lay.origin[1] - lay.size[1] + 2,
                       lay.origin[0] + lay.size[0] - 2, lay.origin[1] - 2, r_side, r_side,
                       (1.6, 1.0), lambda x, y: lay.ground_height(x, y), 3)
    rois_path.write_text(json.dumps({"crs": f"EPSG:{lay.epsg}", "rois": rois}))
    return {"project": psx, "rois": rois_path}


# --- running ------------------------------------------------------------------------------------------
def _child(python, code, args, env):
    return run_json_child([str(python), "-c", code, *map(str, args)], env=env,
                          timeout=TIMEOUT, strict=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smaller inputs (400 plots; 25 photos)")
    ap.add_argument("--no-ref", action="store_true", help="skip easyidp 2.0.4")
    ap.add_argument("--only", choices=["projection", "crops", "demo-crops"], default=None)
    a = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PROJ_DATA=os.environ.get("PROJ_DATA", "/usr/share/proj"))
    ref_env = reference_env(env)
    ref_env.update(HOME=str(OUT), XDG_DATA_HOME=str(OUT))
    ref = REF_PYTHON.exists() and not a.no_ref
    if not ref and not a.no_ref:
        print(f"(easyidp reference environment not found at {REF_PYTHON}: run `make env-ref`)")
    py = sys.executable
    targets = []

    if a.only in (None, "projection"):
        w = wheat_inputs(a.quick)
        rows = []
        for mode in ("clip", "whole", "occlusion"):
            run, r = _child(py, OURS_PROJECT, [WHEAT, w["rois"], mode, w["dsm"]], env)
            rows.append([f"ours ({mode})", r["seconds"], r["examined"] / r["seconds"], r["kept"],
                         run.peak_mb])
        ours_clip = rows[0][2]
        if ref:
            run, r = _child(REF_PYTHON, REF_PROJECT, [WHEAT, w["rois"]], ref_env)
            rows.append(["easyidp 2.0.4 back2raw", r["seconds"], r["examined"] / r["seconds"],
                         r["kept"], run.peak_mb])
            targets.append(target("projection pairs/s, ours (clip) / easyidp",
                                  ratio(ours_clip, rows[-1][2]), 1.0))
        n = int(rows[0][2] * rows[0][1] / 138)
        print(f"\n1. {n} plots × 138 wheat_tanashi cameras ({n * 138:,} ROI × photo pairs)")
        print(table(["tool", "seconds", "pairs/s", "kept", "peak MiB"], rows))

    if a.only in (None, "crops", "demo-crops"):
        cases = [("demo survey, 40 plots × 36 photos", demo_inputs("small" if a.quick else "medium"))]
        if a.only != "demo-crops":
            cases.append(("synthetic, 4000 × 3000 photos", synthetic_inputs(a.quick)))
        for name, case in cases:
            rows = []
            out_ours = OUT / "crops_ours"
            out_ref = OUT / "crops_easyidp"
            for d in (out_ours, out_ref):
                if d.exists():
                    import shutil
                    shutil.rmtree(d)
            run, r = _child(py, OURS_CROPS, [case["project"], case["rois"], out_ours], env)
            rows.append(["ours (back_project + crop_photos)", r["seconds"], run.cpu, r["crops"],
                         r["crops"] / r["seconds"], run.peak_mb])
            if ref:
                run_r, rr = _child(REF_PYTHON, REF_CROPS, [case["project"], case["rois"], out_ref], ref_env)
                rows.append(["easyidp 2.0.4 back2raw(save_folder)", rr["seconds"], run_r.cpu,
                             rr["crops"], rr["crops"] / rr["seconds"], run_r.peak_mb])
                targets.append(target(f"crops, {name}: speed-up", ratio(rr["seconds"], r["seconds"]), 5.0))
            print(f"\n2. raw-photo crops, {name}")
            print(table(["tool", "seconds", "CPU s (process)", "crops", "crops/s", "peak MiB"], rows))
    print_targets(targets)
    return 0


if __name__ == "__main__":
    sys.exit(main())
