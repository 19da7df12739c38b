"""The faults real photo sets bring (issue 24), each with its handled case or message: photos
resized from the sensor's size, 16-bit and multiband TIFFs, DJI thermal R-JPEGs, EXIF-rotated
photos. Built on the real ODM survey (realdata/orthority_odm) and photos derived from it in the
test; checks by construction (OpenSfM calibrations are normalised by the image size, so a
5472×3648 camera is exactly 4× the 1368×912 one; 16-bit photos are 257× the 8-bit ones)."""
import json
import os

import numpy as np
import pytest
import tifffile

from easyidp_toolbox.tests.support import real_survey as rs
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.projection import back_project, photo_statistics, read_photo
from easyidp_toolbox.core.raster import DSM
from easyidp_toolbox.core.projection.ortho import orthorectify_rois


@pytest.fixture(scope="module")
def folder(realdata):
    return realdata / "orthority_odm"


def _odm_with_camera_size(folder, tmp_path, width, height, images=None):
    """The survey with its camera's size in reconstruction.json changed (photos as they are)."""
    (tmp_path / "opensfm").mkdir(parents=True)
    rec = json.loads((folder / "opensfm" / "reconstruction.json").read_text())
    for cam in rec[0]["cameras"].values():
        cam["width"], cam["height"] = width, height
    (tmp_path / "opensfm" / "reconstruction.json").write_text(json.dumps(rec))
    os.symlink(folder / "odm_dem", tmp_path / "odm_dem")
    os.symlink(images or folder / "images", tmp_path / "images")
    return tmp_path


def test_resized_photos_scale_the_calibration(folder, tmp_path):
    """By construction: the project says 5472×3648 (the FC6310R sensor), the photos are stored
    at 1368×912: the calibration is scaled by 1/4, said in the notes, and back-projection gives
    the same pixels as the project made for the stored size."""
    dsm = str(folder / "odm_dem" / "dsm.tif")
    big = open_reconstruction(_odm_with_camera_size(folder, tmp_path, 5472, 3648))
    assert any("resized copies (×0.25)" in n and "5472×3648" in n for n in big.notes)
    assert {(s.width, s.height) for s in big.sensors.values()
            if any(c.sensor_id == s.id for c in big.cameras)} == {(1368, 912)}
    orig = open_reconstruction(folder)
    a = back_project(rs.roi_set(), big, heights=DSM(dsm))
    b = back_project(rs.roi_set(), orig, heights=DSM(dsm))
    assert len(a) == len(b)
    for i in range(len(a)):
        np.testing.assert_allclose(a.rings_of(i)[0], b.rings_of(i)[0], atol=1e-6)


def test_photos_of_another_aspect_are_refused_naming_both_sizes(folder, tmp_path):
    recon = open_reconstruction(_odm_with_camera_size(folder, tmp_path / "p", 5472, 3000))
    assert any("1368×912 px but the sensor is 5472×3000 px, another aspect ratio" in n
               for n in recon.notes)
    with pytest.raises(InputError) as e:
        orthorectify_rois(rs.roi_set(), recon, str(folder / "odm_dem" / "dsm.tif"),
                          tmp_path / "o", selection="photo", photo="100_0005_0140")
    assert "1368×912 px but the camera's sensor is 5472×3000, another aspect ratio" in str(e.value)


def _sixteen_bit_multiband(folder, out):
    """Each photo as a 16-bit, 4-band TIFF (R, G, B × 257 and a synthetic NIR = 2·G·257 capped),
    half of them stored band-sequential (planar), named in upper case with .TIFF."""
    out.mkdir()
    for k, p in enumerate(sorted((folder / "images").iterdir())):
        rgb = read_photo(p).astype(np.uint16) * 257
        nir = np.minimum(rgb[..., 1].astype(np.uint32) * 2, 65535).astype(np.uint16)
        img = np.dstack([rgb, nir])
        name = out / (p.stem.upper() + ".TIFF")
        if k % 2:
            tifffile.imwrite(name, np.moveaxis(img, -1, 0), photometric="minisblack",
                             planarconfig="separate")
        else:
            tifffile.imwrite(name, img, photometric="minisblack", planarconfig="contig")
    return out


