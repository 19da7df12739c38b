"""Orthorectified ROI images from the demo survey's raw photos.

Independent checks: the demo orthomosaic (the texture the photos were rendered from: features
in place by construction) against our images by normalised cross-correlation; occlusion
against a brute-force line of sight written here (dense sampling of the DSM along the segment
from each output pixel's ground point to the camera).
"""
import os

import numpy as np
import pytest
import tifffile

from easyidp_toolbox.core import InputError, open_reconstruction, read_geojson
from easyidp_toolbox.core.projection.ortho import orthorectify_rois
from easyidp_toolbox.core.raster import DSM, open_geotiff


@pytest.fixture(scope="module")
def recon(demo):
    return open_reconstruction(demo.metashape_project)


@pytest.fixture(scope="module")
def plots(demo):
    return read_geojson(demo.plots_geojson, name_field="plot_id")


def _grid(path):
    info = open_geotiff(path)
    img = tifffile.imread(path)
    c, a, _, f, _, e = info.geotransform
    x = c + a * (np.arange(info.width) + 0.5)
    y = f + e * (np.arange(info.height) + 0.5)
    return img, x, y, a


def _ortho_at(ortho_path, x, y):
    """The orthomosaic (1 cm) averaged to 2 cm, at map points: 2 × 2 pixel box around each."""
    o = tifffile.imread(ortho_path).astype(np.float64).mean(axis=2)
    info = open_geotiff(ortho_path)
    col, row = info.map_to_pixel(x, y)
    c0, r0 = np.floor(col - 1).astype(int), np.floor(row - 1).astype(int)
    c0, r0 = np.clip(c0, 0, o.shape[1] - 2), np.clip(r0, 0, o.shape[0] - 2)
    return 0.25 * (o[r0, c0] + o[r0 + 1, c0] + o[r0, c0 + 1] + o[r0 + 1, c0 + 1])


def test_features_in_place_against_the_orthomosaic(demo, recon, plots, tmp_path):
    """Images at 2 cm (the DSM cell): the cross-correlation with the orthomosaic peaks within
    one cell of zero offset (sub-cell peak by a parabola). The photos are point-sampled
    renderings at 3.7 cm of the 2 cm texture, so a fraction of a cell is expected."""
    sel = read_geojson(demo.plots_geojson, name_field="plot_id")
    from easyidp_toolbox.core.roi import ROISet
    some = ROISet([r for r in sel if r.name in ("A1", "B3", "C5", "D7", "E2")], sel.crs)
    res = orthorectify_rois(some, recon, demo.dsm, str(tmp_path), selection="best", gsd=0.02)
    assert len(res.files) == 5 and not res.skipped
    offsets = []
    for path in res.files:
        img, x, y, g = _grid(path)
        X, Y = np.meshgrid(x, y)
        ref = _ortho_at(demo.orthomosaic, X.ravel(), Y.ravel()).reshape(X.shape)
        ours = img[..., :3].astype(np.float64).mean(axis=2)
        alpha = img[..., 3] == 255
        best, scores = None, {}
        m = 4
        core = np.zeros_like(alpha)
        core[m:-m, m:-m] = True
        for dy in range(-3, 4):
            for dx in range(-3, 4):
                a = ours[m:-m, m:-m]
                b = ref[m + dy:ref.shape[0] - m + dy, m + dx:ref.shape[1] - m + dx]
                ok = alpha[m:-m, m:-m]
                av, bv = a[ok] - a[ok].mean(), b[ok] - b[ok].mean()
                scores[dy, dx] = float((av * bv).sum() / np.sqrt((av * av).sum() * (bv * bv).sum()))
        best = max(scores, key=scores.get)
        assert max(abs(best[0]), abs(best[1])) <= 1, (path, best)
        # sub-cell offset by a parabola through the peak and its neighbours
        sub = []
        for axis in (0, 1):
            e = [(-1, 0), (1, 0)] if axis == 0 else [(0, -1), (0, 1)]
            lo, hi, c = scores[e[0]], scores[e[1]], scores[0, 0]
            sub.append(0.5 * (lo - hi) / (lo - 2 * c + hi))
        offsets.append(sub)
        assert scores[0, 0] > 0.8
    offsets = np.array(offsets)
    print(f"\northo vs orthomosaic: sub-cell NCC peak offsets (cells of 2 cm) {np.round(offsets, 2).tolist()}")
    assert np.hypot(*offsets.T).max() < 1.0                # within one DSM cell
    assert np.abs(offsets.mean(axis=0)).max() < 0.5


def _blocked(dsm_path, C, p, step=0.004, start=0.03):
    """Brute-force line of sight: does the DSM (its own bilinear) rise above the segment from
    ground point p to camera C, beyond ``start`` m from p, while the segment is below the
    DSM's highest height?"""
    info = open_geotiff(dsm_path)
    zmax = 97.5
    d = C - p
    L = np.linalg.norm(d)
    t = np.arange(start, L, step) / L
    q = p + t[:, None] * d
    q = q[q[:, 2] < zmax]
    h = DSM(info).heights(q[:, 0], q[:, 1])
    return bool(np.any(h > q[:, 2]))


