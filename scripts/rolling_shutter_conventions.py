"""Which convention do Metashape's per-camera ``<rolling_shutter>`` blocks follow?

Evaluates a fixed list of candidate conventions on a Metashape project with compensation on and
pinned marker observations (the real ``goya_test``): for each candidate, every marker seen in at
least two photos is triangulated from its observations with that candidate's rays, then
reprojected with that candidate's poses (row and pose solved by fixed-point iteration), and the
median / maximum / RMS pixel residuals are printed. Nothing is fitted: each candidate is a
fixed rule (the 3-D marker positions are the only unknowns, as in any triangulation).

A candidate says, for image row ``v`` (pixels) of an image of height ``h``:

- ``tau``: the exposure parameter τ(v): ``v/h`` (first row, span 1), ``v/h − 1/2`` (centre
  row, span 1), ``(v − h/2)/(h/2)`` (centre row, span 2), ``v/h − 1`` (last row, span 1),
  ``(v − cy)/(h/2)`` (principal point, span 2);
- ``frame``: the block's rotation Rs and translation t act in the camera frame
  (Xc(τ) = Rs^(σr·τ)·(R·(X − C) − σt·τ·t)) or in the chunk frame about the camera centre;
- ``σr``, ``σt``: +1 as stored, −1 inverted;
- ``interp``: Rs^τ by axis-angle scaling (constant rate) or linear blending of the matrix;
- ``row``: the sensor (distorted) row or the undistorted row.

Run: ``python -m easyidp_toolbox.scripts.rolling_shutter_conventions [project.psx]``; the table
in ARCHITECTURE.md ("Rolling shutter") is its output on goya_test.
"""
import argparse
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
REALDATA = Path(os.environ.get("EASYIDP_REALDATA", ROOT.parent / "shared" / "realdata"))
GOYA = REALDATA / "easyidp" / "metashape" / "goya_test.psx"


@dataclass(frozen=True)
class Convention:
    name: str
    tau: str = "centre2"          # first1 | centre1 | centre2 | last1 | pp2
    frame: str = "camera"         # camera | chunk
    sr: int = 1
    st: int = 1
    interp: str = "axis-angle"    # axis-angle | linear
    row: str = "sensor"           # sensor | undistorted


CANDIDATES: List[Optional[Convention]] = [None] + [
    Convention(f"camera, τ={t}, σr={sr:+d}, σt={st:+d}", t, "camera", sr, st)
    for t in ("first1", "centre1", "centre2", "last1") for sr, st in ((1, 1), (-1, -1))
] + [
    Convention("camera, τ=centre2, σr=+1, σt=-1", "centre2", "camera", 1, -1),
    Convention("camera, τ=centre2, σr=-1, σt=+1", "centre2", "camera", -1, 1),
    Convention("camera, τ=centre2, rotation only", "centre2", "camera", 1, 0),
    Convention("camera, τ=centre2, translation only", "centre2", "camera", 0, 1),
    Convention("chunk, τ=centre2, σr=+1, σt=+1", "centre2", "chunk", 1, 1),
    Convention("chunk, τ=centre2, σr=-1, σt=-1", "centre2", "chunk", -1, -1),
    Convention("chunk, τ=centre1, σr=+1, σt=+1", "centre1", "chunk", 1, 1),
    Convention("chunk, τ=centre1, σr=-1, σt=-1", "centre1", "chunk", -1, -1),
    Convention("camera, τ=pp2 (about cy), σr=+1, σt=+1", "pp2", "camera", 1, 1),
    Convention("camera, τ=centre2, linear matrix blend", "centre2", "camera", 1, 1, "linear"),
    Convention("camera, τ=centre2, undistorted row", "centre2", "camera", 1, 1,
               row="undistorted"),
]


def _rodrigues(w: np.ndarray) -> np.ndarray:
    a = float(np.linalg.norm(w))
    if a == 0.0:
        return np.eye(3)
    k = w / a
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def _log(M: np.ndarray) -> np.ndarray:
    th = np.arccos(np.clip((np.trace(M) - 1) / 2, -1, 1))
    w = np.array([M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1]])
    return w * (th / (2 * np.sin(th))) if th > 1e-12 else 0.5 * w


