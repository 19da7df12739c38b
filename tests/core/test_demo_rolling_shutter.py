"""The demo survey with rolling-shutter photos (opt-in).

Independent truth: the pixels of the truth's observations are computed by
``tests/support/independent_camera.py`` (OpenCV for the lens, the Metashape terms and the
motion's fixed point written out there, from the camera and motion truth.json states; no
``core`` code). The photos are ray cast row by row and the LabelMe vertices cast from their
row's pose by the generator (``core/demo/readout_motion.py``, with the production lens model);
the generated Metashape project is read back by our reader.
"""
import json
import os
import zipfile

import numpy as np
import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.demo import make_demo_survey
from easyidp_toolbox.core.projection import camera_footprints
from easyidp_toolbox.core.reconstruction import INSIDE
from easyidp_toolbox.tests.support import independent_camera


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    return make_demo_survey(str(tmp_path_factory.mktemp("demo_rs")), seed=0, size="small",
                            rolling_shutter=True)


@pytest.fixture(scope="module")
def truth(survey):
    with open(survey.truth) as fh:
        t = json.load(fh)
    obs = t["observations"]
    t["xyz"] = np.array(t["points"]["xyz"])
    t["obs_point"], t["obs_photo"] = np.array(obs["point"]), np.array(obs["photo"])
    t["obs_pixel"] = independent_camera.observation_pixels(t)     # the independent truth
    return t


@pytest.fixture(scope="module")
def recon(survey):
    return open_reconstruction(survey.metashape_project)


def _truth_vs(recon, truth):
    p = recon.project_points(truth["xyz"], "EPSG:32654")
    index = {lab: i for i, lab in enumerate(p.camera_labels)}
    cam = np.array([index[n] for n in truth["obs_photo"]])
    return p, cam, p.pixels[cam, truth["obs_point"]]


def test_outputs_and_what_is_not_written(survey, truth, recon):
    assert survey.rolling_shutter and survey.pix4d_project is None and survey.pix4d_params is None
    assert not os.path.exists(os.path.join(survey.folder, "pix4d"))
    assert truth["rolling_shutter"] is True and len(truth["obs_point"]) > 5000
    assert all("rolling_shutter" in ph for ph in truth["photos"].values())
    with zipfile.ZipFile(os.path.join(survey.folder, "metashape", "demo_survey.files", "0",
                                      "chunk.zip")) as z:
        doc = z.read("doc.xml").decode()
    assert doc.count("<rolling_shutter>") == 36 and 'name="rolling_shutter" value="true"' in doc
    assert len(recon.rolling_shutter_cameras) == 36
    assert any(n.startswith("rolling-shutter compensation applied: 36 of 36") for n in recon.notes)


def test_truth_pixels_through_the_metashape_project(recon, truth):
    """Independent: 0.01 px from the independent pixels with the motion; the motion itself
    moves the points by pixels (test power)."""
    p, cam, uv = _truth_vs(recon, truth)
    err = np.abs(uv - truth["obs_pixel"]).max()
    print(f"\nrolling-shutter demo: max error {err:.1e} px over {len(uv)} observations")
    assert err < 0.01
    w, h = truth["image_size"]
    t = truth["obs_pixel"]
    margin = np.minimum.reduce([t[:, 0], w - t[:, 0], t[:, 1], h - t[:, 1]])
    assert np.all(p.status[cam, truth["obs_point"]][margin > 0.01] == INSIDE)
    still = open_reconstruction(recon.source)
    for c in still.cameras:
        c.rolling_shutter = None
    _, _, uv0 = _truth_vs(still, truth)
    moved = np.hypot(*(uv0 - truth["obs_pixel"]).T)
    assert np.median(moved) > 1.5 and moved.max() > 10


def test_markers_carry_the_moving_pixels(recon, truth):
    """Independent: the markers the generator pinned sit on the independent pixels."""
    ids = truth["points"]["id"]
    for m in recon.markers:
        sel = truth["obs_point"] == ids.index(m.label)
        want = {truth["obs_photo"][i]: truth["obs_pixel"][i] for i in np.flatnonzero(sel)}
        assert set(m.observations) == set(want)
        for cam, uv in m.observations.items():
            assert np.allclose(uv, want[cam], atol=1e-5)


