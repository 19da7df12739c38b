"""core.radiometry: multispectral band files as reflectance (MicaSense, DJI), panels, captures.

Truth kind [independent]: every photo is a 16-bit TIFF written byte by byte by
``tests/support/vendor_tiff.py`` with the vendors' tags; the expected values come from the
vendors' formulas written out a second time here (MicaSense tutorial 1 and ``image.py``; DJI's P4
Multispectral Image Processing Guide, Eqs. 6–9), from the parameters the test chose, not from the
tags the product reads. The round trips also start from a known reflectance field.
"""
import math
from datetime import datetime, timezone

import numpy as np
import pytest

from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.radiometry import (PhotoValues, ReflectanceOptions, band_key,
                                             group_captures, reflectance_values)
from easyidp_toolbox.core.sun import sun_position
from easyidp_toolbox.tests.support.vendor_tiff import DJI_NS, MICASENSE_NS, write_band_tiff, xmp_packet

ROWS, COLS = 48, 64
CAL = (2.2e-4, 1.5e-7, 2.5e-5)        # a1, a2, a3
VIG_CENTRE = (30.5, 25.0)
VIG_POLY = [1.2e-4, -3.0e-6, 2.0e-8, -1.0e-10, 2.0e-13, -1.0e-16]
BLACK = 4800


def micasense_tags(band, *, horizontal=None, extra=None):
    props = {"Camera:BandName": band, "Camera:RadiometricCalibration": list(CAL),
             "Camera:VignettingCenter": list(VIG_CENTRE), "Camera:VignettingPolynomial": VIG_POLY,
             "MicaCamera:CaptureId": "c0ffee"}
    if horizontal is not None:
        props["DLS:HorizontalIrradiance"] = horizontal
        props["DLS:IrradianceScaleToSIUnits"] = 0.01
    props.update(extra or {})
    return xmp_packet(props, MICASENSE_NS, as_elements=("Camera:BandName",))


def micasense_expected(raw, exposure, gain):
    """MicaSense tutorial 1, written out again: radiance in W/m²/sr/nm."""
    out = np.zeros(raw.shape)
    for row in range(raw.shape[0]):
        for col in range(raw.shape[1]):
            r = math.hypot(col - VIG_CENTRE[0], row - VIG_CENTRE[1])
            poly = 1.0 + sum(k * r ** (i + 1) for i, k in enumerate(VIG_POLY))
            grad = 1.0 / (1.0 + CAL[1] * row / exposure - CAL[2] * row)
            corrected = max(float(raw[row, col]) - BLACK, 0.0) * grad / poly
            out[row, col] = corrected / (gain * exposure) * CAL[0] / 65536.0
    return out


def micasense_raw_from_radiance(radiance, exposure, gain):
    """Invert the same model: the digital numbers a camera would store for ``radiance``."""
    rows, cols = np.mgrid[0:radiance.shape[0], 0:radiance.shape[1]].astype(float)
    r = np.hypot(cols - VIG_CENTRE[0], rows - VIG_CENTRE[1])
    poly = 1.0 + sum(k * r ** (i + 1) for i, k in enumerate(VIG_POLY))
    grad = 1.0 / (1.0 + CAL[1] * rows / exposure - CAL[2] * rows)
    dn = radiance * (gain * exposure) / CAL[0] * 65536.0 * poly / grad + BLACK
    return np.clip(np.round(dn), 0, 65535).astype(np.uint16)


def write_micasense(path, raw, *, band="Red", exposure=0.0015, iso=200, horizontal=None, extra=None,
                    black=BLACK, **kw):
    write_band_tiff(path, raw, xmp=micasense_tags(band, horizontal=horizontal, extra=extra),
                    make="MicaSense", model="RedEdge-MX", software="v6.2.1",
                    black_level=None if black is None else [black] * 4, exposure_s=exposure, iso=iso,
                    when=kw.pop("when", "2024:06:01 02:30:00"), subsec=kw.pop("subsec", "125"), **kw)


def test_micasense_dls2_matches_the_tutorial_formula(tmp_path):
    """[independent] raw → radiance → π·L/E, E = HorizontalIrradiance × scale; saturated masked."""
    rng = np.random.default_rng(3)
    raw = rng.integers(5000, 40000, (ROWS, COLS)).astype(np.uint16)
    raw[5, 7] = 65535
    raw[9, 9] = 65520
    path = tmp_path / "IMG_0001_3.tif"
    write_micasense(path, raw, horizontal=112.0)
    got = reflectance_values(path)
    assert isinstance(got, PhotoValues) and got.unit == "reflectance" and got.bands == ("Red",)
    assert got.values.dtype == np.float32 and got.values.shape == (ROWS, COLS)
    expected = micasense_expected(raw, 0.0015, 2.0) * math.pi / (112.0 * 0.01)
    ok = got.valid
    np.testing.assert_allclose(got.values[ok], expected[ok], rtol=2e-6)
    assert not got.valid[5, 7] and not got.valid[9, 9] and got.valid.sum() == ROWS * COLS - 2
    assert "DLS 2 horizontal" in got.note and "2 saturated pixels masked" in got.note


