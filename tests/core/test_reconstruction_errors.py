"""Bad input: every message names the file and says what is missing."""
import shutil
import zipfile

import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core.reconstruction.pix4d import read_pmatrix


@pytest.fixture(scope="module")
def ms(realdata):
    return realdata / "easyidp" / "metashape"


@pytest.fixture(scope="module")
def params(realdata):
    return realdata / "easyidp" / "pix4d_origin" / "1_initial" / "params"


def _chunk_doc(ms):
    with zipfile.ZipFile(ms / "wheat_tanashi.files" / "0" / "chunk.zip") as z:
        return z.read("doc.xml").decode()


def _project(tmp_path, chunk_xml: str, name="p"):
    tmp_path.mkdir(parents=True, exist_ok=True)
    (tmp_path / f"{name}.psx").write_text('<document version="1.2.0" path="{projectname}.files/project.zip"/>')
    files = tmp_path / f"{name}.files"
    (files / "0").mkdir(parents=True)
    for rel, doc in (("project.zip", '<document><chunks><chunk id="0" path="0/chunk.zip"/></chunks></document>'),
                     ("0/chunk.zip", chunk_xml)):
        with zipfile.ZipFile(files / rel, "w") as z:
            z.writestr("doc.xml", doc)
    return tmp_path / f"{name}.psx"


def test_psx_without_files_folder(tmp_path, ms):
    psx = tmp_path / "lonely.psx"
    shutil.copy(ms / "wheat_tanashi.psx", psx)
    with pytest.raises(InputError, match=r"lonely\.psx.*lonely\.files.*is missing"):
        open_reconstruction(psx)


def test_zip_without_doc_xml(tmp_path, ms):
    psx = _project(tmp_path, _chunk_doc(ms))
    with zipfile.ZipFile(tmp_path / "p.files" / "0" / "chunk.zip", "w") as z:
        z.writestr("other.xml", "<x/>")
    with pytest.raises(InputError, match=r"chunk\.zip: no doc\.xml inside"):
        open_reconstruction(psx)


def test_chunk_without_aligned_cameras(tmp_path, ms):
    import re
    doc = re.sub(r"<transform>[^<]*</transform>", "", _chunk_doc(ms))
    psx = _project(tmp_path, doc)
    with pytest.raises(InputError, match=r"chunk\.zip: chunk 'Chunk 1' has no aligned cameras"):
        open_reconstruction(psx)


@pytest.mark.parametrize("kind", ["fisheye", "spherical"])
def test_unsupported_camera_type(tmp_path, ms, kind):
    psx = _project(tmp_path, _chunk_doc(ms).replace('type="frame">', f'type="{kind}">', 1))
    with pytest.raises(InputError, match=rf"chunk\.zip: sensor 'FC550.*'{kind}' camera model"):
        open_reconstruction(psx)


def test_malformed_numbers_in_metashape(tmp_path, ms):
    psx = _project(tmp_path, _chunk_doc(ms).replace("<f>4785.3046873759595</f>", "<f>4785,30</f>"))
    with pytest.raises(InputError, match=r"chunk\.zip: <f> of sensor .* not a number"):
        open_reconstruction(psx)
    psx2 = _project(tmp_path / "b", _chunk_doc(ms).replace("<transform>9.9893510694370191e-01 ",
                                                            "<transform>", 1))
    with pytest.raises(InputError, match=r"chunk\.zip: <transform> of camera 'DJI_0001' should hold 16"):
        open_reconstruction(psx2)


def _pix4d_copy(tmp_path, params, drop=(), edit=None):
    for f in params.iterdir():
        if any(f.name.endswith(d) for d in drop):
            continue
        (tmp_path / f.name).write_bytes(f.read_bytes())
    if edit:
        name, old, new = edit
        p = next(tmp_path.glob("*" + name))
        p.write_text(p.read_text().replace(old, new, 1))
    return tmp_path


def test_pix4d_without_offset(tmp_path, params):
    folder = _pix4d_copy(tmp_path, params, drop=("_offset.xyz",))
    with pytest.raises(InputError, match=rf"{tmp_path}: no \*_offset\.xyz"):
        open_reconstruction(folder, source_crs="EPSG:32654")


def test_pix4d_without_pmatrix(tmp_path, params):
    folder = _pix4d_copy(tmp_path, params, drop=("_pmatrix.txt", "_calibrated_camera_parameters.txt"))
    with pytest.raises(InputError, match=rf"{tmp_path}: no \*_pmatrix\.txt"):
        open_reconstruction(folder, source_crs="EPSG:32654")


def test_pix4d_malformed_numbers(tmp_path, params):
    folder = _pix4d_copy(tmp_path, params, edit=("_pmatrix.txt", "4436.465963", "4436.46x"))
    with pytest.raises(InputError, match=r"_pmatrix\.txt, line 1: expected numbers"):
        read_pmatrix(next(folder.glob("*_pmatrix.txt")))
    (tmp_path / "b").mkdir()
    folder2 = _pix4d_copy(tmp_path / "b", params)
    p = next(folder2.glob("*_calibrated_camera_parameters.txt"))
    p.write_text(p.read_text().replace("0.02006588392682263564", "nan(", 1))
    with pytest.raises(InputError, match=r"_calibrated_camera_parameters\.txt, line 13: expected numbers"):
        open_reconstruction(folder2, source_crs="EPSG:32654")
    off = next(folder2.glob("*_offset.xyz"))
    off.write_text("368109.000 3956043.000")
    with pytest.raises(InputError, match=r"_offset\.xyz: expected three numbers"):
        open_reconstruction(folder2, source_crs="EPSG:32654")


def test_unknown_path_and_unknown_crs(tmp_path, params):
    with pytest.raises(InputError, match="nothing.psx: file not found"):
        open_reconstruction(tmp_path / "nothing.psx")
    (tmp_path / "x.txt").write_text("hi")
    with pytest.raises(InputError, match=r"x\.txt: not a photogrammetry project"):
        open_reconstruction(tmp_path / "x.txt")
    r = open_reconstruction(params)                   # no _wkt.prj: CRS unknown, said so
    assert r.crs is None and any("CRS is unknown" in n for n in r.notes)
    with pytest.raises(Exception, match="project's CRS is unknown"):
        r.project_points(np.array([[139.5, 35.7, 100.0]]), "EPSG:4326")


def test_pix4d_rig_without_calibrated_camera_parameters(tmp_path, params):
    """A pmatrix-only params folder whose .cam file holds two camera models (a multispectral
    rig, one model per band) is refused: nothing says which band file uses which lens (without
    the check every band would silently take the last model's distortion)."""
    folder = _pix4d_copy(tmp_path, params, drop=("_calibrated_camera_parameters.txt",))
    cam = next(folder.glob("*_pix4d_calibrated_internal_camera_parameters.cam"))
    text = cam.read_text()
    cam.write_text(text + "\n" + text.replace("camera_calibration_file 0", "camera_calibration_file 1"))
    with pytest.raises(InputError, match=r"\.cam: 2 camera models \(a multi-camera rig.*calibrated camera parameters"):
        open_reconstruction(folder, source_crs="EPSG:32654")
