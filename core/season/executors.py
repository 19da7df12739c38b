"""Where the season's jobs run: a local process pool, or a Dask cluster.

* Local (default): :class:`concurrent.futures.ProcessPoolExecutor` with ``workers`` processes,
  started with *spawn* (never fork: QGIS and GDAL hold threads and locks that a fork would copy).
* Dask: ``dask.distributed.Client(address)`` for a running scheduler (``tcp://host:port``), or a
  ``LocalCluster`` of ``workers`` processes on this machine (one thread each, loopback only, no
  dashboard). Dask reschedules the job of a worker that dies on another worker, so the result
  is complete and identical.

Both give futures with ``done()``, ``result()`` and ``cancel()``; :func:`wait_any` polls them so
that a cancel request is seen within a fraction of a second.
"""
import logging
import multiprocessing
import os
import sys
import time
import uuid
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from typing import Iterator, List, Optional

from ..errors import EasyIDPError

POLL_SECONDS = 0.05
CONNECT_TIMEOUT = "20s"          # to reach a Dask scheduler
DASK_HINT = ("Install Dask for the Python that runs EasyIDP: pip install \"dask[distributed]\" "
             "(Debian/Ubuntu: apt install python3-distributed).")


class Runner:
    """A started executor: ``submit(fn, arg, key)`` → future. ``label`` says what it is."""
    label = ""
    workers: Optional[int] = None   # processes, when known

    def submit(self, fn, arg, key: str):
        raise NotImplementedError


class LocalRunner(Runner):
    def __init__(self, pool: ProcessPoolExecutor, workers: int):
        self.pool, self.workers = pool, workers
        self.label = f"{workers} local process{'es' if workers > 1 else ''}"

    def submit(self, fn, arg, key: str):
        return self.pool.submit(fn, arg)


class DaskRunner(Runner):
    def __init__(self, client, label: str, workers: Optional[int]):
        self.client, self.label, self.workers = client, label, workers
        self._token = uuid.uuid4().hex[:8]

    def submit(self, fn, arg, key: str):
        # pure=False: every run computes afresh; a unique key per run and job
        return self.client.submit(fn, arg, key=f"easyidp-{self._token}-{key}", pure=False)


def python_executable() -> str:
    """The Python interpreter for worker processes: this one. Inside QGIS ``sys.executable`` is
    the QGIS program, or whatever ``python3`` comes first on PATH (another Python, whose
    standard library would clash); so take the interpreter of the running Python's own
    installation, and ``sys.executable`` only when it is that one (a virtual environment's)."""
    version = f"{sys.version_info.major}.{sys.version_info.minor}"
    base = sys.base_exec_prefix
    own = ([os.path.join(base, "python.exe"), os.path.join(sys.exec_prefix, "python.exe")]
           if os.name == "nt" else
           [os.path.join(base, "bin", f"python{version}"), os.path.join(base, "bin", "python3")])
    own = [c for c in own if os.path.isfile(c)]
    exe = sys.executable or ""
    if exe and os.path.realpath(exe) in {os.path.realpath(c) for c in own}:
        return exe
    if own:
        return own[0]
    if os.path.basename(exe).lower().startswith("python"):
        return exe
    raise EasyIDPError(f"No Python interpreter found to start worker processes (the running "
                       f"program is {exe!r}, its Python is installed in {base!r}). Run with one "
                       "worker, or on a Dask cluster.")


def _spawn_context():
    exe = python_executable()
    if exe != sys.executable:
        multiprocessing.set_executable(exe)   # spawn (and Dask's nannies) start this interpreter
    return multiprocessing.get_context("spawn")


@contextmanager
def open_runner(workers: Optional[int] = None, scheduler: Optional[str] = None,
                local_cluster: bool = False, log=None) -> Iterator[Runner]:
    """A runner for the season: Dask when ``scheduler`` (an address) or ``local_cluster`` is
    given, else a local process pool of ``workers`` processes (default: the cores)."""
    workers = max(1, int(workers or os.cpu_count() or 1))
    if not scheduler and not local_cluster:
        pool = ProcessPoolExecutor(max_workers=workers, mp_context=_spawn_context())
        try:
            yield LocalRunner(pool, workers)
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
        return
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise EasyIDPError(f"Running on Dask needs the 'distributed' package ({exc}). "
                           f"{DASK_HINT}") from None
    _spawn_context()
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as exc:
            raise EasyIDPError(f"Cannot reach the Dask scheduler at {scheduler!r} ({exc}). Start "
                               "one with `dask scheduler` and workers with `dask worker "
                               "tcp://HOST:8786`, and give its tcp://HOST:PORT address.") from None
        label = f"Dask scheduler {scheduler}"
    else:
        import dask
        # Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536: every freed cell
        # array goes back to the OS and the next one is faulted in page by page
        environ = {k: v for k, v in dask.config.get("distributed.nanny.pre-spawn-environ",
                                                    {}).items() if k != "MALLOC_TRIM_THRESHOLD_"}
        with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=None,
                                   silence_logs=logging.ERROR)
        client = Client(cluster)
        label = f"Dask LocalCluster of {workers} worker process{'es' if workers > 1 else ''}"
    try:
        n = _check_dask_workers(client, scheduler)
        if log is not None:
            log(f"{label}: {n} worker(s)")
        yield DaskRunner(client, label, n)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _importable() -> str:
    """Run on each Dask worker: where it imports the engine from."""
    import importlib
    return importlib.import_module(__name__.rsplit(".", 2)[0]).__file__


def _check_dask_workers(client, scheduler) -> int:
    """Wait for a worker (up to a minute) and check that every worker can import the engine."""
    try:
        client.wait_for_workers(1, timeout=60)
    except Exception:
        raise EasyIDPError(f"The Dask scheduler {scheduler or ''} has no worker after a minute: "
                           "start workers with `dask worker tcp://HOST:PORT`.") from None
    package = __name__.rsplit(".", 2)[0]
    try:
        found = client.run(_importable)
    except Exception as exc:
        raise EasyIDPError(f"The Dask workers cannot import {package} ({type(exc).__name__}: "
                           f"{exc}). On every worker machine, install its dependencies (numpy "
                           "pyproj tifffile imagecodecs laspy lazrs scikit-image) and put the "
                           "folder that holds easyidp_toolbox on PYTHONPATH before starting "
                           "`dask worker`.") from None
    return len(found)


def wait_any(futures: List, is_cancelled=None) -> List:
    """Block until at least one future is done (or a cancel request); returns the done ones."""
    while True:
        done = [f for f in futures if f.done()]
        if done or (is_cancelled is not None and is_cancelled()):
            return done
        time.sleep(POLL_SECONDS)
