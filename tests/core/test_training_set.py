"""Training sets on the raw photos (issue 26): export_training_set on the small demo survey.

Checks and their kind:
* exported COCO/YOLO polygons vs the truth discs projected by a brute force written here (the
  demo generator's true poses and the Metashape frame formula of DESIGN.md, vertex by vertex):
  an independent projection, but the demo truth is made with the same camera model, so this
  proves the reader, heights, clipping and writers consistent with the generator;
* objects hidden by the surface (the generator's own segment test, not the core's ray caster)
  are absent; the train/val split loses no image (by construction of the files);
* formats: pycocotools loads the COCO files; YOLO files parse with the reader of the documented
  format written here; LabelMe files open with the project's reader.
"""
import json
import os

import numpy as np
import pytest

from easyidp_toolbox.core.annotations import read_labelme
from easyidp_toolbox.core.demo.flight import make_camera, plan_flight
from easyidp_toolbox.core.demo.plants import demo_objects, disc_ring, object_visibility
from easyidp_toolbox.core.demo.scene import make_scene
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.projection import export_training_set
from easyidp_toolbox.core.projection.training_set import tile_origins
from easyidp_toolbox.core.reconstruction import open_reconstruction
from easyidp_toolbox.core.roi import ROI, ROISet

MIN_VISIBLE = 0.5


@pytest.fixture(scope="module")
def setup(demo, tmp_path_factory):
    objs = demo_objects(demo.truth_doc)
    rois = ROISet([ROI(o["id"], [[disc_ring(o)]]) for o in objs], demo.crs)
    recon = open_reconstruction(demo.metashape_project)
    whole = tmp_path_factory.mktemp("ts_whole")
    res_whole = export_training_set(rois, [o["class"] for o in objs], recon, demo.dsm, whole,
                                    val_fraction=0.0, min_visible=MIN_VISIBLE)
    tiles = tmp_path_factory.mktemp("ts_tiles")
    res_tiles = export_training_set(rois, [o["class"] for o in objs], recon, demo.dsm, tiles,
                                    tile_size=320, tile_overlap=64, split="region",
                                    val_fraction=0.3, region_size=10.0, seed=1)
    scene = make_scene(demo.seed)
    shots = plan_flight(scene, np.random.default_rng([demo.seed, 1]))
    camera = make_camera(demo.size)
    return dict(objs=objs, rois=rois, recon=recon, whole=whole, res_whole=res_whole,
                tiles=tiles, res_tiles=res_tiles, dsm=demo.dsm, scene=scene, shots=shots, camera=camera)


def brute_force_pixels(scene, camera, shot, ring_xy):
    """Truth disc vertices (map x, y) → pixels: height = the surface (DSM bilinear), local
    frame = map − offset, Xc = R (X − C), then DESIGN.md's frame formula written out."""
    off = scene.offset
    x, y = ring_xy[:, 0] - off[0], ring_xy[:, 1] - off[1]
    X = np.column_stack([x, y, scene.surface_local(x, y)])
    Xc = (X - shot.C) @ shot.R.T
    xn, yn = Xc[:, 0] / Xc[:, 2], Xc[:, 1] / Xc[:, 2]
    c = camera.calibration
    r2 = xn * xn + yn * yn
    radial = 1 + c.k1 * r2 + c.k2 * r2 ** 2 + c.k3 * r2 ** 3
    xd = xn * radial + c.p1 * (r2 + 2 * xn * xn) + 2 * c.p2 * xn * yn
    yd = yn * radial + c.p2 * (r2 + 2 * yn * yn) + 2 * c.p1 * xn * yn
    return np.column_stack([c.cx + xd * (c.f + c.b1) + yd * c.b2, c.cy + yd * c.f])


def coco(folder, split):
    return json.load(open(os.path.join(folder, "coco", f"instances_{split}.json")))


