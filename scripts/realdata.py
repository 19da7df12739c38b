"""The real test data, fetched from its public sources at pinned commits and checked file by file.

    python3 scripts/realdata.py [--to DIR] [--from DIR | --mirror URL]     (make realdata)

The files come from other projects, under their own licences, and stay out of this tree.
``requirements/realdata.tsv`` lists each one: its place in the data folder, the public repository
and the commit it comes from, its path there, and its SHA-256. They go to ``--to`` (default:
``EASYIDP_REALDATA``, else ``../shared/realdata`` beside this clone: where the tests look).

Sources, one of:
- the repositories themselves (default): each file's raw content at its pinned commit;
- ``--mirror URL``: a copy of the data folder served at ``URL`` (``URL/<file>``; ``https://``,
  ``http://`` or ``file://``);
- ``--from DIR``: a local folder with the data folder's layout (another clone's
  ``../shared/realdata``, a USB stick).

Every file is checked against its SHA-256 before it is written; a file already there with the
right checksum is kept. A file that fails the check, or cannot be read, is not written, and the
run lists every such file and exits with status 1. Each file is written to a temporary name
and renamed, so an interrupted run leaves only whole files. Standard library only: it runs with
any Python 3 before any environment exists.
"""

import argparse
import hashlib
import os
import sys
import tempfile
import urllib.request
from pathlib import Path
from typing import List, NamedTuple, Optional

ROOT = Path(__file__).resolve().parents[1]
MANIFEST = ROOT / "requirements" / "realdata.tsv"
RAW = "https://raw.githubusercontent.com/{repo}/{commit}/{path}"
TIMEOUT = 60  # seconds per file


class Entry(NamedTuple):
    file: str  # path in the data folder, with /
    repo: str
    commit: str
    path: str  # path in the repository at the commit
    sha256: str


def read_manifest(path: Path = MANIFEST) -> List[Entry]:
    entries = []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        parts = line.split("\t")
        if len(parts) != 5 or len(parts[4]) != 64 or ".." in parts[0].split("/"):
            raise ValueError(
                f"{path}:{number}: expected file, repository, commit, path and "
                f"SHA-256 separated by tabs, found {line!r}"
            )
        entries.append(Entry(*parts))
    return entries


def default_target() -> Path:
    return Path(os.environ.get("EASYIDP_REALDATA") or ROOT.parent / "shared" / "realdata")


def _sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _read(entry: Entry, source: Optional[Path], mirror: Optional[str]) -> bytes:
    if source is not None:
        return (source / entry.file).read_bytes()
    if mirror is not None:
        url = mirror.rstrip("/") + "/" + entry.file
    else:
        url = RAW.format(repo=entry.repo, commit=entry.commit, path=entry.path)
    if not url.startswith(("https://", "http://", "file://")):
        raise ValueError(f"{url}: only https://, http:// and file:// addresses are read")
    with urllib.request.urlopen(url, timeout=TIMEOUT) as response:  # nosec B310 -- scheme checked above
        return response.read()


def _where(entry: Entry, source: Optional[Path], mirror: Optional[str]) -> str:
    if source is not None:
        return str(source / entry.file)
    if mirror is not None:
        return mirror.rstrip("/") + "/" + entry.file
    return f"{entry.repo}@{entry.commit[:12]}:{entry.path}"


def _write(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def fetch(
    target: Path,
    source: Optional[Path] = None,
    mirror: Optional[str] = None,
    entries: Optional[List[Entry]] = None,
    say=print,
) -> List[str]:
    """Bring every file of ``entries`` (default: the manifest) into ``target``; returns the
    problems (empty: every file is there with its checksum)."""
    entries = read_manifest() if entries is None else entries
    problems, fetched, kept = [], 0, 0
    for entry in entries:
        dest = target / entry.file
        if dest.is_file() and _sha256(dest.read_bytes()) == entry.sha256:
            kept += 1
            continue
        where = _where(entry, source, mirror)
        try:
            data = _read(entry, source, mirror)
        except (OSError, ValueError) as exc:
            problems.append(f"{entry.file}: cannot read {where}: {exc}")
            continue
        got = _sha256(data)
        if got != entry.sha256:
            problems.append(
                f"{entry.file}: {where} has SHA-256 {got}, expected {entry.sha256}; not written"
            )
            continue
        _write(dest, data)
        fetched += 1
    say(
        f"{target}: {fetched} files fetched, {kept} already there, {len(problems)} failed "
        f"(of {len(entries)})"
    )
    return problems


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--to",
        type=Path,
        default=None,
        help="the data folder to fill (default: EASYIDP_REALDATA, else ../shared/realdata)",
    )
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--from", dest="source", type=Path, help="a local folder with the data")
    group.add_argument("--mirror", help="a URL serving the data folder's layout")
    args = parser.parse_args(argv)
    target = args.to or default_target()
    if args.source is not None and not args.source.is_dir():
        print(f"ERROR: {args.source} is not a folder", file=sys.stderr)
        return 2
    problems = fetch(target, args.source, args.mirror)
    for problem in problems:
        print(f"ERROR: {problem}", file=sys.stderr)
    if problems and args.source is None and args.mirror is None:
        print(
            "The public sources could not all be reached: use --from DIR or --mirror URL "
            "(make realdata REALDATA_FROM=DIR or REALDATA_MIRROR=URL).",
            file=sys.stderr,
        )
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
