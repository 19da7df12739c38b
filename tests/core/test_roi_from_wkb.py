"""ROIs from WKB in bulk (core.roi.rois_from_wkb), the path the QGIS tools read layers by."""
import struct

import numpy as np
import pytest
import shapely
from shapely.geometry import MultiPolygon, Polygon

from easyidp_toolbox.core.errors import ROIError
from easyidp_toolbox.core.roi import roi_from_coordinates, rois_from_wkb


def _messy(rng, k):
    """A polygon (closed rings, as GIS store them) with repeated vertices, maybe a hole."""
    t = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 12)))
    cx, cy = rng.uniform(3.6e5, 3.7e5), rng.uniform(3.9e6, 4.0e6)
    shell = np.column_stack([cx + 5 * np.cos(t), cy + 5 * np.sin(t)])
    if k % 3 == 0:
        shell = np.repeat(shell, rng.integers(1, 3, len(shell)), axis=0)   # duplicates
    hole = np.array([[cx - 1, cy - 1], [cx + 1, cy - 1], [cx, cy + 1]])
    return [shell] + ([hole] if k % 4 == 0 else [])


def test_same_rois_as_from_coordinates():
    """[independent] WKB written by shapely (GEOS), 2-D, Z, big-endian, multipolygons, holes,
    duplicate vertices: every ROI equals what roi_from_coordinates makes of the same rings
    (the reader the plugin used before), vertex for vertex, Z included."""
    rng = np.random.default_rng(5)
    names, blobs, coords = [], [], []
    for k in range(60):
        polys = [_messy(rng, k + j) for j in range(1 + (k % 5 == 0))]
        z = k % 2 == 1
        if z:
            polys = [[np.column_stack([r, rng.normal(95, 1, len(r))]) for r in p] for p in polys]
        shp = [Polygon(p[0], p[1:]) for p in polys]
        geom = shp[0] if len(shp) == 1 else MultiPolygon(shp)
        blobs.append(shapely.to_wkb(geom, byte_order=0 if k % 7 == 0 else 1,
                                    output_dimension=3 if z else 2))
        names.append(f"p{k}")
        closed = [[list(g.exterior.coords)] + [list(h.coords) for h in g.interiors] for g in shp]
        coords.append(closed)
    got = rois_from_wkb(names, blobs, "EPSG:32654")
    assert got.crs.to_epsg() == 32654 and got.names == names
    for roi, c in zip(got, coords):
        want = roi_from_coordinates(roi.name, "MultiPolygon", c)
        assert len(roi.parts) == len(want.parts)
        for p, q in zip(roi.parts, want.parts):
            assert [r.tolist() for r in p] == [r.tolist() for r in q]
        assert (roi.z is None) == (want.z is None)
        if want.z is not None:
            assert [[r.tolist() for r in p] for p in roi.z] == [[r.tolist() for r in p]
                                                               for p in want.z]


def test_m_dropped_empty_and_null():
    """[independent] Hand-written WKB: a PolygonM (ISO code 2003) keeps x, y only; an empty
    polygon and a null geometry give ROIs without parts, which validation names."""
    ring = [(0, 0, 7), (4, 0, 7), (4, 3, 7), (0, 0, 7)]
    m = struct.pack("<BII", 1, 2003, 1) + struct.pack("<I", 4) + b"".join(
        struct.pack("<3d", *v) for v in ring)
    empty = struct.pack("<BII", 1, 3, 0)
    got = rois_from_wkb(["m", "empty", "null"], [m, empty, None])
    assert got[0].parts[0][0].tolist() == [[0, 0], [4, 0], [4, 3]] and got[0].z is None
    assert got[1].parts == [] and got[2].parts == []
    with pytest.raises(ROIError, match="'empty' has an empty geometry"):
        got[1].validate()


def test_not_a_polygon_or_truncated():
    """[independent] A point and a truncated polygon are refused with the ROI's name."""
    point = struct.pack("<BI2d", 1, 1, 0.0, 0.0)
    with pytest.raises(ROIError, match="'pt' is a geometry of WKB type 1"):
        rois_from_wkb(["pt"], [point])
    cut = struct.pack("<BII", 1, 3, 1) + struct.pack("<I", 4) + struct.pack("<3d", 0, 0, 1)
    with pytest.raises(ROIError, match="'cut': its geometry"):
        rois_from_wkb(["cut"], [cut])


def test_bulk_validation_matches_ring_by_ring():
    """[independent] Validating a set checks convex one-ring ROIs all at once: squares,
    triangles and regular polygons pass; a star (turns one way, twice round), a bow-tie, a
    ring on one line and a ring with NaN are still refused, each by name, as ROI.validate
    refuses them on its own."""
    from easyidp_toolbox.core.geometry import convex_simple_rings
    from easyidp_toolbox.core.roi import ROI, ROISet
    t5 = np.arange(5) * 2 * np.pi / 5
    good = [np.array([[0, 0], [2, 0], [2, 1], [0, 1.0]]), np.array([[0, 0], [1, 0], [0, 1.0]]),
            np.column_stack([np.cos(t5), np.sin(t5)])]
    bad = {"star": np.column_stack([np.cos(2 * t5), np.sin(2 * t5)]),
           "bowtie": np.array([[0, 0], [1, 1], [1, 0], [0, 1.0]]),
           "line": np.array([[0, 0], [1, 1], [2, 2.0]]),
           "nan": np.array([[0, 0], [1, 0], [np.nan, 1.0]])}
    rings = good + list(bad.values())
    offs = np.cumsum([0] + [len(r) for r in rings])
    assert convex_simple_rings(np.concatenate(rings), offs).tolist() == [True] * 3 + [False] * 4
    ROISet([ROI(f"g{k}", [[r + 1e5]]) for k, r in enumerate(good)]).validate()
    for name, ring in bad.items():
        with pytest.raises(ROIError, match=f"ROI '{name}'"):
            ROISet([ROI("g", [[good[0]]]), ROI(name, [[ring]])]).validate()


