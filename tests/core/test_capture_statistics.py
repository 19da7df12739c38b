"""Plot statistics from the band files of multispectral captures (core/projection/capture_stats.py):
one view per ROI × capture, each band measured through its own camera.

Truth kind [independent]: a flat field with two plots of known, uniform reflectance per band;
each band file is rendered by the test's own pinhole ray casting (ray–plane intersection written
here) from its own band camera, whose pose differs from the other band's (a rig whose lenses
look at the ROI from other pixels), and stored as MicaSense digital numbers by the test's second
writing of MicaSense's model (``test_multispectral.micasense_raw_from_radiance``). The truth of
each plot is the chosen reflectance, so NDVI per plot is known exactly. Measuring the NIR band
through the Red band's polygon (mis-registered pixels) puts the background into the NIR mean and
fails the test.
"""
import math
from pathlib import Path

import numpy as np
import pytest
from pyproj import CRS

from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.projection import back_project, photo_statistics
from easyidp_toolbox.core.reconstruction import Calibration, Camera, Reconstruction, Sensor
from easyidp_toolbox.core.reconstruction.geodesy import OffsetFrame
from easyidp_toolbox.core.roi import ROI, ROISet
from easyidp_toolbox.tests.core.test_multispectral import micasense_raw_from_radiance, write_micasense

UTM = CRS.from_epsg(32654)
OFFSET = np.array([368000.0, 3956000.0, 0.0])
W, H = 320, 240
IRRADIANCE = {"Red": 1.2, "NIR": 0.9}                       # W/m²/nm
# (plot ring in model metres, reflectance per band); the background between them
PLOTS = {"A": ([(-7, -3), (-1, -3), (-1, 3), (-7, 3)], {"Red": 0.05, "NIR": 0.50}),
         "B": ([(1, -3), (7, -3), (7, 3), (1, 3)], {"Red": 0.20, "NIR": 0.25})}
BACKGROUND = {"Red": 0.12, "NIR": 0.32}
# per band: its lens (f, cx, cy); per capture and band: the camera centre and yaw (degrees)
LENS = {"Red": (260.0, 161.3, 118.2), "NIR": (255.0, 157.9, 121.6)}
RIG = [{"Red": ((0.0, 0.0, 30.0), 0.0), "NIR": ((1.6, 0.9, 30.0), 4.0)},
       {"Red": ((1.0, -1.0, 32.0), 10.0), "NIR": ((2.7, -0.2, 32.1), 13.0)}]


def _nadir(yaw_deg):
    """World → camera rotation of a nadir camera turned by ``yaw_deg`` about the vertical."""
    a = math.radians(yaw_deg)
    turn = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    return np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]]) @ turn.T


def _render(band, R, C):
    """The band's reflectance seen at every pixel centre: the test's own ray–plane casting."""
    f, cx, cy = LENS[band]
    v, u = np.mgrid[0:H, 0:W] + 0.5
    d = np.stack([(u - cx) / f, (v - cy) / f, np.ones_like(u)], -1) @ R      # camera → world
    t = -C[2] / d[..., 2]
    x, y = C[0] + t * d[..., 0], C[1] + t * d[..., 1]
    out = np.full((H, W), BACKGROUND[band])
    for ring, refl in PLOTS.values():
        xs, ys = [p[0] for p in ring], [p[1] for p in ring]
        out[(x > min(xs)) & (x < max(xs)) & (y > min(ys)) & (y < max(ys))] = refl[band]
    return out


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    """Two captures of a Red/NIR rig, each band its own camera, written as MicaSense files."""
    folder = tmp_path_factory.mktemp("rig")
    sensors = {b: Sensor(b, f"{b} lens", W, H, Calibration(f=f, cx=cx, cy=cy))
               for b, (f, cx, cy) in LENS.items()}
    cameras = []
    for k, capture in enumerate(RIG):
        for n, (band, (C, yaw)) in enumerate(capture.items()):
            R, C = _nadir(yaw), np.asarray(C, float)
            exposure, gain = (0.001, 2.0) if band == "Red" else (0.0004, 1.0)     # per-band AE
            raw = micasense_raw_from_radiance(_render(band, R, C) * IRRADIANCE[band] / math.pi,
                                              exposure, gain)
            name = f"IMG_000{k}_{3 + n}"
            write_micasense(folder / f"{name}.tif", raw, band=band, exposure=exposure,
                            iso=int(gain * 100), horizontal=IRRADIANCE[band] * 100,
                            extra={"MicaCamera:CaptureId": f"capture{k}"})
            cameras.append(Camera(name, name, band, photo_path=str(folder / f"{name}.tif"),
                                  R=R, C=C))
    recon = Reconstruction(Path("rig"), "synthetic", "rig", UTM, OffsetFrame(UTM, OFFSET), sensors,
                           cameras)
    rois = ROISet([ROI(name, [[np.asarray(ring, float) + OFFSET[:2]]])
                   for name, (ring, _) in PLOTS.items()], UTM)
    return recon, rois, back_project(rois, recon, heights=0.0, distortion=False)


