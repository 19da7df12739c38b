"""QGIS 4 (Qt6) readiness of the plugin's code (``easyidp_qgis/`` and ``__init__.py``), checked
against the QGIS that runs the tests: every Qt or QGIS enum member is reached through its own
enum (``Qgis.MessageLevel.Info``, never ``Qgis.Info``: Qt6 builds have no unscoped aliases), and
nothing that Qt6 removed is used (``exec_``, ``QRegExp``, ``QDesktopWidget``, ``QVariant`` types
or ``QVariant()`` as NULL, compiled resources, ``QFontMetrics.width``, PyQt5 imports). The enums
that moved between QGIS versions come from ``easyidp_qgis/compat.py``, whose old names are
strings."""
import ast
import enum
import importlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

REMOVED = {     # names Qt6 (or QGIS 4) no longer has, and what to use instead
    "exec_": "exec()",
    "QRegExp": "QRegularExpression",
    "QRegExpValidator": "QRegularExpressionValidator",
    "QDesktopWidget": "QScreen (QApplication.primaryScreen())",
    "qApp": "QApplication.instance()",
    "resources_rc": "icons and .ui files by their path",
    "QMatrix": "QTransform",
    "QGLWidget": "QOpenGLWidget",
}


def _is_enum_member(obj) -> bool:
    """A Python enum member (Qt6, QGIS's scoped enums) or a sip enum member (an int subclass)."""
    return isinstance(obj, enum.Enum) or (isinstance(obj, int) and type(obj) not in (int, bool))


def _qt_names(tree) -> dict:
    """{local name: object} of what a module imports from qgis.* (Qt through qgis.PyQt)."""
    names = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module and \
                node.module.split(".")[0] == "qgis":
            module = importlib.import_module(node.module)
            for alias in node.names:
                if hasattr(module, alias.name):
                    names[alias.asname or alias.name] = getattr(module, alias.name)
    return names


def _resolve(node, names):
    """The object an ``a.b.c`` chain rooted at an imported Qt/QGIS name is, or None."""
    if isinstance(node, ast.Name):
        return names.get(node.id)
    if isinstance(node, ast.Attribute):
        owner = _resolve(node.value, names)
        return None if owner is None else getattr(owner, node.attr, None)
    return None


