"""Install Python packages for this Python into a folder of their own, never touching its own.

    python install_packages.py --target FOLDER [--dry-run] REQUIREMENT...

The EasyIDP Toolbox plugin runs this with QGIS's own Python when the user clicks *Install*, and
prints the same command for running by hand. Standard library only: it runs before anything is
installed, and it is also run as a plain file (no package imports).

1. **Constraints.** Every distribution this Python already has outside FOLDER is pinned to its
   installed version, except the requested ones (a requested package that is too old is installed
   anew into FOLDER, which the plugin puts first on ``sys.path``). QGIS's own packages are always
   pinned: numpy and GDAL (``PROTECTED``: never installed; QGIS's GDAL is built against its
   numpy, and a numpy 2 next to a GDAL built on numpy 1 breaks ``osgeo.gdal_array``), pyproj and
   PyQt (``KEPT``: never replaced; installed only where this Python has none). Where numpy is
   absent, ``numpy<2`` unless GDAL is 3.9 or newer. So pip picks the releases that fit this
   Python and its numpy (wheels for this interpreter, ``Requires-Python``, numpy bounds).
2. **Resolve** with ``pip install --dry-run --report`` against this environment, FOLDER first on
   the path: pip keeps what is installed and satisfies the constraints and reports only what to
   add. (``pip install --target`` alone ignores installed packages: it would resolve and download a
   second numpy.) Wheels only (``--only-binary=:all:``): nothing is compiled, no ``setup.py`` runs.
3. **Install** exactly the reported list with ``--no-deps`` (safe: the list is the resolved
   closure) into a staging folder beside FOLDER; then older copies of those distributions are
   removed from FOLDER and the new ones moved in. A cancel or an error before that last step
   leaves FOLDER as it was.

Output: pip's own lines, the commands run (``$ …``), and ``::progress N`` (0–100) lines for the
plugin. Exit status: 0 done (or nothing to do), 1 failed, 2 bad arguments, 130 cancelled.
"""
import argparse
import csv
import glob
import importlib.metadata
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

PROTECTED = ("numpy", "gdal")
KEPT = ("pyproj", "pyqt5", "pyqt6", "pyqt5-sip", "pyqt6-sip", "sip")
STAGING_PREFIX = ".staging-"
MIN_PIP = (22, 2)  # --dry-run and --report
COMMON = ("--only-binary=:all:", "--no-input", "--progress-bar", "off", "--root-user-action",
          "ignore")

# PEP 440 (its appendix regex): a version pip accepts in a constraint.
_PEP440 = re.compile(
    r"^\s*v?(?:[0-9]+!)?[0-9]+(?:\.[0-9]+)*"
    r"(?:[-_.]?(?:a|b|c|rc|alpha|beta|pre|preview)[-_.]?[0-9]*)?"
    r"(?:-[0-9]+|[-_.]?(?:post|rev|r)[-_.]?[0-9]*)?"
    r"(?:[-_.]?dev[-_.]?[0-9]*)?(?:\+[a-z0-9]+(?:[-_.][a-z0-9]+)*)?\s*$", re.IGNORECASE)
_NAME = re.compile(r"^([A-Za-z0-9](?:[A-Za-z0-9._-]*[A-Za-z0-9])?)")


class Cancelled(Exception):
    pass


class Failed(Exception):
    pass


