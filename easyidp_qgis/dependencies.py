"""The plugin's Python packages: the one table, the checks, and the install command.

Everything about dependencies derives from ``DEPENDENCIES``: the message bar of the desktop
(``installer.py``), the message of a tool run headless (``algorithms/base.py``), the install hint,
and the command that installs them. To add a package, add a row: the import name, the pip
requirement (lower bounds: the oldest versions the tests ran with, see ARCHITECTURE.md), and who
needs it: ``ALL`` for the plugin itself, ``TOOLS`` for the tools that name it in their
``REQUIRES`` (each algorithm class in ``algorithms/`` declares the import names it needs; which
tools need a row is derived from them, :func:`tools_requiring`), ``EXTRA`` for the script-only
extras of ``easyidp_toolbox.core``, installed with the others but never blocking anything; e.g.
``Dependency("skimage", "scikit-image>=0.22", TOOLS)`` and ``REQUIRES = (…, "skimage")`` in the
tools that use it. Also add it to ``requirements/qgis.txt`` (the test environment; a test checks
both, that every package the code imports has a row, and that every name in a ``REQUIRES`` has
one).

*Install* installs the releases the tests ran with (``TESTED``, the pins of
``requirements/qgis.txt``; a test keeps them equal), per Python: a Python the tests ran on gets
``==`` its pin; another Python gets the table's lower bound capped below the next major release
of the nearest tested Python's pin (pip then picks the newest release with wheels for it).
What those pins bring with them is whatever pip resolves, and the message bar lists it before
installing. The script-only extras (Dask, OPF, pyshp) are installed only when asked for
(``install_argv(..., extras)``, or the command the messages give).

Packages go to a folder the plugin owns inside the user's QGIS profile
(``<profile>/python/easyidp_toolbox_packages/python3.X``), put first on ``sys.path`` when the plugin
loads. QGIS's own environment is never changed: numpy and GDAL are QGIS's (``PROTECTED``) and are
never installed by the plugin; pyproj and PyQt (``KEPT``) are never replaced, only installed where
QGIS has none (``install_packages.py`` pins them all to the installed versions).
"""
import functools
import importlib.metadata
import importlib.util
import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple, Union

from qgis.PyQt.QtCore import QCoreApplication

ALL = "*"          # the plugin itself (the provider imports it): every tool needs it
TOOLS = "tools"    # the tools whose REQUIRES name it
EXTRA = ()         # a script-only extra of the engine: installed along, never blocking a tool


@dataclass(frozen=True)
class Dependency:
    module: str                          # the name imported
    requirement: str                     # pip requirement: distribution name, extras, specifier
    scope: Union[str, Tuple[()]]         # ALL, TOOLS or EXTRA
    # (distribution, specifier) a package QGIS ships must meet for this one to install beside it
    # (pyopf asks for Pillow >= 10); where QGIS's copy does not, the row is left out of the checks
    # and installs (the code that needs it says so when run)
    needs_shipped: Tuple[str, str] = ()
    python: str = ""                     # the Pythons it has releases for (e.g. ">=3.10"), if not all

    def __post_init__(self):
        if self.scope not in (ALL, TOOLS, EXTRA):
            raise ValueError(f"{self.module}: scope must be ALL, TOOLS or EXTRA, not "
                             f"{self.scope!r} (the tools that need a package say so in their "
                             "REQUIRES)")

    @property
    def tools(self) -> Union[str, Tuple[str, ...]]:
        """``ALL``; the ``NAME`` of every tool whose ``REQUIRES`` names the module (``TOOLS``);
        or ``()`` (``EXTRA``)."""
        return tools_requiring(self.module) if self.scope == TOOLS else self.scope

    @property
    def distribution(self) -> str:
        return _split_requirement(self.requirement)[0]

    @property
    def specifier(self) -> str:
        return _split_requirement(self.requirement)[1]

    def fits_here(self) -> bool:
        """Whether this Python (``python``) and QGIS's own packages (``needs_shipped``) allow
        installing it."""
        here = "%d.%d" % sys.version_info[:2]
        if self.python and not version_satisfies(here, self.python):
            return False
        if not self.needs_shipped:
            return True
        name, spec = self.needs_shipped
        try:
            return version_satisfies(importlib.metadata.version(name), spec)
        except importlib.metadata.PackageNotFoundError:
            return True          # not shipped: pip installs a version that fits

    def needed_by(self, tool: Optional[str]) -> bool:
        """Whether ``tool`` (an algorithm ``NAME``) needs it (``tool=None``: whether any tool
        does: a ``TOOLS`` row is there because one does, and answers without importing the
        algorithms, as the plugin's start does)."""
        if self.scope != TOOLS:
            return self.scope == ALL
        return tool is None or tool in self.tools