def test_wkb_with_height_keeps_every_vertex_and_sets_z():
    """[independent] Polygons and multipolygons written by shapely (2-D, Z, big-endian, with
    holes and a repeated vertex) come back, read by shapely, as MultiPolygonZ with the same
    vertices (closing and repeated ones kept) and Z = the height; null and empty give an empty
    MultiPolygonZ, NaN stays NaN."""
    from easyidp_toolbox.core.roi import wkb_with_height
    sq = [(0, 0), (4, 0), (4, 0), (4, 3), (0, 3), (0, 0)]
    hole = [(1, 1), (2, 1), (2, 2), (1, 1)]
    geoms = [Polygon(sq), MultiPolygon([Polygon(sq, [hole]), Polygon([(9, 9), (10, 9), (9, 10)])]),
             Polygon([(x, y, 7.5) for x, y in sq])]
    blobs = [shapely.to_wkb(geoms[0]), shapely.to_wkb(geoms[1], byte_order=0),
             shapely.to_wkb(geoms[2], output_dimension=3), None, shapely.to_wkb(Polygon())]
    got = [_read_multipolygon_z(b) for b in wkb_with_height(blobs, [1.0, 2.0, np.nan, 3.0, 4.0])]
    for g, src, h in zip(got, geoms, [1.0, 2.0, np.nan]):
        parts = list(src.geoms) if src.geom_type == "MultiPolygon" else [src]
        assert len(g) == len(parts)
        for a, b in zip(g, parts):
            for ca, rb in zip(a, [b.exterior, *b.interiors]):
                assert ca[:, :2].tolist() == np.array(rb.coords)[:, :2].tolist()
                np.testing.assert_array_equal(ca[:, 2], np.full(len(ca), h))
    assert got[3] == [] and got[4] == []


def _read_multipolygon_z(b: bytes) -> list:
    """A second reader, for ISO little-endian MultiPolygonZ (1006) only (older GEOS reads ISO
    Z codes as 2-D)."""
    assert struct.unpack_from("<BI", b, 0) == (1, 1006)
    (n,), pos, out = struct.unpack_from("<I", b, 5), 9, []
    for _ in range(n):
        assert struct.unpack_from("<BI", b, pos) == (1, 1003)
        (nr,), pos, rings = struct.unpack_from("<I", b, pos + 5), pos + 9, []
        for _ in range(nr):
            (nv,) = struct.unpack_from("<I", b, pos)
            rings.append(np.frombuffer(b, "<f8", 3 * nv, pos + 4).reshape(nv, 3))
            pos += 4 + 24 * nv
        out.append(rings)
    assert pos == len(b)
    return out


@pytest.mark.parametrize("big_endian_one", [False, True])
def test_one_ring_plots_in_one_pass(big_endian_one):
    """[independent] One-ring plots (what the one-pass reader takes: Polygon or MultiPolygon of
    one polygon, 2-D or Z in ISO and extended codes, repeated vertices, a null among them),
    written by shapely, give what roi_from_coordinates gives; with one big-endian geometry
    (read geometry by geometry instead) the same. wkb_with_height keeps every vertex."""
    from easyidp_toolbox.core.roi import wkb_with_height
    rng = np.random.default_rng(8)
    names, blobs, coords = [], [], []
    for k in range(40):
        ring = _messy(rng, 3 * k)[0]
        z = k % 3 == 1
        if z:
            ring = np.column_stack([ring, rng.normal(95, 1, len(ring))])
        poly = Polygon(ring)
        geom = MultiPolygon([poly]) if k % 2 else poly
        blobs.append(None if k == 5 else shapely.to_wkb(
            geom, output_dimension=3 if z else 2, flavor="iso" if k % 4 == 1 else "extended",
            byte_order=0 if big_endian_one and k == 7 else 1))
        names.append(f"p{k}")
        coords.append([] if k == 5 else [[list(poly.exterior.coords)]])
    got = rois_from_wkb(names, blobs)
    for roi, c in zip(got, coords):
        want = roi_from_coordinates(roi.name, "MultiPolygon", c)
        assert [[r.tolist() for r in p] for p in roi.parts] == \
            [[r.tolist() for r in p] for p in want.parts]
        assert (roi.z is None) == (want.z is None)
        if want.z is not None:
            assert roi.z[0][0].tolist() == want.z[0][0].tolist()
    for k, w in enumerate(wkb_with_height(blobs, np.arange(40.0))):
        g = _read_multipolygon_z(w)
        if k == 5:
            assert g == []
            continue
        src = np.array(coords[k][0][0])
        assert g[0][0][:, :2].tolist() == src[:, :2].tolist()
        assert (g[0][0][:, 2] == k).all()
