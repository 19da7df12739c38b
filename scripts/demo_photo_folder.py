"""``make demo``, photo folder: footprints and back-projection from the demo photos alone (their
DJI-style EXIF and XMP, written from the truth with the noise ``core/demo/photo_tags_writer.py``
states), with the errors against the survey's truth."""
import os

import numpy as np

from ..tests.support.independent_camera import observation_lookup

IND = "[independent]"


def run_photo_folder_demo(steps, s, truth, out, features) -> list:
    """Runs the two tools on the photos folder; returns the lines to print."""
    photos = os.path.join(s["OUTPUT_FOLDER"], "photos")
    fp = steps.run("camera footprints on the DSM, from the photos' tags alone (no project)",
                   "easyidp:camerafootprints",
                   {"PROJECT": photos, "DSM": s["DSM"],
                    "OUTPUT_CAMERAS": os.path.join(out, "photo_tags_cameras.gpkg"),
                    "OUTPUT_FOOTPRINTS": os.path.join(out, "photo_tags_footprints.gpkg")})
    bp = steps.run("back-project plots, from the photos' tags alone (whole plots)",
                   "easyidp:backprojectrois",
                   {"ROIS": s["PLOTS"], "NAME_FIELD": "plot_id", "PROJECT": photos,
                    "HEIGHT_SOURCE": 1, "DSM": s["DSM"], "CLIP": 1, "MIN_VISIBLE": 0,
                    "OCCLUSION": False, "OUTPUT": os.path.join(out, "plots_in_photos_tags.gpkg"),
                    "OUTPUT_SUMMARY": "TEMPORARY_OUTPUT"})
    centre = []
    for f in features(fp["OUTPUT_CAMERAS"]):
        g = f["_geom"]
        label = os.path.splitext(f["label"])[0]
        centre.append(np.linalg.norm(np.array([g.GetX(), g.GetY(), g.GetZ()])
                                     - truth["photos"][label]["centre"]))
    pix = observation_lookup(truth)            # the independent truth pixels
    err, within = [], []
    for f in features(bp["OUTPUT"]):
        ring = np.array(f["_geom"].GetGeometryRef(0).GetGeometryRef(0).GetPoints())[:, :2] * [1, -1]
        photo = os.path.splitext(f["photo"])[0]
        for k in range(4):
            uv = pix.get((f"{f['roi']}_c{k + 1}", photo))
            if uv is not None:
                err.append(float(np.min(np.linalg.norm(ring - np.asarray(uv), axis=1))))
                within.append(err[-1] <= 2 * f["uncertainty_px"])
    centre, err = np.array(centre), np.array(err)
    return [
        f"  {IND} photo folder (cameras from the photos' EXIF/XMP, no project; "
        f"{truth.get('photo_tags', '')}):",
        f"    camera centres vs the truth: median {np.median(centre):.2f} m, max {centre.max():.2f} m "
        f"({len(centre)} photos)",
        f"    plot corners back-projected vs the truth pixels: median {np.median(err):.1f} px, "
        f"max {err.max():.1f} px over {len(err)} corners; {100 * np.mean(within):.0f} % within "
        f"2 × uncertainty_px",
    ]
