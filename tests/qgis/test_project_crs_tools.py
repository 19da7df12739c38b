"""A Metashape chunk in CH1903+ / LV95 as Metashape writes it (issue 24): footprints through
qgis_process with the default output CRS (the chunk's) work, and a chunk CRS PROJ cannot use
stops with a message naming it, not a traceback; PROJECT_CRS then supplies it."""
import numpy as np
from osgeo import ogr

from easyidp_toolbox.tests.support.project_crs import (CENTRE_LV95, LV95_METASHAPE, LV95_SHIFTED,
                                                       chunk_xml)
from easyidp_toolbox.scripts.qgis_process import run, run_algorithm


def test_lv95_chunk_footprints_headless(qp_env, tmp_path):
    path, _ = chunk_xml(tmp_path, LV95_METASHAPE)
    res = run_algorithm("easyidp:camerafootprints", {
        "PROJECT": path, "GROUND_HEIGHT": CENTRE_LV95[2] - 100.0,
        "OUTPUT_CAMERAS": tmp_path / "cams.gpkg", "OUTPUT_FOOTPRINTS": tmp_path / "fp.gpkg"}, qp_env)
    ds = ogr.Open(res["OUTPUT_CAMERAS"])                 # kept: the layer lives in it
    layer = ds.GetLayer(0)
    assert layer.GetSpatialRef().GetAuthorityCode(None) == "2056"
    f = layer.GetNextFeature()
    np.testing.assert_allclose(f.GetGeometryRef().GetPoint(0), CENTRE_LV95, atol=1e-3)


def test_unusable_chunk_crs_names_it_and_project_crs_supplies_it(qp_env, tmp_path):
    path, _ = chunk_xml(tmp_path, LV95_SHIFTED)
    args = ["run", "easyidp:camerafootprints", "--", f"PROJECT={path}",
            f"GROUND_HEIGHT={CENTRE_LV95[2] - 100.0}", f"OUTPUT_CAMERAS={tmp_path / 'c.gpkg'}",
            f"OUTPUT_FOOTPRINTS={tmp_path / 'f.gpkg'}"]
    proc = run(args, qp_env)
    out = proc.stdout + proc.stderr
    assert proc.returncode == 1 and "CH1903+ / LV95" in out and "EPSG code" in out
    assert "Traceback" not in out and "ProjError" not in out
    proc = run(args + ["PROJECT_CRS=EPSG:2056"], qp_env)
    assert proc.returncode == 0, proc.stdout + proc.stderr
