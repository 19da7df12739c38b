"""Refresh ``i18n/easyidp_<lang>.ts`` from the ``self.tr("…")`` literals and compile ``.qm``.

Existing translations are kept; new strings are added as unfinished. Context: ``EasyIDP``.
Usage: python -m easyidp_toolbox.scripts.update_translations  (needs lrelease: qttools5-dev-tools)
"""
import ast
import glob
import os
import subprocess
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LANGS = ("zh_CN", "ja")
TRANSLATED_ATTRIBUTES = {"DISPLAY", "GROUP", "HELP"}


def source_strings():
    """Literal arguments of ``*.tr("…")`` calls and DISPLAY/GROUP/HELP class attributes."""
    found = []
    for path in sorted(glob.glob(os.path.join(ROOT, "easyidp_qgis", "**", "*.py"), recursive=True)):
        for node in ast.walk(ast.parse(open(path, encoding="utf-8").read())):
            value = None
            if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "tr" and node.args:
                value = node.args[0]
            elif isinstance(node, ast.Assign) and any(getattr(t, "id", None) in TRANSLATED_ATTRIBUTES
                                                      for t in node.targets):
                value = node.value
            if isinstance(value, ast.Constant) and isinstance(value.value, str) and value.value \
                    and value.value not in found:
                found.append(value.value)
    return found


def update(lang, strings):
    ts = os.path.join(ROOT, "i18n", f"easyidp_{lang}.ts")
    known = {}
    if os.path.exists(ts):
        for msg in ET.parse(ts).getroot().iter("message"):
            tr = msg.find("translation")
            if tr is not None and tr.text and tr.get("type") != "unfinished":
                known[msg.findtext("source")] = tr.text
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


if __name__ == "__main__":
    strings = source_strings()
    for lang in LANGS:
        done, total = update(lang, strings)
        print(f"{lang}: {done}/{total} strings translated")
