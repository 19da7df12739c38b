"""The ray–DSM intersector against a brute-force reference written here (dense sampling along
each ray, its own bilinear surface): independent of the code under test.

The DSM has thin ridges (one pixel wide), walls (steps), a nodata hole, noise, and rays that
leave the raster. Frames: a Pix4D-like offset frame in the DSM's CRS (exactly linear) and a
Metashape-like geocentric frame (east-north-up at the scene), where the linearisation is
measured.
"""
import numpy as np
import pytest
from pyproj import CRS, Transformer

from easyidp_toolbox.core.errors import EasyIDPError, InputError
from easyidp_toolbox.core.raster import DSM, HIT, LEFT, MISS, NODATA, first_hits
from easyidp_toolbox.core.reconstruction.geodesy import GeocentricFrame, OffsetFrame

from easyidp_toolbox.tests.support.synthetic import write_tif

ORIGIN = (368000.0, 3956000.0)
PIXEL = 0.25
H, W = 220, 300
NODATA_VALUE = -9999.0


def make_dsm(seed=3):
    rng = np.random.default_rng(seed)
    z = 100.0 + rng.normal(0.0, 0.02, (H, W))
    z += 0.01 * np.arange(W)[None, :]                 # a gentle slope
    z[:, 120] += 6.0                                  # thin ridge (one pixel)
    z[60, :] += 3.0                                   # thin ridge along x
    z[150:, 200:230] += 4.0                           # a wall (step up, then down)
    z[100:130, 40:70] = NODATA_VALUE                  # a hole
    return z.astype(np.float32)


@pytest.fixture(scope="module")
def dsm(tmp_path_factory):
    z = make_dsm()
    path = write_tif(str(tmp_path_factory.mktemp("dsm") / "dsm.tif"), z, origin=ORIGIN,
                     pixel=PIXEL, nodata=NODATA_VALUE, tile=32)
    return path, z


def reference_surface(z):
    """Heights at map (x, y): bilinear between pixel centres, flat beyond the outermost
    centres, NaN on nodata cells and outside the raster (written from the DESIGN convention)."""
    a = np.where(z == NODATA_VALUE, np.nan, z).astype(np.float64)
    pad = np.pad(a, 1, mode="edge")

    def height(x, y):
        col = (x - ORIGIN[0]) / PIXEL
        row = (ORIGIN[1] - y) / PIXEL
        inside = (col >= 0) & (col <= W) & (row >= 0) & (row <= H)
        u, v = np.clip(col + 0.5, 0, W + 0.999999), np.clip(row + 0.5, 0, H + 0.999999)
        iu, iv = np.floor(u).astype(int), np.floor(v).astype(int)
        fu, fv = u - iu, v - iv
        h = (pad[iv, iu] * (1 - fu) * (1 - fv) + pad[iv, iu + 1] * fu * (1 - fv)
             + pad[iv + 1, iu] * (1 - fu) * fv + pad[iv + 1, iu + 1] * fu * fv)
        return np.where(inside, h, np.nan), inside
    return height


def brute_force(height, zmax, points_at, n_rays, t_end, step):
    """First sample at or below the surface, or over nodata below zmax, by dense sampling
    (MISS when the ray enters the raster through its side already under the surface).
    ``points_at(i, t)`` gives map points of ray i. Returns (status, t)."""
    status = np.full(n_rays, MISS)
    t_hit = np.full(n_rays, np.nan)
    for i in range(n_rays):
        t = np.arange(0.0, t_end[i], step)
        p = points_at(i, t)
        h, inside = height(p[:, 0], p[:, 1])
        below = inside & (p[:, 2] <= h)
        nod = inside & np.isnan(h) & (p[:, 2] <= zmax)
        k = np.flatnonzero(below | nod)
        first_inside = np.flatnonzero(inside)[:1]
        if k.size and k[0] > 0 and first_inside.size and k[0] == first_inside[0]:
            continue                 # enters the raster through its side, under the surface
        if k.size:
            status[i] = HIT if below[k[0]] else NODATA
            t_hit[i] = t[k[0]]
        else:
            out = np.flatnonzero(inside)
            if out.size and out[-1] < len(t) - 1 and p[out[-1], 2] <= zmax:
                status[i] = LEFT
    return status, t_hit


