"""Benchmark: back-projection where the user waits, against easyidp 2.0.4's whole script.

    python -m easyidp_toolbox.bench.bench_backward_wait [--quick] [--pairs N] [--no-ref]

The whole job as each user runs it, on the real wheat_tanashi project (138 photos) and
bench_backward's 1,600 plots (``--quick``: 400), geometry Z, whole ROIs only, no occlusion,
every photo kept (47,477 ROI × photo pairs):

- **easyidp 2.0.4**: a Python script that imports easyidp, opens the project, reads the ROIs,
  calls ``back2raw`` and writes EasyIDP's JSON; the CPU seconds (user + system) of its process.
- **desktop**: Back-project ROIs run in a QGIS that is already up (QgsApplication, Processing
  and the plugin loaded, as in the desktop), with GeoPackage outputs: the CPU seconds of
  ``processing.run`` in that process. The first run of the process is the figure (what the
  first click pays, the modules the run imports included); the second run is shown beside it.
- **qgis_process**: ``qgis_process.bin run easyidp:backprojectrois`` with GeoPackage outputs;
  the CPU seconds of its process (QGIS's start-up included).

The three alternate in each round (the machine is shared, its load drifts); figures are the
medians of ``--pairs`` rounds (3). Ratios are easyidp's CPU over ours, from the same rounds.

Bytecode: our modules run from cached bytecode, as in a user's installation (Python writes
``__pycache__`` beside an installed plugin at its first run). The Makefile's
``PYTHONDONTWRITEBYTECODE`` would make every QGIS process compile the plugin's modules again
(0.14–0.2 s of CPU), so our children run with ``PYTHONPYCACHEPREFIX`` in
bench_output/backward_wait/pycache, filled by one warm-up run of each; easyidp's environment
has its bytecode from pip. The row "qgis_process, no bytecode cache" runs the same command with
the Makefile's environment, for comparison (no target).
"""
import argparse
import os
import shutil
import statistics
import sys
from pathlib import Path

from .bench_backward import REF_ROIS, WHEAT
from .common import REF_PYTHON, print_targets, ratio, reference_env, run_child, run_json_child
from .common import table, target

HERE = Path(__file__).resolve().parent
OUT = HERE.parent / "bench_output" / "backward_wait"
TIMEOUT = 3600
DESKTOP_GOAL, QGIS_PROCESS_GOAL = 2.0, 1.3

# argv: PROJECT ROIS_JSON OUT_JSON; EasyIDP's own script, start to end
REF_SCRIPT = REF_ROIS + r"""
ms = idp.Metashape(project, chunk_id=0, check_img_existance=False)
out = ms.back2raw(roi)
idp.jsonfile.save_json(out, sys.argv[3])
print(json.dumps({"kept": sum(len(v) for v in out.values())}))
"""

# argv: PARAMS_JSON RUNS; the tool in a QGIS that is up, CPU of each processing.run
DESKTOP = r"""
import json, os, shutil, sys, time
from qgis.core import QgsApplication, QgsVectorLayer
app = QgsApplication([], False)
app.initQgis()
sys.path.append(os.path.join(QgsApplication.pkgDataPath(), "python", "plugins"))
from processing.core.Processing import Processing
Processing.initialize()
import processing
import easyidp_toolbox
plugin = easyidp_toolbox.classFactory(None)
plugin.initProcessing()
params, runs = json.loads(sys.argv[1]), int(sys.argv[2])
cpu, wall, kept = [], [], None
for k in range(runs):
    folder = os.path.join(params["folder"], f"run{k}")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    p = dict(params["tool"], OUTPUT=os.path.join(folder, "pixels.gpkg"),
             OUTPUT_SUMMARY=os.path.join(folder, "summary.gpkg"))
    t0, w0 = time.process_time(), time.perf_counter()
    res = processing.run("easyidp:backprojectrois", p)
    cpu.append(time.process_time() - t0)
    wall.append(time.perf_counter() - w0)
    kept = QgsVectorLayer(res["OUTPUT"], "pixels", "ogr").featureCount()
print(json.dumps({"cpu": cpu, "wall": wall, "kept": kept}))
os._exit(0)   # nothing of QGIS torn down (as tests/qgis/conftest.py ends)
"""


def our_env(base: dict) -> dict:
    """Our children's environment: bytecode cached in OUT/pycache (see the module's doc)."""
    env = dict(base)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(OUT / "pycache")
    return env


def tool_params(rois_gpkg) -> dict:
    return {"ROIS": str(rois_gpkg), "NAME_FIELD": "name", "PROJECT": str(WHEAT),
            "HEIGHT_SOURCE": 0, "CLIP": 1, "MIN_VISIBLE": 0, "OCCLUSION": False}


def _fresh(folder: Path) -> Path:
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    return folder


def run_desktop(env, params, runs: int = 2):
    import json
    return run_json_child([sys.executable, "-c", DESKTOP,
                           json.dumps({"tool": params, "folder": str(_fresh(OUT / "desktop"))}),
                           str(runs)], env=env, timeout=TIMEOUT, label="desktop", strict=True)


