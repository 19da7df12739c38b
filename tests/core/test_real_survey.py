"""Every projection tool on a real survey with its real photos (issue 24): the OpenDroneMap
project realdata/orthority_odm (4 DJI FC6310R photos over forest and river, ODM's DSM at 0.8 m,
UTM 51N), opened as ODM left it: no odm_georeferencing/, shot keys without extension, no offset
or photos folder given.

Kinds of check, said per test: OpenCV (cv2.projectPoints from the JSON's own pose and
calibration), PROJ (pyproj pipelines written here), brute force in the test (pixel means,
bilinear DSM), and the two checks on real photos that need no truth: two views of one ground
align, and features matched between photos meet on the map. Run with -s to see the figures.
"""
import json
import os

import cv2
import numpy as np
import pytest
from pyproj import Transformer

from easyidp_toolbox.tests.support import real_survey as rs
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.projection import (back_project, crop_photos, forward_project,
                                             photo_statistics, read_photo)
from easyidp_toolbox.core.raster import DSM, first_hits
from easyidp_toolbox.core.projection.ortho import orthorectify_rois
from easyidp_toolbox.core.projection import camera_footprints
from easyidp_toolbox.core.reconstruction import INSIDE
from easyidp_toolbox.core.reconstruction.geodesy import OffsetFrame



@pytest.fixture(scope="module")
def folder(realdata):
    return realdata / "orthority_odm"


@pytest.fixture(scope="module")
def dsm(folder):
    return folder / "odm_dem" / "dsm.tif"


@pytest.fixture(scope="module")
def survey(folder):
    return open_reconstruction(folder)


@pytest.fixture(scope="module")
def cvcams(folder):
    return {k: rs.OpenCVCamera(folder, k) for k in rs.PHOTOS}


@pytest.fixture(scope="module")
def bp(survey, dsm):
    return back_project(rs.roi_set(), survey, heights=DSM(str(dsm)),
                        occlusion_dsm=str(dsm), min_visible=0.0)


# --- opening the project as ODM left it -----------------------------------------------------------
def test_opens_without_offset_or_photos_folder(survey, folder):
    """PROJ check: the photos' GPS positions (topocentric about reference_lla in the file) taken
    to UTM 51N by a PROJ pipeline written here lie within 0.1 m of our camera centres, as ODM's
    bundle adjustment leaves them; read topocentrically they would be about 2 m off."""
    assert survey.crs.to_epsg() == rs.UTM51N
    assert isinstance(survey.frame, OffsetFrame)
    np.testing.assert_array_equal(survey.frame.offset, [*rs.OFFSET, 0.0])
    assert any("map offset from reference_lla" in n and "E 292632.000, N 2731169.000" in n
               for n in survey.notes)
    assert [os.path.basename(c.photo_path) for c in sorted(survey.cameras, key=lambda c: c.label)] \
        == [p + ".tif" for p in rs.PHOTOS]
    rec = json.loads((folder / "opensfm" / "reconstruction.json").read_text())[0]
    lla = rec["reference_lla"]
    topo_to_utm = Transformer.from_pipeline(
        f"+proj=pipeline +step +inv +proj=topocentric +ellps=WGS84 +lat_0={lla['latitude']!r} "
        f"+lon_0={lla['longitude']!r} +h_0={lla['altitude']!r} +step +inv +proj=cart +ellps=WGS84 "
        "+step +proj=utm +zone=51 +ellps=WGS84")
    labels, centres = survey.camera_centres()
    for lab, c in zip(labels, centres):
        g = rec["shots"][lab]["gps_position"]
        e, n, h = topo_to_utm.transform(*g)
        assert np.linalg.norm(c - [e, n, h]) < 0.1, lab


