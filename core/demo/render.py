"""Raw photos by ray casting: every pixel's ray, through the distorted camera, onto the surface.

The ray of a pixel centre is ``C + t·d`` in the local frame, ``d = Rᵀ·(x, y, 1)`` with (x, y)
the undistorted normalised coordinates of the pixel (``Calibration.pixel_to_normalised``,
computed once per camera). Heights are measured above the ground plane, where the surface lies
in the band [rel_min, rel_max]. Each ray's band top is the highest surface of the blocks it
crosses (``Scene.top_blocks``). Over bare soil the crossing is one step from the ground plane
(with the nearest DSM pixel's height: a few mm of noise); elsewhere the ray is marched down
from its band top in ``STEP`` m horizontal steps and the first crossing is refined by regula
falsi (Illinois). The colour is the orthomosaic, averaged to about the photo's ground
resolution, sampled bilinearly at the crossing (weights in 1/256); outside the orthomosaic a
procedural grass. Rendering works in float32 DSM-grid units (about 5 µm); :func:`intersect` is
the exact float64 version used for truth.
"""
import numpy as np

from .field import DOM_PIXEL, DSM_PIXEL
from .flight import CameraModel, Shot
from .scene import CROP_BLOCK, CROP_GROW, Scene, bilinear_grid, ortho_level

STEP = 0.04          # m, horizontal marching step (two DSM pixels)
RENDER_ITER = 2      # regula falsi iterations per crop pixel (then one interpolation)
CHUNK = 4            # marching steps evaluated at once
GRASS = np.array([92.0, 116.0, 60.0], np.float32)


def pixel_rays(camera: CameraModel) -> np.ndarray:
    """(h·w, 3) float32 camera-frame directions (x, y, 1) of the pixel centres, row by row."""
    v, u = np.mgrid[0:camera.height, 0:camera.width]
    x, y = camera.calibration.pixel_to_normalised(u.ravel() + 0.5, v.ravel() + 0.5)
    return np.column_stack([x, y, np.ones_like(x)]).astype(np.float32)


def packed_level(ortho: np.ndarray, level: int) -> np.ndarray:
    """The orthomosaic averaged over 2^level pixels, as (rows, cols) uint32 of RGBX bytes."""
    a = ortho_level(ortho, level)
    out = np.zeros(a.shape[:2] + (4,), np.uint8)
    out[..., :3] = a
    return out.view(np.uint32)[..., 0]


def level_for(camera: CameraModel, height: float) -> int:
    """Orthomosaic level (2^level cm pixels) just finer than the photo's ground resolution."""
    return max(int(np.floor(np.log2(height / camera.calibration.f / DOM_PIXEL))), 0)


class _Ray:
    """Rays of one photo in DSM-grid units of ``Scene.rel`` (padded index coordinates), from
    one origin C (3,) or one origin per ray (n, 3) (a rolling-shutter photo)."""

    def __init__(self, scene: Scene, C: np.ndarray, d: np.ndarray, dtype):
        a, bx, by = scene.ground_plane
        lay, p = scene.layout, DSM_PIXEL
        self.scene, self.dtype = scene, dtype
        cx, cy, cz = C[..., 0], C[..., 1], C[..., 2]
        self.H0 = dtype(cz - (a + bx * cx + by * cy))             # camera height above the plane
        self.D = (d[:, 2] - dtype(bx) * d[:, 0] - dtype(by) * d[:, 1]).astype(dtype)
        self.gx0 = dtype((cx + scene.offset[0] - lay.origin[0]) / p + 0.5)
        self.gy0 = dtype((lay.origin[1] - scene.offset[1] - cy) / p + 0.5)
        self.sx = (d[:, 0] * dtype(1 / p)).astype(dtype)
        self.sy = (d[:, 1] * dtype(-1 / p)).astype(dtype)
        horiz = np.hypot(d[:, 0], d[:, 1])
        # band_top looks at the middle of each ray's crossing of the band: the crossing must stay
        # within the CROP_GROW blocks over which the block tops were spread
        half = 0.5 * (scene.rel_max - scene.rel_min + 2e-3) * horiz / np.maximum(-self.D, 1e-12)
        if np.any(self.D >= 0) or np.any(half > CROP_GROW * CROP_BLOCK * DSM_PIXEL):
            raise ValueError("rays must point down, steeply enough to cross the surface band "
                             "within CROP_GROW blocks")
        self.horiz = horiz

    def subset(self, idx) -> "_Ray":
        out = object.__new__(_Ray)
        out.__dict__.update(self.__dict__)
        for k in ("D", "sx", "sy", "horiz", "H0", "gx0", "gy0"):
            v = getattr(self, k)
            if np.ndim(v):
                setattr(out, k, v[idx])
        return out

    @staticmethod
    def _pick(v, idx):
        """A per-ray quantity at ``idx`` (a single origin's scalars unchanged)."""
        return v if idx is None or not np.ndim(v) else v[idx]

    def grid(self, t, idx=None):
        sx, sy = (self.sx, self.sy) if idx is None else (self.sx[idx], self.sy[idx])
        return self._pick(self.gx0, idx) + t * sx, self._pick(self.gy0, idx) + t * sy

    def f(self, t, idx=None):
        """Height of the ray above the surface at t (any shape that broadcasts with idx)."""
        D = self.D if idx is None else self.D[idx]
        gx, gy = self.grid(t, idx)
        rel = bilinear_grid(self.scene.rel, np.array(gx, copy=True).ravel(),
                            np.array(gy, copy=True).ravel())
        return self._pick(self.H0, idx) + t * D - rel.reshape(gx.shape)

    def band_top(self):
        """(t at the band top, t at the band bottom, band top above the plane) per ray, the
        top read from the block under the middle of the ray's crossing of the band."""
        s = self.scene
        t0 = (self.dtype(s.rel_max + 1e-3) - self.H0) / self.D
        t1 = (self.dtype(s.rel_min - 1e-3) - self.H0) / self.D
        top = _block_top(s, *self.grid(0.5 * (t0 + t1)))
        return (top + self.dtype(1e-3) - self.H0) / self.D, t1, top


