"""Benchmark: crop every plot of a 40 × 40 grid out of a 20000 × 20000 RGB orthomosaic (issue 2).

    python -m easyidp_toolbox.bench.bench_crop_raster [--size 20000] [--quick]

Side by side in one run, each tool in its own child process (clean peak memory), all writing one
deflate GeoTIFF per ROI: ours (core.crop_raster), easyidp 2.0.4 (.venv-ref), the gdalwarp command
per ROI (what QGIS's "Clip raster by mask layer" runs; a labelled subset, extrapolated), GDAL's
Warp called per ROI in one process (stricter: no process start-up) and the floor (decode each
touched tile or strip once, encode the outputs, on all cores: threads in one process, and
one process per core; see crop_workers.py). On a tiled and a stripped copy of the raster, and
ours also on a raster of half the side, to show that its memory does not grow with the raster.

The inputs are generated once, deterministically, into bench_output/ and reused while valid.
Prints the figures, the ratios and PASS/MISS per target; a miss does not fail the run.
"""
import argparse
import json
import math
import os
import shutil
import statistics
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import imagecodecs
import numpy as np
import tifffile

from .common import REF_PYTHON, print_targets, ratio, run_json_child, spread, table, target

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output"
WORKERS = HERE / "crop_workers.py"

GEN_VERSION = 1                       # bump when the generator changes: cached files are rebuilt
SEED = 20240602
EPSG = 32654                          # WGS 84 / UTM 54N
PIXEL = 0.01                          # 1 cm pixels
ORIGIN = (368000.0, 3956000.0)        # map (x, y) of the raster's top-left corner
TILE = 512                            # tile side, and the height of a generated band of rows
PLOT = (300, 200)                     # plot rectangle (width, height) in pixels
MAX_TILT_DEG = 4.0
MARGIN = 200                          # pixels between the outer plot centres and the border
FLAT_TOLERANCE = 1.25                 # "flat" memory: peak(full side) ≤ 1.25 × peak(half side)
CHILD_TIMEOUT = 4 * 3600

# Field-like texture: soil to canopy colour ramp, indexed by a leaf-cover level, plus noise.
_LEVELS = 64
_t = np.linspace(0.0, 1.0, _LEVELS)[:, None]
PALETTE = np.round([118, 96, 72] * (1 - _t) + [56, 112, 44] * _t).astype(np.uint8)


# ---------------------------------------------------------------- inputs


def field_band(index: int, width: int, height: int) -> np.ndarray:
    """Rows [index·TILE, index·TILE + height) of the field image as (height, width, 3) uint8:
    crop rows every 30 px, vigour varying in patches, per-pixel noise (deflates to about 70 %)."""
    rng = np.random.default_rng((SEED, index))
    y = (index * TILE + np.arange(height, dtype=np.float32))[:, None]
    x = np.arange(width, dtype=np.float32)[None, :]
    rows = np.clip(1.6 * np.cos(2 * np.pi * y / 30) - 0.2, 0, 1)
    vigour = (0.55 + 0.25 * np.sin(2 * np.pi * x / 3100 + 0.7) * np.sin(2 * np.pi * y / 2300)
              + 0.2 * np.sin(2 * np.pi * (x + y) / 470))
    img = PALETTE[(np.clip(rows * vigour, 0, 1) * (_LEVELS - 1)).astype(np.uint8)]
    img += rng.integers(0, 16, size=img.shape, dtype=np.uint8)
    return img


def geotiff_tags():
    """ModelPixelScale, ModelTiepoint (pixel corner (0, 0) → ORIGIN) and GeoKeys (EPSG, area)."""
    geokeys = (1, 1, 0, 3,  1024, 0, 1, 1,  1025, 0, 1, 1,  3072, 0, 1, EPSG)
    return [(33550, "d", 3, (PIXEL, PIXEL, 0.0), True),
            (33922, "d", 6, (0.0, 0.0, 0.0, ORIGIN[0], ORIGIN[1], 0.0), True),
            (34735, "H", len(geokeys), geokeys, True)]


