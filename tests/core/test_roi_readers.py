"""open_rois on the files users have: real shapefiles and GeoJSONs (../shared/realdata),
GeoPackages (written by GDAL's ogr2ogr from them), LabelMe on a georeferenced raster,
CloudCompare lists, __geo_interface__ objects; every bad input."""
import json
import subprocess

import numpy as np
import pytest
import shapefile

from easyidp_toolbox.core.errors import EasyIDPError, InputError, ROIError
from easyidp_toolbox.core.raster import open_geotiff
from easyidp_toolbox.core.roi import open_rois, rois_from_geo_interface

from easyidp_toolbox.tests.support.synthetic import write_tif


# ---- real files ------------------------------------------------------------------------------
def test_real_pix4d_shapefile_with_prj(realdata):
    rois = open_rois(realdata / "easyidp/pix4d_origin/roi/roi.shp", name_field="id")
    assert rois.crs.to_epsg() == 32654                        # ESRI-flavoured WKT in the .prj
    assert rois.names == ["0", "1", "2"]
    assert [len(r.rings[0]) for r in rois] == [12, 8, 47]      # 13, 9, 48 stored, closing dropped
    x0, y0, x1, y1 = rois[0].bounds                            # SOURCES.md: 368101–368110 E
    assert 368100 < x0 < x1 < 368111 and 3956025 < y0 < y1 < 3956050
    assert rois[0].z is None and rois[0].attributes == {"id": 0}


def test_real_zipped_shapefile(realdata):
    rois = open_rois(realdata / "data-to-science/multi_field.zip")
    assert len(rois) == 4 and rois.crs.to_epsg() == 4326
    lon, lat = rois[0].rings[0].mean(axis=0)
    assert -87.1 < lon < -86.9 and 40.4 < lat < 40.6            # SOURCES.md: 40.47 N, -86.99 W


def test_real_geojson_single_feature_rfc7946(realdata):
    rois = open_rois(realdata / "d2spy/feature_in_dsm.geojson")
    assert len(rois) == 1 and rois.crs.name.startswith("WGS 84")  # no crs member: CRS84
    assert rois.crs.axis_info[0].direction == "east"               # lon, lat order


def test_real_geojson_3d_polygons_keep_z(realdata):
    rois = open_rois(realdata / "data-to-science/zones_inside_test_tif.geojson")
    assert len(rois) == 20
    assert all(r.z is not None and np.all(r.ring_z[0] == 0) for r in rois)
    assert all(len(r.ring_z) == len(r.rings) for r in rois)
    assert all(len(z) == len(ring) for r in rois for z, ring in zip(r.ring_z, r.rings))


def test_real_pix4d_shapefile_matches_its_geojson_twin(tmp_path, realdata):
    """Independent twin: GDAL's ogr2ogr (not our reader, not pyshp) converts the real roi.shp to
    GeoJSON; both read to the same names, CRS and rings, vertex for vertex."""
    src = realdata / "easyidp/pix4d_origin/roi/roi.shp"
    twin = _ogr2ogr(tmp_path / "twin.geojson", src, fmt="GeoJSON")
    doc = json.loads(twin.read_text())
    shp, gj = open_rois(src, name_field="id"), open_rois(twin, name_field="id")
    assert len(doc["features"]) == len(shp) == len(gj) == 3
    assert shp.names == gj.names and gj.crs.to_epsg() == shp.crs.to_epsg() == 32654
    for a, b, feat in zip(shp, gj, doc["features"]):
        np.testing.assert_array_equal(a.rings[0], b.rings[0])
        gdal_ring = np.asarray(feat["geometry"]["coordinates"][0])[:-1, :2]   # closing dropped
        np.testing.assert_allclose(a.rings[0], gdal_ring, rtol=0, atol=1e-9)


# ---- shapefile structure: holes, multipart, Z, encoding ---------------------------------------
def _write_shp(path, shape_type, shapes, records, fields=(("name", "C"),), prj="EPSG:32654",
               encoding="utf-8", cpg=None):
    with shapefile.Writer(str(path), shapeType=shape_type, encoding=encoding) as w:
        for name, typ in fields:
            w.field(name, typ)
        for shp, rec in zip(shapes, records):
            shp(w)
            w.record(*rec)
    if prj:
        from pyproj import CRS
        path.with_suffix(".prj").write_text(CRS.from_user_input(prj).to_wkt("WKT1_ESRI"))
    if cpg:
        path.with_suffix(".cpg").write_text(cpg)
    return path


