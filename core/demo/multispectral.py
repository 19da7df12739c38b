"""The demo survey's multispectral camera: MicaSense-style band files of the demo flight,
digital numbers under known light.

A two-band camera (Red, NIR: MicaSense RedEdge band files ``IMG_kkkk_3.tif`` and ``_4.tif``)
rides with the RGB camera of the demo flight: each capture is taken at an RGB photo's pose
through the same lens (the demo rig has no offsets between its cameras). What the camera sees
is given in reflectance by a closed-form spectral model of the rendered scene (:func:`true_reflectance`:
soil is brighter in red, green canopy bright in near infrared), so the truth of every pixel is
known. The light drifts over the flight (a passing cloud: the irradiance falls by up to 35 % and
differently per band), and each band sets its own exposure and gain per capture (auto-exposure),
as real cameras do, so the stored digital numbers are neither comparable between bands nor
between photos. The digital numbers are written through the inverse of MicaSense's radiometric
model (dark level, vignetting, row gradient, gain, exposure; see ``core/radiometry/micasense.py``
for the forward model) with sensor noise and a few saturated glints, and the DLS 2 tags carry the irradiance of each
capture. Written here independently of the product's reader: the inverse below is its own code.

:func:`write_multispectral_project` writes a Pix4D project in which every band file is its own
camera (calibrated camera parameters: each band at its capture's pose), so that *Plot statistics
from photos* measures the band files as they come from a rig. :func:`plot_reflectance_truth` is
the truth a plot's reflectance is checked against: the demo's reflectance field (the spectral
model of the RGB photo each capture rides with) averaged over the pixels whose centre is inside
the plot's outline, projected by the generator's own camera model (``flight.project_still``) and
rasterised here by an even-odd test: not the product's back-projection or reader.
"""
import dataclasses
import functools
import io
import math
import os
from typing import Dict, List, Tuple

import numpy as np

from ..files import write_bytes
from ..photos import read_photo
from .field import FieldMess, plot_corners
from .flight import make_camera, plan_flight, project_still
from .pix4d_writer import write_pix4d
from .scene import make_scene

__all__ = ["BANDS", "write_multispectral_flight", "true_reflectance", "capture_light",
           "band_file", "write_multispectral_project", "plot_reflectance_truth", "ndvi"]

BANDS = {"Red": 3, "NIR": 4}                        # MicaSense RedEdge band index per band
CALIBRATION = {"Red": (2.3e-4, 1.4e-7, 2.2e-5), "NIR": (3.2e-4, 0.9e-7, 1.6e-5)}   # a1, a2, a3
VIGNETTING = [1.1e-4, -2.6e-6, 1.6e-8, -6.0e-11, 1.0e-13, -6.0e-17]
BLACK_LEVEL = 4800
CLEAR_SKY = {"Red": 1.25, "NIR": 0.95}             # W/m²/nm, horizontal, at the flight's start
NOISE_DN = 6.0                                     # sensor noise, digital numbers (σ)
GLINTS = 40                                        # saturated 3×3 patches per band file
TARGET_DN = 15000                                  # auto-exposure aims the scene mean here
EXPOSURES = (0.0005, 0.0008, 0.001, 0.0013, 0.0016, 0.002)
GAINS = (1, 2, 4)


def band_file(index: int, band: str) -> str:
    """The MicaSense file name of ``band`` in capture ``index`` (0-based)."""
    return f"IMG_{index:04d}_{BANDS[band]}.tif"


def true_reflectance(rgb: np.ndarray) -> Dict[str, np.ndarray]:
    """The demo's spectral model: per band, the reflectance (float32) of what an RGB photo of the
    demo field shows, from its linearised colour. Green canopy: red ≈ 0.04, NIR ≈ 0.45; soil:
    red ≈ 0.15, NIR ≈ 0.25; shadows darker in both."""
    lin = (np.asarray(rgb, np.float32)[..., :3] / 255.0) ** 2.2
    r, g, b = lin[..., 0], lin[..., 1], lin[..., 2]
    green_excess = np.clip(g - 0.5 * (r + b), 0.0, None)
    red = 0.015 + 0.6 * r
    nir = np.clip(0.06 + 0.9 * (r + g + b) / 3.0 + 4.0 * green_excess, 0.0, 0.8)
    return {"Red": red.astype(np.float32), "NIR": nir.astype(np.float32)}


def capture_light(index: int, count: int) -> Dict[str, float]:
    """Horizontal irradiance (W/m²/nm) per band at capture ``index`` of ``count``: a cloud passes
    over the middle of the flight (red dims more than NIR)."""
    t = index / max(count - 1, 1)
    shade = math.exp(-((t - 0.55) / 0.18) ** 2)
    return {"Red": CLEAR_SKY["Red"] * (1 - 0.35 * shade), "NIR": CLEAR_SKY["NIR"] * (1 - 0.22 * shade)}


