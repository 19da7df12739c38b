"""The synthetic season of bench_season_size: generated once, cached, reused while valid.

A square field in WGS 84 / UTM 54N (ellipsoidal heights) with a plot grid, a lawnmower flight
of 20 MP nadir photos 30 m above the ground (a Metashape project; its geocentric poses fitted by
``core.demo.metashape_writer``), a DSM and an orthomosaic of the same size (tiled GeoTIFFs
written tile by tile, so memory stays at one band of tiles), and a block of synthetic JPEG
photos at the middle of the flight for the steps that decode photos. The other photos of the
project do not exist: the geometry needs none.

Sizes (:data:`FULL` / :data:`QUICK`): the full season is 2,000 cameras (40 lines × 50), 5,000
plots (50 × 100), a 30,000² DSM and orthomosaic (1 cm pixels, 300 m) and 200 photos; the quick
one is a quarter of the field (500 cameras, 1,250 plots, 7,500² rasters at 2 cm, 40 photos).
"""
import json
import math
import os
import shutil
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Tuple

import numpy as np

GEN_VERSION = 1                  # bump when the generator changes: the cache is rebuilt
SEED = 20261203
EPSG = 32654
ORIGIN = (319700.0, 3956200.0)   # top-left corner of the field (and of the rasters), map x, y
GROUND = (95.0, 0.004, 0.002)    # ground height at the bottom-left corner, slope along x, y
ALTITUDE = 30.0                  # m above the ground
PHOTO_W, PHOTO_H = 5472, 3648    # 20 MP
FOCAL_PX = 3648.0                # 8.8 mm on a 13.2 mm wide sensor
PLOT = (4.5, 2.0)                # plot (x, y) size, m
TILE = 512                       # raster tile side, px
HEDGE_EVERY = 10                 # plot rows between two hedges (2.5 m tall, 0.8 m wide)


@dataclass(frozen=True)
class Spec:
    side: float                  # field side, m
    lines: int                   # flight lines (along x)
    per_line: int                # photos per line
    plot_rows: int
    plot_cols: int
    raster: int                  # DSM and orthomosaic side, px
    photo_lines: int             # the block of photos that exist: lines × photos per line
    photo_per_line: int

    @property
    def cameras(self) -> int:
        return self.lines * self.per_line

    @property
    def plots(self) -> int:
        return self.plot_rows * self.plot_cols

    @property
    def pixel(self) -> float:
        return self.side / self.raster

    @property
    def photos(self) -> int:
        return self.photo_lines * self.photo_per_line


FULL = Spec(300.0, 40, 50, 50, 100, 30000, 10, 20)
QUICK = Spec(150.0, 20, 25, 25, 50, 7500, 5, 8)


class SeasonField:
    """What ``write_metashape`` needs of a scene: the layout (origin, size), the local offset
    and the ground plane (duck-typed; the demo's Scene holds whole rasters in memory)."""

    def __init__(self, spec: Spec):
        from easyidp_toolbox.core.demo.field import FieldLayout
        self.layout = FieldLayout(origin=ORIGIN, size=(spec.side, spec.side), rows=spec.plot_rows,
                                  cols=spec.plot_cols, plot_size=PLOT, ground=GROUND,
                                  nodata_cols=0, epsg=EPSG)
        centre = (ORIGIN[0] + spec.side / 2, ORIGIN[1] - spec.side / 2)
        self.offset = np.array([round(centre[0]), round(centre[1]),
                                round(float(self.layout.ground_height(*centre)))], float)

    def ground_local(self, x, y):
        o = self.offset
        return self.layout.ground_height(x + o[0], y + o[1]) - o[2]

    @property
    def ground_plane(self):
        _, sx, sy = GROUND
        return float(self.ground_local(0.0, 0.0)), sx, sy


def ground(x, y, side):
    """Bare-ground height (m) at map (x, y)."""
    h0, sx, sy = GROUND
    return h0 + sx * (x - ORIGIN[0]) + sy * (y - ORIGIN[1] + side)


