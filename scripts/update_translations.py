"""Refresh ``i18n/easyidp_<lang>.ts`` from the user-facing strings and compile the ``.qm`` files.

The strings are found in ``easyidp_qgis/`` with ``ast``: the literal argument of every
``*.tr("…")`` call, the ``DISPLAY``/``GROUP``/``HELP`` class attributes, and every
``translatable("…")`` (strings kept in tables and translated later, such as choice labels).
``tr()`` never receives an f-string: format after translating (``tr("{n} ROIs").format(n=n)``).
Existing translations are kept; new strings are added as unfinished. Context: ``EasyIDP``.

    python -m easyidp_toolbox.scripts.update_translations          (needs lrelease)
    python -m easyidp_toolbox.scripts.update_translations --check  (exit 1 if any is missing)
"""
import ast
import glob
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LANGS = ("zh_CN", "ja")
TRANSLATED_ATTRIBUTES = {"DISPLAY", "GROUP", "HELP"}
MARKERS = {"tr", "translatable"}


def _literal(node):
    """The string of a literal (implicitly concatenated literals included), else None."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    return None


def _read(path: str) -> str:
    with open(path, encoding="utf-8") as fh:
        return fh.read()


def source_strings():
    """The user-facing strings, in source order, without repeats."""
    found = []
    for path in sorted(glob.glob(os.path.join(ROOT, "easyidp_qgis", "**", "*.py"), recursive=True)):
        for node in ast.walk(ast.parse(_read(path))):
            value = None
            if isinstance(node, ast.Call) and node.args:
                name = getattr(node.func, "attr", None) or getattr(node.func, "id", None)
                if name in MARKERS:
                    value = _literal(node.args[0])
            elif isinstance(node, ast.Assign) and any(getattr(t, "id", None) in TRANSLATED_ATTRIBUTES
                                                      for t in node.targets):
                value = _literal(node.value)
            if value and value not in found:
                found.append(value)
    return found


def untranslatable_calls():
    """``tr()`` calls whose argument the extraction cannot read: (file, line, source)."""
    out = []
    for path in sorted(glob.glob(os.path.join(ROOT, "easyidp_qgis", "**", "*.py"), recursive=True)):
        src = _read(path)
        for node in ast.walk(ast.parse(src)):
            if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "tr" and node.args:
                arg = node.args[0]
                ok = _literal(arg) is not None or (
                    isinstance(arg, ast.Attribute) and arg.attr in TRANSLATED_ATTRIBUTES) or (
                    isinstance(arg, (ast.Name, ast.Subscript, ast.Attribute))
                    and not isinstance(arg, ast.JoinedStr))
                if not ok:
                    out.append((os.path.relpath(path, ROOT), node.lineno,
                                ast.get_source_segment(src, node)[:80]))
    return out


def read_catalogue(lang):
    """{source: translation} of the finished messages of ``lang``."""
    ts = os.path.join(ROOT, "i18n", f"easyidp_{lang}.ts")
    known = {}
    if os.path.exists(ts):
        for msg in ET.parse(ts).getroot().iter("message"):
            tr = msg.find("translation")
            if tr is not None and tr.text and tr.get("type") != "unfinished":
                known[msg.findtext("source")] = tr.text
    return known


def update(lang, strings):
    ts = os.path.join(ROOT, "i18n", f"easyidp_{lang}.ts")
    known = read_catalogue(lang)
    root = ET.Element("TS", version="2.1", language=lang)
    ctx = ET.SubElement(root, "context")
    ET.SubElement(ctx, "name").text = "EasyIDP"
    for s in strings:
        msg = ET.SubElement(ctx, "message")
        ET.SubElement(msg, "source").text = s
        tr = ET.SubElement(msg, "translation")
        if s in known:
            tr.text = known[s]
        else:
            tr.set("type", "unfinished")
    ET.indent(root)
    with open(ts, "wb") as fh:
        fh.write(b'<?xml version="1.0" encoding="utf-8"?>\n<!DOCTYPE TS>\n')
        fh.write(ET.tostring(root, encoding="utf-8"))
    subprocess.run(["lrelease", "-silent", ts, "-qm", ts[:-3] + ".qm"], check=True)
    return sum(s in known for s in strings), len(strings)


def main(argv) -> int:
    strings = source_strings()
    bad = untranslatable_calls()
    for where in bad:
        print("tr() of a string the catalogue cannot hold: %s:%d %s" % where)
    if "--check" in argv:
        missing = {lang: [s for s in strings if s not in read_catalogue(lang)] for lang in LANGS}
        for lang, items in missing.items():
            print(f"{lang}: {len(strings) - len(items)}/{len(strings)} strings translated")
        return 1 if bad or any(missing.values()) else 0
    for lang in LANGS:
        done, total = update(lang, strings)
        print(f"{lang}: {done}/{total} strings translated")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
