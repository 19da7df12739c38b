"""The flight as a Pix4Dmapper project: ``name.p4d`` and ``name/1_initial/params/``.

The params folder holds the files Pix4Dmapper writes there, in their formats (compare
``realdata/easyidp/pix4d_origin``): ``offset.xyz`` (no newline), ``pmatrix.txt`` (6 decimals,
trailing space), ``calibrated_camera_parameters.txt`` (8-line header, 10-line blocks, 20
decimals), ``pix4d_calibrated_internal_camera_parameters.cam`` (F/Px/Py in mm),
``calibrated_internal_camera_parameters.cam`` (Inpho style), ``calibrated_images_position.txt``,
``camera.ssk`` and ``wkt.prj``.

Pix4D's frame is the map CRS minus ``offset.xyz`` — exactly the demo's local frame, so the
poses are written as they are. Conventions (as ``core.reconstruction.pix4d`` reads them): K's
principal point is measured from the top-left image corner like ours; distortion acts on
normalised coordinates with tangential terms in OpenCV order (T1 = our p2, T2 = our p1); the
affinity b1 and skew b2 are carried by K (K00 = f + b1, K01 = b2).
"""
import os
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np

from ..files import write_bytes
from .flight import CameraModel, Shot
from .geo import UTM54_WKT, map_to_lonlat

CCP_HEADER = ("fileName imageWidth imageHeight \ncamera matrix K [3x3]\nradial distortion [3x1]\n"
              "tangential distortion [2x1]\ncamera position t [3x1]\ncamera rotation R [3x3]\n"
              "camera model m = K [R|-Rt] X\n\n")


def _n(v) -> str:
    """Pix4D's 20-decimal numbers; whole numbers (0 and 1 of K) without decimals."""
    v = float(v)
    return str(int(v)) if v.is_integer() else f"{v:.20f}"


def _row(values) -> str:
    return " ".join(_n(v) for v in values)


def camera_matrix(camera: CameraModel) -> np.ndarray:
    c = camera.calibration
    return np.array([[c.f + c.b1, c.b2, c.cx], [0.0, c.f, c.cy], [0.0, 0.0, 1.0]])


def _ccp(camera: CameraModel, shots: List[Shot]) -> str:
    c, K = camera.calibration, camera_matrix(camera)
    blocks = [CCP_HEADER]
    for s in shots:
        blocks.append("\n".join([f"{s.filename} {camera.width} {camera.height}",
                                 *(_row(r) for r in K), _row([c.k1, c.k2, c.k3]), _row([c.p2, c.p1]),
                                 _row(s.C), *(_row(r) for r in s.R)]) + "\n")
    return "".join(blocks)


def _pmatrix(camera: CameraModel, shots: List[Shot]) -> str:
    K = camera_matrix(camera)
    lines = []
    for s in shots:
        P = K @ np.hstack([s.R, -(s.R @ s.C)[:, None]])
        lines.append(s.filename + " " + " ".join(f"{v:.6f}" for v in P.ravel()) + " \n")
    return "".join(lines)


def _cam_pix4d(camera: CameraModel) -> str:
    c, px = camera.calibration, camera.pixel_mm
    w_mm, h_mm = camera.width * px, camera.height * px
    return (f"Pix4D camera calibration file 0\n"
            f"#Focal Length mm assuming a sensor width of {w_mm:.20f}x{h_mm:.20f}mm\n"
            f"F {c.f * px:.20f}\n#Principal Point mm\nPx {c.cx * px:.20f}\nPy {c.cy * px:.20f}\n"
            f"#Symmetrical Lens Distortion Coeffs\nK1 {c.k1:.20f}\nK2 {c.k2:.20f}\nK3 {c.k3:.20f}\n"
            f"#Tangential Lens Distortion Coeffs\nT1 {c.p2:.20f}\nT2 {c.p1:.20f}\n")


def _cam_inpho(camera: CameraModel) -> str:
    c, px = camera.calibration, camera.pixel_mm
    w, h = camera.width, camera.height
    F = c.f * px
    xoff, yoff = w / 2 - c.cx, h / 2 - c.cy                  # pixels
    fid = [(w * px / 2, -h * px / 2), (-w * px / 2, -h * px / 2), (-w * px / 2, h * px / 2),
           (w * px / 2, h * px / 2)]
    return (f"camera_calibration_file 0\n"
            f"#Focal Length (mm) assuming a sensor width of {w * px:.20f}x{h * px:.20f}mm\n"
            f"#Image size {w:.20f}x{h:.20f} pixel\nFOCAL {F:.20f}\n\n"
            f"#Principal Point Offset xpoff ypoff in mm (Inpho)\nXPOFF {-xoff * px:.20f}\nYPOFF {yoff * px:.20f}\n"
            f"#Principal Point Offset xpoff ypoff in mm \nXPOFF {xoff * px:.20f}\nYPOFF {yoff * px:.20f}\n"
            f"#Principal Point Offset xpoff ypoff in pixel \nXPOFF {xoff:.20f}\nYPOFF {yoff:.20f}\n\n"
            f"#How many fiducial pairs (max 8):\nNUM_FIDS 4 \n\n#Fiducials position\nDATA_STRIP_SIDE left\n\n"
            f"#Fiducial x,y pairs in mm:\nFID_PAIRS\n"
            + "".join(f"    {a:.20f} {b:.20f}\n" for a, b in fid)
            + f"\n#Symmetrical Lens Distortion Odd-order Poly Coeffs:K0,K1,K2,K3\n"
            f"SYM_DIST 0 {c.k1 / F ** 3:.20f} {c.k2 / F ** 5:.20f} {c.k3 / F ** 7:.20f}\n\n"
            f"#Decentering Lens Coeffs p1,p2,p3\nDEC_DIST {c.p2 / F ** 2:.20f} {c.p1 / F ** 2:.20f} 0\n\n"
            f"#How many distortion pairs (max 20):\nNUM_DIST_PAIRS 20\n\n")