class Project:
    """Stored poses (from our reader, motion switched off) and the raw blocks of one chunk."""

    def __init__(self, psx: Path):
        from easyidp_toolbox.core import open_reconstruction
        from easyidp_toolbox.core.reconstruction.metashape import _open_project, _chunk_entries
        self.recon = open_reconstruction(psx)
        src, doc = _open_project(Path(psx))
        chunk = _chunk_entries(src, doc)[0]["_doc"]
        tr = chunk.find("components/component/transform")
        tr = chunk.find("transform") if tr is None else tr
        rot = np.array(tr.find("rotation").text.split(), float).reshape(3, 3)
        self.scale = float(tr.find("scale").text)
        self.Q = rot                                   # chunk axes → model axes (local CRS)
        self.blocks: Dict[str, Tuple[np.ndarray, np.ndarray]] = {}
        for el in chunk.find("cameras").iter("camera"):
            rs = el.find("rolling_shutter")
            if rs is not None and el.find("transform") is not None:
                self.blocks[el.get("label")] = (
                    np.array(rs.find("rotation").text.split(), float).reshape(3, 3),
                    np.array(rs.find("translation").text.split(), float))
        s = next(iter(self.recon.sensors.values()))
        self.cal, self.w, self.h = s.calibration, s.width, s.height

    def tau(self, c: Convention, v):
        h = self.h
        return {"first1": v / h, "centre1": v / h - 0.5, "centre2": (v - h / 2) / (h / 2),
                "last1": v / h - 1.0, "pp2": (v - self.cal.cy) / (h / 2)}[c.tau]

    def pose(self, c: Optional[Convention], label: str, tau: float):
        """(R, C) of camera ``label`` at τ in the model frame."""
        cam = self.recon.camera(label)
        if c is None or label not in self.blocks:
            return cam.R, cam.C
        Rs, t = self.blocks[label]
        a = c.sr * tau
        E = _rodrigues(a * _log(Rs)) if c.interp == "axis-angle" else \
            np.eye(3) + a * (Rs - np.eye(3))
        if c.frame == "camera":
            return E @ cam.R, cam.C + c.st * tau * self.scale * (t @ cam.R)
        Ec = self.Q @ E @ self.Q.T                     # the rotation in model axes
        return cam.R @ Ec.T, cam.C + c.st * tau * self.scale * (self.Q @ t)

    def row(self, c: Optional[Convention], x, y, v):
        if c is None or c.row == "sensor":
            return v
        return self.cal.project_normalised(np.array([x]), np.array([y]), False)[1][0]

    def project(self, c, label: str, X: np.ndarray) -> np.ndarray:
        tau = 0.0
        for _ in range(60):                            # fixed point: contraction ≈ 0.03
            R, C = self.pose(c, label, tau)
            xc = R @ (X - C)
            x, y = xc[0] / xc[2], xc[1] / xc[2]
            u, v = (a[0] for a in self.cal.project_normalised(np.array([x]), np.array([y])))
            new = self.tau(c, self.row(c, x, y, v)) if c is not None else 0.0
            if abs(new - tau) * self.h < 1e-9:
                break
            tau = new
        return np.array([u, v])

    def ray(self, c, label: str, uv) -> Tuple[np.ndarray, np.ndarray]:
        x, y = (a[0] for a in self.cal.pixel_to_normalised(np.array([uv[0]]), np.array([uv[1]])))
        tau = self.tau(c, self.row(c, x, y, uv[1])) if c is not None else 0.0
        R, C = self.pose(c, label, tau)
        d = R.T @ np.array([x, y, 1.0])
        return C, d / np.linalg.norm(d)


def residuals(p: Project, c: Optional[Convention]) -> Tuple[np.ndarray, Dict[str, np.ndarray]]:
    """Pixel residuals of every observation of the markers seen twice or more, and the
    triangulated marker positions (model frame)."""
    res, where = [], {}
    for m in p.recon.markers:
        obs = {k: np.asarray(v) for k, v in m.observations.items() if p.recon.camera(k).aligned}
        if len(obs) < 2:
            continue
        A, b = np.zeros((3, 3)), np.zeros(3)
        for lab, uv in obs.items():
            o, d = p.ray(c, lab, uv)
            P = np.eye(3) - np.outer(d, d)
            A, b = A + P, b + P @ o
        X = np.linalg.solve(A, b)

        def r(X):
            return np.concatenate([p.project(c, lab, X) - uv for lab, uv in obs.items()])
        for _ in range(5):                             # Gauss-Newton on the reprojection error
            r0 = r(X)
            J = np.column_stack([(r(X + 1e-6 * e) - r0) / 1e-6 for e in np.eye(3)])
            X = X + np.linalg.lstsq(J, -r0, rcond=None)[0]
        res.append(np.hypot(*r(X).reshape(-1, 2).T))
        where[m.label] = X
    return np.concatenate(res), where


def table(psx: Path = GOYA, candidates=CANDIDATES, out=sys.stdout) -> List[dict]:
    p = Project(psx)
    rows = []
    print(f"{'convention':48s} {'median':>7s} {'max':>7s} {'rms':>7s}   n  90–92 (m)", file=out)
    for c in candidates:
        r, where = residuals(p, c)
        bar = np.linalg.norm(where["target 90"] - where["target 92"]) \
            if {"target 90", "target 92"} <= set(where) else float("nan")
        name = "none (one pose per photo)" if c is None else c.name
        rows.append({"name": name, "median": float(np.median(r)), "max": float(r.max()),
                     "rms": float(np.sqrt(np.mean(r * r))), "n": len(r), "bar": float(bar)})
        print(f"{name:48s} {np.median(r):7.3f} {r.max():7.3f} {rows[-1]['rms']:7.3f} "
              f"{len(r):4d}  {bar:.4f}", file=out, flush=True)
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("project", nargs="?", default=str(GOYA))
    a = ap.parse_args(argv)
    table(Path(a.project))
    return 0


if __name__ == "__main__":
    sys.exit(main())
