"""Point-cloud reading and writing: real LAS/LAZ files, PLY round trips, precision, bad input."""
import shutil

import laspy
import numpy as np
import pytest
from plyfile import PlyData, PlyElement
from pyproj import CRS

from easyidp_toolbox.core import InputError, PointCloud, read_point_cloud, write_point_cloud

REAL = ["autzen_geo_proj.las", "autzen_trim.laz", "simple.las", "simple.laz"]


def _laspy_truth(path):
    las = laspy.read(str(path))
    return las, np.column_stack([np.asarray(las.x), np.asarray(las.y), np.asarray(las.z)])


@pytest.mark.parametrize("name", REAL)
def test_real_las_read_matches_laspy(realdata, name):
    path = realdata / "laspy" / name
    cloud = read_point_cloud(path)
    las, xyz = _laspy_truth(path)
    assert len(cloud) == las.header.point_count
    np.testing.assert_array_equal(cloud.xyz, xyz)
    assert cloud.xyz.dtype == np.float64
    for dim in las.point_format.dimension_names:
        if dim not in ("X", "Y", "Z"):
            np.testing.assert_array_equal(cloud.attribute(dim), np.asarray(las[dim]), err_msg=dim)
    assert cloud.fmt == name[-3:]


def test_real_crs_from_geotiff_keys_and_wkt(realdata):
    geo = read_point_cloud(realdata / "laspy" / "autzen_geo_proj.las")
    assert geo.crs.to_epsg() == 2994  # GeoTIFF keys only
    trim = read_point_cloud(realdata / "laspy" / "autzen_trim.laz")
    assert "Lambert_Conformal_Conic" in trim.crs.to_wkt()  # WKT VLR
    assert trim.crs.axis_info[0].unit_name in ("foot", "US survey foot")
    assert read_point_cloud(realdata / "laspy" / "simple.las").crs is None
    given = read_point_cloud(realdata / "laspy" / "simple.las", source_crs=2994)
    assert given.crs.to_epsg() == 2994


@pytest.mark.parametrize("name", REAL)
@pytest.mark.parametrize("out", ["las", "laz"])
def test_real_subset_round_trip_is_bit_exact(realdata, tmp_path, name, out):
    src = realdata / "laspy" / name
    cloud = read_point_cloud(src)
    idx = np.flatnonzero(np.arange(len(cloud)) % 3 == 1)
    target = write_point_cloud(cloud, tmp_path / f"sub.{out}", index=idx)
    back = read_point_cloud(target)
    las, xyz = _laspy_truth(src)
    np.testing.assert_array_equal(back.xyz, xyz[idx])
    for dim in las.point_format.dimension_names:
        np.testing.assert_array_equal(np.asarray(laspy.read(str(target))[dim]),
                                      np.asarray(las[dim])[idx], err_msg=dim)
    assert back.header.point_format.id == las.header.point_format.id
    assert str(back.header.version) == str(las.header.version)
    np.testing.assert_array_equal(back.header.scales, las.header.scales)
    np.testing.assert_array_equal(back.header.offsets, las.header.offsets)
    assert back.header.point_count == len(idx)
    np.testing.assert_allclose(back.header.mins, xyz[idx].min(axis=0))
    assert (cloud.crs is None and back.crs is None) or back.crs == cloud.crs
    assert back.header.are_points_compressed == (out == "laz")
    assert [p.name for p in tmp_path.iterdir()] == [f"sub.{out}"]  # no temp file left


def test_crs_given_for_las_without_crs_is_written(realdata, tmp_path):
    cloud = read_point_cloud(realdata / "laspy" / "simple.las", source_crs="EPSG:2994")
    back = read_point_cloud(write_point_cloud(cloud, tmp_path / "with_crs.las"))
    assert back.crs.to_epsg() == 2994
    custom = CRS.from_proj4("+proj=tmerc +lat_0=0 +lon_0=139.5 +k=1 +x_0=0 +y_0=0 +ellps=GRS80 +units=m")
    cloud = read_point_cloud(realdata / "laspy" / "simple.laz", source_crs=custom)
    back = read_point_cloud(write_point_cloud(cloud, tmp_path / "custom.laz"))
    assert back.crs is not None and back.crs.equals(custom)


