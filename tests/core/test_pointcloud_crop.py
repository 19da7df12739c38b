"""Crop by many ROIs in one pass: real LAS/LAZ, exact counts, attributes, reprojection, errors."""
import shutil

import laspy
import numpy as np
import pytest
from easyidp_toolbox.tests.support.pc_helpers import polygon, random_rois, winding_inside

from easyidp_toolbox.core import (ROI, Cancelled, InputError, PointCloud, ROISet,
                                  crop_point_cloud, read_point_cloud)
from easyidp_toolbox.core.crs import transform_xy
from easyidp_toolbox.core.pointcloud import crop_indices


@pytest.mark.parametrize("name,k", [("autzen_trim.laz", 25), ("autzen_geo_proj.las", 6),
                                    ("simple.las", 8), ("simple.laz", 8)])
def test_real_crop_counts_and_records(realdata, tmp_path, name, k):
    src = realdata / "laspy" / name
    cloud = read_point_cloud(src, source_crs=None if "autzen" in name else "EPSG:2994")
    xyz = cloud.xyz
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    rmax = min(hi[:2] - lo[:2]) / 5
    rois = random_rois(lo, hi, k, np.random.default_rng(7), cloud.crs, rmin=rmax / 4, rmax=rmax)
    res = crop_point_cloud(cloud, rois, tmp_path / "out")
    truth = laspy.read(str(src))
    total = 0
    for roi in rois:
        inside = winding_inside(xyz[:, 0], xyz[:, 1], roi.rings)
        assert res.counts[roi.name] == inside.sum(), roi.name
        total += inside.sum()
        if not inside.any():
            assert roi.name not in res.files
            continue
        out = res.files[roi.name]
        assert out.suffix == src.suffix and out.exists()
        back = laspy.read(str(out))
        for dim in truth.point_format.dimension_names:
            np.testing.assert_array_equal(np.asarray(back[dim]), np.asarray(truth[dim])[inside],
                                          err_msg=f"{roi.name} {dim}")
        np.testing.assert_array_equal(read_point_cloud(out).xyz, xyz[inside])
        assert read_point_cloud(out).crs == cloud.crs
    assert total > 0
    assert not [p for p in (tmp_path / "out").iterdir() if p.name.startswith(".")]


def test_holes_multipart_and_z_range(tmp_path):
    rng = np.random.default_rng(3)
    n = 40_000
    xyz = np.column_stack([rng.uniform(0, 100, n), rng.uniform(0, 100, n), rng.uniform(0, 10, n)])
    cloud = PointCloud.from_arrays(xyz, {"id": np.arange(n, dtype=np.int32)}, crs=32654)
    square = np.array([[10.5, 10.5], [40.5, 10.5], [40.5, 40.5], [10.5, 40.5]])
    hole = np.array([[20.5, 20.5], [30.5, 20.5], [30.5, 30.5], [20.5, 30.5]])
    far_part = polygon(20.1, 80.2, 9.0)
    rois = ROISet([ROI("holed", [[square, hole]]), ROI("multi", [[square + 45.0], [far_part]])],
                  32654)
    idx, _, _ = crop_indices(cloud, rois, z_min=2.0, z_max=8.0)
    for roi, ii in zip(rois, idx):
        expect = np.flatnonzero(winding_inside(xyz[:, 0], xyz[:, 1], roi.rings)
                                & (xyz[:, 2] >= 2) & (xyz[:, 2] <= 8))
        np.testing.assert_array_equal(ii, expect)
    assert not np.any((xyz[idx[0], 0] > 20.5) & (xyz[idx[0], 0] < 30.5)
                      & (xyz[idx[0], 1] > 20.5) & (xyz[idx[0], 1] < 30.5))
    res = crop_point_cloud(cloud, rois, tmp_path, fmt="ply", z_min=2.0, z_max=8.0)
    back = read_point_cloud(res.files["multi"])
    np.testing.assert_array_equal(back.attribute("id"), idx[1])
    np.testing.assert_array_equal(back.xyz, xyz[idx[1]])


def test_rois_reprojected_to_cloud_crs(tmp_path, realdata):
    cloud = read_point_cloud(realdata / "laspy" / "autzen_trim.laz")
    xyz = cloud.xyz
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    native = random_rois(lo, hi, 6, np.random.default_rng(11), cloud.crs)
    lonlat = native.to_crs(4326)
    assert abs(lonlat[0].rings[0][0, 0] + 123) < 1  # Oregon, lon first
    res = crop_point_cloud(cloud, lonlat, tmp_path)
    for roi in lonlat:
        back = [transform_xy(lonlat.crs, cloud.crs, r) for r in roi.rings]
        assert res.counts[roi.name] == winding_inside(xyz[:, 0], xyz[:, 1], back).sum()
    assert sum(res.counts.values()) > 0


def test_missed_and_empty_rois_reported(tmp_path, realdata):
    cloud = read_point_cloud(realdata / "laspy" / "simple.las", source_crs=2994)
    lo, hi = cloud.bounds()
    cx, cy = (lo[:2] + hi[:2]) / 2
    rois = ROISet([ROI("far away", [[polygon(cx + 1e5, cy, 10)]]),
                   ROI("centre", [[polygon(cx, cy, 200)]]),
                   ROI("tiny gap", [[polygon(cx + 0.001, cy + 0.001, 0.05)]])], 2994)
    res = crop_point_cloud(cloud, rois, tmp_path / "a")
    assert res.missed == ["far away"]
    assert res.counts["centre"] > 0
    assert res.empty == ["tiny gap"] and res.counts["tiny gap"] == 0
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == ["centre.las"]
    assert any("far away" in m for m in res.messages) and any("tiny gap" in m for m in res.messages)
    res = crop_point_cloud(cloud, rois, tmp_path / "b", fmt="laz", write_empty=True)
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == ["centre.laz", "tiny gap.laz"]
    assert len(read_point_cloud(res.files["tiny gap"])) == 0