def test_micasense_reflectance_is_free_of_gain_and_exposure(tmp_path):
    """[independent] the same reflectance field under the same light, stored at three gain and
    exposure settings, reads back to the field within 0.002, while the digital numbers differ by
    more than 2×."""
    rows, cols = np.mgrid[0:ROWS, 0:COLS]
    truth = 0.05 + 0.4 * (cols / COLS) * (0.5 + 0.5 * np.sin(rows / 7.0) ** 2)
    irradiance = 0.3                                 # W/m²/nm
    raws = []
    for k, (exposure, iso) in enumerate([(0.001, 100), (0.002, 200), (0.0005, 400)]):
        raw = micasense_raw_from_radiance(truth * irradiance / math.pi, exposure, iso / 100)
        raws.append(raw)
        path = tmp_path / f"IMG_000{k}_4.tif"
        write_micasense(path, raw, band="NIR", exposure=exposure, iso=iso, horizontal=irradiance * 100)
        got = reflectance_values(path)
        assert got.valid.all() and np.abs(got.values - truth).max() < 0.002, (exposure, iso)
    assert raws[1].mean() / raws[0].mean() > 2.0


def _dls1_expected(spectral, when, lat, lon, yaw, pitch, roll):
    """DLS 1 in MicaSense image.py's steps, written again, with the sun from Spencer's (1971)
    declination and equation of time (a second solar-position method)."""
    doy = when.timetuple().tm_yday
    g = 2 * math.pi / 365 * (doy - 1 + (when.hour - 12) / 24)
    decl = (0.006918 - 0.399912 * math.cos(g) + 0.070257 * math.sin(g) - 0.006758 * math.cos(2 * g)
            + 0.000907 * math.sin(2 * g) - 0.002697 * math.cos(3 * g) + 0.00148 * math.sin(3 * g))
    eqt = 229.18 * (0.000075 + 0.001868 * math.cos(g) - 0.032077 * math.sin(g)
                    - 0.014615 * math.cos(2 * g) - 0.040849 * math.sin(2 * g))
    tst = when.hour * 60 + when.minute + when.second / 60 + eqt + 4 * lon
    ha = math.radians(tst / 4 - 180)
    phi = math.radians(lat)
    cos_z = math.sin(phi) * math.sin(decl) + math.cos(phi) * math.cos(decl) * math.cos(ha)
    el = math.pi / 2 - math.acos(cos_z)
    az = math.atan2(math.sin(ha), math.cos(ha) * math.sin(phi) - math.tan(decl) * math.cos(phi)) + math.pi
    sun = np.array([math.cos(az) * math.cos(el), math.sin(az) * math.cos(el), -math.sin(el)])
    cz, sz = math.cos(yaw), math.sin(yaw)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cr, sr = math.cos(roll), math.sin(roll)
    down = np.array([0.0, 0.0, -1.0])
    rot = (np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]]) @ np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
           @ np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))
    theta = math.acos(float(sun @ (rot @ down)))

    def layer(phi_in, n1, n2):
        c1, c2 = math.cos(phi_in), math.sqrt(1 - (n1 / n2 * math.sin(phi_in)) ** 2)
        rs = ((n1 * c1 - n2 * c2) / (n1 * c1 + n2 * c2)) ** 2
        rp = ((n1 * c2 - n2 * c1) / (n1 * c2 + n2 * c1)) ** 2
        return 1 - (rs + rp) / 2
    p1 = math.asin(math.sin(theta) / 1.000277)
    t = layer(p1, 1.000277, 1.6)
    p2 = math.asin(math.sin(p1) / 1.6)
    t *= layer(p2, 1.6, 1.38)
    direct = spectral / t / (1 / 6 + math.cos(theta))
    return direct * math.sin(el) + direct / 6, math.degrees(el)


