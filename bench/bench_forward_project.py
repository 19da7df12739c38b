"""Benchmark: forward projection of 10,000 polygons × 40 vertices (core.projection).

Run: ``python -m easyidp_toolbox.bench.bench_forward_project [--quick] [--polygons 10000]``.

On the demo survey (small: 36 photos of 800×600, DSM 2 cm, Metashape and Pix4D projects),
polygons of 40 vertices (circles of 8–25 px radius, like detected plants) are spread over the
photos and forward-projected photo by photo onto the DSM (densified edges off, so 40 rays per
polygon; and with the default densification). easyidp 2.0.4 has no per-vertex raw → map
projection; its raw → map path fits one homography per ROI and photo from 4 ROI vertices
(``one_raw_roi2geotiff``, image warp excluded): that fit and the mapping of the 40 vertices
through it are timed per polygon in its own environment, as the closest comparable.
"""
import argparse
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
import numpy as np
from skimage.transform import ProjectiveTransform
polys = np.load(sys.argv[1])                       # (n, 40, 2) pixels
rng = np.random.default_rng(0)
t0 = time.perf_counter()
for p in polys:                                     # one ROI: 4 vertices' pixels -> map
    src = p[::10]
    dst = src * 0.04 + rng.normal(0, 0.01, src.shape)
    try:
        pt = ProjectiveTransform.from_estimate(src=src, dst=dst)
    except AttributeError:
        pt = ProjectiveTransform(); pt.estimate(src, dst)
    pt(p)
print(json.dumps({"seconds": time.perf_counter() - t0}))
"""


def polygons(n: int, width: int, height: int, rng) -> np.ndarray:
    t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    r = rng.uniform(8, 25, n)
    c = np.column_stack([rng.uniform(30, width - 30, n), rng.uniform(30, height - 30, n)])
    return c[:, None, :] + r[:, None, None] * np.stack([np.cos(t), np.sin(t)], axis=1)[None]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="1,000 polygons")
    ap.add_argument("--polygons", type=int, default=10000)
    args = ap.parse_args(argv)
    n = 1000 if args.quick else args.polygons
    from easyidp_toolbox.core import open_reconstruction
    from easyidp_toolbox.core.demo import make_demo_survey
    from easyidp_toolbox.core.projection import forward_project
    from easyidp_toolbox.core.raster import DSM
    rng = np.random.default_rng(1)
    with tempfile.TemporaryDirectory() as tmp:
        survey = make_demo_survey(os.path.join(tmp, "survey"), seed=0, size="small")
        polys = polygons(n, 800, 600, rng)
        rows = []
        for name, path in (("Pix4D", survey.pix4d_project), ("Metashape", survey.metashape_project)):
            recon = open_reconstruction(path)
            cams = recon.aligned_cameras
            for densify in (False, True):
                dsm = DSM(survey.dsm)
                t0, c0 = time.perf_counter(), time.process_time()
                done = complete = 0
                for k, cam in enumerate(cams):
                    mine = polys[k::len(cams)]
                    shapes = forward_project(list(mine), cam, recon, dsm, densify=densify)
                    done += len(shapes)
                    complete += sum(s.complete for s in shapes)
                wall, cpu = time.perf_counter() - t0, time.process_time() - c0
                rows.append([f"ours, {name}, densify {'4 px' if densify else 'off'}", done / wall,
                             done / cpu, wall, 100.0 * complete / done])
        ref = None
        if os.path.exists(REF_PY):
            np.save(os.path.join(tmp, "polys.npy"), polys)
            proc = subprocess.run([REF_PY, "-c", REF, os.path.join(tmp, "polys.npy")],
                                  capture_output=True, text=True, env=reference_env())
            if proc.returncode == 0:
                import json
                ref = json.loads(proc.stdout.strip().splitlines()[-1])["seconds"]
                rows.append(["easyidp 2.0.4 homography per ROI (fit + 40 vertices)", n / ref, None,
                             ref, None])
            else:
                print("easyidp run failed:", proc.stderr[-1000:], file=sys.stderr)
        print(f"{n} polygons × 40 vertices over 36 photos; {os.cpu_count()} cores")
        print(table(["run", "polygons/s", "polygons/CPU-s", "wall s", "complete %"], rows))
        if ref:
            print(f"\nours (Pix4D, no densify) vs the homography's per-ROI cost: "
                  f"{rows[0][1] / (n / ref):.2f}× its throughput, while exact on the relief")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
