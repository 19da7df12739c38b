"""The flight as an Open Photogrammetry Format project (what PIX4Dmatic exports): ``project.opf``.

Written with the standard library, file by file as the OPF 1.0 specification lays them out
(https://pix4d.github.io/opf-spec), so that the reader (pyopf, :mod:`core.reconstruction.opf`)
is checked against files it did not write::

    opf/project.opf                  the item catalogue (camera_list, input_cameras,
                                     scene_reference_frame, calibration)
    opf/camera_list.json             camera ids and image URIs (relative: ../photos/DJI_0001.JPG)
    opf/input_cameras.json           the sensor (size, pixel size) and one capture per photo
    opf/scene_reference_frame.json   EPSG:32654; base → canonical: shift = −offset, scale 1
    opf/calibrated_cameras.json      positions (map − offset) and omega/phi/kappa, the sensor

Conventions (those :mod:`core.reconstruction.opf` reads): ``orientation_deg`` (ω, φ, κ) with
R_x(ω)R_y(φ)R_z(κ) = Rᵀ·diag(1, −1, −1) (image right-top-back → processing CRS); the principal
point from the image's top-left corner, as ours; tangential T1 = our p2, T2 = our p1.

OPF's perspective camera has one focal length, so Metashape's affinity b1 of the demo camera is
not written: the OPF project's pixels are u = cx + x'·f (the truth's are cx + x'·(f + b1)), at
most |b1|·max|x'| apart (0.4 px on the small survey). The tests map the truth through that
difference exactly.
"""
import json
import os
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np

from ..files import write_bytes
from .flight import CameraModel, Shot

SENSOR_ID = 1001
FORMAT = "application/opf-{}+json"
ITEM_IDS = {"camera_list": "3e2a4a1c-0c53-4d3b-9a0e-6a3f8f0c1001",
            "input_cameras": "3e2a4a1c-0c53-4d3b-9a0e-6a3f8f0c1002",
            "scene_reference_frame": "3e2a4a1c-0c53-4d3b-9a0e-6a3f8f0c1003",
            "calibration": "3e2a4a1c-0c53-4d3b-9a0e-6a3f8f0c1004"}
PROJECT_ID = "3e2a4a1c-0c53-4d3b-9a0e-6a3f8f0c1000"


def opk_degrees(R: np.ndarray) -> np.ndarray:
    """(ω, φ, κ) in degrees of our world → camera rotation ``R`` (x right, y down, z forward):
    the angles of M = Rᵀ·diag(1, −1, −1) = R_x(ω)R_y(φ)R_z(κ) (|φ| < 90°)."""
    M = R.T @ np.diag([1.0, -1.0, -1.0])
    phi = np.arcsin(np.clip(M[0, 2], -1.0, 1.0))
    omega = np.arctan2(-M[1, 2], M[2, 2])
    kappa = np.arctan2(-M[0, 1], M[0, 0])
    return np.degrees([omega, phi, kappa])


def _perspective(camera: CameraModel) -> dict:
    c = camera.calibration
    return {"type": "perspective", "principal_point_px": [c.cx, c.cy], "focal_length_px": c.f,
            "radial_distortion": [c.k1, c.k2, c.k3], "tangential_distortion": [c.p2, c.p1]}


def _item(kind: str, uri: str, sources: Sequence[str], fmt: str = "") -> dict:
    return {"id": ITEM_IDS[kind], "type": kind, "name": kind,
            "resources": [{"uri": uri, "format": FORMAT.format(fmt or kind.replace("_", "-"))}],
            "sources": [{"id": ITEM_IDS[s], "type": s} for s in sources]}


def write_opf(folder, camera: CameraModel, shots: List[Shot], offset: np.ndarray,
              photo_paths: Sequence[str], epsg: int) -> Dict[str, str]:
    """Write ``folder/project.opf`` and its four JSON resources. Poses are in the local frame
    (map − ``offset``, metres); ``photo_paths`` absolute (written relative to ``folder``)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    ids = [1 + i for i in range(len(shots))]
    rel = [Path(os.path.relpath(os.path.abspath(p), folder.resolve())).as_posix() for p in photo_paths]
    docs = {
        "camera_list.json": {
            "format": FORMAT.format("camera-list"), "version": "1.0",
            "cameras": [{"id": i, "uri": u} for i, u in zip(ids, rel)]},
        "input_cameras.json": {
            "format": FORMAT.format("input-cameras"), "version": "1.0",
            "sensors": [{"id": SENSOR_ID, "name": camera.model,
                         "bands": [{"name": "Red", "weight": 0.2126},
                                   {"name": "Green", "weight": 0.7152},
                                   {"name": "Blue", "weight": 0.0722}],
                         "image_size_px": [camera.width, camera.height],
                         "pixel_size_um": camera.pixel_mm * 1000.0,
                         "internals": _perspective(camera), "shutter_type": "global"}],
            "captures": [{"id": i, "reference_camera_id": i, "rig_model_source": "not_applicable",
                          "time": s.time.replace(":", "-", 2).replace(" ", "T"),
                          "cameras": [{"id": i, "sensor_id": SENSOR_ID, "model_source": "user",
                                       "pixel_type": "uint8", "pixel_range": {"min": 0, "max": 255},
                                       "image_orientation": 1}]}
                         for i, s in zip(ids, shots)]},
        "scene_reference_frame.json": {
            "format": FORMAT.format("scene-reference-frame"), "version": "1.0",
            "crs": {"definition": f"EPSG:{epsg}"},
            "base_to_canonical": {"shift": [-float(v) for v in offset], "scale": [1.0, 1.0, 1.0],
                                  "swap_xy": False}},
        "calibrated_cameras.json": {
            "format": FORMAT.format("calibrated-cameras"), "version": "1.0",
            "sensors": [{"id": SENSOR_ID, "internals": _perspective(camera)}],
            "cameras": [{"id": i, "sensor_id": SENSOR_ID, "position": [float(v) for v in s.C],
                         "orientation_deg": [float(v) for v in opk_degrees(s.R)]}
                        for i, s in zip(ids, shots)]},
        "project.opf": {
            "format": FORMAT.format("project"), "version": "1.0", "id": PROJECT_ID,
            "name": "demo_survey", "description": "EasyIDP demo survey",
            "generator": {"name": "EasyIDP demo", "version": "1"},
            "items": [_item("camera_list", "camera_list.json", ()),
                      _item("input_cameras", "input_cameras.json", ("camera_list",)),
                      _item("scene_reference_frame", "scene_reference_frame.json", ()),
                      _item("calibration", "calibrated_cameras.json",
                            ("input_cameras", "scene_reference_frame"), "calibrated-cameras")]},
    }
    for name, doc in docs.items():
        write_bytes(folder / name, (json.dumps(doc, indent=2) + "\n").encode())
    return {"project": str(folder / "project.opf")}
