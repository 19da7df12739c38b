"""The one polygon vocabulary (core/geometry.py) and the ragged-array helpers (core/ragged.py).

Independent checks: areas, centroids and orientation against shapely (when installed), ragged
index arithmetic against plain Python loops, densification against a per-edge loop.
"""
import numpy as np
import pytest
import shapely

from easyidp_toolbox.core import geometry, ragged
from easyidp_toolbox.core.geometry import FlatPolygons


def _star(rng, n, cx=0.0, cy=0.0, r0=3.0, r1=10.0):
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = rng.uniform(r0, r1, n)
    return np.column_stack([cx + rad * np.cos(ang), cy + rad * np.sin(ang)])


def _polygons(seed, offset=(0.0, 0.0)):
    """Two polygons, the first with a hole, as [[exterior, hole], [exterior]] (mixed orientation)."""
    rng = np.random.default_rng(seed)
    ox, oy = offset
    outer = _star(rng, int(rng.integers(5, 14)), ox, oy)
    hole = 0.25 * _star(rng, 4, 0, 0, 3.0, 4.0)[::-1] + [ox, oy]
    other = _star(rng, int(rng.integers(3, 9)), ox + 40, oy, 1.0, 5.0)
    if rng.uniform() < 0.5:
        outer = outer[::-1]
    return [[outer, hole], [other]]


# --- ragged ----------------------------------------------------------------------------------------
def test_offsets_and_ranges_match_loops():
    lens = np.array([3, 0, 2, 5, 1])
    offs = ragged.offsets(lens)
    assert offs.tolist() == [0, 3, 3, 5, 10, 11] and offs.dtype == np.int64
    starts, stops = np.array([4, 0, 7, 7]), np.array([6, 3, 7, 9])
    want = [i for a, b in zip(starts, stops) for i in range(a, b)]
    assert ragged.ranges(starts, stops).tolist() == want
    assert ragged.ranges([], []).tolist() == []
    assert ragged.run_of(offs).tolist() == [i for i, n in enumerate(lens) for _ in range(n)]
    assert ragged.position_in_run(lens).tolist() == [k for n in lens for k in range(n)]


def test_cyclic_next_wraps_each_run_and_skips_empty_ones():
    offs = ragged.offsets([3, 0, 2, 1])
    assert ragged.cyclic_next(offs).tolist() == [1, 2, 0, 4, 3, 5]


# --- areas, centroids, orientation -------------------------------------------------------------------
def test_ring_area_sign_and_degenerate_rings():
    sq = np.array([[0.0, 0], [2, 0], [2, 1], [0, 1]])
    assert geometry.ring_area(sq) == 2.0
    assert geometry.ring_area(sq[::-1]) == -2.0
    assert geometry.ring_area(sq[:2]) == 0.0 and geometry.ring_area(sq[:0]) == 0.0


def test_ring_area_keeps_its_precision_far_from_the_origin():
    sq = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]]) + [500_000.0, 4_000_000.0]
    assert geometry.ring_area(sq) == 1.0
    area, moment = geometry.ring_moments(sq, np.array([0, 4]))
    assert area[0] == 1.0
    assert moment[0] / area[0] == pytest.approx([500_000.5, 4_000_000.5], abs=1e-6)


@pytest.mark.parametrize("seed", range(8))
def test_ring_moments_match_the_one_ring_area(seed):
    rings = [r for p in _polygons(seed) for r in p]
    area, _ = geometry.ring_moments(np.concatenate(rings), ragged.offsets([len(r) for r in rings]))
    assert area == pytest.approx([geometry.ring_area(r) for r in rings], rel=1e-12)
    # empty rings among them: zero area and moment, the others unchanged
    offs = ragged.offsets([len(rings[0]), 0] + [len(r) for r in rings[1:]])
    a2, m2 = geometry.ring_moments(np.concatenate(rings), offs)
    assert a2[1] == 0.0 and (m2[1] == 0).all()
    assert np.delete(a2, 1) == pytest.approx(area, rel=1e-12)


