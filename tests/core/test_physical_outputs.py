"""Raw-photo crops and orthorectified ROIs in physical units (VALUES = temperature): the
tools that read photo pixels go through core/radiometry, and their float32 TIFFs state the
unit. The FLIR views of test_thermal_statistics (a temperature field the test defines, raw
values the test wrote, a saturated block in IMG_0)."""
import json
import shutil
import struct
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import shapely
import tifffile

from easyidp_toolbox.core.errors import EasyIDPError, InputError
from easyidp_toolbox.core.projection import crop_photos
from easyidp_toolbox.core.projection.ortho import orthorectify_rois
from easyidp_toolbox.core.raster import epsg_geo_tags, open_geotiff, write_geotiff

sys.path.insert(0, str(Path(__file__).parent))
from test_photo_statistics import OFFSET  # noqa: E402
from test_thermal import CAMERA, PHOTO  # noqa: E402
import test_thermal_statistics  # noqa: E402
from easyidp_toolbox.tests.support.planck_reference import planck_by_hand  # noqa: E402

thermal = test_thermal_statistics.thermal   # the fixture: three FLIR views, made for this module
P32 = {k: float(np.float32(v)) for k, v in {**CAMERA, **PHOTO}.items()}   # as the photo stores


def _celsius(raw: np.ndarray) -> np.ndarray:
    """The test's own Planck formula for every raw value (65535: saturated → NaN)."""
    table = {int(v): planck_by_hand(float(v), P32["r1"], P32["r2"], P32["b"], P32["f"], P32["o"],
                                    P32["emissivity"], P32["object_distance"],
                                    P32["reflected_temperature"], P32["atmospheric_temperature"],
                                    P32["relative_humidity"]) for v in np.unique(raw)}
    out = np.vectorize(table.get, otypes=[np.float64])(raw)
    out[raw == 65535] = np.nan
    return out


def _gdal_items(path):
    """GDAL's metadata (TIFF tag 42112) and nodata (42113), parsed here with ElementTree."""
    with tifffile.TiffFile(path) as tif:
        tags = tif.pages.first.tags
        root = ET.fromstring(tags[42112].value)
        nodata = tags[42113].value.strip("\x00 ")
    items = {(i.get("name"), i.get("sample")): i.text for i in root.iter("Item")}
    return items, nodata


def test_crops_in_celsius_equal_planck_of_the_raw_values(thermal, tmp_path):
    """[independent] Every crop pixel equals the test's Planck formula
    (tests/support/planck_reference.py) of the raw value the test wrote at that photo pixel
    (the crop's offset from its sidecar), to 0.001 °C; the saturated block is NaN, not
    averaged (300 pixels); float32 with the polygon as alpha; the unit and the conversion note
    in GDAL's metadata and the sidecar."""
    recon, rois, res, raws, folder = thermal
    out = crop_photos(res, tmp_path / "crops", folder, values="temperature",
                      previews_folder=tmp_path / "previews")
    assert len(out.files) == len(res) == 3 and not out.skipped_photos and len(out.previews) == 1
    for path, side in zip(out.files, out.sidecars):
        assert path.endswith(".tif")
        meta = json.loads(Path(side).read_text())
        j = int(meta["photo"][-1])
        arr = tifffile.imread(path)
        assert arr.dtype == np.float32 and arr.shape[2] == 2
        (c0, r0), (w, h) = meta["offset"], meta["crop_size"]
        want = _celsius(raws[j][r0:r0 + h, c0:c0 + w])
        np.testing.assert_allclose(arr[..., 0], want, atol=1e-3)        # NaN where NaN
        assert np.isnan(arr[..., 0]).sum() == (300 if j == 0 else 0)
        assert set(np.unique(arr[..., 1])) <= {0.0, 1.0} and arr[..., 1].any()
        items, nodata = _gdal_items(path)
        assert nodata == "nan"
        assert items[("UNITTYPE", "0")] == "degC" and items[("DESCRIPTION", "0")] == "temp_c"
        assert items[("EASYIDP_VALUES", None)] == "temperature"
        assert "Planck" in items[("EASYIDP_VALUES_NOTE", None)]
        assert meta["values"]["unit"] == "degC" and "Planck" in meta["values"]["note"]


def _flat_dsm(path):
    """A flat DSM at Z = 0 under the views (10 cm cells)."""
    write_geotiff(str(path), np.zeros((300, 460), np.float32),
                  (OFFSET[0] - 20.0, 0.1, 0.0, OFFSET[1] + 15.0, 0.0, -0.1), epsg_geo_tags(32654))
    return str(path)


