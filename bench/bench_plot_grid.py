"""Benchmark: plot grids (issue 25): 10,000 plots created, and a 20000² orthomosaic fitted with
1,600 plots, against the time to decode that orthomosaic once, measured in the same run.

    python -m easyidp_toolbox.bench.bench_plot_grid [--size 20000] [--quick]

* **create**: ``core.plotgrid.create_plot_grid`` of 100 × 100 plots in two blocks, serpentine,
  with a name pattern (the best of 5, in a child process). Target < 1 s.
* **decode**: every tile of the orthomosaic decoded once by the raster engine's reader
  (``GeoTiff.read_block``) on a pool of as many threads as cores, nothing else: the floor of any
  reading of the raster.
* **fit**: ``core.plotgrid.fit_plot_grid`` (one sweep of the raster averaged on the fly, the
  spectrum, the global and per-plot fits) from the layout turned by 1°, shifted by 0.25 m and
  with its spacing 1 % off. Target ≤ 2 × decode. Its vertex errors against the planted plots
  are printed too.

The orthomosaic (1 cm, RGB, tiled 256, deflate) is generated once, deterministically, into
bench_output/ and reused while its manifest matches: a field turned by 2° with up to 40 × 40
plots (4.6 m apart) of crop rows (0.5 m apart), each planted up to 5 cm off the layout, 2 %
of them empty — as hard as the demo trial (``core.demo.trial_render``): margin grass 0.75 as
green as the crop, weeds in 40 % of the plots and in the alleys, vigour uneven between and
within plots, a missing row segment in every plot (half of them at a row end), shadows and a
soil gradient.
"""
import argparse
import json
import math
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from .common import ratio, run_json_child, table, target
from ..core.demo.trial_render import grass_colour

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output"
GEN_VERSION = 3
SEED = 20251201
EPSG = 32654
PIXEL = 0.01
TILE = 256
ORIGIN = (400000.0, 4000000.0)          # raster's top-left corner
PITCH = 4.6
PLOT = (3.3, 2.5)                       # along the field's x (rows run along it), along y
BEARING = 88.0                          # the field's top edge: 2° off east
EDGE, ROW_SPACING, PLANT = 0.1, 0.5, 0.15
OFFSET = 0.05
EMPTY_SHARE = 0.02


def layout(size: int):
    """(plots per axis, upper-left corner of the field) for a raster of ``size`` pixels."""
    span = size * PIXEL
    t = math.radians(90 - BEARING)
    n = min(40, int((span - 6) / (PITCH * (math.cos(t) + math.sin(t)))))
    field = n * PITCH
    ext = field * (math.cos(t) + math.sin(t))
    x0 = ORIGIN[0] + (span - ext) / 2
    y0 = ORIGIN[1] - (span - ext) / 2 - field * math.sin(t)
    return n, (x0, y0)


def grid_kwargs(n: int, spacing: float = 1.0):
    gap = (PITCH * spacing - PLOT[0], PITCH * spacing - PLOT[1])
    return dict(rows=n, cols=n, size_x=PLOT[0], size_y=PLOT[1], gap_x=gap[0], gap_y=gap[1],
                order="serpentine", pattern="{row:02d}-{col:02d}")


def truth(size: int):
    """(layout grid, planted offsets (n, 2) along the grid axes, empty mask)."""
    from ..core.plotgrid import create_plot_grid, grid_options
    n, ul = layout(size)
    grid, _ = create_plot_grid(f"EPSG:{EPSG}",
                               **grid_options(origin=ul, bearing=BEARING, **grid_kwargs(n)))
    rng = np.random.default_rng(SEED)
    off = rng.uniform(-OFFSET, OFFSET, (len(grid), 2))
    empty = rng.random(len(grid)) < EMPTY_SHARE
    off[empty] = 0
    return grid, off, empty