def test_photos_are_rendered_with_the_motion(survey, truth, recon):
    """Independent pixels: at the truth pixels the photos show the orthomosaic's colours; at the pixels a still
    camera would give (2 px or more away) they do not."""
    import imagecodecs
    import tifffile
    still = open_reconstruction(recon.source)
    for c in still.cameras:
        c.rolling_shutter = None
    _, _, uv0 = _truth_vs(still, truth)
    sel = np.hypot(*(uv0 - truth["obs_pixel"]).T) > 2.0
    assert sel.sum() > 3000
    xyz = truth["xyz"][truth["obs_point"][sel]]
    ortho = tifffile.imread(survey.orthomosaic).astype(float)
    col = ((xyz[:, 0] - 319800.0) / 0.01).astype(int)
    row = ((3956050.0 - xyz[:, 1]) / 0.01).astype(int)
    ref = np.mean([ortho[np.clip(row + dr, 0, ortho.shape[0] - 1),
                         np.clip(col + dc, 0, ortho.shape[1] - 1)]
                   for dr in range(-2, 2) for dc in range(-2, 2)], axis=0)
    photos = truth["obs_photo"][sel]

    def colours(uv):
        out = np.empty((len(uv), 3))
        for name in sorted(set(photos)):
            k = photos == name
            path = os.path.join(survey.folder, truth["photos"][name]["file"])
            img = imagecodecs.jpeg8_decode(open(path, "rb").read())
            c = np.clip(np.floor(uv[k, 0]).astype(int), 0, img.shape[1] - 1)
            r = np.clip(np.floor(uv[k, 1]).astype(int), 0, img.shape[0] - 1)
            out[k] = img[r, c]
        return out

    green = lambda c: c[:, 1] - c[:, 0]                  # noqa: E731 (vegetation contrast)
    moving = np.corrcoef(green(colours(truth["obs_pixel"][sel])), green(ref))[0, 1]
    fixed = np.corrcoef(green(colours(uv0[sel])), green(ref))[0, 1]
    print(f"colour correlation at the moving pixels {moving:.3f}, "
          f"at still-camera pixels {fixed:.3f}")
    # the drop asked was 0.2 before the field had margin grass (issue 32): the grass strip is
    # green at any pixel offset, so still-camera pixels keep more correlation (0.85 vs 0.97)
    assert moving > 0.88 and fixed < moving - 0.1


def test_labelme_vertices_project_back_to_their_clicks(survey, truth, recon):
    """Independent: the LabelMe truth's map points (cast by the generator) project onto their
    clicks by the independent camera; through our reader too."""
    n = 0
    for rel, doc in truth["labelme"].items():
        for shape in doc["shapes"]:
            ind = independent_camera.photo_pixels(truth, doc["photo"], np.array(shape["map"]))[0]
            assert np.abs(ind - np.array(shape["pixels"])).max() < 0.01
            p = recon.project_points(np.array(shape["map"]), "EPSG:32654", cameras=[doc["photo"]])
            assert np.abs(p.pixels[0] - np.array(shape["pixels"])).max() < 0.01
            n += len(shape["pixels"])
    assert n > 20


def test_footprint_rings_project_back_onto_the_photo_border(recon):
    """Footprints get the motion for free: every ring point, projected back, is on the border
    of its photo (each border pixel's ray leaves from its row's centre)."""
    ground = float(np.median(recon.camera_centres("EPSG:32654")[1][:, 2])) - 25.0
    fps = camera_footprints(recon, ground, output_crs="EPSG:4326", cameras=recon.aligned_cameras[:6])
    s = recon.sensors["0"]
    for fp in fps:
        assert fp.complete
        p = recon.project_points(fp.ring, "EPSG:4326", cameras=[fp.label]).pixels[0]
        edge = np.minimum.reduce([np.abs(p[:, 0]), np.abs(p[:, 0] - s.width), np.abs(p[:, 1]),
                                  np.abs(p[:, 1] - s.height)])
        assert edge.max() < 1e-3
