"""Photos found as real photo sets leave them (issue 24): one lookup, core.photos, by file
stem and any case, over several folders, from Windows paths; moved, renamed and missing photos
each with a clear reason. Checks are by construction (files the test creates)."""
import os
import shutil

import pytest

from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.errors import InputError
from easyidp_toolbox.core.photos import PhotoFiles, photo_key, resolve_photos


def _touch(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"\xff\xd8")
    return path


def test_one_key_for_stem_case_extension_and_windows_paths():
    keys = {photo_key(n) for n in ("DJI_0018", "DJI_0018.JPG", "dji_0018.jpg", "DJI_0018.tif",
                                   "C:\\Flights\\A\\DJI_0018.JPG", "/data/x/DJI_0018.jpeg")}
    assert keys == {"dji_0018"}
    assert photo_key("100_0005_0018") == photo_key("100_0005_0018.tif") == "100_0005_0018"
    assert photo_key("IMG.001") == "img.001"          # not a photo extension: kept


def test_folder_matches_by_stem_and_case(tmp_path):
    _touch(tmp_path / "dji_0018.jpg")
    labels = ["DJI_0018", "DJI_0018.JPG", "a", "b"]
    paths = [None, None, "C:\\Users\\me\\Flight\\DJI_0018.JPG", "/old/disk/dji_0018.JPG"]
    found, missing = resolve_photos(labels, paths, tmp_path)
    assert set(found.values()) == {str(tmp_path / "dji_0018.jpg")} and len(found) == 4
    assert not missing


def test_photos_in_several_folders(tmp_path):
    a = _touch(tmp_path / "flight1" / "DJI_0001.JPG")
    b = _touch(tmp_path / "flight2" / "sub" / "DJI_0002.JPG")
    found, missing = resolve_photos(["DJI_0001.JPG", "DJI_0002.JPG", "DJI_0003.JPG"],
                                    [None] * 3, tmp_path)
    assert found == {"DJI_0001.JPG": str(a), "DJI_0002.JPG": str(b)}
    assert "DJI_0003.JPG is not in" in missing["DJI_0003.JPG"]
    found, _ = resolve_photos(["DJI_0001", "DJI_0002"], [None, None],
                              [tmp_path / "flight1", tmp_path / "flight2"])
    assert found == {"DJI_0001": str(a), "DJI_0002": str(b)}


def test_same_name_in_two_folders_decided_by_stored_folder_else_refused(tmp_path):
    _touch(tmp_path / "flight1" / "DJI_0001.JPG")
    two = _touch(tmp_path / "flight2" / "DJI_0001.JPG")
    found, _ = resolve_photos(["c"], ["D:\\survey\\Flight2\\DJI_0001.JPG"], tmp_path)
    assert found == {"c": str(two)}
    found, missing = resolve_photos(["DJI_0001", "x"], [None, "D:\\x\\flight2\\DJI_0001.JPG"],
                                    tmp_path)
    assert "ambiguous" in missing["DJI_0001"] and "flight1" in missing["DJI_0001"] \
        and "flight2" in missing["DJI_0001"]


def test_jpg_preferred_to_dng_in_one_folder(tmp_path):
    jpg = _touch(tmp_path / "DJI_0005.JPG")
    _touch(tmp_path / "DJI_0005.DNG")
    assert resolve_photos(["DJI_0005"], [None], tmp_path)[0] == {"DJI_0005": str(jpg)}
    dng = resolve_photos(["k"], ["/x/DJI_0005.DNG"], tmp_path)[0]["k"]
    assert dng.endswith("DJI_0005.DNG")                # the stored name wins


def test_stored_paths_moved_renamed_missing_windows(tmp_path):
    renamed = _touch(tmp_path / "images" / "dji_0007.jpg")
    _touch(tmp_path / "images" / "shot_1.tif")
    labels = ["renamed", "nokey", "moved", "gone", "win", "none"]
    paths = [str(tmp_path / "images" / "DJI_0007.JPG"), str(tmp_path / "images" / "shot_1"),
             str(tmp_path / "elsewhere" / "DJI_0008.JPG"), str(tmp_path / "images" / "DJI_0009.JPG"),
             "C:\\Survey\\DJI_0010.JPG", None]
    found, missing = resolve_photos(labels, paths)
    assert found == {"renamed": str(renamed), "nokey": str(tmp_path / "images" / "shot_1.tif")}
    assert "does not exist" in missing["moved"] and "give the photos folder" in missing["moved"]
    assert "moved or was deleted" in missing["gone"] and "DJI_0009.JPG" in missing["gone"]
    assert "Windows path" in missing["win"] and "C:\\Survey\\DJI_0010.JPG" in missing["win"]
    assert "stores no path" in missing["none"]


