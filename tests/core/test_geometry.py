"""Polygon primitives: rasterisation rules, even-odd holes, validity, names."""
import numpy as np
import pytest

from easyidp_toolbox.core import geometry
from easyidp_toolbox.core.errors import ROIError
from easyidp_toolbox.core.naming import safe_name, unique_names
from easyidp_toolbox.core.roi import roi_from_coordinates


def _centre_truth(rings, shape):
    """Brute force: winding number of every pixel centre (independent of the scanline code)."""
    rows, cols = shape
    cy, cx = np.mgrid[0:rows, 0:cols] + 0.5
    count = np.zeros(shape, int)
    for ring in rings:
        for (ax, ay), (bx, by) in zip(ring, np.roll(ring, -1, axis=0)):
            up = (ay <= cy) & (by > cy)
            down = (ay > cy) & (by <= cy)
            cross = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
            count += (up & (cross > 0)).astype(int) - (down & (cross < 0)).astype(int)
    return count % 2 == 1  # even-odd over rings (holes reverse nothing here: parity of windings)


@pytest.mark.parametrize("seed", range(20))
def test_rasterize_matches_brute_force_on_random_polygons(seed):
    rng = np.random.default_rng(seed)
    n = rng.integers(3, 12)
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = rng.uniform(3, 12, n)
    outer = np.column_stack([15 + rad * np.cos(ang), 14 + rad * np.sin(ang)])
    hole = np.column_stack([15 + 1.5 * np.cos(ang[:3]), 14 + 1.5 * np.sin(ang[:3])])
    rings = [outer, hole] if abs(geometry.ring_area(hole)) > 0.5 and \
        geometry.points_in_rings(hole[:, 0], hole[:, 1], [outer]).all() else [outer]
    mask = geometry.rasterize(rings, (30, 32))
    assert np.array_equal(mask, _centre_truth(rings, (30, 32)))


@pytest.mark.parametrize("seed", range(10))
def test_all_touched_is_every_pixel_the_polygon_intersects(seed):
    rng = np.random.default_rng(100 + seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, 7))
    ring = np.column_stack([10 + 6 * np.cos(ang) * rng.uniform(0.5, 1, 7),
                            10 + 6 * np.sin(ang) * rng.uniform(0.5, 1, 7)])
    touched = geometry.rasterize([ring], (20, 20), all_touched=True)
    centre = geometry.rasterize([ring], (20, 20))
    # dense sampling inside each pixel: any sample inside means the pixel is touched
    sub = (np.arange(16) + 0.5) / 16
    yy, xx = np.meshgrid(sub, sub, indexing="ij")
    sampled = np.zeros((20, 20), bool)
    for r in range(20):
        for c in range(20):
            sampled[r, c] = geometry.points_in_rings(c + xx.ravel(), r + yy.ravel(), [ring]).any()
    assert (touched >= sampled).all() and (touched >= centre).all()
    # no pixel is touched that the polygon does not come near
    dist = geometry.distance_to_rings(np.mgrid[0:20, 0:20][1] + 0.5, np.mgrid[0:20, 0:20][0] + 0.5, [ring])
    assert not (touched & ~sampled & (dist > 0.71)).any()


def test_holes_and_multipart():
    outer = np.array([[1, 1], [9, 1], [9, 9], [1, 9]], float)
    hole = np.array([[3, 3], [7, 3], [7, 7], [3, 7]], float)
    far = np.array([[12, 1], [14, 1], [14, 3], [12, 3]], float)
    m = geometry.rasterize([outer, hole, far], (10, 16))
    assert m.sum() == 64 - 16 + 4
    assert not m[5, 5] and m[2, 2] and m[2, 13]
    assert geometry.area([outer, hole, far]) == pytest.approx(64 - 16 + 4)


def test_invalid_and_empty_rois_are_named():
    bowtie = roi_from_coordinates("plot 7", "Polygon", [[[0, 0], [2, 2], [2, 0], [0, 2], [0, 0]]])
    with pytest.raises(ROIError, match="plot 7.*crosses itself"):
        bowtie.validate()
    with pytest.raises(ROIError, match="plot 8.*empty"):
        roi_from_coordinates("plot 8", "Polygon", []).validate()
    with pytest.raises(ROIError, match="plot 9.*no area"):
        roi_from_coordinates("plot 9", "Polygon", [[[0, 0], [1, 1], [2, 2], [0, 0]]]).validate()
    with pytest.raises(ROIError, match="tree 1.*Point"):
        roi_from_coordinates("tree 1", "Point", [1, 2])


