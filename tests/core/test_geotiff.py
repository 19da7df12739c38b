"""GeoTIFF metadata: georeferencing, CRS, nodata, layout, and bad files."""
import shutil

import numpy as np
import pytest

from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.raster.geotiff import open_geotiff
from easyidp_toolbox.tests.support.synthetic import write_tif


@pytest.mark.gdal
def test_real_rasters_match_gdal(realdata):
    from osgeo import gdal
    for rel in ("d2spy/dsm.tif", "data-to-science/test.tif", "data-to-science/test_multispectral.tif"):
        tif = open_geotiff(str(realdata / rel))
        ds = gdal.Open(str(realdata / rel))
        assert tif.geotransform == pytest.approx(ds.GetGeoTransform(), abs=1e-9)
        assert (tif.width, tif.height, tif.bands) == (ds.RasterXSize, ds.RasterYSize, ds.RasterCount)
        nd = ds.GetRasterBand(1).GetNoDataValue()
        assert (tif.nodata is None) == (nd is None)
        if nd is not None:
            assert np.float32(tif.nodata) == np.float32(nd)
        assert tif.crs.to_epsg() == 32616


def test_real_raster_kinds(realdata):
    assert open_geotiff(str(realdata / "d2spy/dsm.tif")).kind == "single"
    assert open_geotiff(str(realdata / "data-to-science/test_multispectral.tif")).kind == "multiband"


def test_pixel_map_round_trip(tmp_path):
    tif = open_geotiff(write_tif(str(tmp_path / "a.tif"), np.zeros((10, 20), np.float32),
                                 origin=(100.0, 200.0), pixel=0.5))
    x, y = tif.pixel_to_map(0.5, 0.5)
    assert (x, y) == (100.25, 199.75)   # centre of the top-left pixel
    assert tif.map_to_pixel(x, y) == (0.5, 0.5)


def test_pixel_is_point_is_shifted_like_gdal(tmp_path):
    tif = open_geotiff(write_tif(str(tmp_path / "p.tif"), np.zeros((4, 4), np.float32),
                                 origin=(100.0, 200.0), pixel=1.0, pixel_is_point=True))
    assert tif.geotransform[0] == 99.5 and tif.geotransform[3] == 200.5


def test_missing_file():
    with pytest.raises(InputError, match="Raster not found: /no/such.tif"):
        open_geotiff("/no/such.tif")


def test_not_a_tiff(tmp_path):
    p = tmp_path / "ortho.tif"
    p.write_bytes(b"\x89PNG\r\n\x1a\n" + b"0" * 100)
    with pytest.raises(InputError, match="ortho.tif is not a readable GeoTIFF"):
        open_geotiff(str(p))


def test_without_georeferencing(tmp_path):
    p = write_tif(str(tmp_path / "plain.tif"), np.zeros((4, 4), np.uint8), georef=False)
    with pytest.raises(InputError, match="plain.tif has no georeferencing"):
        open_geotiff(p)


def test_rotated_geotransform_is_refused(tmp_path):
    m = np.eye(4)
    m[0, :] = [0.5, 0.1, 0, 100]
    m[1, :] = [0.1, -0.5, 0, 200]
    p = write_tif(str(tmp_path / "rot.tif"), np.zeros((4, 4), np.uint8), transformation=m)
    with pytest.raises(InputError, match="rot.tif has a rotated geotransform.*Warp it north-up"):
        open_geotiff(p)


def test_north_up_model_transformation_is_read(tmp_path):
    m = np.eye(4)
    m[0, :] = [0.5, 0, 0, 100]
    m[1, :] = [0, -0.5, 0, 200]
    tif = open_geotiff(write_tif(str(tmp_path / "mt.tif"), np.zeros((4, 4), np.uint8), transformation=m))
    assert tif.geotransform == (100, 0.5, 0, 200, 0, -0.5)


def test_truncated_file_names_the_block(tmp_path, realdata):
    src = realdata / "data-to-science/test.tif"
    p = tmp_path / "cut.tif"
    data = src.read_bytes()
    tif = open_geotiff(str(src))
    last = tif._page.dataoffsets[-1]
    p.write_bytes(data[:last + 10])   # IFD intact (it is at the start), the last strip cut off
    with pytest.raises(InputError, match="cut.tif is truncated: its blocks end .* into a file of"):
        open_geotiff(str(p))          # found when opened, before any sweep


