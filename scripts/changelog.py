"""metadata.txt's ``version`` and ``changelog``, made from the one version source and CHANGELOG.md.

    python -m easyidp_toolbox.scripts.changelog [--check]     (make changelog)

The version is ``__version__`` in ``core/__init__.py`` (read as text: nothing is imported). The
changelog is CHANGELOG.md (Keep a Changelog): each released version up to that one, newest first,
becomes one line of ``metadata.txt``'s ``changelog``, ``<version> <entries joined by "; ">.``
(QGIS shows it in the plugin manager). ``--check`` changes nothing and exits 1 when
``metadata.txt`` is out of step; ``make package`` refuses to build then.
"""

import argparse
import re
import sys
from pathlib import Path
from typing import List, Tuple

ROOT = Path(__file__).resolve().parents[1]
_RELEASE = re.compile(r"^## \[(?P<version>[0-9][0-9.]*)\](?: - (?P<date>\d{4}-\d{2}-\d{2}))?\s*$")


def core_version(root: Path = ROOT) -> str:
    """``__version__`` of ``core/__init__.py``."""
    text = (root / "core" / "__init__.py").read_text(encoding="utf-8")
    match = re.search(r'^__version__ = "([^"]+)"$', text, re.MULTILINE)
    if not match:
        raise ValueError(f'{root / "core" / "__init__.py"} has no __version__ = "…" line')
    return match.group(1)


def releases(changelog: str) -> List[Tuple[str, List[str]]]:
    """[(version, entries)] of CHANGELOG.md's released versions, in the file's order (newest
    first); the Unreleased section is left out. An entry is a ``- `` bullet (continued on
    indented lines)."""
    out: List[Tuple[str, List[str]]] = []
    entries = None
    for line in changelog.splitlines():
        if line.startswith("## "):
            match = _RELEASE.match(line)
            entries = [] if match else None
            if match:
                out.append((match.group("version"), entries))
        elif entries is not None and line.startswith("- "):
            entries.append(line[2:].strip())
        elif entries is not None and entries and line.startswith("  ") and line.strip():
            entries[-1] += " " + line.strip()
    return out


def _key(version: str) -> Tuple[int, ...]:
    return tuple(int(p) for p in version.split("."))


def metadata_changelog(changelog: str, version: str) -> str:
    """The value of ``changelog=`` for ``version``: one line per release up to it."""
    lines = [
        f"{v} {'; '.join(e).rstrip('.')}."
        for v, e in releases(changelog)
        if _key(v) <= _key(version)
    ]
    if not lines or not lines[0].startswith(version + " "):
        raise ValueError(
            f"CHANGELOG.md has no section ## [{version}] - <date> for the version "
            "of core/__init__.py"
        )
    return "\n    ".join(lines)


def updated_metadata(metadata: str, version: str, changelog: str) -> str:
    """``metadata.txt``'s text with its ``version=`` and ``changelog=`` (and the changelog's
    continuation lines) replaced; everything else as it was."""
    value = metadata_changelog(changelog, version)
    out, skipping = [], False
    for line in metadata.splitlines():
        if skipping and line[:1] in (" ", "\t") and line.strip():
            continue
        skipping = False
        if line.startswith("version="):
            line = f"version={version}"
        elif line.startswith("changelog="):
            line, skipping = f"changelog={value}", True
        out.append(line)
    return "\n".join(out) + "\n"


def expected_metadata(root: Path = ROOT) -> Tuple[str, str]:
    """(metadata.txt as it is, as it should be)."""
    current = (root / "metadata.txt").read_text(encoding="utf-8")
    changelog = (root / "CHANGELOG.md").read_text(encoding="utf-8")
    return current, updated_metadata(current, core_version(root), changelog)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="only say whether it is in step")
    args = parser.parse_args(argv)
    try:
        current, wanted = expected_metadata()
    except (OSError, ValueError) as exc:
        print(f"ERROR: {exc}", file=sys.stderr)
        return 1
    if current == wanted:
        print("metadata.txt is in step with core.__version__ and CHANGELOG.md")
        return 0
    if args.check:
        print(
            "ERROR: metadata.txt is out of step with core.__version__ and CHANGELOG.md: run "
            "make changelog",
            file=sys.stderr,
        )
        return 1
    (ROOT / "metadata.txt").write_text(wanted, encoding="utf-8")
    print(f"metadata.txt: version {core_version()} and its changelog written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