def tools_requiring(module: str) -> Tuple[str, ...]:
    """The ``NAME`` of every algorithm whose ``REQUIRES`` names ``module``, in the provider's
    order."""
    return _requirements().get(module, ())


@functools.lru_cache(maxsize=None)
def _requirements() -> Dict[str, Tuple[str, ...]]:
    """{import name: tool NAMEs} from the algorithms' ``REQUIRES``. The algorithms are imported
    here, when a tool asks (they import this module; the plugin's start never needs them)."""
    from .algorithms import ALGORITHMS
    found: Dict[str, List[str]] = {}
    for cls in ALGORITHMS:
        for module in cls.REQUIRES:
            found.setdefault(module, []).append(cls.NAME)
    return {module: tuple(names) for module, names in found.items()}


DEPENDENCIES: Tuple[Dependency, ...] = (
    Dependency("numpy", "numpy>=1.24", ALL),                    # arrays (QGIS's own)
    Dependency("pyproj", "pyproj>=3.4", ALL),                   # CRSs (QGIS ships it on Debian)
    Dependency("tifffile", "tifffile>=2023.7.10", TOOLS),       # GeoTIFF reading, writing
    Dependency("imagecodecs", "imagecodecs>=2023.3.16", TOOLS),  # LZW/JPEG/ZSTD, JPEG
    Dependency("laspy", "laspy>=2.5.3", TOOLS),                 # LAS/LAZ
    Dependency("lazrs", "lazrs>=0.5.2", TOOLS),                 # LAZ compression for laspy
    Dependency("plyfile", "plyfile>=1.0.3", TOOLS),             # PLY
    Dependency("shapefile", "pyshp>=3.1.6", EXTRA),             # core.open_rois on shapefiles
    Dependency("scipy", "scipy>=1.10", TOOLS),                  # map_coordinates resampling
    Dependency("shapely", "shapely>=2.0", TOOLS),               # merging the views
    Dependency("skimage", "scikit-image>=0.22", TOOLS),         # Otsu; fuse contours
    Dependency("PIL", "pillow>=9.4", TOOLS),                    # photo headers; captions
    Dependency("matplotlib", "matplotlib>=3.6", TOOLS),         # growth curves
    Dependency("dask", "dask[distributed]>=2024.1", EXTRA),     # Dask clusters (optional)
    Dependency("pyopf", "pyopf>=1.4.1", EXTRA, ("pillow", ">=10"), ">=3.10"),  # OPF projects
)

# The releases the tests ran with, by Python (requirements/qgis.txt, where the QGIS matrix runs
# them: Python 3.11 on Debian 12, 3.13 on Debian 13, 3.14 on sid). A distribution absent here
# (scipy, Pillow, matplotlib, pyproj: QGIS's own on the tested platforms) keeps the table's bound.
TESTED_PYTHONS = ((3, 11), (3, 13), (3, 14))
TESTED: Dict[str, Tuple[Tuple[str, str], ...]] = {   # distribution: ((Python range, version), …)
    "tifffile": (("", "2026.3.3"),),
    "imagecodecs": (("", "2026.1.14"),),
    "laspy": (("", "2.7.0"),),
    "lazrs": (("", "0.8.2"),),
    "plyfile": (("<3.12", "1.0.3"), (">=3.12", "1.1.3")),
    "pyshp": (("", "3.1.6"),),
    "dask": (("", "2026.8.0"),),
    "scikit-image": (("<3.12", "0.24.0"), (">=3.12", "0.26.0")),
    "shapely": (("<3.12", "2.0.7"), (">=3.12", "2.1.2")),
    "pyopf": (("", "1.4.1"),),
}