def test_micasense_dls1_sun_angle_correction(tmp_path):
    """[independent] DLS 1: the irradiance behind the reflectance follows MicaSense's sun–sensor
    angle, Fresnel and 6:1 clear-sky model with the sun from a second method, within 0.5 %."""
    raw = np.full((ROWS, COLS), 20000, np.uint16)
    yaw, pitch, roll = 0.6, 0.08, -0.05
    extra = {"DLS:SpectralIrradiance": 0.9, "DLS:Yaw": yaw, "DLS:Pitch": pitch, "DLS:Roll": roll}
    path = tmp_path / "IMG_0002_1.tif"
    write_micasense(path, raw, band="Blue", extra=extra, when="2024:06:01 02:30:00", subsec="0",
                    latlon=(35.68, 139.77))
    got = reflectance_values(path)
    when = datetime(2024, 6, 1, 2, 30, tzinfo=timezone.utc)
    irradiance, elevation = _dls1_expected(0.9, when, 35.68, 139.77, yaw, pitch, roll)
    expected = micasense_expected(raw, 0.0015, 2.0) * math.pi / irradiance
    np.testing.assert_allclose(got.values, expected, rtol=5e-3)
    assert "DLS 1" in got.note and abs(_elevation(when, 35.68, 139.77) - elevation) < 0.5


def _elevation(when, lat, lon):
    """The sun's elevation (degrees) by the engine's NOAA equations (``core.sun``)."""
    return 90.0 - float(sun_position(when, lon, lat)[0])


def test_sun_position_against_spencer():
    """[independent] NOAA's equations against Spencer's approximations over a day: 0.5° agreement."""
    for hour in (1, 3, 5, 7):
        when = datetime(2024, 6, 1, hour, 0, tzinfo=timezone.utc)
        _, elevation = _dls1_expected(1.0, when, 35.68, 139.77, 0, 0, 0)
        assert abs(_elevation(when, 35.68, 139.77) - elevation) < 0.5


DJI_K = [1.1e-4, 1.2e-6, -2.9e-9, 5.2e-12, -4.2e-15, 1.4e-18]


def write_dji(path, raw, *, band, gain=1.0, exposure_us=1000, adjust=1.0, irradiance=2000.0,
              drop=(), when="2024:06:01 11:30:00", subsec="150", mavic=False):
    props = {"Camera:BandName": band, "drone-dji:BlackLevel": 4096, "drone-dji:SensorGain": gain,
             "drone-dji:ExposureTime": exposure_us, "drone-dji:SensorGainAdjustment": adjust,
             "drone-dji:Irradiance": irradiance}
    if mavic:
        props["drone-dji:VignettingPolynomial"] = ", ".join(str(k) for k in DJI_K)
        props["drone-dji:VignettingCenter"] = "32.0, 24.0"
    else:
        props["drone-dji:VignettingData"] = ", ".join(str(k) for k in DJI_K)
        props["drone-dji:CalibratedOpticalCenterX"] = 32.0
        props["drone-dji:CalibratedOpticalCenterY"] = 24.0
    for key in drop:
        props.pop(key)
    write_band_tiff(path, raw, xmp=xmp_packet(props, DJI_NS), make="DJI",
                    model="M3M" if mavic else "FC6360", black_level=[4096], when=when, subsec=subsec)


def dji_expected(raw, gain, exposure_us, adjust, irradiance):
    """P4 Multispectral Image Processing Guide, Eqs. 6–9, written out again."""
    out = np.zeros(raw.shape)
    for row in range(raw.shape[0]):
        for col in range(raw.shape[1]):
            r = math.sqrt((col - 32.0) ** 2 + (row - 24.0) ** 2)
            k = DJI_K
            vig = k[5] * r ** 6 + k[4] * r ** 5 + k[3] * r ** 4 + k[2] * r ** 3 + k[1] * r ** 2 + k[0] * r + 1
            camera = (raw[row, col] / 65535 * vig - 4096 / 65535) / (gain * exposure_us / 1e6)
            out[row, col] = adjust * max(camera, 0.0) / irradiance
    return out


@pytest.mark.parametrize("mavic", [False, True])
def test_dji_matches_the_guide(tmp_path, mavic):
    """[independent] DJI P4M (VignettingData, CalibratedOpticalCenter) and Mavic 3M
    (VignettingPolynomial, VignettingCenter) tags → the guide's reflectance."""
    rng = np.random.default_rng(5)
    raw = rng.integers(4500, 30000, (ROWS, COLS)).astype(np.uint16)
    raw[0, 0] = 65535
    path = tmp_path / "DJI_20240601113000_0001_MS_NIR.TIF"
    write_dji(path, raw, band="NIR", gain=2.0, exposure_us=800, adjust=1.02, irradiance=1850.0, mavic=mavic)
    got = reflectance_values(path)
    expected = dji_expected(raw, 2.0, 800, 1.02, 1850.0)
    np.testing.assert_allclose(got.values[got.valid], expected[got.valid], rtol=2e-6)
    assert not got.valid[0, 0] and got.bands == ("NIR",) and "drone-dji:Irradiance" in got.note


