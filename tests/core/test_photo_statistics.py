"""Plot statistics from the raw photos (core/projection/photo_stats.py, pixel_occlusion.py,
core/indices.py).

Independent checks, each saying its kind of truth:
- brute force: one polygon in one photo rasterised pixel by pixel with shapely's
  point-in-polygon (not our scanline), the statistics computed with numpy directly: identical;
- numpy's own median/percentile against our order statistics from histograms (integers);
- scikit-image's Otsu on the raw values against ours on the pooled histogram;
- a synthetic scene true by construction: a flat field and a 6 m box, the photo painted by the
  test's own pinhole ray casting (an analytic ray–box–plane test): the pixels hidden by the box
  are left out, their share is right; a ROI half outside the frame counts only its pixels in
  the frame;
- the demo survey's analytic colour truth (ExG and cover from the generator's closed-form
  model), and its orthomosaic rendered with ghosting and blur: the photos are within the stated
  tolerance and closer to the truth than the orthomosaic crop on every defective plot.
"""
import json
import sys
from pathlib import Path

import imagecodecs
import numpy as np
import pytest
import shapely
import tifffile
from pyproj import CRS

from easyidp_toolbox.core import indices as ix
from easyidp_toolbox.core.errors import Cancelled, EasyIDPError, InputError
from easyidp_toolbox.core.projection import back_project, photo_statistics
from easyidp_toolbox.core.photos import decode as photos_module
from easyidp_toolbox.core.projection.across_views import weighted_median
from easyidp_toolbox.core.projection.order_stats import order_stats_float, order_stats_int
from easyidp_toolbox.core.projection.result import BackProjection
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.core.reconstruction import Calibration, Camera, Reconstruction, Sensor
from easyidp_toolbox.core.reconstruction.geodesy import OffsetFrame
from easyidp_toolbox.core.roi import ROI, ROISet

sys.path.insert(0, str(Path(__file__).parent))
from easyidp_toolbox.tests.support.synthetic import write_tif  # noqa: E402

UTM = CRS.from_epsg(32654)
OFFSET = np.array([368000.0, 3956000.0, 0.0])
NADIR = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])
W, H = 800, 600


def _project(tmp_path, cams, images, cal=None, ext="png", bands=3):
    """A Reconstruction of ``cams`` [(R, C)] with the photos ``images`` written to disk."""
    cal = cal or Calibration(f=680.0, cx=403.2, cy=297.9)
    sensor = Sensor("0", "synthetic", W, H, cal)
    folder = tmp_path / "photos"
    folder.mkdir(exist_ok=True)
    out = []
    for i, ((R, C), img) in enumerate(zip(cams, images)):
        path = folder / f"IMG_{i}.{ext}"
        if ext == "png":
            path.write_bytes(imagecodecs.png_encode(img))
        else:
            tifffile.imwrite(path, img, photometric="rgb" if bands == 3 else "minisblack",
                             planarconfig="contig")
        out.append(Camera(str(i), f"IMG_{i}", "0", photo_path=str(path), R=R, C=np.asarray(C, float)))
    return Reconstruction(Path("synthetic"), "synthetic", "s", UTM, OffsetFrame(UTM, OFFSET),
                          {"0": sensor}, out)


def _rois(*rings):
    return ROISet([ROI(f"r{k}", [[np.asarray(r, float) + OFFSET[:2]]]) for k, r in
                   enumerate(rings)], UTM)


def _inside_shapely(polys, shape):
    """Pixel centres inside the polygons, by shapely (an independent point-in-polygon)."""
    geom = shapely.MultiPolygon([shapely.Polygon(p[0], p[1:]) for p in polys])
    cc, rr = np.meshgrid(np.arange(shape[1]) + 0.5, np.arange(shape[0]) + 0.5)
    return shapely.contains_xy(geom, cc, rr)


