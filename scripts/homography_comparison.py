"""Forward projection side by side with easyidp 2.0.4's homography, on the demo survey.

easyidp 2.0.4's raw → map path (``geotiff.one_raw_roi2geotiff``) fits one projective
transform per ROI and photo from the ROI's vertices (their pixels from its ``back2raw_crs``)
and maps every raw pixel through it: flat ground. Here, for plots and photos that see them
whole, the truth points inside each plot (on the crop or the soil) are taken from their true
pixels to the map both ways: easyidp's homography (run in its own environment, ``.venv-ref``;
the transform estimated by scikit-image as easyidp does) and our ray–DSM forward projection.
Both are compared with the truth's map coordinates (horizontal error, metres).

    python -m easyidp_toolbox.scripts.homography_comparison SURVEY_FOLDER
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

from .reference import reference_env, require_reference

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLOTS, PHOTOS_PER_PLOT = 12, 2

REF_SCRIPT = r"""
import json, sys, warnings
warnings.filterwarnings("ignore")
import numpy as np, pyproj
import easyidp as idp
from skimage.transform import ProjectiveTransform
folder, cases_path, out = sys.argv[1:4]
with open(cases_path) as fh:
    cases = json.load(fh)
ms = idp.Metashape(folder + "/metashape/demo_survey.psx", chunk_id=0)
ms.crs = pyproj.CRS.from_epsg(32654)
p4d = idp.Pix4D(folder + "/pix4d/demo_survey.p4d", raw_img_folder=folder + "/photos")
result = {}
for name, recon in (("metashape", ms), ("pix4d", p4d)):
    rows = []
    for c in cases:
        corners = np.array(c["corners"])
        got = recon.back2raw_crs(corners)
        key = c["photo"] if c["photo"] in got else c["photo"] + ".JPG"
        if key not in got:
            rows.append(None)
            continue
        px = np.asarray(got[key])[:, :2]
        # as one_raw_roi2geotiff: raw pixels -> geo, one projective transform from the vertices
        try:
            pt = ProjectiveTransform.from_estimate(src=px, dst=corners[:, :2])
        except AttributeError:
            pt = ProjectiveTransform()
            pt.estimate(px, corners[:, :2])
        rows.append(pt(np.array(c["pixels"])).tolist())
    result[name] = rows
with open(out, "w") as fh:
    json.dump(result, fh)
"""


def cases(truth: dict):
    """(plot, photo, corners xyz, truth point pixels, truth point xyz) for the comparison."""
    from ..core.geometry import points_in_rings
    xyz = np.array(truth["points"]["xyz"])
    obs = truth["observations"]
    from ..tests.support.independent_camera import observation_pixels
    point, photo = np.array(obs["point"]), np.array(obs["photo"])
    pixel = observation_pixels(truth)          # the independent truth (no core code)
    out = []
    for pid in sorted(truth["plots"])[:PLOTS]:
        p = truth["plots"][pid]
        corners = np.array(p["corners"])
        ring = np.vstack([corners[:, :2], corners[:1, :2]])
        for ph in p["photos_whole"][:PHOTOS_PER_PLOT]:
            sel = photo == ph
            inside = points_in_rings(xyz[point[sel], 0], xyz[point[sel], 1], [ring])
            if inside.sum() < 3:
                continue
            out.append({"plot": pid, "photo": ph, "corners": corners.tolist(),
                        "pixels": pixel[sel][inside].tolist(),
                        "xyz": xyz[point[sel][inside]].tolist()})
    return out


def compare(folder: str) -> dict:
    """{project: {"ours": errors (m), "easyidp": errors (m), "points": n}} over the cases."""
    from ..core import open_reconstruction
    from ..core.annotations.model import POINT, PhotoShape
    from ..core.projection import forward_project
    from ..core.raster import DSM
    with open(os.path.join(folder, "truth.json")) as fh:
        truth = json.load(fh)
    cs = cases(truth)
    ref_python = require_reference()
    with tempfile.TemporaryDirectory() as tmp:
        cpath, out = os.path.join(tmp, "cases.json"), os.path.join(tmp, "ref.json")
        with open(cpath, "w") as fh:
            json.dump(cs, fh)
        env = reference_env()
        env.update(HOME=tmp, XDG_DATA_HOME=tmp)
        proc = subprocess.run([ref_python, "-c", REF_SCRIPT, folder, cpath, out],
                              capture_output=True, text=True, env=env, timeout=600)
        if proc.returncode:
            raise RuntimeError("easyidp 2.0.4 failed:\n" + proc.stderr[-3000:])
        with open(out) as fh:
            ref = json.load(fh)
    dsm = DSM(os.path.join(folder, "dsm.tif"))
    result = {}
    for name, path in (("metashape", "metashape/demo_survey.psx"), ("pix4d", "pix4d/demo_survey.p4d")):
        recon = open_reconstruction(os.path.join(folder, path))
        ours, theirs = [], []
        for c, r in zip(cs, ref[name]):
            if r is None:
                continue
            cam = next(k for k in recon.cameras if os.path.splitext(k.label)[0] == c["photo"])
            shapes = forward_project([PhotoShape(str(k), POINT, [np.array([uv])])
                                      for k, uv in enumerate(c["pixels"])], cam, recon, dsm)
            got = np.array([s.points[0][0] for s in shapes])
            true = np.array(c["xyz"])
            ours.append(np.hypot(*(got[:, :2] - true[:, :2]).T))
            theirs.append(np.hypot(*(np.array(r) - true[:, :2]).T))
        ours, theirs = np.concatenate(ours), np.concatenate(theirs)
        result[name] = {"ours": ours, "easyidp": theirs, "points": len(ours), "cases": len(cs)}
    return result


def report(result: dict) -> str:
    lines = []
    for name, r in result.items():
        o, t = r["ours"], r["easyidp"]
        lines.append(f"  {name}: {r['points']} truth points in {r['cases']} plot × photo pairs; "
                     f"horizontal error median / 95 % / max: ours "
                     f"{np.median(o) * 1000:.3f} / {np.percentile(o, 95) * 1000:.3f} / "
                     f"{o.max() * 1000:.3f} mm, easyidp 2.0.4 homography "
                     f"{np.median(t) * 1000:.1f} / {np.percentile(t, 95) * 1000:.1f} / "
                     f"{t.max() * 1000:.1f} mm; mean {o.mean() * 1000:.3f} vs {t.mean() * 1000:.1f} mm")
    return "\n".join(lines)


if __name__ == "__main__":
    print(report(compare(os.path.abspath(sys.argv[1]))))
