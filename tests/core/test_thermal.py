"""Thermal photos in °C (core/radiometry): FLIR radiometric JPEGs (raw PNG and raw TIFF), the
Planck conversion, temperature TIFFs, DJI R-JPEGs and the bad inputs."""
import struct

import numpy as np
import pytest
import tifffile

from easyidp_toolbox.core.demo.flir_writer import write_flir_jpeg
from easyidp_toolbox.core.errors import EasyIDPError, InputError
from easyidp_toolbox.tests.support.planck_reference import planck_by_hand
from easyidp_toolbox.core.radiometry import (TEMPERATURE_PRESETS, PhotoValues, ThermalParameters,
                                             celsius_to_raw, read_flir, read_photo_values)

# a Vue Pro R's constants (of the order exiftool shows for these cameras)
CAMERA = dict(r1=17096.453, r2=0.046642166, b=1428.0, f=1.0, o=-342.0)
PHOTO = dict(emissivity=0.96, object_distance=30.0, reflected_temperature=18.5,
             atmospheric_temperature=24.0, relative_humidity=0.6)


def field(h=96, w=128):
    """A canopy-like temperature field, °C: rows warmer, a cool wet patch, a hot soil strip."""
    yy, xx = np.mgrid[0:h, 0:w]
    t = 22.0 + 6.0 * np.sin(xx / 9.0) * np.cos(yy / 13.0) + yy / 40.0
    t[20:40, 30:60] -= 4.0
    t[:, 100:110] += 15.0
    return t


def write(tmp_path, encoding, t=None, name=None, **kw):
    p = ThermalParameters(**CAMERA, **PHOTO)
    t = field() if t is None else t
    raw = np.round(celsius_to_raw(t, p)).astype(np.uint16)
    path = tmp_path / (name or f"flir_{encoding}.jpg")
    write_flir_jpeg(path, raw, p, encoding=encoding, when="2026:06:01 11:30:15", subsec="250",
                    utc_offset="+09:00", **kw)
    return path, raw, t


@pytest.mark.parametrize("encoding", ["png", "tiff"])
def test_flir_conversion_against_second_planck(tmp_path, encoding):
    """[independent] Every pixel's °C equals Thermimage's formula written out in this test,
    with the photo's parameters and with each object parameter overridden; and the written
    field comes back to within a raw count."""
    path, raw, t = write(tmp_path, encoding)
    v = read_photo_values(path, values="temperature")
    assert isinstance(v, PhotoValues) and v.unit == "degC" and v.bands == ("temp_c",)
    assert v.values.dtype == np.float32 and v.valid.all() and f"({encoding})" in v.note
    p32 = {k: float(np.float32(val)) for k, val in {**CAMERA, **PHOTO}.items()}  # as stored
    rows = np.random.default_rng(3).integers(0, raw.shape[0], 200)
    cols = np.random.default_rng(4).integers(0, raw.shape[1], 200)
    want = [planck_by_hand(float(raw[r, c]), p32["r1"], p32["r2"], p32["b"], p32["f"], p32["o"],
                           p32["emissivity"], p32["object_distance"],
                           p32["reflected_temperature"],
                           p32["atmospheric_temperature"], p32["relative_humidity"])
            for r, c in zip(rows, cols)]
    np.testing.assert_allclose(v.values[rows, cols], want, atol=2e-4)
    # one raw count is about 0.03 °C here: the truth comes back within it
    assert np.abs(v.values - t).max() < 0.03
    opts = dict(emissivity=0.98, object_distance=5.0, reflected_temperature=-10.0,
                atmospheric_temperature=30.0, relative_humidity=80, ir_window_temperature=35.0,
                ir_window_transmission=0.8)
    w = read_photo_values(path, values="temperature", options=opts)
    want = [planck_by_hand(float(raw[r, c]), p32["r1"], p32["r2"], p32["b"], p32["f"], p32["o"],
                           0.98, 5.0, -10.0, 30.0, 0.8, 35.0, 0.8) for r, c in zip(rows, cols)]
    np.testing.assert_allclose(w.values[rows, cols], want, atol=2e-4)
    assert "emissivity 0.98" in w.note and "window 0.8 at 35.00" in w.note


