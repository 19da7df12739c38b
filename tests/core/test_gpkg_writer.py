"""core.gpkg with encoded multipolygons (how Back-project ROIs writes its GeoPackage of photo
pixels): the file read back by GDAL (OGR), an independent reader."""
import struct

import numpy as np
import pytest

from easyidp_toolbox.core.geometry import FlatPolygons
from easyidp_toolbox.core.gpkg import GpkgTable, encoded_multipolygons, write_geopackage

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
HOLE = np.array([[1.0, 1.0], [1.0, 2.0], [2.0, 2.0], [2.0, 1.0]])
RECORDS = [[[SQUARE, HOLE], [SQUARE + [10.0, 3.0]]], [], [[SQUARE * 0.5 + 100.0]]]


def _wkt(polys, flip_y):
    """The WKT of a record, written here from the coordinates (rings closed, y = −y)."""
    if not polys:
        return "MULTIPOLYGON EMPTY"
    s = -1.0 if flip_y else 1.0

    def ring(r):
        r = np.vstack([r, r[:1]])
        return "(" + ",".join(f"{x:g} {s * y:g}" for x, y in r) + ")"
    return "MULTIPOLYGON (" + ",".join("(" + ",".join(map(ring, p)) + ")" for p in polys) + ")"


@pytest.mark.gdal
@pytest.mark.parametrize("flip_y", [False, True])
def test_encoded_multipolygons_read_back_by_gdal(tmp_path, flip_y):
    """[independent] GDAL reads each record's geometry, its fields (NaN and infinity as NULL,
    numpy scalars as numbers, MEDIUMINT as a 32-bit integer, BOOLEAN as a boolean) and the
    layer's extent; the header envelope of each blob is the record's xy box."""
    from osgeo import ogr
    flat = FlatPolygons.from_lists(RECORDS)
    geoms = encoded_multipolygons(flat, flip_y=flip_y)
    rows = [("a", 1, 0.5, True), ("b", 2, float("nan"), False),
            ("c", np.int64(3), float("inf"), np.bool_(True))]
    path = write_geopackage(str(tmp_path / "pixels.gpkg"), [GpkgTable(
        "pixels", [("roi", "TEXT"), ("rank", "MEDIUMINT"), ("score", "REAL"),
                   ("clipped", "BOOLEAN")], rows, geoms)])
    ds = ogr.Open(path)
    layer = ds.GetLayerByName("pixels")
    defn = layer.GetLayerDefn()
    types = [(defn.GetFieldDefn(i).GetType(), defn.GetFieldDefn(i).GetSubType())
             for i in range(defn.GetFieldCount())]
    assert types == [(ogr.OFTString, ogr.OFSTNone), (ogr.OFTInteger, ogr.OFSTNone),
                     (ogr.OFTReal, ogr.OFSTNone), (ogr.OFTInteger, ogr.OFSTBoolean)]
    got = []
    for f in layer:
        g = f.GetGeometryRef()
        want = ogr.CreateGeometryFromWkt(_wkt(RECORDS[len(got)], flip_y))
        assert g.IsEmpty() == want.IsEmpty() and (g.IsEmpty() or g.Equals(want)), len(got)
        got.append([f.GetField(i) if f.IsFieldSetAndNotNull(i) else None for i in range(4)])
    assert got == [["a", 1, 0.5, 1], ["b", 2, None, 0], ["c", 3, None, 1]]
    xy = np.vstack([r for p in RECORDS[0] + RECORDS[2] for r in p]) * [1.0, -1.0 if flip_y else 1.0]
    assert layer.GetExtent() == pytest.approx((xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(),
                                               xy[:, 1].max()))
    ds = None
    import sqlite3
    con = sqlite3.connect(path)
    blobs = [b for (b,) in con.execute("SELECT geom FROM pixels ORDER BY fid")]
    con.close()
    assert blobs[1][:8] == b"GP" + bytes([0, 0b00010001]) + struct.pack("<i", -1)  # empty, no box
    for blob, rec in ((blobs[0], RECORDS[0]), (blobs[2], RECORDS[2])):
        pts = np.vstack([r for p in rec for r in p]) * [1.0, -1.0 if flip_y else 1.0]
        assert blob[3] == 0b00000011
        assert struct.unpack("<4d", blob[8:40]) == (pts[:, 0].min(), pts[:, 0].max(),
                                                    pts[:, 1].min(), pts[:, 1].max())


def test_rows_and_geometries_must_pair(tmp_path):
    """A table with fewer geometries than rows is refused, and nothing is left behind."""
    geoms = encoded_multipolygons(FlatPolygons.from_lists(RECORDS[:1]))
    with pytest.raises(ValueError, match="1 geometries for 2 rows"):
        write_geopackage(str(tmp_path / "x.gpkg"), [GpkgTable("x", [("a", "TEXT")],
                                                              [("a",), ("b",)], geoms)])
    assert list(tmp_path.iterdir()) == []
