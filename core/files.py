"""Files: outputs written atomically and never over an input; JSON inputs read with clear errors.

Every output of the engine (GeoTIFF, point cloud, GeoPackage, JSON, PNG, JPEG) is written to a
hidden temporary file in the destination folder, ``.<stem>.<pid>-<thread>.part<suffix>``, and
renamed into place when complete. A failed or cancelled write removes its temporary file, so
only complete files ever carry their final name. The process id in the temporary name lets a
later run recognise the leftovers of a process that was killed.
"""
import json
import os
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator, Optional, Union

from .errors import InputError

PathLike = Union[str, "os.PathLike[str]"]


def part_name(path: PathLike) -> Path:
    """The temporary name used while ``path`` is being written (same folder, same suffix, so
    format sniffing by suffix still works)."""
    p = Path(path)
    stem, suffix = (p.stem, p.suffix) if p.suffix else (p.name, "")
    return p.with_name(f".{stem}.{os.getpid()}-{threading.get_ident()}.part{suffix}")


@contextmanager
def atomic_output(path: PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; when the block ends without error it replaces
    ``path``, otherwise it is removed.

    >>> with atomic_output("out.json") as tmp:
    ...     tmp.write_text("{}")
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"The output folder {str(path.parent)!r} does not exist: create it first.")
    tmp = part_name(path)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except FileNotFoundError:
            pass
        raise


def write_bytes(path: PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with atomic_output(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_json(path: PathLike, obj, **dump_kw) -> Path:
    """Write ``obj`` as UTF-8 JSON to ``path`` atomically."""
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            json.dump(obj, fh, **dump_kw)
    return Path(path)


def load_json(path: PathLike, what: str):
    """The parsed JSON document at ``path`` (UTF-8, a BOM allowed). ``what`` names the expected
    kind in messages, e.g. "GeoJSON"; a missing file or bad JSON raises :class:`InputError`."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"{what} file not found: {path}")
    try:
        with open(path, "rb") as fh:
            return json.loads(fh.read().decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"{path} is not valid {what} ({exc}).") from None


def same_file(a: PathLike, b: Optional[PathLike]) -> bool:
    """True when ``a`` and ``b`` name the same existing file (or the same resolved path)."""
    if b is None:
        return False
    a, b = Path(a), Path(b)
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def check_not_inputs(target: PathLike, inputs: Iterable[Optional[PathLike]]) -> None:
    """Raise :class:`InputError` if ``target`` would overwrite one of ``inputs``."""
    for src in inputs:
        if src is not None and same_file(target, src):
            raise InputError(f"The output {str(target)!r} is the input file itself: choose another "
                             "output file or folder; inputs are never overwritten.")