def test_occluded_pixels_are_transparent(demo, recon, plots, tmp_path):
    """An oblique view of a tall plot: pixels given alpha 0 for occlusion are hidden by the
    DSM (brute force), those shown are visible."""
    res = orthorectify_rois(plots, recon, demo.dsm, str(tmp_path), selection="all", gsd=0.04)
    k = int(np.argmax(res.occluded))                      # the most occluded view
    assert 0.05 < res.occluded[k] < 0.9            # soil between crop rows, seen slanted
    img, x, y, _ = _grid(res.files[k])
    cam = recon.camera(res.photos[k])
    C = recon.from_model(cam.C[None], "EPSG:32654")[0]
    X, Y = np.meshgrid(x, y)
    from easyidp_toolbox.core.geometry import points_in_rings
    roi = next(r for r in plots if r.name == res.rois[k])
    inside = points_in_rings(X.ravel(), Y.ravel(), [r[:, :2] for r in roi.rings]).reshape(X.shape)
    z = DSM(open_geotiff(demo.dsm)).heights(X.ravel(), Y.ravel()).reshape(X.shape)
    uv = recon.project_points(np.column_stack([X.ravel(), Y.ravel(), z.ravel()]), "EPSG:32654",
                              cameras=[cam])
    in_frame = (uv.status[0] == 0).reshape(X.shape)
    cand = np.argwhere(inside & in_frame & np.isfinite(z))
    rng = np.random.default_rng(0)
    pick = cand[rng.choice(len(cand), min(400, len(cand)), replace=False)]
    agree = 0
    for r, c in pick:
        shown = img[r, c, 3] == 255
        hidden = _blocked(demo.dsm, C, np.array([X[r, c], Y[r, c], z[r, c]]))
        agree += shown != hidden
    assert (img[..., 3][inside & in_frame] == 0).any()
    assert agree >= 0.98 * len(pick), (agree, len(pick))


def test_selections_and_bad_input(demo, recon, plots, tmp_path):
    from easyidp_toolbox.core.roi import ROISet
    two = ROISet(list(plots)[:2], plots.crs)
    best = orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "best"))
    assert sorted(os.path.basename(f) for f in best.files) == ["A1.tif", "A2.tif"]
    native = best.gsd[0]
    assert 0.03 < native < 0.045                              # 25 m / 680 px ≈ 3.7 cm
    every = orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "all"), selection="all")
    assert len(every.files) > 4 and len(set(every.files)) == len(every.files)
    named = orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "one"), selection="photo",
                              photo=best.photos[0])
    assert named.photos == [best.photos[0]] * len(named.files)
    # moved photos: a photos folder finds them by name
    moved = tmp_path / "moved"
    moved.mkdir()
    import shutil
    shutil.copy(recon.camera(best.photos[0]).photo_path, moved)
    again = orthorectify_rois(ROISet([two[0]], plots.crs), recon, demo.dsm, str(tmp_path / "mv"),
                              photos_folder=str(moved))
    assert len(again.files) == 1
    with pytest.raises(InputError, match="holds none of the project.s 1 photos .*DJI_0036.JPG"):
        orthorectify_rois(ROISet([two[1]], plots.crs), recon, demo.dsm, str(tmp_path / "mv2"),
                          selection="photo", photo="DJI_0036", photos_folder=str(moved))
    with pytest.raises(Exception, match="no camera labelled 'IMG_1'"):
        orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "x"), selection="photo", photo="IMG_1")
    with pytest.raises(InputError, match="give the photo's label"):
        orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "x"), selection="photo")
    with pytest.raises(InputError, match="must be positive"):
        orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "x"), gsd=0)
    with pytest.raises(InputError, match="give a larger GSD"):
        orthorectify_rois(two, recon, demo.dsm, str(tmp_path / "x"), gsd=1e-4)
    small = tmp_path / "small"
    small.mkdir()
    import imagecodecs
    photo = recon.camera(best.photos[0]).photo_path
    img = imagecodecs.imread(photo)[::2, ::2]
    (small / os.path.basename(photo)).write_bytes(imagecodecs.jpeg8_encode(np.ascontiguousarray(img)))
    with pytest.raises(InputError, match="400×300 px but the camera's sensor is 800×600"):
        orthorectify_rois(ROISet([two[0]], plots.crs), recon, demo.dsm, str(tmp_path / "s"),
                          selection="photo", photo=best.photos[0], photos_folder=str(small))
    # a damaged photo: named in the error (it is skipped like a missing one, never a traceback)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / os.path.basename(photo)).write_bytes(b"\xff\xd8\xff" + b"\0" * 100)
    with pytest.raises(InputError, match=r"No ROI image was written: A1 / .*"
                                         + os.path.basename(photo).split(".")[0]):
        orthorectify_rois(ROISet([two[0]], plots.crs), recon, demo.dsm, str(tmp_path / "b"),
                          selection="photo", photo=best.photos[0], photos_folder=str(broken))
