"""Benchmark: one season flight at full size, step by step (issue 33: time and peak memory).

    python -m easyidp_toolbox.bench.bench_season_size [--quick] [--cameras 500,1000,2000]

A synthetic season (:mod:`.season_size_inputs`): 2,000 cameras of 20 MP over a 300 m field,
5,000 plots, a 30,000² DSM and orthomosaic (1 cm), and 200 photos that exist (JPEG) at the
middle of the flight; ``--quick``: a quarter of the field (500 cameras, 1,250 plots, 7,500²
rasters, 40 photos). Generated once into bench_output/season_size/ (git-ignored) and reused
while valid; its disk use is printed.

Each step runs in its own child process (:mod:`.season_size_workers`; peak memory is the
child's own), through the engine's facade:

* back-projection with the occlusion test, heights from the DSM, at 500, 1,000 and 2,000
  cameras (the scaling rows; quick: 125, 250, 500), beside the same without occlusion;
* crop raster (every plot out of the orthomosaic), beside the all-core floor of
  bench_crop_raster (decode each touched tile once, encode the crops, a process per core);
* photo statistics, raw-photo crops and a training set on the photos that exist, 3 views per
  plot, over the plots they see.

Prints the figures, the reference beside them where there is one, and the targets
(back-projection with occlusion at the full size: ≤ 2 min and ≤ 4 GiB); a miss does not fail
the run.
"""
import argparse
import os
import shutil
import sys
import time
from pathlib import Path

from .common import print_targets, ratio, run_json_child, table, target
from .season_size_inputs import FULL, QUICK, disk_use, ensure_inputs

HERE = Path(__file__).resolve().parent
OUT = HERE.parent / "bench_output" / "season_size"
WORKERS = HERE / "season_size_workers.py"
CROP_WORKERS = HERE / "crop_workers.py"
TIMEOUT = 3 * 3600
BACK_SECONDS, BACK_MIB = 120.0, 4096.0    # issue 33's targets for back-projection with occlusion
CROP_FLOOR = 1.1                          # crop raster: ≤ 1.1 × the all-core floor


def step(args, label, out=None):
    """(Run, JSON) of one child; its output folder is emptied before and removed after."""
    if out is not None:
        shutil.rmtree(out, ignore_errors=True)
    run, info = run_json_child([sys.executable, *map(str, args)], timeout=TIMEOUT, label=label)
    if out is not None:
        shutil.rmtree(out, ignore_errors=True)
    print(f"    {label}: {run.wall:.1f} s, {run.peak_mb:.0f} MiB", flush=True)
    return run, info


