"""The thermal part of ``make demo``: the demo survey's thermal camera (FLIR radiometric JPEGs
of a known temperature field, ``core/demo/thermal.py``) measured by
easyidp:photostatistics with VALUES = temperature through qgis_process, each plot's temperature
printed against the field's truth."""
import os
import time

import numpy as np

IND = "[independent]"


def run_thermal_demo(steps, s, out, features) -> list:
    """Write the thermal photos into the survey, run the tool into ``out``; returns the
    summary lines to print."""
    from ..core.demo.thermal import write_thermal_photos
    t0 = time.time()
    th = write_thermal_photos(s["OUTPUT_FOLDER"], seed=0)
    print(f"  {time.time() - t0:6.1f} s  thermal camera: {len(th['photos'])} FLIR radiometric "
          "JPEGs of a known temperature field (core generator, not a tool run)", flush=True)
    res = steps.run("plot temperatures from the thermal photos (°C, 3 best views)",
                    "easyidp:photostatistics",
                    {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id",
                     "PROJECT": s["METASHAPE_PROJECT"], "HEIGHT_SOURCE": 1, "DSM": s["DSM"],
                     "PHOTOS": th["folder"], "VALUES": 1, "STATISTICS": "0,1",
                     "PERCENTILES": "", "OUTPUT_VIEWS": os.path.join(out, "plots_thermal_views.gpkg"),
                     "OUTPUT": os.path.join(out, "plots_thermal.gpkg")})
    got = {f["plot_id"]: f for f in features(res["OUTPUT"])}
    err = np.array([got[k]["temp_c_median"] - v for k, v in th["plots"].items()])
    views = features(res["OUTPUT_VIEWS"])
    sun = np.array([v["sun_zenith"] for v in views if v["sun_zenith"] is not None], float)
    phase = np.array([v["phase_angle"] for v in views if v["phase_angle"] is not None], float)
    lines = [f"  {IND} plot temperature (°C, median of the 3 best views) against the field's "
             f"truth: mean |error| {np.mean(np.abs(err)):.3f} °C, max {np.max(np.abs(err)):.3f} °C "
             f"over {len(err)} plots (photos: FLIR raw PNG, noise 0.05 °C, soil 38 °C around)"]
    if sun.size:
        lines.append(f"  {IND} per view: acquisition time from EXIF, sun zenith "
                     f"{sun.min():.1f}–{sun.max():.1f}°, phase angle {phase.min():.1f}–"
                     f"{phase.max():.1f}° over {len(views)} views ({res['OUTPUT_VIEWS']})")
    return lines
