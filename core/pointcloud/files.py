"""Atomic output files: write to a temporary file in the destination folder, then ``os.replace``.

A failed or cancelled write never leaves a half-written file under the final name, and an input
file is never overwritten.
"""
import os
import uuid
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator, Optional

from ..errors import InputError


def same_file(a: Path, b: Optional[Path]) -> bool:
    """True when ``a`` and ``b`` name the same existing file (or the same resolved path)."""
    if b is None or not a.exists():
        return False
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def check_not_inputs(target: Path, inputs: Iterable[Optional[Path]]) -> None:
    """Raise :class:`InputError` if ``target`` would overwrite one of ``inputs``."""
    for src in inputs:
        if src is not None and same_file(Path(target), Path(src)):
            raise InputError(f"The output {str(target)!r} is the input file itself: choose another "
                             "output file or folder; inputs are never overwritten.")


@contextmanager
def atomic_target(path: Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; on success it replaces ``path``, on error it is
    removed. The temporary name keeps the final suffix so format sniffing still works."""
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"The output folder {str(path.parent)!r} does not exist: create it first.")
    tmp = path.with_name(f".{path.stem}.{uuid.uuid4().hex[:8]}.part{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except FileNotFoundError:
            pass
        raise