def write_raster(path: Path, size: int) -> None:
    """Generated band by band (256 rows), tiles deflated on all cores: memory ~ one band."""
    import imagecodecs
    import tifffile
    grid, off, empty = truth(size)
    n = int(grid.row.max())
    ux, uy = np.array(grid.frame.ux), np.array(grid.frame.uy)
    o = np.array(grid.frame.origin)
    # per geometry (row, col) from the upper-left: the plot's offset and whether it is sown
    gr, gc = grid.row - 1, grid.col - 1            # serpentine from the top-left: row is geometry
    offs = np.zeros((n, n, 2), np.float32)
    sown = np.zeros((n, n), bool)
    offs[gr, gc] = off
    sown[gr, gc] = ~empty
    soil_a = np.array([122, 96, 72], np.float32)
    soil_b = np.array([150, 122, 92], np.float32)
    leaf = np.array([58, 132, 46], np.float32)
    weed = np.array([70, 140, 52], np.float32)
    grass = np.array(grass_colour(0.75), np.float32)
    rng = np.random.default_rng((SEED, 7))
    vigour = (1 - 0.6 * rng.random((n, n))).astype(np.float32)          # between plots
    wave = rng.uniform(0, 2 * np.pi, (n, n)).astype(np.float32)           # within
    rows_k = int(np.floor(PLOT[1] / 2 / ROW_SPACING))
    miss_row = rng.integers(-rows_k, rows_k + 1, (n, n))                  # one missing segment
    miss_len = rng.uniform(0.2, 0.7, (n, n))
    at_end = rng.random((n, n)) < 0.5
    end = PLOT[0] / 2 - EDGE
    miss_a = np.where(at_end, np.where(rng.random((n, n)) < 0.5, -end, end - miss_len),
                      rng.uniform(-1.2, 1.2 - miss_len))
    miss_b = miss_a + miss_len
    weedy = rng.random((n, n)) < 0.4
    field = n * PITCH

    def band(b):
        r0 = b * TILE
        rows = min(TILE, size - r0)
        y = (ORIGIN[1] - (r0 + np.arange(rows, dtype=np.float64) + 0.5) * PIXEL)[:, None]
        x = (ORIGIN[0] + (np.arange(size, dtype=np.float64) + 0.5) * PIXEL)[None, :]
        a = (x - o[0]) * ux[0] + (y - o[1]) * ux[1]
        v = (x - o[0]) * uy[0] + (y - o[1]) * uy[1]
        ci = np.floor(a / PITCH).astype(np.int32)
        ri = np.floor(v / PITCH).astype(np.int32)
        ok = (ci >= 0) & (ci < n) & (ri >= 0) & (ri < n)
        cc, rr = np.clip(ci, 0, n - 1), np.clip(ri, 0, n - 1)
        ou = a - ci * PITCH - PLOT[0] / 2 - offs[rr, cc, 0]
        ov = v - ri * PITCH - PLOT[1] / 2 - offs[rr, cc, 1]
        inside = ok & sown[rr, cc] & (np.abs(ou) < PLOT[0] / 2 - EDGE) & \
            (np.abs(ov) < PLOT[1] / 2 - EDGE)
        vig = vigour[rr, cc] * (1 + 0.35 * np.sin(0.9 * ou + wave[rr, cc]))
        h = np.clip(np.cos(2 * np.pi * ov / ROW_SPACING), 0, None) ** 2 * \
            (0.75 + 0.25 * np.cos(2 * np.pi * ou / PLANT))
        cover = np.clip(2.2 * vig * h, 0, 1)
        gone = (np.round(ov / ROW_SPACING) == miss_row[rr, cc]) & (ou >= miss_a[rr, cc]) & \
            (ou <= miss_b[rr, cc])
        w = np.where(inside & ~gone, cover, 0).astype(np.float32)[..., None]
        noise = np.random.default_rng((SEED, b))
        t = (x - ORIGIN[0]) / (size * PIXEL)
        soil = soil_a + (soil_b - soil_a) * t[..., None].astype(np.float32)
        soil = soil * (1 + 0.05 * noise.standard_normal((rows, size, 1)).astype(np.float32))
        img = soil * (1 - w) + leaf * w
        # margin grass: a 2.5 m band outside the field, patchy
        out = np.maximum(np.maximum(-a, a - field), np.maximum(-v, v - field))
        g = (out > 0.25) & (out < 2.75) & (noise.random((rows, size)) < 0.85)
        img[g] = grass
        # weeds: 8 cm squares in the weedy plots and in the alleys
        cell = (np.floor(a / 0.08).astype(np.int64) * 1_000_003 + np.floor(v / 0.08).astype(np.int64))
        hashed = (cell * 2654435761 % 2 ** 32) / 2 ** 32
        wd = ok & (hashed < np.where(weedy[rr, cc] | ~inside, 0.012, 0.0))
        img[wd] = weed
        # shadows: soft blobs on a 25 m lattice
        sh = np.sin(a / 4.1 + 1.3) * np.sin(v / 3.7 + 0.4) > 0.85
        img[sh] *= 0.55
        img = np.clip(img, 0, 255).astype(np.uint8)
        padded = np.zeros((TILE, -(-size // TILE) * TILE, 3), np.uint8)
        padded[:rows, :size] = img
        return [imagecodecs.zlib_encode(np.ascontiguousarray(padded[:, c:c + TILE]), level=6)
                for c in range(0, size, TILE)]

    def segments(pool):
        for tiles in pool.map(band, range(-(-size // TILE))):
            yield from tiles

    geokeys = (1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1, 3072, 0, 1, EPSG)
    tags = [(33550, "d", 3, (PIXEL, PIXEL, 0.0), True),
            (33922, "d", 6, (0.0, 0.0, 0.0, ORIGIN[0], ORIGIN[1], 0.0), True),
            (34735, "H", len(geokeys), geokeys, True)]
    part = path.with_name(path.name + ".part")
    with ThreadPoolExecutor(os.cpu_count()) as pool:
        tifffile.imwrite(part, segments(pool), shape=(size, size, 3), dtype=np.uint8,
                         photometric="rgb", compression="zlib", extratags=tags, metadata=None,
                         tile=(TILE, TILE))
    os.replace(part, path)


def ensure_raster(size: int) -> Path:
    OUT.mkdir(exist_ok=True)
    path = OUT / f"plotgrid_{size}.tif"
    manifest = path.with_suffix(".json")
    spec = dict(version=GEN_VERSION, seed=SEED, size=size)
    try:
        cached = json.loads(manifest.read_text())
        if cached.pop("bytes") == path.stat().st_size and cached == spec:
            return path
    except (OSError, ValueError, KeyError):
        pass
    print(f"  generating {path.name} ...", flush=True)
    t = time.perf_counter()
    manifest.unlink(missing_ok=True)
    write_raster(path, size)
    manifest.write_text(json.dumps(dict(spec, bytes=path.stat().st_size)))
    print(f"  generated in {time.perf_counter() - t:.0f} s", flush=True)
    return path


# ---- children ---------------------------------------------------------------------------------

def child_create() -> dict:
    from ..core.plotgrid import GridAnchor, GridLayout, Numbering, create_plot_grid
    best = math.inf
    for _ in range(5):
        t = time.perf_counter()
        grid, _ = create_plot_grid(f"EPSG:{EPSG}", 100, 100,
                                   anchor=GridAnchor(origin=(500000, 4000000), bearing=80),
                                   layout=GridLayout(size_x=3, size_y=1.5, gap_x=0.5, gap_y=1.0, blocks_x=2, block_gap_x=1.0),
                                   numbering=Numbering(order="serpentine", pattern="{block}-{row:03d}-{col:03d}"))
        best = min(best, time.perf_counter() - t)
    return dict(seconds=best, plots=len(grid))


def child_decode(raster: str) -> dict:
    from ..core.raster.geotiff import open_geotiff
    tif = open_geotiff(raster)
    fd = os.open(raster, os.O_RDONLY)
    t, cpu = time.perf_counter(), time.process_time()
    try:
        with ThreadPoolExecutor(os.cpu_count()) as pool:
            blocks = [(r, c) for r in range(tif.blocks_down) for c in range(tif.blocks_across)]
            n = sum(1 for _ in pool.map(lambda rc: tif.read_block(fd, *rc).shape, blocks))
    finally:
        os.close(fd)
    return dict(seconds=time.perf_counter() - t, cpu=time.process_time() - cpu, blocks=n)


def child_fit(raster: str, size: int) -> dict:
    from ..core.plotgrid import create_plot_grid, fit_plot_grid, grid_options
    grid, off, empty = truth(size)
    n = int(grid.row.max())
    start, _ = create_plot_grid(f"EPSG:{EPSG}", **grid_options(
        origin=grid.frame.origin, bearing=BEARING, **grid_kwargs(n, 1.01)))
    c = start.corners.reshape(-1, 2).mean(axis=0)
    t = math.radians(1.0)
    R = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    rings = [(q - c) @ R.T + c + (0.25, 0.0) for q in start.corners]
    t0, cpu = time.perf_counter(), time.process_time()
    res = fit_plot_grid(rings, raster)
    seconds, cpu = time.perf_counter() - t0, time.process_time() - cpu
    ux, uy = np.array(grid.frame.ux), np.array(grid.frame.uy)
    planted = grid.corners + (off[:, :1] * ux + off[:, 1:] * uy)[:, None, :]
    err = np.array([np.hypot(*(r - p).T) for r, p in zip(res.rings, planted)])
    flagged = np.array([bool(f) for f in res.flag])
    return dict(seconds=seconds, cpu=cpu, plots=len(rings), median_cm=100 * float(np.median(err)),
                max_cm=100 * float(err.max()), empty=int(empty.sum()),
                empty_flagged=int((flagged & empty).sum()), other_flagged=int((flagged & ~empty).sum()),
                work_pixel=res.work_pixel, summary=res.summary(),
                stages=res.seconds)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=20000)
    ap.add_argument("--quick", action="store_true", help="a 6000² orthomosaic")
    ap.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        kind = args.child[0]
        info = child_create() if kind == "create" else child_decode(args.child[1]) \
            if kind == "decode" else child_fit(args.child[1], int(args.child[2]))
        print(json.dumps(info))
        return 0
    size = 6000 if args.quick else args.size
    me = [sys.executable, "-m", __spec__.name, "--child"]
    print("Plot grids: create 10,000 plots; fit a grid to a "
          f"{size}² orthomosaic ({layout(size)[0] ** 2} plots)", flush=True)
    _, create = run_json_child(me + ["create"], label="create", strict=True)
    raster = str(ensure_raster(size))
    # interleaved, best of each: the machine may be shared (the load average is printed)
    decodes, fits = [], []
    for k in range(3):
        decodes.append(run_json_child(me + ["decode", raster], label="decode", strict=True)[1])
        if k < 2:
            fits.append(run_json_child(me + ["fit", raster, str(size)], label="fit", strict=True))
    decode = min(decodes, key=lambda d: d["seconds"])
    run, fit = min(fits, key=lambda rf: rf[1]["seconds"])
    dec = decode["seconds"]
    load = os.getloadavg()[0]
    dec_runs = ", ".join(f"{d['seconds']:.2f}" for d in decodes)
    fit_runs = ", ".join(f"{f[1]['seconds']:.2f}" for f in fits)
    print(table(["step", "seconds", "notes"], [
        ["create 100 × 100 plots (best of 5)", create["seconds"], f"{create['plots']} plots"],
        ["decode the orthomosaic once (best of 3)", dec,
         f"{decode['blocks']} tiles; runs {dec_runs}"],
        ["fit the grid (best of 2)", fit["seconds"],
         f"{fit['plots']} plots, peak {run.peak_mb:.0f} MiB, working pixel {fit['work_pixel']:.2f} m; "
         f"runs {fit_runs}"]]))
    print(f"  load average when done: {load:.1f} on {os.cpu_count()} cores; CPU seconds (all "
          f"threads): decode {min(d['cpu'] for d in decodes):.2f}, fit "
          f"{min(f[1]['cpu'] for f in fits):.2f}, ratio "
          f"{min(f[1]['cpu'] for f in fits) / min(d['cpu'] for d in decodes):.2f}")
    print(f"  fit: {fit['summary']}")
    print("  fit stages: " + ", ".join(f"{k} {v:.2f} s" for k, v in fit["stages"].items()))
    print(f"  vertex error against the planted plots: median {fit['median_cm']:.2f} cm, "
          f"max {fit['max_cm']:.2f} cm; empty plots flagged {fit['empty_flagged']} of "
          f"{fit['empty']}, other plots flagged {fit['other_flagged']}")
    print(table(["target", "value", "goal", "verdict"], [
        target("create 10,000 plots (s)", create["seconds"], 1.0, at_least=False),
        target("fit / decode once", ratio(fit["seconds"], dec), 2.0, at_least=False)]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
