"""Fusion of detections across views (merge mode 'fuse', issue 26) on the medium demo survey.

The round trip: truth discs on the map → training set (COCO) → simulated detections (radial
vertex noise 3 px, 10 % misses, 5 % false positives per photo, seeded) → COCO results read with
their images file → forward projection → fuse (and union for comparison) → scored against the
truth discs (a truth by construction: the generator's positions; the photos come from the same
camera model, so the figures prove consistency and the fusion's robustness, not the model).
The medium survey (1600 × 1200 photos, 1.8 cm per pixel) is used: at the small survey's 3.7 cm
a 3 px vertex noise is a third of a weed's radius.
"""
import json

import numpy as np
import pytest

from easyidp_toolbox.core.annotations import read_annotations
from easyidp_toolbox.core.demo import make_demo_survey
from easyidp_toolbox.core.demo.plants import demo_objects, disc_ring
from easyidp_toolbox.core.demo.round_trip import position_of, score_objects, simulate_detections
from easyidp_toolbox.core.projection import (export_training_set, forward_project, fuse_views,
                                             merge_views)
from easyidp_toolbox.core.projection.forward import ForwardShape
from easyidp_toolbox.core.raster import DSM, HIT
from easyidp_toolbox.core.reconstruction import open_reconstruction
from easyidp_toolbox.core.roi import ROI, ROISet

CONFIDENCE = 0.3     # fused objects kept for scoring


@pytest.fixture(scope="module")
def round_trip(tmp_path_factory):
    s = make_demo_survey(str(tmp_path_factory.mktemp("medium")), seed=0, size="medium")
    truth = json.load(open(s.truth))
    objs = demo_objects(truth)
    rois = ROISet([ROI(o["id"], [[disc_ring(o)]]) for o in objs], s.crs)
    recon = open_reconstruction(s.metashape_project)
    out = tmp_path_factory.mktemp("rt")
    export_training_set(rois, [o["class"] for o in objs], recon, s.dsm, out / "set",
                        val_fraction=0.0)
    coco = out / "set" / "coco" / "instances_train.json"
    sim = simulate_detections(coco, out / "detections.json", seed=0)
    items = read_annotations(out / "detections.json", recon, dataset=coco)
    dsm = DSM(s.dsm)
    shapes = [f for ann, cam in items for f in forward_project(ann.shapes, cam, recon, dsm)]
    photos = [cam.label for _, cam in items]
    fused = merge_views(shapes, "fuse", recon=recon, dsm=s.dsm, photos=photos)
    union = merge_views(shapes, "union")
    return dict(survey=s, objs=objs, sim=sim, fused=fused, union=union, shapes=shapes,
                photos=photos)


def _found(objects, keep=lambda o: True):
    out = []
    for o in objects:
        p = position_of(o)
        if p is not None and keep(o):
            out.append({"class": o.label, "x": p[0], "y": p[1], "obj": o})
    return out


def test_fused_detections_match_the_truth(round_trip):
    """Synthetic truth (the demo discs): recall and precision ≥ 0.98, position error median
    ≤ 1 cm and max ≤ 3 cm (the issue's figures, seed 0: 0.64 and 1.98 cm; seeds 0–7 measured: max 1.98–3.10 cm, and
    3.89 cm for seed 7, a weed whose 4 views are all shifted the same way).
    Union on the same input is measurably less precise."""
    r = round_trip
    fused = _found(r["fused"], lambda o: o.confidence >= CONFIDENCE)
    sf = score_objects(r["objs"], fused)
    su = score_objects(r["objs"], _found(r["union"]))
    print(f"\nfuse : recall {sf['recall']:.3f} precision {sf['precision']:.3f} median "
          f"{sf['median_error_m'] * 100:.2f} cm max {sf['max_error_m'] * 100:.2f} cm")
    print(f"union: recall {su['recall']:.3f} precision {su['precision']:.3f} median "
          f"{su['median_error_m'] * 100:.2f} cm max {su['max_error_m'] * 100:.2f} cm")
    assert sf["recall"] >= 0.98 and sf["precision"] >= 0.98
    assert sf["median_error_m"] <= 0.01
    assert sf["max_error_m"] <= 0.03
    assert su["precision"] < sf["precision"] - 0.1


