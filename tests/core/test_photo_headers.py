"""Photo headers read with Pillow (core/photos/headers.py, issue 39): sizes, EXIF Make and
Orientation, DJI thermal R-JPEGs, and the camera tags of JPEGs, against files written by other
software. [independent]: JPEGs and PNGs encoded by OpenCV (libjpeg/libpng, not Pillow) with EXIF
blocks built here byte by byte (a second TIFF/EXIF writer, written in the test), JPEGs whose EXIF
GDAL wrote (its own EXIF writer) and read back by GDAL, and the real OpenDroneMap photos
(GDAL-written TIFFs, sizes as GDAL reads them). Damaged headers and a missing Pillow are said
plainly.
"""
import struct
import subprocess
import sys
import textwrap

import cv2
import numpy as np
import pytest

from easyidp_toolbox.core.photos import (DJI, jpeg_facts, photo_notes, photo_size,
                                         read_photo_tags)

XMP = (b'<x:xmpmeta xmlns:x="adobe:ns:meta/"><rdf:RDF '
       b'xmlns:rdf="http://www.w3.org/1999/02/22-rdf-syntax-ns#"><rdf:Description '
       b'xmlns:drone-dji="http://www.dji.com/drone-dji/1.0/" drone-dji:GimbalYawDegree="+12.5"'
       b'/></rdf:RDF></x:xmpmeta>')


def _exif(order: str, make: str, orientation: int) -> bytes:
    """An EXIF APP1 payload: TIFF header and IFD0 with Make (ASCII: in the entry when it fits
    in 4 bytes, else after the IFD) and Orientation (SHORT, in the entry), written from the
    TIFF 6.0 layout."""
    o = "<" if order == "II" else ">"
    text = make.encode("ascii") + b"\x00"
    ifd = struct.pack(o + "H", 2)
    value_at = 8 + 2 + 2 * 12 + 4
    if len(text) <= 4:                          # fits the value field: stored there
        ifd += struct.pack(o + "HHI", 0x010F, 2, len(text)) + text.ljust(4, b"\x00")
        text = b""
    else:
        ifd += struct.pack(o + "HHII", 0x010F, 2, len(text), value_at)
    ifd += struct.pack(o + "HHIH2x", 0x0112, 3, 1, orientation)
    ifd += struct.pack(o + "I", 0)
    return b"Exif\x00\x00" + order.encode() + struct.pack(o + "HI", 42, 8) + ifd + text


def _segment(marker: int, payload: bytes) -> bytes:
    return bytes([0xFF, marker]) + struct.pack(">H", len(payload) + 2) + payload


