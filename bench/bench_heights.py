"""Benchmark: ROI heights from a DSM (mean), the tool end to end against exactextract (issue 23).

    python -m easyidp_toolbox.bench.bench_heights [--quick] [--repeat N]

Three cases, in one run (:data:`CASES`): 10,000 plots (a 100 × 100 grid of slightly rotated
2.0 m × 1.2 m rectangles) on a 20000 × 20000 float32 DSM (2 cm, tiled 512, deflate; generated
once into bench_output/heights/), where decoding dominates; and the cost per polygon: 10,000 and
99,856 plots on a 5000 × 5000 one. In each, alternated in every round:

* the tool: ``qgis_process.bin run easyidp:roiheightsfromdsm`` (MODE per polygon, STATISTIC
  mean) with a GeoPackage output, each run after a ``qgis_process`` start-up run
  (bench_end_to_end's ``run native:buffer`` on one point);
* the engine: the core's ``dsm_roi_heights`` on the same plots (bench_end_to_end's engine child);
* exactextract 0.3.0 (PyPI; its Python API in process, in .venv-exactextract: ``make
  env-exactextract``) on the same GeoPackage and DSM: ``exact_extract(dsm, plots, "mean")``,
  timed from the call (it opens both files) to the result.

The means differ by construction: exactextract weights every cell by the share of it the polygon
covers (partial cells at the edges count in part), the tool takes the pixels whose centre is
inside (GDAL's rule, DESIGN.md). The agreement is printed (median and largest difference).
Targets: exactextract's time / (tool − start-up) ≥ 1.5 on 20000², ≥ 1 on 5000² (both counts).
"""
import argparse
import json
import math
import os
import statistics
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import imagecodecs
import numpy as np
import tifffile

from .bench_backward import _grid_plots
from .bench_end_to_end import ENGINE, _errors, _fresh, _write_gpkg, startup_run
from .common import print_targets, ratio, run_child, run_json_child, table, target

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output" / "heights"
EXACT_PYTHON = ROOT / ".venv-exactextract" / "bin" / "python"
EPSG = 32654
PIXEL = 0.02
ORIGIN = (368000.0, 3956000.0)
TILE = 512
GEN_VERSION = 1
TIMEOUT = 3600

EXACT = r"""
import json, sys, time
from exactextract import exact_extract
dsm, plots, out = sys.argv[1:4]
t0 = time.perf_counter()
res = exact_extract(dsm, plots, "mean", include_cols=["name"])   # GeoJSON-like features
t1 = time.perf_counter()
with open(out, "w") as fh:
    json.dump({f["properties"]["name"]: f["properties"]["mean"] for f in res}, fh)
print(json.dumps({"seconds": t1 - t0, "n": len(res)}))
"""


def surface_band(index: int, width: int, height: int) -> np.ndarray:
    """Rows [index·TILE, index·TILE + height) of the DSM: gentle slopes, crop rows, noise (m)."""
    rng = np.random.default_rng((GEN_VERSION, index))
    y = (index * TILE + np.arange(height, dtype=np.float32))[:, None]
    x = np.arange(width, dtype=np.float32)[None, :]
    z = (95.0 + 0.8 * np.sin(2 * np.pi * x / 9000) * np.cos(2 * np.pi * y / 7000)
         + 0.4 * np.clip(np.cos(2 * np.pi * y / 40), 0, 1))
    return (z + rng.normal(0, 0.01, z.shape)).astype(np.float32)


def write_dsm(path: Path, size: int) -> None:
    """Band by band, tiles deflated on all cores; memory stays about one band of tiles."""
    geokeys = (1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, EPSG)
    tags = [(33550, "d", 3, (PIXEL, PIXEL, 0.0), True),
            (33922, "d", 6, (0.0, 0.0, 0.0, ORIGIN[0], ORIGIN[1], 0.0), True),
            (34735, "H", len(geokeys), geokeys, True)]
    n = math.ceil(size / TILE)

    def segments(pool):
        for b in range(n):
            band = surface_band(b, size, min(TILE, size - b * TILE))
            padded = np.zeros((TILE, n * TILE), np.float32)
            padded[:band.shape[0], :size] = band
            yield from pool.map(lambda a: imagecodecs.zlib_encode(np.ascontiguousarray(a)),
                                [padded[:, c:c + TILE] for c in range(0, size, TILE)])
    part = path.with_name(path.name + ".part")
    with ThreadPoolExecutor(os.cpu_count()) as pool:
        tifffile.imwrite(part, segments(pool), shape=(size, size), dtype=np.float32,
                         compression="zlib", tile=(TILE, TILE), extratags=tags, metadata=None)
    os.replace(part, path)


CASES = ((20000, 100, 1.5), (5000, 100, 1.0), (5000, 316, 1.0))
"""(DSM side, plots per grid side, target exactextract / (tool − start-up)): where decoding
dominates (10,000 plots on 20000²), and the cost per polygon (10,000 and 99,856 on 5000²)."""
QUICK_CASES = ((5000, 50, 1.0),)


