"""Cameras and footprints in real QGIS, on the real Metashape and Pix4D projects."""
import numpy as np
import pytest
from qgis.core import (QgsGeometry, QgsPointXY, QgsProcessingContext, QgsProcessingException,
                       QgsProcessingFeedback, QgsVectorLayer, QgsWkbTypes)

from easyidp_toolbox.tests.support.synthetic import write_tif

ALG = "easyidp:camerafootprints"


def _run(params):
    import processing
    return processing.run(ALG, dict({"OUTPUT_CAMERAS": "memory:", "OUTPUT_FOOTPRINTS": "memory:"}, **params),
                          context=QgsProcessingContext(), feedback=QgsProcessingFeedback())


def test_metashape_wheat_on_a_ground_height(provider, realdata):
    res = _run({"PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx"), "GROUND_HEIGHT": 97})
    cams, fps = res["OUTPUT_CAMERAS"], res["OUTPUT_FOOTPRINTS"]
    assert cams.featureCount() == 138 and fps.featureCount() == 138
    assert cams.crs().authid() == "EPSG:4326" and QgsWkbTypes.hasZ(fps.wkbType())
    for cam, fp in zip(cams.getFeatures(), fps.getFeatures()):
        assert cam["label"] == fp["label"] and cam["enabled"]
        assert 20 < cam["height_above_ground"] < 50 and 0 <= cam["view_angle"] < 30
        assert 200 < fp["area"] < 3000 and fp["complete"]
        # the nadir point is inside the footprint for a near-nadir camera
        if cam["view_angle"] < 5:
            assert fp.geometry().contains(QgsGeometry.fromPointXY(QgsPointXY(cam.geometry().asPoint())))


def test_dsm_in_another_crs_gives_the_same_footprints_as_its_height(provider, realdata, tmp_path):
    """A constant DSM in UTM 54N under the lon/lat project: same footprints as GROUND_HEIGHT."""
    from pyproj import Transformer
    res = _run({"PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx"), "GROUND_HEIGHT": 97})
    ext = res["OUTPUT_FOOTPRINTS"].extent()
    to_utm = Transformer.from_crs(4326, 32654, always_xy=True)
    x, y = to_utm.transform([ext.xMinimum(), ext.xMaximum()], [ext.yMinimum(), ext.yMaximum()])
    x0, y1 = min(x) - 20, max(y) + 20
    w, h = int((max(x) - x0 + 20) / 0.5), int((y1 - min(y) + 20) / 0.5)
    dsm = write_tif(str(tmp_path / "dsm.tif"), np.full((h, w), 97.0, np.float32), origin=(x0, y1),
                    pixel=0.5, epsg=32654, tile=256)
    res2 = _run({"PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx"), "DSM": dsm})
    for a, b in zip(res["OUTPUT_FOOTPRINTS"].getFeatures(), res2["OUTPUT_FOOTPRINTS"].getFeatures()):
        assert b["area"] == pytest.approx(a["area"], rel=1e-3)
        assert b["height_above_ground"] == pytest.approx(a["height_above_ground"], abs=1e-3)


def test_pix4d_roi_centroid_is_seen_by_the_footprints_of_its_17_photos(provider, realdata):
    """SOURCES.md: roi.shp polygon 0's centroid at the offset height lies in 17 of 168 photos.

    The footprint ring is the photo border densified to 16 points per edge, so it may differ
    from the exact projection only for photos where the point is within a few pixels of the edge.
    """
    from easyidp_toolbox.core import open_reconstruction
    project = realdata / "easyidp/pix4d_origin/1_initial/params/pix4d.origin_pmatrix.txt"
    res = _run({"PROJECT": str(project), "PROJECT_CRS": "EPSG:32654", "GROUND_HEIGHT": 96.0})
    fps = res["OUTPUT_FOOTPRINTS"]
    assert fps.featureCount() == 168 and fps.crs().authid() == "EPSG:32654"
    roi = QgsVectorLayer(str(realdata / "easyidp/pix4d_origin/roi/roi.shp"), "roi", "ogr")
    ring = next(roi.getFeatures()).geometry().asMultiPolygon()[0][0][:-1]
    centroid = QgsGeometry.fromPointXY(QgsPointXY(np.mean([q.x() for q in ring]), np.mean([q.y() for q in ring])))
    by_footprint = {f["label"] for f in fps.getFeatures() if f.geometry().contains(centroid)}
    recon = open_reconstruction(str(project), source_crs="EPSG:32654")
    p = centroid.asPoint()
    proj = recon.project_points(np.array([[p.x(), p.y(), 96.0]]), "EPSG:32654")
    inside = {lab for lab, st in zip(proj.camera_labels, proj.status[:, 0]) if st == 0}
    assert len(inside) == 17
    w, h = 5472, 3648
    for lab in by_footprint ^ inside:
        u, v = proj.pixels[proj.camera_labels.index(lab), 0]
        assert min(abs(u), abs(u - w), abs(v), abs(v - h)) < 5, lab


