"""The deep-learning round trip of ``make demo`` (issue 26), through qgis_process.

On the medium demo survey (1600 × 1200 photos; made by the core generator, not a tool run) with
its truth plants and weeds (:mod:`core.demo.plants`): export a training set from the map truth
(easyidp:exporttrainingset), simulate detections from its COCO labels (radial vertex noise
3 px, 10 % misses, 5 % false positives per photo, seed 0: :mod:`core.demo.round_trip`),
forward-project and fuse them (easyidp:forwardprojectpolygons, merge 'fuse'; and 'union' for
comparison), and score both against the truth. The truth and the photos come from the same
camera model: the figures show consistency and the fusion's robustness, not the model.

Before it, the read-back (issue 32, :func:`_read_back`): the 40 plots of the small survey
exported as a training set and brought back through Forward-project (merge 'fuse') with each of
its Metashape, Pix4D, ODM and OPF projects, scored against the plots the generator placed
(recall, precision, IoU, corners). A consistency check too: export and read-back share the
camera model; the plots themselves are placed independently of it.
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
    lines = _read_back(steps, out)
    lines += [f"  round trip: {len(objs)} truth objects; {sim['results']} simulated detections "
             f"({sim['missed']} missed, {sim['false']} false)"]
    for mode, sc in scores.items():
        lines.append(f"    {mode:5s}: recall {sc['recall']:.3f}, precision {sc['precision']:.3f}, "
                     f"position error median {100 * sc['median_error_m']:.2f} cm, max "
                     f"{100 * sc['max_error_m']:.2f} cm; views = photos detecting it for "
                     f"{sc['views_equal']}/{sc['matched']}")
    return lines


READ_BACK_KINDS = (("Metashape", "metashape/demo_survey.psx"), ("Pix4D", "pix4d/demo_survey.p4d"),
                   ("ODM", "odm/opensfm/reconstruction.json"), ("OPF", "opf/project.opf"))


def _read_back(steps, out) -> list:
    """Issue 32's read-back, on the small survey of ``out/survey``: a training set exported
    from the generator's 40 plots (exact labels, through the Metashape project) comes back
    through Forward-project with merge 'fuse' for each project kind (the same flight and photos
    in four formats); scored against the plots (:func:`score_outlines`)."""
    from ..core.demo.round_trip import score_outlines
    from ..core.files import write_json
    survey = os.path.join(out, "survey")
    doc = json.load(open(os.path.join(survey, "plots.geojson"), encoding="utf-8"))
    truth = {f["properties"]["plot_id"]: np.array(f["geometry"]["coordinates"][0][:-1])
             for f in doc["features"]}
    for f in doc["features"]:
        f["properties"]["class"] = "plot"
    objects = str(write_json(os.path.join(out, "plots_with_class.geojson"), doc))
    ts = steps.run("training set of the 40 plots (exact labels), for the read-back",
                   "easyidp:exporttrainingset",
                   {"OBJECTS": objects, "CLASS_FIELD": "class", "INSTANCE_FIELD": "plot_id",
                    "PROJECT": os.path.join(survey, READ_BACK_KINDS[0][1]),
                    "DSM": os.path.join(survey, "dsm.tif"), "VAL_FRACTION": 0,
                    "OUTPUT_FOLDER": os.path.join(out, "training_set_plots")})
    labels = os.path.join(ts["OUTPUT_FOLDER"], "labelme", "train")
    lines = ["  read-back of a training set (40 plots, exact LabelMe labels → Forward-project, "
             "merge fuse), against the plots the generator placed (consistency: labels and "
             "read-back share the camera model):"]
    for kind, project in READ_BACK_KINDS:
        res = steps.run(f"plot labels back to the map, {kind} project, merge fuse",
                        "easyidp:forwardprojectpolygons",
                        {"INPUT_FOLDER": labels, "PROJECT": os.path.join(survey, project),
                         "DSM": os.path.join(survey, "dsm.tif"), "MERGE": 3,
                         "OUTPUT": os.path.join(out, f"plots_read_back_{kind.lower()}.gpkg")})
        sc = score_outlines(truth, _rings(res["OUTPUT"]))
        ok = (sc["recall"] >= 0.99 and sc["precision"] >= 0.99 and sc["iou_min"] >= 0.99
              and sc["corner_max_m"] <= 0.01)
        lines.append(f"    {kind:9s}: recall {sc['recall']:.3f}, precision {sc['precision']:.3f}, "
                     f"IoU min {sc['iou_min']:.4f}, corners median "
                     f"{100 * sc['corner_median_m']:.2f} cm, max {100 * sc['corner_max_m']:.2f} cm "
                     f"({'meets' if ok else 'MISSES'} ≥ 0.99, ≥ 0.99, ≤ 1 cm)")
    return lines


def _rings(path):
    """The exterior rings (k, 2) of a polygon layer's features."""
    from osgeo import ogr
    ds = ogr.Open(path)
    out = []
    for f in ds.GetLayer(0):
        g = f.GetGeometryRef()
        if g is None:
            continue
        g = g.GetGeometryRef(0) if g.GetGeometryType() in (ogr.wkbMultiPolygon, ogr.wkbMultiPolygon25D) else g
        out.append(np.array(g.GetGeometryRef(0).GetPoints())[:-1, :2])
    ds = None
    return out
