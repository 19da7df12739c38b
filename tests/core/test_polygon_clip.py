"""Exact polygon clipping to a convex region (core/projection/clip.py).

Independent check: areas against a brute-force point count (even-odd point-in-polygon of a
dense random sample), and against shapes whose clipped area is known by construction.
"""
import numpy as np
import pytest

from easyidp_toolbox.core.geometry import (area_centroid, orient, points_in_rings, polygons_area,
                                           ring_area, self_intersections)
from easyidp_toolbox.core.projection.clip import clip_convex, rectangle

FRAME = rectangle(10.0, 8.0)


def _brute(rings, n=200_000, seed=1):
    """Area of (even-odd rings) ∩ [0, 10] × [0, 8] by counting random points."""
    p = np.random.default_rng(seed).uniform([-1, -1], [11, 9], (n, 2))
    inside = points_in_rings(p[:, 0], p[:, 1], rings)
    inside &= (p[:, 0] >= 0) & (p[:, 0] <= 10) & (p[:, 1] >= 0) & (p[:, 1] <= 8)
    return inside.mean() * 12 * 10


def _in_frame(polys):
    for p in polys:
        for r in p:
            assert r[:, 0].min() >= -1e-9 and r[:, 0].max() <= 10 + 1e-9
            assert r[:, 1].min() >= -1e-9 and r[:, 1].max() <= 8 + 1e-9


def _valid(polys):
    """Every output ring is simple, exteriors positive, holes negative."""
    for p in polys:
        assert ring_area(p[0]) > 0
        for h in p[1:]:
            assert ring_area(h) < 0
        for r in p:
            assert not self_intersections([r])


def test_known_shapes():
    # a square covering the left half
    sq = np.array([[-5, -5], [5, -5], [5, 15], [-5, 15.]])
    out = clip_convex(orient([[sq]]), FRAME)
    assert polygons_area(out) == pytest.approx(40.0)
    # a U whose base is outside: two separate legs, not one polygon with a bridge
    U = np.array([[2, 12], [8, 12], [8, 5], [6, 5], [6, 10], [4, 10], [4, 5], [2, 5.]])
    out = clip_convex(orient([[U]]), FRAME)
    assert len(out) == 2 and polygons_area(out) == pytest.approx(2 * 2 * 3)
    _valid(out)
    # the frame inside a big polygon with a hole inside the frame: frame minus hole
    big = np.array([[-50, -50], [50, -50], [50, 50], [-50, 50.]])
    hole = np.array([[3, 3], [3, 6], [6, 6], [6, 3.]])
    out = clip_convex(orient([[big, hole]]), FRAME)
    assert len(out) == 1 and len(out[0]) == 2 and polygons_area(out) == pytest.approx(80 - 9)
    # a hole crossing the border becomes a notch of the exterior
    hole = np.array([[-3, 3], [-3, 6], [6, 6], [6, 3.]])
    out = clip_convex(orient([[big, hole]]), FRAME)
    assert len(out) == 1 and len(out[0]) == 1 and polygons_area(out) == pytest.approx(80 - 18)
    _valid(out)
    # wholly outside, and a polygon around the frame with a hole around the frame: nothing
    assert clip_convex(orient([[sq + 100]]), FRAME) == []
    ring_hole = np.array([[-10, -10], [-10, 20], [20, 20], [20, -10.]])
    assert clip_convex(orient([[big, ring_hole]]), FRAME) == []
    # area centroid of the left half
    a, c = area_centroid(clip_convex(orient([[sq]]), FRAME))
    assert a == pytest.approx(40) and np.allclose(c, [2.5, 4.0])


def _random_star(rng, centre_range=(-4, 14)):
    while True:
        k = rng.integers(3, 14)
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        rad = rng.uniform(0.5, 9, k)
        c = rng.uniform(*centre_range, 2)
        ring = c + np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
        if not self_intersections([ring]):
            return ring


def test_random_polygons_against_brute_force():
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(120):
        ring = _random_star(rng)
        out = clip_convex(orient([[ring]]), FRAME)
        _in_frame(out)
        _valid(out)
        worst = max(worst, abs(polygons_area(out) - _brute([ring])))
    assert worst < 0.6          # the brute-force count's own noise at 200,000 points


def test_holes_and_multipart_against_brute_force():
    rng = np.random.default_rng(3)
    tried = 0
    for _ in range(40):
        outer = np.array([[-2, -1], [7, -3], [12, 4], [6, 10], [-1, 7.]]) + rng.uniform(-2, 2, 2)
        hole = 0.35 * (outer - outer.mean(0)) + outer.mean(0) + rng.uniform(-2, 2, 2)
        other = _random_star(rng, (8, 16))
        if self_intersections([outer, hole]) or self_intersections([outer, other]) or \
                self_intersections([hole, other]) or points_in_rings(other[:1, 0], other[:1, 1], [outer])[0] \
                or points_in_rings(outer[:1, 0], outer[:1, 1], [other])[0]:
            continue
        tried += 1
        out = clip_convex(orient([[outer, hole], [other]]), FRAME)
        _in_frame(out)
        rings = [r for p in out for r in p]
        assert polygons_area(out) == pytest.approx(_brute([outer, hole, other]), abs=0.6)
        # even-odd membership of the output equals the input's, inside the frame
        p = np.random.default_rng(5).uniform([0, 0], [10, 8], (4000, 2))
        a = points_in_rings(p[:, 0], p[:, 1], rings) if rings else np.zeros(len(p), bool)
        b = points_in_rings(p[:, 0], p[:, 1], [outer, hole, other])
        assert (a == b).mean() > 0.999
    assert tried >= 10


