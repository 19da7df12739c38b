"""ROI heights from a DSM: statistics, sampling, buffers, nodata; checked against GDAL on real data."""
import json

import numpy as np
import pytest

from easyidp_toolbox.core import ROI, ROISet, read_geojson
from easyidp_toolbox.core.raster import DSM, dsm_roi_heights, vertex_heights
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.tests.support.synthetic import write_tif

O = (368000.0, 3956000.0)


def _plane_dsm(tmp_path, nodata=None, **kw):
    """z = 100 + 0.5 x' - 0.25 y' at pixel centres (x', y' map offsets from the origin)."""
    rows, cols = 80, 100
    cy, cx = np.mgrid[0:rows, 0:cols] + 0.5
    z = (100 + 0.5 * cx * 0.5 - 0.25 * (-cy * 0.5)).astype(np.float64)
    return write_tif(str(tmp_path / "plane.tif"), z, origin=O, pixel=0.5, nodata=nodata, **kw), z


def test_bilinear_is_exact_on_a_plane_and_nearest_is_the_pixel(tmp_path):
    path, z = _plane_dsm(tmp_path, tile=16)
    rng = np.random.default_rng(0)
    x = O[0] + rng.uniform(1, 49, 200)
    y = O[1] - rng.uniform(1, 39, 200)
    truth = 100 + 0.5 * (x - O[0]) - 0.25 * (y - O[1])
    assert np.allclose(DSM(path).heights(x, y, method="bilinear"), truth, atol=1e-9)
    near = DSM(path).heights(x, y, method="nearest")
    assert np.array_equal(near, z[((O[1] - y) / 0.5).astype(int), ((x - O[0]) / 0.5).astype(int)])
    assert np.isnan(DSM(path).heights(np.array([O[0] - 5]), np.array([O[1]]),
                                      method="nearest")).all()


def test_diamond_on_constant_dsm_without_nodata_is_the_constant(tmp_path):
    """easyidp 2.0.4 gives 50 here (outside pixels counted as 0)."""
    path = write_tif(str(tmp_path / "c.tif"), np.full((60, 60), 100.0, np.float32), origin=O, pixel=0.5)
    d = np.array([[O[0] + 15, O[1] - 2], [O[0] + 28, O[1] - 15], [O[0] + 15, O[1] - 28],
                  [O[0] + 2, O[1] - 15]])
    for stat in ("mean", "median", "min", "max", "percentile"):
        assert dsm_roi_heights(path, ROISet([ROI("d", [[d]])], 32654), statistic=stat).values == [100.0]


def test_statistics_equal_numpy_on_the_selected_pixels(tmp_path):
    rng = np.random.default_rng(5)
    z = rng.normal(50, 3, (64, 64)).astype(np.float32)
    z[10:20, 10:20] = -9999
    path = write_tif(str(tmp_path / "r.tif"), z, origin=O, pixel=1.0, nodata=-9999, rowsperstrip=3)
    ring = np.array([[O[0] + 5, O[1] - 5], [O[0] + 40, O[1] - 5], [O[0] + 40, O[1] - 30],
                     [O[0] + 5, O[1] - 30]])
    sel = z[5:30, 5:40]
    sel = sel[sel != -9999].astype(float)
    rois = ROISet([ROI("r", [[ring]])], 32654)
    assert dsm_roi_heights(path, rois, statistic="mean").values[0] == pytest.approx(sel.mean())
    assert dsm_roi_heights(path, rois, statistic="median").values[0] == pytest.approx(np.median(sel))
    assert dsm_roi_heights(path, rois, statistic="percentile", percentile=95).values[0] == \
        pytest.approx(np.percentile(sel, 95))
    assert dsm_roi_heights(path, rois, statistic="min").values[0] == pytest.approx(sel.min())


def test_all_nodata_polygon_is_reported_never_zero(tmp_path):
    z = np.full((40, 40), 7.0, np.float32)
    z[:20, :20] = -32767
    path = write_tif(str(tmp_path / "n.tif"), z, origin=O, pixel=1.0, nodata=-32767)
    rois = ROISet([ROI("hole", [[np.array([[O[0] + 2, O[1] - 2], [O[0] + 10, O[1] - 2],
                                           [O[0] + 10, O[1] - 10]])]]),
                   ROI("ok", [[np.array([[O[0] + 25, O[1] - 25], [O[0] + 35, O[1] - 25],
                                         [O[0] + 35, O[1] - 35]])]])], 32654)
    res = dsm_roi_heights(path, rois)
    assert np.isnan(res.values[0]) and res.values[1] == 7.0
    assert list(res.missing) == [0] and "nodata" in res.missing[0]
    v = dsm_roi_heights(path, rois, mode="vertex")
    assert np.isnan(v.values[0][0][0]).all() and list(v.missing) == [0]
    # results are aligned with the ROI order: two ROIs with one name keep their own heights
    twins = ROISet([ROI("A1", rois[0].parts), ROI("A1", rois[1].parts)], 32654)
    res = dsm_roi_heights(path, twins, statistic="max")
    assert np.isnan(res.values[0]) and res.values[1] == 7.0 and list(res.missing) == [0]