def _ndvi(refl):
    return (refl["NIR"] - refl["Red"]) / (refl["NIR"] + refl["Red"])


def test_one_view_per_roi_and_capture_each_band_through_its_own_camera(rig):
    """[independent] one row per ROI × capture with red_refl_*, nir_refl_* and ndvi_* columns;
    every band's mean is its plot's reflectance (its own camera's polygon: no background
    pixel), and NDVI per plot equals the truth's within 0.002, in every view and across views."""
    recon, rois, bp = rig
    assert len(bp) == 8                                   # 2 plots × 2 captures × 2 bands
    st = photo_statistics(bp, recon=recon, rois=rois, values="reflectance",
                          statistics=("mean", "median", "std"), percentiles=(5,))
    assert len(st.record) == 4 and sorted(st.photo) == ["IMG_0000", "IMG_0000", "IMG_0001",
                                                        "IMG_0001"]
    assert st.bands == ["red", "nir"] and st.indices == ["ndvi"]
    assert "red_refl_mean" in st.columns and "nir_refl_p5" in st.columns
    assert "ndvi_mean" in st.columns and "ndvi_median" in st.columns and "cover" not in st.columns
    for v in range(4):
        name = st.roi_names[int(st.roi[v])]
        truth = PLOTS[name][1]
        assert st.used[v] and st.pixels[v] > 500
        assert abs(st.column("red_refl_mean")[v] - truth["Red"]) < 0.002
        assert abs(st.column("nir_refl_mean")[v] - truth["NIR"]) < 0.002
        assert st.column("nir_refl_std")[v] < 0.003             # no background pixel
        assert abs(st.column("ndvi_mean")[v] - _ndvi(truth)) < 0.002
        assert st.acquired[v].startswith("2024-06-01T02:30:00")
    for r, name in enumerate(st.roi_names):
        assert st.views[r] == 2
        assert abs(st.roi_value("ndvi_median")[r] - _ndvi(PLOTS[name][1])) < 0.002
    assert sorted(st.rank.tolist()) == [1, 1, 2, 2]
    assert any("multispectral capture" in n for n in st.notes)


def test_stored_band_files_are_named_by_their_band_tags(rig):
    """[independent] as stored, the band files keep their digital numbers under the tag's band
    name (red_mean, nir_mean), one view per capture; the NDVI of those numbers is off the truth
    (per-band gain and exposure), which is why reflectance is asked for."""
    recon, rois, bp = rig
    st = photo_statistics(bp, values="stored", statistics=("mean",))
    assert st.columns == ["red_mean", "nir_mean", "ndvi_mean"] and len(st.record) == 4
    a = st.roi_names.index("A")
    assert abs(st.roi_value("ndvi_mean")[a] - _ndvi(PLOTS["A"][1])) > 0.05