def random_rays(rng, n, frame_offset):
    """Rays from 5–30 m above the DSM, pointing down at up to 60° (some leave the raster)."""
    x = rng.uniform(ORIGIN[0] - 5, ORIGIN[0] + W * PIXEL + 5, n)
    y = rng.uniform(ORIGIN[1] - H * PIXEL - 5, ORIGIN[1] + 5, n)
    o = np.column_stack([x, y, rng.uniform(105, 130, n)]) - frame_offset
    ang = np.radians(rng.uniform(0, 60, n))
    az = rng.uniform(0, 2 * np.pi, n)
    d = np.column_stack([np.sin(ang) * np.cos(az), np.sin(ang) * np.sin(az), -np.cos(ang)])
    return o, d


def aimed_rays(z, frame_offset):
    """Rays aimed 2 mm above and 2 mm below the crest of the thin ridges, nearly grazing
    (brute-force truth) and rays across the wall."""
    o, d = [], []
    for k in range(12):
        v_row = 10 + 15 * k                             # along the ridge at column 120
        crest = z[v_row, 120]
        x = ORIGIN[0] + 120.5 * PIXEL
        y = ORIGIN[1] - (v_row + 0.5) * PIXEL
        for dz in (0.002, -0.002):
            target = np.array([x, y, crest + dz])
            start = target + np.array([-3.0, 0.3, 1.0])  # shallow: 18° below horizontal
            o.append(start - frame_offset)
            d.append((target - start) / np.linalg.norm(target - start))
    return np.array(o), np.array(d)


def test_offset_frame_matches_brute_force(dsm):
    path, z = dsm
    offset = np.array([ORIGIN[0], ORIGIN[1] - 50.0, 100.0])
    frame = OffsetFrame(CRS.from_epsg(32654), offset)
    rng = np.random.default_rng(7)
    o1, d1 = random_rays(rng, 250, offset)
    o2, d2 = aimed_rays(z, offset)
    o, d = np.vstack([o1, o2]), np.vstack([d1, d2])
    surface = DSM(path).ray_surface()
    hits = first_hits(surface, frame, o, d)
    assert hits.linearisation_error == 0.0            # same CRS: the affine map is exact
    height = reference_surface(z)
    zmax = float(z[z != NODATA_VALUE].max())
    step = 5e-4
    t_end = np.full(len(o), 60.0)
    ref_status, ref_t = brute_force(height, zmax, lambda i, t: o[i] + offset + t[:, None] * d[i],
                                    len(o), t_end, step)
    # every outcome occurs
    assert {HIT, MISS, LEFT, NODATA} <= set(ref_status.tolist())
    assert np.array_equal(hits.status, ref_status), np.flatnonzero(hits.status != ref_status)
    ok = ref_status == HIT
    assert np.abs(hits.distance[ok] - ref_t[ok]).max() <= step + 1e-6
    # the aimed rays: 2 mm above the crest passes it, 2 mm below stops on it
    aimed = hits.distance[len(o1):]
    crest_t = np.linalg.norm([3.0, 0.3, 1.0])
    assert np.all(aimed[1::2] < crest_t + 1e-3)
    assert np.all(aimed[0::2] > crest_t + 0.5)
    # hit points are on the reference surface to 1 mm, and in the DSM's CRS
    h, _ = height(hits.xyz[ok, 0], hits.xyz[ok, 1])
    start = hits.distance[ok] == 0                      # origins under the surface
    assert np.abs(hits.xyz[ok, 2] - h)[~start].max() < 1e-3
    assert np.all(hits.xyz[ok, 2][start] <= h[start])
    assert np.allclose(hits.xyz[ok], o[ok] + offset + hits.distance[ok, None] * d[ok], atol=1e-6)
    assert np.isnan(hits.distance[~ok]).all() and np.isnan(hits.xyz[~ok]).all()


