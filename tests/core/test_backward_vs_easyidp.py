"""Side by side with easyidp 2.0.4 ``Metashape.back2raw`` on the real wheat_tanashi project.

Truth kind: the reference implementation, run in its own environment (.venv-ref). The same 3-D
plot polygons (UTM 54N, ellipsoidal heights as geometry Z) go to both. With EasyIDP's rule
(whole ROIs only, no densification) the photo sets and the vertices must be identical to
1e-6 px. With our defaults (densified edges, clipping) we keep more photos (the ROIs cut by the
frame) and never fewer ROIs; the test prints where and why we differ.
"""
import json
import os
import subprocess

import numpy as np
import pytest
from pyproj import Transformer

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.projection import back_project
from easyidp_toolbox.core.roi import ROI, ROISet
from easyidp_toolbox.scripts.reference import REF_PYTHON


EASYIDP_SCRIPT = r"""
import json, logging, sys, warnings
warnings.filterwarnings("ignore")
logging.disable(logging.CRITICAL)
import numpy as np, pyproj
import easyidp as idp
psx, rois_json, out = sys.argv[1:4]
roi = idp.ROI()
for name, pts in json.load(open(rois_json)).items():
    roi[name] = np.array(pts, dtype=float)
roi.crs = pyproj.CRS.from_epsg(32654)
ms = idp.Metashape(psx, chunk_id=0, check_img_existance=False)
res = ms.back2raw(roi)
json.dump({k: {p: np.asarray(v).tolist() for p, v in ph.items()} for k, ph in res.items()},
          open(out, "w"))
"""


def wheat_plots(rows=10, cols=12, seed=0):
    """Plot rectangles (1.2 m × 0.6 m, slightly rotated) over the wheat_tanashi field, in UTM
    54N with ellipsoidal heights around 96.8 m as geometry Z (each vertex its own height)."""
    rng = np.random.default_rng(seed)
    to_utm = Transformer.from_crs(4326, 32654, always_xy=True)
    x0, y0 = to_utm.transform(139.54015, 35.73754)
    x1, y1 = to_utm.transform(139.54062, 35.73810)
    rois = []
    for i in range(rows):
        for j in range(cols):
            cx = x0 + (x1 - x0) * (j + 0.5) / cols
            cy = y0 + (y1 - y0) * (i + 0.5) / rows
            a = np.radians(rng.uniform(-5, 5))
            local = np.array([[-0.6, -0.3], [0.6, -0.3], [0.6, 0.3], [-0.6, 0.3]])
            ring = local @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]]) + [cx, cy]
            z = 96.8 + rng.normal(0, 0.05, 4)
            rois.append(ROI(f"P{i:02d}_{j:02d}", [[ring]], {}, [[z]]))
    return ROISet(rois, "EPSG:32654")


@pytest.fixture(scope="module")
def easyidp_result(realdata, tmp_path_factory):
    if not REF_PYTHON.exists():
        pytest.fail(f"reference environment with easyidp 2.0.4 not found at {REF_PYTHON}: "
                    "run `make env-ref`")
    tmp = tmp_path_factory.mktemp("easyidp_back2raw")
    rois = wheat_plots()
    closed = {r.name: np.column_stack([np.vstack([r.rings[0], r.rings[0][:1]]),
                                       np.append(r.ring_z[0], r.ring_z[0][0])]).tolist()
              for r in rois}
    (tmp / "rois.json").write_text(json.dumps(closed))
    (tmp / "run.py").write_text(EASYIDP_SCRIPT)
    env = {k: v for k, v in os.environ.items() if k not in ("PROJ_DATA", "PROJ_LIB")}
    env.update(HOME=str(tmp), XDG_DATA_HOME=str(tmp))
    psx = realdata / "easyidp" / "metashape" / "wheat_tanashi.psx"
    proc = subprocess.run([str(REF_PYTHON), str(tmp / "run.py"), str(psx), str(tmp / "rois.json"),
                           str(tmp / "out.json")], capture_output=True, text=True, env=env,
                          timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    with open(tmp / "out.json") as fh:
        theirs = json.load(fh)
    return rois, {k: {p: np.array(v) for p, v in ph.items()} for k, ph in theirs.items()}


def test_identical_to_easyidp_with_its_rule(realdata, easyidp_result):
    rois, theirs = easyidp_result
    recon = open_reconstruction(realdata / "easyidp" / "metashape" / "wheat_tanashi.psx")
    res = back_project(rois, recon, heights="geometry", clip=False, min_visible=0,
                       densify_tolerance=1e12)
    ours = res.to_easyidp_dict()
    assert ours.keys() == theirs.keys()
    worst, pairs = 0.0, 0
    for name in ours:
        assert set(ours[name]) == set(theirs[name]), name
        for photo, uv in ours[name].items():
            worst = max(worst, float(np.abs(uv - theirs[name][photo]).max()))
            pairs += 1
    print(f"\neasyidp 2.0.4 back2raw vs ours (its rule): {len(ours)} plots, {pairs} plot × photo "
          f"pairs, identical photo sets, max vertex difference {worst:.1e} px")
    assert pairs > 1000 and worst < 1e-6


def test_where_our_defaults_differ(realdata, easyidp_result):
    rois, theirs = easyidp_result
    recon = open_reconstruction(realdata / "easyidp" / "metashape" / "wheat_tanashi.psx")
    res = back_project(rois, recon, heights="geometry", min_visible=0)
    ours = res.to_easyidp_dict()
    extra = lost = bent = 0
    for name in ours:
        o, t = set(ours[name]), set(theirs[name])
        lost += len(t - o)
        extra += len(o - t)
        for photo in o & t:                      # unclipped in both: their vertices are ours
            i = [k for k in res.records_of(name) if res.photo[k] == photo][0]
            ring = res.rings_of(i)[0]
            d = np.min(np.linalg.norm(ring[None, :, :] - theirs[name][photo][:-1, None, :], axis=2), axis=1)
            assert d.max() < 1e-6
            bent += len(ring) > 4
    print(f"\nour defaults vs easyidp: {extra} more plot × photo pairs (ROIs clipped to the frame), "
          f"{lost} fewer (a densified edge bends out of the frame), {bent} pairs with densified edges")
    assert extra > 0 and lost <= 0.01 * sum(len(v) for v in theirs.values())
