"""Run the benchmarks (bench/bench_*.py) in turn, each as its own process, and print their output.

    python -m easyidp_toolbox.bench.run_all [NAME ...] [-- ARG ...]

NAMEs (e.g. ``crop_raster``) select benchmarks, default all; ARGs after ``--`` (e.g. ``--quick``)
go to each selected one. Exits non-zero only when a benchmark crashed: a missed target is a
finding of the report, not a failure.
"""
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    cut = argv.index("--") if "--" in argv else len(argv)
    names, args = argv[:cut], argv[cut + 1:]
    modules = sorted(p.stem for p in HERE.glob("bench_*.py"))
    unknown = [n for n in names if f"bench_{n}" not in modules and n not in modules]
    if unknown:
        sys.exit(f"unknown benchmark(s) {unknown}; there are {modules}")
    selected = [m for m in modules if not names or m in names or m[len("bench_"):] in names]
    crashed = []
    for name in selected:
        print(f"\n===== {name} {' '.join(args)}", flush=True)
        start = time.perf_counter()
        code = subprocess.call([sys.executable, "-m", f"{__package__}.{name}", *args])
        print(f"===== {name}: exit {code} after {time.perf_counter() - start:.0f} s", flush=True)
        if code:
            crashed.append(name)
    if crashed:
        print(f"\nbenchmarks that crashed: {', '.join(crashed)}")
    return 1 if crashed else 0


if __name__ == "__main__":
    sys.exit(main())
