"""Benchmark: rays per second of the ray–DSM intersector (core.raster.first_hits).

Run: ``python -m easyidp_toolbox.bench.bench_ray_surface [--quick] [--size 10000] [--rays 400000]``.

A float32 DSM of size² pixels at 2 cm (10000² = 200 m × 200 m, 381 MiB decoded) is written
tile by tile to a temporary GeoTIFF (deflate, tiles of 256): rolling terrain (±3 m), a slope,
and crop rows 0.6 m high every 0.5 m. Rays come from cameras 30 m above the ground in photo-
like bundles (up to 35° off nadir). Measured: a cold run (tiles read from the file as the rays
need them) and a warm run (tiles in memory), for a Pix4D-like frame (exactly linear) and a
Metashape-like geocentric frame (linearisation measured, rays regrouped), each the median of
3 runs. The target is ≥ 100,000 rays/s on 2 cores. easyidp 2.0.4 has no ray–surface intersection, so there is no
reference figure: its raw → map path is a homography (bench_forward_project).
"""
import argparse
import os
import tempfile
import time

import numpy as np

from .common import table, target

PIXEL = 0.02
ORIGIN = (368000.0, 3956000.0)
HEIGHT = 30.0
REPEATS = 3        # runs of each kind; the median is reported


def write_dsm(path: str, size: int) -> None:
    import tifffile
    from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, geotiff_tags

    def tiles():
        for r0 in range(0, size, 256):
            y = (np.arange(r0, r0 + 256)[:, None] + 0.5) * PIXEL
            for c0 in range(0, size, 256):
                x = (np.arange(c0, c0 + 256)[None, :] + 0.5) * PIXEL
                z = (100 + 3 * np.sin(x / 37.0) * np.cos(y / 23.0) + 0.02 * x
                     + 0.6 * np.clip(np.cos(2 * np.pi * x / 0.5), 0, None) ** 2
                     + 0.1 * np.sin(9 * y))
                yield z.astype(np.float32)

    tags = geotiff_tags(epsg_geo_tags(32654), (ORIGIN[0], PIXEL, 0, ORIGIN[1], 0, -PIXEL), None)
    tifffile.imwrite(path, tiles(), shape=(size, size), dtype=np.float32, tile=(256, 256),
                     compression="zlib", compressionargs={"level": 1}, extratags=tags,
                     metadata=None, photometric="minisblack")


def rays(size: int, n: int, seed: int = 0):
    """Map-frame ray origins and unit directions: bundles of 10,000 rays per camera."""
    rng = np.random.default_rng(seed)
    extent = size * PIXEL
    per = 10000
    cams = -(-n // per)
    c = np.column_stack([rng.uniform(0.1, 0.9, cams) * extent + ORIGIN[0],
                         ORIGIN[1] - rng.uniform(0.1, 0.9, cams) * extent,
                         np.full(cams, 100 + HEIGHT)])
    o = np.repeat(c, per, axis=0)[:n]
    ang = np.radians(rng.uniform(0, 35, n))
    az = rng.uniform(0, 2 * np.pi, n)
    d = np.column_stack([np.sin(ang) * np.cos(az), np.sin(ang) * np.sin(az), -np.cos(ang)])
    return o, d


def measure(path, frame, o_model, d_model, repeats: int = REPEATS):
    """Median (wall s, CPU s) of ``repeats`` cold runs (each on a new DSM: tiles read
    from the file as the rays need them) and of as many warm runs (tiles in memory)."""
    from easyidp_toolbox.core.raster import DSM, first_hits
    out = {"cold": [], "warm": []}
    for run in ["cold"] * repeats + ["warm"] * repeats:
        if run == "cold":
            surface = DSM(path).ray_surface()
        t0, c0 = time.perf_counter(), time.process_time()
        hits = first_hits(surface, frame, o_model, d_model)
        out[run].append((time.perf_counter() - t0, time.process_time() - c0))
    for run in ("cold", "warm"):
        out[run] = tuple(np.median(np.array(out[run]), axis=0))
    out["hit"] = float(hits.hit.mean())
    out["tiles"] = (surface.tiles_read, surface.ntu * surface.ntv)
    out["lin"] = hits.linearisation_error
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="2000² DSM, 100,000 rays")
    ap.add_argument("--size", type=int, default=10000)
    ap.add_argument("--rays", type=int, default=400000)
    args = ap.parse_args(argv)
    size, n = (2000, 100000) if args.quick else (args.size, args.rays)
    from pyproj import CRS, Transformer
    from easyidp_toolbox.core.reconstruction.geodesy import GeocentricFrame, OffsetFrame
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "dsm.tif")
        t0 = time.perf_counter()
        write_dsm(path, size)
        print(f"DSM {size}² px at {PIXEL * 100:.0f} cm written in {time.perf_counter() - t0:.1f} s "
              f"({os.path.getsize(path) / 2**20:.0f} MiB); {n} rays, {os.cpu_count()} cores")
        o, d = rays(size, n)
        offset = np.array([ORIGIN[0], ORIGIN[1], 100.0])
        pix4d = OffsetFrame(CRS.from_epsg(32654), offset)
        to_ecef = Transformer.from_crs(32654, 4978, always_xy=True)
        mid = (ORIGIN[0] + size * PIXEL / 2, ORIGIN[1] - size * PIXEL / 2, 100.0)
        metashape = GeocentricFrame(CRS.from_epsg(4326), np.array(to_ecef.transform(*mid)))
        o_ms = metashape.to_model(o, "EPSG:32654")
        d_ms = metashape.to_model(o + d, "EPSG:32654") - o_ms
        rows, checks = [], []
        for name, frame, om, dm in (("Pix4D-like (offset frame)", pix4d, o - offset, d),
                                    ("Metashape-like (geocentric)", metashape, o_ms, d_ms)):
            m = measure(path, frame, om, dm)
            for run in ("cold", "warm"):
                wall, cpu = m[run]
                rows.append([f"{name}, {run}", n / wall, n / cpu, wall, m["hit"] * 100,
                             f"{m['tiles'][0]}/{m['tiles'][1]}", m["lin"] * 1000])
            checks.append(target(f"rays/s, {name}, cold", n / m["cold"][0], 100000))
        print(table(["run", "rays/s", "rays/CPU-s", "wall s", "hit %", "tiles read", "lin. mm"],
                    rows))
        print()
        print(table(["target", "value", "goal", "verdict"], checks))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