def test_missing_calibration_tags_name_the_photo(tmp_path):
    """Missing calibration tags: one message per cause, naming the photo (the product would
    otherwise fail inside numpy or return digital numbers)."""
    raw = np.full((ROWS, COLS), 9000, np.uint16)
    mica = tmp_path / "IMG_0003_2.tif"
    write_micasense(mica, raw, black=None, horizontal=100.0)
    with pytest.raises(InputError, match=r"IMG_0003_2\.tif.*BlackLevel.*missing"):
        reflectance_values(mica)
    dji = tmp_path / "DJI_0003_MS_R.TIF"
    write_dji(dji, raw, band="Red", drop=("drone-dji:SensorGainAdjustment",))
    with pytest.raises(InputError, match=r"DJI_0003_MS_R\.TIF.*SensorGainAdjustment.*missing"):
        reflectance_values(dji)
    no_light = tmp_path / "DJI_0004_MS_R.TIF"
    write_dji(no_light, raw, band="Red", drop=("drone-dji:Irradiance",))
    with pytest.raises(InputError, match=r"DJI_0004_MS_R\.TIF.*no sunlight-sensor irradiance.*panel"):
        reflectance_values(no_light)
    plain = tmp_path / "plain.tif"
    write_band_tiff(plain, raw, xmp=xmp_packet({}, MICASENSE_NS), make="Other", model="X")
    with pytest.raises(InputError, match=r"plain\.tif.*not a band file of a supported"):
        reflectance_values(plain)


def test_altum_pt_lwir_band_is_thermal_not_missing_calibration(tmp_path):
    """[independent] an Altum-PT LWIR band file (MicaSense's thermal band: centi-kelvin, no
    radiometric calibration tags) asked for reflectance gets one line saying it is thermal and
    what to do, not "calibration tags missing"; measured as it says, it reads °C by MicaSense's
    own conversion (``image.py``: °C = (raw − 27315) · 0.01), written out here."""
    from easyidp_toolbox.core.radiometry import read_photo_values
    raw = np.full((ROWS, COLS), 29815, np.uint16)
    raw[3, 4] = 30123
    lwir = tmp_path / "IMG_0007_6.tif"
    write_band_tiff(lwir, raw, xmp=xmp_packet({"Camera:BandName": "LWIR",
                                               "MicaCamera:CaptureId": "pt0"}, MICASENSE_NS,
                                              as_elements=("Camera:BandName",)),
                    make="MicaSense", model="Altum-PT", black_level=[0] * 4)
    with pytest.raises(InputError) as err:
        reflectance_values(lwir)
    text = str(err.value)
    assert "IMG_0007_6.tif" in text and "thermal" in text and "centi-kelvin" in text
    assert "missing" not in text and "\n" not in text
    got = read_photo_values(lwir, values="temperature", options={"temperature_preset": "cK"})
    expected = (raw.astype(float) - 27315.0) * 0.01
    np.testing.assert_allclose(got.values, expected, atol=1e-4)


def test_panel_calibration_and_a_panel_photo_without_a_panel(tmp_path):
    """[independent] reflectance = albedo · L / mean L(panel), the panel area from
    Camera:ReflectArea; a panel photo without that tag and without a region is refused."""
    rows, cols = np.mgrid[0:ROWS, 0:COLS]
    albedo, irradiance = 0.49, 0.5
    scene = np.full((ROWS, COLS), 0.12)
    scene[10:30, 20:44] = albedo                       # the panel
    panel_raw = micasense_raw_from_radiance(scene * irradiance / math.pi, 0.001, 1.0)
    area = {"Camera:ReflectArea": "22,12,22,28,42,28,42,12", "Camera:Albedo": albedo}
    panel = tmp_path / "IMG_0000_5.tif"
    write_micasense(panel, panel_raw, band="Red edge", exposure=0.001, iso=100, extra=area)
    field = 0.05 + 0.5 * cols / COLS
    flight_raw = micasense_raw_from_radiance(field * irradiance / math.pi, 0.0015, 1.0)
    flight = tmp_path / "IMG_0042_5.tif"
    write_micasense(flight, flight_raw, band="Red edge", exposure=0.0015, iso=100)  # no DLS at all
    got = reflectance_values(flight, options=ReflectanceOptions(panel_photos=(str(panel),)))
    assert got.valid.all() and np.abs(got.values - field).max() < 0.002
    assert "calibration panel IMG_0000_5.tif" in got.note
    # the albedo parameter wins over the tag, per band name in any spelling
    scaled = reflectance_values(flight, options=ReflectanceOptions(
        panel_photos=(str(panel),), panel_albedo={"RedEdge": 0.98}))
    np.testing.assert_allclose(scaled.values, got.values * 2, rtol=1e-5)
    bare = tmp_path / "IMG_0001_5.tif"
    write_micasense(bare, panel_raw, band="Red edge", exposure=0.001, iso=100)
    with pytest.raises(InputError, match=r"IMG_0001_5\.tif: a panel photo without a panel"):
        reflectance_values(flight, options=ReflectanceOptions(panel_photos=(str(bare),),
                                                              panel_albedo={"Red edge": 0.49}))
    region = reflectance_values(flight, options=ReflectanceOptions(
        panel_photos=(str(bare),), panel_albedo={"Red edge": albedo}, panel_region=(22, 12, 42, 28)))
    assert np.abs(region.values - field).max() < 0.002
    with pytest.raises(InputError, match=r"IMG_0042_5\.tif: no DLS irradiance.*panel"):
        reflectance_values(flight)


