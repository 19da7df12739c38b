"""The import contract of ``core/`` and ``easyidp_qgis/``, checked on the source by AST (no
QGIS needed). The layer order is stated once, in ``LAYERS``; ARCHITECTURE.md draws it.

* (a) no module imports a module of a higher layer, at module or at function level;
* (b) no import cycle among core modules (the module-level graph, within packages too);
* (c) no function-level import of a core module inside core (only optional third-party ones);
* (d) no private name crosses a package: no ``from pkg.mod import _x`` from another package and
  no ``obj._x`` where ``_x`` is a private function, method or class defined only in another one;
* (e) ``easyidp_qgis`` imports only package faces of core: ``core``, ``core.<package>`` or a
  top-level basics module such as ``core.errors``, never a submodule like ``core.raster.crop``;
* every ``core/…py`` and ``easyidp_qgis/…py`` path that ARCHITECTURE.md names exists.
* every package face imports with the optional packages (easyidp_qgis/dependencies.py) blocked,
  so the plugin loads without them: those are the only function-level imports.

Each check is parametrized per module, so a failure names the module and its offending imports;
``test_checks_can_fail`` runs every check on synthetic sources that break it.
"""
import ast
import os
import re
import subprocess
import sys
import tempfile
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Set, Tuple

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "easyidp_toolbox"       # the repository root is the plugin package

# The layer order, lowest first. A module may import its own package and any package of a lower
# layer, never one of its own layer (other than itself) or a higher one. The basics are core's
# top-level modules (every one of them: a new top-level module is a basic) and may import each
# other, without a cycle. "core" is the face of the whole engine (core/__init__.py).
LAYERS: Tuple[Tuple[str, ...], ...] = (
    ("basics",),                     # errors, crs, progress, geometry, ragged, rotations, wkb,
                                     # files, naming, gpkg, indices,
                                     # height_statistics (the heights vocabulary), safe_xml
    ("photos",),                     # raw photos as files: lookup, headers, tags, decoding
    ("annotations", "radiometry"),   # shapes on raw photos (LabelMe, COCO, YOLO), pixel space;
                                     # raw photos in physical units (thermal, reflectance)
    ("roi",),                        # ROI, ROISet and their readers (LabelMe via annotations)
    ("raster", "pointcloud", "radiometry"),  # the raster engine; point clouds; photo pixels in
                                     # physical units (reflectance)
    ("reconstruction", "plotgrid"),  # the camera model; plot grids (they read an orthomosaic)
    ("projection",),                 # rays, footprints, backward, forward, ortho, statistics
    ("season",),                     # a season of surveys
    ("core",),                       # core/__init__.py, the engine's face
    ("demo",),                       # the demo survey and trial generators
    ("easyidp_qgis",),               # the QGIS plugin
)
LAYER_OF = {name: k for k, names in enumerate(LAYERS) for name in names}

# Private names that may cross a package, each with its reason (keep it short).
PRIVATE_ALLOWED: Dict[str, str] = {}
# Attribute names of the standard library that start with one underscore and are public API.
STDLIB_PRIVATE = {"_replace", "_asdict", "_fields", "_make", "_field_defaults", "_exit",
                  "_getframe", "_current_frames"}


@dataclass
class Import:
    source: str          # the importing module, e.g. "core.raster.crop"
    target: str          # the imported module, e.g. "core.roi.model" (a package: its __init__)
    names: List[str]     # the names taken from it ("from target import names"), or []
    line: int
    lazy: bool           # inside a function

    def __str__(self):
        what = f" ({', '.join(self.names)})" if self.names else ""
        return f"line {self.line}: {'function-level ' if self.lazy else ''}{self.target}{what}"


@dataclass
class Module:
    name: str
    is_package: bool
    tree: ast.Module
    imports: List[Import] = field(default_factory=list)


