"""Hostile inputs through the real qgis_process, each with the message it must give (issue 40,
"Messages that mislead"): the true reason, naming the input, saying what to do.

The damaged files are made here by cutting real files short or emptying them; the layers
without a CRS and the 16-bit, float and JPEG YCbCr orthomosaics are written by GDAL
(``ogr2ogr``/``gdal_translate`` through its Python bindings), not by our code. The colour truth
of the YCbCr crops is GDAL's own decoding of the same file.
"""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from easyidp_toolbox.scripts.qgis_process import run


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("hostile_survey")), seed=0, size="small")


@pytest.fixture(scope="module")
def trial(tmp_path_factory):
    from easyidp_toolbox.core.demo.trial import make_demo_trial
    return make_demo_trial(str(tmp_path_factory.mktemp("hostile_trial")))


def _run(env, alg, **params):
    """(exit code, the message: stderr when it failed, else the log as text)."""
    proc = run(["--json", "run", alg, "--"] + [f"{k}={v}" for k, v in params.items()], env)
    if proc.returncode != 0:
        return proc.returncode, proc.stderr
    log = json.loads(proc.stdout).get("log", {})
    return 0, "\n".join(line for lines in log.values() for line in lines)


def _crop(env, raster, rois, out, **more):
    return _run(env, "easyidp:croprasterbyrois", INPUT=raster, ROIS=rois, OUTPUT_FOLDER=out,
                OUTPUT_INDEX="", **more)


def test_empty_and_damaged_inputs_say_what_is_wrong_not_not_found(qp_env, survey, tmp_path):
    """QGIS's own check said '<file> not found' for each of these existing files."""
    empty_tif, empty_json = tmp_path / "empty.tif", tmp_path / "empty.geojson"
    empty_tif.write_bytes(b"")
    empty_json.write_bytes(b"")
    cut_tif = tmp_path / "cut.tif"
    cut_tif.write_bytes(Path(survey.orthomosaic).read_bytes()[:60])
    cut_json = tmp_path / "cut.geojson"
    cut_json.write_bytes(Path(survey.plots_geojson).read_bytes()[:700])
    cases = [(empty_tif, survey.plots_geojson, "Raster", "it is empty (0 bytes)"),
             (cut_tif, survey.plots_geojson, "Raster", "GDAL cannot open it"),
             (survey.orthomosaic, empty_json, "ROIs", "it is empty (0 bytes)"),
             (survey.orthomosaic, cut_json, "ROIs", "it is not valid JSON")]
    for raster, rois, what, why in cases:
        code, msg = _crop(qp_env, raster, rois, tmp_path / "out")
        bad = raster if what == "Raster" else rois
        assert code == 1, msg
        assert f"{bad} exists but cannot be read as a layer: {why}" in msg and what in msg, msg
        assert "not found" not in msg, msg
    assert not (tmp_path / "out").exists()


def _no_crs_gpkg(src, folder, name):
    """A GeoPackage without a CRS as GDAL writes one: from a shapefile without its .prj
    (GDAL 3.6 gives the layer srs_id 0, which QGIS reads as 'Undefined geographic SRS'; GDAL
    3.10 and later srs_id 99999, 'Undefined SRS'). Returns (path, srs_id)."""
    from osgeo import gdal
    gdal.UseExceptions()
    shp = folder / f"{name}.shp"
    gdal.VectorTranslate(str(shp), str(src), format="ESRI Shapefile")
    os.remove(shp.with_suffix(".prj"))
    out = folder / f"{name}.gpkg"
    gdal.VectorTranslate(str(out), str(shp), format="GPKG")
    import sqlite3
    with sqlite3.connect(out) as con:
        srs_id = con.execute("SELECT srs_id FROM gpkg_geometry_columns").fetchone()[0]
    assert srs_id in (0, 99999), srs_id
    return out, srs_id


def test_a_geopackage_layer_without_a_crs_is_called_so(qp_env, survey, tmp_path):
    """Before: the crop said "ROI '1' has non-finite coordinates" (QGIS transformed from the
    'Undefined geographic SRS'), and Create plot grid called the corners geographic and advised
    a UTM zone computed from metres taken as degrees."""
    rois, srs_id = _no_crs_gpkg(survey.plots_geojson, tmp_path, "plots_nocrs")
    code, msg = _crop(qp_env, survey.orthomosaic, rois, tmp_path / "out")
    assert code == 1 and "the ROI layer 'plots_nocrs' has no CRS" in msg, msg
    assert "Assign projection" in msg, msg
    assert srs_id != 0 or "Undefined geographic SRS" in msg, msg
    assert "non-finite" not in msg
    corners = tmp_path / "corners.geojson"
    corners.write_text(json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"id": k}, "geometry": {"type": "Point", "coordinates": xy}}
        for k, xy in enumerate([[368010, 3956010], [368050, 3956010], [368050, 3955980],
                                [368010, 3955980]])]}))
    pts, _ = _no_crs_gpkg(corners, tmp_path, "corners_nocrs")
    code, msg = _run(qp_env, "easyidp:createplotgrid", CORNERS=pts, ROWS=2, COLS=2,
                     OUTPUT=tmp_path / "grid.gpkg")
    assert code == 1 and "the layer has no CRS" in msg and "UTM zone 4" not in msg, msg
    assert not (tmp_path / "grid.gpkg").exists()