def _block_top(scene: Scene, gx, gy) -> np.ndarray:
    """Band top (m above the plane) of the block under padded grid coordinates (bare outside)."""
    b = scene.top_blocks
    col = ((gx - 0.5) * (1 / CROP_BLOCK) + 1).astype(np.int32)   # block index + 1 (an exact
    row = ((gy - 0.5) * (1 / CROP_BLOCK) + 1).astype(np.int32)   # floor right of block -1)
    ok = (col >= 1) & (col <= b.shape[1]) & (row >= 1) & (row <= b.shape[0])
    out = np.full(len(gx), scene.bare_max, np.float32)
    out[ok] = b[row[ok] - 1, col[ok] - 1]
    return out


def _bracket(ray: _Ray, t_top, t_bot, iterations: int, tol: float, step: float = STEP):
    """March the rays from ``t_top`` (above the surface) to ``t_bot`` (below) in ``step`` m
    horizontal steps; refine the first crossing by Illinois regula falsi."""
    steps = np.maximum(np.ceil(ray.horiz * (t_bot - t_top) / step).astype(np.int64), 1)
    dt = (t_bot - t_top) / steps
    n = len(t_top)
    fa = ray.f(t_top)                              # > 0: above the surface
    rows = np.arange(n)
    ta, tb, fb = t_top.copy(), t_bot.copy(), np.empty_like(fa)
    todo = rows
    k0 = 0
    while todo.size:                               # march CHUNK steps at a time, all at once
        k = np.arange(k0 + 1, k0 + CHUNK + 1)
        T = t_top[todo, None] + dt[todo, None] * np.minimum(k[None, :], steps[todo, None]).astype(dt.dtype)
        F = ray.f(T, todo[:, None])
        below = F <= 0
        hit = below.any(axis=1)
        j = np.argmax(below, axis=1)
        h = todo[hit]
        tb[h], fb[h] = T[hit, j[hit]], F[hit, j[hit]]
        prev = j[hit] - 1
        later = prev >= 0
        ta[h[later]], fa[h[later]] = T[hit, prev][later], F[hit, prev][later]
        miss = ~hit
        ta[todo[miss]], fa[todo[miss]] = T[miss, -1], F[miss, -1]
        todo = todo[miss]
        k0 += CHUNK
    side = np.zeros(n, np.int8)
    for _ in range(iterations):
        t = ta - fa * (tb - ta) / (fb - fa)        # fa > 0 >= fb
        ft = ray.f(t)
        if tol > 0 and np.all(np.abs(ft) < tol):
            return t
        lo = ft > 0
        fb = np.where(lo, fb * np.where(side == 1, 0.5, 1.0).astype(fb.dtype), ft)
        fa = np.where(lo, ft, fa * np.where(side == -1, 0.5, 1.0).astype(fa.dtype))
        ta, tb = np.where(lo, t, ta), np.where(lo, tb, t)
        side = np.where(lo, 1, -1).astype(np.int8)
    return ta - fa * (tb - ta) / (fb - fa)


def intersect(scene: Scene, C: np.ndarray, d: np.ndarray, tol: float = 1e-7) -> np.ndarray:
    """Exact ray parameters t (n,) of the first crossing of ``C + t·d`` (local, float64) with
    the surface, to ``tol`` m in height, marching in DSM half-pixels. ``d`` (n, 3) points down."""
    ray = _Ray(scene, np.asarray(C, np.float64), np.asarray(d, np.float64), np.float64)
    t_top, t_bot, _ = ray.band_top()
    return _bracket(ray, t_top, t_bot, 200, tol, DSM_PIXEL / 2)