def test_exported_polygons_equal_a_brute_force_projection_of_the_truth(setup):
    """Brute force (independent projection of the truth discs): every unclipped COCO polygon
    and YOLO segment equals the projected disc, vertex for vertex, to 0.01 px."""
    s = setup
    by_id = {o["id"]: o for o in s["objs"]}
    shots = {sh.label: sh for sh in s["shots"]}
    doc = coco(s["whole"], "train")
    images = {im["id"]: im for im in doc["images"]}
    w, h = s["camera"].width, s["camera"].height
    worst, compared = 0.0, 0
    for a in doc["annotations"]:
        im = images[a["image_id"]]
        truth = brute_force_pixels(s["scene"], s["camera"], shots[im["photo"]],
                                   disc_ring(by_id[a["attributes"]["instance"]]))
        if truth.min() <= 0 or (truth[:, 0] >= w).any() or (truth[:, 1] >= h).any():
            continue                      # clipped by the frame: checked by the clip tests
        got = np.asarray(a["segmentation"][0]).reshape(-1, 2)
        assert len(got) == len(truth)
        d = np.hypot(*(got[:, None, :] - truth[None, :, :]).transpose(2, 0, 1)).min(axis=1)
        worst = max(worst, float(d.max()))
        compared += 1
        # the YOLO segment line of this object says the same, normalised
        stem = os.path.splitext(im["file_name"])[0]
        lines = read_yolo_file(os.path.join(s["whole"], "labels", "train", stem + ".txt"))
        best = min(np.abs(np.asarray(v).reshape(-1, 2) * [w, h] - got).max()
                   if len(v) == got.size else np.inf for _, v in lines)
        assert best < 1e-3
    assert compared > 1000
    assert worst < 0.01, worst
    print(f"{compared} labels equal the brute-force projection; worst vertex {worst:.2e} px")


def test_hidden_objects_are_absent(setup):
    """Truth by construction (the generator's segment-under-surface test on samples of the disc
    on the surface): where the disc's outline is wholly inside the frame (brute-force
    projection), an object whose visible share is clearly below MIN_VISIBLE is not labelled
    in that photo, and one clearly above is. Near the threshold the two samplings may differ.
    At the frame's edge the rule is the outline's share inside the frame, and relief can push a
    plant's canopy out of the frame while its outline is in: those pairs are counted, not
    asserted."""
    s = setup
    vis = object_visibility(s["scene"], s["camera"], s["shots"], s["objs"], MIN_VISIBLE)
    by_id = {o["id"]: o for o in s["objs"]}
    w, h = s["camera"].width, s["camera"].height
    doc = coco(s["whole"], "train")
    images = {im["id"]: im["photo"] for im in doc["images"]}
    labelled = {(a["attributes"]["instance"], images[a["image_id"]]) for a in doc["annotations"]}
    hidden_absent = hidden_total = seen_ok = seen_total = edge = 0
    for oid, v in vis.items():
        for k, share in enumerate(v["share"]):
            shot = s["shots"][k]
            pair = (oid, shot.label)
            px = brute_force_pixels(s["scene"], s["camera"], shot, disc_ring(by_id[oid]))
            inside = px.min() > 0 and (px[:, 0] < w).all() and (px[:, 1] < h).all()
            if not inside:
                edge += (share < MIN_VISIBLE - 0.1 and pair in labelled)
                continue
            if share < MIN_VISIBLE - 0.1:
                hidden_total += 1
                hidden_absent += pair not in labelled
            elif share > MIN_VISIBLE + 0.1:
                seen_total += 1
                seen_ok += pair in labelled
    print(f"outline in the frame: {hidden_absent}/{hidden_total} hidden pairs absent, "
          f"{seen_ok}/{seen_total} seen pairs labelled; at the frame edge {edge} pairs labelled "
          "whose surface samples are mostly outside")
    assert hidden_total > 0
    assert hidden_absent == hidden_total
    assert seen_ok == seen_total


def test_split_loses_no_image_and_tiles_cover_the_photo(setup):
    """By construction of the files: every tile that holds a label is in one split and none is
    left out (the same set cut without a split has the same tiles); objects in images of both
    splits are counted; tiles are of the stated size and overlap; every label lies inside its
    tile."""
    s = setup
    inst = {sp: {a["attributes"]["instance"] for a in coco(s["tiles"], sp)["annotations"]}
            for sp in ("train", "val")}
    assert inst["train"] and inst["val"]
    res = s["res_tiles"]
    assert res.shared_objects == len(inst["train"] & inst["val"])
    assert res.shared_objects == sum(1 for v in res.object_split.values() if v == "both")
    files = {sp: {im["file_name"] for im in coco(s["tiles"], sp)["images"]} for sp in ("train", "val")}
    assert not files["train"] & files["val"]
    n = res.images["train"] + res.images["val"]
    assert len(files["train"] | files["val"]) == n and res.images["val"] >= 0.5 * 0.3 * n
    assert tile_origins(800, 320, 64) == [0, 256, 480]
    for sp in ("train", "val"):
        doc = coco(s["tiles"], sp)
        for im in doc["images"]:
            assert (im["width"], im["height"]) == (320, 320)
        size = {im["id"]: (im["width"], im["height"]) for im in doc["images"]}
        for a in doc["annotations"]:
            xy = np.asarray(a["segmentation"][0]).reshape(-1, 2)
            assert xy.min() >= -1e-6 and (xy <= np.array(size[a["image_id"]]) + 1e-6).all()


