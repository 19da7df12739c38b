"""Benchmark: Reconstruction.project_points vs easyidp 2.0.4 on the real wheat_tanashi project,
and the cost of rolling-shutter compensation on the real goya_test project.

Run: ``python -m easyidp_toolbox.bench.bench_project_points [--sizes 100000 1000000] [--quick]``.
138 cameras; random lon/lat/ellipsoidal-height points over the field (WGS 84), distortion on,
CRS conversion included. Each side runs in its own subprocess (peak RSS measured there);
easyidp runs in the reference venv (``make env-ref``) and is never imported here. easyidp's
batch path holds all cameras × points at once (~100 bytes per pair), so above
``--ref-chunk`` points it is fed slices of that size (its own code, called per slice).

goya_test (256 cameras with Metashape's rolling-shutter motion, local CRS): the same random
points projected with compensation on and off (the motion removed from the cameras), sparse
(``inside_only``, as above) and dense, each side in its own subprocess, best of ``--repeat``.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from .common import reference_env

ROOT = Path(__file__).resolve().parents[1]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))
PSX = REALDATA / "easyidp" / "metashape" / "wheat_tanashi.psx"
GOYA = REALDATA / "easyidp" / "metashape" / "goya_test.psx"
REF_PY = ROOT / ".venv-ref" / "bin" / "python"

OURS = r"""
import json, resource, sys, time
import numpy as np
from easyidp_toolbox.core import open_reconstruction
pts = np.load(sys.argv[2])
t0 = time.perf_counter()
r = open_reconstruction(sys.argv[1])
t1 = time.perf_counter()
vis = r.project_points(pts, "EPSG:4326", inside_only=True)
t2 = time.perf_counter()
print(json.dumps({"open_s": t1 - t0, "project_s": t2 - t1, "cameras": len(r.aligned_cameras),
                  "hits": int(len(vis.point)),
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

GOYA_CODE = r"""
import json, sys, time
import numpy as np
from easyidp_toolbox.core import open_reconstruction
r = open_reconstruction(sys.argv[1])
on, n, repeat = sys.argv[2] == "on", int(sys.argv[3]), int(sys.argv[4])
if not on:
    for c in r.cameras:
        c.rolling_shutter = None
_, C = r.camera_centres()
rng = np.random.default_rng(0)            # points in the box of the camera centres, ±2 m
pts = rng.uniform(C.min(axis=0) - 2.0, C.max(axis=0) + 2.0, (n, 3))
out = {"cameras": len(r.aligned_cameras), "rolling": len(r.rolling_shutter_cameras)}
for mode, sparse in (("sparse", True), ("dense", False)):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        p = r.project_points(pts, inside_only=sparse)
        best = min(best, time.perf_counter() - t0)
    out[mode] = best
    out[mode + "_hits"] = int(len(p.point) if sparse else p.inside.sum())
print(json.dumps(out))
"""

REF = r"""
import json, logging, resource, sys, time, warnings
warnings.filterwarnings("ignore")
logging.disable(logging.CRITICAL)
import numpy as np
import pyproj
import easyidp as idp
pts = np.load(sys.argv[2])
chunk = int(sys.argv[3])
t0 = time.perf_counter()
ms = idp.Metashape(sys.argv[1], chunk_id=0, check_img_existance=False)
t1 = time.perf_counter()
ms.crs = pyproj.CRS.from_epsg(4326)
transforms, names, groups, sensors = ms._prepare_camera_transforms()
hits = 0
for s in range(0, len(pts), chunk):
    local = ms._world2local(ms._crs2world(pts[s:s + chunk]))
    uv, valid = ms._batch_project_to_cameras(local, transforms, groups, sensors)
    hits += int(valid.sum())
    del uv, valid
t2 = time.perf_counter()
print(json.dumps({"open_s": t1 - t0, "project_s": t2 - t1, "cameras": len(names), "hits": hits,
                  "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def make_points(n: int, seed: int = 0) -> np.ndarray:
    """Points over the wheat_tanashi field: lon/lat (deg) and ellipsoidal height (m)."""
    rng = np.random.default_rng(seed)
    lon = rng.uniform(139.54015, 139.54062, n)
    lat = rng.uniform(35.73754, 35.73810, n)
    h = rng.normal(96.8, 0.3, n)
    return np.column_stack([lon, lat, h])


def run(python: str, code: str, args, env=None) -> dict:
    out = subprocess.run([python, "-c", code, *map(str, args)], capture_output=True, text=True,
                         env=env, timeout=1800)
    if out.returncode != 0:
        raise RuntimeError(f"{python} failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[100_000, 1_000_000])
    ap.add_argument("--ref-chunk", type=int, default=100_000)
    ap.add_argument("--no-ref", action="store_true", help="skip easyidp 2.0.4")
    ap.add_argument("--goya-points", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=3, help="goya: best of this many runs")
    ap.add_argument("--quick", action="store_true", help="20,000 wheat points, 5,000 goya points")
    a = ap.parse_args(argv)
    if a.quick:
        a.sizes, a.goya_points = [20_000], 5_000
    env = dict(os.environ)
    env.setdefault("PROJ_DATA", "/usr/share/proj")
    ref_ok = REF_PY.exists() and not a.no_ref
    if not ref_ok and not a.no_ref:
        print(f"(easyidp reference venv not found at {REF_PY}: run `make env-ref`)")
    print(f"project_points on {PSX.name} (distortion on, lon/lat/h → pixels, CRS conversion included)")
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.sizes:
            f = Path(tmp) / f"pts_{n}.npy"
            np.save(f, make_points(n))
            ours = run(sys.executable, OURS, [PSX, f], env)
            pairs = n * ours["cameras"]
            rate = pairs / ours["project_s"]
            print(f"\n{n:>9,} points × {ours['cameras']} cameras = {pairs:,.0f} pairs")
            print(f"  ours      : {ours['project_s']:7.2f} s  {rate / 1e6:8.1f} M pairs/s  "
                  f"peak {ours['peak_mb']:7.0f} MB  hits {ours['hits']:,}")
            if ref_ok:
                ref = run(str(REF_PY), REF, [PSX, f, a.ref_chunk], reference_env(env))
                rrate = pairs / ref["project_s"]
                sliced = f" (slices of {a.ref_chunk:,})" if n > a.ref_chunk else ""
                print(f"  easyidp   : {ref['project_s']:7.2f} s  {rrate / 1e6:8.1f} M pairs/s  "
                      f"peak {ref['peak_mb']:7.0f} MB  hits {ref['hits']:,}{sliced}")
                print(f"  ratio     : {rate / rrate:7.2f}× throughput, "
                      f"peak memory ours/easyidp {ours['peak_mb'] / ref['peak_mb']:.2f}")
    goya_rolling_shutter(a.goya_points, a.repeat, env)
    return 0


def goya_rolling_shutter(n: int, repeat: int, env) -> None:
    """project_points on goya_test with rolling-shutter compensation on vs off."""
    off = run(sys.executable, GOYA_CODE, [GOYA, "off", n, repeat], env)
    on = run(sys.executable, GOYA_CODE, [GOYA, "on", n, repeat], env)
    pairs = n * on["cameras"]
    print(f"\ngoya_test rolling shutter: {n:,} points × {on['cameras']} cameras = {pairs:,} pairs "
          f"({on['rolling']} cameras with motion), best of {repeat}")
    for mode in ("sparse", "dense"):
        print(f"  {mode:6s}: off {off[mode]:6.2f} s, on {on[mode]:6.2f} s, "
              f"on/off {on[mode] / off[mode]:5.2f}× (target ≤ 3×)  "
              f"hits off {off[mode + '_hits']:,} on {on[mode + '_hits']:,}")


if __name__ == "__main__":
    sys.exit(main())
