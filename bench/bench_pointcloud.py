"""Benchmark: crop a 20-million-point LAS by 1,600 plots, ours vs easyidp 2.0.4, and read 100 M points.

    python -m easyidp_toolbox.bench.bench_pointcloud [--full-easyidp] [--easyidp-rois 40]

Each measured run is a child process (its own ``ru_maxrss``): ours with this interpreter, easyidp
with ``.venv-ref`` (never imported here). easyidp tests every point against every ROI, so by
default it crops a subset of the plots and its crop time is extrapolated linearly to all plots;
the output says so. ``--full-easyidp`` runs it on every plot (about 1,000 s here).
Generated inputs are cached in ``bench_output/pointcloud/`` (git-ignored).
Targets: at least 100× faster than easyidp on 20 M points (issue 23; 50× before), peak memory
at most half of easyidp's, printed in the closing table with easyidp's figure from the same run.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

from .common import REF_PYTHON, print_targets, reference_env, target

ROOT = Path(__file__).resolve().parents[1]
CACHE = ROOT / "bench_output" / "pointcloud"
REF_PY = REF_PYTHON
EPSG = 32654
E0, N0 = 368000.0, 3955000.0
SPEED_TARGET, MEM_TARGET = 100.0, 0.5      # issue 23 (issue 3's speed target was 50×)


def plots(n_rows=40, n_cols=40, w=2.0, h=1.0, gap=0.5, angle_deg=3.0):
    """``n_rows × n_cols`` rectangular plots (w × h m) rotated by ``angle_deg`` about the field
    origin, as {name: (4, 2) array}; and the field's (xmin, ymin, xmax, ymax)."""
    a = np.radians(angle_deg)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    out = {}
    for r in range(n_rows):
        for c in range(n_cols):
            x0, y0 = 5 + c * (w + gap), 5 + r * (h + gap)
            sq = np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
            out[f"plot_{r:02d}_{c:02d}"] = sq @ rot.T + [E0, N0]
    allxy = np.concatenate(list(out.values()))
    lo, hi = allxy.min(axis=0) - 5, allxy.max(axis=0) + 5
    return out, (lo[0], lo[1], hi[0], hi[1])


def make_las(path: Path, n: int, extent, seed=0, chunk=5_000_000):
    """A LAS 1.2 point format 2 file (RGB) of ``n`` uniform points over ``extent``, UTM 54N,
    scale 1 mm, written in chunks (memory: one chunk)."""
    import laspy
    from pyproj import CRS
    if path.exists():
        return path
    header = laspy.LasHeader(version="1.2", point_format=2)
    header.scales = [0.001, 0.001, 0.001]
    header.offsets = [E0, N0, 0.0]
    header.add_crs(CRS.from_epsg(EPSG))
    rng = np.random.default_rng(seed)
    tmp = path.with_suffix(".part.las")
    with laspy.open(str(tmp), mode="w", header=header) as w:
        for s in range(0, n, chunk):
            m = min(chunk, n - s)
            rec = laspy.ScaleAwarePointRecord.zeros(m, header=header)
            x = rng.uniform(extent[0], extent[2], m)
            y = rng.uniform(extent[1], extent[3], m)
            rec.x, rec.y = x, y
            rec.z = 100 + 0.3 * np.sin(x) + rng.uniform(0, 1.0, m)
            for c in ("red", "green", "blue"):
                rec[c] = rng.integers(0, 65536, m, dtype=np.uint16)
            w.write_points(rec)
    os.replace(tmp, path)
    return path


def _child(python, code: str, timeout=None) -> dict:
    """Run ``code`` in a child interpreter; it prints one JSON line prefixed with 'RESULT '.
    Adds the child's peak resident memory (ru_maxrss of the child, MiB)."""
    wrapped = textwrap.dedent(code) + textwrap.dedent("""
        import resource as _r
        RES["maxrss_mib"] = _r.getrusage(_r.RUSAGE_SELF).ru_maxrss / 1024
        print("RESULT " + json.dumps(RES), flush=True)
    """)
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    env.setdefault("PROJ_DATA", "/usr/share/proj")
    if Path(python) == REF_PY:
        env = reference_env(env)
    p = subprocess.run([str(python), "-c", wrapped], capture_output=True, text=True,
                       timeout=timeout, env=env)
    for line in p.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    raise RuntimeError(f"child {python} failed (exit {p.returncode}):\n{p.stderr[-3000:]}")


OURS = """
import json, time
import numpy as np
from easyidp_toolbox.core import ROI, ROISet, read_point_cloud, crop_point_cloud
rois_np = np.load({rois!r})
names = json.load(open({names!r}))
t0 = time.perf_counter()
cloud = read_point_cloud({las!r})
rois = ROISet([ROI(n, [[r]]) for n, r in zip(names, rois_np)], {epsg})
res = crop_point_cloud(cloud, rois, {out!r}, fmt="las")
RES = {{"seconds": time.perf_counter() - t0, "files": len(res.files),
       "points": int(sum(res.counts.values()))}}
"""