@pytest.mark.parametrize("seed", range(8))
def test_area_centroid_orientation_against_shapely(seed):
    polys = _polygons(seed, offset=(300_000.0, 5_000_000.0))
    ref = shapely.MultiPolygon([(p[0], p[1:]) for p in polys])
    area, cen = geometry.area_centroid(polys)
    assert area == pytest.approx(ref.area, rel=1e-9)
    assert geometry.polygons_area(polys) == pytest.approx(ref.area, rel=1e-9)
    assert cen == pytest.approx([ref.centroid.x, ref.centroid.y], abs=1e-6)
    for p in geometry.orient(polys):
        assert shapely.LinearRing(p[0]).is_ccw
        assert all(not shapely.LinearRing(h).is_ccw for h in p[1:])
        assert (geometry.ring_area(p[0]) > 0) == shapely.LinearRing(p[0]).is_ccw
    # flat polygons of many records: the same, record by record
    recs = [_polygons(s) for s in range(seed, seed + 3)]
    a, c = FlatPolygons.from_lists(recs).areas_centroids()
    for k, rec in enumerate(recs):
        ref = shapely.MultiPolygon([(p[0], p[1:]) for p in rec])
        assert a[k] == pytest.approx(ref.area, rel=1e-9)
        assert c[k] == pytest.approx([ref.centroid.x, ref.centroid.y], abs=1e-9)


def test_area_centroid_of_nothing():
    area, cen = geometry.area_centroid([])
    assert area == 0.0 and np.isnan(cen).all()


def test_flat_polygons_round_trip_take_and_ring_list():
    recs = [_polygons(1), [], _polygons(2)[1:]]
    flat = FlatPolygons.from_lists(recs)
    assert len(flat) == 3
    for k, rec in enumerate(recs):
        back = flat.polygons(k)
        assert len(back) == len(rec)
        for p, q in zip(back, rec):
            assert len(p) == len(q) and all(np.array_equal(a, b) for a, b in zip(p, q))
    sub = flat.take([2, 0])
    assert [len(sub.polygons(i)) for i in range(2)] == [1, 2]
    assert np.array_equal(sub.polygons(1)[0][1], recs[0][0][1])
    assert len(geometry.ring_list(recs[0])) == 3


# --- densification ------------------------------------------------------------------------------------
def _densify_loop(ring, step, closed, max_pieces=None):
    """Per-edge reference: ceil(length / step) equal pieces per edge."""
    ends = np.vstack([ring[1:], ring[:1]]) if closed else ring[1:]
    starts = ring if closed else ring[:-1]
    pts = []
    for a, b in zip(starts, ends):
        n = max(int(np.ceil(np.hypot(*(b - a)) / step)), 1)
        if max_pieces:
            n = min(n, max_pieces)
        pts += [a + (k / n) * (b - a) for k in range(n)]
    if not closed:
        pts.append(ring[-1])
    return np.array(pts)


@pytest.mark.parametrize("closed", [True, False])
@pytest.mark.parametrize("seed", range(5))
def test_densify_matches_a_per_edge_loop(seed, closed):
    ring = _star(np.random.default_rng(seed), 7)
    xy, offs, orig = geometry.densify(ring, np.array([0, len(ring)]), 0.7, closed=closed)
    want = _densify_loop(ring, 0.7, closed)
    assert offs.tolist() == [0, len(want)]
    assert np.allclose(xy, want, rtol=0, atol=1e-12)
    assert np.array_equal(xy[orig], ring)
    assert np.max(np.linalg.norm(np.diff(xy, axis=0), axis=1)) <= 0.7 + 1e-12


def test_densify_per_ring_steps_and_a_cap():
    rings = [_star(np.random.default_rng(s), 5) for s in range(3)]
    offs = ragged.offsets([len(r) for r in rings])
    step = np.array([0.5, np.inf, 2.0])
    xy, new_offs, _ = geometry.densify(np.concatenate(rings), offs, step, max_pieces=3)
    assert np.array_equal(xy[new_offs[1]:new_offs[2]], rings[1])          # inf: unchanged
    for k in (0, 2):
        want = _densify_loop(rings[k], step[k], True, max_pieces=3)
        assert np.allclose(xy[new_offs[k]:new_offs[k + 1]], want, atol=1e-12)


def test_split_edges_interpolates_any_vertex_quantity():
    offs = np.array([0, 3])
    src, dst, t, new = geometry.split_edges(offs, np.array([2, 1, 1]))
    assert src.tolist() == [0, 0, 1, 2] and dst.tolist() == [1, 1, 2, 0]
    assert t.tolist() == [0.0, 0.5, 0.0, 0.0] and new.tolist() == [0, 4]
