"""make realdata (scripts/realdata.py): files from a local folder, a mirror (file://) or their
public sources, each checked against its SHA-256 before it is written.

Truth kind: SHA-256 computed here with hashlib over bytes the test writes (independent of the
script's own checks); the real data folder, where present, against the manifest's pins.
"""

import hashlib
import subprocess
import sys
from pathlib import Path

import pytest

from easyidp_toolbox.scripts import realdata as rd

ROOT = Path(__file__).resolve().parents[2]


def _entries(source: Path, files: dict):
    """Write ``files`` ({name: bytes}) into ``source``; their manifest entries."""
    out = []
    for name, data in files.items():
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        (source / name).write_bytes(data)
        digest = hashlib.sha256(data).hexdigest()
        out.append(rd.Entry(name, "owner/repo", "0" * 40, f"data/{name}", digest))
    return out


FILES = {"a/dsm.tif": b"II*\x00" + bytes(range(256)) * 8, "b/plots.geojson": b'{"type": 1}'}


def test_the_manifest_pins_every_file():
    entries = rd.read_manifest()
    assert len(entries) == 40
    assert len({e.file for e in entries}) == len(entries)
    for e in entries:
        assert len(e.commit) == 40 and int(e.commit, 16) >= 0, e
        assert len(e.sha256) == 64 and int(e.sha256, 16) >= 0, e
        assert "/" in e.repo and not e.file.startswith("/") and ".." not in e.file, e
    assert {e.file.split("/")[0] for e in entries} == {
        "d2spy",
        "data-to-science",
        "easyidp",
        "laspy",
        "opensfm_berlin",
        "orthority_odm",
    }


def test_from_a_local_folder_then_kept(tmp_path):
    entries = _entries(tmp_path / "src", FILES)
    said = []
    assert rd.fetch(tmp_path / "dest", tmp_path / "src", entries=entries, say=said.append) == []
    for name, data in FILES.items():
        assert (tmp_path / "dest" / name).read_bytes() == data
    assert "2 files fetched, 0 already there" in said[-1]
    assert rd.fetch(tmp_path / "dest", tmp_path / "src", entries=entries, say=said.append) == []
    assert "0 files fetched, 2 already there" in said[-1]


def test_from_a_mirror_url(tmp_path):
    entries = _entries(tmp_path / "mirror", FILES)
    url = (tmp_path / "mirror").as_uri()
    assert rd.fetch(tmp_path / "dest", mirror=url, entries=entries, say=lambda _: None) == []
    assert (tmp_path / "dest" / "a" / "dsm.tif").read_bytes() == FILES["a/dsm.tif"]


def test_a_file_that_fails_its_checksum_is_not_written(tmp_path):
    entries = _entries(tmp_path / "src", FILES)
    (tmp_path / "src" / "a" / "dsm.tif").write_bytes(b"II*\x00 truncated")
    problems = rd.fetch(tmp_path / "dest", tmp_path / "src", entries=entries, say=lambda _: None)
    assert len(problems) == 1 and problems[0].startswith("a/dsm.tif: ")
    assert "has SHA-256" in problems[0] and entries[0].sha256 in problems[0]
    assert not (tmp_path / "dest" / "a").exists()  # nothing, not even a part file
    assert (tmp_path / "dest" / "b" / "plots.geojson").is_file()


def test_a_wrong_file_in_the_target_is_replaced(tmp_path):
    entries = _entries(tmp_path / "src", FILES)
    (tmp_path / "dest" / "b").mkdir(parents=True)
    (tmp_path / "dest" / "b" / "plots.geojson").write_bytes(b"edited by hand")
    assert rd.fetch(tmp_path / "dest", tmp_path / "src", entries=entries, say=lambda _: None) == []
    assert (tmp_path / "dest" / "b" / "plots.geojson").read_bytes() == FILES["b/plots.geojson"]


def test_missing_files_and_other_schemes_are_reported(tmp_path):
    entries = _entries(tmp_path / "src", FILES)
    (tmp_path / "src" / "b" / "plots.geojson").unlink()
    problems = rd.fetch(tmp_path / "dest", tmp_path / "src", entries=entries, say=lambda _: None)
    assert [p.split(":")[0] for p in problems] == ["b/plots.geojson"]
    problems = rd.fetch(
        tmp_path / "d2", mirror="ftp://host/x", entries=entries[:1], say=lambda _: None
    )
    assert "only https://, http:// and file://" in problems[0]


def test_a_bad_manifest_line_is_refused(tmp_path):
    path = tmp_path / "m.tsv"
    path.write_text("# comment\nd/x.tif\towner/repo\tabc\tx.tif\n")
    with pytest.raises(ValueError, match=r"m.tsv:2: expected file, repository, commit"):
        rd.read_manifest(path)


def test_make_realdata_from_the_shared_copy(realdata, tmp_path):
    """The command make realdata runs, from a local copy of the real data (the network here
    reaches no git host): every file of the manifest, checksums as pinned."""
    run = subprocess.run(
        [
            sys.executable,
            str(ROOT / "scripts" / "realdata.py"),
            "--to",
            str(tmp_path / "data"),
            "--from",
            str(realdata),
        ],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    assert "40 files fetched, 0 already there, 0 failed (of 40)" in run.stdout
    for e in rd.read_manifest():
        data = (tmp_path / "data" / e.file).read_bytes()
        assert (
            hashlib.sha256(data).hexdigest()
            == e.sha256
            == hashlib.sha256((realdata / e.file).read_bytes()).hexdigest()
        )
