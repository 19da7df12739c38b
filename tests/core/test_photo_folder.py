"""Cameras from the photos' own tags (EXIF and XMP), without a photogrammetry project (issue 28).

On the real OpenDroneMap survey (realdata/orthority_odm: 4 DJI FC6310R photos, RTK fixed,
GDAL-written TIFFs at ¼ size with EXIF in GDAL's metadata and XMP in tag 700) against three
independent sources: GDAL's own reading of the tags, the cameras OpenDroneMap solved for the
same flight (reconstruction.json read by OpenCV, tests/support/real_survey.py), and Orthority
0.7.0's EXIF reader (``oty exif --export-params``, its own environment). Bad input on small
JPEGs written here with Pillow. Run with -s to see the figures.
"""
import json
import os
import subprocess

import numpy as np
import pytest
import shapely
from PIL import Image

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.photos import DJI, XMP_NS, read_photo_tags
from easyidp_toolbox.core.projection import back_project, camera_footprints
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.core.reconstruction import open_photos
from easyidp_toolbox.tests.support import real_survey as rs


@pytest.fixture(scope="module")
def odm(realdata):
    return realdata / "orthority_odm"


@pytest.fixture(scope="module")
def tagged(odm):
    return open_reconstruction(odm / "images")


@pytest.fixture(scope="module")
def solved(odm):
    return open_reconstruction(odm)


# --- reading the tags ---------------------------------------------------------------------------
@pytest.mark.gdal
def test_gdal_tiff_tags_as_gdal_reads_them(odm):
    """[independent] GDAL's own reader: every EXIF_* item and the xml:XMP domain GDAL reports
    for the GDAL-written TIFFs are what read_photo_tags finds (tag 42112 and tag 700 with its
    ``xml:XMP=`` prefix, which Pillow does not see)."""
    from osgeo import gdal
    for path in sorted((odm / "images").glob("*.tif")):
        ds = gdal.Open(str(path))
        md = ds.GetMetadata()
        xmp = ds.GetMetadata("xml:XMP")[0]
        t = read_photo_tags(path)
        assert t.kind == "gdal-tiff" and t.size == (ds.RasterXSize, ds.RasterYSize) == (1368, 912)
        for key in ("EXIF_FocalLength", "EXIF_GPSAltitude", "EXIF_PixelXDimension",
                    "EXIF_FocalLengthIn35mmFilm"):
            assert t.exif_float(key[5:]) == pytest.approx(float(md[key].strip("()")))
        lat = [float(v) for v in md["EXIF_GPSLatitude"].replace("(", "").replace(")", "").split()]
        assert t.exif["GPSLatitude"] == pytest.approx(tuple(lat))
        assert t.exif["Model"] == md["EXIF_Model"]
        dewarp = xmp.split('DewarpData="')[1].split('"')[0]
        assert t.xmp[(DJI, "DewarpData")] == dewarp
        assert t.xmp_float(DJI, "GimbalPitchDegree") == -60.0


def test_photo_folder_is_recognised(odm, tagged, tmp_path):
    """[consistency only] a folder of photos opens as one (not as a Pix4D folder), in the
    photos' UTM zone, with the notes saying where each part came from and how rough it is; a
    list of paths gives the same cameras."""
    assert tagged.software == "Photo tags" and tagged.crs.to_epsg() == rs.UTM51N
    assert sorted(c.label for c in tagged.cameras) == list(rs.PHOTOS)
    text = " ".join(tagged.notes)
    for part in ("RTK on 4 of 4 photos", "GimbalYaw/Pitch/RollDegree", "DewarpData",
                 "expected uncertainty", "1.5°"):
        assert part in text
    assert set(tagged.uncertainty_px) == set(rs.PHOTOS)
    listed = open_reconstruction(sorted(str(p) for p in (odm / "images").glob("*.tif")))
    for c in tagged.cameras:
        d = listed.camera(c.label)
        np.testing.assert_allclose(tagged.from_model(c.C[None]), listed.from_model(d.C[None]))
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(InputError, match="no JPEG or TIFF photos") as err:
        open_reconstruction(empty)
    assert "Pix4D" not in str(err.value)