def test_geocentric_frame_is_linearised_within_a_millimetre(dsm):
    """Metashape-like frame: ENU at the scene, DSM in UTM. Truth by dense sampling where every
    sample point is converted exactly with PROJ."""
    path, z = dsm
    to_ecef = Transformer.from_crs(32654, 4978, always_xy=True)
    centre = np.array(to_ecef.transform(ORIGIN[0] + 40, ORIGIN[1] - 30, 100.0))
    frame = GeocentricFrame(CRS.from_epsg(4326), centre)
    rng = np.random.default_rng(11)
    o_map, d_map = random_rays(rng, 60, np.zeros(3))
    # ray origins and directions in the model frame, through two exact points per ray
    o = frame.to_model(o_map, "EPSG:32654")
    p2 = frame.to_model(o_map + 10.0 * d_map, "EPSG:32654")
    d = (p2 - o) / np.linalg.norm(p2 - o, axis=1, keepdims=True)
    surface = DSM(path).ray_surface()
    hits = first_hits(surface, frame, o, d)
    assert 0.0 < hits.linearisation_error < 1e-3
    height = reference_surface(z)
    zmax = float(z[z != NODATA_VALUE].max())
    step = 2e-3
    ref_status, ref_t = brute_force(
        height, zmax, lambda i, t: frame.from_model(o[i] + t[:, None] * d[i], "EPSG:32654"),
        len(o), np.full(len(o), 60.0), step)
    assert np.array_equal(hits.status, ref_status)
    ok = ref_status == HIT
    assert ok.sum() > 30
    assert np.abs(hits.distance[ok] - ref_t[ok]).max() <= step + 1e-3
    exact = frame.from_model(o[ok] + hits.distance[ok, None] * d[ok], "EPSG:32654")
    assert np.abs(hits.xyz[ok] - exact).max() < 1e-3
    h, _ = height(exact[:, 0], exact[:, 1])
    assert np.abs(exact[:, 2] - h).max() < 2e-3      # on the surface (slopes up to 24 m/m)


def test_hits_lie_on_the_surface_across_tile_edges(tmp_path):
    """Rays entering a tile exactly at its edge (tiles of 8 cells: edges everywhere), on rows
    of sharp steps, read cold (tile by tile as the rays need them) and warm: every hit lies
    on the reference surface and both runs agree (independent truth: the surface written here;
    once a ray entering a tile was solved against the wrong cell at its edge, and a thread
    could pass over a tile another thread was reading)."""
    z = make_dsm()
    z[:, ::4] = np.where(z[:, ::4] == NODATA_VALUE, NODATA_VALUE, z[:, ::4] + 0.6)  # crop rows
    path = write_tif(str(tmp_path / "rows.tif"), z, origin=ORIGIN, pixel=PIXEL,
                     nodata=NODATA_VALUE, tile=32)
    offset = np.array([ORIGIN[0], ORIGIN[1] - 50.0, 100.0])
    frame = OffsetFrame(CRS.from_epsg(32654), offset)
    o, d = random_rays(np.random.default_rng(5), 20000, offset)
    surface = DSM(path).ray_surface(tile=8)
    cold = first_hits(surface, frame, o, d)
    warm = first_hits(surface, frame, o, d)
    assert np.array_equal(cold.status, warm.status)
    assert np.allclose(cold.distance, warm.distance, atol=1e-9, equal_nan=True)
    ok = (cold.status == HIT) & (cold.distance > 0)
    assert ok.sum() > 5000
    h, _ = reference_surface(z)(cold.xyz[ok, 0], cold.xyz[ok, 1])
    assert np.abs(cold.xyz[ok, 2] - h).max() < 1e-3