def test_shapefile_holes_multipart_and_z(tmp_path):
    outer = [[0, 0], [0, 10], [10, 10], [10, 0], [0, 0]]        # clockwise (exterior)
    hole = [[2, 2], [8, 2], [8, 8], [2, 8], [2, 2]]            # counter-clockwise (hole)
    other = [[20, 0], [20, 5], [25, 5], [25, 0], [20, 0]]
    p = _write_shp(tmp_path / "a.shp", shapefile.POLYGONZ, [
        lambda w: w.polyz([[(x, y, 100 + x) for x, y in outer], [(x, y, 1) for x, y in hole],
                           [(x, y, 7) for x, y in other]])], [["plot é"]])
    (roi,) = open_rois(p, name_field="name")
    assert roi.name == "plot é"
    assert len(roi.parts) == 2 and len(roi.parts[0]) == 2      # exterior + hole, then the other
    assert roi.area == pytest.approx(100 - 36 + 25)
    np.testing.assert_array_equal(roi.z[0][0], 100 + roi.parts[0][0][:, 0])
    assert np.all(roi.z[1][0] == 7)


def test_shapefile_encoding_from_cpg(tmp_path):
    p = _write_shp(tmp_path / "b.shp", shapefile.POLYGON,
                   [lambda w: w.poly([[[0, 0], [0, 1], [1, 1], [1, 0], [0, 0]]])], [["Ölfeld"]],
                   encoding="latin-1", cpg="ISO-8859-1")
    assert open_rois(p, name_field="name").names == ["Ölfeld"]



# ---- GeoPackage ------------------------------------------------------------------------------
def _ogr2ogr(dst, src, *args, fmt="GPKG"):
    """GDAL's ogr2ogr (gdal-bin): an independent GeoPackage (or other format) writer."""
    subprocess.run(["ogr2ogr", "-f", fmt, *args, str(dst), str(src)], check=True,
                   capture_output=True)
    return dst


def test_geopackage_written_by_gdal_reads_as_its_source(tmp_path, realdata):
    """Independent writer: GDAL's ogr2ogr copies the real roi.shp, the real 3-D GeoJSON and a
    shapefile with holes, several parts and Z into GeoPackages; each reads as its source."""
    shp = realdata / "easyidp/pix4d_origin/roi/roi.shp"
    gpkg = open_rois(_ogr2ogr(tmp_path / "roi.gpkg", shp), name_field="id")
    ref = open_rois(shp, name_field="id")
    assert gpkg.names == ref.names and gpkg.crs.to_epsg() == ref.crs.to_epsg() == 32654
    for a, b in zip(gpkg, ref):
        np.testing.assert_array_equal(a.rings[0][:, :2], b.rings[0][:, :2])
    zones = realdata / "data-to-science/zones_inside_test_tif.geojson"
    gz, rz = open_rois(_ogr2ogr(tmp_path / "zones.gpkg", zones)), open_rois(zones)
    assert len(gz) == len(rz) == 20 and all(r.z is not None for r in gz)
    for a, b in zip(gz, rz):
        np.testing.assert_array_equal(a.rings[0], b.rings[0])
        np.testing.assert_array_equal(a.ring_z[0], b.ring_z[0])
    outer = [[0, 0], [0, 10], [10, 10], [10, 0], [0, 0]]
    hole = [[2, 2], [8, 2], [8, 8], [2, 8], [2, 2]]
    other = [[20, 0], [20, 5], [25, 5], [25, 0], [20, 0]]
    p = _write_shp(tmp_path / "parts.shp", shapefile.POLYGONZ, [
        lambda w: w.polyz([[(x, y, 100 + x) for x, y in outer], [(x, y, 1) for x, y in hole],
                           [(x, y, 7) for x, y in other]])], [["plot é"]])
    (roi,) = open_rois(_ogr2ogr(tmp_path / "parts.gpkg", p), name_field="name")
    (want,) = open_rois(p, name_field="name")
    assert roi.name == "plot é" and roi.area == pytest.approx(want.area) == pytest.approx(89)
    assert len(roi.parts) == 2 and len(roi.parts[0]) == 2
    np.testing.assert_array_equal(roi.z[0][0], want.z[0][0])


def test_geopackage_blob_big_endian_and_measures():
    """Truth by construction: a blob with a big-endian ISO PolygonZM and an envelope."""
    import struct
    from easyidp_toolbox.core.roi.geopackage import geometry
    ring = [(0.0, 0.0, 5.0, 9.0), (0.0, 2.0, 6.0, 9.0), (2.0, 2.0, 7.0, 9.0), (0.0, 0.0, 5.0, 9.0)]
    wkb = struct.pack(">BII", 0, 3003, 1) + struct.pack(">I", len(ring)) + \
        b"".join(struct.pack(">4d", *v) for v in ring)
    head = b"GP" + bytes([0, 0b0101]) + struct.pack("<i", 4326) + struct.pack("<6d", *[0.0] * 6)
    g = geometry(head + wkb, "test")
    assert g == {"type": "Polygon", "coordinates": [[list(v[:3]) for v in ring]]}
    assert geometry(b"GP" + bytes([0, 0b10001]) + struct.pack("<i", 0), "test") is None
    with pytest.raises(InputError, match="truncated"):
        geometry(head + wkb[:-9], "test")