def test_valid_polygon_with_hole_passes_validation():
    roi = roi_from_coordinates("p", "Polygon", [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]],
                                                [[2, 2], [4, 2], [4, 4], [2, 4], [2, 2]]])
    assert roi.validate().area == pytest.approx(96)


def test_names_are_safe_and_unique():
    assert safe_name('a/b\\c:d*e?"f<g>h|i') == "a_b_c_d_e_f_g_h_i"
    assert safe_name("CON") == "_CON"
    assert safe_name("  ..  ") == "roi"
    assert unique_names(["A", "a", "a", "b/c", "b_c"]) == ["A", "a_2", "a_3", "b_c", "b_c_2"]


@pytest.mark.parametrize("seed", range(30))
def test_convex_fast_path_agrees_with_the_edge_pairs(seed):
    """[independent] The strictly-convex shortcut of ``self_intersections`` against a brute
    force written here (every pair of non-adjacent edges tested with orientation signs), on
    random convex rings, stars (every turn to one side, winding twice), bow-ties and random
    rings in either orientation."""
    rng = np.random.default_rng(300 + seed)
    n = int(rng.integers(3, 9))
    kind = seed % 4
    if kind == 0:      # convex
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        ring = np.column_stack([np.cos(ang), np.sin(ang)]) * rng.uniform(1, 50)
    elif kind == 1:    # a star polygon {m/2}: turns to one side, winds twice
        m = 5 + 2 * (seed % 3)
        ang = 2 * np.pi * 2 * np.arange(m) / m
        ring = np.column_stack([np.cos(ang), np.sin(ang)])
    elif kind == 2:    # a bow-tie
        ring = np.array([[0, 0], [2, 2], [2, 0], [0, 2]], float) + rng.uniform(-0.3, 0.3, (4, 2))
    else:              # random vertex order
        ring = rng.uniform(0, 10, (n, 2))
    if rng.random() < 0.5:
        ring = ring[::-1]
    ring = ring + rng.uniform(-1e3, 1e3, 2)

    def orient(p, q, r):
        return np.sign((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]))

    k = len(ring)
    crossing = False
    for i in range(k):
        for j in range(i + 1, k):
            if j == i + 1 or (i == 0 and j == k - 1):
                continue
            a, b, c, d = ring[i], ring[(i + 1) % k], ring[j], ring[(j + 1) % k]
            if orient(a, b, c) * orient(a, b, d) <= 0 and orient(c, d, a) * orient(c, d, b) <= 0:
                crossing = True
    assert bool(geometry.self_intersections([ring])) == crossing


def test_row_spans_agree_with_rasterize():
    """[independent] The one-pass spans of many one-ring polygons against the winding-number
    brute force above (convex, concave, off-grid and outside the grid); None only where a row
    crosses the ring more than twice (then rasterize, also checked)."""
    rng = np.random.default_rng(7)
    rings, shapes = [], []
    for k in range(60):
        n = int(rng.integers(3, 9))
        ang = np.sort(rng.uniform(0, 2 * np.pi, n))
        rad = rng.uniform(2, 9, n) if k % 2 else np.full(n, rng.uniform(2, 9))
        rings.append(np.column_stack([8 + rad * np.cos(ang), 7 + rad * np.sin(ang)])
                     + rng.uniform(-6, 6, 2))
        shapes.append((int(rng.integers(1, 20)), int(rng.integers(1, 20))))
    spans = geometry.row_spans(rings, shapes)
    fallback = 0
    for ring, shape, sp in zip(rings, shapes, spans):
        truth = _centre_truth([ring], shape)
        if sp is None:
            fallback += 1
            assert np.array_equal(geometry.rasterize([ring], shape), truth)   # the caller's way
            continue
        c = np.arange(shape[1])
        assert np.array_equal((c >= sp[0][:, None]) & (c < sp[1][:, None]), truth)
    assert 0 < fallback < len(rings)