def truth_shares(survey, objs, grid=0.02):
    """Per object id, ((photos,) share of it that each photo sees, photo labels), from the
    generator's truth (true poses and its own projection, the scene's surface, its
    segment-under-surface test; not the core's back-projection, occlusion or ray casting): the
    share of the disc's outline (pixel area) inside the frame, times the share of its surface
    samples (a ``grid`` m grid) in the frame that no surface hides: the exporter's rule."""
    import shapely
    from easyidp_toolbox.core.demo.flight import make_camera, plan_flight
    from easyidp_toolbox.core.demo.scene import make_scene
    from easyidp_toolbox.core.demo.truth import hidden, project
    from easyidp_toolbox.core.reconstruction import INSIDE
    scene = make_scene(survey.seed)
    shots = plan_flight(scene, np.random.default_rng([survey.seed, 1]))
    camera = make_camera(survey.size)
    frame = shapely.box(0, 0, camera.width, camera.height)
    off = scene.offset
    C = np.array([sh.C for sh in shots])
    out = {}
    for o in objs:
        ring = disc_ring(o) - off[:2]
        rz = np.column_stack([ring, scene.surface_local(ring[:, 0], ring[:, 1])])
        g = np.arange(-o["radius"], o["radius"] + 1e-9, grid)
        gx, gy = [a.ravel() for a in np.meshgrid(g, g)]
        keep = gx ** 2 + gy ** 2 <= o["radius"] ** 2
        x, y = o["centre"][0] - off[0] + gx[keep], o["centre"][1] - off[1] + gy[keep]
        pts = np.column_stack([x, y, scene.surface_local(x, y)])
        ring_px, _ = project(camera, shots, rz)
        _, st = project(camera, shots, pts)
        share = np.zeros(len(shots))
        for k in range(len(shots)):
            inf = st[k] == INSIDE
            if not inf.any():
                continue
            poly = shapely.Polygon(ring_px[k]).buffer(0)
            inside = poly.intersection(frame).area / poly.area if poly.area > 0 else 0.0
            hid = hidden(scene, np.repeat(C[k][None], int(inf.sum()), axis=0), pts[inf])
            share[k] = inside * (1.0 - hid.mean())
        out[o["id"]] = (share, [sh.label for sh in shots])
    return out


def test_view_counts_equal_the_photos_that_see_the_object(round_trip):
    """Two counts per fused object matched to a truth disc:

    * ``expected_views`` (the photos searched that could see it) equals the number of searched
      photos whose truth share (:func:`truth_shares`) is at least 0.5 (min_visible), for at
      least 98 % of the objects none of whose photos is within ±0.05 of that threshold (near
      it the fused outline and the truth sampling may decide either way; those are counted).
      Seed 0: 197 of 198; the other was not examined;
    * ``views`` equals the number of simulated detections of it that survived the misses, in
      the same photos, for at least 97 % of the objects (the others: a view moved more than
      15 cm by occlusion or the frame that overlaps none of the others, left as its own group).
    """
    r = round_trip
    fused = _found(r["fused"], lambda o: o.confidence >= CONFIDENCE)
    sf = score_objects(r["objs"], fused)
    shares = truth_shares(r["survey"], [o for o in r["objs"] if o["id"] in sf["matches"]])
    clear = equal_exp = border = 0
    views_equal = 0
    for t, j in sf["matches"].items():
        o = fused[j]["obj"]
        share, labels = shares[t]
        share = share * np.isin(labels, r["photos"])      # the photos searched (aligned)
        if np.abs(share - 0.5).min() > 0.05:
            clear += 1
            equal_exp += o.expected_views == int((share >= 0.5).sum())
        else:
            border += 1
        det = set(r["sim"]["detected"].get(t, []))
        views_equal += o.views == len(det) and set(o.photos) == det
    n = sf["matched"]
    print(f"\nexpected views = truth photos for {equal_exp}/{clear} objects clear of the "
          f"threshold ({border} near it); views = surviving detections for {views_equal}/{n}")
    assert clear >= 0.5 * n
    assert equal_exp >= 0.98 * clear
    assert views_equal >= 0.97 * n