def canonical(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def say(text: str = "") -> None:
    print(text, flush=True)


def progress(percent: float) -> None:
    say(f"::progress {int(max(0, min(100, percent)))}")


def _release(version: str):
    match = re.match(r"\s*v?([0-9]+(?:\.[0-9]+)*)", version or "")
    return tuple(int(p) for p in match.group(1).split(".")) if match else ()


def _inside(path: str, folder: str) -> bool:
    path, folder = os.path.normcase(os.path.abspath(path)), os.path.normcase(os.path.abspath(folder))
    return path == folder or path.startswith(folder + os.sep)


def installed_distributions():
    """{canonical name: (name, version, folder)} for the first copy of each on ``sys.path``."""
    found = {}
    for dist in importlib.metadata.distributions():
        try:
            name, version = dist.metadata["Name"], dist.version
        except Exception:  # nosec B112 -- a broken metadata file must not stop the install
            continue
        if not name or not version:
            continue
        key = canonical(name)
        if key in found:
            continue
        path = getattr(dist, "_path", None)
        folder = os.path.dirname(str(path)) if path is not None else str(dist.locate_file(""))
        found[key] = (name, version, folder)
    return found


def constraints(target: str, requested: set) -> list:
    """The pins described in the module docstring (requested: canonical names)."""
    have = installed_distributions()
    pins = []
    for key, (name, version, folder) in sorted(have.items()):
        if _inside(folder, target) or (key in requested and key not in PROTECTED + KEPT):
            continue
        if _NAME.match(name) and _PEP440.match(version):
            pins.append(f"{name}=={version.strip()}")
    if "numpy" not in have and "gdal" in have and _release(have["gdal"][1]) < (3, 9):
        pins.append("numpy<2")
    return pins


def pip_env(target: str) -> dict:
    """pip's environment: FOLDER first on the path; pip's own configuration (index, proxy,
    certificates) untouched, except options that cannot apply to an install into FOLDER."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [target, env.get("PYTHONPATH")]))
    env.update(PIP_USER="0", PIP_REQUIRE_VIRTUALENV="0", PIP_DISABLE_PIP_VERSION_CHECK="1",
               PYTHONIOENCODING="utf-8", PYTHONUNBUFFERED="1")
    return env


def run_pip(args: list, env: dict, start: float, end: float, expected: int) -> None:
    """Run ``python -m pip ARGS``, passing its lines through and advancing the progress."""
    cmd = [sys.executable, "-m", "pip", *args]
    say("$ " + " ".join(cmd))
    step = (end - start) / max(1, expected)
    done = start
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,  # nosec B603 -- this Python's pip, argument list, no shell
                            text=True, encoding="utf-8", errors="replace", bufsize=1)
    try:
        for line in proc.stdout:
            line = line.rstrip()
            say(line)
            if line.startswith(("Collecting ", "Processing ")):
                done = min(end, done + step)
                progress(done)
        proc.wait()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    if proc.returncode != 0:
        raise Failed(f"pip failed (exit status {proc.returncode}); its messages are above.")


def check_pip() -> None:
    try:
        import pip  # noqa: F401 (only its version is read)
        version = _release(pip.__version__)
    except ImportError:
        raise Failed(f"pip is not available for {sys.executable}. On Debian/Ubuntu install the "
                     "package python3-pip; elsewhere pip comes with QGIS's Python.") from None
    if version < MIN_PIP:
        raise Failed(f"pip {'.'.join(map(str, version))} of {sys.executable} is older than "
                     f"{'.'.join(map(str, MIN_PIP))}, which this installer needs (--dry-run "
                     "--report). Use a newer QGIS, or install the packages listed above with pip "
                     "yourself.")


def resolve(target: str, requirements: list, env: dict) -> list:
    """[(name, version)] that pip would add to satisfy ``requirements`` (step 2)."""
    requested = {canonical(_NAME.match(r.strip()).group(1)) for r in requirements}
    refused = sorted(requested & set(PROTECTED))
    if refused:
        raise Failed("QGIS's own packages are never installed here: " + ", ".join(refused))
    with tempfile.TemporaryDirectory(prefix="easyidp-pip-") as tmp:
        cfile = os.path.join(tmp, "constraints.txt")
        with open(cfile, "w", encoding="utf-8") as fh:
            fh.write("\n".join(constraints(target, requested)) + "\n")
        report = os.path.join(tmp, "report.json")
        run_pip(["install", "--dry-run", "--report", report, *COMMON, "--constraint", cfile,
                 *requirements],
                env, 2, 40, len(requirements) + 2)
        with open(report, encoding="utf-8") as fh:
            items = json.load(fh).get("install", [])
    plan = [(i["metadata"]["name"], i["metadata"]["version"]) for i in items]
    have = {k for k, (_, _, folder) in installed_distributions().items()
            if not _inside(folder, target)}
    bad = [f"{n} {v}" for n, v in plan if canonical(n) in PROTECTED
           or (canonical(n) in KEPT and canonical(n) in have)]
    if bad:  # cannot happen with the pins; checked because it must never happen
        raise Failed(f"pip would install {', '.join(bad)} over QGIS's own; nothing was installed.")
    return plan


def _remove_distribution(target: str, key: str) -> None:
    """Remove an installed copy of distribution ``key`` from FOLDER, by its RECORD."""
    for info in glob.glob(os.path.join(target, "*.dist-info")):
        name = os.path.basename(info)[:-len(".dist-info")].rsplit("-", 1)[0]
        if canonical(name) != key:
            continue
        record = os.path.join(info, "RECORD")
        dirs = set()
        if os.path.isfile(record):
            with open(record, newline="", encoding="utf-8") as fh:
                for row in csv.reader(fh):
                    if not row:
                        continue
                    path = os.path.normpath(os.path.join(target, row[0]))
                    if _inside(path, target) and os.path.isfile(path):
                        os.remove(path)
                        dirs.add(os.path.dirname(path))
        shutil.rmtree(info, ignore_errors=True)
        for d in sorted(dirs, key=len, reverse=True):  # empty package folders left behind
            while _inside(d, target) and os.path.normcase(d) != os.path.normcase(target):
                try:
                    os.rmdir(d)
                except OSError:
                    break
                d = os.path.dirname(d)


def _merge(src: str, dst: str) -> None:
    """Move ``src`` to ``dst``; folders are merged (namespace packages, ``bin``)."""
    if os.path.isdir(src) and os.path.isdir(dst) and not os.path.islink(dst):
        for entry in os.listdir(src):
            _merge(os.path.join(src, entry), os.path.join(dst, entry))
        return
    if os.path.isdir(dst) and not os.path.islink(dst):
        shutil.rmtree(dst)
    elif os.path.lexists(dst):
        os.remove(dst)
    os.replace(src, dst)


def install(target: str, plan: list, env: dict) -> None:
    """Step 3: staged install of exactly ``plan``, then moved into FOLDER."""
    parent = os.path.dirname(os.path.abspath(target))
    os.makedirs(parent, exist_ok=True)
    for old in glob.glob(os.path.join(parent, STAGING_PREFIX + "*")):  # left by a killed run
        if time.time() - os.path.getmtime(old) > 3600:
            shutil.rmtree(old, ignore_errors=True)
    stage = tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=parent)
    try:
        run_pip(["install", "--no-deps", *COMMON, "--no-warn-script-location", "--target", stage,
                 *[f"{n}=={v}" for n, v in plan]], env, 40, 95, len(plan))
        blocked = _block_signals()
        try:
            os.makedirs(target, exist_ok=True)
            for info in glob.glob(os.path.join(stage, "*.dist-info")):
                name = os.path.basename(info)[:-len(".dist-info")].rsplit("-", 1)[0]
                _remove_distribution(target, canonical(name))
            for entry in os.listdir(stage):
                _merge(os.path.join(stage, entry), os.path.join(target, entry))
        finally:
            if blocked is not None:  # a cancel that came during the move comes too late
                for sig in (signal.SIGTERM, signal.SIGINT):
                    signal.signal(sig, signal.SIG_IGN)
            _unblock_signals(blocked)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def _block_signals():
    """Moving into FOLDER is not interrupted by a cancel (POSIX; a short step)."""
    if hasattr(signal, "pthread_sigmask"):
        return signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGTERM, signal.SIGINT})
    return None


def _unblock_signals(previous) -> None:
    if previous is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _on_signal(signum, frame):
    raise Cancelled()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--target", required=True, help="the folder the packages go to")
    parser.add_argument("--dry-run", action="store_true", help="resolve and print, install nothing")
    parser.add_argument("requirements", nargs="+", help="pip requirements, e.g. 'laspy>=2.5'")
    args = parser.parse_args(argv)
    target = os.path.abspath(args.target)
    for sig in (signal.SIGTERM, signal.SIGINT):
        signal.signal(sig, _on_signal)
    sys.path.insert(0, target)  # what the plugin does: FOLDER first
    env = pip_env(target)
    try:
        say(f"Python: {sys.executable} ({sys.version.split()[0]}); packages folder: {target}")
        progress(0)
        check_pip()
        plan = resolve(target, args.requirements, env)
        if not plan:
            progress(100)
            say("Nothing to install: every requirement is already met.")
            return 0
        say("To install: " + ", ".join(f"{n} {v}" for n, v in plan))
        if args.dry_run:
            return 0
        install(target, plan, env)
        progress(100)
        say(f"Installed into {target}: " + ", ".join(f"{n} {v}" for n, v in plan))
        return 0
    except Cancelled:
        say("Cancelled; the packages folder was left as it was.")
        return 130
    except Failed as exc:
        say(f"ERROR: {exc}")
        return 1


if __name__ == "__main__":
    sys.exit(main())