def _odm_copy(folder, tmp_path, coords=None, keep_lla=True, lla_shift=0.0):
    """An ODM folder in tmp_path: the real reconstruction.json (reference_lla dropped, or moved
    north by ``lla_shift`` degrees, on request), the DSM and photos linked, and an
    odm_georeferencing/coords.txt if given."""
    (tmp_path / "opensfm").mkdir(parents=True)
    rec = json.loads((folder / "opensfm" / "reconstruction.json").read_text())
    if not keep_lla:
        rec[0].pop("reference_lla")
    rec[0].get("reference_lla", {"latitude": 0.0})["latitude"] += lla_shift
    (tmp_path / "opensfm" / "reconstruction.json").write_text(json.dumps(rec))
    for sub in ("odm_dem", "images"):
        os.symlink(folder / sub, tmp_path / sub)
    if coords is not None:
        (tmp_path / "odm_georeferencing").mkdir()
        (tmp_path / "odm_georeferencing" / "coords.txt").write_text(coords)
    return tmp_path


def test_coords_txt_offset_wins(survey, folder, tmp_path):
    """By construction: a coords.txt offset 0.5 m east of reference_lla's moves every camera
    0.5 m east (still the map frame by the GPS evidence: 0.5 m against 2 m), and the notes
    say where the offset came from."""
    recon = open_reconstruction(_odm_copy(folder, tmp_path, "WGS84 UTM 51N\n292632.5 2731169\n"))
    assert any("coords.txt, line 2" in n for n in recon.notes)
    np.testing.assert_allclose(recon.camera_centres()[1] - survey.camera_centres()[1],
                               np.tile([0.5, 0.0, 0.0], (4, 1)), atol=1e-6)


def test_missing_offset_names_the_missing_file(folder, tmp_path):
    with pytest.raises(InputError) as e:
        open_reconstruction(_odm_copy(folder, tmp_path / "a", None, keep_lla=False))
    msg = str(e.value)
    assert "coords.txt is missing" in msg and "dsm.tif" not in msg and "reference_lla" in msg
    with pytest.raises(InputError) as e:
        open_reconstruction(_odm_copy(folder, tmp_path / "b", "WGS84 UTM 51N\n", keep_lla=False))
    assert "coords.txt: the east/north offset (line 2) is missing" in str(e.value)
    assert "dsm.tif" not in str(e.value)
    # a reference off whole metres is OpenSfM's own, not ODM's offset point: not used
    with pytest.raises(InputError, match=r"coords\.txt is missing, and reference_lla is at .* not "
                                         r"on whole metres"):
        open_reconstruction(_odm_copy(folder, tmp_path / "c", None, lla_shift=1e-6))


# --- every tool on the survey -----------------------------------------------------------------
def test_footprints(survey, dsm, cvcams):
    """OpenCV check: every footprint vertex that met the DSM projects (cv2.projectPoints) onto
    the frame border of its photo, to 0.01 px."""
    fps = camera_footprints(survey, DSM(str(dsm)))
    assert sorted(f.label for f in fps) == list(rs.PHOTOS)
    for f in fps:
        assert f.photo_path and os.path.isfile(f.photo_path)
        assert 60 < f.height_above_ground < 110 and 20 < f.view_angle < 40
        ring = np.asarray(f.ring)
        z = rs.dsm_bilinear(dsm, ring[:, 0], ring[:, 1])
        on_dsm = np.abs(ring[:, 2] - z) < 1e-3 if ring.shape[1] == 3 else np.ones(len(ring), bool)
        assert on_dsm.sum() >= 8
        xyz = ring if ring.shape[1] == 3 else np.column_stack([ring, z])
        uv = cvcams[f.label].project(xyz[on_dsm])
        w, h = cvcams[f.label].width, cvcams[f.label].height
        border = np.minimum.reduce([np.abs(uv[:, 0]), np.abs(uv[:, 0] - w),
                                    np.abs(uv[:, 1]), np.abs(uv[:, 1] - h)])
        assert border.max() < 0.01, (f.label, border.max())


