"""Crops of the raw photos and previews (core/projection/photo_crops.py).

Independent checks: crop pixels against the photo array read back by imagecodecs/tifffile,
alpha against an even-odd point-in-polygon test of every pixel centre, one decode per photo
(counted), and the bad-input cases (missing, undecodable, wrong-size photos; folders).
"""
import json
import os
from pathlib import Path

import imagecodecs
import numpy as np
import pytest
import tifffile
from pyproj import CRS

from easyidp_toolbox.core import Cancelled, InputError
from easyidp_toolbox.core.geometry import points_in_rings
from easyidp_toolbox.core.projection import back_project, crop_photos, draw_previews
from easyidp_toolbox.core.projection import photo_crops
from easyidp_toolbox.core.photos import decode as photos_module
from easyidp_toolbox.core.reconstruction import Calibration, Camera, Reconstruction, Sensor
from easyidp_toolbox.core.reconstruction.geodesy import OffsetFrame
from easyidp_toolbox.core.roi import ROI, ROISet

UTM = CRS.from_epsg(32654)
OFFSET = np.array([368000.0, 3956000.0, 0.0])
NADIR = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])


def _scene(tmp_path, ext="png", bands=3, dtype=np.uint8, n_cams=3):
    """Nadir cameras 30 m over flat ground, 800 × 600 photos of random pixels on disk."""
    cal = Calibration(f=680.0, cx=403.2, cy=297.9, k1=-0.06, k2=0.04, p1=0.0009, p2=-0.0006)
    sensor = Sensor("0", "synthetic", 800, 600, cal)
    rng = np.random.default_rng(0)
    folder = tmp_path / "photos"
    folder.mkdir(exist_ok=True)
    cams = []
    for i in range(n_cams):
        path = folder / f"IMG_{i}.{ext}"
        shape = (600, 800) if bands == 1 else (600, 800, bands)
        top = 255 if dtype == np.uint8 else 60000
        img = rng.integers(0, top, shape).astype(dtype)
        if ext == "png":
            path.write_bytes(imagecodecs.png_encode(img))
        else:
            tifffile.imwrite(path, img, photometric="minisblack" if bands != 3 else "rgb",
                             planarconfig="contig")
        cams.append(Camera(str(i), f"IMG_{i}", "0", photo_path=str(path), R=NADIR,
                           C=np.array([4.0 * i, 0.0, 30.0])))
    recon = Reconstruction(Path("synthetic"), "synthetic", "s", UTM, OffsetFrame(UTM, OFFSET),
                           {"0": sensor}, cams)
    squares = []
    for k, (x, y, s) in enumerate([(0, 0, 3), (6, 2, 2), (-9, -6, 5), (14, 0, 2)]):
        ring = np.array([[x - s, y - s], [x + s, y - s], [x + s, y + s], [x - s, y + s]])
        hole = np.array([[x - s / 3, y - s / 3], [x - s / 3, y + s / 3], [x + s / 3, y + s / 3],
                         [x + s / 3, y - s / 3]])
        squares.append(ROI(f"plot/{k}", [[ring + OFFSET[:2], hole + OFFSET[:2]]]))
    res = back_project(ROISet(squares, UTM), recon, heights=0.0, min_visible=0.05)
    return recon, res, folder


def test_crops_equal_the_photo_inside_the_polygon(tmp_path):
    recon, res, _ = _scene(tmp_path)
    decoded = []
    real = photos_module.read_photo

    def counting(path):
        decoded.append(path)
        return real(path)
    photos_module.read_photo = counting
    try:
        out = crop_photos(res, tmp_path / "crops", margin=3, workers=2)
    finally:
        photos_module.read_photo = real
    assert len(decoded) == len(set(decoded)) == len(set(res.photo))     # each photo once
    assert len(out.files) == len(res) and not out.skipped_photos and out.empty == 0
    assert (tmp_path / "crops" / "plot_0").is_dir()                       # '/' made safe
    for png, side in zip(out.files, out.sidecars):
        meta = json.loads(Path(side).read_text())
        assert meta["file"] == os.path.basename(png)
        crop = imagecodecs.imread(png)
        photo = imagecodecs.imread(meta["photo_path"])
        c0, r0 = meta["offset"]
        h, w = crop.shape[:2]
        assert [w, h] == meta["crop_size"]
        assert np.array_equal(crop[..., :3], photo[r0:r0 + h, c0:c0 + w])
        rings = [np.array(r) for p in meta["polygons_crop"] for r in p]
        cc, rr = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
        inside = points_in_rings(cc.ravel(), rr.ravel(), rings).reshape(h, w)
        assert (crop[..., 3] == np.where(inside, 255, 0)).mean() > 0.998  # edge ties aside
        # margin: the polygon's box grown by 3 px (inside the frame)
        allxy = np.concatenate([np.array(r) for p in meta["polygons_photo"] for r in p])
        assert c0 == max(int(np.floor(allxy[:, 0].min())) - 3, 0)
        assert meta["rank"] >= 1 and 0 < meta["score"] <= 1 and "top-left corner" in meta["pixels"]