# QGIS's own packages: checked, never installed (a plugin must not replace QGIS's numpy or GDAL).
PROTECTED = ("numpy", "gdal")
# Also QGIS's: never replaced (a copy that is too old is reported, not shadowed), but installed
# where this QGIS's Python has none.
KEPT = ("pyproj", "pyqt5", "pyqt6", "pyqt5-sip", "pyqt6-sip", "sip")

PACKAGES_FOLDER = "easyidp_toolbox_packages"
INSTALL_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "install_packages.py")


class _I18n:
    """``tr`` for this module's messages (the catalogue script collects ``*.tr("…")`` literals)."""

    @staticmethod
    def tr(text: str) -> str:
        return QCoreApplication.translate("EasyIDP", text)


_i18n = _I18n()


@dataclass(frozen=True)
class Missing:
    """A package that is not importable (``installed`` None) or whose version is refused."""

    dependency: Dependency
    installed: Optional[str]

    @property
    def protected(self) -> bool:
        """Whether the plugin leaves it to QGIS: numpy, GDAL; pyproj when QGIS has one."""
        key = canonical(self.dependency.distribution)
        return key in PROTECTED or (key in KEPT and self.installed is not None)

    def describe(self) -> str:
        """The distribution name; with the refused version and the requirement when too old."""
        dep = self.dependency
        if self.installed is None:
            return dep.distribution
        return _i18n.tr("{name} {version} (needs {spec})").format(
            name=dep.distribution, version=self.installed, spec=dep.specifier)


# --- checks -----------------------------------------------------------------------------------

def missing(tool: Optional[str] = None, include_extras: bool = False) -> List[Missing]:
    """The packages ``tool`` needs (``None``: any tool) that are absent or too old, table order.

    ``include_extras`` adds the script-only extras (``EXTRA``), which the installer installs
    along with the rest. Rows that do not fit this QGIS (``needs_shipped``) are left out. Importability is checked without importing (``find_spec``); the version
    comes from the distribution metadata found first on ``sys.path``, as the import would.
    """
    importlib.invalidate_caches()
    found = []
    for dep in DEPENDENCIES:
        if not (dep.needed_by(tool) or (include_extras and dep.scope == EXTRA)) \
                or not dep.fits_here():
            continue
        state = _state(dep)
        if state is not True:
            found.append(Missing(dep, state or None))
    return found


def _state(dep: Dependency):
    """True when usable; else the installed version that is refused, or '' when absent."""
    try:
        spec = importlib.util.find_spec(dep.module)
    except (ImportError, ValueError):
        spec = None
    if spec is None:
        return ""
    try:
        version = importlib.metadata.version(dep.distribution)
    except importlib.metadata.PackageNotFoundError:
        return True  # importable without metadata (e.g. a system build): accepted as is
    return True if version_satisfies(version, dep.specifier) else version


def dependency_for_module(module: Optional[str]) -> Optional[Dependency]:
    """The table row of a module name as ``ImportError.name`` gives it (``a.b`` → ``a``)."""
    top = (module or "").split(".")[0]
    return next((d for d in DEPENDENCIES if d.module == top), None)


# --- versions (the subset of PEP 440 the table uses: release numbers and comparisons) ----------

_CLAUSE = re.compile(r"^\s*(==|!=|>=|<=|>|<)\s*([0-9]+(?:\.[0-9]+)*)\s*$")


def _release(version: str) -> Tuple[int, ...]:
    match = re.match(r"\s*v?([0-9]+(?:\.[0-9]+)*)", version)
    if not match:
        raise ValueError(f"not a version: {version!r}")
    parts = [int(p) for p in match.group(1).split(".")]
    while len(parts) > 1 and parts[-1] == 0:
        parts.pop()
    return tuple(parts)


def version_satisfies(version: str, specifier: str) -> bool:
    """Whether ``version`` meets ``specifier`` (e.g. ``">=1.24,<2"``), comparing release numbers.

    A version that cannot be read is accepted (a distribution's own build of a package).
    """
    try:
        have = _release(version)
    except ValueError:
        return True
    for clause in filter(None, (c.strip() for c in specifier.split(","))):
        match = _CLAUSE.match(clause)
        if not match:
            raise ValueError(f"unsupported version clause {clause!r}")
        op, want = match.group(1), _release(match.group(2))
        ok = {"==": have == want, "!=": have != want, ">=": have >= want, "<=": have <= want,
              ">": have > want, "<": have < want}[op]
        if not ok:
            return False
    return True