def inputs(size: int, side: int) -> dict:
    OUT.mkdir(parents=True, exist_ok=True)
    dsm = OUT / f"dsm_{size}_v{GEN_VERSION}.tif"
    if not dsm.exists():
        print(f"(generating a {size} × {size} DSM: once)", flush=True)
        write_dsm(dsm, size)
    plots = OUT / f"plots_{side}x{side}_{size}.gpkg"
    if not plots.exists():
        extent = size * PIXEL
        x0, y1 = ORIGIN
        rois = _grid_plots(x0 + 1, y1 - extent + 1, x0 + extent - 1, y1 - 1, side, side,
                           (0.5 * extent / side, 0.3 * extent / side),
                           lambda x, y: np.zeros(len(x)), 11)
        _write_gpkg(plots, {k: [p[:2] for p in v] for k, v in rois.items()}, f"EPSG:{EPSG}",
                    z=False)
    return {"dsm": dsm, "plots": plots, "size": size, "n": side * side}


def _read_heights(path: Path) -> dict:
    from osgeo import ogr
    ds = ogr.Open(str(path))
    return {f.GetField("name"): f.GetField("height") for f in ds.GetLayer(0)}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="2,500 plots on a 5000² DSM")
    ap.add_argument("--repeat", type=int, default=None, help="runs per figure (default 3; 1 quick)")
    a = ap.parse_args(argv)
    repeat = a.repeat or (1 if a.quick else 3)
    goals = []
    for size, side, goal in (QUICK_CASES if a.quick else CASES):
        goals += case(inputs(size, side), repeat, goal)
    print_targets(goals)
    return 0


def case(d: dict, repeat: int, goal: float) -> list:
    """One DSM and plot set: the tool, the engine and exactextract alternated in each of the
    ``repeat`` rounds; prints its table, returns its target rows."""
    from ..scripts.qgis_process import EXE, qgis_process_env
    env = qgis_process_env(str(_fresh(OUT / "profile")))
    tool, locks, errors, starts, engine, ex = [], 0, [], [], [], []
    means = OUT / "exactextract_means.json"
    for _ in range(repeat):                      # alternated: the shared machine's load drifts
        starts.append(startup_run(EXE, env))
        folder = _fresh(OUT / "run")
        r = run_child([EXE, "run", "easyidp:roiheightsfromdsm", "--", f"ROIS={d['plots']}",
                       f"DSM={d['dsm']}", "MODE=0", "STATISTIC=0",
                       f"OUTPUT={folder / 'heights.gpkg'}"], env=env, timeout=TIMEOUT)
        if not r.ok:
            raise RuntimeError(f"qgis_process failed:\n{r.stderr[-3000:]}")
        n_locks, errs = _errors(r)
        locks, errors = locks + n_locks, errors + errs
        tool.append(r.wall)
        _, info = run_json_child([sys.executable, "-c", ENGINE, "roiheightsfromdsm", json.dumps(
            {"rois": str(d["plots"]), "name_field": "name", "dsm": str(d["dsm"]),
             "crs": f"EPSG:{EPSG}"})], timeout=TIMEOUT, label="engine", strict=True)
        engine.append(info["seconds"])
        if EXACT_PYTHON.exists():
            _, info = run_json_child([str(EXACT_PYTHON), "-c", EXACT, str(d["dsm"]),
                                      str(d["plots"]), str(means)], timeout=TIMEOUT,
                                     label="exactextract", strict=True)
            ex.append(info["seconds"])
    startup = statistics.median(starts)
    ours = _read_heights(folder / "heights.gpkg")
    rows = [["qgis_process start-up (native:buffer, one point, before each tool run)", startup,
             None],
            ["tool end to end (qgis_process, GeoPackage output)", statistics.median(tool), None],
            ["tool − start-up", statistics.median(tool) - startup, None],
            ["engine: core dsm_roi_heights (in process)", statistics.median(engine), None]]
    goals = []
    if ex:
        rows.append(["exactextract 0.3.0 exact_extract(mean), in process",
                     statistics.median(ex), None])
        theirs = json.loads(means.read_text())
        diff = np.array([abs(ours[k] - theirs[k]) for k in ours
                         if ours[k] is not None and theirs.get(k) is not None
                         and math.isfinite(theirs[k])])
        print(f"\nMeans, ours (pixel centres inside) vs exactextract (partial cells weighted), "
              f"{len(diff)} plots: median difference {1000 * np.median(diff):.2f} mm, largest "
              f"{1000 * diff.max():.2f} mm")
        tool_net = statistics.median(tool) - startup
        where = f"{d['n']:,} plots on {d['size']}²"
        goals.append(target(f"{where}: exactextract / (tool − start-up)",
                            ratio(statistics.median(ex), tool_net), goal))
        goals.append(target(f"{where}: exactextract / tool end to end (with start-up)",
                            ratio(statistics.median(ex), statistics.median(tool)), 1.0))
        goals.append(target(f"{where}: exactextract / engine",
                            ratio(statistics.median(ex), statistics.median(engine)), goal))
    else:
        print(f"(exactextract environment not found at {EXACT_PYTHON}: run `make env-exactextract`)")
    print(f"\nROI heights (mean), {d['n']:,} plots on a {d['size']} × {d['size']} float32 DSM, "
          f"median of {repeat} (s); {locks} lock messages, {len(errors)} ERROR lines in the tool's log")
    print(table(["run", "seconds", ""], [r[:2] + [""] for r in rows]))
    return goals


if __name__ == "__main__":
    sys.exit(main())
