"""LabelMe photo annotations: every shape type in the project pixel convention; bad files."""
import json

import numpy as np
import pytest

from easyidp_toolbox.core.annotations import read_labelme
from easyidp_toolbox.core.errors import InputError


def _write(tmp_path, shapes, **extra):
    doc = {"version": "5.2.1", "flags": {}, "shapes": shapes, "imagePath": "DJI_0001.JPG",
           "imageData": None, "imageHeight": 600, "imageWidth": 800, **extra}
    p = tmp_path / "a.json"
    p.write_text(json.dumps(doc))
    return p


def _shape(kind, points, label="x", **kw):
    return {"label": label, "points": points, "group_id": None, "shape_type": kind, "flags": {}, **kw}


def test_real_labelme_file(realdata):
    doc = read_labelme(realdata / "easyidp/labelme/labelme_demo_img.json")
    assert (doc.image, doc.width, doc.height) == ("labelme_demo_img.JPG", 4608, 3456)
    (s,) = doc.shapes
    assert s.label == "1" and s.kind == "polygon" and s.rings[0].shape == (4, 2)
    np.testing.assert_allclose(s.rings[0][0], [2447.239263803681, 1369.325153374233])  # no shift


def test_shape_types(tmp_path):
    p = _write(tmp_path, [_shape("rectangle", [[10, 20], [30, 60]], "box"),
                          _shape("circle", [[100, 100], [110, 100]], "disc"),
                          _shape("linestrip", [[0, 0], [5, 5], [9, 0]], "row"),
                          _shape("point", [[3.5, 4.5]], "head", description="wheat head"),
                          _shape("polygon", [[0, 0], [4, 0], [4, 3]], "tri", score=0.9)])
    box, disc, row, head, tri = read_labelme(p).shapes
    np.testing.assert_array_equal(box.rings[0], [[10, 20], [30, 20], [30, 60], [10, 60]])
    assert disc.kind == "polygon" and len(disc.rings[0]) == 64
    np.testing.assert_allclose(np.hypot(*(disc.rings[0] - 100).T), 10)
    assert row.kind == "line" and head.kind == "point" and head.attributes == {"description": "wheat head"}
    assert tri.score == 0.9 and tri.source_type == "polygon"


@pytest.mark.parametrize("shapes, message", [
    ([_shape("mask", [[0, 0], [1, 1]])], "'mask' is not supported"),
    ([_shape("polygon", [[0, 0], [1, 1]])], "needs at least 3"),
    ([_shape("polygon", [[0, 0], [1, "a"], [2, 2]])], "not (x, y) pixel pairs"),
    ([_shape("polygon", [[0, 0], [1, float("nan")], [2, 2]])], "not finite"),
    (["oops"], "shape 0 is not an object"),
])
def test_bad_shapes_are_named(tmp_path, shapes, message):
    p = _write(tmp_path, shapes)
    with pytest.raises(InputError, match="a.json") as exc:
        read_labelme(p)
    assert message in str(exc.value)


def test_bad_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_labelme(tmp_path / "none.json")
    p = tmp_path / "x.json"
    p.write_text("{")
    with pytest.raises(InputError, match="not valid LabelMe JSON"):
        read_labelme(p)
    p.write_text('{"type": "FeatureCollection", "features": []}')
    with pytest.raises(InputError, match="no 'shapes' list"):
        read_labelme(p)
    with pytest.raises(InputError, match="imageWidth is 0"):
        read_labelme(_write(tmp_path, [], imageWidth=0))
