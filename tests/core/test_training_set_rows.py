"""Export's occlusion rule on row crops that hide their own soil (issue 32).

World: tests/support/row_crops.py (plots of 1.2 m rows 0.5 m apart, weeds, margin grass, uneven
vigour, an 10 m shed; six cameras about 40° off nadir and one at nadir). Truth kind:
**independent** — analytic rays against the world's boxes (a slab test) and the pinhole formula,
both written in the support module; the code under test sees only the rasterised DSM and a
Reconstruction of the same poses.
"""
from pathlib import Path

import numpy as np
import pytest

from easyidp_toolbox.core.projection import back_project, export_training_set
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.core.reconstruction import Calibration, Camera, Reconstruction, Sensor
from easyidp_toolbox.core.reconstruction.geodesy import OffsetFrame
from easyidp_toolbox.core.roi import ROI, ROISet
from easyidp_toolbox.tests.support import row_crops as world

MIN_VISIBLE = 0.5


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    from pyproj import CRS
    tmp = tmp_path_factory.mktemp("rows")
    w = world.write_world(tmp)
    utm = CRS.from_epsg(32654)
    sensor = Sensor("0", "pinhole", world.W, world.H,
                    Calibration(f=world.F, cx=world.W / 2, cy=world.H / 2))
    cams = [Camera(str(k), label, "0", photo_path=path, R=R, C=np.asarray(C, float))
            for k, (label, R, C, path) in enumerate(w["cameras"])]
    recon = Reconstruction(Path("rows"), "rows", "s", utm, OffsetFrame(utm, world.OFFSET),
                           {"0": sensor}, cams)
    rois = ROISet([ROI(name, [[ring]]) for name, ring in w["plots"].items()], utm)
    return dict(recon=recon, rois=rois, dsm=w["dsm"], truth=world.truth(), tmp=tmp)


def test_the_world_hides_the_soil_between_rows(rows):
    """The world is hard: the surface-sample rule (Back-project's occlusion on the DSM) calls
    plots hidden that nothing outside them hides (truth: independent rays)."""
    bp = back_project(rows["rois"], rows["recon"], heights=DSM(rows["dsm"]),
                      occlusion_dsm=DSM(rows["dsm"]), min_visible=0.0)
    self_hidden = [float(bp.occluded_fraction[i]) for i in range(len(bp))
                   if rows["truth"][(bp.roi_names[bp.roi[i]], bp.photo[i])] == (True, 0.0)]
    print(f"\nsurface-sample rule on plots hidden by nothing outside: occluded share median "
          f"{np.median(self_hidden):.2f}, max {max(self_hidden):.2f} of {len(self_hidden)} pairs")
    assert len(self_hidden) >= 20 and max(self_hidden) > 0.5


def test_a_plot_hidden_by_nothing_outside_itself_is_labelled(rows, tmp_path):
    """Truth (independent): every plot × photo with the plot in the frame and no line of sight
    to its top blocked by anything but its own rows and weeds is labelled; a plot at least 75 %
    hidden by the shed or a neighbour is not."""
    import json
    res = export_training_set(rows["rois"], ["plot"] * len(rows["rois"]), rows["recon"],
                              rows["dsm"], tmp_path / "set", val_fraction=0.0,
                              min_visible=MIN_VISIBLE)
    doc = json.load(open(tmp_path / "set" / "coco" / "instances_train.json"))
    photo = {im["id"]: im["photo"] for im in doc["images"]}
    labelled = {(a["attributes"]["instance"], photo[a["image_id"]]) for a in doc["annotations"]}
    must = {k for k, (inside, hid) in rows["truth"].items() if inside and hid == 0.0}
    must_not = {k for k, (inside, hid) in rows["truth"].items() if hid >= 0.75}
    print(f"\n{len(must)} pairs in the frame and hidden by nothing outside: "
          f"{len(must & labelled)} labelled; {len(must_not)} pairs ≥ 75 % hidden by others: "
          f"{len(must_not & labelled)} labelled; {res.summary()}")
    assert len(must) >= 20 and len(must_not) >= 1
    assert must <= labelled, sorted(must - labelled)
    assert not must_not & labelled, sorted(must_not & labelled)
