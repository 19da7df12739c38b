"""Orthorectify ROIs, in real QGIS and through qgis_process, on the demo survey."""
import os

import numpy as np
import pytest
from qgis.core import QgsProcessingContext, QgsProcessingException, QgsProcessingFeedback

ALG = "easyidp:orthorectifyrois"


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("ortho_survey")), seed=0, size="small")


def _run(params):
    import processing
    return processing.run(ALG, params, context=QgsProcessingContext(),
                          feedback=QgsProcessingFeedback())


def test_best_photo_per_plot(provider, survey, tmp_path):
    from osgeo import gdal
    res = _run({"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
                "PROJECT": survey.metashape_project, "DSM": survey.dsm,
                "OUTPUT_FOLDER": str(tmp_path / "best")})
    assert res["WRITTEN"] == 40 and len(res["OUTPUT_FILES"]) == 40
    ds = gdal.Open(os.path.join(str(tmp_path / "best"), "A1.tif"))
    assert ds.RasterCount == 4 and "UTM zone 54N" in ds.GetProjection()
    assert ds.GetRasterBand(4).GetColorInterpretation() == gdal.GCI_AlphaBand
    alpha = ds.GetRasterBand(4).ReadAsArray()
    assert 0.5 < (alpha == 255).mean() < 1.0            # the plot, not its bounding box
    assert 0.03 < ds.GetGeoTransform()[1] < 0.045       # native resolution at 25 m


def test_named_photo_and_bad_inputs(provider, survey, tmp_path):
    res = _run({"ROIS": survey.plots_geojson, "NAME_FIELD": "plot_id",
                "PROJECT": survey.pix4d_project, "DSM": survey.dsm, "SELECTION": 2,
                "PHOTO": "DJI_0005.JPG", "GSD": 0.05, "OUTPUT_FOLDER": str(tmp_path / "one")})
    assert 0 < res["WRITTEN"] < 40                     # the plots that photo sees
    with pytest.raises(QgsProcessingException, match="give the photo's label"):
        _run({"ROIS": survey.plots_geojson, "PROJECT": survey.pix4d_project, "DSM": survey.dsm,
              "SELECTION": 2, "OUTPUT_FOLDER": str(tmp_path / "x")})
    with pytest.raises(QgsProcessingException, match="no camera labelled 'NOPE'"):
        _run({"ROIS": survey.plots_geojson, "PROJECT": survey.pix4d_project, "DSM": survey.dsm,
              "SELECTION": 2, "PHOTO": "NOPE", "OUTPUT_FOLDER": str(tmp_path / "x")})


def test_headless(qp_env, survey, tmp_path):
    from easyidp_toolbox.scripts.qgis_process import run_algorithm
    res = run_algorithm(ALG, {"ROIS": survey.plots_geojson, "NAME_FIELD": "plot_id",
                              "PROJECT": survey.metashape_project, "DSM": survey.dsm,
                              "SELECTION": 1, "GSD": 0.08, "OUTPUT_FOLDER": tmp_path / "all"},
                        qp_env)
    assert res["WRITTEN"] > 80
    assert len(os.listdir(tmp_path / "all")) == res["WRITTEN"]
    assert np.all([f.endswith(".tif") for f in res["OUTPUT_FILES"]])


def test_mask_none_keeps_every_framed_pixel(provider, survey, tmp_path):
    """[consistency only] MASK 'none' (Orthority's behaviour) against the occlusion mask, same
    ROIs and photos: every pixel the mask keeps is kept with the same values, and the pixels
    only 'none' keeps are the hidden ground (some, on the demo's oblique views of its trees)."""
    from osgeo import gdal
    runs = {}
    for mask in (0, 1):
        res = _run({"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
                    "PROJECT": survey.metashape_project, "DSM": survey.dsm, "SELECTION": 1,
                    "GSD": 0.08, "MASK": mask, "OUTPUT_FOLDER": str(tmp_path / f"m{mask}")})
        runs[mask] = sorted(res["OUTPUT_FILES"])
    assert [os.path.basename(f) for f in runs[0]] == [os.path.basename(f) for f in runs[1]]
    extra = 0
    for fa, fb in zip(runs[0], runs[1]):
        a, b = gdal.Open(fa).ReadAsArray(), gdal.Open(fb).ReadAsArray()
        masked, none = a[3] > 0, b[3] > 0
        assert not (masked & ~none).any()
        assert np.array_equal(a[:3, masked], b[:3, masked])
        extra += int((none & ~masked).sum())
    assert extra > 0