def plot_geometry(spec: Spec):
    """(names, centres (n, 2), pitch (px, py)) of the plot grid, row-major from the north-west."""
    px, py = (spec.side - 10.0) / spec.plot_cols, (spec.side - 10.0) / spec.plot_rows
    c, r = np.meshgrid(np.arange(spec.plot_cols), np.arange(spec.plot_rows))
    cx = ORIGIN[0] + 5.0 + (c.ravel() + 0.5) * px
    cy = ORIGIN[1] - 5.0 - (r.ravel() + 0.5) * py
    names = [f"P{i + 1:02d}-{j + 1:03d}" for i in range(spec.plot_rows) for j in range(spec.plot_cols)]
    return names, np.column_stack([cx, cy]), (px, py)


def write_plots(path: Path, spec: Spec) -> None:
    names, centres, _ = plot_geometry(spec)
    rng = np.random.default_rng([SEED, 1])
    hw, hh = PLOT[0] / 2, PLOT[1] / 2
    feats = []
    for name, (cx, cy) in zip(names, centres):
        a = np.radians(rng.uniform(-1.5, 1.5))        # drawn by hand: a little off the grid
        ca, sa = np.cos(a), np.sin(a)
        ring = [[round(cx + ca * u - sa * v, 4), round(cy + sa * u + ca * v, 4)]
                for u, v in ((-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh), (-hw, -hh))]
        feats.append({"type": "Feature", "properties": {"name": name, "class": "plot"},
                      "geometry": {"type": "Polygon", "coordinates": [ring]}})
    path.write_text(json.dumps({"type": "FeatureCollection", "features": feats, "crs": {
        "type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{EPSG}"}}}))


def _band_xy(spec: Spec, b: int):
    rows = min(TILE, spec.raster - b * TILE)
    x = ORIGIN[0] + (np.arange(spec.raster, dtype=np.float64) + 0.5) * spec.pixel
    y = ORIGIN[1] - (b * TILE + np.arange(rows, dtype=np.float64) + 0.5) * spec.pixel
    return x[None, :], y[:, None]


def _canopy(spec: Spec, x, y):
    """Crop height (m) above the ground at map points: each plot's own height, in rows 25 cm
    apart, lower at its edges; hedges every HEDGE_EVERY plot rows (the occluders)."""
    _, _, (px, py) = plot_geometry(spec)
    u = (x - ORIGIN[0] - 5.0) / px
    v = (ORIGIN[1] - 5.0 - y) / py
    iu, iv = np.floor(u), np.floor(v)
    inside = ((iu >= 0) & (iu < spec.plot_cols) & (iv >= 0) & (iv < spec.plot_rows)
              & (np.abs(u - iu - 0.5) * px < PLOT[0] / 2 - 0.1)
              & (np.abs(v - iv - 0.5) * py < PLOT[1] / 2 - 0.1))
    k = (iv * spec.plot_cols + iu).astype(np.int64) % 9973
    vigour = 0.35 + 0.8 * ((k * 7919) % 1000) / 1000.0          # a height per plot, 0.35–1.15 m
    rows = 0.65 + 0.35 * np.cos(2 * np.pi * (y - ORIGIN[1]) / 0.25)
    h = np.where(inside, vigour * rows, 0.0)
    hedge = (np.abs(v - np.round(v / HEDGE_EVERY) * HEDGE_EVERY) * py < 0.4) & (v > 1) & \
        (v < spec.plot_rows - 1)
    return np.where(hedge, 2.5, h)


def dsm_band(spec: Spec, b: int) -> np.ndarray:
    x, y = _band_xy(spec, b)
    return (ground(x, y, spec.side) + _canopy(spec, x, y)).astype(np.float32)


PALETTE = np.array([[122, 96, 72], [58, 132, 46], [40, 90, 36]], np.float32)


