"""core.wkb: the WKB the QGIS plugin turns into features, checked by shapely's own reader (an
independent decoder) and against bytes packed by hand."""
import struct

import numpy as np
import pytest
import shapely.wkb

from easyidp_toolbox.core.wkb import flat_multipolygons_wkb, multipolygon_wkb, polygon_wkb

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
HOLE = np.array([[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0]])


def test_polygon_bytes_as_packed_by_hand():
    tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]]
    want = struct.pack("<BII I", 1, 3, 1, 4) + struct.pack("<8d", 0, 0, 1, 0, 0, 2, 0, 0)
    assert polygon_wkb([tri]) == want


@pytest.mark.parametrize("polygons, z, wkt", [
    ([[SQUARE]], False, "MULTIPOLYGON (((0 0, 4 0, 4 4, 0 4, 0 0)))"),
    ([[SQUARE, HOLE], [SQUARE + 10]], False,
     "MULTIPOLYGON (((0 0, 4 0, 4 4, 0 4, 0 0), (1 1, 1 2, 2 2, 2 1, 1 1)), "
     "((10 10, 14 10, 14 14, 10 14, 10 10)))"),
    ([[np.column_stack([SQUARE, [1, 2, 3, 4]])]], True,
     "MULTIPOLYGON Z (((0 0 1, 4 0 2, 4 4 3, 0 4 4, 0 0 1)))"),
    ([], False, "MULTIPOLYGON EMPTY"),
])
def test_multipolygons_read_back_by_shapely(polygons, z, wkt):
    got = shapely.wkb.loads(multipolygon_wkb(polygons, z=z))
    assert got.equals_exact(shapely.from_wkt(wkt), 0) if polygons else got.is_empty
    assert got.has_z == z


def test_short_rings_and_empty_polygons_are_left_out():
    line = SQUARE[:2]
    got = shapely.wkb.loads(multipolygon_wkb([[line], [SQUARE, line]], min_vertices=3))
    assert got.wkt == "MULTIPOLYGON (((0 0, 4 0, 4 4, 0 4, 0 0)))"


def test_closed_rings_are_kept_as_they_are():
    closed = np.vstack([SQUARE, SQUARE[:1]])
    assert multipolygon_wkb([[closed]], close=False) == multipolygon_wkb([[SQUARE]])


def test_photo_pixels_are_written_with_y_down_as_minus_row():
    got = shapely.wkb.loads(multipolygon_wkb([[SQUARE + [0, 1]]], flip_y=True))
    assert got.wkt == "MULTIPOLYGON (((0 -1, 4 -1, 4 -5, 0 -5, 0 -1)))"


def test_many_records_at_once_are_the_bytes_of_each_record():
    """flat_multipolygons_wkb against multipolygon_wkb record by record (the reference written
    one record at a time): holes, several polygons, records without rings, a hole first."""
    from easyidp_toolbox.core.geometry import FlatPolygons
    rng = np.random.default_rng(0)
    records = [[[SQUARE, HOLE], [SQUARE + 10]], [], [[SQUARE * 2]], [[HOLE]],
               [[SQUARE], [SQUARE + 5, HOLE + 5, HOLE + 6]], []]
    records += [[[rng.random((int(rng.integers(3, 40)), 2)) * 1000]] for _ in range(200)]
    flat = FlatPolygons.from_lists(records)
    for flip in (False, True):
        got = flat_multipolygons_wkb(flat, flip_y=flip)
        assert len(got) == len(records)
        for k, polys in enumerate(records):
            assert got[k] == multipolygon_wkb(flat.polygons(k), flip_y=flip), k
    assert shapely.wkb.loads(got[0]).equals_exact(shapely.from_wkt(
        "MULTIPOLYGON (((0 0, 4 0, 4 -4, 0 -4, 0 0), (1 -1, 1 -2, 2 -2, 2 -1, 1 -1)), "
        "((10 -10, 14 -10, 14 -14, 10 -14, 10 -10)))"), 0)
    assert flat_multipolygons_wkb(FlatPolygons.empty()) == []
