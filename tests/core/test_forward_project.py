"""Forward projection on the demo survey, against its truth (true by construction: the LabelMe
vertices' map coordinates and the truth points were made by the generator's own exact ray
casting on its scene, not by core.projection), on both the Metashape (geocentric) and the
Pix4D (offset) projects; round trips through project_points; multi-view merge; bad input."""
import json
import os

import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.annotations import read_annotations
from easyidp_toolbox.core.annotations.model import POINT, PhotoShape
from easyidp_toolbox.core.projection import forward_project, merge_views
from easyidp_toolbox.core.raster import DSM, HIT, NODATA

DSM_CELL = 0.02


@pytest.fixture(scope="module", params=["metashape", "pix4d"])
def project(request, demo):
    path = demo.metashape_project if request.param == "metashape" else demo.pix4d_project
    return open_reconstruction(path)


@pytest.fixture(scope="module")
def dsm(demo):
    return DSM(demo.dsm)


def _truth_shapes(demo, cam):
    key = f"labelme/{os.path.splitext(cam.label)[0]}.json"
    return demo.truth_doc["labelme"][key]["shapes"]


def _area(xy):
    x, y = xy[:, 0] - xy[0, 0], xy[:, 1] - xy[0, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_labelme_polygons_land_on_their_true_map_coordinates(demo, project, dsm, capsys):
    errors, area_err = [], []
    for ann, cam in read_annotations(os.path.dirname(demo.labelme[0]), project):
        shapes = forward_project(ann.shapes, cam, project, dsm, densify=False)
        truth = _truth_shapes(demo, cam)
        assert [s.label for s in shapes] == [t["label"] for t in truth]
        for s, t in zip(shapes, truth):
            assert s.complete
            true_xyz = np.array(t["map"])
            errors.append(np.linalg.norm(s.points[0] - true_xyz, axis=1))
            area_err.append(abs(s.area_m2 - _area(true_xyz)) / _area(true_xyz))
    e = np.concatenate(errors)
    with capsys.disabled():
        print(f"\n{project.software}: {len(e)} LabelMe vertices, error median {np.median(e):.2e} m, "
              f"max {e.max():.2e} m; area error max {100 * max(area_err):.4f} %")
    # the bounds are 0.5 and 2 DSM cells and 1 %; the same surface gives far better
    assert np.median(e) <= 0.5 * DSM_CELL and e.max() <= 2 * DSM_CELL
    assert np.median(e) < 1e-4 and e.max() < 1e-3
    assert max(area_err) < 0.01


def test_round_trip_map_to_pixel_to_map(demo, project, dsm):
    """Truth points → project_points → pixel → forward_project: back to the point (1 mm) where
    the photo sees it (the truth's observations). The truth ignores occluders within 15 mm of
    a point (truth.OCCLUSION_START) and takes the nodata strip as bare ground: there the first
    hit may be a leaf just before the point, or the ray may cross nodata (reported)."""
    from easyidp_toolbox.core.demo.truth import OCCLUSION_START
    t = demo.truth_doc
    xyz = np.array(t["points"]["xyz"])
    obs_p = np.array(t["observations"]["point"])
    obs_photo = np.array(t["observations"]["photo"])
    west = dsm.tif.pixel_to_map(40.0, 0.0)[0]             # end of the nodata strip
    errors, grazing, nodata = [], 0, 0
    for photo in sorted(set(obs_photo.tolist()))[::5]:
        pts = xyz[obs_p[obs_photo == photo]]
        cam = next(c for c in project.cameras if os.path.splitext(c.label)[0] == photo)
        uv = project.project_points(pts, "EPSG:32654", cameras=[cam]).pixels[0]
        shapes = forward_project([PhotoShape(str(k), POINT, [u[None]]) for k, u in enumerate(uv)],
                                 cam, project, dsm)
        got = np.array([s.points[0][0] for s in shapes])
        st = np.array([s.status[0][0] for s in shapes])
        near_strip = pts[:, 0] < west + 1.5
        assert np.all((st == HIT) | ((st == NODATA) & near_strip))
        nodata += int((st == NODATA).sum())
        C = project.from_model(cam.C[None], "EPSG:32654")[0]
        e = np.linalg.norm(got - pts, axis=1)[st == HIT]
        before = (np.linalg.norm(pts - C, axis=1) - np.linalg.norm(got - C, axis=1))[st == HIT]
        leaf = (e > 1e-3) & (before > 0) & (e < OCCLUSION_START)
        grazing += int(leaf.sum())
        errors.append(e[~leaf])
    e = np.concatenate(errors)
    assert len(e) > 1000 and e.max() < 1e-3, e.max()
    assert grazing < 0.01 * len(e) and nodata < 0.01 * len(e)


def test_densified_edges_follow_the_surface(demo, project, dsm):
    ann, cam = read_annotations(demo.labelme[0], project)[0]
    coarse = forward_project(ann.shapes[:1], cam, project, dsm, densify=False)[0]
    fine = forward_project(ann.shapes[:1], cam, project, dsm, densify=2.0)[0]
    assert fine.original[0].sum() == len(coarse.points[0])
    assert np.allclose(fine.points[0][fine.original[0]], coarse.points[0], atol=1e-9)
    assert len(fine.points[0]) > 10 * len(coarse.points[0])
    # every densified vertex is on the DSM surface (heights from the DSM itself)
    p = fine.points[0]
    assert np.abs(DSM(demo.dsm).heights(p[:, 0], p[:, 1]) - p[:, 2]).max() < 1e-3


def test_multi_view_merge(demo, project, dsm):
    shapes = []
    for ann, cam in read_annotations(os.path.dirname(demo.labelme[0]), project):
        shapes += forward_project(ann.shapes, cam, project, dsm)
    none = merge_views(shapes, "none")
    union = merge_views(shapes, "union")
    best = merge_views(shapes, "best")
    assert len(none) == len(shapes) == 20
    plots = {s.label for s in shapes}
    assert len(union) == len(best) == len(plots)        # one object per plot
    seen = {lab: sum(s.label == lab for s in shapes) for lab in plots}
    for m in union:                      # the views' clicks differ by ~1 px: a bit larger
        assert m.views == seen[m.label] and m.complete and len(m.parts) == 1
        areas = [s.area_m2 for s in shapes if s.label == m.label]
        assert max(areas) * (1 - 1e-9) <= m.area_m2 <= min(sum(areas), 1.05 * max(areas))
    for m in best:
        assert m.views == seen[m.label] and m.photos[0] in {s.photo for s in m.members}
    assert max(m.views for m in union) >= 2


def test_rays_that_miss_are_reported_per_vertex(demo, project, dsm):
    """A polygon reaching over the sky-less edge of the photo onto the DSM's nodata strip."""
    cam = next(c for c in project.aligned_cameras)        # the first photo sees the west edge
    w, h = project.sensors[cam.sensor_id].width, project.sensors[cam.sensor_id].height
    poly = np.array([[1.0, 1.0], [w / 2, 1.0], [w / 2, h - 1.0], [1.0, h - 1.0]])
    s = forward_project([poly], cam, project, dsm)[0]
    assert not s.complete and 0 < s.missing < len(s.points[0])
    assert "nodata" in s.why_incomplete() or "left" in s.why_incomplete()
    assert len(s.rings[0]) == len(s.points[0]) - s.missing


def test_dsm_in_another_crs(demo, project, tmp_path):
    """The DSM resampled onto a transverse Mercator grid of its own: results given back in
    UTM 54N agree with the truth to a fraction of a DSM cell (the resampling smooths)."""
    from pyproj import CRS, Transformer
    from easyidp_toolbox.core.raster import open_geotiff
    from easyidp_toolbox.core.raster.geotiff_write import write_geotiff
    tm = CRS.from_proj4("+proj=tmerc +lat_0=35.73 +lon_0=139.0 +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m")
    src = open_geotiff(demo.dsm)
    x0, y1 = src.pixel_to_map(0, 0)
    x1, y0 = src.pixel_to_map(src.width, src.height)
    to_tm = Transformer.from_crs("EPSG:32654", tm, always_xy=True)
    cx, cy = to_tm.transform([x0, x1, x0, x1], [y0, y0, y1, y1])
    px = 0.02
    gx0, gy1 = min(cx), max(cy)
    nx, ny = int((max(cx) - gx0) / px), int((gy1 - min(cy)) / px)
    gx, gy = np.meshgrid(gx0 + (np.arange(nx) + 0.5) * px, gy1 - (np.arange(ny) + 0.5) * px)
    ux, uy = Transformer.from_crs(tm, "EPSG:32654", always_xy=True).transform(gx, gy)
    z = DSM(src).heights(ux.ravel(), uy.ravel()).reshape(ny, nx)
    z = np.where(np.isnan(z), -9999.0, z).astype(np.float32)
    path = str(tmp_path / "dsm_tm.tif")
    write_geotiff(path, z, (gx0, px, 0.0, gy1, 0.0, -px), {}, nodata_text="-9999")
    dsm_tm = DSM(path, crs=tm.to_wkt())
    errors = []
    for ann, cam in read_annotations(os.path.dirname(demo.labelme[0]), project):
        shapes = forward_project(ann.shapes, cam, project, dsm_tm, densify=False, output_crs="EPSG:32654")
        for s, t in zip(shapes, _truth_shapes(demo, cam)):
            errors.append(np.linalg.norm(s.points[0] - np.array(t["map"]), axis=1))
    e = np.concatenate(errors)
    assert np.median(e) <= 0.5 * DSM_CELL and np.nanmax(e) <= 2 * DSM_CELL


def test_bad_annotations(demo, project, tmp_path):
    folder = os.path.dirname(demo.labelme[0])
    doc = json.load(open(demo.labelme[0]))
    # an image that is not a photo of the project
    bad = dict(doc, imagePath="../photos/IMG_9999.JPG")
    p = tmp_path / "IMG_9999.json"
    p.write_text(json.dumps(bad))
    with pytest.raises(InputError, match="IMG_9999.*not a photo of the project"):
        read_annotations(str(p), project)
    # a LabelMe file drawn on a resized copy
    small = dict(doc, imageWidth=400, imageHeight=300)
    p = tmp_path / "DJI_0005.json"
    p.write_text(json.dumps(small))
    with pytest.raises(InputError, match=r"400×300 px.*800×600"):
        read_annotations(str(p), project)
    # COCO with a malformed annotation: named
    coco = {"images": [{"id": 1, "file_name": "DJI_0005.JPG", "width": 800, "height": 600}],
            "categories": [{"id": 3, "name": "plot"}],
            "annotations": [{"id": 7, "image_id": 1, "category_id": 3, "bbox": [10, 10, 50, 40]},
                            {"id": 8, "image_id": 1, "category_id": 3, "segmentation": [[1, 2, 3]]}]}
    p = tmp_path / "coco.json"
    p.write_text(json.dumps(coco))
    with pytest.raises(InputError, match=r"annotations\[1\] segmentation\[0\]: 3 numbers"):
        read_annotations(str(p), project)
    coco["annotations"][1] = {"id": 9, "image_id": 2, "category_id": 3, "bbox": [1, 1, 2, 2]}
    p.write_text(json.dumps(coco))
    with pytest.raises(InputError, match="image_id 2"):
        read_annotations(str(p), project)
    coco["annotations"][1] = {"id": 9, "image_id": 1, "category_id": 3,
                              "segmentation": {"counts": "abc", "size": [600, 800]}}
    p.write_text(json.dumps(coco))
    with pytest.raises(InputError, match="RLE"):
        read_annotations(str(p), project)
    # YOLO with a malformed line: named
    yolo = tmp_path / "yolo"
    yolo.mkdir()
    (yolo / "DJI_0005.txt").write_text("0 0.5 0.5 0.1 0.1\n0 0.2 0.3\n")
    with pytest.raises(InputError, match=r"DJI_0005.txt, line 2: 2 numbers"):
        read_annotations(str(yolo), project)
    (yolo / "DJI_0005.txt").write_text("0 0.5 0.5 0.1 x\n")
    with pytest.raises(InputError, match="line 1"):
        read_annotations(str(yolo), project)
    (yolo / "DJI_0005.txt").write_text("0 50 60 10 10\n")
    with pytest.raises(InputError, match="normalised"):
        read_annotations(str(yolo), project)
    assert folder


def test_coco_and_yolo_give_the_same_pixels_as_labelme(demo, project, tmp_path):
    """The LabelMe polygons written as COCO segmentations and YOLO polygons (normalised) and
    boxes: the same shapes come back, matched to the same photo."""
    ann, cam = read_annotations(demo.labelme[0], project)[0]
    w, h = 800, 600
    coco = {"images": [{"id": 5, "file_name": "photos/" + os.path.basename(ann.image), "width": w,
                        "height": h}],
            "categories": [{"id": 1, "name": "plot"}],
            "annotations": [{"id": k, "image_id": 5, "category_id": 1, "score": 0.9,
                             "segmentation": [s.rings[0].ravel().tolist()]}
                            for k, s in enumerate(ann.shapes)]}
    (tmp_path / "c.json").write_text(json.dumps(coco))
    got, cam2 = read_annotations(str(tmp_path / "c.json"), project)[0]
    assert cam2.label == cam.label and [s.score for s in got.shapes] == [0.9] * len(ann.shapes)
    for a, b in zip(ann.shapes, got.shapes):
        assert np.allclose(a.rings[0], b.rings[0]) and b.label == "plot"
    yolo = tmp_path / "labels"
    yolo.mkdir()
    (yolo / "classes.txt").write_text("plot\n")
    lines = [" ".join(["0"] + [f"{v:.9f}" for v in (s.rings[0] / [w, h]).ravel()] + ["0.75"])
             for s in ann.shapes]
    r = ann.shapes[0].rings[0]
    (x0, y0), (x1, y1) = r.min(axis=0), r.max(axis=0)
    lines.append(f"0 {(x0 + x1) / 2 / w} {(y0 + y1) / 2 / h} {(x1 - x0) / w} {(y1 - y0) / h}")
    (yolo / (os.path.splitext(os.path.basename(ann.image))[0] + ".txt")).write_text("\n".join(lines))
    got, cam3 = read_annotations(str(yolo), project)[0]
    assert cam3.label == cam.label and got.shapes[0].label == "plot"
    for a, b in zip(ann.shapes, got.shapes):
        assert np.allclose(a.rings[0], b.rings[0], atol=1e-5) and b.score == 0.75
    assert np.allclose(got.shapes[-1].rings[0], [[x0, y0], [x1, y0], [x1, y1], [x0, y1]], atol=1e-5)


def test_real_labelme_file(realdata, project):
    """The real LabelMe 4.5.6 file (SOURCES.md 1c): read as is, recognised, and refused with
    its image's name for a project it does not belong to."""
    from easyidp_toolbox.core.annotations import detect_format, read_labelme
    path = realdata / "easyidp" / "labelme" / "labelme_demo_img.json"
    ann = read_labelme(path)
    assert (ann.width, ann.height, ann.image) == (4608, 3456, "labelme_demo_img.JPG")
    assert [(s.label, s.kind, len(s.rings[0])) for s in ann.shapes] == [("1", "polygon", 4)]
    assert detect_format(path) == "labelme"
    with pytest.raises(InputError, match="labelme_demo_img.JPG.*not a photo of the project"):
        read_annotations(path, project)