def test_vectorised_convex_clip_equals_the_general_one():
    """Many convex rings clipped at once (Sutherland–Hodgman, exact for convex rings) against
    the Weiler–Atherton clipper, ring by ring; and the convexity test against random shapes."""
    from easyidp_toolbox.core.projection.clip import clip_convex_rings_to_frames, convex_rings
    rng = np.random.default_rng(11)
    rings, sizes = [], []
    for _ in range(300):
        k = rng.integers(3, 9)
        ang = np.sort(rng.uniform(0, 2 * np.pi, k))
        ring = rng.uniform(-3, 13, 2) + rng.uniform(1, 6) * np.column_stack([np.cos(ang), np.sin(ang)])
        if rng.uniform() < 0.5:
            ring = ring[::-1]
        rings.append(ring)
        sizes.append(rng.choice([[10.0, 8.0], [6.0, 12.0]]))
    offsets = np.concatenate([[0], np.cumsum([len(r) for r in rings])])
    assert convex_rings(np.concatenate(rings), offsets).all()
    sizes = np.array(sizes)
    xy, off = clip_convex_rings_to_frames(np.concatenate(rings), offsets, sizes[:, 0], sizes[:, 1])
    for i, ring in enumerate(rings):
        out = xy[off[i]:off[i + 1]]
        ref = clip_convex(orient([[ring]]), rectangle(*sizes[i]))
        a = abs(ring_area(out)) if len(out) >= 3 else 0.0
        assert a == pytest.approx(polygons_area(ref), abs=1e-9)
        if len(out):
            assert out.min() >= 0 and (out <= sizes[i]).all()
    star = np.array([[0, 0], [4, 0], [1, 1], [2, 4], [0, 2.]])
    tri = np.array([[0, 0], [4, 0], [0, 3.]])
    both = np.concatenate([star, tri])
    assert convex_rings(both, np.array([0, 5, 8])).tolist() == [False, True]


def test_a_ring_folded_on_the_frame_edge_is_not_turned_into_the_frame():
    """A ring that crosses itself by a hair where it crosses the frame's edge (as a DSM-height
    ROI seen obliquely does; demo seed 7, plant A6_P2 in DJI_0016, came back as the whole
    photo). Independent check: the brute-force point count; by construction the clipped area
    never exceeds the ring's own."""
    th = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    circle = np.column_stack([9.5 + 2 * np.cos(th), 4 + 2 * np.sin(th)])
    folded = 0
    for i in range(64):
        ring = circle.copy()
        ring[[i, (i + 1) % 64]] = ring[[(i + 1) % 64, i]]      # two neighbours swapped: a fold
        out = clip_convex(orient([[ring]]), FRAME)
        _in_frame(out)
        assert polygons_area(out) <= abs(ring_area(ring)) + 1e-9
        assert polygons_area(out) == pytest.approx(_brute([ring]), abs=0.2)
        folded += abs(ring[i, 0] - 10) < 0.5
    assert folded >= 2          # some folds sit on the edge x = 10


@pytest.mark.parametrize("corner", [0, 1, 2, 3])
def test_a_ring_inside_with_a_vertex_on_a_corner_is_itself(corner):
    """By construction: a triangle inside the frame with one vertex on a corner of it comes back
    as itself, and a hole of that shape in a polygon around the frame is cut out of the frame
    (the frame's corner probe lay inside the triangle: the whole frame came back as a second
    part)."""
    c = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 8.0], [0.0, 8.0]])[corner]
    inward = np.array([5.0, 4.0]) - c
    side = np.array([-inward[1], inward[0]])
    tri = np.array([c, c + 0.6 * inward + 0.1 * side, c + 0.4 * inward - 0.3 * side])
    got = clip_convex(orient([[tri]]), FRAME)
    assert len(got) == 1 and len(got[0]) == 1
    assert polygons_area(got) == pytest.approx(abs(ring_area(tri)), rel=1e-12)
    around = np.array([[-5.0, -5.0], [15.0, -5.0], [15.0, 13.0], [-5.0, 13.0]])
    got = clip_convex(orient([[around, tri]]), FRAME)
    _valid(got)
    assert polygons_area(got) == pytest.approx(80.0 - abs(ring_area(tri)), rel=1e-12)