def _field(i, col, row):
    """The temperature the fixture wrote at (continuous) photo pixel indices of view ``i``."""
    return 24.0 + 5.0 * np.sin(col / 37.0 + i) + 3.0 * np.cos(row / 53.0) + 0.5 * i


def test_ortho_in_celsius_samples_the_field_and_masks_saturation(thermal, tmp_path):
    """[independent values; geometry from our project_points, tested elsewhere] Each view's
    orthorectified ROI in °C over a flat DSM: at every output pixel with a value, the
    temperature equals the field the test defined at the photo pixel the pixel's ground point
    projects to, to 0.03 °C (raw rounding and bilinear sampling); in IMG_0 the pixels whose
    bilinear sample touches the saturated block are NaN with alpha 0 (masked, never averaged:
    every value stays in the field's range); float32, unit and NaN nodata in GDAL's metadata."""
    recon, rois, res, raws, folder = thermal
    dsm = _flat_dsm(tmp_path / "dsm.tif")
    out = orthorectify_rois(rois, recon, dsm, tmp_path / "ortho", selection="all",
                            photos_folder=folder, occlusion=False, values="temperature")
    assert len(out.files) == 3 and not out.skipped
    ring = shapely.Polygon(rois[0].rings[0])
    for path, label in zip(out.files, out.photos):
        i = int(label[-1])
        img = tifffile.imread(path)
        assert img.dtype == np.float32 and img.shape[2] == 2
        t, alpha = img[..., 0], img[..., 1]
        assert np.array_equal(np.isnan(t), alpha == 0)
        c, a, _, f, _, e = open_geotiff(path).geotransform
        rr, cc = np.indices(t.shape).reshape(2, -1)
        x, y = c + a * (cc + 0.5), f + e * (rr + 0.5)
        inside = shapely.contains_xy(ring, x, y)
        rr, cc, x, y = rr[inside], cc[inside], x[inside], y[inside]
        uv = recon.project_points(np.column_stack([x, y, np.zeros(len(x))]), recon.crs,
                                  cameras=[recon.camera(label)]).pixels[0]
        col, row = uv[:, 0] - 0.5, uv[:, 1] - 0.5                # continuous pixel indices
        touches = (i == 0) & (col > 389) & (col < 420) & (row > 289) & (row < 300)
        assert touches.sum() > (300 if i == 0 else -1)
        assert np.isnan(t[rr[touches], cc[touches]]).all()
        got = t[rr[~touches], cc[~touches]]
        assert np.isfinite(got).all()
        assert np.abs(got - _field(i, col[~touches], row[~touches])).max() < 0.03
        items, nodata = _gdal_items(path)
        assert nodata == "nan" and items[("UNITTYPE", "0")] == "degC"
        assert items[("DESCRIPTION", "1")] == "alpha"


def _lose_a_record(src: Path, dst: Path) -> None:
    """``src`` without the second segment of its FLIR records (the raw data cannot be read)."""
    data = src.read_bytes()
    k = data.index(b"FLIR\x00\x01\x01")
    (n,) = struct.unpack(">H", data[k - 2:k])
    dst.write_bytes(data[:k - 4] + data[k - 2 + n:])


def test_a_photo_whose_raw_data_cannot_be_read(thermal, tmp_path):
    """[independent] IMG_1 with a FLIR record segment lost (a damaged file made here): the
    crops skip it with a message naming the photo; orthorectifying from it alone stops with
    that message; the other views are written. An unknown VALUES is refused."""
    recon, rois, res, raws, folder = thermal
    bad = tmp_path / "thermal"
    shutil.copytree(folder, bad)
    _lose_a_record(folder / "IMG_1.jpg", bad / "IMG_1.jpg")
    out = crop_photos(res, tmp_path / "crops", bad, values="temperature")
    assert len(out.files) == 2 and list(out.skipped_photos) == ["IMG_1"]
    assert "IMG_1.jpg" in out.skipped_photos["IMG_1"] and \
        "FLIR raw data cannot be read" in out.skipped_photos["IMG_1"]
    with pytest.raises(InputError, match=r"IMG_1\.jpg.*FLIR raw data cannot be read"):
        orthorectify_rois(rois, recon, _flat_dsm(tmp_path / "dsm.tif"), tmp_path / "ortho",
                          selection="photo", photo="IMG_1", photos_folder=bad,
                          occlusion=False, values="temperature")
    with pytest.raises(EasyIDPError, match="Unknown values 'kelvin'"):
        crop_photos(res, tmp_path / "crops2", folder, values="kelvin")


