"""The independent projection truth (``tests/support/independent_camera.py``) and the demo truth.

- the module that computes the independent truth imports neither ``easyidp_toolbox.core`` nor
  anything under it (a fresh interpreter's ``sys.modules``, and its source's imports);
- its pieces against OpenCV and the manual's formulas (Rodrigues, the p1/p2 order, b1/b2);
- independent: the pixels the demo generator writes into truth.json (made with the production
  camera model) equal the independent ones, global and rolling shutter.
"""
import ast
import json
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest

from easyidp_toolbox.tests.support import independent_camera as ic

MODULE = Path(ic.__file__)


def test_the_independent_truth_does_not_import_the_core():
    """A fresh interpreter imports the module and runs it: no ``easyidp_toolbox.core`` module
    is loaded. And its source imports nothing but numpy, OpenCV and the standard library."""
    code = ("import sys, numpy as np\n"
            "from easyidp_toolbox.tests.support import independent_camera as ic\n"
            "cam = ic.Camera(dict(width=8, height=6, f=7.0, cx=0.1, cy=0.0, b1=0.1, b2=0.0, "
            "k1=0.01, k2=0.0, k3=0.0, p1=0.0, p2=0.0))\n"
            "cam.camera_pixels(np.array([[0.1, 0.2, 1.0]]))\n"
            "print(sorted(m for m in sys.modules if m.startswith('easyidp_toolbox.')))\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=str(MODULE.parent), timeout=120)
    assert proc.returncode == 0, proc.stderr[-2000:]
    loaded = eval(proc.stdout.strip().splitlines()[-1])
    assert loaded and not [m for m in loaded if m.startswith("easyidp_toolbox.core")], loaded
    tree = ast.parse(MODULE.read_text())
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            assert node.level == 0, f"relative import in {MODULE.name}: {ast.dump(node)}"
            names.add(node.module.split(".")[0])
    assert names <= {"json", "cv2", "numpy"}, names


def test_rodrigues_equals_opencv():
    v = np.random.default_rng(3).normal(0, 0.8, (20, 3))
    v[0] = 0.0
    want = np.array([cv2.Rodrigues(x)[0] for x in v])
    assert np.abs(ic._rodrigues(v) - want).max() < 1e-12


def test_metashape_terms_by_hand():
    """One term at a time against the manual's formula evaluated by hand: p1 multiplies
    r² + 2x² in x (OpenCV's p2 does), b1 stretches u only, b2 adds y'·b2 to u."""
    base = dict(width=100, height=80, f=50.0, cx=1.5, cy=-2.0, b1=0.0, b2=0.0,
                k1=0.0, k2=0.0, k3=0.0, p1=0.0, p2=0.0)
    x, y = 0.3, -0.2
    r2 = x * x + y * y
    cases = {"p1": (x + 0.01 * (r2 + 2 * x * x), y + 2 * 0.01 * x * y),
             "p2": (x + 2 * 0.01 * x * y, y + 0.01 * (r2 + 2 * y * y)),
             "k1": (x * (1 + 0.01 * r2), y * (1 + 0.01 * r2))}
    for term, (xd, yd) in cases.items():
        cam = ic.Camera({**base, term: 0.01})
        uv, inside = cam.camera_pixels(np.array([[x, y, 1.0]]))
        assert inside[0]
        assert np.allclose(uv[0], [50 + 1.5 + 50 * xd, 40 - 2.0 + 50 * yd], atol=1e-12), term
    uv, _ = ic.Camera({**base, "b1": 0.7, "b2": 0.3}).camera_pixels(np.array([[x, y, 1.0]]))
    assert np.allclose(uv[0], [51.5 + x * 50.7 + y * 0.3, 38.0 + y * 50], atol=1e-12)
    uv, inside = ic.Camera(base).camera_pixels(np.array([[x, y, -1.0], [5.0, 0.0, 1.0]]))
    assert not inside.any() and np.isnan(uv[0]).all()


def test_demo_truth_pixels_equal_the_independent_truth(demo):
    """Independent: every observation pixel of truth.json (the generator's, production model)
    against the independent truth; and the plot corners each photo holds whole."""
    doc = demo.truth_doc
    uv = ic.observation_pixels(doc)
    err = np.abs(uv - np.asarray(doc["observations"]["pixel"])).max()
    print(f"\ndemo truth.json vs the independent truth: max {err:.1e} px over {len(uv)} observations")
    assert err < 1e-6
    ids = doc["points"]["id"]
    xyz = np.asarray(doc["points"]["xyz"])
    for pid, plot in doc["plots"].items():
        corners = xyz[[ids.index(f"{pid}_c{k}") for k in range(1, 5)]]
        for photo in plot["photos_whole"]:
            assert ic.photo_pixels(doc, photo, corners)[1].all(), (pid, photo)


@pytest.fixture(scope="module")
def moving(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    s = make_demo_survey(str(tmp_path_factory.mktemp("moving")), seed=1, rolling_shutter=True)
    with open(s.truth) as fh:
        return json.load(fh)


def test_rolling_shutter_truth_pixels_equal_the_independent_truth(moving):
    """Independent: the rolling-shutter survey's truth pixels (the generator's own root search)
    against the fixed point written out in the support module; the motion matters (pixels move
    by more than a pixel without it)."""
    uv = ic.observation_pixels(moving)
    want = np.asarray(moving["observations"]["pixel"])
    err = np.abs(uv - want).max()
    still = {**moving, "photos": {k: {kk: vv for kk, vv in v.items() if kk != "rolling_shutter"}
                                  for k, v in moving["photos"].items()}}
    moved = np.abs(ic.observation_pixels(still) - want).max()
    print(f"\nrolling-shutter truth vs the independent truth: max {err:.1e} px "
          f"(without the motion {moved:.1f} px)")
    assert err < 1e-6 and moved > 1.0