def _reference(values, stats=("mean", "median", "std"), qs=()):
    """numpy directly."""
    out = []
    for s in stats:
        out.append({"mean": np.mean, "median": np.median, "std": np.std}[s](values))
    out += list(np.percentile(values, qs)) if len(qs) else []
    return out


# --- indices and order statistics -------------------------------------------------------------
def test_indices_are_their_formulas_and_bins_are_exact():
    rng = np.random.default_rng(3)
    v = rng.integers(0, 256, (5, 4000)).astype(np.float64)
    names = ["blue", "green", "red", "rededge", "nir"]
    b, g, r, re, nir = v
    with np.errstate(invalid="ignore", divide="ignore"):
        truth = {"exg": (2 * g - r - b) / (r + g + b), "exgr": (3 * g - 2.4 * r - b) / (r + g + b),
                 "vari": (g - r) / (g + r - b), "gli": (2 * g - r - b) / (2 * g + r + b),
                 "ndvi": (nir - r) / (nir + r), "ndre": (nir - re) / (nir + re)}
    assert ix.available(names) == list(ix.INDICES)
    for kind, t in truth.items():
        t[~np.isfinite(t)] = np.nan
        np.testing.assert_array_equal(ix.compute(kind, v, names), t)
    # exact bins: a value is in bin k iff edges[k] <= v < edges[k + 1]
    for kind in ix.INDEX_RANGE:
        e = ix.bin_edges(kind)
        vals = np.concatenate([e[::7], rng.uniform(e[0], e[-1], 5000)])
        k = ix.bins_of(kind, vals)
        assert np.all(vals >= e[k]) and np.all((vals < e[k + 1]) | (k == ix.INDEX_BINS - 1))
    # a cover from the pooled histogram at Otsu's threshold equals the share of the raw values
    exg = truth["exg"][np.isfinite(truth["exg"])]
    start, counts = ix.index_histogram("exg", exg)
    full = np.zeros(ix.INDEX_BINS, np.int64)
    ix.add_histogram(full, (start, counts))
    t = ix.otsu_threshold("exg", full)
    assert ix.cover_from_histogram("exg", (start, counts), t) == ix.cover(exg, t)
    from skimage.filters import threshold_otsu
    assert abs(t - threshold_otsu(exg, nbins=ix.INDEX_BINS)) < 0.01
    assert ix.canonical_band("Red Edge") == "rededge" and ix.canonical_band("NIR") == "nir"
    with pytest.raises(EasyIDPError, match="Unknown vegetation index"):
        ix.check_indices(["exg", "ndwi"])


def test_order_statistics_from_histograms_are_numpys():
    rng = np.random.default_rng(5)
    qs = (0.0, 2.5, 5.0, 25.0, 33.3, 50.0, 75.0, 95.0, 99.9, 100.0)
    for n in (1, 2, 3, 10, 101, 1000, 4097):
        for top in (256, 65536):
            v = rng.integers(0, top, n).astype(np.float64)
            med, pct = order_stats_int(v, True, qs)
            assert med == np.median(v)
            assert list(pct) == list(np.percentile(v, qs)), (n, top)
    # floats (index values): few and many, with ties, one value, a wide spread
    for n in (1, 7, 5000, 20001):
        for v in (rng.normal(0.3, 0.2, n), np.round(rng.normal(0, 1, n), 2), np.full(n, 0.25),
                  np.concatenate([rng.normal(0, 1, n - 1), [1e6]])):
            med, pct = order_stats_float(v, True, qs)
            assert med == np.median(v) and list(pct) == list(np.percentile(v, qs)), n


def test_weighted_median():
    x = np.array([3.0, 1.0, 2.0, 10.0])
    assert weighted_median(x, np.ones(4)) == np.median(x)
    assert weighted_median(x[:3], np.ones(3)) == 2.0
    assert weighted_median(x, np.array([0.1, 0.1, 0.1, 5.0])) == 10.0
    assert weighted_median(x, np.array([1.0, 1.0, 2.0, 0.0])) == 2.0   # half reached at 2: [1,2]|
    assert np.isnan(weighted_median(x, np.zeros(4)))