def test_extra_bytes_and_16bit_colour_kept(tmp_path):
    header = laspy.LasHeader(version="1.4", point_format=7)
    header.add_extra_dims([laspy.ExtraBytesParams("height_above", np.float32),
                           laspy.ExtraBytesParams("normal", "3f8")])
    header.scales = [0.001, 0.001, 0.001]
    header.offsets = [500000.0, 4000000.0, 0.0]
    las = laspy.LasData(header)
    rng = np.random.default_rng(1)
    n = 500
    las.x = 500000 + rng.uniform(0, 50, n)
    las.y = 4000000 + rng.uniform(0, 50, n)
    las.z = rng.uniform(0, 3, n)
    las.red = rng.integers(0, 65536, n, dtype=np.uint16)
    las.classification = rng.integers(0, 200, n).astype(np.uint8)
    las.height_above = rng.uniform(0, 2, n).astype(np.float32)
    las.normal = rng.normal(size=(n, 3))
    las.gps_time = rng.uniform(0, 1e6, n)
    src = tmp_path / "ext.las"
    las.write(str(src))
    cloud = read_point_cloud(src, source_crs=32654)
    idx = np.arange(0, n, 2)
    back = read_point_cloud(write_point_cloud(cloud, tmp_path / "out.laz", index=idx))
    for name in ("red", "classification", "height_above", "gps_time"):
        np.testing.assert_array_equal(back.attribute(name), np.asarray(las[name])[idx])
    np.testing.assert_array_equal(back.attribute("normal"), np.asarray(las["normal"])[idx])
    assert back.crs.to_epsg() == 32654
    # LAS → PLY keeps every dimension, coordinates exact as float64
    ply = read_point_cloud(write_point_cloud(cloud, tmp_path / "out.ply"), source_crs=32654)
    np.testing.assert_array_equal(ply.xyz, cloud.xyz)
    np.testing.assert_array_equal(ply.attribute("red"), np.asarray(las.red))
    np.testing.assert_array_equal(ply.attribute("normal_2"), np.asarray(las.normal)[:, 2])


def _ply(path, arr, text=False, byte_order="<", extra=()):
    PlyData([PlyElement.describe(arr, "vertex"), *extra], text=text,
            byte_order=byte_order, comments=["written by test"]).write(str(path))


@pytest.mark.parametrize("text", [False, True])
@pytest.mark.parametrize("order", ["<", ">"])
def test_ply_round_trip_keeps_every_property(tmp_path, text, order):
    n = 300
    rng = np.random.default_rng(2)
    arr = np.empty(n, dtype=[("x", "f8"), ("y", "f8"), ("z", "f4"), ("red", "u2"), ("green", "u2"),
                             ("blue", "u2"), ("nx", "f4"), ("scalar_Confidence", "f8"),
                             ("label", "i4"), ("alpha", "u1")])
    arr["x"] = 368000.123456789 + rng.uniform(0, 100, n)  # UTM size, beyond float32
    arr["y"] = 3955000.987654321 + rng.uniform(0, 100, n)
    for name in ("z", "nx", "scalar_Confidence"):
        arr[name] = rng.normal(size=n)
    for name in ("red", "green", "blue"):
        arr[name] = rng.integers(0, 65536, n)
    arr["label"] = rng.integers(-5, 5, n)
    arr["alpha"] = rng.integers(0, 256, n)
    src = tmp_path / "in.ply"
    _ply(src, arr, text, order)
    cloud = read_point_cloud(src, source_crs=32654)
    np.testing.assert_array_equal(cloud.xyz[:, 0], arr["x"])  # float64 exact
    assert cloud.header.text == text
    idx = np.arange(1, n, 4)
    out = write_point_cloud(cloud, tmp_path / "out.ply", index=idx)
    back = PlyData.read(str(out))
    assert back.text == text
    v = back["vertex"].data
    assert v.dtype.names == arr.dtype.names
    for name in arr.dtype.names:
        assert v.dtype[name].newbyteorder("=") == arr.dtype[name].newbyteorder("=") or text
        np.testing.assert_array_equal(v[name], arr[name][idx], err_msg=name)
    assert "written by test" in back.comments