def test_back_projection_against_opencv(bp, dsm, cvcams):
    """OpenCV check: each ROI corner, at its bilinear DSM height (brute force here), projected
    by cv2.projectPoints is a vertex of the back-projected polygon (to 0.01 px); each ROI is
    seen by both photos of its pair."""
    rois = rs.roi_set()
    for r_i, (pair, _c) in enumerate(rs.PAIR_CENTRES.items()):
        recs = [i for i in range(len(bp)) if int(bp.roi[i]) == r_i]
        photos = {str(bp.photo[i]) for i in recs}
        assert set(pair) <= photos, (rs.roi_name(pair), photos)
        corners = np.asarray(rois[r_i].rings[0])[:4, :2]
        xyz = np.column_stack([corners, rs.dsm_bilinear(dsm, corners[:, 0], corners[:, 1])])
        for i in recs:
            if bp.clipped[i]:
                continue
            ring = bp.rings_of(i)[0]
            uv = cvcams[str(bp.photo[i])].project(xyz)
            d = np.linalg.norm(ring[None, :, :] - uv[:, None, :], axis=2).min(axis=1)
            assert d.max() < 0.01, (rs.roi_name(pair), str(bp.photo[i]), d.max())


def test_crops_and_previews(bp, tmp_path):
    """Brute force: each crop holds the photo's own pixels at the window its sidecar names."""
    res = crop_photos(bp, tmp_path / "crops", previews_folder=tmp_path / "previews")
    assert not res.skipped_photos
    assert len(res.files) == len(bp) and len(res.previews) == len(rs.PAIR_CENTRES)
    for f, side in zip(res.files, res.sidecars):
        with open(side) as fh:
            meta = json.load(fh)
        assert os.path.isfile(meta["photo_path"]) and meta["photo_path"].endswith(".tif")
        photo = read_photo(meta["photo_path"])
        crop = read_photo(f)
        assert crop.shape[2] == 4 and (crop[..., 3] > 0).any()
        x0, y0 = meta["offset"]
        win = photo[y0:y0 + crop.shape[0], x0:x0 + crop.shape[1]]
        inside = crop[..., 3] > 0
        np.testing.assert_array_equal(crop[..., :3][inside], win[inside])


def test_forward_projection_against_opencv(survey, dsm, cvcams, bp):
    """OpenCV check: the back-projected polygon of each ROI in its best photo, forward-projected
    onto the DSM, lands on points that cv2.projectPoints takes back to the input pixels (to
    0.01 px) and whose heights are the DSM's (bilinear, brute force, 1 cm); the result is the
    ROI again where the photo sees the ground it was cut from (round trip, 5 cm median)."""
    ground = DSM(str(dsm))
    for i in range(len(bp)):
        if int(bp.rank[i]) != 1:
            continue
        photo = str(bp.photo[i])
        ring = bp.rings_of(i)[0]
        shape = forward_project([ring], photo, survey, ground, densify=False)[0]
        pts, ok = shape.points[0], shape.status[0] == 0
        assert ok.mean() > 0.5
        uv = cvcams[photo].project(pts[ok])
        np.testing.assert_allclose(uv, ring[ok], atol=0.01)
        np.testing.assert_allclose(pts[ok, 2], rs.dsm_bilinear(dsm, pts[ok, 0], pts[ok, 1]),
                                   atol=0.01)
        assert np.isfinite(shape.area_m2) and shape.area_m2 > 50


def test_forward_projection_of_labelme_with_a_windows_image_path(survey, dsm, tmp_path):
    """A LabelMe file drawn on the photo, its imagePath a Windows path in another case and
    extension: matched to shot 100_0005_0140 by the one photo lookup."""
    from easyidp_toolbox.core.annotations import read_annotations
    doc = {"version": "5.0.1", "flags": {}, "imagePath": "..\\Images\\100_0005_0140.TIF",
           "imageData": None, "imageWidth": 1368, "imageHeight": 912,
           "shapes": [{"label": "crown", "points": [[600, 400], [700, 400], [700, 480], [600, 480]],
                       "shape_type": "polygon", "flags": {}, "group_id": None}]}
    (tmp_path / "a.json").write_text(json.dumps(doc))
    [(ann, cam)] = read_annotations(tmp_path / "a.json", survey)
    assert cam.label == "100_0005_0140"
    shapes = forward_project(ann.shapes, cam.label, survey, DSM(str(dsm)))
    assert shapes[0].complete and 100 < shapes[0].area_m2 < 400