def test_flyr_reads_what_we_write(tmp_path):
    """[independent] flyr 5.1.0 (a separate FLIR reader) decodes the raw-PNG photo to the same
    raw values, and its own Planck conversion agrees with ours to 0.01 °C (flyr carries a
    273.17 in its humidity term); on the XT2's raw TIFF it fails, as the issue reports, where
    we read it (on our file it does not raise: it takes the TIFF's bytes for raw values)."""
    import flyr
    path, raw, t = write(tmp_path, "png")
    th = flyr.unpack(str(path))
    ours = read_flir(path, path.read_bytes())
    np.testing.assert_array_equal(ours.raw, raw)
    np.testing.assert_allclose(th.celsius, read_photo_values(path, values="temperature").values,
                               atol=0.01)
    tpath, traw, _ = write(tmp_path, "tiff")
    with np.errstate(invalid="ignore"):
        misread = flyr.unpack(str(tpath)).celsius     # flyr takes the TIFF's bytes as values
    assert not np.allclose(misread, read_photo_values(tpath, values="temperature").values, atol=1)
    np.testing.assert_array_equal(read_flir(tpath, tpath.read_bytes()).raw, traw)


def test_saturated_pixels_masked(tmp_path):
    """[independent] Pixels at the camera's raw range limits (and 0, 65535) are invalid, the
    others valid: the mask is set by the written raw values, not by our conversion."""
    p = ThermalParameters(**CAMERA, **PHOTO)
    raw = np.round(celsius_to_raw(field(), p)).astype(np.uint16)
    raw[0, :5] = 65535
    raw[1, :5] = 0
    raw[2, :5] = 3900                       # at the range's top: saturated
    path = tmp_path / "sat.jpg"
    write_flir_jpeg(path, raw, p, raw_range=(1000, 3900))
    v = read_photo_values(path, values="temperature")
    bad = np.zeros(raw.shape, bool)
    bad[:3, :5] = True
    bad |= (raw >= 3900) | (raw <= 1000)
    np.testing.assert_array_equal(~v.valid, bad)


def test_damaged_flir_photo(tmp_path):
    """[independent] A FLIR JPEG whose second record segment is lost, and one whose records
    are cut short: a message naming the photo and what to do, no traceback of the parser."""
    noisy = np.tile(field(), (4, 4)) + np.random.default_rng(1).normal(0, 3, (384, 512))
    path, _, _ = write(tmp_path, "png", t=noisy)
    data = path.read_bytes()
    k = data.index(b"FLIR\x00\x01\x01")                     # segment 1 of several
    (n,) = struct.unpack(">H", data[k - 2:k])
    (tmp_path / "lost.jpg").write_bytes(data[:k - 4] + data[k - 2 + n:])
    with pytest.raises(InputError, match=r"lost\.jpg.*FLIR raw data cannot be read.*missing"):
        read_photo_values(tmp_path / "lost.jpg", values="temperature")
    cut = bytearray(data)
    j = data.index(b"FFF\x00")
    struct.pack_into(">I", cut, j + 0x1C, 40)               # 40 directory entries: past the end
    (tmp_path / "cut.jpg").write_bytes(bytes(cut))
    with pytest.raises(InputError, match=r"cut\.jpg.*cannot be read.*temperature TIFF"):
        read_photo_values(tmp_path / "cut.jpg", values="temperature")


def _jpeg_with(tmp_path, name, make, app3):
    from PIL import Image
    import io
    ex = Image.Exif()
    ex[0x010F] = make
    ex[0x0110] = "ZH20T"
    buf = io.BytesIO()
    Image.fromarray(np.zeros((8, 8, 3), np.uint8)).save(buf, "JPEG", exif=ex.tobytes())
    data = buf.getvalue()
    seg = b"\xff\xe3" + struct.pack(">H", 2 + 64) + bytes(64) if app3 else b""
    (tmp_path / name).write_bytes(data[:2] + seg + data[2:])
    return tmp_path / name


