"""The measured side of bench_season_size: one step per child process (its own peak memory).

    python season_size_workers.py STEP FOLDER [ARG ...]

Steps, each through the engine's facade (``easyidp_toolbox.core``) as a script user calls it:

* ``backproject FOLDER N occlusion|none``: back-project every plot into the first N cameras of
  the flight, vertex heights from the DSM, with or without the occlusion test on it;
* ``crop FOLDER OUT``: crop every plot out of the orthomosaic;
* ``stats FOLDER``, ``crops FOLDER OUT``: back-project into the cameras whose photos exist,
  best 3 views per plot, then photo statistics / raw-photo crops of those views;
* ``training FOLDER OUT``: a training set of every plot on those photos, best 3 views.

Each prints one JSON line: the seconds of the measured call(s) and what they produced.
"""
import json
import sys
import time
from pathlib import Path


def _open(folder):
    from easyidp_toolbox.core import open_reconstruction, open_rois
    from easyidp_toolbox.core.raster import DSM

    folder = Path(folder)
    rois = open_rois(str(folder / "plots.geojson"), name_field="name")
    recon = open_reconstruction(str(folder / "metashape" / "season.psx"))
    return folder, rois, recon, DSM(str(folder / "dsm.tif"))


def _photo_views(rois, recon, dsm, folder):
    from easyidp_toolbox.core import back_project

    cams = json.loads((folder / "photo_cameras.json").read_text())
    return back_project(rois, recon, heights=dsm, cameras=cams, occlusion_dsm=dsm, max_views=3)


def backproject(folder, n, mode):
    from easyidp_toolbox.core import back_project

    folder, rois, recon, dsm = _open(folder)
    cams = [c.label for c in recon.aligned_cameras][:int(n)]
    t0 = time.perf_counter()
    res = back_project(rois, recon, heights=dsm, cameras=cams,
                       occlusion_dsm=dsm if mode == "occlusion" else None)
    seconds = time.perf_counter() - t0
    print(json.dumps(dict(seconds=seconds, cameras=len(cams), rois=len(rois), records=len(res),
                          plots_seen=len(set(res.roi.tolist())))), flush=True)


def crop(folder, out):
    from easyidp_toolbox.core import crop_raster_by_rois, open_rois

    folder = Path(folder)
    rois = open_rois(str(folder / "plots.geojson"), name_field="name")
    t0 = time.perf_counter()
    res = crop_raster_by_rois(str(folder / "ortho.tif"), rois, out)
    print(json.dumps(dict(seconds=time.perf_counter() - t0, files=len(res.files))), flush=True)


def stats(folder):
    from easyidp_toolbox.core import photo_statistics

    folder, rois, recon, dsm = _open(folder)
    t0 = time.perf_counter()
    views = _photo_views(rois, recon, dsm, folder)
    t1 = time.perf_counter()
    res = photo_statistics(views)
    t2 = time.perf_counter()
    print(json.dumps(dict(seconds=t2 - t1, project_s=t1 - t0, records=len(views),
                          plots=len(set(views.roi.tolist())), used=int(res.used.sum()))),
          flush=True)


def crops(folder, out):
    from easyidp_toolbox.core import crop_photos

    folder, rois, recon, dsm = _open(folder)
    t0 = time.perf_counter()
    views = _photo_views(rois, recon, dsm, folder)
    t1 = time.perf_counter()
    res = crop_photos(views, out)
    t2 = time.perf_counter()
    print(json.dumps(dict(seconds=t2 - t1, project_s=t1 - t0, records=len(views),
                          files=len(res.files))), flush=True)


def training(folder, out):
    from easyidp_toolbox.core import export_training_set

    folder, rois, recon, dsm = _open(folder)
    cams = json.loads((folder / "photo_cameras.json").read_text())
    t0 = time.perf_counter()
    res = export_training_set(rois, ["plot"] * len(rois), recon, str(folder / "dsm.tif"), out,
                              cameras=cams, max_views=3)
    print(json.dumps(dict(seconds=time.perf_counter() - t0, files=len(res.files),
                          images=sum(res.images.values()))), flush=True)


STEPS = {"backproject": backproject, "crop": crop, "stats": stats, "crops": crops,
         "training": training}

if __name__ == "__main__":
    STEPS[sys.argv[1]](*sys.argv[2:])
