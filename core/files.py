"""Files: outputs written atomically and never over an input; output folders locked and checked;
JSON inputs read with clear errors.

Every output of the engine (GeoTIFF, point cloud, GeoPackage, JSON, PNG, JPEG) is written to a
hidden temporary file in the destination folder, ``.<stem>.<pid>-<thread>.part<suffix>``, and
renamed into place when complete. A failed or cancelled write removes its temporary file, so
only complete files ever carry their final name. The process id in the temporary name lets a
later run recognise the leftovers of a process that was killed.
"""
import errno
import json
import os
import re
import shutil
import socket
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterable, Iterator, List, Optional, Union

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
    except BaseException as exc:
        try:
            tmp.unlink()
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError) and exc.errno == errno.ENOSPC:
            raise InputError(f"No space left on the disk while writing {str(path)!r}; nothing "
                             "was left half-written. Free some space and run again.") from None
        raise


def write_bytes(path: PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with atomic_output(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_json(path: PathLike, obj, **dump_kw) -> Path:
    """Write ``obj`` as UTF-8 JSON to ``path`` atomically. (Encoded with ``json.dumps``: without
    ``indent`` that is the C encoder, several times faster than ``json.dump``'s.)"""
    text = json.dumps(obj, **dump_kw)
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(text)
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
        a_exists, b_exists = a.exists(), b.exists()
        if a_exists and b_exists:
            return os.path.samefile(a, b)
        if a_exists != b_exists:    # one exists, the other not: not one file (no resolve)
            return False
    except OSError:
        pass
    return a.resolve() == b.resolve()


def check_not_inputs(target: PathLike, inputs: Iterable[Optional[PathLike]]) -> None:
    """Raise :class:`InputError` if ``target`` would overwrite one of ``inputs``."""
    for src in inputs:
        if src is not None and same_file(target, src):
            raise InputError(f"The output {str(target)!r} is the input file itself: choose another "
                             "output file or folder; inputs are never overwritten.")


# ---- output folders: one run at a time, no leftovers, nothing replaced unasked -------------------
LOCK_NAME = ".easyidp.lock"
MIN_FREE_BYTES = 64 * 1024 * 1024
_PART = re.compile(r"^\..+\.(\d+)-\d+\.part(\.[^.]*)?$")


def is_part_name(name: str) -> bool:
    """Whether a file name is a temporary name of :func:`part_name` (a write in progress, or the
    leftover of a killed run)."""
    return _PART.match(os.path.basename(name)) is not None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:        # another user's process
        return True
    return True


def check_output_folder(folder: PathLike, what: str = "Output folder",
                        min_free: int = MIN_FREE_BYTES) -> Path:
    """Create ``folder`` if needed and check that a run can write there, before any work.

    Raises :class:`InputError` naming the folder when it is a file, cannot be created, is not
    writable (read-only file system, permissions) or has less than ``min_free`` bytes free.
    """
    folder = Path(os.path.abspath(os.fspath(folder)))
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{what} {str(folder)!r} is a file, not a folder: choose a folder.")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        why = "it is on a read-only file system" if exc.errno == errno.EROFS else \
            (exc.strerror or str(exc))
        raise InputError(f"{what} {str(folder)!r} cannot be created ({why}): "
                         "choose a folder you can write to.") from None
    probe = folder / f".easyidp-probe.{os.getpid()}-{threading.get_ident()}"
    try:
        with open(probe, "wb") as fh:
            fh.write(b"\0")
    except OSError as exc:
        why = {errno.EROFS: "it is on a read-only file system",
               errno.ENOSPC: "its disk is full"}.get(exc.errno, exc.strerror or str(exc))
        raise InputError(f"{what} {str(folder)!r} cannot be written to: {why}. Choose a folder "
                         "you can write to.") from None
    finally:
        try:
            probe.unlink()
        except OSError:
            pass
    free = shutil.disk_usage(folder).free
    if free < min_free:
        raise InputError(f"{what} {str(folder)!r} has only {free / 2**20:.1f} MiB free; the run "
                         f"needs at least {min_free / 2**20:.0f} MiB. Free some space or choose "
                         "another folder.")
    return folder


def remove_leftovers(folder: PathLike, depth: int = 3) -> List[Path]:
    """Remove what killed runs (process gone) left in ``folder`` and its subfolders down to
    ``depth`` levels (back-projection's crops sit in one folder per ROI, a training set's
    images three folders down): temporary ``.part`` files and the lock files of single outputs
    that no run holds; returns them. Temporary files of live processes, and locks that are
    held, are left alone."""
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        m = _PART.match(entry.name)
        if entry.is_dir(follow_symlinks=False):
            if depth > 0:
                removed += remove_leftovers(entry.path, depth - 1)
        elif m and int(m.group(1)) != os.getpid() and not _alive(int(m.group(1))):
            try:
                os.remove(entry.path)
                removed.append(Path(entry.path))
            except OSError:
                pass
        elif entry.name != LOCK_NAME and is_lock_name(entry.name):
            try:
                hold_lock(entry.path).release()        # not held: a killed run's; removed
                removed.append(Path(entry.path))
            except (LockHeld, OSError):
                pass
    return removed


class OutputFolder:
    """A folder a run writes many files into: checked before any work, locked against a second
    run writing into it at the same time, cleaned of the leftovers of killed runs, and guarded so
    that no file the run did not create is replaced unless ``overwrite``.

    >>> with OutputFolder("crops", inputs=["ortho.tif"]) as out:
    ...     paths = out.claim(["A1.tif", "A2.tif"])     # raises if any exists (or is an input)
    """

    def __init__(self, folder: PathLike, *, overwrite: bool = False,
                 inputs: Iterable[Optional[PathLike]] = (), what: str = "Output folder",
                 min_free: int = MIN_FREE_BYTES):
        self.folder = Path(os.path.abspath(os.fspath(folder)))
        self.overwrite, self.what, self.min_free = overwrite, what, min_free
        self.inputs = [Path(p) for p in inputs if p is not None]
        self.leftovers: List[Path] = []
        self._token = f"{os.getpid()}-{threading.get_ident()}-{time.time_ns()}"
        self._locked = False

    def __enter__(self) -> "OutputFolder":
        check_output_folder(self.folder, self.what, self.min_free)
        self._lock()
        self.leftovers = remove_leftovers(self.folder)
        return self

    def __exit__(self, *exc) -> None:
        self._unlock()

    # -- the lock ------------------------------------------------------------------------------
    def _lock(self) -> None:
        try:
            self._held = hold_lock(self.folder / LOCK_NAME, self._token)
        except LockHeld as held:
            raise InputError(
                f"Another EasyIDP run ({held.holder_text()}) is writing into "
                f"{str(self.folder)!r}. Wait for it to finish or choose another folder.") from None
        self._locked = True

    def _unlock(self) -> None:
        if self._locked:
            self._held.release()
            self._locked = False

    # -- output names ----------------------------------------------------------------------------
    def check_not_inputs(self, names: Iterable[str]) -> None:
        """Raise :class:`InputError` if one of ``names`` in the folder is an input."""
        for n in names:
            check_not_inputs(self.folder / n, self.inputs)

    def claim(self, names: Iterable[str]) -> List[Path]:
        """The paths of ``names`` in the folder, after checking that none is an input and, unless
        ``overwrite``, that none exists. Raises :class:`InputError` listing the conflicts before
        anything is written."""
        paths = [self.folder / n for n in names]
        self.check_not_inputs(p.name for p in paths)
        if not self.overwrite:
            taken = [p.name for p in paths if p.exists() or p.is_symlink()]
            if taken:
                shown = ", ".join(taken[:10]) + (f" and {len(taken) - 10} more" if len(taken) > 10 else "")
                raise InputError(
                    f"{len(taken)} output file(s) already exist in {str(self.folder)!r}: {shown}. "
                    "Nothing was written. Choose an empty folder, or allow replacing existing "
                    "outputs (overwrite; in QGIS the advanced option 'Overwrite existing files').")
        return paths


def _read_lock(path: Path) -> dict:
    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
        return data if isinstance(data, dict) else {}
    except (OSError, ValueError):
        return {}


# ---- exclusive locks: held by an open file, released by the system when the process dies -------
class LockHeld(Exception):
    """The lock is held by another run; ``holder`` is what that run wrote into the lock file."""

    def __init__(self, path: Path, holder: dict):
        super().__init__(str(path))
        self.path, self.holder = path, holder

    def holder_text(self) -> str:
        """'process 123 on host, since 2026-12-03 09:30:00' (what is known of the holder)."""
        h = self.holder
        return (f"process {h.get('pid', '?')} on {h.get('host', '?')}, since "
                f"{h.get('started', 'an unknown time')}")


def _try_lock(fd: int) -> bool:
    """Take an exclusive, non-blocking lock on the open file ``fd``: ``flock`` on POSIX (one per
    open file, so two runs in one process's threads exclude each other too), one byte far past
    the lock's text with ``msvcrt.locking`` on Windows. The system drops it when the process
    ends, however it ends, so a killed run's lock is never stale."""
    if os.name == "nt":                      # pragma: no cover (not run on this platform)
        import msvcrt
        os.lseek(fd, 1 << 30, os.SEEK_SET)
        try:
            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)
        except OSError:
            return False
        return True
    import fcntl
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        return False
    return True


class HeldLock:
    """A lock file held by this run (:func:`hold_lock`); :meth:`release` removes it."""

    def __init__(self, path: Path, fd: int):
        self.path, self.fd = path, fd

    def release(self) -> None:
        if self.fd < 0:
            return
        try:                                 # removed while still held: no one can take the
            os.unlink(self.path)             # old file after it is released
        except OSError:
            pass
        os.close(self.fd)
        self.fd = -1


def hold_lock(path: PathLike, run_id: Optional[str] = None) -> HeldLock:
    """Create (or take over) the lock file ``path`` and lock it exclusively, writing who holds it
    (process, host, start time) into it; raises :class:`LockHeld` when another run (another
    process, or another thread of this one) holds it. Exclusive by the system's file lock, not by
    checking first: of runs started together exactly one gets it. The lock file of a killed run
    is not locked any more and is simply taken over."""
    path = Path(path)
    for _ in range(20):
        fd = os.open(path, os.O_CREAT | os.O_RDWR, 0o644)
        if not _try_lock(fd):
            os.close(fd)
            raise LockHeld(path, _holder(path))
        try:                                 # its holder may have removed it between our open
            same = os.path.samestat(os.fstat(fd), os.stat(path))    # and our lock: try again
        except OSError:
            same = False
        if not same:
            os.close(fd)
            continue
        os.ftruncate(fd, 0)
        os.lseek(fd, 0, os.SEEK_SET)
        os.write(fd, json.dumps({"pid": os.getpid(), "host": socket.gethostname(), "run": run_id,
                                 "started": time.strftime("%Y-%m-%d %H:%M:%S")}).encode())
        return HeldLock(path, fd)
    raise LockHeld(path, {})


def _holder(path: Path, wait: float = 1.0) -> dict:
    """What the lock file says of its holder. A holder writes that just after taking the lock,
    so a run refused in between finds the file empty or half written: read again for up to
    ``wait`` s before giving up (then the message says the holder is unknown)."""
    deadline = time.monotonic() + wait
    while True:
        holder = _read_lock(path)
        if holder.get("pid") is not None or time.monotonic() > deadline:
            return holder
        time.sleep(0.02)


def file_lock_name(path: PathLike) -> Path:
    """The lock file of one output file: ``.<name>.easyidp.lock`` next to it."""
    p = Path(path)
    return p.with_name(f".{p.name}{LOCK_NAME}")


def is_lock_name(name: str) -> bool:
    """Whether a file name is one of the lock files (of a folder or of one output file)."""
    name = os.path.basename(name)
    return name == LOCK_NAME or (name.startswith(".") and name.endswith(LOCK_NAME))
