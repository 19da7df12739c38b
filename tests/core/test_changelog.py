"""CHANGELOG.md, core.__version__ and metadata.txt stay in step (scripts/changelog.py)."""

import configparser
from pathlib import Path

import pytest

from easyidp_toolbox import core
from easyidp_toolbox.scripts import changelog

ROOT = Path(__file__).resolve().parents[2]


def _metadata(text: str) -> dict:
    parser = configparser.ConfigParser(interpolation=None)
    parser.optionxform = str
    parser.read_string(text)
    return dict(parser.items("general"))


def test_metadata_is_made_from_the_changelog_and_the_version():
    current, wanted = changelog.expected_metadata(ROOT)
    assert current == wanted, "metadata.txt is out of step: run make changelog"
    meta = _metadata(current)
    assert meta["version"] == core.__version__ == changelog.core_version(ROOT)
    assert meta["changelog"].startswith(core.__version__ + " ")


def test_the_changelog_has_every_release_newest_first():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    assert text.startswith("# Changelog\n") and "## [Unreleased]" in text
    versions = [v for v, _ in changelog.releases(text)]
    assert versions[-3:] == ["0.3.0", "0.2.0", "0.1.0"]
    keys = [tuple(int(p) for p in v.split(".")) for v in versions]
    assert keys == sorted(keys, reverse=True) and core.__version__ in versions
    assert all(entries for _, entries in changelog.releases(text))


CHANGES = """# Changelog

## [Unreleased]
### Added
- not yet

## [1.1.0] - 2027-01-02
### Added
- two
  continued
### Fixed
- three.

## [1.0.0] - 2027-01-01
- one
"""
META = "[general]\nname=X\nversion=0.9\nchangelog=0.9 old\n    0.8 older\nicon=i.svg\n"


def test_updated_metadata_replaces_version_and_changelog_only():
    text = changelog.updated_metadata(META, "1.1.0", CHANGES)
    assert text == (
        "[general]\nname=X\nversion=1.1.0\n"
        "changelog=1.1.0 two continued; three.\n    1.0.0 one.\nicon=i.svg\n"
    )
    assert _metadata(text)["changelog"] == "1.1.0 two continued; three.\n1.0.0 one."
    older = changelog.updated_metadata(META, "1.0.0", CHANGES)
    assert "changelog=1.0.0 one.\n" in older and "1.1.0" not in older


def test_a_version_without_its_section_is_refused():
    with pytest.raises(ValueError, match=r"no section ## \[1.2.0\]"):
        changelog.updated_metadata(META, "1.2.0", CHANGES)