def ortho_band(spec: Spec, b: int) -> np.ndarray:
    x, y = _band_xy(spec, b)
    h = _canopy(spec, x, y).astype(np.float32)
    leaf = np.clip(h / 0.7, 0, 1)[..., None]
    img = PALETTE[0] * (1 - leaf) + PALETTE[1] * leaf
    img *= (0.9 + 0.1 * np.sin((x + 3 * y) / 0.37)).astype(np.float32)[..., None]
    return img.astype(np.uint8)


def write_raster(path: Path, spec: Spec, band, dtype, samples: int, compression) -> None:
    """A tiled GeoTIFF from ``band(spec, b)`` (TILE rows at a time), tile by tile."""
    import tifffile
    from easyidp_toolbox.core.raster.geotiff_write import epsg_geo_tags, geotiff_tags

    n = spec.raster
    nt = math.ceil(n / TILE)

    def tiles():
        with ThreadPoolExecutor(1) as ahead:       # the next band is computed while this one is written
            fut = ahead.submit(band, spec, 0)
            for b in range(nt):
                arr = fut.result()
                if b + 1 < nt:
                    fut = ahead.submit(band, spec, b + 1)
                pad = np.zeros((TILE, nt * TILE) + arr.shape[2:], dtype)
                pad[:arr.shape[0], :n] = arr
                for c in range(nt):
                    yield pad[:, c * TILE:(c + 1) * TILE]

    gt = (ORIGIN[0], spec.pixel, 0.0, ORIGIN[1], 0.0, -spec.pixel)
    part = path.with_name(path.name + ".part")
    shape = (n, n, samples) if samples > 1 else (n, n)
    kw = dict(compression="zlib", compressionargs={"level": 1}, predictor=True) \
        if compression == "deflate" else dict(compression="jpeg", compressionargs={"level": 85})
    tifffile.imwrite(part, tiles(), shape=shape, dtype=dtype, tile=(TILE, TILE),
                     photometric="rgb" if samples == 3 else "minisblack", metadata=None,
                     extratags=geotiff_tags(epsg_geo_tags(EPSG), gt, None), **kw)
    os.replace(part, path)


def flight(spec: Spec, field: SeasonField):
    """The shots (local poses) of the lawnmower flight, with slight tilts and position noise."""
    from easyidp_toolbox.core.demo.flight import Shot, nadir_rotation
    from easyidp_toolbox.core.rotations import rotation_matrix

    rng = np.random.default_rng([SEED, 2])
    off = field.offset
    dx, dy = spec.side / spec.per_line, spec.side / spec.lines
    shots = []
    for line in range(spec.lines):
        y = ORIGIN[1] - (line + 0.5) * dy - off[1]
        east = line % 2 == 0
        cols = range(spec.per_line) if east else range(spec.per_line - 1, -1, -1)
        for j in cols:
            x = ORIGIN[0] + (j + 0.5) * dx - off[0]
            tilt = np.clip(rng.normal(0.0, 1.5, 2), -4, 4)
            R = rotation_matrix(np.radians([tilt[0], tilt[1], rng.normal(0, 1)])) @ \
                nadir_rotation(0.0 if east else np.pi)
            C = np.array([x, y, float(field.ground_local(x, y)) + ALTITUDE])
            C += rng.normal(0.0, [0.1, 0.1, 0.1])
            n = len(shots) + 1
            shots.append(Shot(f"DJI_{n:04d}", f"DJI_{n:04d}.JPG", R, C, line + 1,
                              90.0 if east else 270.0, C + off + rng.normal(0, 1.0, 3),
                              f"2024:06:01 10:{n // 60 % 60:02d}:{n % 60:02d}"))
    return shots


def photo_block(spec: Spec):
    """Indices (flight order) of the shots whose photos exist: a block at the flight's middle."""
    l0 = (spec.lines - spec.photo_lines) // 2
    j0 = (spec.per_line - spec.photo_per_line) // 2
    out = []
    for line in range(l0, l0 + spec.photo_lines):
        for j in range(j0, j0 + spec.photo_per_line):
            out.append(line * spec.per_line + (j if line % 2 == 0 else spec.per_line - 1 - j))
    return sorted(out)