def read_yolo_file(path):
    """The YOLO label format as Ultralytics documents it: one object per line, the class index
    then normalised numbers (4 for a box cx cy w h, an even number ≥ 6 for a polygon)."""
    out = []
    with open(path, encoding="utf-8") as fh:
        text = fh.read()
    for line in text.splitlines():
        parts = line.split()
        cls, vals = int(parts[0]), [float(v) for v in parts[1:]]
        assert len(vals) == 4 or (len(vals) >= 6 and len(vals) % 2 == 0), line
        assert all(0.0 <= v <= 1.0 for v in vals), line
        out.append((cls, vals))
    return out


def test_formats_load(setup):
    """pycocotools loads COCO; YOLO parses with the documented format and agrees with COCO
    (class index = category order; boxes = the polygons' extents); LabelMe opens with the
    project's reader."""
    from pycocotools.coco import COCO
    s = setup
    folder = s["tiles"]
    yaml = open(os.path.join(folder, "data.yaml"), encoding="utf-8").read()
    assert "train: images/train" in yaml and "val: images/val" in yaml
    assert '0: "plant"' in yaml and '1: "weed"' in yaml
    for sp in ("train", "val"):
        api = COCO(os.path.join(folder, "coco", f"instances_{sp}.json"))
        assert len(api.getImgIds()) == s["res_tiles"].images[sp]
        assert len(api.getAnnIds()) == s["res_tiles"].annotations[sp]
        names = {c["id"]: c["name"] for c in api.loadCats(api.getCatIds())}
        for img_id in api.getImgIds()[:20]:
            im = api.loadImgs(img_id)[0]
            assert os.path.isfile(os.path.join(folder, "images", sp, im["file_name"]))
            assert os.path.isfile(os.path.join(folder, "yolo_detect", "images", sp, im["file_name"]))
            anns = api.loadAnns(api.getAnnIds(imgIds=img_id))
            mask = api.annToMask(anns[0])
            assert mask.shape == (im["height"], im["width"]) and mask.any()
            stem = os.path.splitext(im["file_name"])[0]
            seg = read_yolo_file(os.path.join(folder, "labels", sp, stem + ".txt"))
            det = read_yolo_file(os.path.join(folder, "yolo_detect", "labels", sp, stem + ".txt"))
            assert len(seg) == len(det) == len(anns)     # one part per object in these tiles
            for a, (c, v), (c2, box) in zip(anns, seg, det):
                assert names[a["category_id"]] == ["plant", "weed"][c] and c == c2
                x, y, bw, bh = a["bbox"]
                W, H = im["width"], im["height"]
                np.testing.assert_allclose(box, [(x + bw / 2) / W, (y + bh / 2) / H, bw / W, bh / H],
                                           atol=1e-6)
            lm = read_labelme(os.path.join(folder, "labelme", sp, stem + ".json"))
            assert len(lm.shapes) == len(anns) and (lm.width, lm.height) == (im["width"], im["height"])
            np.testing.assert_allclose(lm.shapes[0].rings[0],
                                       np.asarray(anns[0]["segmentation"][0]).reshape(-1, 2), atol=1e-3)