# --- brute force: one polygon in one photo ---------------------------------------------------
@pytest.fixture(scope="module")
def flat(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("flat")
    rng = np.random.default_rng(11)
    images = []
    for i in range(3):
        img = rng.integers(0, 256, (H, W, 3)).astype(np.uint8)
        img[..., 1] = np.clip(img[..., 1].astype(int) + 60 * (i + 1), 0, 255)   # some "green"
        images.append(img)
    recon = _project(tmp, [(NADIR, [3.0 * i, 0.0, 30.0]) for i in range(3)], images)
    # an irregular ROI with vertices off the pixel grid (no centre lies exactly on an edge)
    ring = np.array([[-4.013, -2.507], [3.121, -3.333], [5.477, 1.905], [0.713, 4.219],
                     [-3.377, 2.641]])
    hole = np.array([[-0.5, -0.5], [0.61, -0.53], [0.37, 0.77]])
    rois = ROISet([ROI("plot", [[ring + OFFSET[:2], hole + OFFSET[:2]]]),
                   ROI("small", [[np.array([[8.03, 1.01], [10.07, 1.13], [9.51, 3.02]]) + OFFSET[:2]]])], UTM)
    res = back_project(rois, recon, heights=0.0, min_visible=0.0)
    return recon, rois, res, images, tmp


def test_brute_force_identical(flat):
    recon, rois, res, images, tmp = flat
    qs = (5.0, 50.0, 95.0)
    st = photo_statistics(res, statistics=("mean", "median", "std"), percentiles=qs,
                          cover_threshold=0.1)
    assert st.columns[:5] == ["red_mean", "red_median", "red_std", "red_p5", "red_p50"]
    assert st.indices == ["exg", "exgr", "vari", "gli"] and st.cover_index == "exg"
    checked = 0
    for k in range(len(st.record)):
        i = st.record[k]
        j = int(res.photo_index[i])
        img = images[j]
        inside = _inside_shapely(res.polygons_of(i), img.shape[:2])
        v = img[inside].astype(np.float64)
        assert st.pixels[k] == st.polygon_pixels[k] == inside.sum()
        ref = []
        for b in range(3):
            ref += _reference(v[:, b], qs=qs)
        for kind in ("exg", "exgr", "vari", "gli"):
            idx = ix.compute(kind, v.T, ["red", "green", "blue"])
            ref += _reference(idx[np.isfinite(idx)], qs=qs)
        exg = (2 * v[:, 1] - v[:, 0] - v[:, 2]) / v.sum(axis=1)
        ref.append(np.mean(exg[np.isfinite(exg)] >= 0.1))
        np.testing.assert_allclose(st.values[k], ref, rtol=1e-12, atol=0)
        assert st.gsd[k] == res.gsd[i] and st.roi_names[st.roi[k]] == res.roi_names[res.roi[i]]
        checked += 1
    assert checked == len(res) >= 4
    # across views: plain medians, MAD, min, max of the views used
    r = st.roi_names.index("plot")
    sel = np.flatnonzero((st.roi == r) & st.used)
    q = st.columns.index("green_mean")
    g = st.values[sel, q]
    assert st.roi_value("green_mean")[r] == np.median(g) and st.views[r] == len(sel) == 3
    assert st.mad[r, q] == np.median(np.abs(g - np.median(g)))
    assert st.minimum[r, q] == g.min() and st.maximum[r, q] == g.max()


def test_otsu_cover_is_the_raw_share_at_the_pooled_threshold(flat):
    recon, rois, res, images, tmp = flat
    st = photo_statistics(res, statistics=("mean",), indices=["exg"])
    assert st.threshold_source.startswith("Otsu") and st.cover_threshold is not None
    for k in range(len(st.record)):
        i = st.record[k]
        img = images[int(res.photo_index[i])]
        v = img[_inside_shapely(res.polygons_of(i), img.shape[:2])].astype(np.float64)
        exg = (2 * v[:, 1] - v[:, 0] - v[:, 2]) / v.sum(axis=1)
        assert st.column("cover")[k] == np.mean(exg[np.isfinite(exg)] >= st.cover_threshold)


def test_each_photo_decoded_once_and_weighting_and_selection(flat):
    recon, rois, res, images, tmp = flat
    decoded = []
    real = photos_module.read_photo
    photos_module.read_photo = lambda p: decoded.append(p) or real(p)
    try:
        st = photo_statistics(res, workers=2, max_views=2, weighted=True)
    finally:
        photos_module.read_photo = real
    assert len(decoded) == len(set(decoded)) == len(set(res.photo)) == st.photos_decoded
    r = st.roi_names.index("plot")
    sel = np.flatnonzero(st.roi == r)
    used = sel[st.used[sel]]
    assert len(used) == 2 and set(st.rank[used]) == {1, 2}
    assert all(st.why[k] == "beyond the views per ROI" for k in sel if not st.used[k])
    q = st.columns.index("red_mean")
    assert st.median[r, q] == weighted_median(st.values[used, q], st.score[used])
    # the minimum visible share leaves views out
    from dataclasses import replace
    part = replace(res, visible_fraction=np.where(res.photo == "IMG_2", 0.4, 1.0))
    st2 = photo_statistics(part, min_visible=0.5)
    for k in range(len(st2.record)):
        assert st2.used[k] == (res.photo[k] != "IMG_2")
        assert st2.used[k] or st2.why[k] == "below the minimum visible share"


def test_a_shadow_in_one_view_is_flagged(tmp_path):
    """A 3 × 3 grid of plots in three photos; in the third, a "cloud shadow" darkens the centre
    plot: its views disagree (and that view deviates) far more than the field's typical, and the
    median of the three views is that of the two unshaded ones' side."""
    rng = np.random.default_rng(4)
    images = [rng.integers(60, 200, (H, W, 3)).astype(np.uint8) for _ in range(3)]
    f, cx, cy = 680.0, 403.2, 297.9
    u0, u1 = int(cx + f * (-4.5) / 30), int(cx + f * (-1.5) / 30)     # plot at x = 3 m from x = 6
    v0, v1 = int(cy - f * 1.5 / 30), int(cy + f * 1.5 / 30)
    images[2][v0:v1, u0:u1] //= 2
    recon = _project(tmp_path, [(NADIR, [3.0 * i, 0.0, 30.0]) for i in range(3)], images)
    sq = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    rois = _rois(*[sq + [3 + dx, dy] for dy in (-4, 0, 4) for dx in (-4, 0, 4)])
    res = back_project(rois, recon, heights=0.0, min_visible=0.0)
    st = photo_statistics(res, statistics=("mean",), indices=["exg"])
    centre = st.roi_names.index("r4")
    assert np.all(st.views == 3)
    others = np.delete(st.disagreement, centre)
    print(f"\nshadowed plot: disagreement {st.disagreement[centre]:.1f}, others median "
          f"{np.median(others):.2f}")
    assert st.disagreement[centre] > 10 * np.median(others) and np.median(others) < 3
    k = int(np.nanargmax(st.deviation))
    assert st.roi[k] == centre and st.photo[k] == "IMG_2"
    q = st.columns.index("red_mean")
    sel = np.flatnonzero(st.roi == centre)
    assert st.median[centre, q] == np.median(st.values[sel, q]) > st.values[k, q] + 30


def test_rebuilt_from_records_gives_the_same_values(flat):
    """The route of the QGIS tool's photo-pixel layer input."""
    recon, rois, res, images, tmp = flat
    recs = [{"roi": res.roi_names[res.roi[i]], "photo": str(res.photo[i]),
             "polygons": res.polygons_of(i), "rank": int(res.rank[i]), "score": res.score[i],
             "gsd": res.gsd[i], "visible_fraction": res.visible_fraction[i]} for i in range(len(res))]
    photos = {lab: {"path": p, "width": int(s[0]), "height": int(s[1])}
              for lab, p, s in zip(res.photo_labels, res.photo_paths, res.image_sizes)}
    again = BackProjection.from_records(res.roi_names, recs[::-1], photos)
    a = photo_statistics(res, cover_threshold=0.1)
    b = photo_statistics(again, cover_threshold=0.1)
    np.testing.assert_array_equal(a.median, b.median)
    with pytest.raises(EasyIDPError, match="not among the ROIs"):
        BackProjection.from_records(["other"], recs, photos)


def test_previews_one_per_roi_with_values(flat):
    recon, rois, res, images, tmp = flat
    folder = tmp / "previews"
    st = photo_statistics(res, previews_folder=folder, preview_views=2)
    assert [Path(p).name for p in st.previews] == ["plot.png", "small.png"]
    sheet = imagecodecs.imread(st.previews[0])
    assert sheet.ndim == 3 and sheet.shape[2] == 3 and sheet.shape[0] > 256
    with pytest.raises(InputError, match="already exists|Nothing was written"):
        photo_statistics(res, previews_folder=folder)
    photo_statistics(res, previews_folder=folder, overwrite=True)


def test_bad_inputs_are_named(flat, tmp_path):
    recon, rois, res, images, tmp = flat
    for kw, msg in (({"statistics": ["mean", "mode"]}, "Unknown statistic mode"),
                    ({"percentiles": [5, 120]}, "outside 0–100"),
                    ({"percentiles": ["x"]}, "not a number"),
                    ({"indices": ["ndwi"]}, "Unknown vegetation index"),
                    ({"min_visible": 2}, "between 0 and 1"),
                    ({"max_views": -1}, "0 \\(all\\) or more"),
                    ({"statistics": [], "percentiles": []}, "No statistic"),
                    ({"bands": ["red", "green"]}, "3 band\\(s\\) but 2"),
                    ({"bands": ["red", "red", "blue"]}, "must differ"),
                    ({"occlusion_dsm": "dsm.tif"}, "needs the photogrammetry project"),
                    ({"occlusion_dsm": "dsm.tif", "recon": recon,
                      "rois": ROISet([rois[0]], UTM)}, "not those of the back-projection")):
        with pytest.raises(EasyIDPError, match=msg):
            photo_statistics(res, **kw)
    with pytest.raises(InputError, match="does not exist"):
        photo_statistics(res, tmp_path / "nowhere")
    # a missing photo and one of another size are skipped, named, and the rest measured
    moved = tmp_path / "moved"
    moved.mkdir()
    (moved / "IMG_0.png").write_bytes(imagecodecs.png_encode(images[0]))
    (moved / "IMG_1.png").write_bytes(imagecodecs.png_encode(images[1][:300]))
    st = photo_statistics(res, moved)
    assert set(st.skipped_photos) == {"IMG_1", "IMG_2"} and "300" in st.skipped_photos["IMG_1"]
    assert st.photos_decoded == 1 and st.used.sum() == int((res.photo == "IMG_0").sum())
    assert all(st.why[k] == "photo not available" for k in range(len(st.record)) if not st.used[k])
    # a photo with other bands than the first (another camera of the project) is skipped
    (moved / "IMG_2.png").write_bytes(imagecodecs.png_encode(np.ascontiguousarray(images[2][..., 0])))
    (moved / "IMG_1.png").write_bytes(imagecodecs.png_encode(images[1]))
    st = photo_statistics(res, moved)
    assert list(st.skipped_photos) == ["IMG_2"] and "1 band(s)" in st.skipped_photos["IMG_2"]
    # cancelling stops the run, and no preview is left behind
    calls = []
    with pytest.raises(Cancelled):
        photo_statistics(res, moved, previews_folder=tmp_path / "pv",
                         is_cancelled=lambda: calls.append(1) or len(calls) > 2)
    assert not [p for p in (tmp_path / "pv").iterdir() if not p.name.startswith(".easyidp")]


def test_16bit_multispectral_keeps_its_values(tmp_path):
    """Truth kind: brute force on a 5-band uint16 photo (values up to 60000): no 8-bit
    conversion; NDVI and NDRE from the named bands; cover on NDVI."""
    rng = np.random.default_rng(2)
    img = rng.integers(1000, 60000, (H, W, 5)).astype(np.uint16)
    img[:, :400, 4] = 50000                        # a "vegetated" west half: high nir
    img[:, :400, 2] = 5000
    recon = _project(tmp_path, [(NADIR, [0.0, 0.0, 30.0])], [img], ext="tif", bands=5)
    rois = _rois(np.array([[-3.1, -2.03], [2.9, -2.11], [3.05, 2.2], [-2.93, 2.07]]))
    res = back_project(rois, recon, heights=0.0, min_visible=0.0)
    st = photo_statistics(res, bands=["Blue", "Green", "Red", "Red Edge", "NIR"],
                          statistics=("mean", "median"), percentiles=(99,), cover_threshold=0.5)
    assert st.bands == ["blue", "green", "red", "rededge", "nir"]
    assert st.indices == ["exg", "exgr", "vari", "gli", "ndvi", "ndre"] and st.cover_index == "ndvi"
    inside = _inside_shapely(res.polygons_of(0), (H, W))
    v = img[inside].astype(np.float64)
    assert st.column("nir_mean")[0] == pytest.approx(v[:, 4].mean(), rel=1e-12)
    assert st.column("nir_p99")[0] == np.percentile(v[:, 4], 99) and st.column("nir_p99")[0] > 255
    ndvi = (v[:, 4] - v[:, 2]) / (v[:, 4] + v[:, 2])
    assert st.column("ndvi_median")[0] == pytest.approx(np.median(ndvi), rel=1e-12)
    assert st.column("cover")[0] == np.mean(ndvi >= 0.5)
    ndre = (v[:, 4] - v[:, 3]) / (v[:, 4] + v[:, 3])
    assert st.column("ndre_mean")[0] == pytest.approx(ndre.mean(), rel=1e-12)


# --- a scene true by construction: half outside the frame, half hidden by a box ---------------
BOX = (np.array([-2.0, -2.0, 0.0]), np.array([2.0, 2.0, 6.0]))
RED, GREEN, BLUE = (220, 20, 20), (20, 200, 20), (20, 20, 220)


def _look_at(C, target):
    z = np.asarray(target, float) - C
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    return np.array([x, np.cross(z, x), z])


def _paint(R, C, f, cx, cy, roi_ring):
    """The photo by the test's own pinhole ray casting: red where the first hit is the box,
    green where it is the ground inside the ROI, blue elsewhere; and which pixels see the box."""
    v, u = np.mgrid[0:H, 0:W]
    d = np.column_stack([(u.ravel() + 0.5 - cx) / f, (v.ravel() + 0.5 - cy) / f,
                         np.ones(u.size)]) @ R
    lo, hi = BOX
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - C) / d, (hi - C) / d
    tmin = np.max(np.minimum(t1, t2), axis=1)
    tmax = np.min(np.maximum(t1, t2), axis=1)
    box = (tmax >= tmin) & (tmax > 0)
    tg = -C[2] / d[:, 2]
    g = C[:2] + tg[:, None] * d[:, :2]
    on_roi = shapely.contains_xy(shapely.Polygon(roi_ring), g[:, 0], g[:, 1])
    img = np.empty((u.size, 3), np.uint8)
    img[:] = BLUE
    img[on_roi] = GREEN
    img[box] = RED
    return img.reshape(H, W, 3), box.reshape(H, W)