def _lerp(a: np.ndarray, b: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Per-byte a + (b − a)·w/256 of packed RGBX uint32 (w uint32 in 0..256), in integers."""
    lo = np.uint32(0x00FF00FF)
    iw = np.uint32(256) - w
    rb = ((a & lo) * iw + (b & lo) * w) >> np.uint32(8)
    ga = (((a >> np.uint32(8)) & lo) * iw + ((b >> np.uint32(8)) & lo) * w) & ~lo
    return (rb & lo) | ga


def ortho_colour(scene: Scene, level_img: np.ndarray, level: int, fx, fy) -> np.ndarray:
    """Bilinear colour (n,) packed RGBX uint32 of the packed orthomosaic level at padded
    DSM-grid coordinates (weights in 1/256); procedural grass outside the orthomosaic."""
    k = np.float32(DSM_PIXEL / (DOM_PIXEL * 2 ** level))
    fc = (fx - np.float32(0.5)) * k - np.float32(0.5)
    fr = (fy - np.float32(0.5)) * k - np.float32(0.5)
    h, w = level_img.shape
    inside = (fc >= -0.5) & (fc <= w - 0.5) & (fr >= -0.5) & (fr <= h - 0.5)
    np.clip(fc, 0, w - 1.001, out=fc)
    np.clip(fr, 0, h - 1.001, out=fr)
    c0, r0 = fc.astype(np.int32), fr.astype(np.int32)
    wc = ((fc - c0) * 256 + 0.5).astype(np.uint32)
    wr = ((fr - r0) * 256 + 0.5).astype(np.uint32)
    img = level_img.ravel()                        # one gather per corner
    i = r0 * np.int32(w) + c0
    top = _lerp(img[i], img[i + 1], wc)
    i += w
    out = _lerp(top, _lerp(img[i], img[i + 1], wc), wr)
    if not inside.all():                           # 2 cm cells of grass, pseudo-random shades
        o = ~inside
        ix = np.floor(fx[o] * 0.5).astype(np.int64)
        iy = np.floor(fy[o] * 0.5).astype(np.int64)
        v = (((ix * 73856093) ^ (iy * 19349663)) % 251).astype(np.float32) / 125.0 - 1.0
        rgb = np.clip(GRASS + 14.0 * v[:, None] + 0.5, 0, 255).astype(np.uint8)
        px = np.zeros((len(rgb), 4), np.uint8)
        px[:, :3] = rgb
        out[o] = px.view(np.uint32)[:, 0]
    return out


def render_photo(scene: Scene, camera: CameraModel, shot: Shot, rays: np.ndarray,
                 level_img: np.ndarray, level: int) -> np.ndarray:
    """The photo (h, w, 3) uint8 that ``shot`` takes of the scene (``rays`` from
    :func:`pixel_rays`, ``level_img`` from :func:`packed_level`)."""
    return render_rays(scene, camera, shot.C, rays @ shot.R.astype(np.float32), level_img, level)


def render_rays(scene: Scene, camera: CameraModel, C: np.ndarray, d: np.ndarray,
                level_img: np.ndarray, level: int) -> np.ndarray:
    """The photo (h, w, 3) uint8 whose pixels (row by row) see along local float32 directions
    ``d`` (h·w, 3) from ``C``: the camera centre (3,) or one origin per pixel (h·w, 3)."""
    ray, t = _surface_hits(scene, C, d)
    col = ortho_colour(scene, level_img, level, *ray.grid(t))
    return np.ascontiguousarray(col.view(np.uint8).reshape(camera.height, camera.width, 4)[..., :3])


def surface_hits(scene: Scene, C: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The local points (n, 3) float32 where the rays ``C + t·d`` (as :func:`render_rays`
    takes them) first meet the surface: what each pixel of a rendered photo shows."""
    _ray, t = _surface_hits(scene, C, d)
    return (np.asarray(C, np.float32) + t[:, None] * d).astype(np.float32)


def _surface_hits(scene: Scene, C: np.ndarray, d: np.ndarray):
    f32 = np.float32
    ray = _Ray(scene, C, d, f32)
    t_top, t_bot, top = ray.band_top()
    # bare soil: one step from the ground plane, t = (rel − H0) / D with rel of the nearest
    # DSM pixel (a few mm of noise: well below a photo pixel); computed for every ray
    gx, gy = ray.grid(-ray.H0 / ray.D)
    a = scene.rel
    near = np.clip(gy + f32(0.5), 0, a.shape[0] - 1).astype(np.int32) * np.int32(a.shape[1]) \
        + np.clip(gx + f32(0.5), 0, a.shape[1] - 1).astype(np.int32)
    t = (a.ravel()[near] - ray.H0) / ray.D
    crop = np.flatnonzero(top > scene.bare_max)
    if crop.size:
        t[crop] = _bracket(ray.subset(crop), t_top[crop], t_bot[crop], RENDER_ITER, 0.0)
    return ray, t


__all__ = ["pixel_rays", "packed_level", "level_for", "intersect", "ortho_colour", "render_photo",
           "render_rays"]