EASYIDP = """
import json, time, warnings, logging
warnings.filterwarnings("ignore")
import numpy as np
t_imp = time.perf_counter()
import easyidp as idp
from pyproj import CRS
rois_np = np.load({rois!r})
names = json.load(open({names!r}))
t0 = time.perf_counter()
pcd = idp.PointCloud({las!r})
t1 = time.perf_counter()
roi = idp.ROI()
for n, r in zip(names, rois_np):
    roi[n] = np.vstack([r, r[:1]])
roi.crs = CRS.from_epsg({epsg})
out = roi.crop(pcd, save_folder={out!r})
t2 = time.perf_counter()
RES = {{"seconds": t2 - t0, "read_seconds": t1 - t0, "crop_seconds": t2 - t1,
       "files": len(out), "points": int(sum(len(v.points) for v in out.values() if v is not None))}}
"""

READ = """
import json, time
from easyidp_toolbox.core import read_point_cloud
t0 = time.perf_counter()
cloud = read_point_cloud({las!r})
xyz = cloud.xyz
RES = {{"seconds": time.perf_counter() - t0, "points": len(cloud),
       "xyz_mib": xyz.nbytes / 2**20}}
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=float, default=20e6)
    ap.add_argument("--easyidp-rois", type=int, default=40,
                    help="plots given to easyidp when not --full-easyidp (time extrapolated)")
    ap.add_argument("--full-easyidp", action="store_true", help="run easyidp on all 1,600 plots")
    ap.add_argument("--read-points", type=float, default=100e6)
    ap.add_argument("--skip-read", action="store_true")
    ap.add_argument("--skip-easyidp", action="store_true")
    ap.add_argument("--cache", type=Path, default=CACHE)
    ap.add_argument("--quick", action="store_true",
                    help="a fast run: 2 M points, 40 plots for easyidp, 10 M points read")
    a = ap.parse_args(argv)
    if a.quick:
        a.points, a.read_points = min(a.points, 2e6), min(a.read_points, 10e6)
    cache = a.cache
    cache.mkdir(parents=True, exist_ok=True)
    rois, extent = plots()
    names = list(rois)
    np.save(cache / "rois.npy", np.stack([rois[n] for n in names]))
    (cache / "names.json").write_text(json.dumps(names))
    n = int(a.points)
    las = make_las(cache / f"cloud_{n}.las", n, extent)
    print(f"== crop: {n:,} points (LAS 1.2 PF2, RGB, UTM 54N) by {len(names)} plots → LAS files")

    goals = []
    out = cache / "out_ours"
    shutil.rmtree(out, ignore_errors=True)
    ours = _child(sys.executable, OURS.format(rois=str(cache / "rois.npy"),
                                              names=str(cache / "names.json"), las=str(las),
                                              out=str(out), epsg=EPSG))
    print(f"  ours:    {ours['seconds']:.1f} s (read + crop + write), peak {ours['maxrss_mib']:.0f} MiB, "
          f"{ours['files']} files, {ours['points']:,} points")

    if not a.skip_easyidp:
        if not REF_PY.exists():
            raise SystemExit(f"{REF_PY} is missing: run `make env-ref` first.")
        k = len(names) if a.full_easyidp else min(a.easyidp_rois, len(names))
        sub = cache / "rois_sub.npy"
        np.save(sub, np.stack([rois[nm] for nm in names[:k]]))
        (cache / "names_sub.json").write_text(json.dumps(names[:k]))
        eout = cache / "out_easyidp"
        shutil.rmtree(eout, ignore_errors=True)
        eout.mkdir()
        ref = _child(REF_PY, EASYIDP.format(rois=str(sub), names=str(cache / "names_sub.json"),
                                            las=str(las), out=str(eout), epsg=EPSG))
        if k == len(names):
            t_ref, label = ref["seconds"], "measured on all plots"
        else:
            t_ref = ref["read_seconds"] + ref["crop_seconds"] * len(names) / k
            label = (f"EXTRAPOLATED from {k} of {len(names)} plots: read {ref['read_seconds']:.1f} s "
                     f"+ crop {ref['crop_seconds']:.1f} s × {len(names) / k:g}")
        print(f"  easyidp: {t_ref:.1f} s ({label}), peak {ref['maxrss_mib']:.0f} MiB"
              f"{'' if k == len(names) else ' (peak measured on the subset run)'}")
        ours_sub = sum(1 for nm in names[:k] if (out / f"{nm}.las").exists())
        print(f"  check: easyidp wrote {ref['files']} crops of {k}, ours {ours_sub} of the same plots")
        goals += [target(f"point cloud crop, {n / 1e6:g} M points × {len(names)} plots: "
                         f"easyidp 2.0.4 time ({t_ref:.0f} s{'' if k == len(names) else ', extrapolated'}) "
                         f"/ ours ({ours['seconds']:.1f} s) (issue's row)",
                         t_ref / ours["seconds"], SPEED_TARGET),
                  target("point cloud crop: ours peak / easyidp peak",
                         ours["maxrss_mib"] / ref["maxrss_mib"], MEM_TARGET, at_least=False)]

    if not a.skip_read:
        m = int(a.read_points)
        print(f"== read: {m:,} points LAS (generated once into {cache})")
        big = make_las(cache / f"cloud_{m}.las", m, extent, seed=1)
        r = _child(sys.executable, READ.format(las=str(big)))
        print(f"  ours: {r['seconds']:.1f} s to read and get float64 xyz, peak {r['maxrss_mib']:.0f} MiB "
              f"(the xyz array alone is {r['xyz_mib']:.0f} MiB; EasyIDP's paper claims 100 M points in "
              f"2 GB = 2048 MiB)")
        print(f"  memory / xyz size: {r['maxrss_mib'] / r['xyz_mib']:.2f}")
    print_targets(goals)


if __name__ == "__main__":
    main()