def test_orthorectification(survey, dsm, tmp_path):
    """Every ROI from every photo that sees it; images named by ROI and photo, on DSM grids."""
    res = orthorectify_rois(rs.roi_set(), survey, str(dsm), tmp_path, selection="all")
    assert not any("not found" in w for w in res.skipped.values()), res.skipped
    assert len(res.files) >= 2 * len(rs.PAIR_CENTRES)
    for pair in rs.PAIR_CENTRES:
        for p in pair:
            assert (tmp_path / f"{rs.roi_name(pair)}_{p}.tif").is_file()
    assert all(0.05 < g < 0.3 for g in res.gsd)          # native: ~0.1 m at 80–110 m range


def _polygon_mask(rings, shape):
    """Pixel centres inside ``rings`` (exterior and holes, even-odd rule), brute force."""
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]] + 0.5
    inside = np.zeros(shape, bool)
    edges = [(r[k], r[(k + 1) % len(r)]) for r in rings for k in range(len(r))]
    for (x0, y0), (x1, y1) in edges:
        cross = (y0 > yy) != (y1 > yy)
        with np.errstate(divide="ignore", invalid="ignore"):
            xi = x0 + (yy - y0) * (x1 - x0) / (y1 - y0)
        inside ^= cross & (xx < xi)
    return inside


def test_plot_statistics_against_brute_force(bp, survey, dsm):
    """Brute force: the mean red, green, blue of each ROI × photo is the mean of the photo's
    pixels whose centre is inside the back-projected polygon (its holes are the parts the DSM
    hides; no per-pixel occlusion test here);
    with the occlusion test, the shares are in [0, 1] and every ROI keeps a value."""
    st = photo_statistics(bp, statistics=("mean",))
    cols = [st.columns.index(f"{b}_mean") for b in ("red", "green", "blue")]
    photos = {}
    for k in range(len(st.record)):
        i = int(st.record[k])
        lab = str(bp.photo[i])
        if lab not in photos:
            photos[lab] = read_photo(next(c.photo_path for c in survey.cameras if c.label == lab))
        img = photos[lab]
        m = _polygon_mask(bp.rings_of(i), img.shape[:2])
        assert m.sum() == st.polygon_pixels[k]
        np.testing.assert_allclose(st.values[k, cols], img[m].mean(axis=0), rtol=0, atol=1e-6)
    occ = photo_statistics(bp, statistics=("mean",), recon=survey, rois=rs.roi_set(),
                           occlusion_dsm=str(dsm))
    assert np.all((occ.occluded_share >= 0) & (occ.occluded_share <= 1))
    assert np.isfinite(occ.median[:, cols]).all()


# --- checks on real photos that need no truth ----------------------------------------------------
GRIDS_M = (0.8, 0.4)           # asserted: the DSM cell and half of it
GRID_INFO_M = 0.15             # reported only: about the photos' own ground resolution
HALF_M = 15.0


def _pair_orthos(survey, dsm, pair, gsd, tmp_path):
    import tifffile
    from easyidp_toolbox.core.roi.model import ROISet, roi_from_coordinates
    cx, cy = rs.PAIR_CENTRES[pair]
    rois = ROISet([roi_from_coordinates("r", "Polygon", [rs.square(cx, cy, HALF_M)])],
                  f"EPSG:{rs.UTM51N}")
    out = []
    for p in pair:
        d = tmp_path / f"{rs.roi_name(pair)}_{gsd}_{p}"
        res = orthorectify_rois(rois, survey, str(dsm), d, selection="photo", photo=p, gsd=gsd)
        out.append(tifffile.imread(res.files[0]))
    a, b = out
    assert a.shape == b.shape                    # one grid: origin and size are multiples of gsd
    mask = (a[..., 3] > 0) & (b[..., 3] > 0)     # in both frames and not occluded in either
    grey = [cv2.cvtColor(x[..., :3], cv2.COLOR_RGB2GRAY).astype(np.float64) for x in (a, b)]
    return grey[0], grey[1], mask