def test_a_capture_missing_a_band_is_not_used_and_a_band_twice_is_refused(rig, tmp_path):
    """[independent] a capture whose NIR file is gone keeps its row, unused, saying which band
    is missing; two files of one band in one capture are refused, naming both."""
    recon, rois, bp = rig
    import shutil
    folder = tmp_path / "photos"
    shutil.copytree(Path(bp.photo_paths[0]).parent, folder)
    (folder / "IMG_0001_4.tif").unlink()
    st = photo_statistics(bp, folder, values="reflectance", statistics=("mean",))
    late = [v for v in range(len(st.record)) if st.photo[v] == "IMG_0001"]
    assert late and all(not st.used[v] and "no nir view" in st.why[v] for v in late)
    assert all(st.used[v] for v in range(len(st.record)) if st.photo[v] == "IMG_0000")
    shutil.copy(folder / "IMG_0000_4.tif", folder / "IMG_0001_4.tif")   # capture0's NIR twice
    with pytest.raises(InputError, match=r"band 'NIR' of capture capture0 is also in"):
        photo_statistics(bp, folder, values="reflectance", statistics=("mean",))


def test_pix4d_band_file_without_a_calibrated_pose_is_refused_with_what_to_do(rig, tmp_path):
    """[independent] a Pix4D project of the rig (written by the demo's Pix4D writer from the
    rig's poses) whose params folder lacks one band file's calibration (Pix4D disabled it):
    Pix4D writes no rig relatives into its params folder, so that band file is kept unaligned
    and a note names the project and what to do; the calibrated band files are placed by their
    own poses (the same pixels as the rig's cameras), and Plot statistics keeps that capture's
    row unused, saying which band is missing."""
    from easyidp_toolbox.core.demo.flight import CameraModel, Shot
    from easyidp_toolbox.core.demo.pix4d_writer import write_pix4d
    from easyidp_toolbox.core.reconstruction import open_reconstruction
    recon, rois, bp = rig
    f, cx, cy = LENS["Red"]
    model = CameraModel(label="rig", model="rig", width=W, height=H, pixel_mm=0.003,
                        calibration=Calibration(f=f, cx=cx, cy=cy))
    cams = [c for c in recon.cameras if c.sensor_id == "Red"] + \
        [c for c in recon.cameras if c.sensor_id == "NIR"]
    shots = [Shot(label=c.label, filename=Path(c.photo_path).name, R=c.R, C=c.C, line=0,
                  yaw_deg=0.0, gps=c.C + OFFSET, time="2024:06:01 02:30:00") for c in cams]
    p4d = Path(write_pix4d(tmp_path, "rig", model, shots, OFFSET, [c.photo_path for c in cams])["p4d"])
    params = tmp_path / "rig" / "1_initial" / "params"
    ccp = params / "rig_calibrated_camera_parameters.txt"
    text = ccp.read_text().split("IMG_0001_4.tif")[0]          # the last image's block dropped
    ccp.write_text(text)
    pm = params / "rig_pmatrix.txt"
    pm.write_text("".join(line for line in pm.read_text().splitlines(True)
                          if not line.startswith("IMG_0001_4")))
    p4 = open_reconstruction(p4d)
    aligned = {c.label: c.aligned for c in p4.cameras}
    assert aligned["IMG_0001_4.tif"] is False and sum(aligned.values()) == 3
    note = next(n for n in p4.notes if "no calibrated pose" in n)
    assert str(p4d) in note and "IMG_0001_4.tif" in note and "no rig relatives" in note
    assert "enable them in Pix4Dmapper" in note and "Metashape" in note
    red = p4.project_points(np.array([[OFFSET[0] - 4.0, OFFSET[1], 0.0]]), UTM)
    ours = recon.project_points(np.array([[OFFSET[0] - 4.0, OFFSET[1], 0.0]]), UTM)
    assert np.abs(red.pixels[0] - ours.pixels[0]).max() < 1e-6
    st = photo_statistics(back_project(rois, p4, heights=0.0, distortion=False),
                          values="reflectance", statistics=("mean",))
    late = [v for v in range(len(st.record)) if st.photo[v] == "IMG_0001"]
    assert late and all(not st.used[v] and "no nir view" in st.why[v] for v in late)