def module_name(path: Path, root: Path) -> Tuple[str, bool]:
    parts = list(path.relative_to(root).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    return ".".join(parts[:-1] if is_package else parts), is_package


def parse_sources(sources: Dict[str, Tuple[str, bool]]) -> Dict[str, Module]:
    """{module name: (source, is_package)} → parsed modules with their project imports."""
    mods = {name: Module(name, pkg, ast.parse(src)) for name, (src, pkg) in sources.items()}
    for mod in mods.values():
        _collect(mod, mod.tree, False, mods)
    return mods


def _collect(mod: Module, node, lazy: bool, mods: Dict[str, Module]):
    for child in ast.iter_child_nodes(node):
        inner = lazy or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
        if isinstance(child, ast.ImportFrom):
            base = _resolve(mod, child.level, child.module)
            if base is not None:
                modules = {}
                for alias in child.names:      # "from pkg import submodule" imports the submodule
                    sub = f"{base}.{alias.name}"   # ... unless pkg's face binds that name itself
                    target = sub if sub in mods and not (
                        base in mods and alias.name in _bound_names(mods[base].tree)) else base
                    modules.setdefault(target, []).append(alias.name)
                mod.imports += [Import(mod.name, t, n, child.lineno, lazy)
                                for t, n in modules.items()]
        elif isinstance(child, ast.Import):
            for alias in child.names:
                target = _strip(alias.name)
                if target is not None:
                    mod.imports.append(Import(mod.name, target, [], child.lineno, lazy))
        _collect(mod, child, inner, mods)


def _bound_names(tree) -> set:
    """Names a module binds at its top level (imports, definitions, assignments)."""
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            names |= {(a.asname or a.name).split(".")[0] for a in node.names}
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return names


def _strip(name: str):
    if name == PACKAGE or name.startswith(PACKAGE + "."):
        return name[len(PACKAGE) + 1:] or None
    return None


def _resolve(mod: Module, level: int, module):
    if level == 0:
        return _strip(module or "")
    base = mod.name.split(".")
    if not mod.is_package:
        base = base[:-1]
    base = base[:len(base) - (level - 1)]
    return ".".join(base + ([module] if module else [])) or None


def package_of(name: str) -> str:
    """The package a module belongs to: ``core.<package>``, a top-level core module itself,
    ``core`` for core/__init__.py, or ``easyidp_qgis``."""
    parts = name.split(".")
    return ".".join(parts[:2]) if parts[0] == "core" else parts[0]


def layer_of(name: str, mods: Dict[str, Module]) -> int:
    parts = name.split(".")
    if parts[0] != "core":
        return LAYER_OF[parts[0]]
    if len(parts) == 1:
        return LAYER_OF["core"]
    top = ".".join(parts[:2])
    if top in mods and not mods[top].is_package:
        return LAYER_OF["basics"]
    return LAYER_OF[parts[1]]


# ---- the checks: each returns the offences of one module, as readable strings ------------------
def upward_imports(mods: Dict[str, Module], name: str) -> List[str]:
    """(a) imports of a module of a higher layer, or of another package of the same layer."""
    mine, pkg = layer_of(name, mods), package_of(name)
    bad = []
    for imp in mods[name].imports:
        if imp.target not in mods or package_of(imp.target) == pkg:
            continue
        theirs = layer_of(imp.target, mods)
        if theirs > mine or (theirs == mine and mine != LAYER_OF["basics"]):
            bad.append(f"{imp} is in layer {LAYERS[theirs]}, {name} in {LAYERS[mine]}")
    return bad


def import_graph(mods: Dict[str, Module]) -> Dict[str, Set[str]]:
    """Module-level imports among core modules. Importing ``a.b.c`` also runs ``a.b``'s
    ``__init__``: that edge is added unless ``a.b`` is a package of the importer itself."""
    graph = {n: set() for n in mods if n.split(".")[0] == "core"}
    for name in graph:
        for imp in mods[name].imports:
            if imp.lazy or imp.target not in graph or imp.target == name:
                continue
            graph[name].add(imp.target)
            parts = imp.target.split(".")
            for k in range(1, len(parts)):
                parent = ".".join(parts[:k])
                if parent in graph and not (name + ".").startswith(parent + "."):
                    graph[name].add(parent)
    return graph


def cycles(mods: Dict[str, Module]) -> Dict[str, List[str]]:
    """(b) {module: one import cycle through it} for every module on a cycle."""
    graph, found = import_graph(mods), {}
    for start in sorted(graph):
        path = _path(graph, start, start)
        if path:
            found[start] = path
    return found


def _path(graph, start, goal):
    """The shortest import path start → … → goal (breadth first), or None."""
    prev, todo = {start: None}, [start]
    while todo:
        nxt = []
        for node in todo:
            for t in sorted(graph[node]):
                if t == goal:
                    path = [node]
                    while prev[path[-1]] is not None:
                        path.append(prev[path[-1]])
                    return path[::-1] + [goal]
                if t not in prev:
                    prev[t] = node
                    nxt.append(t)
        todo = nxt
    return None


def lazy_core_imports(mods: Dict[str, Module], name: str) -> List[str]:
    """(c) function-level imports of project modules inside core."""
    if name.split(".")[0] != "core":
        return []
    return [str(imp) for imp in mods[name].imports if imp.lazy]


def private_definitions(mods: Dict[str, Module]) -> Dict[str, Set[str]]:
    """{private function, method or class name: the packages that define it}."""
    defs: Dict[str, Set[str]] = {}
    for mod in mods.values():
        for node in ast.walk(mod.tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) \
                    and _private(node.name):
                defs.setdefault(node.name, set()).add(package_of(mod.name))
    return defs


def own_private_names(mod: Module) -> Set[str]:
    """Private names a module gives itself: defined, or assigned as an attribute (``x._n = …``,
    an object's own state)."""
    names = set()
    for node in ast.walk(mod.tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)                     # class-body attributes, __slots__-free
    return {n for n in names if _private(n)}


def _private(name: str) -> bool:
    return name.startswith("_") and not name.endswith("_") and name not in STDLIB_PRIVATE


def private_crossings(mods: Dict[str, Module], name: str, defs=None) -> List[str]:
    """(d) private names of another package: imported, or used as an attribute."""
    defs = private_definitions(mods) if defs is None else defs
    pkg, bad = package_of(name), []
    for imp in mods[name].imports:
        if imp.target in mods and package_of(imp.target) != pkg:
            bad += [f"{imp}: imports {n}" for n in imp.names
                    if _private(n) and n not in PRIVATE_ALLOWED]
    own = set().union(*(own_private_names(m) for m in mods.values() if package_of(m.name) == pkg))
    for node in ast.walk(mods[name].tree):
        if isinstance(node, ast.Attribute) and _private(node.attr) and node.attr not in own \
                and node.attr not in PRIVATE_ALLOWED and pkg not in defs.get(node.attr, {pkg}):
            bad.append(f"line {node.lineno}: .{node.attr} is private to "
                       f"{', '.join(sorted(defs[node.attr]))}")
    return bad


def non_face_imports(mods: Dict[str, Module], name: str) -> List[str]:
    """(e) imports by the plugin of a core module that is not a package face."""
    if name.split(".")[0] != "easyidp_qgis":
        return []
    return [f"{imp} is not a package face: import it from "
            f"{package_of(imp.target)}" for imp in mods[name].imports
            if imp.target in mods and imp.target.split(".")[0] == "core"
            and not mods[imp.target].is_package and package_of(imp.target) != imp.target]


PATH_NAMED = re.compile(r"(?<![\w/.])((?:core|easyidp_qgis)/[\w/]+\.py)\b")


def missing_paths(text: str, root: Path) -> List[str]:
    """Paths ``core/….py`` and ``easyidp_qgis/….py`` named in ``text`` that do not exist."""
    return sorted({p for p in PATH_NAMED.findall(text) if not (root / p).is_file()})


# ---- the project -------------------------------------------------------------------------------
def _project() -> Dict[str, Module]:
    sources = {}
    for top in ("core", "easyidp_qgis"):
        for path in sorted((ROOT / top).rglob("*.py")):
            name, is_package = module_name(path, ROOT)
            sources[name] = (path.read_text(encoding="utf-8"), is_package)
    return parse_sources(sources)


MODS = _project()
CORE = sorted(n for n in MODS if n.split(".")[0] == "core")
PLUGIN = sorted(n for n in MODS if n.split(".")[0] == "easyidp_qgis")
DEFS = private_definitions(MODS)
CYCLES = cycles(MODS)


def test_every_package_has_a_layer():
    packages = {n.split(".")[1] for n in CORE if "." in n and MODS[n].is_package}
    assert packages <= set(LAYER_OF), f"packages with no layer in LAYERS: {packages - set(LAYER_OF)}"


@pytest.mark.parametrize("name", CORE + PLUGIN)
def test_no_upward_import(name):
    assert upward_imports(MODS, name) == []


@pytest.mark.parametrize("name", CORE)
def test_no_import_cycle(name):
    assert name not in CYCLES, f"import cycle: {' -> '.join(CYCLES[name])}"


@pytest.mark.parametrize("name", CORE)
def test_no_function_level_import_of_core(name):
    assert lazy_core_imports(MODS, name) == []


@pytest.mark.parametrize("name", CORE + PLUGIN)
def test_no_private_name_crosses_a_package(name):
    assert private_crossings(MODS, name, DEFS) == []


@pytest.mark.parametrize("name", PLUGIN)
def test_plugin_imports_only_package_faces(name):
    assert non_face_imports(MODS, name) == []


def test_architecture_names_existing_files():
    text = (ROOT / "ARCHITECTURE.md").read_text(encoding="utf-8")
    assert PATH_NAMED.findall(text), "ARCHITECTURE.md names no file: the pattern is broken"
    assert missing_paths(text, ROOT) == []


def optional_packages(root: Path) -> List[str]:
    """The modules easyidp_qgis/dependencies.py lists as needed by some tools only (not ALL)."""
    tree = ast.parse((root / "easyidp_qgis" / "dependencies.py").read_text(encoding="utf-8"))
    return sorted(call.args[0].value for call in ast.walk(tree)
                  if isinstance(call, ast.Call) and getattr(call.func, "id", "") == "Dependency"
                  and not (isinstance(call.args[2], ast.Name) and call.args[2].id == "ALL"))


FACES = sorted(n for n in CORE if MODS[n].is_package or n.count(".") == 1)


def test_every_face_imports_without_the_optional_packages():
    """The plugin loads (and says what to install) when a tool's packages are missing: every
    package face and basic module imports with them blocked; they are imported where used."""
    optional = optional_packages(ROOT)
    assert {"tifffile", "laspy", "shapely"} <= set(optional)
    with tempfile.TemporaryDirectory() as folder:   # the package as installed: easyidp_toolbox
        os.symlink(ROOT, os.path.join(folder, PACKAGE))
        script = textwrap.dedent(f"""
            import importlib, importlib.abc, sys
            class Block(importlib.abc.MetaPathFinder):
                def find_spec(self, name, path, target=None):
                    if name.split(".")[0] in {optional!r}:
                        raise ImportError("blocked " + name)
            sys.meta_path.insert(0, Block())
            sys.path.insert(0, {folder!r})
            failed = []
            for face in {FACES!r}:
                try:
                    importlib.import_module("{PACKAGE}." + face)
                except ImportError as e:
                    failed.append(face + ": " + str(e))
            print(repr(failed))
            """)
        out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                             check=True).stdout
    assert ast.literal_eval(out.strip().splitlines()[-1]) == []


