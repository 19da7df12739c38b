"""The multispectral part of ``make demo`` (issue 34): a MicaSense-style Red/NIR camera rides
with the demo flight (``core/demo/multispectral.py``: digital numbers under a passing cloud, with
per-band, per-capture exposure and gain, and DLS 2 tags), with a Pix4D project in which every
band file is its own camera. easyidp:photostatistics measures the plots through qgis_process,
one view per plot × capture (each band through its own camera), twice: with VALUES = reflectance
and as stored (the digital numbers). Each plot's NDVI (median of its 3 best views) is printed
against the truth: the demo's reflectance field under the plot outline, projected by OpenCV from
the camera and poses truth.json states (``tests/support/independent_camera.py``), in the same
views."""
import os
import time

import numpy as np

IND = "[independent]"
HEIGHT = 95.5            # m, the vertex height of every plot outline (the truth's too)


def run_multispectral_demo(steps, s, out, features, *, views: int = 3) -> list:
    """Write the band files and their project into ``out``/multispectral, run the tool twice;
    print the per-plot table and return the summary lines to print."""
    import json

    from ..core.demo.multispectral import (ndvi, plot_reflectance_truth,
                                           write_multispectral_flight, write_multispectral_project)
    from ..tests.support.independent_camera import photo_pixels

    t0 = time.time()
    photo_dir = os.path.join(s["OUTPUT_FOLDER"], "photos")
    photos = sorted(os.path.join(photo_dir, f) for f in os.listdir(photo_dir)
                    if f.lower().endswith(".jpg"))
    folder = os.path.join(out, "multispectral")
    flight = write_multispectral_flight(photos, folder)
    p4d = write_multispectral_project(os.path.join(out, "multispectral_project"), flight)
    print(f"  {time.time() - t0:6.1f} s  multispectral band files: {2 * len(flight)} files of "
          f"{len(flight)} captures and their Pix4D project (core generator, not a tool run)",
          flush=True)
    runs = {}
    for values, name, label in ((2, "reflectance", "reflectance"), (0, "stored", "digital numbers")):
        runs[name] = steps.run(
            f"plot NDVI from the multispectral band files ({label}, {views} best views)",
            "easyidp:photostatistics",
            {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": p4d, "HEIGHT_SOURCE": 3,
             "GROUND_HEIGHT": HEIGHT, "VALUES": values, "STATISTICS": "0", "PERCENTILES": "",
             "MAX_IMAGES": views,
             "OUTPUT_VIEWS": os.path.join(out, f"plots_multispectral_{name}_views.gpkg"),
             "OUTPUT": os.path.join(out, f"plots_multispectral_{name}.gpkg")})

    t0 = time.time()
    with open(s["TRUTH"]) as fh:
        doc = json.load(fh)
    used_views = [(v["roi"], v["photo"]) for v in features(runs["reflectance"]["OUTPUT_VIEWS"])
                  if v["used"]]
    truth = plot_reflectance_truth(flight, HEIGHT, keys=set(used_views),
                                   project=lambda label, xyz: photo_pixels(doc, label, xyz)[0])
    used = {}                              # plot -> truth of its used views
    for key in used_views:
        used.setdefault(key[0], []).append(truth.get(key))
    got = {f["plot_id"]: f["ndvi_mean"] for f in features(runs["reflectance"]["OUTPUT"])}
    dn = {f["plot_id"]: f["ndvi_mean"] for f in features(runs["stored"]["OUTPUT"])}
    refl = {f["plot_id"]: (f["red_refl_mean"], f["nir_refl_mean"])
            for f in features(runs["reflectance"]["OUTPUT"])}

    print("\nMultispectral NDVI per plot (Red, NIR; median of the 3 best captures; from "
          "reflectance and from the stored digital numbers) − truth")
    print(f"  {'plot':<5} {'NDVI':>6} {'truth':>6} {'error':>9}   {'DN NDVI':>7} {'error':>7}   "
          f"{'red':>6} {'NIR':>6}")
    e_ndvi, e_dn, skipped = [], [], []
    for plot in sorted(used):
        wants = used[plot]
        if any(w is None for w in wants) or got.get(plot) is None:
            skipped.append(plot)           # a used view sees the plot's outline cut by the frame
            continue
        want = float(np.median([ndvi(w) for w in wants]))
        e_ndvi.append(got[plot] - want)
        e_dn.append(dn[plot] - want)
        print(f"  {plot:<5} {got[plot]:6.3f} {want:6.3f} {got[plot] - want:+9.6f}   "
              f"{dn[plot]:7.3f} {dn[plot] - want:+7.3f}   {refl[plot][0]:6.3f} {refl[plot][1]:6.3f}")
    e_ndvi, e_dn = np.abs(e_ndvi), np.abs(e_dn)
    print(f"  {time.time() - t0:6.1f} s  truth of {len(e_ndvi)} plots (the demo's reflectance "
          "field under the OpenCV-projected plot outlines; not a tool run)", flush=True)
    note = f"; {len(skipped)} plot(s) without a whole-outline truth view left out" if skipped else ""
    return [f"  {IND} multispectral (MicaSense-style Red/NIR band files as a rig in a Pix4D "
            f"project, DLS 2, a passing cloud, per-band auto-exposure), through the tool: NDVI from "
            f"reflectance within {e_ndvi.max():.4f} (mean {e_ndvi.mean():.4f}) of the truth over "
            f"{len(e_ndvi)} plots; NDVI from the stored digital numbers off by up to "
            f"{e_dn.max():.3f} (mean {e_dn.mean():.3f}){note}; truth: the demo's reflectance field "
            f"under the plot outlines projected by OpenCV (digital numbers written by the "
            f"generator's own inverse of MicaSense's model)"]