def test_phase_shift_measure_recovers_known_shifts(survey, dsm, tmp_path):
    """Truth by construction for the measuring tool: a real orthorectified image moved by known
    sub-pixel shifts, on the real common mask, is measured to 0.03 px."""
    from scipy.ndimage import shift as nd_shift
    pair = ("100_0005_0136", "100_0005_0140")
    a, _b, mask = _pair_orthos(survey, dsm, pair, 0.4, tmp_path)
    for dx, dy in ((0.3, -0.2), (-0.15, 0.25), (1.0, 0.5)):
        moved = nd_shift(a, (dy, dx), order=3, mode="nearest")
        mx, my = rs.phase_shift(a, moved, mask)
        assert abs(mx - dx) < 0.03 and abs(my - dy) < 0.03, ((dx, dy), (mx, my))


def test_two_views_of_one_ground_align(survey, dsm, tmp_path):
    """No truth needed: the same ROI orthorectified from the two photos of each overlapping
    pair, on one grid, aligns by phase correlation to ≤ 0.3 px where both photos see the
    ground (alpha > 0 in both: inside both frames, not occluded by the DSM), on the DSM's
    0.8 m grid and on 0.4 m. Figures printed per pair, also on a 0.15 m grid (not asserted)."""
    rows = []
    for pair in rs.overlapping_pairs():
        for gsd in GRIDS_M + (GRID_INFO_M,):
            a, b, mask = _pair_orthos(survey, dsm, pair, gsd, tmp_path)
            dx, dy = rs.phase_shift(a, b, mask)
            rows.append((pair, gsd, mask.mean(), rs.ncc(a, b, mask), dx, dy))
    print("\ntwo views, one ground (ROI 30 m × 30 m; shift of the second view, px of the grid)")
    print(f"{'pair':>11} {'grid m':>6} {'common':>6} {'NCC':>6} {'dx':>7} {'dy':>7} {'|d| px':>7} {'|d| m':>6}")
    for pair, gsd, share, c, dx, dy in rows:
        d = float(np.hypot(dx, dy))
        print(f"{pair[0][-4:]}/{pair[1][-4:]} {gsd:6.2f} {share:6.2f} {c:6.3f} {dx:7.3f} "
              f"{dy:7.3f} {d:7.3f} {d * gsd:6.3f}")
    for pair, gsd, share, c, dx, dy in rows:
        assert share > 0.3 and c > 0.6, (pair, gsd, share, c)
        if gsd in GRIDS_M:
            assert np.hypot(dx, dy) <= 0.3, (pair, gsd, dx, dy)


def _sift(img):
    g = cv2.cvtColor(img, cv2.COLOR_RGB2GRAY)
    return cv2.SIFT_create(nfeatures=4000).detectAndCompute(g, None)