def gib(nbytes: float) -> str:
    return f"{nbytes / 2 ** 30:.2f} GiB"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="a quarter of the field: 500 cameras, 1,250 plots, 7,500² rasters")
    ap.add_argument("--cameras", help="comma-separated camera counts of the scaling rows "
                    "(default: a quarter, a half and all of the flight)")
    ap.add_argument("--steps", default="backproject,crop,stats,crops,training",
                    help="comma-separated subset of backproject,crop,stats,crops,training")
    a = ap.parse_args(argv)
    spec = QUICK if a.quick else FULL
    counts = [int(c) for c in a.cameras.split(",")] if a.cameras else \
        [spec.cameras // 4, spec.cameras // 2, spec.cameras]
    steps = a.steps.split(",")
    if set(steps) - {"backproject", "crop", "stats", "crops", "training"}:
        ap.error(f"--steps: unknown {sorted(set(steps) - {'backproject', 'crop', 'stats', 'crops', 'training'})}")
    OUT.mkdir(parents=True, exist_ok=True)
    print(f"Season size: {spec.cameras:,} cameras of 20 MP, {spec.plots:,} plots, "
          f"{spec.raster:,}² DSM and orthomosaic ({spec.pixel * 100:g} cm), {spec.photos} photos "
          f"on disk; {os.cpu_count()} cores", flush=True)
    t0 = time.perf_counter()
    folder, paths = ensure_inputs(OUT, spec, log=lambda s: print(s, flush=True))
    made = time.perf_counter() - t0
    sizes = {k: p.stat().st_size for k, p in paths.items()}
    print(f"  inputs in {folder} ({'ready' if made < 5 else f'generated in {made:.0f} s'}): "
          f"{gib(disk_use(folder))} on disk (DSM {gib(sizes['dsm'])}, orthomosaic "
          f"{gib(sizes['ortho'])}, photos {gib(disk_use(folder / 'photos'))})", flush=True)
    runs = OUT / f"runs_{os.getpid()}"   # outputs of this run only, removed after each step
    rows, checks = [], []

    if "backproject" in steps:
        print("  back-projection (heights from the DSM):", flush=True)
        for n in counts:
            run, info = step([WORKERS, "backproject", folder, n, "occlusion"],
                             f"{n} cameras, occlusion")
            ref_run, ref = step([WORKERS, "backproject", folder, n, "none"],
                                f"{n} cameras, no occlusion") if n == max(counts) else (None, None)
            last = n == max(counts)
            rows.append([f"back-projection with occlusion, {n:,} cameras",
                         info and info["seconds"], run.cpu, run.peak_mb,
                         info and f"{info['records']:,} records, {info['plots_seen']:,} plots",
                         ref and ref["seconds"], ref_run and ref_run.peak_mb,
                         f"≤ {BACK_SECONDS:g} s, ≤ {BACK_MIB:g} MiB" if last else "-"])
            if last:
                note = "" if n >= FULL.cameras else f" ({n:,} of {FULL.cameras:,} cameras)"
                checks.append(target(f"back-projection with occlusion, seconds{note}",
                                     info and info["seconds"], BACK_SECONDS, False))
                checks.append(target(f"back-projection with occlusion, peak MiB{note}",
                                     run.peak_mb if info else None, BACK_MIB, False))

    if "crop" in steps:
        print("  crop raster (orthomosaic, every plot):", flush=True)
        run, info = step([WORKERS, "crop", folder, runs / "crop"], "ours", runs / "crop")
        ref_run, ref = step([CROP_WORKERS, "floor_procs", paths["ortho"], paths["plots"],
                             runs / "floor"], "all-core floor", runs / "floor")
        rows.append(["crop raster", info and info["seconds"], run.cpu, run.peak_mb,
                     info and f"{info['files']:,} files", ref and ref["loop_s"],
                     ref_run.peak_mb, f"≤ {CROP_FLOOR:g} × floor"])
        checks.append(target("crop raster / all-core floor (crop seconds)",
                             ratio(info and info["seconds"], ref and ref["loop_s"]),
                             CROP_FLOOR, False))

    views = f"{spec.photos} photos, 3 views per plot"
    if "stats" in steps:
        print(f"  photo statistics ({views}):", flush=True)
        run, info = step([WORKERS, "stats", folder], "photo statistics")
        rows.append([f"photo statistics ({views})", info and info["seconds"], run.cpu,
                     run.peak_mb,
                     info and f"{info['used']:,} of {info['records']:,} views used, "
                             f"{info['plots']:,} plots",
                     None, None, "-"])
    if "crops" in steps:
        print(f"  raw-photo crops ({views}):", flush=True)
        run, info = step([WORKERS, "crops", folder, runs / "crops"], "crops", runs / "crops")
        rows.append([f"raw-photo crops ({views})", info and info["seconds"], run.cpu,
                     run.peak_mb,
                     info and f"{info['files']:,} crops", None, None, "-"])
    if "training" in steps:
        print(f"  training set ({views}):", flush=True)
        run, info = step([WORKERS, "training", folder, runs / "training"], "training set",
                         runs / "training")
        rows.append([f"training-set export ({views})", info and info["seconds"], run.cpu,
                     run.peak_mb,
                     info and f"{info['images']:,} images, {info['files']:,} files", None, None,
                     "-"])
    shutil.rmtree(runs, ignore_errors=True)

    print()
    print(table(["step", "seconds", "cpu s", "peak MiB", "output", "reference s", "reference MiB",
                 "target"], rows))
    print_targets(checks)
    print("\nseconds: inside the measured call (photo statistics and crops: after their "
          "back-projection, 3 views per plot on the photos that exist); peak: the child "
          "process's largest resident set; cpu s: its user + system seconds (start-up "
          "included), steadier than seconds on a busy machine. References: back-projection without the occlusion "
          "test (same cameras); crop raster: the all-core floor of bench_crop_raster.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