@pytest.fixture(scope="module")
def box_scene(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("box")
    half, px = 20.0, 0.02
    n = int(2 * half / px)
    z = np.zeros((n, n), np.float32)
    c = (np.arange(n) + 0.5) * px - half
    z[(np.abs(c)[None, :] <= 2.0) & (np.abs(c)[:, None] <= 2.0)] = 6.0
    dsm = write_tif(str(tmp / "dsm.tif"), z, origin=(OFFSET[0] - half, OFFSET[1] + half), pixel=px,
                    tile=256)
    f, cx, cy = 900.0, 400.0, 300.0
    behind = np.array([[2.6, -3.0], [8.0, -3.0], [8.0, 3.0], [2.6, 3.0]])
    poses = [np.array([-14.0, 0.0, 30.0]), np.array([1.0, 0.5, 40.0])]
    Rs = [_look_at(C, [3.0, 0.5, 0.0]) for C in poses]
    painted = [_paint(R, C, f, cx, cy, behind) for R, C in zip(Rs, poses)]
    recon = _project(tmp, list(zip(Rs, poses)), [p[0] for p in painted],
                     cal=Calibration(f=f, cx=cx, cy=cy))
    rois = _rois(behind)
    return recon, rois, dsm, painted


def test_pixels_hidden_by_a_box_are_left_out(box_scene):
    recon, rois, dsm, painted = box_scene
    res = back_project(rois, recon, heights=0.0, occlusion_dsm=DSM(dsm), min_visible=0)
    plain = photo_statistics(res, indices=[], statistics=("mean",))
    st = photo_statistics(res, indices=[], statistics=("mean",), recon=recon, rois=rois,
                          occlusion_dsm=DSM(dsm))
    for k in range(len(st.record)):
        i = st.record[k]
        j = int(res.photo_index[i])
        inside = _inside_shapely(res.polygons_of(i), (H, W))
        truth = painted[j][1][inside].mean()             # analytic: the pixel's ray meets the box
        print(f"\n{res.photo[i]}: occluded share {st.occluded_share[k]:.4f}, truth {truth:.4f}, "
              f"red mean kept {st.column('red_mean')[k]:.1f}, without the test "
              f"{plain.column('red_mean')[k]:.1f}")
        assert st.occluded_share[k] == pytest.approx(truth, abs=0.01)
        assert st.pixels[k] == st.polygon_pixels[k] - round(st.occluded_share[k] * st.polygon_pixels[k])
        # what is kept is the ROI's ground (green); the box (red) is gone but for edge pixels
        red_kept = (st.column("red_mean")[k] - GREEN[0]) / (RED[0] - GREEN[0]) * st.pixels[k]
        assert red_kept < 0.01 * st.polygon_pixels[k]
        if truth > 0.2:
            assert plain.column("red_mean")[k] > 60      # without the test the box is measured
            assert st.visible_share[k] == pytest.approx(res.visible_fraction[i] * (1 - truth), abs=0.01)
    assert np.nanmax(st.occluded_share) > 0.2 and np.nanmin(st.occluded_share) < 0.01
    assert st.rays > 0 and any("lines of sight" in n for n in st.notes)


def test_roi_half_outside_the_frame_counts_its_pixels_in_the_frame(tmp_path):
    """Truth kind: the unclipped polygon (projected vertices) rasterised by shapely on a canvas
    three times the photo, then cut at the frame."""
    img = np.zeros((H, W, 3), np.uint8)
    img[:, :, 1] = 200
    recon = _project(tmp_path, [(NADIR, [0.0, 0.0, 30.0])], [img])
    ring = np.array([[8.03, -3.01], [25.13, -3.07], [25.2, 3.11], [8.09, 3.02]])   # x > 17.8 m out
    rois = _rois(ring)
    res = back_project(rois, recon, heights=0.0, min_visible=0.0)
    st = photo_statistics(res)
    uv = recon.project_points(np.column_stack([ring + OFFSET[:2], np.zeros(4)]), UTM).pixels[0]
    big = _inside_shapely([[uv + [W, H]]], (3 * H, 3 * W))
    full = big.sum()
    in_frame = big[H:2 * H, W:2 * W].sum()
    assert res.clipped[0] and 0.3 < in_frame / full < 0.7
    assert st.pixels[0] == st.polygon_pixels[0] == in_frame
    assert res.visible_fraction[0] == pytest.approx(in_frame / full, abs=0.01)
    assert st.column("green_mean")[0] == 200.0


# --- the demo survey: colour truth, and the orthomosaic with ghosting and blur ---------------
EXG_TOLERANCE, COVER_TOLERANCE = 0.015, 0.03
"""Stated tolerances of the across-view values (3 best views) against the analytic truth."""


@pytest.fixture(scope="module")
def defects_survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import NO_MESS, make_demo_survey
    # the tidy field (NO_MESS): on issue 32's messy field the 3 best views see the tall rows
    # obliquely, hiding soil the nadir colour truth counts (ExG error up to 0.064, tolerance
    # 0.015); a view-dependent colour truth is the follow-up
    s = make_demo_survey(str(tmp_path_factory.mktemp("defects")), seed=0, size="small",
                         field_mess=NO_MESS,
                         ortho_defects=True)
    with open(s.truth) as fh:
        s.truth_doc = json.load(fh)
    return s


def _orthomosaic_traits(survey, rois):
    """ExG and cover of the orthomosaic crops, by the season tool's engine (Otsu per
    orthomosaic), the product's statistics of an orthomosaic."""
    from easyidp_toolbox.core.season import run_season
    from easyidp_toolbox.core.season.series import surveys_from_rows
    table = surveys_from_rows([{"date": "2024-06-01", "orthomosaic": survey.orthomosaic}],
                              survey.folder)
    t = run_season(table, rois, traits=["index", "cover"], workers=1).table()
    return {n: t[(n, "2024-06-01")] for n in rois.names}


def test_demo_plots_against_the_colour_truth_and_the_orthomosaic(defects_survey):
    from easyidp_toolbox.core import open_reconstruction
    from easyidp_toolbox.core.roi import read_geojson
    s = defects_survey
    truth = s.truth_doc["plots"]
    defects = s.truth_doc["ortho_defects"]
    rois = read_geojson(s.plots_geojson, name_field="plot_id")
    recon = open_reconstruction(s.metashape_project)
    dsm = DSM(s.dsm)
    res = back_project(rois, recon, heights=dsm, occlusion_dsm=dsm, min_visible=0.0)
    st = photo_statistics(res, statistics=("mean",), indices=["exg"], max_views=3,
                          recon=recon, rois=rois, occlusion_dsm=dsm)
    exg = dict(zip(st.roi_names, st.roi_value("exg_mean")))
    cover = dict(zip(st.roi_names, st.roi_value("cover")))
    e_photo = {n: exg[n] - truth[n]["exg"] for n in truth}
    c_photo = {n: cover[n] - truth[n]["cover"] for n in truth}
    print(f"\nphotos (3 best views): ExG error max {max(map(abs, e_photo.values())):.4f}, cover "
          f"error max {max(map(abs, c_photo.values())):.4f} over {len(truth)} plots; "
          f"threshold {st.cover_threshold:.3f}")
    assert max(map(abs, e_photo.values())) < EXG_TOLERANCE
    assert max(map(abs, c_photo.values())) < COVER_TOLERANCE
    assert np.all(st.views == 3) and np.nanmax(st.occluded_share) < 0.01
    ortho = _orthomosaic_traits(s, rois)
    for kind in ("ghosting", "blur"):
        for n in defects[kind]:
            e_o = ortho[n]["exg"] - truth[n]["exg"]
            c_o = ortho[n]["cover"] - truth[n]["cover"]
            print(f"{kind} {n}: ExG error photos {e_photo[n]:+.4f}, orthomosaic {e_o:+.4f}; "
                  f"cover error photos {c_photo[n]:+.4f}, orthomosaic {c_o:+.4f}")
            assert abs(e_photo[n]) < abs(e_o) and abs(c_photo[n]) < abs(c_o)