def test_features_agree_on_the_map(survey, dsm):
    """No truth needed: SIFT matches between the two raw photos of each overlapping pair
    (Lowe ratio 0.8, RANSAC fundamental matrix at 1 px), each keypoint forward-projected
    through its own photo onto the DSM: the two map points of a match are a median ≤ 2 DSM
    cells (1.6 m) apart; each map point back-projected into the other photo lands a median
    ≤ 2 px from its match. What bounds it: the DSM (0.8 m cells over tree crowns, a height
    error dz moves a point dz·tan(view angle) sideways, differently in each view), not the
    keypoints (≈ 0.5 px ≈ 5 cm)."""
    surface = DSM(str(dsm)).ray_surface()
    cams = {c.label: c for c in survey.cameras}
    feats = {k: _sift(read_photo(cams[k].photo_path)) for k in rs.PHOTOS}
    print("\nfeatures agree on the map (SIFT + RANSAC; distances between the two map points)")
    print(f"{'pair':>11} {'inliers':>7} {'med m':>6} {'p90 m':>6} {'max m':>6} {'reproj med px':>13} {'p90 px':>6}")
    for a, b in rs.overlapping_pairs():
        (ka, da), (kb, db) = feats[a], feats[b]
        good = [m for m, n in cv2.BFMatcher(cv2.NORM_L2).knnMatch(da, db, k=2)
                if m.distance < 0.8 * n.distance]
        pa = np.float64([ka[m.queryIdx].pt for m in good])
        pb = np.float64([kb[m.trainIdx].pt for m in good])
        _F, inl = cv2.findFundamentalMat(pa, pb, cv2.FM_RANSAC, 1.0, 0.999)
        inl = inl.ravel().astype(bool)
        pa, pb = pa[inl] + 0.5, pb[inl] + 0.5            # OpenCV centres at integers → ours
        xyz = []
        for lab, uv in ((a, pa), (b, pb)):
            o, d = survey.pixel_to_ray(cams[lab], uv)
            xyz.append(first_hits(surface, survey.frame, o, d))
        ok = xyz[0].hit & xyz[1].hit
        dist = np.linalg.norm(xyz[0].xyz[ok, :2] - xyz[1].xyz[ok, :2], axis=1)
        back = survey.project_points(xyz[0].xyz[ok], f"EPSG:{rs.UTM51N}", cameras=[b])
        seen = back.status[0] == INSIDE               # a's map point may fall outside b's frame
        err = np.linalg.norm(back.pixels[0][seen] - pb[ok][seen], axis=1)
        assert seen.mean() > 0.9
        print(f"{a[-4:]}/{b[-4:]} {ok.sum():7d} {np.median(dist):6.2f} {np.percentile(dist, 90):6.2f} "
              f"{dist.max():6.2f} {np.median(err):13.2f} {np.percentile(err, 90):6.2f}")
        assert ok.sum() >= 20
        assert np.median(dist) <= 2 * 0.8
        assert np.median(err) <= 2.0


def test_occlusion_mask_coarse_first_agrees_with_every_ray(survey, dsm, tmp_path, monkeypatch):
    """Brute force: the orthorectification's hidden-ground mask, cast on a coarse grid first and
    refined near its edges, against one ray per output pixel (the mask as it was): the alpha
    bands differ at ≤ 0.05 % of the pixels, with at most half the rays. Figures printed."""
    import tifffile
    from easyidp_toolbox.core.projection import ortho
    rays = {"n": 0}
    exact_fn = ortho.line_of_sight

    def counting(recon, cam, surface, p, tol):
        rays["n"] += len(p)
        return exact_fn(recon, cam, surface, p, tol)

    monkeypatch.setattr(ortho, "line_of_sight", counting)
    rois = rs.roi_set(half=15.0)
    fast = orthorectify_rois(rois, survey, str(dsm), tmp_path / "fast", selection="all")
    n_fast = rays["n"]
    rays["n"] = 0
    monkeypatch.setattr(ortho, "line_of_sight_coarse_first",
                        lambda recon, cam, surface, p, tol, *a: counting(recon, cam, surface, p, tol))
    slow = orthorectify_rois(rois, survey, str(dsm), tmp_path / "slow", selection="all")
    n_slow = rays["n"]
    diff = total = 0
    for fa, fb in zip(fast.files, slow.files):
        a, b = tifffile.imread(fa)[..., 3] > 0, tifffile.imread(fb)[..., 3] > 0
        diff += int((a != b).sum())
        total += a.size
    print(f"\nocclusion mask: {n_fast} rays coarse-first against {n_slow} (one per pixel), "
          f"{diff} of {total} pixels differ ({100 * diff / total:.4f} %)")
    assert [os.path.basename(f) for f in fast.files] == [os.path.basename(f) for f in slow.files]
    assert n_fast <= 0.5 * n_slow and diff <= 5e-4 * total
