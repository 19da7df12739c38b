"""Benchmark: orthorectified images of 400 ROIs from their best raw photos.

Also: with and without the hidden-ground mask, on the demo and on the real OpenDroneMap survey
(``../shared/realdata/orthority_odm``: 5 ROIs of 80 m × 80 m in its photos' overlaps, every
photo that sees them), ROIs/s, ground pixels/s and the share of the time the mask costs.

Also, beside Orthority 0.7.0 (``EASYIDP_ORTHORITY``, ``make env-orthority``) as users run
each: ``oty odm`` on the real survey (every photo orthorectified whole, native resolution)
against ``qgis_process run easyidp:orthorectifyrois`` over near whole-photo ROIs (each photo's
footprint on the DSM, best photo: the photo itself), wall times from the command line with
start-up on both sides, with the occlusion mask and without it (MASK none, Orthority's
behaviour), the runs alternated.

Run: ``python -m easyidp_toolbox.bench.bench_orthorectify [--quick]``.

On the demo survey (small), each of the 40 plots is cut into 10 ROIs (400 in all, about
0.8 m × 1.25 m). Ours: ``orthorectify_rois`` with ``selection="best"`` (backward projection
and scoring included), native resolution, ray–DSM occlusion, GeoTIFFs written. easyidp 2.0.4
(its own environment): for the same ROI and photo pairs, ``back2raw_crs`` for the ROI's
pixels and ``one_raw_roi2geotiff`` (one homography per ROI, skimage warp; photos decoded once,
images not saved), which ignores relief and occlusion.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from .common import REF_PYTHON, reference_env, table

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REF_PY = str(REF_PYTHON)

REF = r"""
import json, sys, time, warnings
warnings.filterwarnings("ignore")
import numpy as np, pyproj
import easyidp as idp
from skimage.io import imread
folder, cases_path = sys.argv[1:3]
cases = json.load(open(cases_path))
ms = idp.Metashape(folder + "/metashape/demo_survey.psx", chunk_id=0)
ms.crs = pyproj.CRS.from_epsg(32654)
crs = pyproj.CRS.from_epsg(32654)
t0 = time.perf_counter()
images, done = {}, 0
for c in cases:
    xyz = np.array(c["xyz"])
    px = ms.back2raw_crs(xyz).get(c["photo"])
    if px is None:
        continue
    if c["photo"] not in images:
        images[c["photo"]] = imread(folder + "/photos/" + c["photo"] + ".JPG")
    idp.geotiff.one_raw_roi2geotiff(crs, xyz, images[c["photo"]], np.asarray(px)[:, :2])
    done += 1
print(json.dumps({"seconds": time.perf_counter() - t0, "done": done}))
"""


def split_plots(plots, nx=5, ny=2):
    """Each plot rectangle cut into nx × ny ROIs (plots are rectangles, 4 corners)."""
    from easyidp_toolbox.core.roi import ROI, ROISet
    out = []
    for p in plots:
        c = p.rings[0][:4, :2]
        for i in range(nx):
            for j in range(ny):
                def at(u, v):
                    return c[0] + u * (c[1] - c[0]) + v * (c[3] - c[0])
                u0, u1, v0, v1 = i / nx, (i + 1) / nx, j / ny, (j + 1) / ny
                ring = np.array([at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1)])   # open
                out.append(ROI(f"{p.name}_{i}{j}", [[ring]]))
    return ROISet(out, plots.crs)


def mask_rows(label, rois, recon, dsm, tmp, selection):
    """[label + mask on/off, ROI images/s, ground Mpx/s, wall s, images] and the mask's share."""
    import tifffile
    from easyidp_toolbox.core.projection.ortho import orthorectify_rois
    rows, walls = [], {}
    for occ in (False, True):
        out = os.path.join(tmp, f"{label}_{occ}")
        t0 = time.perf_counter()
        res = orthorectify_rois(rois, recon, dsm, out, selection=selection, occlusion=occ)
        wall = time.perf_counter() - t0
        px = sum(int((tifffile.imread(f)[..., -1] > 0).sum()) for f in res.files)
        walls[occ] = wall
        rows.append([f"{label}, {'with' if occ else 'without'} the occlusion mask",
                     len(res.files) / wall, px / wall / 1e6, wall, len(res.files)])
    return rows, (walls[True] - walls[False]) / walls[True]


def real_survey():
    """(ROISet, Reconstruction, DSM path) of the real ODM survey, or None when not there."""
    from pathlib import Path
    from easyidp_toolbox.core import open_reconstruction
    from easyidp_toolbox.core.roi.model import ROISet, roi_from_coordinates
    root = Path(os.path.realpath(ROOT))           # the tree, also when run through .plugins/
    folder = Path(os.environ.get("EASYIDP_REALDATA", root.parent / "shared" / "realdata")) \
        / "orthority_odm"
    if not folder.is_dir():
        return None
    centres = [(292785.0, 2731141.0), (292681.0, 2731069.0), (292657.0, 2731093.0),
               (292777.0, 2731037.0), (292665.0, 2730973.0)]
    h = 40.0
    rois = ROISet([roi_from_coordinates(f"r{k}", "Polygon", [[[x - h, y - h], [x + h, y - h],
                                                             [x + h, y + h], [x - h, y + h],
                                                             [x - h, y - h]]])
                   for k, (x, y) in enumerate(centres)], "EPSG:32651")
    return rois, open_reconstruction(folder), str(folder / "odm_dem" / "dsm.tif")