# --- against the cameras OpenDroneMap solved ------------------------------------------------------
def test_against_solved_cameras(odm, tagged, solved):
    """[independent] OpenDroneMap's bundle adjustment of the same flight (reconstruction.json;
    pixels by cv2.projectPoints from its own pose). Measured: centres 1–5 cm apart (RTK fixed),
    optical axes 0.5–1.35° apart, footprints on the DSM IoU 0.905–0.949, and the five plot
    centres back-projected with both 9–22 px apart (median 14 px) at 1368×912, inside the
    stated 24 px (1.5°)."""
    axis, centre = [], []
    for c in solved.cameras:
        e = tagged.camera(c.label)
        centre.append(np.linalg.norm(tagged.from_model(e.C[None])[0] - solved.from_model(c.C[None])[0]))
        axis.append(np.degrees(np.arccos(np.clip(e.R[2] @ c.R[2], -1, 1))))
    print("centre differences (m)", np.round(centre, 3), "axis angles (°)", np.round(axis, 2))
    assert max(centre) < 0.08 and max(axis) < 1.6
    dsm = DSM(str(odm / "odm_dem" / "dsm.tif"))
    fe = {f.label: f for f in camera_footprints(tagged, dsm)}
    fs = {f.label: f for f in camera_footprints(solved, dsm)}
    iou = []
    for k in rs.PHOTOS:
        a, b = shapely.Polygon(fe[k].ring[:, :2]), shapely.Polygon(fs[k].ring[:, :2])
        iou.append(a.intersection(b).area / a.union(b).area)
    print("footprint IoU", np.round(iou, 3))
    assert min(iou) > 0.88
    dist = []
    for pair, (x, y) in rs.PAIR_CENTRES.items():
        z = rs.dsm_bilinear(odm / "odm_dem" / "dsm.tif", [x], [y])[0]
        for k in pair:
            truth = rs.OpenCVCamera(odm, k).project([[x, y, z]])[0]
            ours = tagged.project_points([[x, y, z]], cameras=[k]).pixels[0, 0]
            dist.append(np.linalg.norm(ours - truth))
            assert dist[-1] < 2 * tagged.uncertainty_px[k], (pair, k)
    print("plot centres, tags vs solved (px)", np.round(dist, 1))
    assert np.median(dist) < min(tagged.uncertainty_px.values())


def test_uncertainty_in_back_projection(odm, tagged, solved):
    """[consistency only] back-projected records carry the photo's uncertainty_px for cameras
    from tags, none for the solved project."""
    dsm = DSM(str(odm / "odm_dem" / "dsm.tif"))
    bp = back_project(rs.roi_set(), tagged, heights=dsm, min_visible=0.0)
    assert set(bp.photo.tolist()) <= set(bp.uncertainty_px)
    assert all(20 < v < 30 for v in bp.uncertainty_px.values())
    assert back_project(rs.roi_set(), solved, heights=dsm, min_visible=0.0).uncertainty_px == {}


# --- against Orthority's EXIF reader --------------------------------------------------------------
def _opk_matrix(omega, phi, kappa):
    """Orthority's (Pix4D's PATB) camera → world rotation, written here: Rx(ω)·Ry(φ)·Rz(κ)."""
    co, so, cp, sp, ck, sk = (np.cos(omega), np.sin(omega), np.cos(phi), np.sin(phi),
                              np.cos(kappa), np.sin(kappa))
    rx = np.array([[1, 0, 0], [0, co, -so], [0, so, co]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[ck, -sk, 0], [sk, ck, 0], [0, 0, 1]])
    return rx @ ry @ rz