# ---- the checks can fail -----------------------------------------------------------------------
def _synthetic(files: Dict[str, str]) -> Dict[str, Module]:
    """Modules from {path: source}."""
    return parse_sources({module_name(Path(p), Path("."))[0]: (src, p.endswith("__init__.py"))
                          for p, src in files.items()})


def test_checks_can_fail(tmp_path):
    mods = _synthetic({
        "core/__init__.py": "from .roi import ROI\n",
        "core/errors.py": "",
        "core/crs.py": "def f():\n    from .errors import InputError\n",
        "core/roi/__init__.py": "from .model import ROI\n",
        "core/roi/model.py": "from ..raster.crop import crop\nfrom ..raster import geotiff\n",
        "core/raster/__init__.py": "from .crop import crop\n",
        "core/raster/crop.py": "from ..roi.model import ROI\nfrom ..roi.model import _ring\n",
        "core/raster/geotiff.py": "def _decode(): pass\n",
        "core/pointcloud/__init__.py": "from ..raster import crop\n",
        "core/season/__init__.py": "import easyidp_toolbox.core.roi\n"
                                   "def g(t):\n    return t._decode(), t._replace()\n",
        "easyidp_qgis/__init__.py": "from ..core.raster.crop import crop\n"
                                    "from ..core import errors, roi, raster\n",
    })
    assert [s.split(":")[0] for s in upward_imports(mods, "core.roi.model")] == ["line 1", "line 2"]
    assert upward_imports(mods, "core.pointcloud") != []              # same layer, other package
    assert upward_imports(mods, "core.raster.crop") == []
    assert set(cycles(mods)) >= {"core.roi.model", "core.raster.crop"}
    assert "core.season" not in cycles(mods)
    assert lazy_core_imports(mods, "core.crs") == ["line 2: function-level core.errors (InputError)"]
    assert private_crossings(mods, "core.raster.crop")[0].endswith("imports _ring")
    assert private_crossings(mods, "core.season") == ["line 3: ._decode is private to core.raster"]
    assert private_crossings(mods, "core.raster.geotiff") == []
    assert len(non_face_imports(mods, "easyidp_qgis")) == 1
    (tmp_path / "core").mkdir()
    (tmp_path / "core" / "a.py").write_text("")
    assert missing_paths("`core/a.py` and core/b.py, not x/core/c.py", tmp_path) == ["core/b.py"]
