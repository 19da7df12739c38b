"""Benchmark: a season of surveys, and the EasyIDP v2 paper's 100,000² headline (issue 14).

    python -m easyidp_toolbox.bench.bench_season [--quick] [--dates N] [--size S] [--grid G]
        [--headline-size H] [--headline-grid G] [--skip-headline] [--keep]

1. Season: N dates × G² plots on S² RGB orthomosaics and float32 DSMs (tiled 512, deflate), the
   crop growing from date to date. run_season with 1 local worker, 2 local workers and a Dask
   LocalCluster of 2 workers: wall time, speed-up, scaling efficiency (t1 / (2 t2)), peak memory
   per worker process. Reference: easyidp 2.0.4 (no season tool: ``roi.crop`` of both rasters
   and numpy traits per crop), one date measured and multiplied by N.
2. Headline: "cropping thousands of small ROIs from a 100,000 × 100,000 pixel GeoTIFF takes over
   3 hours" (EasyIDP v2 paper, §4). A 100,000² RGB raster is written tile by tile from a few
   pre-encoded tiles of a highly compressible pattern (about 0.75 GB instead of 30 GB; decoding
   it is cheaper than a real orthomosaic's), then 10,000 plots are cropped (crop_raster_by_rois)
   and their traits computed (run_season); easyidp 2.0.4 crops every K-th plot (extrapolated),
   watched so that it never exceeds 4 GiB.

Defaults: the issue's sizes; --quick: 6000², 225 plots, 4 dates, headline 20000² with 1,600
plots. Rasters are generated tile by tile (never whole in memory) into bench_output/season/,
after checking the free disk space, and deleted at the end unless --keep. Timings on a shared
machine are indicative.
"""
import argparse
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import imagecodecs
import numpy as np
import tifffile

from .common import REF_PYTHON
from .bench_crop_raster import OUT, TILE, geotiff_tags, write_rois
from .common import print_targets, ratio, reference_env, run_json_child, table, target

HERE = Path(__file__).resolve().parent
WORKERS = HERE / "season_workers.py"
CROP_WORKERS = HERE / "crop_workers.py"
SEASON = OUT / "season"
SEED = 20241114
PERIOD = 30                 # px between crop rows (the season rasters)
HEADLINE_PERIOD = 32        # px between crop rows (the headline: divides the tile height)
SOIL, LEAF = np.array([122, 96, 72], np.uint8), np.array([58, 132, 46], np.uint8)
NOISE_TILES = 8
CHILD_TIMEOUT = 6 * 3600
MEMORY_CAP = 4 * 1024 ** 3  # bytes: easyidp is killed above this


# ---------------------------------------------------------------- inputs

def _noise(rgb: bool):
    rng = np.random.default_rng(SEED)
    if rgb:
        return [rng.integers(0, 8, (TILE, TILE, 3), dtype=np.uint8) for _ in range(NOISE_TILES)]
    return [rng.normal(0.0, 0.003, (TILE, TILE)).astype(np.float32) for _ in range(NOISE_TILES)]


def growth(k: int, n: int):
    """(half-width of a crop row in px, canopy height in m) on date k of n."""
    g = (k + 1) / n
    return 2.0 + 9.0 * g, 0.1 + 0.8 * g