def test_buffer_grows_and_shrinks_the_polygon(tmp_path):
    z = np.zeros((100, 100), np.float32)
    z[40:60, 40:60] = 1.0   # a 20 x 20 m block at 1 m pixels
    path = write_tif(str(tmp_path / "b.tif"), z, origin=O, pixel=1.0)
    ring = np.array([[O[0] + 40, O[1] - 40], [O[0] + 60, O[1] - 40], [O[0] + 60, O[1] - 60],
                     [O[0] + 40, O[1] - 60]])
    rois = ROISet([ROI("b", [[ring]])], 32654)
    assert dsm_roi_heights(path, rois, statistic="mean").values[0] == 1.0
    grown = dsm_roi_heights(path, rois, statistic="mean", buffer=5).values[0]
    # buffered square: 400 + 4 * 20 * 5 + pi * 25 pixels, of which 400 are 1
    assert grown == pytest.approx(400 / (400 + 400 + np.pi * 25), rel=0.03)
    assert dsm_roi_heights(path, rois, statistic="min", buffer=-3).values[0] == 1.0


def test_vertex_buffer_statistic(tmp_path):
    path, z = _plane_dsm(tmp_path)
    x, y = np.array([O[0] + 20.0]), np.array([O[1] - 20.0])
    mean = vertex_heights(path, x, y, buffer=2.0, statistic="mean")
    assert mean[0] == pytest.approx(100 + 0.5 * 20 - 0.25 * -20, abs=1e-6)  # symmetric disc on a plane


def test_dsm_must_have_one_band(realdata):
    rois = read_geojson(str(realdata / "data-to-science/zones_inside_test_tif.geojson"))
    with pytest.raises(InputError, match="test_multispectral.tif has 6 bands"):
        dsm_roi_heights(str(realdata / "data-to-science/test_multispectral.tif"), rois)


@pytest.mark.gdal
def test_real_polygon_means_match_gdal(realdata, tmp_path):
    """Mean of the pixels gdalwarp -cutline keeps, on the real DSM, for the 20 lon/lat plots."""
    from osgeo import gdal
    from pyproj import Transformer
    gdal.UseExceptions()
    src = str(realdata / "data-to-science/test.tif")
    path = str(realdata / "data-to-science/zones_inside_test_tif.geojson")
    ours = dsm_roi_heights(src, read_geojson(path), statistic="mean").values
    doc = json.load(open(path))
    c, a, _, f, _, e = gdal.Open(src).GetGeoTransform()
    to_utm = Transformer.from_crs("OGC:CRS84", 32616, always_xy=True)
    for k, feat in enumerate(doc["features"]):
        cut = str(tmp_path / f"c{k}.geojson")
        json.dump({"type": "FeatureCollection", "crs": doc["crs"], "features": [feat]}, open(cut, "w"))
        lon, lat = np.array(feat["geometry"]["coordinates"][0])[:, :2].T
        x, y = to_utm.transform(lon, lat)
        # the cutline envelope snapped outwards to the source grid: no pixel is cut off
        te = (c + np.floor((x.min() - c) / a) * a, f + np.ceil((y.min() - f) / e) * e,
              c + np.ceil((x.max() - c) / a) * a, f + np.floor((y.max() - f) / e) * e)
        ds = gdal.Warp(str(tmp_path / f"g{k}.tif"), src, cutlineDSName=cut, outputBounds=te,
                       xRes=a, yRes=-e)
        g = ds.ReadAsArray()
        assert ours[k] == pytest.approx(g[g != -32767].astype(float).mean(), abs=1e-9)


def test_real_vertex_heights_on_lonlat_rois(realdata):
    rois = read_geojson(str(realdata / "d2spy/feature_in_dsm.geojson"))
    res = dsm_roi_heights(str(realdata / "d2spy/dsm.tif"), rois, mode="vertex")
    z = np.concatenate([r for p in res.values[0] for r in p])
    assert np.isfinite(z).all() and (187.9 < z).all() and (z < 188.4).all()