def _ssk(camera: CameraModel) -> str:
    c, px = camera.calibration, camera.pixel_mm
    w, h = camera.width, camera.height
    label = f"{camera.model}_{camera.focal_mm:.1f}_{w}x{h}"
    rows = [("focal_length", f"{c.f * px:.20f}"),
            ("ppac", f"{(c.cx - w / 2) * px:.20f} {(h / 2 - c.cy) * px:.20f}"),
            ("ppbs", " 0 0"), ("film_format", f"{h * px:.20f} {w * px:.20f}"),
            ("lens_distortion_flag", "off"), ("io_required", "yes"), ("camera_type", "frame"),
            ("media_type", "digital"), ("pixel_size", f"{px * 1000:.20f} {px * 1000:.20f}"),
            ("image_size_in_pixels", f"{h} {w}"), ("scanline_orientation", "4"),
            ("photo_coord_sys_orientation", "1"),
            ("photo_coord_sys_origin", f"{(h - 1) / 2:.20f} {(w - 1) / 2:.20f}"),
            ("focal_length_calibration_flag", "off"), ("calibrated_focal_length_stddev", "0.03"),
            ("ppac_calibration_flag", "off"), ("calibrated_ppac_stddevs", "0.003   0.003"),
            ("self_calibration_enabled_params", "0"), ("antenna_offsets", "0   0   0")]
    body = "".join(f"    {k + ':':<35}{v}\n" for k, v in rows)
    return f"begin camera_parameters {label} (RGB)(1)\n{body}end camera_parameters\n"


def _p4d(camera: CameraModel, shots: List[Shot], rel_paths: Sequence[str], offset) -> str:
    lla = map_to_lonlat(np.array([s.gps for s in shots]))
    images = "".join(
        f'            <image path="{p}" group="group1" enabled="true">\n'
        f'                <camera id="0"/>\n'
        f'                <gps lat="{g[1]:.12f}" lng="{g[0]:.12f}" alt="{g[2]:.3f}" xyAcc="5" zAcc="10"/>\n'
        f'            </image>\n' for p, g in zip(rel_paths, lla))
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<pix4dmapper>\n'
            f'    <software>\n        <projectVersion>4.5.6</projectVersion>\n'
            f'        <p4dVersion>22</p4dVersion>\n    </software>\n'
            f'    <options>\n        <loadTemplate>3d-maps</loadTemplate>\n    </options>\n'
            f'    <inputs>\n        <coordinateSystems>\n'
            f'            <output wkt=\'{UTM54_WKT}\'/>\n        </coordinateSystems>\n'
            f'        <cameras>\n            <camera id="0" name="{camera.model}" '
            f'width="{camera.width}" height="{camera.height}"/>\n        </cameras>\n'
            f'        <images>\n{images}        </images>\n    </inputs>\n</pix4dmapper>\n')


def write_pix4d(folder, name: str, camera: CameraModel, shots: List[Shot], offset: np.ndarray,
                photo_paths: Sequence[str]) -> Dict[str, str]:
    """Write ``folder/name.p4d`` and ``folder/name/1_initial/params/name_*``. Poses are in the
    local frame (map − ``offset``); ``photo_paths`` absolute (written relative to the .p4d)."""
    folder = Path(folder)
    params = folder / name / "1_initial" / "params"
    params.mkdir(parents=True, exist_ok=True)
    off = offset
    files = {
        "offset.xyz": f"{off[0]:.3f} {off[1]:.3f} {off[2]:.3f}",
        "pmatrix.txt": _pmatrix(camera, shots),
        "calibrated_camera_parameters.txt": _ccp(camera, shots),
        "pix4d_calibrated_internal_camera_parameters.cam": _cam_pix4d(camera),
        "calibrated_internal_camera_parameters.cam": _cam_inpho(camera),
        "calibrated_images_position.txt": "".join(
            f"{s.filename},{s.C[0] + off[0]:.6f},{s.C[1] + off[1]:.6f},{s.C[2] + off[2]:.6f}\n"
            for s in shots),
        "camera.ssk": _ssk(camera),
        "wkt.prj": UTM54_WKT,
    }
    for suffix, text in files.items():
        write_bytes(params / f"{name}_{suffix}", text.encode())
    rel = [Path(os.path.relpath(os.path.abspath(p), folder.resolve())).as_posix() for p in photo_paths]
    p4d = folder / f"{name}.p4d"
    write_bytes(p4d, _p4d(camera, shots, rel, off).encode())
    return {"p4d": str(p4d), "params": str(params)}