def test_against_orthority(odm, tagged, tmp_path):
    """[independent] Orthority 0.7.0 (``oty exif --export-params``, its own venv) on the same
    photos: centres within 1 mm, rotations within 0.001°, focal lengths within 0.01 px,
    principal point and Brown terms the same. Conventions: Orthority's PATB camera (x right,
    y up, z back) is ours (x right, y down, z forward) times diag(1, −1, −1); its principal
    point is an offset from the image centre over max(w, h); its p1, p2 are OpenCV's (ours
    swapped)."""
    oty = os.environ.get("EASYIDP_ORTHORITY", "")
    assert oty and os.path.exists(oty), "Orthority not found: make env-orthority (EASYIDP_ORTHORITY)"
    photos = sorted(str(p) for p in (odm / "images").glob("*.tif"))
    env = {k: v for k, v in os.environ.items() if k not in ("PROJ_DATA", "PROJ_LIB", "PYTHONPATH")}
    run = subprocess.run([oty, "exif", "--export-params", "--out-dir", str(tmp_path), *photos],
                         capture_output=True, text=True, timeout=300, env=env)
    assert run.returncode == 0, run.stderr[-2000:]
    cam = {}                          # int_param.yaml: one camera, "    key: value" lines
    for line in (tmp_path / "int_param.yaml").read_text().splitlines()[1:]:
        key, value = line.strip().split(": ", 1)
        cam[key] = value if key == "type" else json.loads(value)
    ext = json.loads((tmp_path / "ext_param.geojson").read_text())
    assert ext["world_crs"] == f"EPSG:{rs.UTM51N}"
    s = tagged.sensors[tagged.cameras[0].sensor_id]
    w, h = cam["im_size"]
    assert (s.width, s.height) == (w, h)
    k = w / cam["sensor_size"][0]
    cal = s.calibration
    assert abs(cal.f + cal.b1 - cam["focal_len"][0] * k) < 0.01
    assert abs(cal.f - cam["focal_len"][1] * k) < 0.01
    assert abs((cal.cx - w / 2) / max(w, h) - cam["cx"]) < 1e-9
    assert abs((cal.cy - h / 2) / max(w, h) - cam["cy"]) < 1e-9
    assert (cal.k1, cal.k2, cal.k3, cal.p1, cal.p2) == pytest.approx(
        (cam["k1"], cam["k2"], cam["k3"], cam["p2"], cam["p1"]), abs=1e-12)
    flip = np.diag([1.0, -1.0, -1.0])
    worst_c, worst_a = 0.0, 0.0
    for f in ext["features"]:
        p = f["properties"]
        c = tagged.camera(p["filename"])
        worst_c = max(worst_c, np.abs(tagged.from_model(c.C[None])[0] - p["xyz"]).max())
        r_oty = (_opk_matrix(*p["opk"]) @ flip).T           # world → our camera axes
        cosang = (np.trace(c.R @ r_oty.T) - 1) / 2
        worst_a = max(worst_a, np.degrees(np.arccos(np.clip(cosang, -1, 1))))
    print(f"vs Orthority: centres {worst_c * 1000:.4f} mm, rotations {worst_a:.6f}°")
    assert worst_c < 0.001 and worst_a < 0.001


# --- camera JPEGs and bad input -------------------------------------------------------------------
DJI_XMP = ('<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
           'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description '
           'xmlns:drone-dji="http://www.dji.com/drone-dji/1.0/" {attrs}/></rdf:RDF></x:xmpmeta>')


def write_jpeg(path, *, gps=True, attitude=True, model="FC6310R", size=(64, 48), lat=24.68):
    """A small camera JPEG: EXIF by Pillow (Make, Model, FocalLengthIn35mmFilm, GPS) and a
    DJI XMP packet in its own APP1 segment, as DJI cameras write them."""
    ex = Image.Exif()
    ex[0x010F], ex[0x0110] = "DJI", model
    ex[0x8769] = {0xA405: 24}
    if gps:
        ex[0x8825] = {1: "N", 2: (float(int(lat)), 40.0, 49.0), 3: "E", 4: (120.0, 57.0, 6.0),
                      5: b"\x00", 6: 186.5}
    Image.new("RGB", size, (90, 140, 60)).save(path, exif=ex.tobytes(), quality=80)
    attrs = 'drone-dji:RelativeAltitude="+99.9"'
    if attitude:
        attrs += (' drone-dji:GimbalYawDegree="+92.9" drone-dji:GimbalPitchDegree="-90.0"'
                  ' drone-dji:GimbalRollDegree="+0.00"')
    packet = XMP_NS + DJI_XMP.format(attrs=attrs).encode()
    data = path.read_bytes()
    path.write_bytes(data[:2] + b"\xff\xe1" + (len(packet) + 2).to_bytes(2, "big") + packet + data[2:])
    return path