@pytest.fixture(scope="module")
def thermal(survey):
    """The demo survey's thermal camera: FLIR JPEGs of a known temperature field, the first 6
    photos (same file names as the survey's, so its projects measure them)."""
    from easyidp_toolbox.core.demo.thermal import write_thermal_photos
    return write_thermal_photos(survey.folder, seed=0, limit=6)


def test_headless_plot_temperatures(qp_env, survey, thermal, tmp_path):
    """[independent] qgis_process with VALUES = temperature on the thermal photos: GDAL reads
    float32 GeoTIFFs whose band says degC and temp_c, NaN nodata, alpha, the conversion note
    in the metadata; the median of each plot's pixels is the temperature the field was made
    with (thermal_truth, not read by the tool) within 0.1 °C (noise 0.05 °C per pixel)."""
    from osgeo import gdal
    from easyidp_toolbox.scripts.qgis_process import run_algorithm
    res = run_algorithm(ALG, {"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
                              "PROJECT": survey.metashape_project, "DSM": survey.dsm,
                              "PHOTOS": thermal["folder"], "SELECTION": 1, "GSD": 0.06,
                              "VALUES": 1, "OUTPUT_FOLDER": tmp_path / "temp"}, qp_env)
    assert res["WRITTEN"] >= 10
    checked = 0
    for path in res["OUTPUT_FILES"]:
        ds = gdal.Open(path)
        band = ds.GetRasterBand(1)
        assert band.DataType == gdal.GDT_Float32 and band.GetUnitType() == "degC"
        assert band.GetDescription() == "temp_c" and np.isnan(band.GetNoDataValue())
        assert ds.GetRasterBand(2).GetColorInterpretation() == gdal.GCI_AlphaBand
        assert ds.GetMetadataItem("EASYIDP_VALUES") == "temperature"
        assert "Planck" in ds.GetMetadataItem("EASYIDP_VALUES_NOTE")
        t = band.ReadAsArray()
        plot = os.path.basename(path).split("_DJI_")[0]
        if np.isfinite(t).sum() > 200:
            assert abs(np.nanmedian(t) - thermal["plots"][plot]) < 0.1, path
            checked += 1
        del ds
    assert checked >= 5


def test_thermal_photo_whose_raw_data_cannot_be_read(provider, survey, thermal, tmp_path):
    """[independent] A thermal photo whose FLIR records lost a segment (damaged here): the
    tool stops with a message naming the photo when it is the only one asked for."""
    import shutil
    import struct
    folder = tmp_path / "thermal"
    shutil.copytree(thermal["folder"], folder)
    data = (folder / "DJI_0003.JPG").read_bytes()
    k = data.index(b"FLIR\x00\x01\x01")
    (n,) = struct.unpack(">H", data[k - 2:k])
    (folder / "DJI_0003.JPG").write_bytes(data[:k - 4] + data[k - 2 + n:])
    with pytest.raises(QgsProcessingException,
                       match=r"DJI_0003\.JPG.*FLIR raw data cannot be read"):
        _run({"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
              "PROJECT": survey.metashape_project, "DSM": survey.dsm, "PHOTOS": str(folder),
              "SELECTION": 2, "PHOTO": "DJI_0003", "GSD": 0.08, "VALUES": 1, "MASK": 1,
              "OUTPUT_FOLDER": str(tmp_path / "out")})
