"""Backward projection (core/projection): ROIs into the raw photos that see them.

Independent checks, by kind:
- demo survey truth (generated with the true poses, written before any of this code ran):
  whole-only photo sets per plot (the generator's, made with the production camera model:
  consistency only), corner pixels (independent: ``tests/support/independent_camera.py``),
  and visible fractions against a dense ground sampling of each plot (consistency only: the
  sampling is projected by our reader);
- synthetic scenes true by construction (a camera looking at the horizon, a ROI around the
  whole view): no fold-back, fractions against a dense ground sampling;
- the real wheat_tanashi markers as tiny ROIs against Metashape's own pinned observations;
- the real Pix4D roi.shp on the real Pix4D project;
- bad input: each case names what to fix.
The side-by-side with easyidp 2.0.4 is in test_backward_vs_easyidp.py.
"""
import json
from pathlib import Path

import numpy as np
import pytest
from pyproj import CRS

from easyidp_toolbox.core import EasyIDPError, ROIError, open_reconstruction
from easyidp_toolbox.core.demo import make_demo_survey
from easyidp_toolbox.core.geometry import points_in_rings
from easyidp_toolbox.core.projection import (BackProjection, PerROIHeights, back_project,
                                             read_easyidp_json)
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.core.reconstruction import (INSIDE, Calibration, Camera, Reconstruction,
                                                 Sensor)
from easyidp_toolbox.core.reconstruction.geodesy import LocalFrame, OffsetFrame
from easyidp_toolbox.core.roi import ROI, ROISet, read_geojson
from easyidp_toolbox.tests.support import independent_camera

NO_DENSIFY = 1e12   # densify_tolerance that keeps the input vertices only


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    return make_demo_survey(str(tmp_path_factory.mktemp("bp_survey")), seed=0, size="small")


@pytest.fixture(scope="module")
def truth(survey):
    with open(survey.truth) as fh:
        return json.load(fh)


@pytest.fixture(scope="module")
def plots(survey):
    return read_geojson(survey.plots_geojson, name_field="plot_id")


@pytest.fixture(scope="module")
def metashape(survey):
    return open_reconstruction(survey.metashape_project)


# --- demo survey truth ----------------------------------------------------------------------------
@pytest.mark.parametrize("project", ["metashape", "pix4d"])
def test_whole_only_photo_sets_equal_the_truth(survey, truth, plots, project):
    """Consistency only (the generator computes photos_whole with the production camera): the
    demo truth's photo sets, every 10 cm of each plot's outline on the surface inside the frame."""
    recon = open_reconstruction(survey.metashape_project if project == "metashape"
                                else survey.pix4d_project)
    res = back_project(plots, recon, heights=DSM(survey.dsm), clip=False, min_visible=0)
    assert not res.clipped.any() and (res.visible_fraction == 1).all()
    for name in plots.names:
        ours = {Path(p).stem for p in res.photo[res.records_of(name)]}
        assert ours == set(truth["plots"][name]["photos_whole"]), name
    assert res.dropped["partly_outside"] > 0


def test_corners_land_on_the_true_pixels(survey, truth, plots, metashape):
    """Independent: the demo truth's plot corners (on the surface) against their pixels by the
    independent camera (tests/support/independent_camera.py), for the pairs the truth sees."""
    res = back_project(plots, metashape, heights=DSM(survey.dsm), clip=False,
                       min_visible=0, densify_tolerance=NO_DENSIFY)
    pix = independent_camera.observation_lookup(truth)
    worst, n = 0.0, 0
    for i in range(len(res)):
        ring = res.rings_of(i)[0]
        assert len(ring) == 4
        name = res.roi_names[res.roi[i]]
        for k in range(4):
            key = (f"{name}_c{k + 1}", res.photo[i])
            if key in pix:       # not hidden by a neighbour's crop
                worst = max(worst, float(np.abs(ring[k] - pix[key]).max()))
                n += 1
    print(f"\nplot corners vs truth: {n} vertices, max {worst:.1e} px")
    assert n > 500 and worst < 0.01