def test_camera_jpeg(tmp_path):
    """[independent: pyproj's geodesic for the azimuth] a JPEG as a camera writes it (Pillow's EXIF, an XMP APP1 segment): the
    35 mm focal length on the 43.27 mm diagonal, the GPS position, DJI's gimbal angles; a nadir
    photo at yaw 92.9° has its image top towards the azimuth 92.9° (east)."""
    write_jpeg(tmp_path / "DJI_0001.JPG")
    recon = open_photos(tmp_path)
    (cam,) = recon.cameras
    s = recon.sensors[cam.sensor_id]
    assert s.calibration.f == pytest.approx(24 * np.hypot(64, 48) / np.hypot(36, 24))
    lonlat = recon.from_model(cam.C[None], "EPSG:4326")[0]
    assert lonlat[:2] == pytest.approx([120 + 57 / 60 + 6 / 3600, 24 + 40 / 60 + 49 / 3600], abs=1e-9)
    assert lonlat[2] == pytest.approx(186.5)
    up_in_image = -cam.R[1]           # image "up" (−y) in map axes (east, north, up)
    az = np.degrees(np.arctan2(up_in_image[0], up_in_image[1]))
    assert cam.R[2] == pytest.approx([0, 0, -1], abs=1e-9)
    # the grid azimuth of the true azimuth 92.9° there: 10 m along the geodesic, in UTM
    from pyproj import Geod, Transformer
    lon2, lat2, _ = Geod(ellps="WGS84").fwd(lonlat[0], lonlat[1], 92.9, 10.0)
    x, y = Transformer.from_crs("EPSG:4326", recon.crs, always_xy=True).transform(
        [lonlat[0], lon2], [lonlat[1], lat2])
    assert az == pytest.approx(np.degrees(np.arctan2(x[1] - x[0], y[1] - y[0])), abs=1e-4)


def test_bad_input_one_message_per_cause(tmp_path):
    """[consistency only] no GPS, no attitude (no XMP gimbal angles), mixed cameras, an empty
    folder and a folder of other files: one line per cause naming the photos and the tags."""
    write_jpeg(tmp_path / "ok.jpg")
    write_jpeg(tmp_path / "nogps1.jpg", gps=False)
    write_jpeg(tmp_path / "nogps2.jpg", gps=False)
    write_jpeg(tmp_path / "noatt.jpg", attitude=False)
    with pytest.raises(InputError) as err:
        open_photos(tmp_path)
    msg = str(err.value)
    lines = sorted(ln for ln in msg.splitlines() if ln.startswith("- "))
    assert len(lines) == 2
    assert "GPSLatitude" in lines[0] and "nogps1.jpg, nogps2.jpg" in lines[0]
    assert "GimbalYaw/Pitch/RollDegree" in lines[1] and lines[1].endswith(": noatt.jpg")
    assert "ok.jpg" not in msg
    mixed = tmp_path / "mixed"
    mixed.mkdir()
    write_jpeg(mixed / "a.jpg")
    write_jpeg(mixed / "b.jpg", model="FC7303")
    with pytest.raises(InputError, match=r"2 cameras .*FC6310R 64×48.*a\.jpg.*FC7303.*b\.jpg"):
        open_photos(mixed)
    other = tmp_path / "other"
    other.mkdir()
    (other / "x.png").write_bytes(b"\x89PNG")
    with pytest.raises(InputError, match=r"no JPEG or TIFF photos.*x\.png"):
        open_reconstruction(other)
    with pytest.raises(InputError, match="take-off height"):
        open_photos(mixed, camera_heights="relative")
    (tmp_path / "positions.csv").write_text("filename,x,y,z,omega,phi,kappa\n")
    with pytest.raises(InputError, match="not read yet; give the folder of photos"):
        open_reconstruction(tmp_path / "positions.csv")


