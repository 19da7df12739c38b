"""The deep-learning round trip of ``make demo`` (issue 26), through qgis_process.

On the medium demo survey (1600 × 1200 photos; made by the core generator, not a tool run) with
its truth plants and weeds (:mod:`core.demo.plants`): export a training set from the map truth
(easyidp:exporttrainingset), simulate detections from its COCO labels (radial vertex noise
3 px, 10 % misses, 5 % false positives per photo, seed 0: :mod:`core.demo.round_trip`),
forward-project and fuse them (easyidp:forwardprojectpolygons, merge 'fuse'; and 'union' for
comparison), and score both against the truth. The truth and the photos come from the same
camera model: the figures show consistency and the fusion's robustness, not the model.
"""
import json
import os
import time

import numpy as np

CONFIDENCE = 0.3      # fused objects below this confidence are not counted as found


def _layer(path):
    from osgeo import ogr
    ds = ogr.Open(path)
    out = []
    for f in ds.GetLayer(0):
        g = f.GetGeometryRef()
        c = g.Centroid() if g is not None else None
        out.append({**f.items(), "x": c.GetX() if c else np.nan, "y": c.GetY() if c else np.nan})
    ds = None
    return out


def run_round_trip_demo(steps, out) -> list:
    """Run the round trip into ``out``; returns the lines to print."""
    from ..core.demo import make_demo_survey
    from ..core.demo.plants import demo_objects, disc_ring
    from ..core.demo.round_trip import score_objects, simulate_detections
    from ..core.files import write_json
    t0 = time.time()
    s = make_demo_survey(os.path.join(out, "survey_medium"), seed=0, size="medium")
    print(f"  {time.time() - t0:6.1f} s  medium demo survey for the round trip (core generator, "
          "not a tool run)", flush=True)
    objs = demo_objects(json.load(open(s.truth)))
    objects = os.path.join(out, "truth_objects.geojson")
    write_json(objects, {"type": "FeatureCollection",
                         "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::32654"}},
                         "features": [{"type": "Feature",
                                       "properties": {"class": o["class"], "id": o["id"]},
                                       "geometry": {"type": "Polygon", "coordinates": [
                                           np.vstack([disc_ring(o), disc_ring(o)[:1]]).tolist()]}}
                                      for o in objs]})
    ts = steps.run(f"training set from {len(objs)} truth plants and weeds (COCO, YOLO, LabelMe)",
                   "easyidp:exporttrainingset",
                   {"OBJECTS": objects, "CLASS_FIELD": "class", "INSTANCE_FIELD": "id",
                    "PROJECT": s.metashape_project, "DSM": s.dsm, "VAL_FRACTION": 0,
                    "OUTPUT_FOLDER": os.path.join(out, "training_set")})
    coco = os.path.join(ts["OUTPUT_FOLDER"], "coco", "instances_train.json")
    det = os.path.join(out, "simulated_detections.json")
    sim = simulate_detections(coco, det, seed=0)
    scores = {}
    for mode, merge in (("fuse", 3), ("union", 1)):
        res = steps.run(f"simulated detections to the map, merge {mode}",
                        "easyidp:forwardprojectpolygons",
                        {"INPUT": det, "COCO_IMAGES": coco, "PROJECT": s.metashape_project,
                         "DSM": s.dsm, "MERGE": merge,
                         "OUTPUT": os.path.join(out, f"detections_{mode}.gpkg")})
        feats = _layer(res["OUTPUT"])
        if mode == "fuse":
            feats = [f for f in feats if (f.get("confidence") or 0) >= CONFIDENCE]
        found = [{"class": f["label"], "x": f["x"], "y": f["y"], "views": f["views"]} for f in feats]
        sc = score_objects(objs, found)
        sc["views_equal"] = sum(found[j]["views"] == len(set(sim["detected"].get(t, [])))
                                for t, j in sc["matches"].items())
        scores[mode] = sc
    lines = [f"  round trip: {len(objs)} truth objects; {sim['results']} simulated detections "
             f"({sim['missed']} missed, {sim['false']} false)"]
    for mode, sc in scores.items():
        lines.append(f"    {mode:5s}: recall {sc['recall']:.3f}, precision {sc['precision']:.3f}, "
                     f"position error median {100 * sc['median_error_m']:.2f} cm, max "
                     f"{100 * sc['max_error_m']:.2f} cm; views = photos detecting it for "
                     f"{sc['views_equal']}/{sc['matched']}")
    return lines