def write_raster(path: Path, size: int, tiled: bool) -> None:
    """Generate band by band and deflate the segments on all cores; memory stays ~ one band."""
    def segments(pool):
        for b in range(math.ceil(size / TILE)):
            band = field_band(b, size, min(TILE, size - b * TILE))
            if tiled:  # tiles are always whole: pad the last row and column of tiles
                padded = np.zeros((TILE, math.ceil(size / TILE) * TILE, 3), np.uint8)
                padded[:band.shape[0], :size] = band
                pieces = [padded[:, c:c + TILE] for c in range(0, size, TILE)]
            else:
                pieces = list(band)
            yield from pool.map(lambda a: imagecodecs.zlib_encode(np.ascontiguousarray(a)), pieces)

    part = path.with_name(path.name + ".part")
    layout = dict(tile=(TILE, TILE)) if tiled else dict(rowsperstrip=1)
    with ThreadPoolExecutor(os.cpu_count()) as pool:
        tifffile.imwrite(part, segments(pool), shape=(size, size, 3), dtype=np.uint8,
                         photometric="rgb", compression="zlib", extratags=geotiff_tags(),
                         metadata=None, **layout)
    os.replace(part, path)


def raster_problems(path: Path, size: int, tiled: bool) -> list:
    """What GDAL disagrees with: size, bands, geotransform, CRS, block layout, compression."""
    from osgeo import gdal
    gdal.UseExceptions()
    try:
        ds = gdal.Open(str(path))
    except RuntimeError as exc:
        return [str(exc)]
    problems = []
    if (ds.RasterXSize, ds.RasterYSize, ds.RasterCount) != (size, size, 3):
        problems.append(f"size {ds.RasterXSize}×{ds.RasterYSize}×{ds.RasterCount}")
    expected = (ORIGIN[0], PIXEL, 0.0, ORIGIN[1], 0.0, -PIXEL)
    if not np.allclose(ds.GetGeoTransform(), expected, rtol=0, atol=1e-9):
        problems.append(f"geotransform {ds.GetGeoTransform()} instead of {expected}")
    srs = ds.GetSpatialRef()
    if srs is None or srs.GetAuthorityCode(None) != str(EPSG):
        problems.append(f"CRS {srs and srs.GetName()} instead of EPSG:{EPSG}")
    block = ds.GetRasterBand(1).GetBlockSize()
    if block != ([TILE, TILE] if tiled else [size, 1]):
        problems.append(f"block size {block}")
    if ds.GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE") != "DEFLATE":
        problems.append("not deflate")
    return problems


def ensure_raster(size: int, tiled: bool) -> Path:
    """The cached raster if it is still valid, else a freshly generated one."""
    path = OUT / f"ortho_{size}_{'tiled' if tiled else 'stripped'}.tif"
    manifest = path.with_suffix(".json")
    spec = dict(version=GEN_VERSION, seed=SEED, size=size, tiled=tiled, tile=TILE)
    try:
        cached = json.loads(manifest.read_text())
        if (cached.pop("bytes") == path.stat().st_size and cached == spec
                and not raster_problems(path, size, tiled)):
            return path
    except (OSError, ValueError, KeyError):
        pass
    print(f"  generating {path.name} ...", flush=True)
    manifest.unlink(missing_ok=True)
    write_raster(path, size, tiled)
    problems = raster_problems(path, size, tiled)
    if problems:
        raise SystemExit(f"{path}: generated raster is wrong: {'; '.join(problems)}")
    manifest.write_text(json.dumps(dict(spec, bytes=path.stat().st_size)))
    return path


def plot_grid(size: int, grid: int):
    """(name, (4, 2) map coordinates) of grid × grid plots, slightly rotated and jittered."""
    rng = np.random.default_rng(SEED)
    half = np.array(PLOT) / 2
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * half  # pixels, x right, y down
    step = (size - 2 * MARGIN) / (grid - 1)
    for r in range(grid):
        for c in range(grid):
            a = np.radians(rng.uniform(-MAX_TILT_DEG, MAX_TILT_DEG))
            rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            centre = MARGIN + step * np.array([c, r]) + rng.uniform(-10, 10, 2)
            px = corners @ rot.T + centre
            xy = np.column_stack([ORIGIN[0] + px[:, 0] * PIXEL, ORIGIN[1] - px[:, 1] * PIXEL])
            yield f"plot_r{r + 1:02d}c{c + 1:02d}", xy


def write_rois(size: int, grid: int):
    """The plot grid as GeoJSON (ours, the floor) and as a shapefile with .prj (easyidp, GDAL)."""
    from osgeo import gdal
    gdal.UseExceptions()
    stem = OUT / f"plots_{size}_{grid}x{grid}"
    features = [{"type": "Feature", "properties": {"name": name},
                 "geometry": {"type": "Polygon",
                              "coordinates": [np.vstack([xy, xy[:1]]).round(4).tolist()]}}
                for name, xy in plot_grid(size, grid)]
    geojson = stem.with_suffix(".geojson")
    geojson.write_text(json.dumps({
        "type": "FeatureCollection", "features": features,
        "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{EPSG}"}}}))
    shp = stem.with_suffix(".shp")
    for ext in (".shp", ".shx", ".dbf", ".prj", ".cpg"):
        stem.with_suffix(ext).unlink(missing_ok=True)
    gdal.VectorTranslate(str(shp), str(geojson), format="ESRI Shapefile")
    return geojson, shp, len(features)


