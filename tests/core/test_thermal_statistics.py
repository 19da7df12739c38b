"""Plot statistics from photos in °C: FLIR photos of a known temperature field measured by
photo_statistics(values="temperature"), each view's time, sun and phase angle."""
import math
import sys
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pandas as pd
import pvlib
import pyproj
import pytest
import shapely

from easyidp_toolbox.core.demo.flir_writer import write_flir_jpeg
from easyidp_toolbox.core.errors import EasyIDPError
from easyidp_toolbox.core.projection import back_project, photo_statistics
from easyidp_toolbox.core.radiometry import ThermalParameters, celsius_to_raw
from easyidp_toolbox.core.roi import ROI, ROISet
from easyidp_toolbox.core.sun import sun_position

sys.path.insert(0, str(Path(__file__).parent))
from test_photo_statistics import NADIR, OFFSET, UTM, H, W, _inside_shapely, _project  # noqa: E402
from test_thermal import CAMERA, PHOTO  # noqa: E402
from easyidp_toolbox.tests.support.planck_reference import planck_by_hand  # noqa: E402


@pytest.fixture(scope="module")
def thermal(tmp_path_factory):
    """Three nadir FLIR views 30 m over a flat field whose temperature varies across it; a
    block of saturated pixels inside the plot of the first photo."""
    tmp = tmp_path_factory.mktemp("thermal")
    p = ThermalParameters(**CAMERA, **PHOTO)
    cams = [(NADIR, [3.0 * i, 0.0, 30.0]) for i in range(3)]
    recon = _project(tmp, cams, [np.zeros((H, W, 3), np.uint8)] * 3)   # the project's photos
    folder = tmp / "thermal"
    folder.mkdir()
    yy, xx = np.mgrid[0:H, 0:W]
    raws = []
    for i in range(3):
        t = 24.0 + 5.0 * np.sin(xx / 37.0 + i) + 3.0 * np.cos(yy / 53.0) + 0.5 * i
        raw = np.round(celsius_to_raw(t, p)).astype(np.uint16)
        if i == 0:
            raw[290:300, 390:420] = 65535                              # saturated
        write_flir_jpeg(folder / f"IMG_{i}.jpg", raw, p, when=f"2026:06:01 11:30:{15 + i:02d}",
                        subsec="250", utc_offset="+09:00")
        raws.append(raw)
    ring = np.array([[-4.013, -2.507], [3.121, -3.333], [5.477, 1.905], [0.713, 4.219],
                     [-3.377, 2.641]])
    rois = ROISet([ROI("plot", [[ring + OFFSET[:2]]])], UTM)
    res = back_project(rois, recon, heights=0.0, min_visible=0.0)
    return recon, rois, res, raws, folder


def test_plot_temperatures_equal_pixels_under_mask(thermal):
    """[independent] Each view's temp_c mean and median equal numpy's over the pixels shapely
    finds inside the back-projected polygon, converted by the Planck formula written out in
    tests/support/planck_reference.py from the raw values we wrote (saturated ones left out), to 0.001 °C."""
    recon, rois, res, raws, folder = thermal
    st = photo_statistics(res, folder, values="temperature", recon=recon, rois=rois,
                          statistics=("mean", "median"), percentiles=(90,))
    assert st.columns == ["temp_c_mean", "temp_c_median", "temp_c_p90"]
    assert st.values_kind == "temperature"
    assert any("FLIR Vue Pro R raw (png) to °C by Planck" in n for n in st.notes)
    p32 = {k: float(np.float32(v)) for k, v in {**CAMERA, **PHOTO}.items()}
    for k in range(len(st.record)):
        j = int(st.photo[k][-1])
        polys = res.rings_of(int(st.record[k]))
        inside = _inside_shapely([polys], raws[j].shape) & (raws[j] < 65535)
        vals = np.array([planck_by_hand(float(r), p32["r1"], p32["r2"], p32["b"], p32["f"],
                                        p32["o"], p32["emissivity"], p32["object_distance"],
                                        p32["reflected_temperature"],
                                        p32["atmospheric_temperature"], p32["relative_humidity"])
                         for r in raws[j][inside]])
        assert st.pixels[k] == inside.sum() < st.polygon_pixels[k] + (1 if j else 0)
        assert st.values[k, 0] == pytest.approx(vals.mean(), abs=1e-3)
        assert st.values[k, 1] == pytest.approx(np.median(vals), abs=1e-3)
        assert st.values[k, 2] == pytest.approx(np.percentile(vals, 90), abs=1e-3)
    assert st.polygon_pixels[list(st.photo).index("IMG_0")] - \
        st.pixels[list(st.photo).index("IMG_0")] == 300          # the saturated block
    rows = st.view_rows()
    assert "temp_c_mean" in rows[0] and "red_mean" not in rows[0]


