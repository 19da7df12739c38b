"""The DSM object: opening (path or GeoTiff, CRS override, one band), heights at points in any
CRS (nodata and outside → NaN), and its ray surface."""
import numpy as np
import pytest
from pyproj import CRS, Transformer

from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.raster import DSM, RaySurface, as_dsm, open_geotiff, valid_heights
from easyidp_toolbox.tests.support.synthetic import write_tif

O = (368000.0, 3956000.0)
UTM54 = CRS.from_epsg(32654)


@pytest.fixture()
def dsm_path(tmp_path):
    """60 × 80 pixels of 0.5 m: z = 100 + col − 0.5 row, with nodata in a 4 × 4 block."""
    rows, cols = np.mgrid[0:60, 0:80]
    z = (100.0 + cols - 0.5 * rows).astype(np.float32)
    z[20:24, 30:34] = -9999
    return write_tif(str(tmp_path / "dsm.tif"), z, origin=O, pixel=0.5, nodata=-9999, tile=16)


def _points(n=500, seed=0):
    rng = np.random.default_rng(seed)
    return O[0] + rng.uniform(-2, 42, n), O[1] - rng.uniform(-2, 32, n)


def test_a_path_and_an_opened_geotiff_give_the_same_heights(dsm_path):
    x, y = _points()
    a = DSM(dsm_path).heights(x, y)
    b = DSM(open_geotiff(dsm_path)).heights(x, y)
    assert a.dtype == np.float64 and a.shape == x.shape
    assert np.array_equal(a, b, equal_nan=True)
    # outside the raster and on the nodata block: NaN; elsewhere a height
    outside = (x < O[0]) | (x > O[0] + 40) | (y > O[1]) | (y < O[1] - 30)
    assert np.isnan(a[outside]).all()
    cx, cy = O[0] + 16.0, O[1] - 11.0         # the centre of the nodata block
    assert np.isnan(DSM(dsm_path).heights(np.array([cx]), np.array([cy]), method="nearest")).all()
    assert np.isfinite(a[~outside & ((np.abs(x - cx) > 3) | (np.abs(y - cy) > 3))]).all()


def test_heights_keep_the_shape_of_the_points(dsm_path):
    x, y = _points(12)
    z = DSM(dsm_path).heights(x.reshape(3, 4), y.reshape(3, 4))
    assert z.shape == (3, 4)
    assert np.array_equal(z.ravel(), DSM(dsm_path).heights(x, y), equal_nan=True)


def test_points_in_another_crs_are_transformed_to_the_dsm_crs(dsm_path):
    x, y = _points()
    lon, lat = Transformer.from_crs(UTM54, CRS.from_epsg(4326), always_xy=True).transform(x, y)
    dsm = DSM(dsm_path)
    back = Transformer.from_crs(CRS.from_epsg(4326), UTM54, always_xy=True).transform(lon, lat)
    expected = dsm.heights(*back)
    for method in ("bilinear", "nearest"):
        assert np.array_equal(dsm.heights(lon, lat, crs="EPSG:4326", method=method),
                              dsm.heights(*back, method=method), equal_nan=True)
    # the DSM's own CRS, given or not, is not transformed
    assert np.array_equal(dsm.heights(x, y, crs=32654), dsm.heights(x, y), equal_nan=True)
    assert np.isfinite(expected).sum() > 300


def test_a_dsm_without_crs_takes_the_points_as_they_are(tmp_path):
    z = np.full((10, 10), 7.0, np.float32)
    path = write_tif(str(tmp_path / "local.tif"), z, origin=(0.0, 10.0), pixel=1.0, georef=False,
                     transformation=[[1, 0, 0, 0], [0, -1, 0, 10], [0, 0, 0, 0], [0, 0, 0, 1]])
    dsm = DSM(path)
    assert dsm.crs is None
    assert dsm.heights(np.array([5.0]), np.array([5.0]), crs="EPSG:4326")[0] == 7.0


def test_crs_override_and_checks(dsm_path, tmp_path):
    assert DSM(dsm_path).crs == UTM54
    assert DSM(dsm_path, crs="EPSG:32653").crs == CRS.from_epsg(32653)
    assert DSM(open_geotiff(dsm_path), crs="EPSG:32653").crs == CRS.from_epsg(32653)
    rgb = write_tif(str(tmp_path / "rgb.tif"), np.zeros((8, 8, 3), np.uint8))
    with pytest.raises(InputError, match=r"rgb.tif has 3 bands; a DSM must have exactly one"):
        DSM(rgb)
    with pytest.raises(InputError, match="Raster not found"):
        DSM(str(tmp_path / "none.tif"))
    with pytest.raises(ValueError, match="sampling must be one of"):
        DSM(dsm_path).heights(np.zeros(1), np.zeros(1), method="cubic")
    with pytest.raises(TypeError):      # crs and method are keywords: no silent mix-up
        DSM(dsm_path).heights(np.zeros(1), np.zeros(1), "nearest")


def test_as_dsm_and_the_ray_surface(dsm_path):
    dsm = DSM(dsm_path)
    assert as_dsm(dsm) is dsm
    assert as_dsm(dsm, crs="EPSG:32653").crs == CRS.from_epsg(32653)
    assert isinstance(as_dsm(dsm_path), DSM) and isinstance(as_dsm(open_geotiff(dsm_path)), DSM)
    surface = dsm.ray_surface()
    assert isinstance(surface, RaySurface) and surface.tif is dsm.tif
    assert dsm.ray_surface() is surface                     # kept: its tiles are read once
    assert dsm.ray_surface(tile=8) is not surface and dsm.ray_surface(tile=8).T == 8
    assert DSM(dsm_path).ray_surface() is not surface
    assert dsm.describe() == f"DSM {dsm_path} (bilinear per vertex)"


def test_valid_heights():
    tif = type("T", (), {"nodata": -9999.0})()
    arr = np.array([1.0, np.nan, -9999.0, np.inf], np.float32)
    assert valid_heights(tif, arr).tolist() == [True, False, False, False]
    tif.nodata = None
    assert valid_heights(tif, np.array([3, -9999], np.int16)).tolist() == [True, True]
