"""Benchmark: plot statistics from the raw photos (issue 17) against decoding the photos alone.

    python -m easyidp_toolbox.bench.bench_photo_statistics [--quick] [--keep-photos]

1,600 plots (bench_backward's 40 × 40 grid of 0.8 m × 1.2 m rectangles over the wheat_tanashi
field) × the photos that see them, through the real wheat_tanashi project (138 cameras, DJI FC550,
4608 × 3456), with **synthetic photos of 4608 × 3456** generated on disk (JPEG, quality 90, crop
rows on soil with noise, one photo in memory at a time). Measured, each in its own child process:

1. decoding alone: every photo the plots appear in, decoded once by the same pass
   (``DecodedPhotos``, the same threads) and dropped;
2. ``photo_statistics`` with the band means, mean ExG and the cover only;
3. ``photo_statistics`` with its defaults and two percentiles: every plot × photo measured
   (3 bands and 4 indices: mean, median, standard deviation, 5th and 95th percentiles; cover
   with Otsu's threshold: 36 statistics) and summarised;
4. the same with the per-pixel occlusion test against bench_backward's 2 cm DSM of the field
   (hedges 1.5 m tall).

Figures: seconds, seconds per photo decoded, and the ratio to decoding alone (the backward
projection is run in the child first and timed apart). ``--quick``: 400 plots × 30 photos.
Timings on a shared machine are indicative.
"""
import argparse
import json
import os
import sys
from pathlib import Path

import numpy as np

from .bench_backward import WHEAT, wheat_inputs
from .common import ratio, run_json_child, table

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output" / "photo_statistics"
GEN_VERSION = 1
TIMEOUT = 6 * 3600
QUICK_CAMERAS = 30

_SETUP = r"""
import json, sys, time
import numpy as np
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.roi import ROI, ROISet
from easyidp_toolbox.core.projection import back_project
project, rois_path, photos, n_cams = sys.argv[1:5]
d = json.load(open(rois_path))
rois = ROISet([ROI(k, [[np.array(v)[:-1, :2]]], {}, [[np.array(v)[:-1, 2]]])
               for k, v in d["rois"].items()], d["crs"])
recon = open_reconstruction(project)
cams = [c.label for c in recon.aligned_cameras][:int(n_cams) or None]
t0 = time.perf_counter()
res = back_project(rois, recon, heights="geometry", cameras=cams, min_visible=0.5)
t_bp = time.perf_counter() - t0
"""

DECODE = _SETUP + r"""
from easyidp_toolbox.core.projection import DecodedPhotos, resolve_photos
used = sorted(set(res.photo_index.tolist()))
found, missing = resolve_photos([res.photo_labels[j] for j in used],
                                [res.photo_paths[j] for j in used], photos)
assert not missing, missing
t0 = time.perf_counter()
n = 0
with DecodedPhotos([found[res.photo_labels[j]] for j in used], res.image_sizes[used]) as dec:
    for k, img, why in dec:
        assert img is not None, why
        n += 1
        del img
t = time.perf_counter() - t0
print(json.dumps({"seconds": t, "photos": n, "records": len(res), "backproject_s": t_bp}))
"""

STATS = _SETUP + r"""
from easyidp_toolbox.core.projection import photo_statistics
from easyidp_toolbox.core.raster import DSM
mode = sys.argv[5]
kw = dict(percentiles=(5, 95))
if mode == "means":
    kw = dict(statistics=("mean",), indices=["exg"])
elif mode != "full":
    kw.update(recon=recon, rois=rois, occlusion_dsm=DSM(mode))
t0 = time.perf_counter()
st = photo_statistics(res, photos, **kw)
t = time.perf_counter() - t0
print(json.dumps({"seconds": t, "photos": st.photos_decoded, "records": len(st.record),
                  "pixels": int(st.pixels.sum()), "rays": st.rays, "backproject_s": t_bp,
                  "columns": len(st.columns), "threshold": st.cover_threshold}))
"""


def photo_folder(quick: bool) -> Path:
    """Synthetic JPEG photos of 4608 × 3456 named after the wheat_tanashi cameras."""
    from easyidp_toolbox.core import open_reconstruction
    from easyidp_toolbox.core.files import write_bytes
    import imagecodecs
    folder = OUT / f"photos_4608x3456_v{GEN_VERSION}"
    folder.mkdir(parents=True, exist_ok=True)
    recon = open_reconstruction(str(WHEAT))
    cams = recon.aligned_cameras[:QUICK_CAMERAS] if quick else recon.aligned_cameras
    rng = np.random.default_rng(17)
    w, h = 4608, 3456
    col = np.arange(w)
    for k, cam in enumerate(cams):
        path = folder / (cam.label + ".JPG")
        if path.exists():
            continue
        # crop rows (about 6 px of green in 14) on soil, per-photo phase, grain noise
        phase = rng.uniform(0, 14)
        leaf = (((col + phase) % 14.0) < 6.0)[None, :]
        img = np.empty((h, w, 3), np.uint8)
        for b, (soil, green) in enumerate(((122, 58), (96, 132), (72, 46))):
            img[..., b] = np.where(leaf, green, soil)
        img += rng.integers(0, 16, (h, w, 1), dtype=np.uint8)
        write_bytes(path, imagecodecs.jpeg8_encode(img, level=90))
        del img
    return folder


def _child(code, args, env):
    return run_json_child([sys.executable, "-c", code, *map(str, args)], env=env,
                          timeout=TIMEOUT, strict=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="400 plots × 30 photos")
    ap.add_argument("--no-occlusion", action="store_true", help="skip the occlusion run")
    a = ap.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    (ROOT / "bench_output" / "backward").mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, PROJ_DATA=os.environ.get("PROJ_DATA", "/usr/share/proj"))
    w = wheat_inputs(a.quick)
    photos = photo_folder(a.quick)
    n_cams = QUICK_CAMERAS if a.quick else 0
    args = [WHEAT, w["rois"], photos, n_cams]
    run_d, d = _child(DECODE, args, env)
    rows = [["decoding alone (DecodedPhotos)", d["seconds"], d["seconds"] / d["photos"], 1.0,
             run_d.peak_mb]]
    runs = [("photo_statistics, means and ExG only", args + ["means"]),
            ("photo_statistics (36 statistics)", args + ["full"])]
    if not a.no_occlusion:
        runs.append(("photo_statistics + occlusion per pixel", args + [w["dsm"]]))
    extra = []
    for label, argv_ in runs:
        run, r = _child(STATS, argv_, env)
        rows.append([label, r["seconds"], r["seconds"] / r["photos"],
                     ratio(r["seconds"], d["seconds"]), run.peak_mb])
        extra.append(f"  {label}: {r['records']:,} plot × photo views, {r['pixels'] / 1e6:,.0f} "
                     f"Mpx measured, {r['columns']} statistics per view, {r['rays']:,} lines of "
                     f"sight; cover threshold {r['threshold']:.3f}")
    print(f"\nPlot statistics: {d['records']:,} plot × photo pairs of "
          f"{len(json.load(open(w['rois']))['rois']):,} plots in {d['photos']} synthetic photos "
          f"of 4608 × 3456 (back-projection {d['backproject_s']:.1f} s, not included)")
    print(table(["run", "seconds", "s / photo", "× decoding", "peak MiB"], rows))
    print("\n".join(extra))
    return 0


if __name__ == "__main__":
    sys.exit(main())