def _dense_fraction(recon, corners, n=(300, 200)):
    """Share of a dense grid over a plot (bilinear between its corners on the surface) inside
    each photo's frame: the truth of the visible fraction, by sampling."""
    u, v = np.meshgrid((np.arange(n[0]) + 0.5) / n[0], (np.arange(n[1]) + 0.5) / n[1])
    u, v = u.ravel()[:, None], v.ravel()[:, None]
    c = np.asarray(corners)
    pts = c[0] * (1 - u) * (1 - v) + c[1] * u * (1 - v) + c[2] * u * v + c[3] * (1 - u) * v
    p = recon.project_points(pts, "EPSG:32654")
    return dict(zip(p.camera_labels, (p.status == INSIDE).mean(axis=1)))


def test_clipped_visible_fractions_against_dense_sampling(survey, truth, plots, metashape):
    """Truth kind: dense ground sampling (60,000 points per plot) of the demo plots."""
    res = back_project(plots, metashape, heights=DSM(survey.dsm), clip=True, min_visible=0)
    assert res.clipped.sum() > 100
    errs = []
    for name in plots.names:
        frac = _dense_fraction(metashape, truth["plots"][name]["corners"])
        recs = res.records_of(name)
        assert {res.photo[i] for i in recs} == {k for k, f in frac.items() if f > 0}, name
        errs += [res.visible_fraction[i] - frac[res.photo[i]] for i in recs]
        for i in recs:            # polygons inside the frame, finite
            for ring in res.rings_of(i):
                assert np.isfinite(ring).all()
                assert ring.min() >= -1e-9 and (ring <= [800 + 1e-9, 600 + 1e-9]).all()
    errs = np.abs(errs)
    print(f"\nvisible fraction vs dense sampling: {len(errs)} pairs, max {errs.max():.4f}")
    assert errs.max() < 0.005


def test_ranking_fields_and_limits(survey, plots, metashape):
    res = back_project(plots, metashape, heights=DSM(survey.dsm), min_visible=0.5,
                       max_views=3)
    assert isinstance(res, BackProjection)
    counts = res.photos_per_roi()
    assert counts.max() <= 3 and (counts > 0).all()
    assert res.dropped["beyond_max_images"] > 0 and res.dropped["below_min_visible"] > 0
    for name in plots.names:
        recs = res.records_of(name)
        assert list(res.rank[recs]) == list(range(1, len(recs) + 1))
        assert (np.diff(res.score[recs]) <= 0).all()
    share = res.visible_fraction * (1 - np.nan_to_num(res.occluded_fraction))
    assert (share >= 0.5).all() and np.isnan(res.occluded_fraction).all()
    assert (res.score > 0).all() and (res.score <= 1).all()
    assert ((res.gsd > 0.02) & (res.gsd < 0.06)).all()          # 25 m, f = 680 px: ~3.7 cm
    assert ((res.view_angle >= 0) & (res.view_angle < 45)).all()
    assert ((res.centre_distance >= 0) & (res.centre_distance <= 1.01)).all()
    best = res.best()
    assert set(best) == set(plots.names)


def test_easyidp_dict_and_json(tmp_path, survey, plots, metashape):
    res = back_project(plots, metashape, heights=DSM(survey.dsm))
    d = res.to_easyidp_dict()
    assert list(d) == plots.names
    i = 0
    arr = d[res.roi_names[res.roi[i]]][res.photo[i]]
    assert np.array_equal(arr[0], arr[-1]) and len(arr) == len(res.rings_of(i)[0]) + 1
    path = res.write_easyidp_json(tmp_path / "roi_image_order.json")
    back = read_easyidp_json(path)
    assert back.keys() == d.keys()
    for roi, photos in d.items():
        assert list(back[roi]) == list(photos)
        for ph, a in photos.items():
            assert np.allclose(back[roi][ph], a, atol=1e-9)


