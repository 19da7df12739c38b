"""ROI heights and canopy summaries from a point cloud."""
import numpy as np
import pytest
from easyidp_toolbox.tests.support.pc_helpers import winding_inside

from easyidp_toolbox.core import (ROI, EasyIDPError, InputError, PointCloud, ROISet,
                                  canopy_summary, read_point_cloud)
from easyidp_toolbox.core.pointcloud import cloud_roi_heights
from easyidp_toolbox.core.height_statistics import statistic_of

E0, N0 = 368000.0, 3955000.0  # UTM-size coordinates


@pytest.fixture(scope="module")
def field_cloud():
    """A 20 m × 20 m field: ground at z = 50 + 0.01·(x − E0), plants in two plots."""
    rng = np.random.default_rng(4)
    n = 60_000
    x = E0 + rng.uniform(0, 20, n)
    y = N0 + rng.uniform(0, 20, n)
    ground = 50 + 0.01 * (x - E0)
    plant = ((x - E0) > 2) & ((x - E0) < 8) & ((y - N0) > 2) & ((y - N0) < 8)
    z = ground + np.where(plant, rng.uniform(0, 1.2, n), 0.0)
    return PointCloud.from_arrays(np.column_stack([x, y, z]), crs=32654), ground


def _sq(x0, y0, x1, y1):
    return np.array([[E0 + x0, N0 + y0], [E0 + x1, N0 + y0], [E0 + x1, N0 + y1], [E0 + x0, N0 + y1]])


def _rois():
    return ROISet([ROI("plants", [[_sq(2.003, 2.007, 7.997, 7.991)]]),
                   ROI("bare", [[_sq(12.003, 12.007, 17.997, 17.991)]])], 32654)


def test_polygon_statistics_match_direct_computation(field_cloud):
    cloud, _ = field_cloud
    xyz = cloud.xyz
    for stat, q in (("mean", 50), ("median", 50), ("min", 50), ("max", 50), ("std", 50),
                    ("percentile", 95), ("pmin", 5), ("pmax", 10)):
        got = cloud_roi_heights(cloud, _rois(), mode="polygon", statistic=stat, percentile=q)
        assert got.mode == "polygon" and len(got.values) == len(_rois())
        for i, roi in enumerate(_rois()):
            z = xyz[winding_inside(xyz[:, 0], xyz[:, 1], roi.rings), 2]
            if stat == "percentile":
                direct = np.percentile(z, q)
            elif stat == "pmin":        # EasyIDP's kernels
                direct = z[z <= np.percentile(z, q)].mean()
            elif stat == "pmax":
                direct = z[z >= np.percentile(z, 100 - q)].mean()
            else:
                direct = getattr(np, stat)(z)
            assert got.values[i] == pytest.approx(direct, rel=0, abs=1e-12)
    z = np.array([1.0, 2, 3, 4, 5, 6, 7, 8, 9, 10])
    assert statistic_of(z, "percentile", 50) == 5.5 and statistic_of(z, "max") == 10
    assert np.isnan(statistic_of(np.array([]), "mean"))
    with pytest.raises(EasyIDPError, match="between 0 and 100, not 120"):
        cloud_roi_heights(cloud, _rois(), statistic="percentile", percentile=120)
    with pytest.raises(EasyIDPError, match="Unknown statistic 'p95'"):
        cloud_roi_heights(cloud, _rois(), statistic="p95")


def test_vertex_mode_nearest_and_buffer(field_cloud):
    cloud, _ = field_cloud
    xyz = cloud.xyz
    near = cloud_roi_heights(cloud, _rois(), mode="point")             # EasyIDP's name for vertex
    disc = cloud_roi_heights(cloud, _rois(), mode="vertex", statistic="mean", buffer=0.5)
    assert near.mode == disc.mode == "vertex"
    for i, roi in enumerate(_rois()):
        v = np.concatenate(roi.rings)
        got_near = np.concatenate(near.values[i][0])                # [part][ring] nesting
        assert got_near.shape == (len(v),)
        for j, (vx, vy) in enumerate(v):
            d2 = (xyz[:, 0] - vx) ** 2 + (xyz[:, 1] - vy) ** 2
            assert got_near[j] == xyz[np.argmin(d2), 2]
            assert np.concatenate(disc.values[i][0])[j] == pytest.approx(xyz[d2 <= 0.25, 2].mean(),
                                                                          abs=1e-12)
    far = ROISet([ROI("outside", [[_sq(100, 100, 101, 101)]])], 32654)
    assert np.all(np.isfinite(cloud_roi_heights(cloud, far, mode="vertex").values[0][0][0]))


def test_canopy_summary_grounds(field_cloud):
    cloud, ground = field_cloud
    xyz = cloud.xyz
    inside = winding_inside(xyz[:, 0], xyz[:, 1], _rois()[0].rings)
    h_true = xyz[inside, 2] - ground[inside]
    by_array = canopy_summary(cloud, _rois(), ground=ground)
    by_call = canopy_summary(cloud, _rois(), ground=lambda x, y: 50 + 0.01 * (x - E0))
    for res in (by_array, by_call):
        row = res[0]
        assert row["count"] == inside.sum()
        for q in (5, 50, 95, 99):
            assert row[f"h_p{q}"] == pytest.approx(np.percentile(h_true, q), abs=1e-9)
        assert row["h_max"] == pytest.approx(h_true.max(), abs=1e-9)
        assert res[1]["h_p99"] == pytest.approx(0.0, abs=1e-9)
    const = canopy_summary(cloud, _rois(), ground=50.0, percentiles=(50,))[0]
    assert const["ground"] == 50.0
    assert const["h_p50"] == pytest.approx(np.median(xyz[inside, 2] - 50.0))
    lowest = canopy_summary(cloud, _rois(), ground_percentile=1)[0]
    z = xyz[inside, 2]
    assert lowest["ground"] == pytest.approx(np.percentile(z, 1))
    assert lowest["h_p95"] == pytest.approx(np.percentile(z - np.percentile(z, 1), 95))
    assert lowest["density"] == pytest.approx(inside.sum() / _rois()[0].area)
    with pytest.raises(InputError, match="one ground height per point"):
        canopy_summary(cloud, _rois(), ground=np.zeros(3))


def test_empty_roi_gives_nan_and_zero_count(field_cloud):
    cloud, _ = field_cloud
    rois = ROISet([ROI("off", [[_sq(300, 300, 301, 301)]])], 32654)
    (row,) = canopy_summary(cloud, rois)
    assert row["count"] == 0 and np.isnan(row["h_p50"])
    res = cloud_roi_heights(cloud, rois)
    assert np.isnan(res.values[0]) and "no point" in res.missing[0]


def test_real_laz_canopy_counts(realdata):
    cloud = read_point_cloud(realdata / "laspy" / "autzen_trim.laz")
    xyz = cloud.xyz
    ring = np.array([[636500.003, 849000.007], [636700.001, 849010.0], [636650.0, 849200.0]])
    rois = ROISet([ROI("tri", [[ring]])], cloud.crs)
    (row,) = canopy_summary(cloud, rois, ground=400.0)
    inside = winding_inside(xyz[:, 0], xyz[:, 1], [ring])
    assert row["count"] == inside.sum() > 0
    assert row["h_p50"] == pytest.approx(np.median(xyz[inside, 2]) - 400.0)