def _settings(radiance_mean: float, band: str, index: int) -> Tuple[float, int]:
    """Auto-exposure: of the three (exposure s, gain) pairs that bring the mean closest to
    TARGET_DN, the one this capture's hunting lands on."""
    a1 = CALIBRATION[band][0]
    pairs = [(e, g) for e in EXPOSURES for g in GAINS]
    pairs.sort(key=lambda p: abs(radiance_mean * p[0] * p[1] / a1 * 65536.0 + BLACK_LEVEL - TARGET_DN))
    return pairs[(index + 2 * (band == "NIR")) % 3]


def _digital_numbers(radiance: np.ndarray, band: str, exposure: float, gain: int, rng) -> np.ndarray:
    """The inverse of MicaSense's model: DN = L·g·tₑ/a1·2¹⁶·P(r)/R(y) + dark level, with noise."""
    a1, a2, a3 = CALIBRATION[band]
    rows, cols = radiance.shape
    cx, cy = cols / 2 + 7.5, rows / 2 - 4.0
    y, x = np.mgrid[0:rows, 0:cols].astype(np.float64)
    r = np.hypot(x - cx, y - cy)
    poly = 1.0 + sum(k * r ** (i + 1) for i, k in enumerate(VIGNETTING))
    row_gradient = 1.0 / (1.0 + a2 * y / exposure - a3 * y)
    dn = radiance * gain * exposure / a1 * 65536.0 * poly / row_gradient + BLACK_LEVEL
    dn += rng.normal(0.0, NOISE_DN, dn.shape)
    for _ in range(GLINTS):                        # specular glints: saturated 3×3 patches
        r0, c0 = rng.integers(0, rows - 3), rng.integers(0, cols - 3)
        dn[r0:r0 + 3, c0:c0 + 3] = 65535
    return np.clip(np.round(dn), 0, 65535).astype(np.uint16), (cx, cy)


def _xmp(band: str, index: int, centre, irradiance: float) -> bytes:
    cal = "".join(f"<rdf:li>{v!r}</rdf:li>" for v in CALIBRATION[band])
    vig = "".join(f"<rdf:li>{v!r}</rdf:li>" for v in VIGNETTING)
    ctr = "".join(f"<rdf:li>{v!r}</rdf:li>" for v in centre)
    return ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
            'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description rdf:about="" '
            'xmlns:Camera="http://pix4d.com/camera/1.0/" xmlns:DLS="http://micasense.com/DLS/1.0/" '
            'xmlns:MicaCamera="http://micasense.com/MicaCamera/1.0/" '
            f'MicaCamera:CaptureId="demo-capture-{index:04d}" Camera:RigCameraIndex="{BANDS[band] - 1}" '
            f'DLS:HorizontalIrradiance="{irradiance * 100:.4f}" DLS:IrradianceScaleToSIUnits="0.01">'
            f'<Camera:BandName>{band}</Camera:BandName>'
            f'<Camera:RadiometricCalibration><rdf:Seq>{cal}</rdf:Seq></Camera:RadiometricCalibration>'
            f'<Camera:VignettingCenter><rdf:Seq>{ctr}</rdf:Seq></Camera:VignettingCenter>'
            f'<Camera:VignettingPolynomial><rdf:Seq>{vig}</rdf:Seq></Camera:VignettingPolynomial>'
            '</rdf:Description></rdf:RDF></x:xmpmeta>').encode("utf-8")


def write_multispectral_flight(photos: List[str], folder, *, seed: int = 0) -> List[dict]:
    """Write the band files of one capture per RGB photo (same order) into ``folder``.

    Returns per capture: ``photo`` (the RGB photo it rides with), ``files`` {band: path},
    ``irradiance`` {band: W/m²/nm}, ``exposure`` {band: s}, ``gain`` {band: ×}."""
    import tifffile
    rng = np.random.default_rng(seed + 34)
    os.makedirs(folder, exist_ok=True)
    captures = []
    for k, photo in enumerate(photos):
        truth = true_reflectance(read_photo(photo))
        light = capture_light(k, len(photos))
        record = {"photo": photo, "files": {}, "irradiance": light, "exposure": {}, "gain": {}}
        for band in BANDS:
            radiance = truth[band].astype(np.float64) * light[band] / math.pi
            exposure, gain = _settings(float(radiance.mean()), band, k)
            dn, centre = _digital_numbers(radiance, band, exposure, gain, rng)
            path = os.path.join(os.fspath(folder), band_file(k, band))
            stamp = f"2024:06:01 02:{10 + k // 30:02d}:{(2 * k) % 60:02d}"
            buffer = io.BytesIO()
            tifffile.imwrite(buffer, dn, photometric="minisblack", software="v6.2.1", extratags=[
                (271, "s", 0, "MicaSense", True), (272, "s", 0, "RedEdge-MX", True),
                (700, "B", 0, _xmp(band, k, centre, light[band]), True),
                (50714, "H", 4, (BLACK_LEVEL,) * 4, True),
                (33434, "2I", 1, (int(round(exposure * 1e6)), 1000000), True),
                (34867, "I", 1, gain * 100, True),
                (36867, "s", 0, stamp, True)])
            write_bytes(path, buffer.getvalue())
            record["files"][band] = path
            record["exposure"][band] = exposure
            record["gain"][band] = gain
        captures.append(record)
    return captures