def test_captures_are_grouped_by_the_vendor_tags(tmp_path):
    """[independent] band files grouped by CaptureId (MicaSense) and by capture time (DJI), the
    band taken from the band tag whatever the file name says; a band twice is refused."""
    raw = np.full((8, 8), 9000, np.uint16)
    names = ["Blue", "Green", "Red", "NIR", "Red edge"]
    paths = []
    for capture in ("aaa", "bbb"):
        for k, band in enumerate(names):
            path = tmp_path / f"IMG_{capture}_{5 - k}.tif"          # file numbers reversed
            write_band_tiff(path, raw, xmp=xmp_packet(
                {"Camera:BandName": band, "MicaCamera:CaptureId": capture}, MICASENSE_NS),
                make="MicaSense", model="RedEdge-M")
            paths.append(path)
    for stamp in ("113000", "113002"):
        for band in ("G", "R", "RE", "NIR"):
            path = tmp_path / f"DJI_20240601{stamp}_0001_MS_{band}.TIF"
            write_dji(path, raw, band={"G": "Green", "R": "Red", "RE": "RedEdge", "NIR": "NIR"}[band],
                      when=f"2024:06:01 11:30:{stamp[-2:]}", mavic=True)
            paths.append(path)
    captures = group_captures(paths[::-1])
    assert len(captures) == 4
    by_key = {c.key: c.bands for c in captures}
    assert by_key["aaa"]["Blue"].endswith("IMG_aaa_5.tif") and by_key["bbb"]["Red edge"].endswith("IMG_bbb_1.tif")
    dji = [c for c in captures if c.key.startswith("2024")]
    assert all(sorted(band_key(b) for b in c.bands) == ["green", "nir", "red", "red_edge"] for c in dji)
    with pytest.raises(InputError, match=r"band 'Blue' of capture aaa is also in"):
        group_captures([paths[0], paths[0]])


def test_demo_multispectral_camera_reads_back_to_its_truth(demo, tmp_path):
    """[independent] of the reader: the demo's band files are written by the generator's own
    inverse of MicaSense's model (core/demo/multispectral.py) from its spectral model's
    reflectance; the product's reader recovers that reflectance pixel by pixel, glints masked,
    while the stored digital numbers differ between captures by the light and the settings."""
    from easyidp_toolbox.core.demo.multispectral import true_reflectance, write_multispectral_flight
    from easyidp_toolbox.core.photos import read_photo
    photos = demo.photos[10:14]
    flight = write_multispectral_flight(photos, tmp_path / "ms")
    captures = group_captures(sorted((tmp_path / "ms").iterdir()))
    assert len(captures) == 4 and all(sorted(c.bands) == ["NIR", "Red"] for c in captures)
    ratios = []
    for rec in flight:
        truth = true_reflectance(read_photo(rec["photo"]))
        for band, path in rec["files"].items():
            got = reflectance_values(path)
            assert 0 < (~got.valid).sum() < 0.01 * got.valid.size       # glints only
            err = np.abs(got.values - truth[band])[got.valid]
            assert err.mean() < 2e-4 and np.percentile(err, 99) < 2e-3, (path, err.mean())
        ratios.append(rec["exposure"]["NIR"] * rec["gain"]["NIR"] * rec["irradiance"]["NIR"]
                      / (rec["exposure"]["Red"] * rec["gain"]["Red"] * rec["irradiance"]["Red"]))
    assert max(ratios) / min(ratios) > 1.3