def test_goya_local_crs_and_unaligned_cameras(provider, realdata, tmp_path):
    res = _run({"PROJECT": str(realdata / "easyidp/metashape/goya_test.psx"), "GROUND_HEIGHT": 0,
                "OUTPUT_CAMERAS": str(tmp_path / "cams.gpkg")})
    cams = QgsVectorLayer(res["OUTPUT_CAMERAS"], "cams", "ogr")
    assert cams.featureCount() == 256 and cams.crs().description() == "Local Coordinates (m)"
    labels = {f["label"] for f in cams.getFeatures()}
    assert not {"DJI_0538.JPG", "DJI_0539.JPG", "DJI_0540.JPG"} & labels


def test_bad_inputs(provider, realdata, tmp_path):
    with pytest.raises(QgsProcessingException, match="Give a DSM or a ground height"):
        _run({"PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx")})
    with pytest.raises(QgsProcessingException, match="CRS is unknown.*Project CRS"):
        _run({"PROJECT": str(realdata / "easyidp/pix4d_origin/1_initial/params/pix4d.origin_pmatrix.txt"),
              "GROUND_HEIGHT": 96})
    lone = tmp_path / "lonely.psx"
    lone.write_bytes((realdata / "easyidp/metashape/goya_test.psx").read_bytes())
    with pytest.raises(QgsProcessingException, match="lonely"):
        _run({"PROJECT": str(lone), "GROUND_HEIGHT": 0})
    other = tmp_path / "notes.txt"
    other.write_text("hello")
    with pytest.raises(QgsProcessingException, match="notes.txt: not a photogrammetry project"):
        _run({"PROJECT": str(other), "GROUND_HEIGHT": 0})


def test_opensfm_reconstruction_file(provider, realdata):
    """The real OpenSfM reconstruction (3 street photos in Berlin): cameras in the WGS 84 / UTM
    zone of its reference point, placed where OpenSfM's topocentric frame puts them."""
    from pyproj import Transformer
    import json
    path = realdata / "opensfm_berlin" / "reconstruction_example.json"
    res = _run({"PROJECT": str(path), "GROUND_HEIGHT": 0})
    cams = res["OUTPUT_CAMERAS"]
    assert cams.featureCount() == 3 and cams.crs().authid() == "EPSG:32633"
    doc = json.loads(path.read_text())[0]
    ref = doc["reference_lla"]
    e0, n0 = Transformer.from_crs(4326, 32633, always_xy=True).transform(ref["longitude"], ref["latitude"])
    for f in cams.getFeatures():
        p = f.geometry().constGet()
        assert abs(p.x() - e0) < 60 and abs(p.y() - n0) < 60 and 0 < p.z() < 60
        assert f["photo_path"] == ""                       # no images/ folder beside it


def test_opensfm_chunk_out_of_range_is_refused(provider, realdata):
    with pytest.raises(QgsProcessingException, match=r"no reconstruction #3: it holds 1"):
        _run({"PROJECT": str(realdata / "opensfm_berlin" / "reconstruction_example.json"),
              "CHUNK": "3", "GROUND_HEIGHT": 0})