@functools.lru_cache(maxsize=1)
def _shots(seed: int, size: str, mess):
    """(scene, camera, {file name: shot}) of the demo survey (the scene is made once per run)."""
    scene = make_scene(seed, mess=FieldMess() if mess is None else mess)
    camera = make_camera(size)
    shots = plan_flight(scene, np.random.default_rng([seed, 1]))
    return scene, camera, {os.path.basename(sh.filename): sh for sh in shots}


def write_multispectral_project(folder, captures: List[dict], *, seed: int = 0,
                                size: str = "small", mess=None) -> str:
    """Write ``folder/multispectral.p4d`` and its params: one camera per band file of
    ``captures`` (:func:`write_multispectral_flight`), at the pose of the RGB photo its capture
    rides with; the survey must have been made with the same ``seed``, ``size`` and ``mess``.
    Returns the .p4d path."""
    scene, camera, shots = _shots(seed, size, mess)
    band_shots, paths = [], []
    for rec in captures:
        shot = shots[os.path.basename(rec["photo"])]
        for path in rec["files"].values():
            band_shots.append(dataclasses.replace(shot, filename=os.path.basename(path),
                                                  label=os.path.splitext(os.path.basename(path))[0]))
            paths.append(path)
    return write_pix4d(folder, "multispectral", camera, band_shots, scene.offset, paths)["p4d"]


def _inside(poly: np.ndarray, shape) -> Tuple[int, int, np.ndarray]:
    """(r0, c0, mask): the pixel centres inside the closed polygon ``poly`` (n, 2) pixels, by
    the even-odd rule over its bounding box."""
    rows, cols = shape
    c0, r0 = (max(int(np.floor(v)), 0) for v in poly.min(axis=0))
    c1, r1 = min(int(np.ceil(poly[:, 0].max())), cols), min(int(np.ceil(poly[:, 1].max())), rows)
    y, x = np.mgrid[r0:max(r1, r0), c0:max(c1, c0)] + 0.5
    inside = np.zeros(x.shape, bool)
    for (xa, ya), (xb, yb) in zip(poly, np.roll(poly, -1, axis=0)):
        if ya == yb:
            continue
        cross = ((ya > y) != (yb > y)) & (x < xa + (y - ya) * (xb - xa) / (yb - ya))
        inside ^= cross
    return r0, c0, inside


def plot_reflectance_truth(captures: List[dict], height: float, *, seed: int = 0,
                           size: str = "small", mess=None, step: float = 0.05,
                           project=None, keys=None) -> Dict[tuple, dict]:
    """{(plot id, capture name ``IMG_kkkk``): {band: mean reflectance}} of every plot a capture
    sees whole: the demo's reflectance field under the plot outline at ``height`` (map
    vertical), edges sampled every ``step`` m and projected into the RGB photo the capture rides
    with by ``project(photo label, map xyz (n, 3)) → pixels (n, 2)`` (default: the generator's
    camera model at the true pose, ``flight.project_still``); ``keys``: only these (plot id,
    capture name) pairs (None: all)."""
    scene, camera, shots = _shots(seed, size, mess)
    if project is None:
        def project(label, xyz):
            shot = next(sh for sh in shots.values() if sh.label == label)
            return project_still(camera, [shot], xyz - scene.offset)[0][0]
    out = {}
    for rec in captures:
        shot = shots[os.path.basename(rec["photo"])]
        name = os.path.basename(rec["files"]["Red"]).rsplit("_", 1)[0]
        plots = [p for p in scene.plots if keys is None or (p["plot_id"], name) in keys]
        if not plots:
            continue
        truth = true_reflectance(read_photo(rec["photo"]))
        for p in plots:
            corners = plot_corners(p)
            ring = []
            for a, b in zip(corners, np.roll(corners, -1, axis=0)):
                n = max(int(np.ceil(np.hypot(*(b - a)) / step)), 1)
                ring += [a + (b - a) * t for t in np.arange(n) / n]
            xyz = np.column_stack([np.array(ring), np.full(len(ring), height)])
            px = np.asarray(project(shot.label, xyz), float)
            if not np.all(np.isfinite(px)) or px[:, 0].min() < 0 or px[:, 1].min() < 0 or \
                    px[:, 0].max() > camera.width or px[:, 1].max() > camera.height:
                continue
            r0, c0, mask = _inside(px, (camera.height, camera.width))
            if mask.sum() < 50:
                continue
            rows, cols = slice(r0, r0 + mask.shape[0]), slice(c0, c0 + mask.shape[1])
            out[(p["plot_id"], name)] = {b: float(truth[b][rows, cols][mask].mean()) for b in BANDS}
    return out


def ndvi(reflectance: Dict[str, float]) -> float:
    """NDVI of a plot's mean reflectance per band."""
    return (reflectance["NIR"] - reflectance["Red"]) / (reflectance["NIR"] + reflectance["Red"])