def test_fused_objects_carry_scores_heights_and_confidence(round_trip):
    r = round_trip
    for o in r["fused"]:
        assert o.views == len(o.photos) >= 1
        assert o.max_score >= o.mean_score > 0
        assert 0 < o.confidence <= 1
        assert np.isfinite(o.position[2])
        assert o.parts[0][0].shape[1] == 3
    # false positives are seen once where several photos could have seen them
    single = [o for o in r["fused"] if o.views == 1]
    assert single and np.median([o.expected_views for o in single]) >= 3


def _shape(photo, ring, score, label="plant"):
    ring = np.column_stack([ring, np.zeros(len(ring))])
    return ForwardShape(photo, label, "polygon", [ring], [np.full(len(ring), HIT, np.uint8)],
                        [np.ones(len(ring), bool)], score=score, area_m2=1.0, perimeter_m=4.0)


def test_nms_within_a_photo_and_groups_across_photos(round_trip):
    """By construction: two near-copies in one photo are one detection (the higher score);
    the same square in three photos is one object of 3 views; a square 10 m away is another;
    the consensus of three shifted squares is their majority region, not their union."""
    s = round_trip["survey"]
    recon = open_reconstruction(s.metashape_project)
    x0, y0 = 319830.0, 3956030.0
    sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    shapes = [_shape("DJI_0001", sq + [x0, y0], 0.9), _shape("DJI_0001", sq + [x0 + 0.02, y0], 0.5),
              _shape("DJI_0002", sq + [x0 + 0.1, y0], 0.8), _shape("DJI_0003", sq + [x0 - 0.1, y0], 0.7),
              _shape("DJI_0002", sq + [x0 + 10, y0], 0.6)]
    out = fuse_views(shapes, recon, s.dsm, photos=["DJI_0001", "DJI_0002", "DJI_0003"])
    assert sorted(o.views for o in out) == [1, 3]
    big = [o for o in out if o.views == 3][0]
    assert big.max_score == 0.9 and abs(big.mean_score - 0.8) < 1e-9
    xy = big.parts[0][0][:, :2]
    # majority (2 of 3) of squares at -0.1, 0, +0.1: x from x0 to x0 + 1, area 1 m² (union 1.2)
    assert abs(xy[:, 0].min() - x0) < 0.03 and abs(xy[:, 0].max() - (x0 + 1)) < 0.03
    assert abs(big.position[0] - (x0 + 0.5)) < 0.01


def test_an_object_over_the_dsm_edge_is_fused(round_trip):
    """By construction: a square in three photos that reaches past the DSM's east edge is one
    object; its vertices off the DSM take the height of the others (no error), and its expected
    views are counted."""
    s = round_trip["survey"]
    recon = open_reconstruction(s.metashape_project)
    dsm = DSM(s.dsm)
    xe, yn = dsm.tif.pixel_to_map(np.array([float(dsm.tif.width)]), np.array([dsm.tif.height / 2.0]))
    sq = np.array([[-0.5, 0], [0.5, 0], [0.5, 1], [-0.5, 1]], float) + [float(xe[0]), float(yn[0])]
    out = fuse_views([_shape(p, sq, 0.8) for p in ("DJI_0001", "DJI_0002", "DJI_0003")],
                     recon, dsm, photos=["DJI_0001", "DJI_0002", "DJI_0003"])
    assert len(out) == 1 and out[0].views == 3
    assert np.isfinite(out[0].parts[0][0][:, 2]).all() and np.isfinite(out[0].position[2])