# --- heights ------------------------------------------------------------------------------------------
def test_height_sources_agree(survey, plots, metashape):
    """A constant, one value per ROI, an attribute, and geometry Z at the same height give
    the same result."""
    h = 95.3
    ref = back_project(plots, metashape, heights=h, densify_tolerance=NO_DENSIFY)
    rois_z = ROISet([ROI(r.name, r.parts, dict(r.attributes, hz=h),
                         [[np.full(len(ring), h) for ring in part] for part in r.parts])
                     for r in plots], plots.crs)
    for heights in ([h] * len(plots), "hz", "geometry"):
        src = heights if heights == "geometry" else PerROIHeights(heights)
        other = back_project(rois_z, metashape, heights=src, densify_tolerance=NO_DENSIFY)
        assert len(other) == len(ref) and np.array_equal(other.photo, ref.photo)
        assert np.allclose(other.polygons.xy, ref.polygons.xy, atol=1e-9)


def test_dsm_heights_follow_the_densified_edges(survey, plots, metashape):
    res = back_project(ROISet(plots[:3], plots.crs), metashape, heights=DSM(survey.dsm))
    v = res.settings["vertices"]
    assert v["densified"] > v["input"] == 12
    assert np.isfinite(res.polygons.xy).all()


# --- synthetic scenes true by construction ------------------------------------------------------
UTM = CRS.from_epsg(32654)
OFFSET = np.array([368000.0, 3956000.0, 0.0])


def _recon(poses, cal=None, size=(800, 600)):
    cal = cal or Calibration(f=680.0, cx=403.2, cy=297.9, k1=-0.062, k2=0.041, k3=-0.012,
                             p1=0.0009, p2=-0.0006)
    sensor = Sensor("0", "synthetic", size[0], size[1], cal)
    cams = [Camera(str(i), f"IMG_{i}", "0", photo_path=f"/nowhere/IMG_{i}.JPG", R=R, C=np.asarray(C, float))
            for i, (R, C) in enumerate(poses)]
    return Reconstruction(Path("synthetic"), "synthetic", "synthetic", UTM, OffsetFrame(UTM, OFFSET),
                          {"0": sensor}, cams)


def _look(tilt_deg):
    """Camera rotation looking north, tilted ``tilt_deg`` from nadir towards the horizon."""
    t = np.radians(tilt_deg)
    nadir = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])   # x east, y south, z down
    tilt = np.array([[1, 0, 0], [0, np.cos(t), -np.sin(t)], [0, np.sin(t), np.cos(t)]])
    return tilt @ nadir


def _roi(name, ring_local, holes=()):
    return ROI(name, [[np.asarray(ring_local, float) + OFFSET[:2]] +
                      [np.asarray(h, float) + OFFSET[:2] for h in holes]])


def _sampled_fraction(recon, roi, z, n=400):
    x0, y0, x1, y1 = roi.bounds
    gx, gy = np.meshgrid(x0 + (x1 - x0) * (np.arange(n) + 0.5) / n,   # cell centres: none on
                         y0 + (y1 - y0) * (np.arange(n) + 0.5) / n)   # the ROI's boundary
    inside = points_in_rings(gx.ravel(), gy.ravel(), roi.rings)
    pts = np.column_stack([gx.ravel()[inside], gy.ravel()[inside], np.full(inside.sum(), z)])
    p = recon.project_points(pts, UTM)
    return (p.status == INSIDE).mean(axis=1), pts, p