def qt6_problems(path: Path) -> list:
    """``file:line: what`` for each Qt5-only or unscoped name in the Python file ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    names = _qt_names(tree)
    found = []

    def say(node, text):
        found.append(f"{path.name}:{node.lineno}: {text}")

    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            modules = [a.name for a in node.names] + [getattr(node, "module", None) or ""]
            for m in modules:
                if m.split(".")[0] in ("PyQt5", "PyQt4", "PyQt6"):
                    say(node, f"import from {m}: use qgis.PyQt")
            for alias in node.names:
                if alias.name in REMOVED:
                    say(node, f"{alias.name}: removed in Qt6, use {REMOVED[alias.name]}")
        elif isinstance(node, ast.Name) and node.id in REMOVED:
            say(node, f"{node.id}: removed in Qt6, use {REMOVED[node.id]}")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                node.func.id == "QVariant":
            say(node, "QVariant(...): use qgis.core.NULL (QGIS 4 has no QVariant() as NULL)")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr == "width" and isinstance(node.func.value, ast.Call) and \
                getattr(node.func.value.func, "attr", getattr(node.func.value.func, "id", "")) in \
                ("fontMetrics", "QFontMetrics", "QFontMetricsF"):
            say(node, "QFontMetrics.width(): removed in Qt6, use horizontalAdvance()")
        elif isinstance(node, ast.Attribute):
            if node.attr in REMOVED:
                say(node, f".{node.attr}: removed in Qt6, use {REMOVED[node.attr]}")
                continue
            if isinstance(node.value, ast.Name) and node.value.id == "QVariant":
                say(node, f"QVariant.{node.attr}: QGIS 4 declares types with QMetaType; use "
                          "compat.FieldType")
                continue
            owner = _resolve(node.value, names)
            if owner is None:
                continue
            if not hasattr(owner, node.attr):
                say(node, f"{ast.unparse(node)}: not in this QGIS ({_version()}); an enum that "
                          "moved between versions belongs in compat.py")
                continue
            member = getattr(owner, node.attr)
            if not _is_enum_member(member):
                continue
            kind = type(member)
            scoped = f"{kind.__qualname__}.{getattr(member, 'name', None) or node.attr}"
            if owner is not kind:
                say(node, f"{ast.unparse(node)}: unscoped enum, use {scoped} (or its name in "
                          "compat.py)")
            elif isinstance(member, enum.Enum) and member.name != node.attr and \
                    kind.__module__.startswith("qgis"):
                say(node, f"{ast.unparse(node)}: an old alias, use {scoped}")
    return sorted(set(found))


def _version() -> str:
    from qgis.core import Qgis
    return Qgis.QGIS_VERSION


def _plugin_files():
    return sorted((ROOT / "easyidp_qgis").rglob("*.py")) + [ROOT / "__init__.py"]


def test_the_plugin_uses_no_qt5_only_or_unscoped_name(qgis_app):
    problems = [p for f in _plugin_files() for p in qt6_problems(f)]
    assert problems == [], "\n".join(problems)


PLANTED = '''
from qgis.core import Qgis, QgsFeatureSink, QgsProcessing, QgsWkbTypes
from qgis.PyQt.QtCore import QRegExp, Qt, QVariant
from PyQt5.QtWidgets import QDesktopWidget
from . import resources_rc

a = QgsProcessing.TypeVectorPolygon
b = QgsFeatureSink.FastInsert
c = Qgis.Info
d = Qt.AlignLeft
e = QVariant.String
f = QVariant()
g = QRegExp("x")
dialog.exec_()
w = widget.fontMetrics().width("text")
h = QgsWkbTypes.NoSuchEnumMember
'''

FINE = '''
from qgis.core import Qgis, QgsFeatureSink, QgsWkbTypes
from qgis.PyQt.QtCore import Qt

from .compat import ProcessingSourceType

a = ProcessingSourceType.VectorPolygon
b = QgsFeatureSink.Flag.FastInsert
c = Qgis.MessageLevel.Info
d = Qt.AlignmentFlag.AlignLeft
e = QgsWkbTypes.geometryType
dialog.exec()
w = widget.fontMetrics().horizontalAdvance("text")
'''


def test_the_check_finds_planted_qt5_names(qgis_app, tmp_path):
    """The check is real: each planted Qt5-only or unscoped name is reported, with its line;
    their Qt6 forms are not."""
    bad = tmp_path / "bad.py"
    bad.write_text(PLANTED)
    problems = qt6_problems(bad)
    text = "\n".join(problems)
    for line, what in ((3, "QRegExp: removed"), (4, "use qgis.PyQt"),
                       (4, "QDesktopWidget: removed"), (5, "resources_rc: removed"),
                       (7, "QgsProcessing.TypeVectorPolygon: unscoped enum"),
                       (8, "QgsFeatureSink.FastInsert: unscoped enum, use QgsFeatureSink.Flag."),
                       (9, "Qgis.Info: unscoped enum, use Qgis.MessageLevel.Info"),
                       (10, "Qt.AlignLeft: unscoped enum, use Qt.AlignmentFlag.AlignLeft"),
                       (11, "QVariant.String: QGIS 4 declares types with QMetaType"),
                       (12, "QVariant(...): use qgis.core.NULL"), (13, "QRegExp: removed"),
                       (14, ".exec_: removed in Qt6"), (15, "QFontMetrics.width()"),
                       (16, "QgsWkbTypes.NoSuchEnumMember: not in this QGIS")):
        assert any(p.startswith(f"bad.py:{line}: ") and what in p for p in problems), \
            (line, what, text)
    fine = tmp_path / "fine.py"
    fine.write_text(FINE)
    assert qt6_problems(fine) == []