def test_multiband_16bit_photos_give_tiffs_with_alpha(tmp_path):
    recon, res, _ = _scene(tmp_path, ext="tif", bands=5, dtype=np.uint16, n_cams=1)
    out = crop_photos(res, tmp_path / "crops")
    assert out.files and all(f.endswith(".tif") for f in out.files)
    with tifffile.TiffFile(out.files[0]) as tif:
        page = tif.pages.first
        arr = page.asarray()
        assert arr.dtype == np.uint16 and arr.shape[2] == 6 and page.extrasamples[-1] == 2
    meta = json.loads(Path(out.sidecars[0]).read_text())
    photo = tifffile.imread(meta["photo_path"])
    c0, r0 = meta["offset"]
    assert np.array_equal(arr[..., :5], photo[r0:r0 + arr.shape[0], c0:c0 + arr.shape[1]])
    assert set(np.unique(arr[..., 5])) == {0, 65535}


def test_previews_one_per_roi(tmp_path):
    recon, res, _ = _scene(tmp_path)
    out = draw_previews(res, tmp_path / "previews", max_views=2)
    seen = [n for n, c in zip(res.roi_names, res.photos_per_roi()) if c]
    assert len(out.previews) == len(seen) and not out.files
    sheet = imagecodecs.imread(out.previews[0])
    assert sheet.ndim == 3 and sheet.shape[0] == photo_crops.PREVIEW_HEIGHT + 2 * photo_crops.PREVIEW_GAP


def test_missing_undecodable_and_wrong_size_photos_are_skipped(tmp_path):
    recon, res, folder = _scene(tmp_path)
    os.remove(folder / "IMG_0.png")
    (folder / "IMG_1.png").write_bytes(b"\x89PNG\r\n\x1a\n broken")
    out = crop_photos(res, tmp_path / "crops")
    assert "not found" in out.skipped_photos["IMG_0"]
    assert "IMG_1.png cannot be decoded" in out.skipped_photos["IMG_1"]
    assert out.files and all("IMG_2" in f for f in out.files)
    (folder / "IMG_2.png").write_bytes(imagecodecs.png_encode(np.zeros((10, 10, 3), np.uint8)))
    out = crop_photos(res, tmp_path / "crops3")
    assert "is 10×10 px but the camera's sensor is 800×600" in out.skipped_photos["IMG_2"]
    assert not out.files


def test_photos_folder_override_and_bad_folders(tmp_path):
    recon, res, folder = _scene(tmp_path)
    moved = tmp_path / "moved"
    folder.rename(moved)
    out = crop_photos(res, tmp_path / "crops", photos_folder=moved)
    assert out.files and not out.skipped_photos
    with pytest.raises(InputError, match="does not exist"):
        crop_photos(res, tmp_path / "c2", photos_folder=tmp_path / "nope")
    other = tmp_path / "other"
    other.mkdir()
    (other / "DSC_1.JPG").write_bytes(b"x")
    with pytest.raises(InputError, match="holds none of the project's 3 photos"):
        crop_photos(res, tmp_path / "c3", photos_folder=other)
    with pytest.raises(InputError, match="None of the 3 photos is available"):
        crop_photos(res, tmp_path / "c4")                    # the project's paths are gone


def test_cancel_leaves_no_partial_files(tmp_path):
    recon, res, _ = _scene(tmp_path)
    calls = []
    with pytest.raises(Cancelled):
        crop_photos(res, tmp_path / "crops", is_cancelled=lambda: calls.append(1) or len(calls) > 2)
    assert not list((tmp_path / "crops").rglob("*.part*"))
