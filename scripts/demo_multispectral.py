"""The multispectral part of ``make demo`` (issue 34): a MicaSense-style Red/NIR camera rides
with the demo flight (``core/demo/multispectral.py``: digital numbers under a passing cloud, with
per-band, per-capture exposure and gain, and DLS 2 tags); every band file is read as reflectance
(``core.radiometry``), and each plot's reflectance and NDVI are measured in the 3 best views,
through the same back-projected plot mask in every band of a capture, against the truth of the
spectral model under the same mask, and against NDVI from the stored digital numbers.

The per-plot values are computed here through the core's back-projection (``back_project``) and
the record masks Plot statistics uses (``window_mask``), not through the tool's reflectance
choice (``VALUES``): not a tool run."""
import os
import time

import numpy as np


def run_multispectral_demo(s, out, *, views: int = 3) -> list:
    """Write the band files into ``out``/multispectral, measure every plot; return the summary
    lines to print (after printing the per-plot table)."""
    import tifffile

    from ..core import open_reconstruction
    from ..core.projection.photo_stats import window_mask
    from ..core.demo.multispectral import BANDS, true_reflectance, write_multispectral_flight
    from ..core.projection import back_project
    from ..core.projection.photos import read_photo
    from ..core.radiometry import group_captures, reflectance_values
    from ..core.raster import DSM
    from ..core.roi import read_geojson

    t0 = time.time()
    photo_dir = os.path.join(s["OUTPUT_FOLDER"], "photos")
    photos = sorted(os.path.join(photo_dir, f) for f in os.listdir(photo_dir)
                    if f.lower().endswith(".jpg"))
    folder = os.path.join(out, "multispectral")
    flight = write_multispectral_flight(photos, folder)
    band_files = sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".tif"))
    captures = {c.key: c.bands for c in group_captures(band_files)}
    by_photo = {}
    for rec in flight:                    # the capture of each RGB photo, found by its tags
        key = next(k for k, b in captures.items() if b["Red"] == rec["files"]["Red"])
        by_photo[os.path.splitext(os.path.basename(rec["photo"]))[0]] = (captures[key], rec)
    print(f"  {time.time() - t0:6.1f} s  multispectral band files: {len(band_files)} files, "
          f"{len(captures)} captures (core generator, not a tool run)", flush=True)

    t0 = time.time()
    rois = read_geojson(os.path.join(s["OUTPUT_FOLDER"], "plots.geojson"), name_field="plot_id")
    recon = open_reconstruction(s["METASHAPE_PROJECT"])
    dsm = DSM(s["DSM"])
    bp = back_project(rois, recon, heights=dsm, occlusion_dsm=dsm, clip=False, max_views=views)
    sums = {}                              # plot -> {"refl"|"truth"|"dn": {band: [view means]}}
    cache = {}
    masked = [0]                           # saturated pixels left out inside the plot masks
    for i in np.argsort(bp.photo_index, kind="stable"):    # photo by photo: each read once
        label = os.path.splitext(os.path.basename(str(bp.photo[i])))[0]
        bands, rec = by_photo[label]
        if label not in cache:
            truth = true_reflectance(read_photo(rec["photo"]))
            cache.clear()
            cache[label] = {b: (reflectance_values(bands[b]), tifffile.imread(bands[b]), truth[b])
                            for b in BANDS}
        r0, c0, mask = window_mask(bp, i)
        rows, cols = slice(r0, r0 + mask.shape[0]), slice(c0, c0 + mask.shape[1])
        plot = bp.roi_names[int(bp.roi[i])]
        acc = sums.setdefault(plot, {"refl": {}, "truth": {}, "dn": {}})
        for band, (values, dn, truth) in cache[label].items():
            use = mask & values.valid[rows, cols]      # each band through its own file's mask
            acc["refl"].setdefault(band, []).append(float(values.values[rows, cols][use].mean()))
            acc["truth"].setdefault(band, []).append(float(truth[rows, cols][use].mean()))
            acc["dn"].setdefault(band, []).append(float(dn[rows, cols][use].mean()))
            masked[0] += int((mask & ~values.valid[rows, cols]).sum())

    def ndvi(d):
        nir, red = np.mean(d["NIR"]), np.mean(d["Red"])
        return (nir - red) / (nir + red)

    print("\nMultispectral reflectance per plot (Red, NIR; 3 best views; NDVI from reflectance "
          "and from the stored digital numbers) − truth")
    print(f"  {'plot':<5} {'NDVI':>6} {'truth':>6} {'error':>9}   {'DN NDVI':>7} {'error':>7}   "
          f"{'red err':>9} {'NIR err':>9}")
    e_ndvi, e_dn, e_refl = [], [], []
    for plot in sorted(sums):
        a = sums[plot]
        n_meas, n_true, n_dn = ndvi(a["refl"]), ndvi(a["truth"]), ndvi(a["dn"])
        er = [np.mean(a["refl"][b]) - np.mean(a["truth"][b]) for b in ("Red", "NIR")]
        e_ndvi.append(n_meas - n_true)
        e_dn.append(n_dn - n_true)
        e_refl += er
        print(f"  {plot:<5} {n_meas:6.3f} {n_true:6.3f} {n_meas - n_true:+9.6f}   {n_dn:7.3f} "
              f"{n_dn - n_true:+7.3f}   {er[0]:+9.6f} {er[1]:+9.6f}")
    e_ndvi, e_dn, e_refl = np.abs(e_ndvi), np.abs(e_dn), np.abs(e_refl)
    print(f"  {time.time() - t0:6.1f} s  reflectance of {len(sums)} plots in {len(bp)} views "
          f"(core back-projection and core.radiometry, not a tool run)", flush=True)
    return [f"  multispectral (MicaSense-style Red/NIR, DLS 2, a passing cloud, per-band auto-"
            f"exposure): reflectance within {e_refl.max():.6f} (mean {e_refl.mean():.6f}), NDVI "
            f"within {e_ndvi.max():.6f} (mean {e_ndvi.mean():.6f}) of the truth over {len(sums)} "
            f"plots; NDVI from the stored digital numbers off by up to {e_dn.max():.3f} (mean "
            f"{e_dn.mean():.3f}); {masked[0]} saturated pixels (glints) left out inside the plot masks"]
