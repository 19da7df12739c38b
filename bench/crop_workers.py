"""The measured side of bench_crop_raster: one tool per child process, run by file path.

    python crop_workers.py TOOL RASTER ROIS OUT_DIR [--every K]

TOOL is ``ours``, ``easyidp``, ``gdal``, ``gdalwarp``, ``floor`` or ``floor_procs``. Each runs
under its own interpreter (easyidp in .venv-ref, which cannot import easyidp_toolbox), so this
module imports nothing but the standard library at the top. Each crops every ROI of ROIS into OUT_DIR (GDAL: every K-th
with ``--every K``, a labelled subset when all would take too long) and prints one JSON line:
``{"files": written, "rois": attempted, "loop_s": seconds spent cropping}``.
"""
import json
import math
import os
import sys
import time


def emit(files, rois, loop_s, **extra):
    print(json.dumps(dict(files=files, rois=rois, loop_s=loop_s, **extra)), flush=True)


def ours(raster, geojson, out_dir):
    from easyidp_toolbox.core.raster.crop import crop_raster_by_rois
    from easyidp_toolbox.core.roi import read_geojson

    rois = read_geojson(geojson, name_field="name")
    t0 = time.perf_counter()
    res = crop_raster_by_rois(raster, rois, out_dir, all_touched=False)
    emit(len(res.files), len(rois), time.perf_counter() - t0, skipped=len(res.skipped))


def easyidp(raster, shp, out_dir):
    """What an EasyIDP user writes: ROI(shp).crop(tif, save_folder=...)."""
    import easyidp as idp

    roi = idp.ROI(shp, name_field="name")
    t0 = time.perf_counter()
    roi.crop(raster, save_folder=out_dir)
    emit(len(os.listdir(out_dir)), len(roi), time.perf_counter() - t0)


def gdal(raster, shp, out_dir, every=1):
    """QGIS "Clip raster by mask layer" per feature, with "keep resolution of input raster":
    gdalwarp -cutline -cwhere -crop_to_cutline -tr <input res> -tap -dstalpha, deflate.
    In-process with the source opened once: kinder to GDAL than QGIS, which starts one gdalwarp
    process per feature. (Without -tr/-tap, GDAL 3.6 snaps the cutline envelope inwards and
    drops edge pixels whose centres are inside the ROI.)"""
    from osgeo import gdal, ogr

    gdal.UseExceptions()
    vectors = ogr.Open(shp)  # keep a reference: the layer dies with its data source
    names = [feat.GetField("name") for feat in vectors.GetLayer()][::every]
    src = gdal.Open(raster)
    _, xres, _, _, _, yres = src.GetGeoTransform()
    t0 = time.perf_counter()
    for name in names:
        gdal.Warp(os.path.join(out_dir, name + ".tif"), src, format="GTiff",
                  cutlineDSName=shp, cutlineWhere=f"name = '{name}'", cropToCutline=True,
                  xRes=xres, yRes=abs(yres), targetAlignedPixels=True, dstAlpha=True,
                  creationOptions=["COMPRESS=DEFLATE"])
    emit(len(os.listdir(out_dir)), len(names), time.perf_counter() - t0)


def gdalwarp(raster, shp, out_dir, every=1):
    """What QGIS "Clip raster by mask layer" runs for one feature, as a command per ROI:
    gdalwarp -cutline -cwhere -crop_to_cutline -tr <input res> -tap -dstalpha, deflate."""
    import subprocess

    from osgeo import gdal, ogr

    vectors = ogr.Open(shp)
    names = [feat.GetField("name") for feat in vectors.GetLayer()][::every]
    _, xres, _, _, _, yres = gdal.Open(raster).GetGeoTransform()
    t0 = time.perf_counter()
    for name in names:
        subprocess.run(["gdalwarp", "-q", "-overwrite", "-of", "GTiff", "-cutline", shp,
                        "-cwhere", f"name = '{name}'", "-crop_to_cutline", "-tr", repr(xres),
                        repr(abs(yres)), "-tap", "-dstalpha", "-co", "COMPRESS=DEFLATE", raster,
                        os.path.join(out_dir, name + ".tif")], check=True)
    emit(len(os.listdir(out_dir)), len(names), time.perf_counter() - t0)


def floor(raster, geojson, out_dir):
    """The least work any tool must do: decode every tile or strip touched by an ROI exactly
    once and deflate-encode (tifffile.imwrite) one RGBA array the size of each ROI's bounding
    window (its real pixels, alpha constant), on all cores (one process, a thread per core:
    the codecs release the GIL, the copies do not). No mask, no georeferencing, no
    reprojection: a lower bound, not a tool."""
    with open(geojson, encoding="utf-8") as fh:
        feats = json.load(fh)["features"]
    t0 = time.perf_counter()
    jobs, segments = _floor_share(raster, feats, out_dir, 0, 1, os.cpu_count())
    emit(len(os.listdir(out_dir)), jobs, time.perf_counter() - t0, segments=segments)


