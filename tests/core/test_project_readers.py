"""The project readers' registry (core/reconstruction/readers.py): who recognises what, the
precedence where two readers recognise the same folder, and the message for a path nobody
recognises."""
import importlib
import pkgutil

import numpy as np
import pytest

from easyidp_toolbox.core import InputError, open_reconstruction
from easyidp_toolbox.core import reconstruction
from easyidp_toolbox.core.reconstruction import metashape, odm, opf, photo_folder, pix4d
from easyidp_toolbox.core.reconstruction.readers import READERS, reader_for

NAMES = ["Metashape", "OpenDroneMap / OpenSfM", "OPF (PIX4Dmatic)", "Photos", "Pix4D"]


def test_the_registry_lists_every_reader_module_once_in_its_order():
    """[consistency only] Every module of core/reconstruction that defines a READER is in
    READERS, and the precedence is the one readers.py documents."""
    found = []
    for info in pkgutil.iter_modules(reconstruction.__path__):
        module = importlib.import_module(f"{reconstruction.__name__}.{info.name}")
        if hasattr(module, "READER"):
            found.append(module.READER)
    assert sorted(r.name for r in found) == sorted(r.name for r in READERS)
    assert [r.name for r in READERS] == NAMES
    assert READERS == (metashape.READER, odm.READER, opf.READER, photo_folder.READER,
                       pix4d.READER)


def test_nobody_recognises_says_what_each_reader_expects(tmp_path):
    """A file no reader recognises, and a folder that is no project (a text file and a
    subfolder): the message names the path and lists every kind with what it expects."""
    (tmp_path / "x.txt").write_text("hi")
    folder = tmp_path / "stuff"
    (folder / "sub").mkdir(parents=True)
    (folder / "notes.txt").write_text("hi")
    for path in (tmp_path / "x.txt", folder):
        with pytest.raises(InputError) as err:
            open_reconstruction(path)
        text = str(err.value)
        assert text.startswith(f"{path}: not a photogrammetry project I can read"), text
        for name, wants in zip(NAMES, (".psx", "reconstruction.json", "project.opf",
                                       "folder of JPEG/TIFF", "params folder")):
            assert f"\n- {name}: " in text and wants in text, (name, text)
    with pytest.raises(InputError, match="nothing.bin: file not found") as err:
        open_reconstruction(tmp_path / "nothing.bin")
    assert err.value.key == "project_not_found"          # the plugin translates it
    (tmp_path / "poses.csv").write_text("name,x,y,z\n")
    with pytest.raises(InputError, match="poses.csv: a table of camera positions"):
        open_reconstruction(tmp_path / "poses.csv")


def _odm_folder_with_more(realdata, folder):
    """The real ODM project (symlinked) in ``folder``, with an OPF project file and a Pix4D
    params file beside its opensfm/ (another tool's output in the same folder)."""
    folder.mkdir()
    for name in ("images", "odm_dem", "opensfm"):
        (folder / name).symlink_to(realdata / "orthority_odm" / name, target_is_directory=True)
    (folder / "project.opf").write_text("{}")
    (folder / "other_pmatrix.txt").write_text("")
    return folder


def test_an_odm_folder_that_other_readers_also_recognise_is_odms(realdata, tmp_path):
    """[independent truth: the real ODM project opened alone] OPF and Pix4D recognise the folder
    too; ODM comes first in READERS, so the same cameras are read as from the project alone."""
    folder = _odm_folder_with_more(realdata, tmp_path / "odm")
    assert odm.READER.recognises(folder) and opf.READER.recognises(folder)
    assert pix4d.READER.recognises(folder) and not photo_folder.READER.recognises(folder)
    assert reader_for(folder) is odm.READER
    alone = open_reconstruction(realdata / "orthority_odm")
    mixed = open_reconstruction(folder)
    assert [c.label for c in mixed.cameras] == [c.label for c in alone.cameras]
    assert mixed.crs == alone.crs
    for a, b in zip(alone.cameras, mixed.cameras):
        np.testing.assert_array_equal(a.R, b.R)
        np.testing.assert_array_equal(a.C, b.C)


def test_precedence_of_the_other_overlaps(tmp_path):
    """An OPF project folder that also holds a .p4d is OPF's; photos with a stray Pix4D offset
    file are the photos' (both recognise the folder), but photos beside a pmatrix file are
    Pix4D's (the photo reader leaves it); a list of paths is the photos'."""
    both = tmp_path / "both"
    both.mkdir()
    (both / "project.opf").write_text("{}")
    (both / "old.p4d").write_text("<pix4dmapper/>")
    assert opf.READER.recognises(both) and pix4d.READER.recognises(both)
    assert reader_for(both) is opf.READER
    params = tmp_path / "params_and_photos"
    params.mkdir()
    (params / "IMG_0001.JPG").write_bytes(b"")
    assert reader_for(params) is photo_folder.READER
    (params / "p_offset.xyz").write_text("0 0 0\n")
    assert pix4d.READER.recognises(params) and reader_for(params) is photo_folder.READER
    (params / "p_pmatrix.txt").write_text("")
    assert not photo_folder.READER.recognises(params) and reader_for(params) is pix4d.READER
    assert reader_for(params / "p_offset.xyz") is pix4d.READER      # a file of a params folder
    assert reader_for([params / "IMG_0001.JPG"]) is photo_folder.READER
    named = tmp_path / "survey"                  # a Pix4D project folder beside its .p4d
    (named / "other").mkdir(parents=True)
    (tmp_path / "survey.p4d").write_text("<pix4dmapper/>")
    assert reader_for(named) is pix4d.READER
    for name, reader in (("a.PSX", metashape.READER), ("a.psz", metashape.READER),
                         ("cams.xml", metashape.READER), ("r.json", odm.READER),
                         ("p.opf", opf.READER), ("p.p4d", pix4d.READER)):
        (tmp_path / name).write_text("")
        assert reader_for(tmp_path / name) is reader, name