def test_folder_errors_name_the_folder(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        resolve_photos(["a"], [None], tmp_path / "nope")
    _touch(tmp_path / "other.jpg")
    with pytest.raises(InputError, match="holds none of the project's 1 photos"):
        resolve_photos(["DJI_0001.JPG"], [None], tmp_path)


def test_odm_shot_keys_without_extension_find_their_photos(realdata):
    """The real survey: shot keys ``100_0005_0018`` and photos ``100_0005_0018.tif``."""
    recon = open_reconstruction(realdata / "orthority_odm")
    assert all(os.path.isfile(c.photo_path) and c.photo_path.endswith(".tif")
               for c in recon.cameras)
    assert not any("in no reconstruction" in n for n in recon.notes)


def test_odm_photo_in_no_reconstruction_is_named(realdata, tmp_path):
    src = realdata / "orthority_odm"
    (tmp_path / "opensfm").mkdir()
    shutil.copy(src / "opensfm" / "reconstruction.json", tmp_path / "opensfm")
    (tmp_path / "odm_dem").mkdir()
    os.symlink(src / "odm_dem" / "dsm.tif", tmp_path / "odm_dem" / "dsm.tif")
    (tmp_path / "images").mkdir()
    for p in (src / "images").iterdir():            # renamed in another case
        os.symlink(p, tmp_path / "images" / p.name.upper())
    _touch(tmp_path / "images" / "EXTRA_0001.JPG")
    recon = open_reconstruction(tmp_path)
    assert all(os.path.isfile(c.photo_path) for c in recon.cameras)
    note = [n for n in recon.notes if "in no reconstruction" in n]
    assert len(note) == 1 and "1 photo(s)" in note[0] and "EXTRA_0001.JPG" in note[0]
    assert len(PhotoFiles(tmp_path / "images")) == 5


def test_camera_named_by_its_photo_file(realdata):
    """A tool given a photo name (``photo=``, annotations, a pixel layer's photo field) finds the
    camera by the same key: ``100_0005_0018.TIF`` is shot ``100_0005_0018``."""
    recon = open_reconstruction(realdata / "orthority_odm")
    assert recon.camera("100_0005_0018.TIF").label == "100_0005_0018"
    assert recon.camera("/elsewhere/100_0005_0140.tif").label == "100_0005_0140"
    with pytest.raises(Exception, match="no camera labelled"):
        recon.camera("100_0005_9999")


def test_pix4d_windows_image_paths_kept_and_reported(realdata, tmp_path):
    """A .p4d written on Windows: its absolute image paths are kept as written (not joined to
    the project folder) and reported as Windows paths; with a photos folder they are found by
    file name."""
    src = realdata / "easyidp" / "pix4d_origin" / "1_initial" / "params"
    shutil.copytree(src, tmp_path / "proj" / "1_initial" / "params")
    (tmp_path / "proj.p4d").write_text(
        '<pix4dmapper><inputs><images>'
        '<image path="C:\\Users\\me\\Flight\\DJI_0172.JPG"/>'
        '<image path="C:\\Users\\me\\Flight\\dji_0173.jpg"/>'
        '</images></inputs></pix4dmapper>')
    recon = open_reconstruction(tmp_path / "proj.p4d")
    cams = {c.label: c for c in recon.cameras}
    assert cams["DJI_0172.JPG"].photo_path == "C:\\Users\\me\\Flight\\DJI_0172.JPG"
    assert cams["DJI_0173.JPG"].photo_path.endswith("dji_0173.jpg")
    found, missing = resolve_photos(["DJI_0172.JPG"], [cams["DJI_0172.JPG"].photo_path])
    assert "Windows path" in missing["DJI_0172.JPG"]
    _touch(tmp_path / "photos" / "DJI_0172.jpg")
    found, _ = resolve_photos(["DJI_0172.JPG"], [cams["DJI_0172.JPG"].photo_path], tmp_path / "photos")
    assert found["DJI_0172.JPG"] == str(tmp_path / "photos" / "DJI_0172.jpg")


def test_photo_of_an_unlisted_type_found_by_its_whole_name(tmp_path):
    raw = _touch(tmp_path / "IMG_0001.ARW")
    _touch(tmp_path / "IMG_0001.json")                   # a sidecar is not the photo
    found, _ = resolve_photos(["IMG_0001.arw"], [None], tmp_path)
    assert found == {"IMG_0001.arw": str(raw)}
    with pytest.raises(InputError, match=r"looked for e\.g\. IMG_0001; it has IMG_0001\.ARW"):
        resolve_photos(["IMG_0001"], [None], tmp_path)   # neither the .ARW nor the .json