def test_geopackage_from_our_writer_keeps_names_and_attributes(tmp_path):
    """Consistency only (our writer, our reader): names from a field, other fields kept."""
    from easyidp_toolbox.core.gpkg import GpkgTable, write_geopackage
    sq = lambda x: [np.array([[x, 0], [x, 1], [x + 1, 1], [x + 1, 0.0]])]  # noqa: E731
    path = write_geopackage(str(tmp_path / "plots #1 é?.gpkg"), [GpkgTable(
        "plots", [("plot", "TEXT"), ("yield", "REAL")], [("A1", 1.5), ("A2", 2.5)],
        [[sq(0)], [sq(2), sq(5)]], "EPSG:32654")])
    rois = open_rois(path, name_field="plot")
    assert rois.names == ["A1", "A2"] and rois.crs.to_epsg() == 32654
    assert [r.attributes["yield"] for r in rois] == [1.5, 2.5]
    assert rois[1].area == pytest.approx(2.0)
    assert open_rois(path).names == ["1", "2"]                  # the fid by default


def test_geopackage_names_with_double_quotes_are_quoted_not_sql(tmp_path):
    """Table and field names are SQL identifiers: a ``"`` in them (a user's layer name) is
    doubled inside the quotes, so the name is stored and read back as it is."""
    import sqlite3
    from easyidp_toolbox.core.gpkg import GpkgTable, quote_identifier, write_geopackage
    assert quote_identifier('plots "2024"') == '"plots ""2024"""'
    table, field = 'plots "2024"; DROP TABLE gpkg_contents; --', 'yield "t/ha"'
    path = write_geopackage(str(tmp_path / "quotes.gpkg"), [GpkgTable(
        table, [(field, "REAL")], [(1.5,), (2.5,)],
        [[[np.array([[0, 0], [0, 1], [1, 1.0]])]], [[np.array([[2, 0], [2, 1], [3, 1.0]])]]],
        "EPSG:32654")])
    con = sqlite3.connect(path)
    tables = {r[0] for r in con.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert table in tables and "gpkg_contents" in tables
    assert con.execute("SELECT table_name FROM gpkg_contents").fetchall() == [(table,)]
    con.close()
    rois = open_rois(path, layer=table)
    assert rois.names == ["1", "2"] and [r.attributes[field] for r in rois] == [1.5, 2.5]


def test_geopackage_bad_inputs(tmp_path, realdata):
    import sqlite3
    from easyidp_toolbox.core.gpkg import GpkgTable, write_geopackage
    shp = realdata / "easyidp/pix4d_origin/roi/roi.shp"
    two = _ogr2ogr(tmp_path / "two.gpkg", shp, "-nln", "first")
    _ogr2ogr(two, shp, "-update", "-nln", "second")
    with pytest.raises(InputError, match=r"holds 2 feature layers \(first, second\): say which"):
        open_rois(two)
    assert len(open_rois(two, layer="second")) == len(open_rois(shp))
    with pytest.raises(InputError, match="no feature layer 'third'"):
        open_rois(two, layer="third")
    pts = tmp_path / "pts.geojson"
    pts.write_text('{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": '
                   '{}, "geometry": {"type": "Point", "coordinates": [1, 2]}}]}')
    with pytest.raises(InputError, match="POINT geometries, not polygons"):
        open_rois(_ogr2ogr(tmp_path / "pts.gpkg", pts, "-a_srs", "EPSG:32654"))
    text = tmp_path / "text.gpkg"
    text.write_text("not a database")
    with pytest.raises(InputError, match="text.gpkg"):
        open_rois(text)
    sqlite3.connect(tmp_path / "plain.gpkg").execute("CREATE TABLE t (a)").connection.commit()
    with pytest.raises(InputError, match="is not a GeoPackage"):
        open_rois(tmp_path / "plain.gpkg")
    nocrs = write_geopackage(str(tmp_path / "nocrs.gpkg"), [GpkgTable(
        "p", [], [()], [[[np.array([[0, 0], [0, 1], [1, 1.0]])]]], None)])
    with pytest.raises(InputError, match="its CRS is undefined"):
        open_rois(nocrs)
    assert open_rois(nocrs, source_crs="EPSG:32654").crs.to_epsg() == 32654
    con = sqlite3.connect(nocrs)
    con.execute("UPDATE p SET geom = substr(geom, 1, 30)")
    con.commit()
    con.close()
    with pytest.raises(InputError, match=r"nocrs.gpkg, layer 'p', feature 1: the geometry is truncated"):
        open_rois(nocrs, source_crs="EPSG:32654")

# ---- LabelMe on a georeferenced raster, CloudCompare, geo_interface ---------------------------
def test_labelme_real_file_on_a_raster(tmp_path, realdata):
    lm = realdata / "easyidp/labelme/labelme_demo_img.json"      # 4608 x 3456, one polygon "1"
    tif = write_tif(tmp_path / "ortho.tif", np.zeros((3456, 4608), np.uint8), origin=(1000.0, 2000.0),
                    pixel=0.01, tile=256)
    rois = open_rois(lm, raster=open_geotiff(tif))
    assert rois.names == ["1"] and rois.crs.to_epsg() == 32654
    px = np.array(json.loads(lm.read_text())["shapes"][0]["points"])
    np.testing.assert_allclose(rois[0].rings[0], np.column_stack([1000 + 0.01 * px[:, 0],
                                                                  2000 - 0.01 * px[:, 1]]))


def test_labelme_needs_its_raster(tmp_path, realdata):
    with pytest.raises(InputError, match="give the georeferenced raster"):
        open_rois(realdata / "easyidp/labelme/labelme_demo_img.json")
    small = write_tif(tmp_path / "small.tif", np.zeros((10, 10), np.uint8))
    with pytest.raises(InputError, match="4608 × 3456 image"):
        open_rois(realdata / "easyidp/labelme/labelme_demo_img.json", raster=open_geotiff(small))
    with pytest.raises(InputError, match=r"opened, raster=open_geotiff\("):   # a path: open it
        open_rois(realdata / "easyidp/labelme/labelme_demo_img.json", raster=small)


def test_labelme_raster_as_a_path_from_the_facade(tmp_path):
    """[independent] easyidp_toolbox.core.open_rois takes the LabelMe raster as a path (what the
    README documented): a LabelMe file written here, on a GeoTIFF of 0.05 m pixels from
    (500000, 4000100); the map vertices are the pixel corners through that affine, by hand."""
    import easyidp_toolbox.core as core
    tif = write_tif(tmp_path / "ortho.tif", np.zeros((200, 300), np.uint8),
                    origin=(500000.0, 4000100.0), pixel=0.05)
    points = [[10.0, 20.0], [110.5, 20.0], [110.5, 80.25], [10.0, 80.25]]
    doc = {"version": "5.2.1", "flags": {}, "imagePath": "ortho.tif", "imageData": None,
           "imageHeight": 200, "imageWidth": 300,
           "shapes": [{"label": "plot_7", "points": points, "group_id": None,
                       "shape_type": "polygon", "flags": {}}]}
    lm = tmp_path / "plots.json"
    lm.write_text(json.dumps(doc))
    for raster in (str(tif), tif):                                   # str and PathLike
        rois = core.open_rois(lm, raster=raster)
        assert rois.names == ["plot_7"] and rois.crs.to_epsg() == 32654
        ring = rois[0].rings[0]
        want = np.array([[500000 + 0.05 * c, 4000100 - 0.05 * r] for c, r in points])
        np.testing.assert_allclose(ring[:4] if len(ring) > 4 else ring, want, atol=1e-9)
    with pytest.raises(InputError, match="Raster not found: .*nothing.tif"):
        core.open_rois(lm, raster=tmp_path / "nothing.tif")
    with pytest.raises(InputError, match="opens a path itself"):    # the subpackage's refuses
        open_rois(lm, raster=str(tif))


def test_cloudcompare_point_lists(tmp_path):
    a = tmp_path / "tree_7.txt"
    a.write_text("1.5,2.0,30.1\n4.0,2.0,30.2\n4.0,5.5,30.3\n1.5,2.0,30.1\n")
    b = tmp_path / "labels.txt"
    b.write_text("Point #0, 1, 2, 3\nPoint #1, 5, 2, 3\nPoint #2, 5, 6, 4\n")
    (ra,) = open_rois(a, source_crs="EPSG:32654")
    assert ra.name == "tree_7" and len(ra.rings[0]) == 3 and ra.area == pytest.approx(4.375)
    np.testing.assert_allclose(ra.ring_z[0], [30.1, 30.2, 30.3])
    (rb,) = open_rois(b, source_crs="EPSG:32654")
    np.testing.assert_allclose(rb.rings[0], [[1, 2], [5, 2], [5, 6]])
    with pytest.raises(InputError, match="carry no CRS"):
        open_rois(a)
    bad = tmp_path / "bad.txt"
    bad.write_text("1,2,3\nhello world\n4,5,6\n")
    with pytest.raises(InputError, match="line 2"):
        open_rois(bad, source_crs="EPSG:32654")


@pytest.mark.geopandas
def test_geodataframe_and_shapely(realdata):
    """geopandas and shapely (independent readers) against our shapefile reader."""
    import geopandas as gpd
    from shapely.geometry import Polygon
    gdf = gpd.read_file(realdata / "easyidp/pix4d_origin/roi/roi.shp")
    rois = open_rois(gdf, name_field="id")                      # CRS from gdf.crs
    ref = open_rois(realdata / "easyidp/pix4d_origin/roi/roi.shp", name_field="id")
    assert rois.names == ref.names and rois.crs.equals(ref.crs)
    for a, b in zip(rois, ref):
        np.testing.assert_allclose(a.rings[0], b.rings[0])
    sq = rois_from_geo_interface([Polygon([(0, 0), (1, 0), (1, 1)]), Polygon([(5, 5), (6, 5), (6, 6)])],
                                 crs="EPSG:32654")
    assert sq.names == ["0", "1"] and sq[1].area == pytest.approx(0.5)
    with pytest.raises(InputError, match="CRS is unknown"):
        rois_from_geo_interface(Polygon([(0, 0), (1, 0), (1, 1)]))


# ---- bad input -------------------------------------------------------------------------------
def test_bad_inputs_name_the_file(tmp_path):
    with pytest.raises(InputError, match="not found"):
        open_rois(tmp_path / "missing.shp")
    p = _write_shp(tmp_path / "noprj.shp", shapefile.POLYGON,
                   [lambda w: w.poly([[[0, 0], [0, 1], [1, 1], [0, 0]]])], [["a"]], prj=None)
    with pytest.raises(InputError, match="no .prj file"):
        open_rois(p)
    assert open_rois(p, source_crs="EPSG:32654").crs.to_epsg() == 32654
    pts = _write_shp(tmp_path / "pts.shp", shapefile.POINT, [lambda w: w.point(1, 2)], [["a"]])
    with pytest.raises(InputError, match="Point shapes, not polygons"):
        open_rois(pts)
    trunc = tmp_path / "trunc.shp"
    data = (tmp_path / "noprj.shp").read_bytes()
    for ext in (".shx", ".dbf", ".prj"):
        src = (tmp_path / "noprj").with_suffix(ext)
        if src.exists():
            trunc.with_suffix(ext).write_bytes(src.read_bytes())
    trunc.write_bytes(data[:120])
    with pytest.raises(InputError, match="trunc.shp"):
        open_rois(trunc, source_crs="EPSG:32654")
    empty = tmp_path / "empty.geojson"
    empty.write_text('{"type": "FeatureCollection", "features": []}')
    with pytest.raises(InputError, match="empty"):
        open_rois(empty)
    line = tmp_path / "line.geojson"
    line.write_text('{"type": "Feature", "properties": {}, "geometry": '
                    '{"type": "LineString", "coordinates": [[0, 0], [1, 1]]}}')
    with pytest.raises(ROIError, match="LineString, not a polygon"):
        open_rois(line)
    nogeom = tmp_path / "nogeom.geojson"
    nogeom.write_text('{"type": "FeatureCollection", "features": [{"type": "Feature", '
                      '"properties": {"id": "A1"}, "geometry": null}]}')
    with pytest.raises(InputError, match="has no geometry"):
        open_rois(nogeom)
    with pytest.raises(InputError, match="no field 'plot'"):
        open_rois(nogeom, name_field="plot")
    broken = tmp_path / "broken.geojson"
    broken.write_text('{"type": "FeatureCollection", "features": [')
    with pytest.raises(InputError, match="not valid GeoJSON"):
        open_rois(broken)
    other = tmp_path / "plots.kml"
    other.write_text("<kml/>")
    with pytest.raises(InputError, match="not an ROI format"):
        open_rois(other)
    badprj = _write_shp(tmp_path / "badprj.shp", shapefile.POLYGON,
                        [lambda w: w.poly([[[0, 0], [0, 1], [1, 1], [0, 0]]])], [["a"]], prj=None)
    badprj.with_suffix(".prj").write_text("this is not WKT")
    with pytest.raises(InputError, match="not a CRS"):
        open_rois(badprj)
    assert issubclass(InputError, EasyIDPError)
