"""``make demo``: build the demo field, run every EasyIDP tool on it through qgis_process, report.

Usage: python -m easyidp_toolbox.scripts.demo OUTPUT_FOLDER
"""
import os
import sys
import time

from ..core.demo_field import make_demo_field
from .qgis_process import qgis_process_env, run_algorithm


def main(out: str) -> int:
    out = os.path.abspath(out)
    t0 = time.time()
    field = make_demo_field(os.path.join(out, "data"))
    steps = [("demo field (orthomosaic, DSM, 24 plots)", time.time() - t0)]
    env = qgis_process_env()

    def step(label, alg, params):
        t = time.time()
        res = run_algorithm(alg, params, env)
        steps.append((label, time.time() - t))
        return res

    dom = step("crop orthomosaic by plots", "easyidp:croprasterbyrois",
               {"INPUT": field.orthomosaic, "ROIS": field.plots, "NAME_FIELD": "plot_id",
                "OUTPUT_FOLDER": os.path.join(out, "crops_orthomosaic")})
    dsm = step("crop DSM by plots", "easyidp:croprasterbyrois",
               {"INPUT": field.dsm, "ROIS": field.plots, "NAME_FIELD": "plot_id",
                "OUTPUT_FOLDER": os.path.join(out, "crops_dsm")})
    heights_path = os.path.join(out, "plots_with_heights.gpkg")
    step("plot heights from DSM (95th percentile)", "easyidp:roiheightsfromdsm",
         {"ROIS": field.plots, "DSM": field.dsm, "MODE": 0, "STATISTIC": 4, "PERCENTILE": 95,
          "OUTPUT": heights_path})
    ground = step("plot ground from DSM (2nd percentile, 0.3 m around)", "easyidp:roiheightsfromdsm",
                  {"ROIS": field.plots, "DSM": field.dsm, "MODE": 0, "STATISTIC": 4,
                   "PERCENTILE": 2, "BUFFER": 0.3, "OUTPUT": os.path.join(out, "plots_ground.gpkg")})

    top, low = _heights(heights_path), _heights(ground["OUTPUT"])
    err = [abs((top[k] - low[k]) - field.canopy_height[k]) for k in top]

    print(f"\nEasyIDP demo: results in {out}")
    for label, seconds in steps:
        print(f"  {seconds:6.2f} s  {label}")
    print(f"  inputs:  {field.orthomosaic}\n           {field.dsm}\n           {field.plots}")
    print(f"  outputs: {os.path.join(out, 'crops_orthomosaic')} ({dom['CROPPED']} GeoTIFFs)\n"
          f"           {os.path.join(out, 'crops_dsm')} ({dsm['CROPPED']} GeoTIFFs)\n"
          f"           {heights_path}")
    print(f"Summary: {dom['CROPPED']} plots cropped from the orthomosaic and the DSM; plot canopy "
          f"height (p95 - ground) vs the generated truth: mean error {100 * sum(err) / len(err):.1f} cm, "
          f"max {100 * max(err):.1f} cm.")
    return 0


def _heights(gpkg: str) -> dict:
    from osgeo import ogr
    ds = ogr.Open(gpkg)  # keep the dataset alive while its layer is read
    return {f["plot_id"]: f["height"] for f in ds.GetLayer(0)}


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "demo_output"))