def test_roi_behind_the_camera_never_folds_back():
    """A camera 10 m up looking 75° off nadir; a 40 m × 200 m strip of ground runs from behind
    it past its view. Vertices behind the camera and beyond the lens model's radius must not
    fold into the frame; the visible share equals a dense ground count."""
    recon = _recon([(_look(75), [0.0, 0.0, 10.0])])
    strip = _roi("strip", [[-20, -60], [20, -60], [20, 140], [-20, 140]],
                 holes=[[[-5, 30], [-5, 40], [5, 40], [5, 30]]])
    rois = ROISet([strip], UTM)
    res = back_project(rois, recon, heights=0.0, min_visible=0)
    assert len(res) == 1 and res.clipped[0]
    truth, pts, p = _sampled_fraction(recon, strip, 0.0)
    assert res.visible_fraction[0] == pytest.approx(truth[0], abs=0.003)
    rings = res.rings_of(0)
    for r in rings:
        assert np.isfinite(r).all() and r.min() >= -1e-6 and (r <= [800 + 1e-6, 600 + 1e-6]).all()
    # the in-frame samples fall inside the pixel polygons (even-odd), those out of it do not
    uv = p.pixels[0][p.status[0] == INSIDE]
    hit = points_in_rings(uv[:, 0], uv[:, 1], rings)
    assert hit.mean() > 0.995
    # easyidp's all-vertices rule would drop it; ours keeps the visible part
    whole = back_project(rois, recon, heights=0.0, clip=False, min_visible=0)
    assert len(whole) == 0 and "strip" in whole.unseen


def test_roi_around_the_whole_view_is_the_frame():
    """A 2 km square around a nadir camera: no vertex in the photo, the polygon is the frame,
    the visible share is the footprint's area over the ROI's."""
    recon = _recon([(_look(0), [0.0, 0.0, 30.0])])
    big = _roi("field", [[-1000, -1000], [1000, -1000], [1000, 1000], [-1000, 1000]])
    res = back_project(ROISet([big], UTM), recon, heights=0.0, min_visible=0)
    assert len(res) == 1
    ring = res.rings_of(0)[0]
    assert abs(res.polygons.areas_centroids()[0][0] - 800 * 600) < 1e-6
    assert ring.min() >= 0 and ring[:, 0].max() <= 800 and ring[:, 1].max() <= 600
    # footprint area from the frame border cast onto z = 0
    from easyidp_toolbox.core.reconstruction import border_pixels
    o, d = recon.pixel_to_ray(recon.cameras[0], border_pixels(800, 600, 200))
    g = o + d * (-o[2] / d[:, 2])[:, None]
    x, y = g[:, 0], g[:, 1]
    fp = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    assert res.visible_fraction[0] == pytest.approx(fp / 2000 ** 2, rel=1e-4)


def test_unseen_rois_are_reported_by_name():
    recon = _recon([(_look(0), [0.0, 0.0, 30.0])])
    near = _roi("near", [[-2, -2], [2, -2], [2, 2], [-2, 2]])
    far = _roi("far", [[500, 500], [502, 500], [502, 502], [500, 502]])
    res = back_project(ROISet([near, far], UTM), recon, heights=0.0)
    assert list(res.roi_names) == ["near", "far"] and res.photos_per_roi().tolist() == [1, 0]
    assert res.unseen == {"far": "no photo sees it"}


# --- real data -------------------------------------------------------------------------------------
def test_wheat_tanashi_markers_as_tiny_rois(realdata):
    """Truth kind: Metashape's pinned marker observations (real project). A 2 cm square ROI at
    each GCP's reference must land within Metashape's own residual of the pinned pixel (the
    known median 5.5 px is Metashape's adjustment); every photo with a pinned observation inside
    the frame must hold the ROI."""
    recon = open_reconstruction(realdata / "easyidp" / "metashape" / "wheat_tanashi.psx")
    rois, dists = [], []
    for m in recon.markers:
        lon, lat, h = m.reference
        dx = 0.01 / (111320.0 * np.cos(np.radians(lat)))
        dy = 0.01 / 110574.0
        ring = np.array([[lon - dx, lat - dy], [lon + dx, lat - dy], [lon + dx, lat + dy],
                         [lon - dx, lat + dy]])
        rois.append(ROI(m.label, [[ring]], {}, [[np.full(4, h)]]))
    res = back_project(ROISet(rois, "EPSG:4326"), recon, heights="geometry", min_visible=0)
    n_pinned = 0
    for m in recon.markers:
        recs = res.records_of(m.label)
        photos = {res.photo[i]: i for i in recs}
        for label, uv in m.observations.items():
            n_pinned += 1
            assert label in photos, (m.label, label)
            centre = res.rings_of(photos[label])[0].mean(axis=0)
            dists.append(np.hypot(*(centre - uv)))
    dists = np.array(dists)
    print(f"\nwheat markers: {n_pinned} pinned observations, distance to ours median "
          f"{np.median(dists):.1f} px, max {dists.max():.1f} px")
    assert n_pinned == 23
    assert np.median(dists) < 6.0 and dists.max() < 11.0