def test_heights_above_the_take_off_point(odm, tagged, solved):
    """[independent] ODM's solved heights: DJI's RelativeAltitude + the take-off height
    (AbsoluteAltitude − RelativeAltitude of the first photo, 86.61 m) gives the solved heights
    within 6 cm; with the DSM under the first photo as the take-off ground the heights are that
    DSM height (bilinear, in the test) + RelativeAltitude: 24 m too high here, because this
    survey's first photo was not taken over the take-off point (said in the docs)."""
    rel = open_reconstruction(odm / "images", camera_heights="relative", takeoff_height=86.61)
    assert "take-off height 86.61 m" in rel.notes[0]
    for c in solved.cameras:
        dz = rel.from_model(rel.camera(c.label).C[None])[0][2] - solved.from_model(c.C[None])[0][2]
        assert abs(dz) < 0.06, c.label
    dsm = DSM(str(odm / "odm_dem" / "dsm.tif"))
    on_dsm = open_reconstruction(odm / "images", camera_heights="relative", takeoff_height=dsm)
    first = read_photo_tags(odm / "images" / "100_0005_0018.tif")
    lon, lat = first.xmp_float(DJI, "GpsLongtitude"), first.xmp_float(DJI, "GpsLatitude")
    from pyproj import Transformer
    x, y = Transformer.from_crs("EPSG:4326", rs.UTM51N, always_xy=True).transform(lon, lat)
    ground = rs.dsm_bilinear(odm / "odm_dem" / "dsm.tif", [x], [y])[0]
    c = on_dsm.camera("100_0005_0018")
    z = on_dsm.from_model(c.C[None])[0][2]
    assert z == pytest.approx(ground + first.xmp_float(DJI, "RelativeAltitude"), abs=0.01)
    with pytest.raises(InputError, match="folder of photos, not to a solved project"):
        open_reconstruction(odm, camera_heights="relative", takeoff_height=86.61)


# --- the demo survey's tagged photos -------------------------------------------------------------
def test_gimbal_angles_round_trip():
    """[consistency only] gimbal_angles inverts gimbal_rotation (with a convergence) over
    yaw, pitch and roll away from the pitch ±90° singularity."""
    from easyidp_toolbox.core.reconstruction.photo_poses import gimbal_angles, gimbal_rotation
    rng = np.random.default_rng(5)
    for yaw, pitch, roll, conv in zip(rng.uniform(0, 360, 50), rng.uniform(-89, 89, 50),
                                      rng.uniform(-30, 30, 50), rng.uniform(-3, 3, 50)):
        R = gimbal_rotation(yaw, pitch, roll, conv)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
        assert gimbal_angles(R, conv) == pytest.approx((yaw, pitch, roll), abs=1e-8)


def test_demo_photos_carry_dji_tags(demo):
    """[consistency only: the generator writes the tags with the inverse of the reader's
    convention, which tests against ODM and Orthority above check independently] the demo
    photos alone give cameras within the stated noise of the truth: centres as the logged GNSS
    (0.8 m, 1.5 m), rotations within 4° (1°, 0.5°, 0.5°), the lens exact."""
    recon = open_photos(demo.photo_folder)
    truth = demo.truth_doc
    assert len(recon.cameras) == len(truth["photos"]) == 36
    cal = recon.sensors[recon.cameras[0].sensor_id].calibration
    t = truth["camera"]
    assert cal.f == pytest.approx(t["f"], abs=1e-5) and cal.b1 == pytest.approx(t["b1"], abs=1e-5)
    assert cal.cx == pytest.approx(t["width"] / 2 + t["cx"], abs=1e-5)
    centre, angle = [], []
    for label, p in truth["photos"].items():
        c = recon.camera(label)
        centre.append(np.linalg.norm(recon.from_model(c.C[None])[0] - p["centre"]))
        dR = c.R @ np.array(p["rotation"]).T
        angle.append(np.degrees(np.arccos(np.clip((np.trace(dR) - 1) / 2, -1, 1))))
    assert max(centre) < 6.0 and 0.3 < np.median(centre) < 3.0
    assert max(angle) < 4.0 and 0.2 < np.median(angle) < 2.0