def test_nothing_is_overwritten_and_bad_input_is_named(setup, tmp_path):
    s = setup
    objs = s["objs"][:6]
    rois = ROISet([ROI(o["id"], [[disc_ring(o)]]) for o in objs], s["rois"].crs)
    cls = [o["class"] for o in objs]
    export_training_set(rois, cls, s["recon"], s["dsm"], tmp_path, val_fraction=0)
    before = {p: os.path.getmtime(p) for p in tmp_path.rglob("*") if p.is_file()}
    with pytest.raises(InputError, match="already holds a training set"):
        export_training_set(rois, cls, s["recon"], s["dsm"], tmp_path, val_fraction=0)
    assert before == {p: os.path.getmtime(p) for p in tmp_path.rglob("*") if p.is_file()}
    export_training_set(rois, cls, s["recon"], s["dsm"], tmp_path, val_fraction=0,
                        overwrite=True)
    with pytest.raises(InputError, match="one class per object"):
        export_training_set(rois, cls[:-1], s["recon"], s["dsm"], tmp_path / "x")
    with pytest.raises(InputError, match="overlap"):
        export_training_set(rois, cls, s["recon"], s["dsm"], tmp_path / "y", tile_size=64,
                            tile_overlap=64)


def test_detections_on_tiles_come_back_to_the_photo_and_the_map(setup):
    """The round trip through tiles. By construction of the files: the tiled set's own labels,
    read back as detections on the tiles (YOLO segment files and LabelMe files, named after the
    tiles, with the set's tiles.json), are the labels of the COCO file (whose images carry
    photo_window) in the photo's pixels, to the files' rounding (COCO and LabelMe 1e-4 px,
    YOLO 1e-7 of a tile). Then forward-projected and fused: every labelled object comes back once,
    at its truth centre (synthetic truth: the demo discs), although many were cut by the
    overlap of two tiles (duplicates in one photo suppressed)."""
    from easyidp_toolbox.core.annotations import read_annotations, read_tile_index
    from easyidp_toolbox.core.demo.round_trip import score_objects
    from easyidp_toolbox.core.projection import forward_project, fuse_views
    from easyidp_toolbox.core.raster import DSM
    s = setup
    folder = s["tiles"]
    index = read_tile_index(folder)
    assert index.tiles and all(w[2] <= 320 and w[3] <= 320 for _, w in index.tiles.values())
    shapes, photos = [], set()
    dsm = DSM(s["dsm"])
    for sp in ("train", "val"):
        coco_file = os.path.join(folder, "coco", f"instances_{sp}.json")
        want = {}
        for ann, cam in read_annotations(coco_file, s["recon"]):
            want.setdefault(cam.label, []).extend(sh.rings[0] for sh in ann.shapes)
        for sub, tol in (("labels", 0.5e-4 + 0.5e-7 * 320 + 1e-9), ("labelme", 1e-4 + 1e-9)):
            got = {}
            for ann, cam in read_annotations(os.path.join(folder, sub, sp), s["recon"], tiles=folder):
                assert ann.image == cam.label and (ann.width, ann.height) == (None, None)
                got.setdefault(cam.label, []).extend(sh.rings[0] for sh in ann.shapes)
                if sub == "labels":
                    shapes += forward_project(ann.shapes, cam, s["recon"], dsm)
                    photos.add(cam.label)
            assert sorted(got) == sorted(want)
            for photo in want:
                a = sorted(want[photo], key=lambda r: tuple(np.round(r.mean(axis=0), 2)))
                b = sorted(got[photo], key=lambda r: tuple(np.round(r.mean(axis=0), 2)))
                assert len(a) == len(b)
                for ra, rb in zip(a, b):
                    assert ra.shape == rb.shape and np.abs(ra - rb).max() <= tol
    fused = fuse_views(shapes, s["recon"], dsm, cameras=sorted(photos))
    labelled = set(s["res_tiles"].object_split)
    truth = [o for o in s["objs"] if o["id"] in labelled]
    found = [{"class": o.label, "x": o.position[0], "y": o.position[1]} for o in fused]
    sc = score_objects(truth, found)
    print(f"\ntiles: {len(shapes)} labels on tiles of {len(photos)} photos → {len(fused)} fused "
          f"objects; recall {sc['recall']:.3f} precision {sc['precision']:.3f}, position error "
          f"median {100 * sc['median_error_m']:.2f} cm, max {100 * sc['max_error_m']:.2f} cm")
    # measured: recall 1.000, precision 0.976 (one piece too many) since views that only the
    # object's own canopy hides are labelled too (issue 32); 0.98 and 0.98 before
    assert sc["recall"] >= 0.98 and sc["precision"] >= 0.97
    assert sc["median_error_m"] <= 0.01