def test_a_cancelled_read_leaves_the_surface_usable(tmp_path):
    """Cancelled in the middle of reading tiles, then run again on the same surface: the same
    hits as on a fresh surface (a partial read must not leave tiles marked as read whose
    storage the next read reuses)."""
    from easyidp_toolbox.core.errors import Cancelled
    rng = np.random.default_rng(2)
    z = (100.0 + np.cumsum(rng.normal(0, 0.05, (1200, 300)), axis=0)).astype(np.float32)
    path = write_tif(str(tmp_path / "tall.tif"), z, origin=ORIGIN, pixel=PIXEL, tile=32)
    offset = np.array([ORIGIN[0], ORIGIN[1] - 150.0, 100.0])
    frame = OffsetFrame(CRS.from_epsg(32654), offset)
    n = 4000
    o = np.column_stack([rng.uniform(0, 300 * PIXEL, n) + ORIGIN[0],
                         ORIGIN[1] - rng.uniform(0, 1200 * PIXEL, n),
                         np.full(n, float(z.max()) + 20.0)]) - offset
    d = np.column_stack([rng.normal(0, 0.2, n), rng.normal(0, 0.2, n), -np.ones(n)])
    fresh = first_hits(DSM(path).ray_surface(tile=8), frame, o, d)
    calls = []
    first_hits(DSM(path).ray_surface(tile=8), frame, o, d, is_cancelled=lambda: calls.append(1))
    for stop in range(1, len(calls), max(1, len(calls) // 6)):   # cancel at six points
        surface = DSM(path).ray_surface(tile=8)
        checks = iter(range(len(calls)))
        with pytest.raises(Cancelled):
            first_hits(surface, frame, o, d, is_cancelled=lambda: next(checks) >= stop)
        again = first_hits(surface, frame, o, d)
        assert np.array_equal(again.status, fresh.status), stop
        assert np.allclose(again.distance, fresh.distance, atol=1e-9, equal_nan=True), stop

def test_reads_only_the_tiles_along_the_rays(dsm):
    path, _ = dsm
    offset = np.array([ORIGIN[0], ORIGIN[1] - 50.0, 100.0])
    frame = OffsetFrame(CRS.from_epsg(32654), offset)
    surface = DSM(path).ray_surface(tile=32)
    o = np.array([[20.0, 20.0, 20.0]])
    hits = first_hits(surface, frame, o, np.array([[0.0, 0.0, -1.0]]))
    assert hits.status[0] == HIT
    assert surface.tiles_read <= 2 < surface.ntu * surface.ntv


def test_max_distance_and_upward_rays(dsm):
    path, _ = dsm
    offset = np.array([ORIGIN[0], ORIGIN[1] - 50.0, 100.0])
    frame = OffsetFrame(CRS.from_epsg(32654), offset)
    surface = DSM(path).ray_surface()
    o = np.array([20.0, 20.0, 20.0])
    d = np.array([[0, 0, -1.0], [0, 0, -1.0], [0, 0, 1.0], [1.0, 0, 0]])
    hits = first_hits(surface, frame, o, d, max_distance=np.array([5.0, 50.0, 50.0, 500.0]))
    assert hits.status.tolist() == [MISS, HIT, MISS, MISS]
    assert hits.distance[1] == pytest.approx(20.0 - (hits.xyz[1, 2] - 100.0), abs=1e-9)
    # origin under the surface: the hit is the origin
    below = first_hits(surface, frame, np.array([20.0, 20.0, -5.0]), np.array([[1.0, 0, 0]]))
    assert below.status[0] == HIT and below.distance[0] == 0.0


def test_bad_input(dsm, tmp_path):
    path, z = dsm
    frame = OffsetFrame(CRS.from_epsg(32654), np.zeros(3))
    surface = DSM(path).ray_surface()
    with pytest.raises(EasyIDPError, match="zero vector"):
        first_hits(surface, frame, np.zeros(3), np.zeros((1, 3)))
    with pytest.raises(EasyIDPError, match=r"\(n, 3\)"):
        first_hits(surface, frame, np.zeros(3), np.zeros((2, 2)))
    rgb = write_tif(str(tmp_path / "rgb.tif"), np.zeros((8, 8, 3), np.uint8))
    with pytest.raises(InputError, match="exactly one"):
        DSM(rgb)
    # a DSM in a CRS the frame cannot reach
    local = OffsetFrame(None, np.zeros(3))
    with pytest.raises(EasyIDPError, match="CRS is unknown"):
        first_hits(surface, local, np.zeros(3), np.array([[0, 0, -1.0]]))