def test_dense_points_over_many_blocks_match_the_pixel_rule(tmp_path):
    """Points read in grouped windows (several 256-pixel cells, nodata, raster edges) give what the
    documented rule gives point by point."""
    rng = np.random.default_rng(3)
    z = rng.normal(50, 3, (300, 600)).astype(np.float32)
    z[rng.random(z.shape) < 0.2] = -9999
    path = write_tif(str(tmp_path / "d.tif"), z, origin=O, pixel=0.5, nodata=-9999, tile=32)
    x = O[0] + rng.uniform(-2, 302, 3000)
    y = O[1] - rng.uniform(-2, 152, 3000)
    x[:4], y[:4] = [O[0], O[0] + 300, O[0] + 0.25, O[0] + 300], [O[1], O[1] - 150, O[1] - 0.25, O[1]]
    col, row = (x - O[0]) / 0.5, (O[1] - y) / 0.5

    def pixel(r, c):
        return z[r, c] if 0 <= r < 300 and 0 <= c < 600 and z[r, c] != -9999 else None

    near, bil = [], []
    for c, r in zip(col, row):
        if not (0 <= c <= 600 and 0 <= r <= 300):
            near.append(np.nan)
            bil.append(np.nan)
            continue
        v = pixel(min(int(np.floor(r)), 299), min(int(np.floor(c)), 599))
        near.append(np.nan if v is None else v)
        c0, r0 = int(np.floor(c - 0.5)), int(np.floor(r - 0.5))
        fc, fr = c - 0.5 - c0, r - 0.5 - r0
        num = den = 0.0
        for dr, dc, w in ((0, 0, (1 - fr) * (1 - fc)), (0, 1, (1 - fr) * fc),
                          (1, 0, fr * (1 - fc)), (1, 1, fr * fc)):
            v = pixel(r0 + dr, c0 + dc)
            if v is not None:
                num, den = num + w * v, den + w
        bil.append(num / den if den > 0 else np.nan)
    np.testing.assert_allclose(DSM(path).heights(x, y, method="nearest"), near, atol=1e-9)
    np.testing.assert_allclose(DSM(path).heights(x, y, method="bilinear"), bil, atol=1e-9)


def test_a_negative_buffer_larger_than_the_roi_blames_the_buffer(tmp_path):
    z = np.full((100, 100), 5.0, np.float32)
    path = write_tif(str(tmp_path / "b.tif"), z, origin=O, pixel=1.0)
    ring = np.array([[O[0] + 40, O[1] - 40], [O[0] + 60, O[1] - 40], [O[0] + 60, O[1] - 60],
                     [O[0] + 40, O[1] - 60]])
    res = dsm_roi_heights(path, ROISet([ROI("p", [[ring]])], 32654), buffer=-1000)
    assert np.isnan(res.values[0]) and "buffer of -1000" in res.missing[0]
    assert "smaller negative buffer" in res.missing[0]


def test_statistics_of_many_groups_equal_numpy_group_by_group():
    """[independent] The batched statistics (one pass over many ROIs' pixels) equal numpy's
    own on each group: float32 values, NaN and inf ignored, a group with no finite value NaN."""
    from easyidp_toolbox.core.height_statistics import statistics_of
    rng = np.random.default_rng(3)
    groups = [rng.normal(95, 2, rng.integers(1, 300)).astype(np.float32) for _ in range(50)]
    groups[3][::2] = np.nan
    groups[7][0] = np.inf
    groups.insert(10, np.array([np.nan], np.float32))
    for stat, fn in (("mean", np.mean), ("min", np.min), ("max", np.max), ("std", np.std),
                     ("median", np.median)):
        got = statistics_of(groups, stat)
        want = [fn(g[np.isfinite(g)].astype(np.float64)) if np.isfinite(g).any() else np.nan
                for g in groups]
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, equal_nan=True)


def test_span_pixels_are_the_rasterized_pixels(tmp_path):
    """[independent] The pixel indices listed from row spans (the per-polygon fast path) are
    the pixels geometry.rasterize (the even-odd toggle rasterizer) sets, for rotated
    rectangles, triangles and slivers, some cut by the raster edge; a window larger than
    SMALL_WINDOW gets None (its mask is used)."""
    from easyidp_toolbox.core.geometry import rasterize
    from easyidp_toolbox.core.raster.geotiff import open_geotiff
    from easyidp_toolbox.core.raster.roi_pixels import SMALL_WINDOW, place_rois, span_pixels
    path = write_tif(str(tmp_path / "r.tif"), np.zeros((120, 120), np.float32), origin=O,
                     pixel=1.0)
    rng = np.random.default_rng(11)
    rois = []
    for k in range(300):
        c = rng.uniform(-5, 125, 2)
        n = 3 if k % 3 == 0 else 4
        t = np.sort(rng.uniform(0, 2 * np.pi, n)) if n == 3 else \
            rng.uniform(0, np.pi) + np.array([0, 0.5, 1, 1.5]) * np.pi
        r = rng.uniform(0.3, 9 if k % 7 else 60)
        ring = np.column_stack([O[0] + c[0] + r * np.cos(t), O[1] - c[1] + (1.0 if k % 7 == 0 else 0.4) * r * np.sin(t)])
        rois.append(ROI(f"p{k}", [[ring]]))
    placed, _ = place_rois(open_geotiff(path), ROISet(rois, 32654))
    got = span_pixels(placed)
    checked = big = 0
    for p, idx in zip(placed, got):
        w = p.window
        if p.spans is None:
            assert idx is None
            continue
        if w.rows * w.cols > SMALL_WINDOW:
            assert idx is None
            big += 1
            continue
        want = np.flatnonzero(rasterize(p.rings, (w.rows, w.cols)))
        assert idx.tolist() == want.tolist(), p.roi.name
        checked += 1
    assert checked > 200 and big > 0