def test_training_images_in_celsius(thermal, tmp_path):
    """[independent] Export a training set with values = temperature, whole photos and tiles:
    every image is a float32 TIFF (PNG and JPEG cannot hold °C) equal to the test's Planck
    formula of the raw values the test wrote in its window of the photo, NaN on the saturated
    block; COCO names the .tif files; the unit is in GDAL's metadata and the manifest."""
    from easyidp_toolbox.core.projection import export_training_set
    recon, rois, res, raws, folder = thermal
    dsm = _flat_dsm(tmp_path / "dsm.tif")
    for tile in (0, 256):
        out = tmp_path / f"set{tile}"
        export_training_set(rois, ["plot"], recon, dsm, out, photos_folder=folder,
                            split="photo", tile_size=tile, values="temperature")
        coco = [json.loads((out / "coco" / f"instances_{s}.json").read_text())
                for s in ("train", "val")]
        names = [(s, im) for s, doc in zip(("train", "val"), coco) for im in doc["images"]]
        assert len(names) >= 2 and all(im["file_name"].endswith(".tif") for _, im in names)
        for s, im in names:
            path = out / "images" / s / im["file_name"]
            arr = tifffile.imread(path)
            assert arr.dtype == np.float32
            x0, y0, w, h = im["photo_window"]
            j = int(im["photo"][-1])
            np.testing.assert_allclose(arr, _celsius(raws[j][y0:y0 + h, x0:x0 + w]), atol=1e-3)
            assert _gdal_items(path)[0][("UNITTYPE", "0")] == "degC"
            assert (out / "yolo_detect" / "images" / s / im["file_name"]).exists()
        manifest = json.loads((out / "training_set.json").read_text())
        assert manifest["values"] == {"values": "temperature", "unit": "degC"}


def test_crops_in_reflectance_equal_the_spectral_truth(demo, tmp_path):
    """[independent] Crops with values = reflectance of MicaSense-style band files written by
    the demo's multispectral camera (digital numbers from its spectral model's reflectance,
    through its own inverse of MicaSense's model, under a passing cloud, with saturated
    glints): each crop pixel equals the spectral model's reflectance of the RGB photo's pixel
    (mean error < 3e-4), glints NaN; one band, named by its band tag, unit reflectance."""
    import dataclasses

    from easyidp_toolbox.core import open_reconstruction, read_geojson
    from easyidp_toolbox.core.demo.multispectral import true_reflectance, write_multispectral_flight
    from easyidp_toolbox.core.projection import back_project
    from easyidp_toolbox.core.photos import read_photo
    from easyidp_toolbox.core.raster import DSM
    from easyidp_toolbox.core.roi import ROISet
    recon = open_reconstruction(demo.metashape_project)
    plots = read_geojson(demo.plots_geojson, name_field="plot_id")
    rois = ROISet([r for r in plots if r.name in ("B3", "C4")], plots.crs)
    bp = back_project(rois, recon, heights=DSM(demo.dsm), max_views=2, min_visible=0.9)
    assert len(bp) >= 2
    rgb = {lab: path for lab, path in zip(bp.photo_labels, bp.photo_paths)}
    used = sorted({bp.photo_labels[j] for j in bp.photo_index})
    flight = write_multispectral_flight([rgb[lab] for lab in used], tmp_path / "ms")
    band = {lab: ("Red", "NIR")[k % 2] for k, lab in enumerate(used)}
    files = {lab: rec["files"][band[lab]] for lab, rec in zip(used, flight)}
    bp = dataclasses.replace(bp, photo_paths=[files.get(lab, p) for lab, p in
                                              zip(bp.photo_labels, bp.photo_paths)])
    out = crop_photos(bp, tmp_path / "crops", values="reflectance")
    assert len(out.files) == len(bp) and not out.skipped_photos
    for path, side in zip(out.files, out.sidecars):
        meta = json.loads(Path(side).read_text())
        lab = meta["camera"]
        arr = tifffile.imread(path)
        assert arr.dtype == np.float32 and arr.shape[2] == 2
        (x0, y0), (w, h) = meta["offset"], meta["crop_size"]
        truth = true_reflectance(read_photo(rgb[lab]))[band[lab]][y0:y0 + h, x0:x0 + w]
        ok = np.isfinite(arr[..., 0])
        assert ok.mean() > 0.97
        assert np.abs(arr[..., 0] - truth)[ok].mean() < 3e-4
        items, nodata = _gdal_items(path)
        assert items[("UNITTYPE", "0")] == "reflectance" and nodata == "nan"
        assert meta["values"]["bands"] == [band[lab]]