def footprint_rois_geojson(folder, path) -> None:
    """Near whole-photo ROIs of the real survey: each photo's footprint on the DSM, densified to
    10 m edges, each vertex pulled towards the centre until it lies on DSM data (the photos
    reach beyond the DSM), named by the photo."""
    from easyidp_toolbox.core import open_reconstruction
    from easyidp_toolbox.core.projection import camera_footprints
    from easyidp_toolbox.core.raster import DSM
    dsm = DSM(str(folder / "odm_dem" / "dsm.tif"))
    feats = []
    for f in camera_footprints(open_reconstruction(folder), dsm):
        ring = np.asarray(f.ring)[:, :2]
        ring = ring[:-1] if np.allclose(ring[0], ring[-1]) else ring
        dense = []
        for a, b in zip(ring, np.roll(ring, -1, axis=0)):
            k = max(1, int(np.ceil(np.hypot(*(b - a)) / 10.0)))
            dense.extend(a + (b - a) * t for t in np.arange(k) / k)
        ring = np.array(dense)
        c = ring.mean(axis=0)
        for s in np.linspace(1.0, 0.3, 36):
            p = c + s * (ring - c)
            ok = np.isfinite(dsm.heights(p[:, 0], p[:, 1]))
            todo = ~np.isfinite(dsm.heights(ring[:, 0], ring[:, 1]))
            ring[todo & ok] = p[todo & ok]
        ring = np.vstack([ring, ring[:1]])
        feats.append({"type": "Feature", "properties": {"name": f.label},
                      "geometry": {"type": "Polygon", "coordinates": [ring.tolist()]}})
    with open(path, "w") as fh:
        json.dump({"type": "FeatureCollection", "features": feats, "crs": {
            "type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32651"}}}, fh)