def test_declared_sizes_are_not_trusted(tmp_path):
    """A 318-byte TIFF declaring 200000 × 200000 pixels in one strip, and an uncompressed
    raster holding fewer bytes than it declares: refused at open, nothing allocated by them."""
    import struct
    w = h = 200000
    tags = sorted([(256, 4, 1, w), (257, 4, 1, h), (258, 3, 1, 8), (259, 3, 1, 1), (262, 3, 1, 1),
                   (273, 4, 1, 0), (277, 3, 1, 1), (278, 4, 1, h), (279, 4, 1, 100),
                   (33550, 12, 3, 0), (33922, 12, 6, 0)])
    data_off = 8 + 2 + len(tags) * 12 + 4
    ps_off, tp_off = data_off + 100, data_off + 124
    fixed = {273: data_off, 33550: ps_off, 33922: tp_off}
    b = bytearray(b"II*\x00" + struct.pack("<I", 8) + struct.pack("<H", len(tags)))
    for t, ty, c, v in tags:
        v = fixed.get(t, v)
        b += struct.pack("<HHIHH", t, ty, c, v, 0) if ty == 3 else struct.pack("<HHII", t, ty, c, v)
    b += struct.pack("<I", 0) + bytes(100) + struct.pack("<3d", 1, 1, 0) + struct.pack("<6d", *[0] * 6)
    huge = tmp_path / "huge.tif"
    huge.write_bytes(bytes(b))
    with pytest.raises(InputError, match="huge.tif declares strips of 200000 × 200000 pixels"):
        open_geotiff(str(huge))
    small = write_tif(str(tmp_path / "s.tif"), np.ones((64, 64), np.uint16), compression=None)
    raw = bytearray(open(small, "rb").read())
    import tifffile
    with tifffile.TiffFile(small) as tf:            # halve every strip's byte count in place
        tag = tf.pages[0].tags[279]
        counts = tag.value
        fmt = {3: "<H", 4: "<I", 16: "<Q"}[tag.dtype]
        for i, c in enumerate(counts):
            struct.pack_into(fmt, raw, tag.valueoffset + i * struct.calcsize(fmt), c // 2)
    bad = tmp_path / "bad.tif"
    bad.write_bytes(bytes(raw))
    with pytest.raises(InputError, match="bad.tif is damaged: it declares 64 × 64 uncompressed"):
        open_geotiff(str(bad))


def test_copy_keeps_metadata(tmp_path, realdata):
    p = tmp_path / "copy.tif"
    shutil.copy(realdata / "d2spy/dsm.tif", p)
    assert open_geotiff(str(p)).nodata == pytest.approx(3.4028234663852886e38)


def test_unreadable_crs_is_noted_never_silently_dropped(tmp_path):
    """GeoKeys naming a CRS that cannot be read leave a note; a given CRS needs none."""
    from easyidp_toolbox.tests.support.synthetic import geokeys
    import tifffile
    data = np.zeros((4, 4), np.float32)
    for code, words in ((32767, "user-defined"), (9999, "not a CRS PROJ knows")):
        path = str(tmp_path / f"k{code}.tif")
        keys = list(geokeys())
        keys[-1] = code                               # ProjectedCSTypeGeoKey
        tifffile.imwrite(path, data, extratags=[
            (33550, "d", 3, (1.0, 1.0, 0.0), True), (33922, "d", 6, (0, 0, 0, 0, 10, 0), True),
            (34735, "H", len(keys), tuple(keys), True)], metadata=None)
        tif = open_geotiff(path)
        assert tif.crs is None and len(tif.notes) == 1 and words in tif.notes[0], tif.notes
        assert path in tif.notes[0] and "Give the raster's CRS" in tif.notes[0]
        assert open_geotiff(path, crs="EPSG:32654").notes == []
    ok = open_geotiff(write_tif(str(tmp_path / "ok.tif"), data))
    assert ok.crs.to_epsg() == 32654 and ok.notes == []