def test_sixteen_bit_multiband_photos(folder, tmp_path):
    """By construction: statistics of the 16-bit 4-band copies are 257 × those of the 8-bit
    photos (red, green, blue), NDVI comes from the named nir band, orthorectified images keep
    16 bits and 4 bands (+ alpha)."""
    dsm = str(folder / "odm_dem" / "dsm.tif")
    recon = open_reconstruction(folder)
    bp = back_project(rs.roi_set(), recon, heights=DSM(dsm), min_visible=0.0)
    photos16 = _sixteen_bit_multiband(folder, tmp_path / "p16")
    st8 = photo_statistics(bp, statistics=("mean",))
    st16 = photo_statistics(bp, photos_folder=photos16, bands=["red", "green", "blue", "nir"],
                            statistics=("mean",))
    for b in ("red", "green", "blue"):
        np.testing.assert_allclose(st16.values[:, st16.columns.index(f"{b}_mean")],
                                   257 * st8.values[:, st8.columns.index(f"{b}_mean")], rtol=1e-9)
    assert "ndvi_mean" in st16.columns and np.isfinite(st16.values[:, st16.columns.index("ndvi_mean")]).all()
    res = orthorectify_rois(rs.roi_set(), recon, dsm, tmp_path / "o", photos_folder=photos16)
    img = tifffile.imread(res.files[0])
    assert img.dtype == np.uint16 and img.shape[2] == 5


def _jpeg_with(img, make=None, orientation=None, app3_segments=0):
    """A JPEG of ``img`` (imagecodecs) with an EXIF block (Make, Orientation) and DJI-style
    APP3 segments (where DJI R-JPEGs keep the raw thermal data) inserted after SOI."""
    import struct
    import imagecodecs
    body = imagecodecs.jpeg_encode(img, level=95)
    entries = []
    if make is not None:
        raw = make.encode() + b"\x00"
        entries.append((0x010F, 2, len(raw), raw))
    if orientation is not None:
        entries.append((0x0112, 3, 1, struct.pack(">HH", orientation, 0)))
    ifd, extra = b"", b""
    base = 8 + 2 + 12 * len(entries) + 4
    for tag, typ, n, val in entries:
        if len(val) <= 4:
            ifd += struct.pack(">HHI", tag, typ, n) + val.ljust(4, b"\x00")
        else:
            ifd += struct.pack(">HHII", tag, typ, n, base + len(extra))
            extra += val
    tiff = b"MM\x00\x2a" + struct.pack(">I", 8) + struct.pack(">H", len(entries)) + ifd + \
        b"\x00\x00\x00\x00" + extra
    app1 = b"Exif\x00\x00" + tiff
    segs = b"\xff\xe1" + struct.pack(">H", len(app1) + 2) + app1
    for _ in range(app3_segments):
        payload = bytes(60000)
        segs += b"\xff\xe3" + struct.pack(">H", len(payload) + 2) + payload
    return body[:2] + segs + body[2:]


def _photos_as_jpeg(folder, out, **kw):
    out.mkdir()
    for p in sorted((folder / "images").iterdir()):
        (out / (p.stem + ".JPG")).write_bytes(_jpeg_with(read_photo(p), **kw))
    return out


def test_dji_thermal_rjpeg_is_said_to_be_a_palette(folder, tmp_path):
    """A DJI R-JPEG (EXIF Make DJI, APP3 thermal segments): measured as the colours it stores,
    and the notes say plainly that they are a palette, not temperatures; an ordinary DJI JPEG
    (no APP3) gets no such note."""
    from easyidp_toolbox.core.photos import jpeg_facts
    dsm = str(folder / "odm_dem" / "dsm.tif")
    recon = open_reconstruction(folder)
    bp = back_project(rs.roi_set(), recon, heights=DSM(dsm), min_visible=0.0)
    rj = _photos_as_jpeg(folder, tmp_path / "rjpeg", make="DJI", app3_segments=11)
    assert jpeg_facts(next(rj.iterdir()))["thermal"] is True
    st = photo_statistics(bp, photos_folder=rj, statistics=("mean",))
    note = [n for n in st.notes if "R-JPEG" in n]
    assert len(note) == 1 and "palette" in note[0] and "not temperatures" in note[0]
    assert np.isfinite(st.median).any()
    plain = _photos_as_jpeg(folder, tmp_path / "plain", make="DJI")
    assert not any("R-JPEG" in n for n in photo_statistics(bp, photos_folder=plain,
                                                           statistics=("mean",)).notes)


def test_exif_rotated_photos_are_read_as_stored(folder, tmp_path):
    """Stated behaviour: a photo with EXIF orientation 6 is decoded as stored (912 rows ×
    1368 columns, the pixels the project measured), not turned upright, and the notes say so."""
    from easyidp_toolbox.core.photos import jpeg_facts
    dsm = str(folder / "odm_dem" / "dsm.tif")
    recon = open_reconstruction(folder)
    bp = back_project(rs.roi_set(), recon, heights=DSM(dsm), min_visible=0.0)
    rot = _photos_as_jpeg(folder, tmp_path / "rot", make="DJI", orientation=6)
    first = sorted(rot.iterdir())[0]
    assert jpeg_facts(first)["orientation"] == 6
    assert read_photo(first).shape == (912, 1368, 3)
    st = photo_statistics(bp, photos_folder=rot, statistics=("mean",))
    assert any("EXIF orientation [6]" in n and "read as stored" in n for n in st.notes)