def write_photos(folder: Path, names) -> None:
    """Synthetic 20 MP JPEGs: one field-like texture, shifted and shaded per photo."""
    import imagecodecs
    from easyidp_toolbox.core.files import write_bytes

    rng = np.random.default_rng([SEED, 3])
    r = np.arange(PHOTO_H, dtype=np.float32)[:, None]
    c = np.arange(PHOTO_W, dtype=np.float32)[None, :]
    leaf = np.clip(1.4 * np.cos(2 * np.pi * c / 31.0) * (0.7 + 0.3 * np.sin(r / 211.0)), 0, 1)
    base = (PALETTE[0] * (1 - leaf[..., None]) + PALETTE[1] * leaf[..., None]).astype(np.uint8)
    base += rng.integers(0, 6, base.shape, dtype=np.uint8)
    del leaf

    def one(k_name):
        k, name = k_name
        img = np.roll(base, (k * 97) % PHOTO_H, axis=0)
        write_bytes(folder / name, imagecodecs.jpeg8_encode(img, level=88))

    folder.mkdir(parents=True, exist_ok=True)
    with ThreadPoolExecutor(os.cpu_count()) as pool:
        list(pool.map(one, enumerate(names)))


def write_project(folder: Path, spec: Spec) -> None:
    from easyidp_toolbox.core.demo.flight import CameraModel
    from easyidp_toolbox.core.demo.metashape_writer import write_metashape
    from easyidp_toolbox.core.reconstruction import Calibration

    field = SeasonField(spec)
    cal = Calibration(f=FOCAL_PX, cx=PHOTO_W / 2 + 11.3, cy=PHOTO_H / 2 - 7.9, b1=1.2, b2=0.0,
                      k1=-0.031, k2=0.018, k3=-0.004, p1=0.0004, p2=-0.0002)
    cam = CameraModel("Season20 (8.80mm)", "Season20", PHOTO_W, PHOTO_H, cal, 13.2 / PHOTO_W)
    shots = flight(spec, field)
    block = photo_block(spec)
    write_photos(folder / "photos", [shots[k].filename for k in block])
    paths = [str(folder / "photos" / s.filename) for s in shots]
    write_metashape(folder / "metashape", "season", field, cam, shots, paths, [],
                    np.random.default_rng([SEED, 4]))
    (folder / "photo_cameras.json").write_text(json.dumps([shots[k].label for k in block]))


def disk_use(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file())


def ensure_inputs(root: Path, spec: Spec, log=print) -> Tuple[Path, dict]:
    """The cached season for ``spec`` under ``root`` (rebuilt when missing, stale or
    incomplete); returns (its folder, {what: path})."""
    folder = root / f"season_{spec.cameras}cams_{spec.raster}px_v{GEN_VERSION}"
    manifest = folder / "manifest.json"
    paths = {"project": folder / "metashape" / "season.psx", "plots": folder / "plots.geojson",
             "dsm": folder / "dsm.tif", "ortho": folder / "ortho.tif",
             "photo_cameras": folder / "photo_cameras.json"}
    want = dict(version=GEN_VERSION, seed=SEED, spec=asdict(spec))
    try:
        have = json.loads(manifest.read_text())
        if have.get("inputs") == want and all(p.exists() for p in paths.values()) and \
                have.get("bytes") == disk_use(folder) - manifest.stat().st_size:
            return folder, paths
    except (OSError, ValueError):
        pass
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    log(f"  generating {folder.name}: plots, project and {spec.photos} photos ...")
    write_plots(paths["plots"], spec)
    write_project(folder, spec)
    log(f"  generating the {spec.raster}² DSM ...")
    write_raster(paths["dsm"], spec, dsm_band, np.float32, 1, "deflate")
    log(f"  generating the {spec.raster}² orthomosaic ...")
    write_raster(paths["ortho"], spec, ortho_band, np.uint8, 3, "jpeg")
    manifest.write_text(json.dumps(dict(inputs=want, bytes=disk_use(folder))))
    return folder, paths