def test_time_sun_and_phase_angle(thermal):
    """[independent] Each view's time is its photo's EXIF time (sub-seconds and offset); the sun
    is pvlib's SPA at the plot's centre then (to 0.02° on the sky); the phase angle is the angle between
    the sun and the camera as pyproj's geodesic azimuth and the camera height give it."""
    recon, rois, res, raws, folder = thermal
    st = photo_statistics(res, folder, values="temperature", recon=recon, rois=rois)
    to_ll = pyproj.Transformer.from_crs(UTM, "EPSG:4326", always_xy=True)
    lon, lat = _roi_ll(rois)
    geod = pyproj.Geod(ellps="WGS84")
    for k in range(len(st.record)):
        i = int(st.photo[k][-1])
        assert st.acquired[k] == f"2026-06-01T11:30:{15 + i:02d}.250000+09:00"
        when = pd.Timestamp(st.acquired[k]).tz_convert("UTC")
        ref = pvlib.solarposition.spa_python(pd.DatetimeIndex([when]), lat, lon)
        assert st.sun_zenith[k] == pytest.approx(ref["zenith"].iloc[0], abs=0.02)
        da = (st.sun_azimuth[k] - ref["azimuth"].iloc[0] + 180) % 360 - 180
        assert abs(da) * math.sin(math.radians(st.sun_zenith[k])) < 0.02   # on the sky
        cx, cy = to_ll.transform(OFFSET[0] + 3.0 * i, OFFSET[1])
        az, _, dist = geod.inv(lon, lat, cx, cy)
        view_zen = math.degrees(math.atan2(dist, 30.0))
        sz, sa = math.radians(ref["zenith"].iloc[0]), math.radians(ref["azimuth"].iloc[0])
        vz, va = math.radians(view_zen), math.radians(az)
        sun = (math.sin(sz) * math.sin(sa), math.sin(sz) * math.cos(sa), math.cos(sz))
        cam = (math.sin(vz) * math.sin(va), math.sin(vz) * math.cos(va), math.cos(vz))
        want = math.degrees(math.acos(sum(a * b for a, b in zip(sun, cam))))
        assert st.phase_angle[k] == pytest.approx(want, abs=0.05)
    row = st.view_rows()[0]
    assert {"acquired", "sun_zenith", "sun_azimuth", "phase_angle"} <= set(row)


def test_sun_position_against_pvlib():
    """[independent] NOAA's algorithm (core/sun.py) against pvlib's SPA (NREL) over 60 random
    places and times of 2000–2060: within 0.02° (azimuth weighted by the sine of the zenith,
    where it is defined)."""
    rng = np.random.default_rng(0)
    secs = rng.uniform(0, 60 * 365.25 * 86400, 60)
    lats, lons = rng.uniform(-65, 65, 60), rng.uniform(-180, 180, 60)
    for s, la, lo in zip(secs, lats, lons):
        when = datetime.fromtimestamp(946684800 + s, timezone.utc)
        z, a = sun_position(when, lo, la)
        ref = pvlib.solarposition.spa_python(pd.DatetimeIndex([when]), la, lo)
        assert abs(z - ref["zenith"].iloc[0]) < 0.02
        da = (a - ref["azimuth"].iloc[0] + 180) % 360 - 180
        assert abs(da) * math.sin(math.radians(z)) < 0.02


def test_naive_time_and_bad_values(thermal, tmp_path):
    """[independent] Photos whose time has no UTC offset get their time but no sun (a note says
    to give the offset; with it, the sun, and the previews of °C views are drawn); unknown values and reflectance are refused."""
    recon, rois, res, raws, folder = thermal
    p = ThermalParameters(**CAMERA, **PHOTO)
    naive = tmp_path / "naive"
    naive.mkdir()
    for i in range(3):
        write_flir_jpeg(naive / f"IMG_{i}.jpg", raws[i], p, when="2026:06:01 11:30:15")
    st = photo_statistics(res, naive, values="temperature", recon=recon, rois=rois)
    assert st.acquired[0] == "2026-06-01T11:30:15" and np.isnan(st.sun_zenith).all()
    assert any("without a UTC offset" in n for n in st.notes)
    st2 = photo_statistics(res, naive, values="temperature", recon=recon, rois=rois,
                           utc_offset=9, previews_folder=tmp_path / "previews")
    assert len(st2.previews) == 1 and Path(st2.previews[0]).stat().st_size > 1000
    np.testing.assert_allclose(st2.sun_zenith, sun_position(
        datetime(2026, 6, 1, 2, 30, 15, tzinfo=timezone.utc), *_roi_ll(rois))[0], atol=1e-6)
    with pytest.raises(EasyIDPError, match="Unknown values"):
        photo_statistics(res, folder, values="radiance")
    from easyidp_toolbox.core import radiometry
    if radiometry.reflectance_values is None:
        with pytest.raises(EasyIDPError, match="reflectance: not in this build"):
            photo_statistics(res, folder, values="reflectance")


def _roi_ll(rois):
    """The plot's area centroid (shapely) in lon, lat."""
    cen = shapely.Polygon(rois[0].rings[0]).centroid
    return pyproj.Transformer.from_crs(UTM, "EPSG:4326", always_xy=True).transform(cen.x, cen.y)