def floor_procs(raster, geojson, out_dir):
    """The floor on all cores without the GIL: one process per core, each decoding and
    encoding, on one thread, a contiguous share of the ROIs (ordered by their last tile or
    strip) and the segments they touch. A segment shared by two shares is decoded by both
    (``segments`` counts the decodes, ``touched`` the distinct segments): a little more work
    than the floor, never less."""
    from concurrent.futures import ProcessPoolExecutor

    with open(geojson, encoding="utf-8") as fh:
        feats = json.load(fh)["features"]
    n = os.cpu_count()
    t0 = time.perf_counter()
    with ProcessPoolExecutor(n) as pool:
        parts = list(pool.map(_floor_share, [raster] * n, [feats] * n, [out_dir] * n,
                              range(n), [n] * n, [1] * n))
    emit(len(os.listdir(out_dir)), sum(p[0] for p in parts), time.perf_counter() - t0,
         segments=sum(p[1] for p in parts), processes=n)


def _floor_share(raster, feats, out_dir, share, shares, threads):
    """Share ``share`` of ``shares`` of the floor's work on ``threads`` threads; returns (ROIs
    cropped, segments decoded)."""
    from easyidp_toolbox.core.raster.geotiff_write import DEFLATE_LEVEL  # encode as ours does
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np
    import tifffile

    with tifffile.TiffFile(raster) as tif, ThreadPoolExecutor(threads) as pool:
        page = tif.pages.first
        height, width = page.shape[:2]
        scale = page.tags["ModelPixelScaleTag"].value
        tie = page.tags["ModelTiepointTag"].value
        if page.is_tiled:
            seg_h, seg_w = page.tilelength, page.tilewidth
        else:
            seg_h, seg_w = page.rowsperstrip, width
        seg_cols = math.ceil(width / seg_w)

        # Pixel window [r0, r1) × [c0, c1) of each ROI and the segments it touches.
        jobs = []
        for feat in feats:
            ring = np.asarray(feat["geometry"]["coordinates"][0], dtype=float)
            cols = (ring[:, 0] - tie[3]) / scale[0]
            rows = (tie[4] - ring[:, 1]) / scale[1]
            r0, r1 = max(0, math.floor(rows.min())), min(height, math.ceil(rows.max()))
            c0, c1 = max(0, math.floor(cols.min())), min(width, math.ceil(cols.max()))
            segs = [ty * seg_cols + tx for ty in range(r0 // seg_h, (r1 - 1) // seg_h + 1)
                    for tx in range(c0 // seg_w, (c1 - 1) // seg_w + 1)]
            jobs.append((max(segs), feat["properties"]["name"], (r0, r1, c0, c1), segs))
        jobs.sort(key=lambda j: j[0])
        jobs = jobs[share * len(jobs) // shares:(share + 1) * len(jobs) // shares]
        pending = {}
        for job in jobs:
            for s in job[3]:
                pending[s] = pending.get(s, 0) + 1
        touched = sorted(pending)

        def decode_one(item):
            index, data = item
            seg, _, shape = page.decode(data, index, jpegtables=page.jpegtables)
            return index, seg.reshape(shape[-3:])

        def encode_one(name, window, pieces):
            r0, r1, c0, c1 = window
            crop = np.full((r1 - r0, c1 - c0, 4), 255, np.uint8)
            for sr, sc, seg in pieces:  # segment origin (row, col) and its pixels
                ra, rb = max(r0, sr), min(r1, sr + seg.shape[0])
                ca, cb = max(c0, sc), min(c1, sc + seg.shape[1])
                crop[ra - r0:rb - r0, ca - c0:cb - c0, :3] = seg[ra - sr:rb - sr, ca - sc:cb - sc]
            tifffile.imwrite(os.path.join(out_dir, name + ".tif"), crop, photometric="rgb",
                             extrasamples=["unassalpha"], compression="zlib",
                             compressionargs={"level": DEFLATE_LEVEL}, predictor=True)

        # Decode in index order, a batch at a time; an ROI is encoded as soon as its last
        # segment is decoded, and a segment is dropped when no waiting ROI needs it.
        cache, encodes, next_job = {}, [], 0
        batch_size = max(seg_cols, 512 // seg_h * seg_cols)  # one tile row or 512 strip rows
        for b in range(0, len(touched), batch_size):
            batch = []
            for index in touched[b:b + batch_size]:
                tif.filehandle.seek(page.dataoffsets[index])
                batch.append((index, tif.filehandle.read(page.databytecounts[index])))
            cache.update(pool.map(decode_one, batch))
            while next_job < len(jobs) and jobs[next_job][0] <= batch[-1][0]:
                _, name, window, segs = jobs[next_job]
                pieces = [((s // seg_cols) * seg_h, (s % seg_cols) * seg_w, cache[s]) for s in segs]
                encodes.append(pool.submit(encode_one, name, window, pieces))
                for s in segs:
                    pending[s] -= 1
                    if not pending[s]:
                        del cache[s]
                next_job += 1
        for fut in encodes:
            fut.result()
    return len(jobs), len(touched)


TOOLS = {"ours": ours, "easyidp": easyidp, "gdal": gdal, "gdalwarp": gdalwarp, "floor": floor,
         "floor_procs": floor_procs}

if __name__ == "__main__":
    tool, raster, rois, out_dir = sys.argv[1:5]
    os.makedirs(out_dir, exist_ok=True)
    if "--every" in sys.argv:
        TOOLS[tool](raster, rois, out_dir, every=int(sys.argv[sys.argv.index("--every") + 1]))
    else:
        TOOLS[tool](raster, rois, out_dir)
