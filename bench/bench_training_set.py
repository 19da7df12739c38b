"""Benchmark: training-set export and detection fusion (issue 26), time and peak memory.

Run: ``python -m easyidp_toolbox.bench.bench_training_set [--quick] [--objects 10000]
[--detections 100000]``.

1. **Export**: ``--objects`` discs (radius 0.1–0.3 m, 32 vertices, two classes) at random
   over the small demo survey's field (36 photos of 800 × 600, its Metashape project and DSM),
   exported as whole photos (occlusion tested, COCO + YOLO + LabelMe). The brief asks for 138
   photos: the demo has 36, and the 138-camera wheat_tanashi project has no photos to copy.
2. **Fusion**: ``--detections`` map polygons (32 vertices) of objects each seen in 6–12
   photos with 2 cm vertex noise, plus 5 % false positives, fused (NMS, groups, consensus,
   expected views by back-projection with occlusion) on the same survey.

Peak memory: the process's maximum resident set (``ru_maxrss``) after each step, and its
growth over the step. Figures from a shared 2-core machine.
"""
import argparse
import os
import resource
import tempfile
import time

import numpy as np


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _discs(n, lay, rng, vertices=32):
    t = np.linspace(0, 2 * np.pi, vertices, endpoint=False)
    x0, y1 = lay.origin
    c = np.column_stack([rng.uniform(x0 + 2, x0 + lay.size[0] - 2, n),
                         rng.uniform(y1 - lay.size[1] + 2, y1 - 2, n)])
    r = rng.uniform(0.1, 0.3, n)
    return c, r, c[:, None, :] + r[:, None, None] * np.stack([np.cos(t), np.sin(t)], -1)[None]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--objects", type=int, default=10000)
    ap.add_argument("--detections", type=int, default=100000)
    a = ap.parse_args(argv)
    n_obj = 500 if a.quick else a.objects
    n_det = 5000 if a.quick else a.detections
    from ..core.demo import make_demo_survey
    from ..core.demo.scene import SURVEY_FIELD
    from ..core.projection import export_training_set, fuse_views
    from ..core.projection.forward import ForwardShape
    from ..core.raster import HIT
    from ..core.reconstruction import open_reconstruction
    from ..core.roi import ROI, ROISet
    rng = np.random.default_rng(0)
    with tempfile.TemporaryDirectory() as tmp:
        s = make_demo_survey(os.path.join(tmp, "survey"), seed=0, size="small")
        recon = open_reconstruction(s.metashape_project)
        _, _, rings = _discs(max(n_obj, 1), SURVEY_FIELD, rng)
        rois = ROISet([ROI(f"o{k}", [[r]]) for k, r in enumerate(rings)], s.crs)
        classes = ["a" if k % 2 else "b" for k in range(len(rois))]
        if n_obj:                                  # --objects 0: fusion only
            rss0, t0 = _rss_mib(), time.perf_counter()
            res = export_training_set(rois, classes, recon, s.dsm, os.path.join(tmp, "set"),
                                      val_fraction=0.0)
            t_export, rss1 = time.perf_counter() - t0, _rss_mib()
            labels = sum(res.annotations.values())
            print(f"1. export {n_obj:,} objects × {len(recon.aligned_cameras)} photos: "
                  f"{t_export:.1f} s, {labels:,} labels, {sum(res.images.values())} images; "
                  f"peak RSS {rss1:.0f} MiB (+{rss1 - rss0:.0f})", flush=True)

        # detections on the map: objects × views with noise, plus false positives
        photos = [c.label for c in recon.aligned_cameras]
        n_true = int(n_det / 1.05)
        per = rng.integers(6, 13, size=n_true)
        n_o = int(np.searchsorted(np.cumsum(per), n_true)) + 1
        centres, radii, base = _discs(n_o, SURVEY_FIELD, rng)
        shapes = []
        for k in range(n_o):
            for p in rng.choice(len(photos), size=min(per[k], len(photos)), replace=False):
                ring = base[k] + rng.normal(0, 0.02, base[k].shape)
                shapes.append(_shape(ForwardShape, HIT, photos[p], ring, rng.uniform(0.6, 0.95)))
                if len(shapes) >= n_true:
                    break
            if len(shapes) >= n_true:
                break
        _, _, fakes = _discs(n_det - len(shapes), SURVEY_FIELD, rng)
        for ring in fakes:
            shapes.append(_shape(ForwardShape, HIT, photos[rng.integers(len(photos))], ring,
                                 rng.uniform(0.3, 0.9)))
        rss2, t0 = _rss_mib(), time.perf_counter()
        fused = fuse_views(shapes, recon, s.dsm, photos=photos)
        t_fuse, rss3 = time.perf_counter() - t0, _rss_mib()
        kept = sum(1 for o in fused if o.confidence >= 0.3)
        print(f"2. fuse {len(shapes):,} detections ({k + 1:,} objects, {len(fakes):,} false): "
              f"{t_fuse:.1f} s, {len(fused):,} groups, {kept:,} with confidence ≥ 0.3; "
              f"peak RSS {rss3:.0f} MiB (+{rss3 - rss2:.0f})", flush=True)
    return 0


def _shape(cls, hit, photo, ring, score):
    r3 = np.column_stack([ring, np.full(len(ring), 95.0)])
    return cls(photo, "a", "polygon", [r3], [np.full(len(ring), hit, np.uint8)],
               [np.ones(len(ring), bool)], score=float(score), area_m2=float("nan"),
               perimeter_m=float("nan"))


if __name__ == "__main__":
    raise SystemExit(main())