# ---------------------------------------------------------------- measuring


def measure(tool, raster, rois, tag, every=1):
    """One child run of crop_workers.py; returns (Run, the JSON line it printed or None)."""
    python, env = sys.executable, None
    if tool == "easyidp":  # rasterio's wheel brings its own PROJ: Debian's PROJ_DATA slows it 5×
        python = str(REF_PYTHON)
        env = {k: v for k, v in os.environ.items() if k not in ("PROJ_DATA", "PROJ_LIB")}
    out = OUT / "crop_raster" / f"{tool}_{tag}"
    shutil.rmtree(out, ignore_errors=True)
    cmd = [python, str(WORKERS), tool, str(raster), str(rois), str(out)]
    return run_json_child(cmd + (["--every", str(every)] if every > 1 else []), env=env,
                          timeout=CHILD_TIMEOUT, label=tool)


TITLES = {"ours": "ours", "floor": "floor (decode + encode), threads",
          "floor_procs": "floor (decode + encode), a process per core", "easyidp": "easyidp 2.0.4",
          "gdalwarp": "gdalwarp per ROI (QGIS clip)", "gdal": "GDAL Warp, one process"}


class Row:
    """The figures of one tool on one raster: its median run (by wall time) over the repeats."""

    def __init__(self, tool, raster_label, results, n_rois):
        self.raster, self.tool = raster_label, TITLES[tool]
        self.runs = [run for run, _ in results]
        good = sorted((pair for pair in results if pair[1] is not None), key=lambda p: p[0].wall)
        self.run, self.info = good[(len(good) - 1) // 2] if good else (None, None)
        self.wall = self.run.wall if self.run else None
        self.cpu = self.run.cpu if self.run else None
        self.loop = self.info["loop_s"] if self.info else None
        self.peak = max(run.peak_mb for run, _ in good) if good else None
        if self.info and self.info["rois"] < n_rois:  # a subset: extrapolate the cropping loop
            extra = self.loop * (n_rois / self.info["rois"] - 1)
            self.wall, self.loop, self.cpu = self.wall + extra, self.loop + extra, None
            self.tool += f" [{self.info['rois']}/{n_rois} ROIs, extrapolated]"

    def cells(self):
        files = f"{self.info['files']}/{self.info['rois']}" if self.info else "FAILED"
        return [self.raster, self.tool, self.wall, spread(self.runs) or None, self.loop,
                self.cpu, self.peak, files]


def warm_page_cache(path: Path) -> None:
    with open(path, "rb") as fh:
        while fh.read(1 << 24):
            pass


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, help="raster side in pixels (default 20000; quick 4000)")
    ap.add_argument("--grid", type=int, help="plots per side (default 40; quick 10)")
    ap.add_argument("--quick", action="store_true", help="small smoke test of the benchmark")
    ap.add_argument("--repeat", type=int, help="runs of ours and the floor, median taken "
                    "(default 3; quick 1); easyidp and GDAL run once")
    ap.add_argument("--gdal-every", type=int, default=1,
                    help="GDAL Warp in one process crops every K-th ROI only and is extrapolated "
                         "(default 1: all)")
    ap.add_argument("--gdalwarp-every", type=int, default=10,
                    help="the gdalwarp command (one process per ROI, as QGIS's Clip raster by "
                         "mask layer) crops every K-th ROI only and is extrapolated (default 10)")
    ap.add_argument("--tools", default="ours,floor,floor_procs,easyidp,gdalwarp,gdal",
                    help="comma-separated subset of ours,floor,floor_procs,easyidp,gdalwarp,gdal")
    args = ap.parse_args(argv)
    size = args.size or (4000 if args.quick else 20000)
    grid = args.grid or (10 if args.quick else 40)
    repeat = args.repeat or (1 if args.quick else 3)
    tools = args.tools.split(",")
    if set(tools) - set(TITLES):
        ap.error(f"--tools: unknown {sorted(set(tools) - set(TITLES))}")
    if "easyidp" in tools and not REF_PYTHON.exists():
        sys.exit(f"{REF_PYTHON} is missing: run `make env-ref` first (or leave out easyidp).")

    OUT.mkdir(exist_ok=True)
    shutil.rmtree(OUT / "crop_raster", ignore_errors=True)
    print(f"Crop raster by ROIs: {grid * grid} plots of {PLOT[0]}×{PLOT[1]} px (tilted up to "
          f"±{MAX_TILT_DEG:g}°), RGB uint8 {size}×{size}, deflate; {os.cpu_count()} cores",
          flush=True)
    tiled = ensure_raster(size, True)
    stripped = ensure_raster(size, False)
    small = ensure_raster(size // 2, True)
    rois, small_rois = write_rois(size, grid), write_rois(size // 2, grid)
    for path in (tiled, stripped, small):
        warm_page_cache(path)

    results = {}  # (tool, raster label) -> [(Run, info), ...]

    def record(tool, label, raster, roi_file, every=1):
        run, info = measure(tool, raster, roi_file, label.replace(" ", "_"), every)
        results.setdefault((tool, label), []).append((run, info))
        print(f"    {tool}: {run.wall:.1f} s, {run.peak_mb:.0f} MiB", flush=True)

    t, s, h = f"tiled {size}", f"stripped {size}", f"tiled {size // 2}"
    for label, raster, roi_files in ((t, tiled, rois), (s, stripped, rois), (h, small, small_rois)):
        print(f"  {label}:", flush=True)
        fast = ["ours"] if label == h else ["ours", "floor", "floor_procs"]
        for _ in range(repeat):  # interleaved, so a drift in machine speed hits both alike
            for tool in fast:
                if tool in tools:
                    record(tool, label, raster, roi_files[0])
        if label != h:
            if "easyidp" in tools:
                record("easyidp", label, raster, roi_files[1])
            if "gdalwarp" in tools:
                record("gdalwarp", label, raster, roi_files[1], args.gdalwarp_every)
            if "gdal" in tools:
                record("gdal", label, raster, roi_files[1], args.gdal_every)
    rows = {key: Row(*key, res, grid * grid) for key, res in results.items()}

    print()
    print(table(["raster", "tool", "wall s", "min–max", "crop s", "cpu s", "peak MiB", "files"],
                [r.cells() for r in rows.values()]))

    def rel(attr, tool_a, label_a, tool_b, label_b=None):
        a, b = rows.get((tool_a, label_a)), rows.get((tool_b, label_b or label_a))
        return ratio(getattr(a, attr), getattr(b, attr)) if a and b else None

    def paired(label, floor="floor"):
        """Median over the interleaved runs of ours/floor, pair by pair (robust to drift)."""
        pairs = zip(results.get(("ours", label), []), results.get((floor, label), []))
        ratios = [a.wall / b.wall for (a, ia), (b, ib) in pairs if ia and ib]
        return statistics.median(ratios) if ratios else None

    checks = [
        target("easyidp time / ours, tiled", rel("wall", "easyidp", t, "ours"), 4),
        target("easyidp time / ours, stripped", rel("wall", "easyidp", s, "ours"), 10),
        target("gdalwarp per ROI (QGIS) time / ours, tiled", rel("wall", "gdalwarp", t, "ours"), 3),
        target("gdalwarp per ROI (QGIS) time / ours, stripped", rel("wall", "gdalwarp", s, "ours"), 3),
        target("GDAL Warp one process / ours, tiled (stricter)", rel("wall", "gdal", t, "ours"), 3),
        target("GDAL Warp one process / ours, stripped (stricter)", rel("wall", "gdal", s, "ours"), 3),
        target("ours peak / easyidp peak, tiled", rel("peak", "ours", t, "easyidp"), 0.5, False),
        target("ours peak / easyidp peak, stripped", rel("peak", "ours", s, "easyidp"), 0.5, False),
        target(f"ours peak, {t} / {h} (4× the pixels)", rel("peak", "ours", t, "ours", h),
               FLAT_TOLERANCE, False),
        target("ours time / floor, tiled (paired runs)", paired(t), 1.5, False),
        target("ours time / floor, stripped (paired runs)", paired(s), 1.5, False),
        target("ours time / all-core floor (a process per core), tiled (issue's row)",
               paired(t, "floor_procs"), 1.1, False),
        target("ours time / all-core floor (a process per core), stripped (issue's row)",
               paired(s, "floor_procs"), 1.1, False),
    ]
    print_targets(checks)
    print(f"\nwall: the whole child process (start-up and imports included), median of {repeat} "
          "for ours and the floor, one run for easyidp and GDAL; crop s: inside the crop call; "
          "cpu s: user + system; peak: largest resident set over the runs. Crops in",
          OUT / "crop_raster")
    return 0


if __name__ == "__main__":
    sys.exit(main())