def _split_requirement(requirement: str) -> Tuple[str, str]:
    """``"dask[distributed]>=2024.1"`` → ``("dask", ">=2024.1")``."""
    match = re.match(r"^\s*([A-Za-z0-9][A-Za-z0-9._-]*)\s*(?:\[[^\]]*\])?\s*(.*)$", requirement)
    if not match:
        raise ValueError(f"not a requirement: {requirement!r}")
    return match.group(1), match.group(2).strip()


def canonical(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


# --- where packages go, and the interpreter that installs them --------------------------------

def packages_dir(profile_dir: Optional[str] = None) -> str:
    """The plugin's package folder in the QGIS profile, one per Python minor version."""
    if profile_dir is None:
        from qgis.core import QgsApplication
        profile_dir = QgsApplication.qgisSettingsDirPath()
    return os.path.normpath(os.path.join(
        profile_dir, "python", PACKAGES_FOLDER, "python{}.{}".format(*sys.version_info[:2])))


def activate(profile_dir: Optional[str] = None) -> str:
    """Put the package folder first on ``sys.path`` (once), before any package is imported.

    First, so a package the plugin installed because QGIS's copy is too old wins over it; it
    never holds numpy or GDAL. Returns the folder (which need not exist yet).
    """
    folder = packages_dir(profile_dir)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    sys.path_importer_cache.pop(folder, None)  # the folder may have been created since
    importlib.invalidate_caches()
    return folder


def python_executable() -> str:
    """QGIS's Python interpreter, the one that runs pip.

    Embedded in QGIS, ``sys.executable`` is not reliable: it is ``qgis-bin.exe`` on Windows, the
    QGIS binary in the macOS app, and on Linux whatever ``python3`` is first on ``PATH`` (a
    pyenv shim, say). The interpreter is looked for in ``sys.exec_prefix`` first.
    """
    ver = "{}.{}".format(*sys.version_info[:2])
    exe_dir = os.path.dirname(sys.executable or "")
    if os.name == "nt":
        candidates = [os.path.join(p, name) for p in (sys.exec_prefix, sys.base_exec_prefix, exe_dir)
                      for name in ("python.exe", "python3.exe")]
    else:
        candidates = [os.path.join(p, "bin", name) for p in (sys.exec_prefix, sys.base_exec_prefix)
                      for name in (f"python{ver}", "python3")]
        candidates += [os.path.join(exe_dir, "bin", f"python{ver}"),  # QGIS.app/Contents/MacOS/bin
                       os.path.join(exe_dir, "bin", "python3"), os.path.join(exe_dir, "python3")]
    for path in candidates:
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    return sys.executable


def check_python(python: str) -> Optional[str]:
    """None when ``python`` is the same Python version as QGIS's; else what is wrong."""
    want = "{}.{}".format(*sys.version_info[:2])
    try:
        out = subprocess.run([python, "-c", "import sys; print('%d.%d' % sys.version_info[:2])"],  # nosec B603 -- QGIS's Python, no shell
                             capture_output=True, text=True, timeout=60, **_no_window())
    except (OSError, subprocess.SubprocessError) as exc:
        return _i18n.tr("QGIS's Python interpreter {python} cannot run: {error}").format(
            python=python, error=exc)
    got = out.stdout.strip()
    if got != want:
        return _i18n.tr("{python} is Python {got}, but QGIS runs Python {want}; QGIS's own "
                        "interpreter was not found").format(python=python, got=got or "?",
                                                            want=want)
    return None


def _no_window() -> dict:
    """subprocess options that keep a console window from flashing up on Windows."""
    return {"creationflags": subprocess.CREATE_NO_WINDOW} if os.name == "nt" else {}


# --- the install command and the messages -----------------------------------------------------

def installable(items: Sequence[Missing]) -> List[Missing]:
    """The packages the plugin may install (not QGIS's numpy, GDAL or an existing pyproj)."""
    return [m for m in items if not m.protected]


def tested_version(distribution: str, python: Tuple[int, int]) -> Optional[str]:
    """The release the tests ran with on ``python`` (a tested Python), or None."""
    for spec, version in TESTED.get(canonical(distribution), ()):
        if not spec or version_satisfies("%d.%d" % python, spec):
            return version
    return None


def pinned_requirement(dep: Dependency, python: Optional[Tuple[int, int]] = None) -> str:
    """The requirement *Install* gives pip for ``dep`` on ``python`` (default: this one).

    A tested Python: ``name[extras]==<the tested release>``. Another Python: the table's
    specifier and ``<`` the next major release of the nearest tested Python's pin (the newer
    one on a tie). Not in ``TESTED``: the table's requirement."""
    python = tuple(python or sys.version_info[:2])
    name = dep.requirement[:len(dep.requirement) - len(dep.specifier)].strip()
    if canonical(dep.distribution) not in TESTED:
        return dep.requirement
    if python in TESTED_PYTHONS:
        pin = tested_version(dep.distribution, python)
        return f"{name}=={pin}" if version_satisfies(pin, dep.specifier) else dep.requirement
    nearest = min(TESTED_PYTHONS, key=lambda t: (abs(t[1] - python[1]), -t[1]))
    major = int(tested_version(dep.distribution, nearest).split(".")[0])
    return ",".join(filter(None, [f"{name}{dep.specifier}", f"<{major + 1}"]))


def install_argv(items: Sequence[Missing], python: Optional[str] = None,
                 target: Optional[str] = None) -> List[str]:
    """The command that installs ``items`` into the package folder (what *Install* runs), each
    at its pinned release (``pinned_requirement``)."""
    reqs = [pinned_requirement(m.dependency) for m in installable(items)]
    return [python or python_executable(), INSTALL_SCRIPT, "--target", target or packages_dir(),
            *reqs]


def format_command(argv: Sequence[str], windows: Optional[bool] = None) -> str:
    """``argv`` as one line to paste into the platform's shell (cmd.exe or PowerShell on
    Windows: double quotes around anything with a space or ``<>|&^()``, as ``>=`` needs)."""
    if windows is None:
        windows = os.name == "nt"
    if windows:
        return " ".join(f'"{a}"' if re.search(r'[\s<>|&^()]', a) or not a else a for a in argv)
    return " ".join(shlex.quote(a) for a in argv)


def describe(items: Sequence[Missing]) -> str:
    return ", ".join(m.describe() for m in items)


def protected_message(items: Sequence[Missing]) -> str:
    """What to say when QGIS's own numpy or GDAL is missing or too old, or its pyproj too old
    (empty when not)."""
    bad = [m for m in items if m.protected]
    if not bad:
        return ""
    return _i18n.tr("QGIS's own {packages}: the plugin does not replace QGIS's packages; use a "
                    "newer QGIS.").format(packages=describe(bad))


def install_instructions(items: Sequence[Missing]) -> str:
    """How to install ``items`` by hand: the exact command (and the desktop's Install button)."""
    parts = []
    if installable(items):
        parts.append(_i18n.tr("To install them, click Install in the EasyIDP message bar of the "
                              "QGIS desktop, or run:\n{command}").format(
            command=format_command(install_argv(items))))
    note = protected_message(items)
    if note:
        parts.append(note)
    return "\n".join(parts)


def tool_message(display_name: str, items: Sequence[Missing], headless: bool = False) -> str:
    """Why ``display_name`` cannot run: the missing packages and how to install them.

    ``headless``: the run was refused (qgis_process or a Processing run), so say that nothing
    was installed.
    """
    text = _i18n.tr("{tool} needs Python packages that QGIS's Python does not have: {packages}."
                    ).format(tool=display_name, packages=describe(items))
    if headless:
        text += " " + _i18n.tr("Nothing was installed.")
    return text + "\n" + install_instructions(items)


def import_error_message(exc: ImportError) -> str:
    """An ImportError in a tool, named with the table's requirement and the install command."""
    dep = dependency_for_module(getattr(exc, "name", None))
    if dep is None:
        return _i18n.tr("{error}. Install the missing Python package for QGIS's Python ({python})."
                        ).format(error=exc, python=python_executable())
    return f"{exc}. " + install_instructions([Missing(dep, None)])


def install_hint() -> str:
    """The generic hint: how to install every package of the table."""
    items = [Missing(d, None) for d in DEPENDENCIES if canonical(d.distribution) not in PROTECTED]
    return _i18n.tr("The plugin's Python packages are installed with the Install button the "
                    "QGIS desktop shows when one is missing, or by running:\n{command}").format(
        command=format_command(install_argv(items)))