def run_qgis_process(exe, env, params):
    folder = _fresh(OUT / "qgis_process")
    args = [f"{k}={str(v).lower() if isinstance(v, bool) else v}" for k, v in params.items()]
    r = run_child([exe, "run", "easyidp:backprojectrois", "--", *args,
                   f"OUTPUT={folder / 'pixels.gpkg'}", f"OUTPUT_SUMMARY={folder / 'summary.gpkg'}"],
                  env=env, timeout=TIMEOUT)
    if not r.ok:
        raise RuntimeError(f"qgis_process failed ({r.returncode}):\n{r.stderr[-3000:]}")
    return r


def run_reference(env, rois_json):
    out = _fresh(OUT / "easyidp") / "back2raw.json"
    return run_json_child([str(REF_PYTHON), "-c", REF_SCRIPT, str(WHEAT), str(rois_json), str(out)],
                          env=env, timeout=TIMEOUT, label="easyidp", strict=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="400 plots instead of 1,600")
    ap.add_argument("--pairs", type=int, default=3, help="alternating rounds (default 3)")
    ap.add_argument("--no-ref", action="store_true", help="skip easyidp 2.0.4")
    a = ap.parse_args(argv)
    from ..scripts.qgis_process import EXE, qgis_process_env
    from .bench_end_to_end import OUT as E2E_OUT
    from .bench_end_to_end import wheat_case_inputs
    for folder in (OUT, E2E_OUT, E2E_OUT.parent / "backward"):
        folder.mkdir(parents=True, exist_ok=True)
    w = wheat_case_inputs(a.quick)
    params = tool_params(w["rois"])
    env = our_env(dict(os.environ, PROJ_DATA=os.environ.get("PROJ_DATA", "/usr/share/proj")))
    qp_plain = qgis_process_env(str(_fresh(OUT / "profile")))
    qp_plain["PYTHONDONTWRITEBYTECODE"] = "1"
    qp_env = our_env(qp_plain)
    ref = REF_PYTHON.exists() and not a.no_ref
    if not ref and not a.no_ref:
        print(f"(easyidp reference environment not found at {REF_PYTHON}: run `make env-ref`)")
    ref_env = reference_env(dict(os.environ))
    ref_env.update(HOME=str(OUT), XDG_DATA_HOME=str(OUT))

    run_desktop(env, params, runs=1)                 # warm-up: the bytecode cache
    run_qgis_process(EXE, qp_env, params)
    rounds = {"easyidp": [], "desktop": [], "desktop2": [], "qgis_process": [], "compiling": []}
    walls = {k: [] for k in rounds}
    kept = {}
    for k in range(a.pairs):
        if ref:
            run, info = run_reference(ref_env, w["rois_json"])
            rounds["easyidp"].append(run.cpu)
            walls["easyidp"].append(run.wall)
            kept["easyidp"] = info["kept"]
        _, info = run_desktop(env, params)
        for key, i in (("desktop", 0), ("desktop2", 1)):
            rounds[key].append(info["cpu"][i])
            walls[key].append(info["wall"][i])
        kept["ours"] = info["kept"]
        r = run_qgis_process(EXE, qp_env, params)
        rounds["qgis_process"].append(r.cpu)
        walls["qgis_process"].append(r.wall)
        r = run_qgis_process(EXE, qp_plain, params)
        rounds["compiling"].append(r.cpu)
        walls["compiling"].append(r.wall)
        print(f"  round {k + 1}: " + ", ".join(f"{n} {v[-1]:.2f} s" for n, v in rounds.items() if v),
              flush=True)

    med = {n: statistics.median(v) if v else None for n, v in rounds.items()}
    ref_cpu = med["easyidp"]
    labels = {"easyidp": "easyidp 2.0.4 script (import … write JSON)",
              "desktop": "desktop: the tool's first run in QGIS (GeoPackage outputs)",
              "desktop2": "desktop: its second run",
              "qgis_process": "qgis_process run easyidp:backprojectrois (GeoPackage outputs)",
              "compiling": "the same, no bytecode cache (make's PYTHONDONTWRITEBYTECODE)"}
    rows = [[labels[n], med[n], min(walls[n]) if walls[n] else None,
             ratio(ref_cpu, med[n]) if n != "easyidp" else None] for n in rounds]
    n_plots = 400 if a.quick else 1600
    print(f"\nBack-projection where the user waits: {n_plots} plots × 138 wheat_tanashi photos "
          f"(pairs kept: ours {kept.get('ours')}, easyidp {kept.get('easyidp', '—')}); "
          f"median CPU (user + system) of {a.pairs} alternating rounds")
    print(table(["run", "CPU s", "wall s (min)", "easyidp CPU / this"], rows))
    print_targets([
        target("desktop: easyidp script CPU / the tool's CPU", ratio(ref_cpu, med["desktop"]),
               DESKTOP_GOAL),
        target("qgis_process: easyidp script CPU / its CPU", ratio(ref_cpu, med["qgis_process"]),
               QGIS_PROCESS_GOAL)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
