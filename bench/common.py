"""Small helpers shared by the benchmarks: time a child process, report figures and targets.

Every measured tool runs in its own child process, so its peak memory is its own. The kernel's
accounting of a child (``ru_maxrss`` from ``wait4``) starts from the resident size of the process
that forked it (with vfork, its peak), so ``run_child`` forks through a tiny launcher and the
benchmark's own memory does not leak into the figures. ``ru_maxrss`` is the largest resident set
of the child or of any descendant it waited for (not their sum); the launcher's few MiB of Python
are the floor of what can be read.
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

from ..scripts.reference import REF_PYTHON, reference_env  # noqa: F401 (the benchmarks' one way)

# argv: RESULT_FILE COMMAND...; times COMMAND from outside and writes its accounting as JSON.
_LAUNCHER = r"""
import json, os, sys, time
start = time.perf_counter()
try:
    pid = os.fork()
except OSError as exc:
    sys.exit(f"cannot fork: {exc}")
if pid == 0:
    try:
        os.execvp(sys.argv[2], sys.argv[2:])
    except OSError as exc:
        os.write(2, f"cannot run {sys.argv[2]}: {exc}\n".encode())
    os._exit(127)
_, status, ru = os.wait4(pid, 0)
wall = time.perf_counter() - start
with open(sys.argv[1], "w") as fh:
    json.dump(dict(wall=wall, cpu=ru.ru_utime + ru.ru_stime, maxrss_kib=ru.ru_maxrss,
                   returncode=os.waitstatus_to_exitcode(status)), fh)
"""


@dataclass
class Run:
    wall: float          # seconds, from start to reaping
    cpu: float           # user + system seconds of the child (and its reaped descendants)
    peak_mb: float       # peak resident set size, MiB
    returncode: int
    stdout: str
    stderr: str

    @property
    def ok(self) -> bool:
        return self.returncode == 0


def run_child(cmd: Sequence[str], env: Optional[dict] = None, cwd: Optional[str] = None,
              timeout: Optional[float] = None) -> Run:
    """Run ``cmd`` to completion (killed after ``timeout`` s); output goes to temporary files."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err, \
            tempfile.NamedTemporaryFile("r", suffix=".json") as result:
        proc = subprocess.Popen([sys.executable, "-S", "-c", _LAUNCHER, result.name, *cmd],
                                stdout=out, stderr=err, stdin=subprocess.DEVNULL, env=env,
                                cwd=cwd, start_new_session=True)
        killer = None
        if timeout:
            killer = threading.Timer(timeout, os.killpg, (proc.pid, signal.SIGKILL))
            killer.start()
        proc.wait()
        if killer:
            killer.cancel()
        out.seek(0)
        err.seek(0)
        stdout, stderr = (f.read().decode(errors="replace") for f in (out, err))
        try:
            acct = json.load(result)
        except ValueError:  # the launcher was killed (timeout) or failed
            return Run(float("nan"), float("nan"), float("nan"), proc.returncode or -1, stdout,
                       stderr + f"\n(no accounting: launcher exit {proc.returncode})")
        return Run(acct["wall"], acct["cpu"], acct["maxrss_kib"] / 1024.0,  # Linux: KiB
                   acct["returncode"], stdout, stderr)


def run_json_child(cmd: Sequence[str], env: Optional[dict] = None,
                   timeout: Optional[float] = None, label: str = "",
                   strict: bool = False) -> Tuple[Run, Optional[dict]]:
    """:func:`run_child`, and the JSON object the child printed on its last line of output;
    None (and the tail of its output printed, after ``label``) when it failed, or with
    ``strict`` a RuntimeError."""
    run = run_child(cmd, env=env, timeout=timeout)
    info = None
    if run.ok:
        try:
            info = json.loads(run.stdout.strip().splitlines()[-1])
        except (ValueError, IndexError):
            pass
    if info is None and strict:
        raise RuntimeError(f"{label or cmd[0]} failed ({run.returncode}):\n{run.stderr[-3000:]}")
    if info is None:
        tail = "\n      ".join((run.stderr or run.stdout).strip().splitlines()[-8:])
        print(f"    {label + ' ' if label else ''}FAILED (exit {run.returncode}):\n      {tail}",
              flush=True)
    return run, info

def spread(runs: List[Run]) -> str:
    """'min–max' of the wall times, to show how noisy the machine was."""
    walls = [r.wall for r in runs]
    if len(walls) < 2:
        return ""
    return f"{min(walls):.1f}–{max(walls):.1f}"


def ratio(numerator: Optional[float], denominator: Optional[float]) -> Optional[float]:
    if numerator is None or not denominator:
        return None
    return numerator / denominator


def table(headers: Sequence[str], rows: Sequence[Sequence]) -> str:
    """A plain-text table; floats get 2 decimals (1 when ≥ 100), None prints as '-'."""
    def cell(v):
        if v is None:
            return "-"
        if isinstance(v, float):
            return f"{v:.1f}" if abs(v) >= 100 else f"{v:.2f}"
        return str(v)
    cells = [[cell(v) for v in row] for row in rows]
    widths = [max(len(str(h)), *(len(r[i]) for r in cells)) for i, h in enumerate(headers)]

    def fmt(row):  # first column left-aligned, figures right-aligned
        return "  ".join(v.ljust(w) if i == 0 else v.rjust(w)
                         for i, (v, w) in enumerate(zip(row, widths)))
    return "\n".join([fmt([str(h) for h in headers]), "  ".join("-" * w for w in widths)]
                     + [fmt(r) for r in cells])


def target(label: str, value: Optional[float], goal: float, at_least: bool = True) -> list:
    """A row [label, value, goal, PASS/MISS] for :func:`table`; a missing value is a MISS."""
    if value is None:
        verdict = "MISS (no figure)"
    else:
        verdict = "PASS" if (value >= goal if at_least else value <= goal) else "MISS"
    return [label, value, ("≥ " if at_least else "≤ ") + f"{goal:g}", verdict]


def print_targets(goals: Sequence[list]) -> None:
    """The benchmark's closing table of targets (rows from :func:`target`), when it has any."""
    if goals:
        print("\nTargets")
        print(table(["target", "value", "goal", "verdict"], goals))