def test_dji_rjpeg_and_plain_jpeg(tmp_path):
    """[independent] A DJI R-JPEG (EXIF Make DJI, raw data in APP3, as the H20T writes) gets the
    one line saying what to do; a JPEG with neither FLIR nor DJI records says it holds no
    temperatures; a PNG is refused."""
    dji = _jpeg_with(tmp_path, "DJI_0001_T.JPG", "DJI", True)
    with pytest.raises(InputError, match=r"DJI_0001_T\.JPG: DJI thermal R-JPEG.*dji_irp.*folder"):
        read_photo_values(dji, values="temperature")
    plain = _jpeg_with(tmp_path, "plain.jpg", "Canon", False)
    with pytest.raises(InputError, match="plain.jpg holds no temperatures"):
        read_photo_values(plain, values="temperature")
    import imagecodecs
    (tmp_path / "x.png").write_bytes(imagecodecs.png_encode(np.zeros((4, 4), np.uint8)))
    with pytest.raises(InputError, match="neither a FLIR radiometric JPEG nor a TIFF"):
        read_photo_values(tmp_path / "x.png", values="temperature")


@pytest.mark.parametrize("preset,dtype,stored", [
    ("degC", np.float32, lambda t: t),
    ("K", np.float32, lambda t: t + 273.15),
    ("ddegC", np.int16, lambda t: np.round(t * 10)),
    ("mdegC", np.int32, lambda t: np.round(t * 1000)),
    ("cK", np.uint16, lambda t: np.round((t + 273.15) * 100)),
])
def test_temperature_tiffs(tmp_path, preset, dtype, stored):
    """[independent] Temperature TIFFs as converters write them, read in °C by preset and by
    the same scale and offset given as numbers; the quantisation of each format bounds the
    error. Nodata and integer extremes are invalid."""
    t = field()
    arr = stored(t).astype(dtype)
    if arr.dtype.kind in "iu":
        arr[0, 0] = np.iinfo(dtype).max
    else:
        arr[0, 0] = np.nan
    path = tmp_path / f"t_{preset}.tif"
    tifffile.imwrite(path, arr)
    v = read_photo_values(path, values="temperature", options={"temperature_preset": preset})
    scale, offset, _ = TEMPERATURE_PRESETS[preset]
    assert not v.valid[0, 0] and v.valid.sum() == t.size - 1
    tol = {"degC": 1e-5, "K": 3e-5, "ddegC": 0.051, "mdegC": 6e-4, "cK": 0.006}[preset]
    assert np.abs(v.values[v.valid] - t[v.valid]).max() < tol
    w = read_photo_values(path, values="temperature",
                          options={"temperature_scale": scale, "temperature_offset": offset})
    np.testing.assert_array_equal(w.values[w.valid], v.values[v.valid])
    # GDAL's nodata tag
    path2 = tmp_path / "nodata.tif"
    f = t.astype(np.float32)
    f[5, 5] = -9999
    tifffile.imwrite(path2, f, extratags=[(42113, "s", 0, "-9999", True)])
    assert not read_photo_values(path2, values="temperature").valid[5, 5]


def test_bad_options_and_values(tmp_path):
    """[independent] Bad object parameters, presets, scales and value kinds each get their
    message; reflectance is not part of this build."""
    path, _, _ = write(tmp_path, "png")
    for opts, msg in [({"emissivity": 0}, "Emissivity 0"), ({"emissivity": "x"}, "number"),
                      ({"ir_window_transmission": 1.5}, "window transmission"),
                      ({"relative_humidity": 150}, "humidity"),
                      ({"object_distance": -1}, "negative")]:
        with pytest.raises(EasyIDPError, match=msg):
            read_photo_values(path, values="temperature", options=opts)
    tif = tmp_path / "t.tif"
    tifffile.imwrite(tif, field().astype(np.float32))
    with pytest.raises(EasyIDPError, match="Unknown temperature preset"):
        read_photo_values(tif, values="temperature", options={"temperature_preset": "F"})
    with pytest.raises(EasyIDPError, match="scale must be a finite number other than 0"):
        read_photo_values(tif, values="temperature", options={"temperature_scale": 0})
    with pytest.raises(EasyIDPError, match="Unknown values"):
        read_photo_values(tif, values="radiance")
    from easyidp_toolbox.core import radiometry
    if radiometry.reflectance_values is None:      # until the multispectral readers are merged
        with pytest.raises(EasyIDPError, match="reflectance: not in this build"):
            read_photo_values(tif, values="reflectance")
    s = read_photo_values(tif)
    assert s.unit == "stored" and s.values.dtype == np.float32 and s.valid.all()