def test_real_pix4d_roi_shapefile(realdata):
    """The real roi.shp (3 plots, UTM 54N) on the real Pix4D project at the offset height."""
    from easyidp_toolbox.core.roi import open_rois
    base = realdata / "easyidp" / "pix4d_origin"
    rois = open_rois(base / "roi" / "roi.shp", name_field="id")
    recon = open_reconstruction(base, source_crs="EPSG:32654")
    res = back_project(rois, recon, heights=96.0, min_visible=0)
    counts = dict(zip(res.roi_names, res.photos_per_roi()))
    whole = back_project(rois, recon, heights=96.0, clip=False, min_visible=0)
    print(f"\nPix4D roi.shp: photos per plot {counts} (clipped), "
          f"{dict(zip(whole.roi_names, whole.photos_per_roi()))} (whole only)")
    assert all(c > 0 for c in counts.values())
    assert np.isfinite(res.polygons.xy).all() and len(res.polygons.xy) > 0
    assert (whole.photos_per_roi() <= res.photos_per_roi()).all()


# --- bad input --------------------------------------------------------------------------------------
def test_no_height_source(plots, metashape):
    with pytest.raises(EasyIDPError, match="No height source"):
        back_project(plots, metashape, heights=None)
    with pytest.raises(ROIError, match="have no Z"):
        back_project(plots, metashape, heights="geometry")
    with pytest.raises(ROIError, match="no attribute 'nope'"):
        back_project(plots, metashape, heights=PerROIHeights("nope"))
    with pytest.raises(EasyIDPError, match="3 heights given for 40 ROIs"):
        back_project(plots, metashape, heights=PerROIHeights([1, 2, 3]))


def test_dsm_not_under_the_rois(tmp_path, plots, metashape):
    import sys
    sys.path.insert(0, str(Path(__file__).parent))
    from easyidp_toolbox.tests.support.synthetic import write_tif
    dsm = write_tif(str(tmp_path / "far.tif"), np.zeros((10, 10), np.float32),
                    origin=(100000.0, 100000.0))
    with pytest.raises(ROIError, match="DSM has no data under some vertices of 40 ROI"):
        back_project(plots, metashape, heights=DSM(dsm))


def test_rois_without_crs_or_in_an_unrelated_crs(plots, metashape):
    with pytest.raises(ROIError, match="have no CRS"):
        back_project(ROISet(list(plots), None), metashape, heights=95.0)
    local = _recon([(_look(0), [0.0, 0.0, 30.0])])
    local.crs, local.frame = None, LocalFrame(None)
    with pytest.raises(EasyIDPError, match="cannot be placed in the project"):
        back_project(plots, local, heights=95.0)


def test_project_without_aligned_cameras(plots):
    recon = _recon([(_look(0), [0.0, 0.0, 30.0])])
    recon.cameras[0].R = None
    with pytest.raises(EasyIDPError, match="no aligned, enabled camera"):
        back_project(ROISet([_roi("a", [[0, 0], [1, 0], [1, 1]])], UTM), recon, heights=0.0)


def test_bad_numbers(plots, metashape):
    for kw, msg in (({"min_visible": 1.5}, "min_visible"), ({"max_views": -1}, "max_views"),
                    ({"densify_tolerance": 0}, "densify_tolerance")):
        with pytest.raises(EasyIDPError, match=msg):
            back_project(plots, metashape, heights=95.0, **kw)