def _opencv_jpeg(path, width, height, *segments):
    """A JPEG encoded by OpenCV, ``segments`` (marker, payload) inserted after its SOI."""
    img = (np.indices((height, width)).sum(0) % 256).astype(np.uint8)
    ok, data = cv2.imencode(".jpg", np.dstack([img, 255 - img, img // 2]))
    assert ok
    data = data.tobytes()
    path.write_bytes(data[:2] + b"".join(_segment(m, p) for m, p in segments) + data[2:])
    return path


@pytest.mark.parametrize("order", ["II", "MM"])
def test_opencv_jpeg_with_exif_built_here(tmp_path, order):
    """[independent] Size from OpenCV's SOF (37×23, not square), Make and Orientation from an
    EXIF block written here, APP3 segments as DJI's R-JPEG keeps them: read as written."""
    path = _opencv_jpeg(tmp_path / "DJI_0001.JPG", 37, 23, (0xE1, _exif(order, "DJI Tech", 6)),
                        (0xE1, b"http://ns.adobe.com/xap/1.0/\x00" + XMP),
                        (0xE3, b"\x00" * 64), (0xE3, b"\x01" * 64))
    assert photo_size(path) == (37, 23)
    assert jpeg_facts(path) == {"make": "DJI Tech", "orientation": 6, "thermal": True}
    tags = read_photo_tags(path)
    assert (tags.size, tags.kind) == ((37, 23), "jpeg")
    assert tags.exif["Make"] == "DJI Tech" and tags.exif["Orientation"] == 6
    short = _opencv_jpeg(tmp_path / "short.jpg", 5, 3, (0xE1, _exif(order, "DJI", 3)))
    assert jpeg_facts(short) == {"make": "DJI", "orientation": 3, "thermal": False}
    assert tags.xmp_float(DJI, "GimbalYawDegree") == 12.5
    notes = photo_notes([str(path)])
    assert any("R-JPEG" in n for n in notes) and any("EXIF orientation [6]" in n for n in notes)


def test_dji_xmp_without_exif_make_and_no_app3(tmp_path):
    """[independent] DJI's XMP and no EXIF: the maker is DJI; no APP3: not a thermal R-JPEG; no
    Orientation: 1 (upright as stored)."""
    path = _opencv_jpeg(tmp_path / "a.jpg", 16, 9,
                        (0xE1, b"http://ns.adobe.com/xap/1.0/\x00" + XMP))
    assert jpeg_facts(path) == {"make": "DJI", "orientation": 1, "thermal": False}
    assert photo_notes([str(path)]) == []


def test_opencv_png_and_other_formats(tmp_path):
    """[independent] A PNG encoded by OpenCV: its IHDR size; a BMP: not told (None), as before;
    jpeg_facts of a PNG: {} (not a JPEG)."""
    img = np.zeros((11, 29, 3), np.uint8)
    cv2.imwrite(str(tmp_path / "p.png"), img)
    cv2.imwrite(str(tmp_path / "p.bmp"), img)
    assert photo_size(tmp_path / "p.png") == (29, 11)
    assert photo_size(tmp_path / "p.bmp") is None
    assert jpeg_facts(tmp_path / "p.png") == {}


def test_damaged_headers(tmp_path):
    """Damaged headers: a truncated JPEG and a file that only starts like one give no size
    and no facts; a damaged EXIF block (not TIFF data) is as none (Make unknown, Orientation 1)
    as read_photo_tags reads it; a missing file gives no size."""
    good = _opencv_jpeg(tmp_path / "good.jpg", 40, 30, (0xE1, _exif("II", "DJI", 3)))
    (tmp_path / "cut.jpg").write_bytes(good.read_bytes()[:40])
    (tmp_path / "soi.jpg").write_bytes(b"\xff\xd8")
    bad_exif = _opencv_jpeg(tmp_path / "bad_exif.jpg", 40, 30,
                            (0xE1, b"Exif\x00\x00XX" + b"\x07" * 20))
    for name in ("cut.jpg", "soi.jpg"):
        assert photo_size(tmp_path / name) is None
        assert jpeg_facts(tmp_path / name) == {}
    assert photo_size(bad_exif) == (40, 30)
    assert jpeg_facts(bad_exif) == {"make": "", "orientation": 1, "thermal": False}
    tags = read_photo_tags(bad_exif)
    assert tags.size == (40, 30) and "Make" not in tags.exif
    assert photo_size(tmp_path / "absent.jpg") is None


def test_missing_pillow_is_said(tmp_path):
    """Without Pillow (its import blocked, as the plugin meets a Python without it), reading a
    JPEG's header says what to install, naming the photo, instead of failing with an
    ImportError or returning nothing."""
    path = _opencv_jpeg(tmp_path / "DJI_0002.JPG", 8, 8)
    script = textwrap.dedent(f"""
        import importlib.abc, sys
        class Block(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path, target=None):
                if name.split(".")[0] == "PIL":
                    raise ImportError("blocked " + name)
        sys.meta_path.insert(0, Block())
        from easyidp_toolbox.core.errors import EasyIDPError
        from easyidp_toolbox.core.photos import jpeg_facts, photo_size
        for fn in (photo_size, jpeg_facts):
            try:
                fn({str(path)!r})
            except EasyIDPError as exc:
                print(exc)
        """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         check=True, cwd=tmp_path,
                         env=_env_with_package()).stdout.strip().splitlines()
    assert len(out) == 2
    assert all("DJI_0002.JPG" in line and "Pillow" in line and "pip install pillow" in line
               for line in out)


def _env_with_package():
    """The environment of this test run, with the folder holding ``easyidp_toolbox`` on the
    path (as the test session imports it)."""
    import os

    import easyidp_toolbox
    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.abspath(easyidp_toolbox.__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    return env


@pytest.mark.gdal
def test_gdal_written_jpeg_exif(tmp_path):
    """[independent] A JPEG whose EXIF GDAL wrote from EXIF_* metadata items: the size, Make,
    Model, Orientation and FocalLength as GDAL reads them back."""
    from osgeo import gdal
    gdal.UseExceptions()
    mem = gdal.GetDriverByName("MEM").Create("", 53, 31, 3, gdal.GDT_Byte)
    for b in range(3):
        mem.GetRasterBand(b + 1).WriteArray(np.full((31, 53), 40 * b, np.uint8))
    mem.SetMetadata({"EXIF_Make": "DJI", "EXIF_Model": "FC6310R", "EXIF_Orientation": "8",
                     "EXIF_FocalLength": "(8.8)"})
    path = str(tmp_path / "gdal.jpg")
    gdal.GetDriverByName("JPEG").CreateCopy(path, mem)
    back = gdal.Open(path)
    meta = back.GetMetadata()
    assert photo_size(path) == (back.RasterXSize, back.RasterYSize) == (53, 31)
    facts = jpeg_facts(path)
    assert (facts["make"], facts["orientation"]) == (meta["EXIF_Make"], int(meta["EXIF_Orientation"]))
    tags = read_photo_tags(path)
    assert tags.exif["Model"] == meta["EXIF_Model"]
    assert tags.exif_float("FocalLength") == pytest.approx(float(meta["EXIF_FocalLength"][1:-1]))


@pytest.mark.gdal
def test_real_gdal_tiffs_sizes(realdata):
    """[independent] The real OpenDroneMap photos (GDAL-written TIFFs, EXIF in tag 42112, XMP in
    tag 700): their size as GDAL reads it, and their tags still read from those two tags."""
    from osgeo import gdal
    gdal.UseExceptions()
    paths = sorted((realdata / "orthority_odm" / "images").glob("*.tif"))
    assert len(paths) == 4
    for p in paths:
        ds = gdal.Open(str(p))
        assert photo_size(p) == (ds.RasterXSize, ds.RasterYSize)
        tags = read_photo_tags(p)
        assert tags.kind == "gdal-tiff" and tags.exif["Make"] == ds.GetMetadataItem("EXIF_Make")
        assert tags.xmp_float(DJI, "GimbalYawDegree") is not None