def test_no_crs_is_refused_with_a_clear_message(tmp_path, realdata):
    rois = ROISet([ROI("p", [[polygon(637000, 849000, 50)]])], 2994)
    with pytest.raises(InputError, match="simple.las.*no coordinate reference system.*crs="):
        crop_point_cloud(realdata / "laspy" / "simple.las", rois, tmp_path)
    arr_cloud = PointCloud.from_arrays(np.array([[637000.0, 849000.0, 1.0]]))
    with pytest.raises(InputError, match="INPUT_CRS"):
        crop_point_cloud(arr_cloud, rois, tmp_path)
    res = crop_point_cloud(realdata / "laspy" / "simple.las", rois, tmp_path, source_crs=2994)
    assert list(res.counts) == ["p"]


def test_cancel_leaves_no_file(tmp_path, realdata):
    cloud = read_point_cloud(realdata / "laspy" / "autzen_trim.laz")
    lo, hi = cloud.bounds()
    rois = random_rois(lo, hi, 10, np.random.default_rng(5), cloud.crs)
    seen = []
    calls = {"n": 0}

    def cancel_during_writes():
        calls["n"] += 1
        return len(seen) > 0 and seen[-1] > 70  # after some files are written

    with pytest.raises(Cancelled):
        crop_point_cloud(cloud, rois, tmp_path / "w", progress=seen.append,
                         is_cancelled=cancel_during_writes)
    assert list((tmp_path / "w").iterdir()) == []
    with pytest.raises(Cancelled):  # cancelled during the pass: nothing written either
        crop_point_cloud(cloud, rois, tmp_path / "p", is_cancelled=lambda: True, chunk_size=1000)
    assert list((tmp_path / "p").iterdir()) == []
    assert calls["n"] > 1


def test_never_overwrites_the_input(tmp_path, realdata):
    src = tmp_path / "plot.las"
    shutil.copy(realdata / "laspy" / "simple.las", src)
    before = src.read_bytes()
    lo, hi = read_point_cloud(src).bounds()
    rois = ROISet([ROI("plot", [[polygon(*(lo[:2] + hi[:2]) / 2, 50)]])], None)
    with pytest.raises(InputError, match="input file itself"):
        crop_point_cloud(src, rois, tmp_path)
    assert src.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plot.las"]


def test_duplicate_names_and_overlaps(tmp_path):
    xyz = np.array([[1.0, 1.0, 0.0], [2.0, 2.0, 0.0], [8.0, 8.0, 0.0]])
    cloud = PointCloud.from_arrays(xyz)
    sq = np.array([[0.5, 0.5], [3.5, 0.5], [3.5, 3.5], [0.5, 3.5]])
    rois = ROISet([ROI("a/b", [[sq]]), ROI("a/b", [[sq + 0.7]])])
    res = crop_point_cloud(cloud, rois, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_b.las", "a_b_2.las"]
    assert len(read_point_cloud(tmp_path / "a_b.las")) == 2
    assert len(read_point_cloud(tmp_path / "a_b_2.las")) == 1
    assert res.counts == {"a_b": 2, "a_b_2": 1}
    assert [i.name for i in res.items] == ["a/b", "a/b"]


def test_box_grid_pairs_are_every_point_in_every_box_extent():
    """Brute force written here: every (point, box) with the point inside the box's extent,
    edges included, ordered by point then box; points on box edges and corners, boxes of
    mixed sizes that overlap, any cell size."""
    from easyidp_toolbox.core.pointcloud import index
    rng = np.random.default_rng(3)
    lo = rng.uniform(0, 50, (60, 2))
    boxes = np.hstack([lo, lo + rng.uniform(0.5, 6, (60, 2))])
    pts = np.vstack([rng.uniform(-2, 58, (5000, 2)), boxes[:, :2], boxes[:, 2:],
                     boxes[:, [0, 3]], boxes[:, [2, 1]]])
    x, y = pts[:, 0], pts[:, 1]
    inside = (x[:, None] >= boxes[:, 0]) & (x[:, None] <= boxes[:, 2]) & \
        (y[:, None] >= boxes[:, 1]) & (y[:, None] <= boxes[:, 3])
    want = np.nonzero(inside)                       # row-major: by point, then box
    for cells in (1, 3, 6, 13):
        old, index.CELLS_PER_BOX = index.CELLS_PER_BOX, cells
        try:
            pt, box = index.BoxGrid(boxes).pairs(x, y)
        finally:
            index.CELLS_PER_BOX = old
        assert np.array_equal(pt, want[0]) and np.array_equal(box, want[1]), cells


def test_gather_records_is_fancy_indexing():
    from easyidp_toolbox.core.pointcloud.cloud import gather_records
    dt = np.dtype([("X", "<i4"), ("Y", "<i4"), ("Z", "<i4"), ("i", "<u2"), ("b", "u1")])
    rec = np.zeros(1000, dt)
    for name in dt.names:
        rec[name] = np.arange(1000) * 7 % 251
    idx = np.random.default_rng(0).integers(0, 1000, 300)
    assert gather_records(rec, idx).tobytes() == rec[idx].tobytes()
    assert gather_records(rec, idx).dtype == dt
    mask = rec["X"] > 100
    assert gather_records(rec, mask).tobytes() == rec[mask].tobytes()