def test_ply_colourless_and_float_colours(tmp_path):
    arr = np.zeros(4, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    arr["x"] = [0, 1, 2, 3]
    _ply(tmp_path / "plain.ply", arr)
    cloud = read_point_cloud(tmp_path / "plain.ply")
    assert cloud.attribute_names == []
    back = read_point_cloud(write_point_cloud(cloud, tmp_path / "plain_out.ply", index=[1, 3]))
    np.testing.assert_array_equal(back.xyz[:, 0], [1, 3])
    # float colours stay floats, and converting to LAS maps [0, 1] onto 16 bits
    arr = np.zeros(2, dtype=[("x", "f8"), ("y", "f8"), ("z", "f8"), ("red", "f4"),
                             ("green", "f4"), ("blue", "f4")])
    arr["red"] = [0.0, 1.0]
    arr["green"] = [0.5, 0.25]
    _ply(tmp_path / "fcol.ply", arr)
    cloud = read_point_cloud(tmp_path / "fcol.ply")
    assert cloud.attribute("red").dtype == np.float32
    las = read_point_cloud(write_point_cloud(cloud, tmp_path / "fcol.las"))
    np.testing.assert_array_equal(las.attribute("red"), [0, 65535])
    # a mesh PLY: faces are reported and not carried
    faces = PlyElement.describe(np.array([([0, 1, 2],)], dtype=[("vertex_indices", "i4", (3,))]),
                                "face")
    _ply(tmp_path / "mesh.ply", arr, extra=[faces])
    assert read_point_cloud(tmp_path / "mesh.ply").header.other_elements == ["face"]


def test_utm_coordinates_exact_through_las(tmp_path):
    xyz = np.array([[368123.4567, 3955123.4561, 101.2345], [368999.0001, 3955999.9999, 99.0]])
    cloud = PointCloud.from_arrays(xyz, {"intensity": np.array([7, 9], np.uint16)}, crs=32654)
    back = read_point_cloud(write_point_cloud(cloud, tmp_path / "utm.las"))
    np.testing.assert_allclose(back.xyz, xyz, rtol=0, atol=1e-9)  # 0.1 mm grid holds these
    assert back.xyz.dtype == np.float64 and back.crs.to_epsg() == 32654
    np.testing.assert_array_equal(back.attribute("intensity"), [7, 9])


def test_bad_inputs_are_named(tmp_path, realdata):
    with pytest.raises(InputError, match="does not exist"):
        read_point_cloud(tmp_path / "missing.las")
    (tmp_path / "cloud.xyz").write_text("1 2 3\n")
    with pytest.raises(InputError, match="unsupported file type"):
        read_point_cloud(tmp_path / "cloud.xyz")
    (tmp_path / "junk.las").write_bytes(b"not a las file at all" * 20)
    with pytest.raises(InputError, match="junk.las"):
        read_point_cloud(tmp_path / "junk.las")
    data = (realdata / "laspy" / "simple.las").read_bytes()
    (tmp_path / "cut.las").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="cut.las.*truncated"):
        read_point_cloud(tmp_path / "cut.las")
    data = (realdata / "laspy" / "autzen_trim.laz").read_bytes()
    (tmp_path / "cut.laz").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="cut.laz"):
        read_point_cloud(tmp_path / "cut.laz")
    arr = np.zeros(3, dtype=[("x", "f4"), ("y", "f4"), ("height", "f4")])
    _ply(tmp_path / "noz.ply", arr)
    with pytest.raises(InputError, match="noz.ply.*no z"):
        read_point_cloud(tmp_path / "noz.ply")
    arr = np.zeros(1000, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    _ply(tmp_path / "full.ply", arr)
    (tmp_path / "short.ply").write_bytes((tmp_path / "full.ply").read_bytes()[:5000])
    with pytest.raises(InputError, match="short.ply"):
        read_point_cloud(tmp_path / "short.ply")


def test_never_overwrites_input(tmp_path, realdata):
    src = tmp_path / "simple.las"
    shutil.copy(realdata / "laspy" / "simple.las", src)
    before = src.read_bytes()
    cloud = read_point_cloud(src)
    with pytest.raises(InputError, match="input file itself"):
        write_point_cloud(cloud, src, index=[0, 1])
    assert src.read_bytes() == before


def _las14(path):
    header = laspy.LasHeader(version="1.4", point_format=7)
    header.add_extra_dims([laspy.ExtraBytesParams("amp", np.float32)])
    las = laspy.LasData(header)
    rng = np.random.default_rng(9)
    las.x, las.y, las.z = rng.uniform(0, 10, 50), rng.uniform(0, 10, 50), rng.uniform(0, 1, 50)
    las.return_number = rng.integers(1, 12, 50)
    las.amp = rng.uniform(0, 1, 50).astype(np.float32)
    las.write(str(path))
    return path


@pytest.mark.parametrize("name", REAL + ["las14"])
def test_fast_las_writer_is_byte_identical_to_laspy(realdata, tmp_path, name):
    import copy
    src = _las14(tmp_path / "v14.las") if name == "las14" else realdata / "laspy" / name
    cloud = read_point_cloud(src)
    idx = np.arange(2, len(cloud), 5)
    fast = write_point_cloud(cloud, tmp_path / "fast.las", index=idx)
    ref = laspy.LasData(copy.deepcopy(cloud.header),
                        laspy.PackedPointRecord(np.asarray(cloud.records)[idx],
                                                cloud.header.point_format))
    ref.write(str(tmp_path / "ref.las"))
    assert fast.read_bytes() == (tmp_path / "ref.las").read_bytes()


def test_unreadable_crs_record_is_noted(realdata, tmp_path):
    """A LAS whose WKT VLR is garbage: read, noted, never silently 'no CRS'."""
    las = laspy.read(str(realdata / "laspy/simple.las"))
    las.header.vlrs.append(laspy.vlrs.known.WktCoordinateSystemVlr("this is not WKT"))
    path = tmp_path / "badcrs.las"
    las.write(str(path))
    cloud = read_point_cloud(path)
    assert cloud.crs is None and len(cloud.notes) == 1
    assert "badcrs.las" in cloud.notes[0] and "CRS record cannot be read" in cloud.notes[0]
    given = read_point_cloud(path, source_crs="EPSG:32654")
    assert given.crs.to_epsg() == 32654 and "the CRS given is used" in given.notes[0]
    assert read_point_cloud(realdata / "laspy/autzen_geo_proj.las").notes == []