@pytest.mark.parametrize("dtype,scale", [("UInt16", "0 255 0 65535"), ("Float32", "0 255 0 1")])
def test_a_16_bit_or_float_rgb_orthomosaic_is_fitted_as_rgb(qp_env, trial, tmp_path, dtype, scale):
    """Before: 'a 3-band raster is not RGB: choose the NDVI index'. ExG is a ratio, so the same
    colours in 16 bits or floats give the 8-bit fit (truth: the fit of the 8-bit original)."""
    from osgeo import gdal
    deep = tmp_path / f"ortho_{dtype}.tif"
    gdal.Translate(str(deep), trial.orthomosaic,
                   options=f"-ot {dtype} -scale {scale} -co TILED=YES -co COMPRESS=DEFLATE")
    assert gdal.Open(str(deep)).GetRasterBand(1).GetColorInterpretation() == gdal.GCI_RedBand
    grid = os.path.join(trial.folder, "plots.gpkg")
    code, msg = _run(qp_env, "easyidp:fitplotgrid", GRID=grid, ORTHOMOSAIC=deep,
                     OUTPUT=tmp_path / "fit.gpkg")
    assert code == 0, msg
    assert "NDVI" not in msg
    code8, msg8 = _run(qp_env, "easyidp:fitplotgrid", GRID=grid, ORTHOMOSAIC=trial.orthomosaic,
                       OUTPUT=tmp_path / "fit8.gpkg")
    assert code8 == 0
    glob_line = [line for line in msg.splitlines() if line.startswith("Global correction")]
    assert glob_line and glob_line == [line for line in msg8.splitlines()
                                       if line.startswith("Global correction")], (msg, msg8)


def test_a_buffer_larger_than_the_roi_is_named(qp_env, survey, tmp_path):
    """Before: the summary blamed the DSM ('no valid pixel under any of them')."""
    code, msg = _run(qp_env, "easyidp:roiheightsfromdsm", DSM=survey.dsm, ROIS=survey.plots_gpkg,
                     BUFFER=-100, OUTPUT=tmp_path / "h.gpkg")
    assert code == 0, msg
    assert "all empty (NULL): the buffer of -100 (DSM map units) shrinks it to nothing" in msg
    assert "no valid pixel" not in msg and "smaller than a pixel" not in msg


def _tmpfs_ro(path):
    path.mkdir()
    ok = subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=1m", "tmpfs", str(path)],
                        capture_output=True).returncode == 0
    return path if ok else None


def test_a_read_only_output_location_is_called_so(qp_env, survey, tmp_path):
    """A real read-only file system (a tmpfs mounted ro: make test runs as root, on the host and
    in the Debian roots, so mounting it must work; a failure to mount fails, never skips).
    Before: QGIS's writer said 'unable to open database file'."""
    ro = _tmpfs_ro(tmp_path / "ro")
    assert ro is not None, "mounting a read-only tmpfs failed: make test runs as root"
    try:
        for out in (ro / "h.gpkg", ro / "sub" / "h.gpkg"):
            code, msg = _run(qp_env, "easyidp:roiheightsfromdsm", DSM=survey.dsm,
                             ROIS=survey.plots_gpkg, OUTPUT=out)
            assert code == 1 and f"{out} cannot be written: it is on a read-only file system" in msg, msg
            assert "unable to open database" not in msg
        code, msg = _crop(qp_env, survey.orthomosaic, survey.plots_gpkg, ro / "crops")
        assert code == 1 and "read-only file system" in msg and str(ro / "crops") in msg, msg
    finally:
        subprocess.run(["umount", str(ro)])


def test_a_jpeg_ycbcr_orthomosaic_is_cropped_to_rgb_and_alpha(qp_env, survey, tmp_path):
    """Written with gdal_translate -co COMPRESS=JPEG -co PHOTOMETRIC=YCBCR (tiled, and in
    strips with GDAL's internal mask): every crop is red, green, blue and alpha, without a
    nodata, with GDAL's decoded colours inside the ROI (truth: GDAL's ReadAsArray)."""
    from osgeo import gdal
    gdal.UseExceptions()
    for name, opts in (("tiled", "-co TILED=YES"), ("strips", "-mask 1")):
        ycc = tmp_path / f"ycbcr_{name}.tif"
        gdal.Translate(str(ycc), survey.orthomosaic, options=f"-b 1 -b 2 -b 3 {opts} -co "
                       "COMPRESS=JPEG -co PHOTOMETRIC=YCBCR")
        out = tmp_path / f"crops_{name}"
        code, msg = _crop(qp_env, ycc, survey.plots_gpkg, out, NAME_FIELD="plot_id")
        assert code == 0, msg
        src = gdal.Open(str(ycc))
        sgt = src.GetGeoTransform()
        for pid in survey.plot_ids[::7]:
            ds = gdal.Open(str(out / f"{pid}.tif"))
            assert ds.RasterCount == 4
            assert [ds.GetRasterBand(i + 1).GetColorInterpretation() for i in range(4)] == [
                gdal.GCI_RedBand, gdal.GCI_GreenBand, gdal.GCI_BlueBand, gdal.GCI_AlphaBand]
            assert all(ds.GetRasterBand(i + 1).GetNoDataValue() is None for i in range(4))
            gt = ds.GetGeoTransform()
            x0, y0 = round((gt[0] - sgt[0]) / sgt[1]), round((gt[3] - sgt[3]) / sgt[5])
            ref = src.ReadAsArray(x0, y0, ds.RasterXSize, ds.RasterYSize)
            got = ds.ReadAsArray()
            inside = got[3] == 255
            assert inside.mean() > 0.5 and set(np.unique(got[3])) <= {0, 255}
            assert np.array_equal(got[:3][:, inside], ref[:, inside]), pid
            assert not got[:3][:, ~inside].any()
