"""GeoTIFF metadata: georeferencing, CRS, nodata, layout, and bad files."""
import shutil

import numpy as np
import pytest

from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.raster.geotiff import open_geotiff
from synthetic import write_tif


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
    t2 = open_geotiff(str(p))
    import os
    fd = os.open(str(p), os.O_RDONLY)
    try:
        with pytest.raises(InputError, match="cut.tif is truncated"):
            t2.read_block(fd, t2.blocks_down - 1, 0)
    finally:
        os.close(fd)


def test_copy_keeps_metadata(tmp_path, realdata):
    p = tmp_path / "copy.tif"
    shutil.copy(realdata / "d2spy/dsm.tif", p)
    assert open_geotiff(str(p)).nodata == pytest.approx(3.4028234663852886e38)


def test_unreadable_crs_is_noted_never_silently_dropped(tmp_path):
    """GeoKeys naming a CRS that cannot be read leave a note; a given CRS needs none."""
    from synthetic import geokeys
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