def season_tiles(size: int, k: int, n: int, rgb: bool):
    """The tiles of date k, row by row (each TILE², padded at the edges)."""
    half, height = growth(k, n)
    noise = _noise(rgb)
    y_all = np.arange(-(-size // TILE) * TILE, dtype=np.float32)
    for r in range(0, size, TILE):
        y = y_all[r:r + TILE][:, None]
        d = np.abs((y % PERIOD) - PERIOD / 2) / half
        leaf = d < 1
        if rgb:
            row = np.where(leaf[..., None], LEAF, SOIL).astype(np.uint8)     # (TILE, 1, 3)
        else:
            dome = np.where(leaf, height * np.sqrt(np.clip(1 - d ** 2, 0, 1)), 0)
        for c in range(0, size, TILE):
            nz = noise[(r // TILE * 7 + c // TILE * 3) % NOISE_TILES]
            if rgb:
                yield np.broadcast_to(row, (TILE, TILE, 3)) + nz
            else:
                x = (c + np.arange(TILE, dtype=np.float32))[None, :]
                yield np.round(95.0 + 2e-4 * x + 1e-4 * y + dome + nz, 3).astype(np.float32)


def write_season_raster(path: Path, size: int, k: int, n: int, rgb: bool) -> None:
    tags = geotiff_tags() + ([] if rgb else [(42113, "s", 0, "-9999", True)])
    part = path.with_name(path.name + ".part")
    tifffile.imwrite(part, season_tiles(size, k, n, rgb), shape=(size, size, 3) if rgb else
                     (size, size), dtype=np.uint8 if rgb else np.float32, tile=(TILE, TILE),
                     photometric="rgb" if rgb else "minisblack", compression="zlib",
                     compressionargs={"level": 1}, predictor=True, maxworkers=os.cpu_count(),
                     extratags=tags, metadata=None)
    os.replace(part, path)


def headline_variants():
    """Pre-encoded tiles: crop rows every HEADLINE_PERIOD px, 5 % of pixels brighter."""
    rng = np.random.default_rng(SEED)
    y = np.arange(TILE)[:, None]
    leaf = np.abs((y % HEADLINE_PERIOD) - HEADLINE_PERIOD / 2) < 7
    base = np.broadcast_to(np.where(leaf[..., None], LEAF, SOIL), (TILE, TILE, 3)).astype(np.uint8)
    out = []
    for _ in range(NOISE_TILES):
        img = base.copy()
        img[rng.random((TILE, TILE)) < 0.05] += 9
        out.append(imagecodecs.zlib_encode(img, level=6))
    return out


def write_headline(path: Path, size: int, variants) -> None:
    n = -(-size // TILE)
    part = path.with_name(path.name + ".part")
    tiles = (variants[(r * 7 + c * 3) % len(variants)] for r in range(n) for c in range(n))
    tifffile.imwrite(part, tiles, shape=(size, size, 3), dtype=np.uint8, tile=(TILE, TILE),
                     photometric="rgb", compression="zlib", extratags=geotiff_tags(),
                     metadata=None)
    os.replace(part, path)


def rois_in_season(size: int, grid: int):
    """The crop benchmark's plot grid (GeoJSON and shapefile), moved into SEASON."""
    geojson, shp, n = write_rois(size, grid)
    for p in sorted(geojson.parent.glob(geojson.stem + ".*")):
        shutil.move(str(p), SEASON / p.name)
    return SEASON / geojson.name, SEASON / shp.name, n


def check_disk(need: float, what: str) -> None:
    free = shutil.disk_usage(OUT).free
    print(f"  {what}: about {need / 1e9:.2f} GB needed, {free / 1e9:.0f} GB free", flush=True)
    if need * 1.5 > free:
        sys.exit(f"not enough free disk space for {what}")


# ---------------------------------------------------------------- measuring

def child(cmd, env=None):
    return run_json_child(cmd, env=env, timeout=CHILD_TIMEOUT)


def watched(cmd, env=None):
    """Run ``cmd``, sampling the resident memory of its process tree; killed above MEMORY_CAP.
    Returns (wall s, peak bytes sampled, JSON line or None, killed)."""
    import psutil
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                            start_new_session=True, text=True)
    peak, killed = 0, False

    def watch():
        nonlocal peak, killed
        p = psutil.Process(proc.pid)
        while proc.poll() is None:
            try:
                rss = sum(q.memory_info().rss for q in [p, *p.children(recursive=True)])
            except psutil.Error:
                rss = 0
            peak = max(peak, rss)
            if rss > MEMORY_CAP:
                killed = True
                os.killpg(proc.pid, signal.SIGKILL)
            time.sleep(0.2)
    th = threading.Thread(target=watch, daemon=True)
    th.start()
    out, err = proc.communicate(timeout=CHILD_TIMEOUT)
    th.join()
    info = None
    try:
        info = json.loads(out.strip().splitlines()[-1])
    except (ValueError, IndexError):
        print("    easyidp FAILED" + (" (killed above 4 GiB)" if killed else "") + ":\n      "
              + "\n      ".join(err.strip().splitlines()[-6:]), flush=True)
    return time.perf_counter() - t0, peak, info, killed


def per_worker_peak(info) -> float:
    """The largest peak resident memory (MiB) of any worker process (None-safe)."""
    peaks = {}
    for _, worker, mb, _ in info["jobs"]:
        if mb is not None:
            peaks[worker] = max(peaks.get(worker, 0.0), mb)
    return max(peaks.values()) if peaks else None


# ---------------------------------------------------------------- main

def run_season_bench(size, grid, dates, reference):
    print(f"\nSeason: {dates} dates × {grid * grid} plots on {size}² RGB orthomosaics and float32 "
          f"DSMs (tiled {TILE}, deflate); {os.cpu_count()} cores", flush=True)
    SEASON.mkdir(parents=True, exist_ok=True)
    check_disk(dates * size * size * (3 * 0.6 + 4 * 0.35), "the season rasters")
    t0 = time.perf_counter()
    lines = ["date,orthomosaic,dsm"]
    for k in range(dates):
        ortho, dsm = SEASON / f"ortho_{k:02d}.tif", SEASON / f"dsm_{k:02d}.tif"
        write_season_raster(ortho, size, k, dates, True)
        write_season_raster(dsm, size, k, dates, False)
        lines.append(f"2024-{5 + k // 28:02d}-{1 + k % 28:02d},{ortho.name},{dsm.name}")
    surveys = SEASON / "surveys.csv"
    surveys.write_text("\n".join(lines) + "\n")
    geojson, shp, n_rois = rois_in_season(size, grid)
    on_disk = sum(p.stat().st_size for p in SEASON.glob("*.tif"))
    print(f"  generated {2 * dates} rasters ({on_disk / 1e9:.2f} GB) in "
          f"{time.perf_counter() - t0:.0f} s", flush=True)

    rows, infos = [], {}
    for label, workers, mode in (("1 local worker", 1, "local"), ("2 local workers", 2, "local"),
                                 ("Dask LocalCluster, 2 workers", 2, "dask")):
        run, info = child([sys.executable, str(WORKERS), "season", str(surveys), str(geojson),
                           str(workers), mode])
        infos[label] = (run, info)
        busy = {}
        for _, worker, _, seconds in (info or {}).get("jobs", []):
            busy.setdefault(worker, []).append(seconds or 0.0)
        print(f"    {label}: {run.wall:.1f} s; jobs per worker (busy s): "
              + ", ".join(f"{len(v)} ({sum(v):.0f})" for v in busy.values()), flush=True)
    ref = None
    if reference:
        run, info = child([str(REF_PYTHON), str(WORKERS), "easyidp", str(SEASON / "ortho_00.tif"),
                           str(SEASON / "dsm_00.tif"), str(shp)], env=reference_env())
        if info:
            ref = (run.wall - info["loop_s"]) + info["loop_s"] * dates   # one date, × N
            print(f"    easyidp 2.0.4, one date: {run.wall:.1f} s → {ref:.0f} s for {dates} "
                  f"dates (extrapolated)", flush=True)
    t1 = infos["1 local worker"][0].wall if infos["1 local worker"][1] else None
    for label, (run, info) in infos.items():
        if info is None:
            rows.append([label, None, None, None, None, None, "FAILED"])
            continue
        n = 1 if label.startswith("1") else 2
        speed = ratio(t1, run.wall)
        rows.append([label, run.wall, speed, speed / n if speed else None,
                     per_worker_peak(info), run.peak_mb,
                     f"{info['rows']} values, {len(info['problems'])} problems"])
    rows.append(["easyidp 2.0.4 (1 date × N)", ref, ratio(t1, ref), None, None, None,
                 "extrapolated" if ref else "not run"])
    print()
    print(table(["run", "wall s", "speed-up", "efficiency", "peak MiB/worker",
                 "peak MiB (any)", "note"], rows))
    best = min((r.wall for r, i in infos.values() if i), default=None)
    print(f"\n  easyidp 2.0.4 / ours (1 worker): {ratio(ref, t1) or float('nan'):.1f}×; "
          f"/ ours (best): {ratio(ref, best) or float('nan'):.1f}×")
    print("  wall: the whole child process (start-up, imports, worker start-up included); "
          "peak MiB/worker: the largest peak resident set of a worker process; peak (any): the "
          "largest of the child and its workers (wait4).")

    def wall(label):
        run, info = infos[label]
        return run.wall if info else None
    t2 = wall("2 local workers")
    speed = ratio(t1, t2)
    return [target("season: Dask LocalCluster (2) / 2 local processes (issue's row)",
                   ratio(wall("Dask LocalCluster, 2 workers"), t2), 1.15, at_least=False),
            target(f"season: efficiency of 2 local workers on {os.cpu_count()} cores, "
                   "t1 / (2 t2) (issue's row)", speed / 2 if speed else None, 0.85)]


def run_headline(size, grid, reference, every):
    print(f"\nHeadline: {grid * grid} plots from a {size:,}² RGB GeoTIFF (tiled {TILE}, deflate)",
          flush=True)
    SEASON.mkdir(parents=True, exist_ok=True)
    variants = headline_variants()
    n_tiles = (-(-size // TILE)) ** 2
    estimate = sum(len(v) for v in variants) / len(variants) * n_tiles
    print(f"  raw {size * size * 3 / 1e9:.1f} GB; compressed estimate {estimate / 1e9:.2f} GB "
          f"({n_tiles:,} tiles of about {estimate / n_tiles / 1024:.0f} KiB)", flush=True)
    check_disk(estimate + grid * grid * 40e3, "the headline raster and its crops")
    path = SEASON / f"headline_{size}.tif"
    t0 = time.perf_counter()
    write_headline(path, size, variants)
    print(f"  written: {path.stat().st_size / 1e9:.2f} GB in {time.perf_counter() - t0:.0f} s",
          flush=True)
    geojson, shp, n_rois = rois_in_season(size, grid)
    out = SEASON / "headline_crops"
    shutil.rmtree(out, ignore_errors=True)
    rows = []
    run, info = child([sys.executable, str(CROP_WORKERS), "ours", str(path), str(geojson),
                       str(out)])
    rows.append(["ours: crop every plot to GeoTIFF", run.wall, run.peak_mb,
                 f"{info['files']}/{info['rois']} files" if info else "FAILED"])
    print(f"    crop: {run.wall:.1f} s, {run.peak_mb:.0f} MiB", flush=True)
    shutil.rmtree(out, ignore_errors=True)
    table_csv = SEASON / "headline.csv"
    table_csv.write_text(f"date,orthomosaic\n2024-06-01,{path.name}\n")
    run2, info2 = child([sys.executable, str(WORKERS), "season", str(table_csv), str(geojson),
                         "1", "local"])
    rows.append(["ours: traits of every plot (run_season, 1 worker)", run2.wall,
                 per_worker_peak(info2) if info2 else None,
                 f"{info2['rows']} values" if info2 else "FAILED"])
    print(f"    traits: {run2.wall:.1f} s", flush=True)
    ref = None
    if reference:
        sub = SEASON / "headline_subset"
        sub.mkdir(exist_ok=True)
        from osgeo import gdal
        gdal.UseExceptions()
        subset = sub / "plots.shp"
        picked = ",".join(f"'plot_r{r:02d}c{c:02d}'" for r in range(1, grid + 1, every)
                          for c in range(1, grid + 1, every))
        gdal.VectorTranslate(str(subset), str(shp), format="ESRI Shapefile",
                             where=f"name IN ({picked})")
        wall, peak, info3, killed = watched([str(REF_PYTHON), str(CROP_WORKERS), "easyidp",
                                             str(path), str(subset), str(sub / "crops")],
                                            env=reference_env())
        if info3:
            ref = wall + info3["loop_s"] * (n_rois / info3["rois"] - 1)
            rows.append([f"easyidp 2.0.4: crop [{info3['rois']}/{n_rois} plots, extrapolated]",
                         ref, peak / 1024 ** 2, f"{info3['rois']} files"])
        else:
            rows.append(["easyidp 2.0.4: crop", None, peak / 1024 ** 2,
                         "killed above 4 GiB" if killed else "FAILED"])
        shutil.rmtree(sub, ignore_errors=True)
    print()
    print(table(["job", "wall s", "peak MiB", "note"], rows))
    if ref:
        print(f"\n  easyidp 2.0.4 / ours (crop): {ratio(ref, run.wall):.0f}×")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes (minutes)")
    ap.add_argument("--size", type=int, help="season raster side (default 20000; quick 6000)")
    ap.add_argument("--grid", type=int, help="plots per side (default 40; quick 15)")
    ap.add_argument("--dates", type=int, help="season dates (default 10; quick 4)")
    ap.add_argument("--headline-size", type=int, help="default 100000; quick 20000")
    ap.add_argument("--headline-grid", type=int, help="default 100; quick 40")
    ap.add_argument("--headline-every", type=int, default=10,
                    help="easyidp crops the plots of every K-th row and column (default 10)")
    ap.add_argument("--skip-season", action="store_true")
    ap.add_argument("--skip-headline", action="store_true")
    ap.add_argument("--no-reference", action="store_true", help="do not run easyidp 2.0.4")
    ap.add_argument("--keep", action="store_true", help="keep the generated rasters")
    args = ap.parse_args(argv)
    q = args.quick
    reference = not args.no_reference
    if reference and not REF_PYTHON.exists():
        sys.exit(f"{REF_PYTHON} is missing: run `make env-ref` first (or --no-reference).")
    OUT.mkdir(exist_ok=True)
    load = os.getloadavg()[0]
    print(f"load average {load:.2f}; disk: {shutil.disk_usage(OUT).free / 1e9:.0f} GB free in "
          f"{OUT}", flush=True)
    goals = []
    try:
        if not args.skip_season:
            goals = run_season_bench(args.size or (6000 if q else 20000), args.grid or (15 if q else 40),
                             args.dates or (4 if q else 10), reference)
        if not args.skip_headline:
            run_headline(args.headline_size or (20000 if q else 100000),
                         args.headline_grid or (40 if q else 100), reference,
                         args.headline_every)
    finally:
        if not args.keep:
            shutil.rmtree(SEASON, ignore_errors=True)
    print_targets(goals)
    return 0


if __name__ == "__main__":
    sys.exit(main())
