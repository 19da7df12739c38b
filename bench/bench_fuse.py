"""Benchmark: fusion of detections across views (merge 'fuse', issue 32), time and peak memory.

Run: ``python -m easyidp_toolbox.bench.bench_fuse [--quick] [--detections 100000]``.

On the small demo survey (36 photos of 800 × 600, its Metashape project and DSM):
``--detections`` map polygons (32 vertices) of discs (radius 0.1–0.3 m) each seen in 6–12
photos with 2 cm vertex noise, plus 5 % false positives, fused (NMS, groups, sub-cell consensus
outline with lines of sight, expected views by back-projection with occlusion). Each merge runs
in its own child process (its peak resident memory is its own), on the same detections:

* **figure**: merge 'fuse'; target ≤ 60 s for 100,000 detections (issue 32; 207 s before);
* **reference** from the same run: merge 'union' of the same detections (grouping by overlap and
  a union per group: no vote, no lines of sight, no expected views).
"""
import argparse
import json
import os
import pickle
import sys
import tempfile
import time

import numpy as np

from .bench_training_set import _discs
from .common import print_targets, run_json_child, table, target

TARGET_S = 60.0          # fusion of 100,000 detections (issue 32)


def detections(n_det: int, photos, rng):
    """(shapes, objects, false): ``n_det`` ForwardShapes on the survey field."""
    from ..core.demo.scene import SURVEY_FIELD
    from ..core.projection.forward import ForwardShape
    from ..core.raster import HIT

    def shape(photo, ring, score):
        r3 = np.column_stack([ring, np.full(len(ring), 95.0)])
        return ForwardShape(photo, "a", "polygon", [r3], [np.full(len(ring), HIT, np.uint8)],
                            [np.ones(len(ring), bool)], score=float(score), area_m2=float("nan"),
                            perimeter_m=float("nan"))

    n_true = int(n_det / 1.05)
    per = rng.integers(6, 13, size=n_true)
    n_o = int(np.searchsorted(np.cumsum(per), n_true)) + 1
    base = _discs(n_o, SURVEY_FIELD, rng)[2]
    shapes, k = [], 0
    for k in range(n_o):
        for p in rng.choice(len(photos), size=min(per[k], len(photos)), replace=False):
            shapes.append(shape(photos[p], base[k] + rng.normal(0, 0.02, base[k].shape),
                                rng.uniform(0.6, 0.95)))
            if len(shapes) >= n_true:
                break
        if len(shapes) >= n_true:
            break
    fakes = _discs(n_det - len(shapes), SURVEY_FIELD, rng)[2]
    for ring in fakes:
        shapes.append(shape(photos[rng.integers(len(photos))], ring, rng.uniform(0.3, 0.9)))
    return shapes, k + 1, len(fakes)


def child(mode: str, data: str, project: str, dsm: str) -> None:
    """Merge the pickled shapes; print one JSON line (wall and CPU seconds, objects)."""
    from ..core.projection import merge_views
    from ..core.reconstruction import open_reconstruction
    with open(data, "rb") as fh:
        shapes, photos = pickle.load(fh)
    recon = open_reconstruction(project)
    t0, c0 = time.perf_counter(), time.process_time()
    if mode == "fuse":
        out = merge_views(shapes, "fuse", recon=recon, dsm=dsm, cameras=photos)
        kept = sum(1 for o in out if o.confidence >= 0.3)
    else:
        out = merge_views(shapes, "union")
        kept = len(out)
    print(json.dumps({"seconds": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                      "objects": len(out), "kept": kept}))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="10,000 detections")
    ap.add_argument("--detections", type=int, default=100000)
    ap.add_argument("--child", nargs=4, metavar=("MODE", "DATA", "PROJECT", "DSM"),
                    help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.child:
        child(*a.child)
        return 0
    n_det = 10000 if a.quick else a.detections
    from ..core.demo import make_demo_survey
    from ..core.reconstruction import open_reconstruction
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as tmp:
        s = make_demo_survey(os.path.join(tmp, "survey"), seed=0, size="small")
        photos = [c.label for c in open_reconstruction(s.metashape_project).aligned_cameras]
        shapes, n_obj, n_false = detections(n_det, photos, rng)
        data = os.path.join(tmp, "shapes.pkl")
        with open(data, "wb") as fh:
            pickle.dump((shapes, photos), fh, protocol=pickle.HIGHEST_PROTOCOL)
        rows, got = [], {}
        for mode in ("fuse", "union"):
            run, info = run_json_child([sys.executable, "-m", f"{__package__}.bench_fuse",
                                        "--child", mode, data, s.metashape_project, s.dsm],
                                       label=mode)
            got[mode] = info["seconds"] if info else None
            rows.append([f"merge '{mode}'" + (" (figure)" if mode == "fuse" else " (reference)"),
                         info["seconds"] if info else None, info["cpu"] if info else None,
                         run.peak_mb,
                         info["objects"] if info else None, info["kept"] if info else None])
    print(f"{len(shapes):,} detections ({n_obj:,} objects in 6–12 of 36 photos, {n_false:,} "
          f"false); {os.cpu_count()} cores")
    print(table(["run", "merge s", "merge CPU s", "peak MiB (process)", "objects",
                 "kept (confidence ≥ 0.3)"],
                rows))
    if got["fuse"] and got["union"]:
        print(f"\nfuse / union time: {got['fuse'] / got['union']:.2f}")
    goal = TARGET_S * n_det / 100000
    print_targets([target(f"fuse {n_det:,} detections, s (60 s per 100,000)", got["fuse"], goal,
                          at_least=False)])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