def orthority_rows(tmp, pairs: int):
    """Orthority 0.7.0's ``oty odm`` against the tool through ``qgis_process`` (mask on, off),
    wall times from the command line, alternated ``pairs`` times; (rows, target rows)."""
    import statistics
    from pathlib import Path
    from .common import print_targets, run_child, target
    from ..scripts.qgis_process import EXE, qgis_process_env
    real = real_survey()
    oty = os.environ.get("EASYIDP_ORTHORITY", os.path.join(ROOT, ".venv-orthority", "bin", "oty"))
    if real is None or not os.path.exists(oty):
        print("Orthority rows left out: " + ("the real survey is not there" if real is None else
                                             f"no Orthority at {oty} (make env-orthority)"))
        return
    folder = Path(real[2]).parent.parent
    rois = os.path.join(tmp, "footprints.geojson")
    footprint_rois_geojson(folder, rois)
    env = qgis_process_env(os.path.join(tmp, "profile"))
    oty_env = {k: v for k, v in os.environ.items() if k != "PROJ_DATA"}   # its wheels' own PROJ
    runs = {"oty": [], 0: [], 1: []}                  # (wall, CPU) per pair

    def run_oty(i):
        out = os.path.join(tmp, f"oty{i}")
        os.makedirs(out)
        r = run_child([oty, "odm", "--dataset-dir", str(folder), "--out-dir", out], env=oty_env)
        if not r.ok:
            raise RuntimeError(f"oty odm failed:\n{r.stderr[-2000:]}")
        runs["oty"].append((r.wall, r.cpu))

    def run_ours(i, mask):
        r = run_child([EXE, "run", "easyidp:orthorectifyrois", "--", f"ROIS={rois}",
                       "NAME_FIELD=name", f"PROJECT={folder / 'opensfm' / 'reconstruction.json'}",
                       f"DSM={real[2]}", "SELECTION=0", f"MASK={mask}",
                       f"OUTPUT_FOLDER={os.path.join(tmp, f'ours{mask}_{i}')}"], env=env)
        if not r.ok:
            raise RuntimeError(f"qgis_process failed:\n{r.stderr[-3000:]}")
        runs[mask].append((r.wall, r.cpu))

    for i in range(pairs):            # A/B alternated: Orthority first in even pairs, last in odd
        for what in (["oty", 1, 0] if i % 2 == 0 else [0, 1, "oty"]):
            if what == "oty":
                run_oty(i)
            else:
                run_ours(i, what)
    med = {k: statistics.median(w for w, _ in v) for k, v in runs.items()}
    cpu = {k: statistics.median(c for _, c in v) for k, v in runs.items()}
    ratio = {m: statistics.median(a[0] / b[0] for a, b in zip(runs["oty"], runs[m])) for m in (0, 1)}
    r = run_child([EXE, "help", "easyidp:orthorectifyrois"], env=env)    # start-up: QGIS + plugin
    n_oty = len([f for f in os.listdir(os.path.join(tmp, "oty0")) if f.endswith(".tif")])
    n_ours = len(os.listdir(os.path.join(tmp, f"ours0_{pairs - 1}")))
    print(f"\nReal survey, whole photos, beside Orthority 0.7.0 in the same run ({pairs} A/B pairs, "
          "the order alternated; wall s from the command line, start-up included; medians; the "
          "ratio is the median of the pairs' Orthority wall / ours)")
    print(table(["run", "wall s", "CPU s", "images", "Orthority wall s", "Orthority / ours",
                 "target"], [
        ["Orthority 0.7.0: oty odm (no occlusion mask)", med["oty"], cpu["oty"], n_oty, None, None,
         None],
        ["ours: qgis_process, MASK none", med[1], cpu[1], n_ours, med["oty"], ratio[1], "≥ 1.5"],
        ["ours: qgis_process, occlusion mask", med[0], cpu[0], n_ours, med["oty"], ratio[0],
         "≥ 0.7"],
        ["qgis_process start-up alone (help of the tool; once)", r.wall, r.cpu, None, None, None,
         None]]))
    print_targets([target("real survey, no mask: Orthority wall / ours", ratio[1], 1.5),
                   target("real survey, occlusion mask: Orthority wall / ours", ratio[0], 0.7)])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="100 ROIs")
    ap.add_argument("--orthority-only", action="store_true",
                    help="only the rows beside Orthority (real survey)")
    ap.add_argument("--pairs", type=int, default=3, help="alternated runs beside Orthority")
    args = ap.parse_args(argv)
    if args.orthority_only:
        with tempfile.TemporaryDirectory() as tmp:
            orthority_rows(tmp, args.pairs)
        return 0
    from easyidp_toolbox.core import open_reconstruction, read_geojson
    from easyidp_toolbox.core.demo import make_demo_survey
    from easyidp_toolbox.core.projection.ortho import orthorectify_rois
    from easyidp_toolbox.core.raster import DSM
    with tempfile.TemporaryDirectory() as tmp:
        s = make_demo_survey(os.path.join(tmp, "survey"), seed=0, size="small")
        rois = split_plots(read_geojson(s.plots_geojson, name_field="plot_id"))
        if args.quick:
            from easyidp_toolbox.core.roi import ROISet
            rois = ROISet(list(rois)[:100], rois.crs)
        recon = open_reconstruction(s.metashape_project)
        t0, c0 = time.perf_counter(), time.process_time()
        res = orthorectify_rois(rois, recon, s.dsm, os.path.join(tmp, "out"))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        rows = [["ours: best photo, native GSD, occlusion, GeoTIFF written", len(res.files) / wall,
                 len(res.files) / cpu, wall, len(res.files)]]
        by_name = {r.name: r for r in rois}
        cases = []
        dsm = DSM(s.dsm)
        for name, photo in zip(res.rois, res.photos):
            ring = by_name[name].rings[0][:4, :2]
            z = dsm.heights(ring[:, 0], ring[:, 1])
            xyz = np.column_stack([ring, z])
            cases.append({"photo": photo, "xyz": np.vstack([xyz, xyz[:1]]).tolist()})
        if os.path.exists(REF_PY):
            path = os.path.join(tmp, "cases.json")
            with open(path, "w") as fh:
                json.dump(cases, fh)
            env = reference_env()
            env.update(HOME=tmp, XDG_DATA_HOME=tmp)
            proc = subprocess.run([REF_PY, "-c", REF, s.folder, path], capture_output=True,
                                  text=True, env=env)
            if proc.returncode == 0:
                ref = json.loads(proc.stdout.strip().splitlines()[-1])
                rows.append(["easyidp 2.0.4: back2raw + one homography per ROI (not saved)",
                             ref["done"] / ref["seconds"], None, ref["seconds"], ref["done"]])
            else:
                print("easyidp run failed:", proc.stderr[-1500:], file=sys.stderr)
        print(f"{len(rois)} ROIs; {os.cpu_count()} cores")
        print(table(["run", "ROIs/s", "ROIs/CPU-s", "wall s", "images"], rows))
        if len(rows) > 1:
            print(f"\nratio ours/easyidp (ROIs per second): {rows[0][1] / rows[1][1]:.2f}")
        mrows, shares = [], []
        r, share = mask_rows(f"demo, {len(rois)} ROIs, best photo", rois, recon, s.dsm, tmp,
                             "best")
        mrows += r
        shares.append(("demo", share))
        real = real_survey()
        if real is not None:
            r, share = mask_rows("real ODM survey, 5 ROIs, every photo", *real, tmp, "all")
            mrows += r
            shares.append(("real ODM survey", share))
        else:
            print("real survey not found (../shared/realdata/orthority_odm): its rows are left out")
        print()
        print(table(["run", "ROI images/s", "ground Mpx/s", "wall s", "images"], mrows))
        for what, share in shares:
            print(f"{what}: the occlusion mask takes {100 * share:.0f} % of the time")
        orthority_rows(tmp, 1 if args.quick else args.pairs)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
