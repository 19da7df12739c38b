"""The measured side of bench_season: one run per child process, by file path.

    python season_workers.py season TABLE ROIS WORKERS local|dask
    python season_workers.py easyidp ORTHO DSM SHP

``season``: our run_season on the survey table (local processes or a Dask LocalCluster of
WORKERS processes). ``easyidp``: what an easyidp 2.0.4 user writes for one date (it has no
season or pool): ``roi.crop`` of the orthomosaic and of the DSM, then the same traits with numpy
on every crop. Each prints one JSON line. Only the standard library is imported at the top, so
the easyidp side runs in .venv-ref.
"""
import json
import sys
import time


def season(table, geojson, workers, mode):
    from easyidp_toolbox.core.roi import read_geojson
    from easyidp_toolbox.core.season import run_season

    rois = read_geojson(geojson, name_field="name")
    t0 = time.perf_counter()
    r = run_season(table, rois, workers=int(workers), local_cluster=mode == "dask")
    loop = time.perf_counter() - t0
    print(json.dumps(dict(rows=len(r.rows), rois=len(rois), dates=len(r.dates), loop_s=loop,
                          executor=r.executor, problems=[str(p) for p in r.problems],
                          jobs=[[j.kind, j.worker, j.peak_mb, j.seconds] for j in r.jobs])),
          flush=True)


def easyidp(ortho, dsm, shp):
    """One date with easyidp 2.0.4: crop both rasters in memory, then ExG, cover (fixed
    threshold), band means and DSM heights (p50, p95, p99 above the ROI's 2nd percentile)."""
    import numpy as np
    import easyidp as idp

    roi = idp.ROI(shp, name_field="name")
    t0 = time.perf_counter()
    values = {}
    for name, arr in roi.crop(ortho).items():
        a = np.asarray(arr)
        ok = a[..., 3] > 0 if a.shape[-1] == 4 else np.ones(a.shape[:2], bool)
        v = a[ok][:, :3].astype(np.float64)
        exg = (2 * v[:, 1] - v[:, 0] - v[:, 2]) / np.maximum(v.sum(axis=1), 1)
        values[name] = [*v.mean(axis=0), exg.mean(), float(np.mean(exg > 0.1))]
    for name, arr in roi.crop(dsm).items():
        z = np.asarray(arr, np.float64)
        z = z[(z > -9000) & np.isfinite(z)]
        values[name] += list(np.percentile(z, [50, 95, 99]) - np.percentile(z, 2))
    print(json.dumps(dict(rois=len(values), loop_s=time.perf_counter() - t0)), flush=True)


TOOLS = {"season": season, "easyidp": easyidp}

if __name__ == "__main__":
    TOOLS[sys.argv[1]](*sys.argv[2:])
