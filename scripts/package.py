"""Build the plugin zip for *Plugins ▸ Install from ZIP* and plugins.qgis.org, and check it.

    python -m easyidp_toolbox.scripts.package [--output DIR] [--strict]   (make package [STRICT=1])

writes ``DIR/easyidp_toolbox-<version>.zip`` (default ``dist/``): the folder ``easyidp_toolbox/``
with only what runs (``__init__.py``, ``metadata.txt``, ``LICENSE``, the code of ``core/`` and
``easyidp_qgis/``, icons, compiled translations ``.qm``, styles). The version comes from
``metadata.txt``. Files are the ones git tracks or would track (not ignored; every file of the
tree when it is not a git checkout).

Checks, as the QGIS plugin repository applies them (qgis/QGIS-Django,
``qgis-app/plugins/validator.py``; versions as its ``VersionField`` sorts them), are errors;
placeholders the repository would accept but that are not real (example.org addresses) are
warnings, which ``--strict`` turns into errors. ``qgisMaximumVersion`` must be there and be a
QGIS 4 version (4.99): without it QGIS 4 and the repository hide the plugin from QGIS 4 users;
``supportsQt6=True`` must be there too (Qt 6 builds of QGIS flag plugins without it).
``metadata.txt``'s version and changelog must be what ``scripts/changelog.py`` makes of
``core.__version__`` and ``CHANGELOG.md``.

The zip's contents then go through the repository's scan (``security_scan``): Bandit with the
rules the repository enables (``BANDIT_RULES``; it blocks on findings of every severity,
hard-coded passwords B105–B107 included), detect-secrets, and the plugin-repository checks of
``qgis-plugin-analyzer``. Any finding is an error, except one on a line with ``# nosec <rule>``
followed by its reason (a ``# nosec`` without a rule or a reason is an error itself). Writes
through the project's one atomic writer (``core.files.atomic_output``), so it runs in the
plugin's environment (``make env``), which has the three scanners (``requirements/qgis.txt``).
"""
import argparse
import configparser
import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path
from typing import List, Optional, Tuple

from ..core.files import atomic_output
from .changelog import expected_metadata

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PLUGIN_ID = "easyidp_toolbox"
MAX_SIZE = 25_000_000  # the repository's upload limit (PLUGIN_MAX_UPLOAD_SIZE)
TOP_FILES = ("__init__.py", "metadata.txt", "LICENSE")
RUNTIME_DIRS = ("core", "easyidp_qgis", "icons", "i18n", "styles")
RUNTIME_SUFFIXES = (".py", ".qm", ".svg", ".png", ".qml", ".json")
REQUIRED = ("name", "description", "version", "qgisMinimumVersion", "author", "email", "about",
            "tracker", "repository")  # the repository's PLUGIN_REQUIRED_METADATA
URL_FIELDS = ("tracker", "repository", "homepage")
FORBIDDEN_URLS = ("http://bugs", "http://repo", "http://homepage")  # the plugin builder defaults
# The Bandit rules plugins.qgis.org enables (its bandit_rules.json, QGIS-Plugins-Website, 2026):
# every rule but B109, B404 (import subprocess), B410 (import lxml) and B411 (import xmlrpc).
# Both its "critical" and its "warning" rules are refused here, at every Bandit severity.
BANDIT_RULES = (
    "B101", "B102", "B103", "B104", "B105", "B106", "B107", "B108", "B110", "B111", "B112",
    "B113", "B201", "B202", "B301", "B302", "B303", "B304", "B305", "B306", "B307", "B308",
    "B310", "B311", "B312", "B313", "B314", "B315", "B316", "B317", "B318", "B319", "B320",
    "B321", "B323", "B324", "B401", "B402", "B403", "B405", "B406", "B407", "B408", "B409",
    "B412", "B413", "B501", "B502", "B503", "B504", "B505", "B506", "B507", "B508", "B509",
    "B601", "B602", "B603", "B604", "B605", "B606", "B607", "B608", "B609", "B610", "B611",
    "B612", "B613", "B614", "B615", "B701", "B702", "B703", "B704")
# "# nosec B603 -- why" (or ": why"): rule ids, then a reason of a few words
NOSEC = re.compile(r"#\s*nosec\b(?P<rest>.*)$")
NOSEC_JUSTIFIED = re.compile(r"^:?\s*B\d{3}(\s*,\s*B\d{3})*\s*(--|:|-|#)\s*\S.{8,}")
PLACEHOLDER_HOSTS = re.compile(r"(^|\.)(example\.(org|com|net)|localhost|[^.]+\.(example|invalid|test))$",
                               re.IGNORECASE)


# --- metadata ---------------------------------------------------------------------------------

def read_metadata(text: str) -> dict:
    parser = configparser.ConfigParser(interpolation=None)
    parser.optionxform = str
    parser.read_string(text)
    if not parser.has_section("general"):
        raise ValueError("metadata.txt has no [general] section")
    return dict(parser.items("general"))


def _host(url: str) -> str:
    match = re.match(r"^[A-Za-z][A-Za-z0-9+.-]*://([^/?#:@]*@)?([^/?#:]+)", url or "")
    return match.group(2) if match else ""


def check_metadata(meta: dict, names: Optional[List[str]] = None) -> Tuple[List[str], List[str]]:
    """(errors, warnings) for ``metadata.txt`` values; ``names``: the plugin's files, to find
    the icon and the licence (paths relative to the plugin folder)."""
    errors, warnings = [], []
    for key in REQUIRED:
        if not meta.get(key, "").strip():
            errors.append(f"metadata.txt: {key} is required by the plugin repository")
    version = meta.get("version", "").strip()
    if version and not re.fullmatch(r"[0-9]{1,3}(\.[0-9]{1,3}){1,3}", version):
        errors.append(f"metadata.txt: version {version!r} must be 2 to 4 dotted numbers of up to "
                      "3 digits (the repository sorts versions as a.b.c.d)")
    value = meta.get("qgisMinimumVersion", "").strip()
    if value and not re.fullmatch(r"3\.[0-9]{1,2}(\.[0-9]{1,2})?", value):
        errors.append(f"metadata.txt: qgisMinimumVersion {value!r} must be a QGIS 3 version such "
                      "as 3.22")
    value = meta.get("qgisMaximumVersion", "").strip()
    if not re.fullmatch(r"4\.[0-9]{1,2}(\.[0-9]{1,2})?", value):
        errors.append(f"metadata.txt: qgisMaximumVersion {value or '(missing)'} must be a QGIS 4 "
                      "version, 4.99: without it QGIS 4 and plugins.qgis.org hide the plugin "
                      "from QGIS 4 users")
    if version and not re.search(rf"(?mi)^\s*(version\s*)?v?{re.escape(version)}\b",
                                 meta.get("changelog", "")):
        errors.append(f"metadata.txt: changelog has no entry for version {version} (a line "
                      f"starting with '{version}')")
    if "/" in meta.get("author", ""):
        errors.append("metadata.txt: the repository refuses an author with a slash")
    email = meta.get("email", "").strip()
    if email and not re.fullmatch(r"[^@\s]+@[^@\s]+\.[^@\s]+", email):
        errors.append(f"metadata.txt: email {email!r} is not an address")
    elif PLACEHOLDER_HOSTS.search(email.rsplit("@", 1)[-1]):
        warnings.append(f"metadata.txt: email {email} is a placeholder; give the maintainers' "
                        "address before uploading to plugins.qgis.org")
    for key in URL_FIELDS:
        url = meta.get(key, "").strip()
        if not url:
            continue
        if url in FORBIDDEN_URLS or not re.match(r"^https?://", url) or not _host(url):
            errors.append(f"metadata.txt: {key} {url!r} is not a valid http(s) address")
        elif PLACEHOLDER_HOSTS.search(_host(url)):
            warnings.append(f"metadata.txt: {key} {url} is a placeholder; give the project's "
                            "public address before uploading to plugins.qgis.org")
    for key in ("experimental", "deprecated", "server"):
        value = meta.get(key)
        if value is not None and value.strip().lower() not in ("true", "false", "1", "0"):
            errors.append(f"metadata.txt: {key} must be True or False, not {value!r}")
    if meta.get("supportsQt6", "").strip().lower() not in ("true", "yes", "1"):
        errors.append("metadata.txt: supportsQt6=True is needed: Qt 6 builds of QGIS (3.44, "
                      "4.x) flag plugins without it")
    if meta.get("hasProcessingProvider", "").strip().lower() != "yes":
        errors.append("metadata.txt: hasProcessingProvider=yes is needed for qgis_process")
    if names is not None:
        icon = meta.get("icon", "").strip()
        if icon and icon.lstrip("./") not in names:
            errors.append(f"metadata.txt: icon {icon} is not in the package")
        if "LICENSE" not in names:
            errors.append("LICENSE is missing (the repository requires it since June 2024)")
    return errors, warnings


# --- files and zip ----------------------------------------------------------------------------

def _candidates(root: str) -> List[str]:
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                              "--exclude-standard"], capture_output=True, check=True)
        return [p for p in out.stdout.decode("utf-8").split("\0") if p]
    except (OSError, subprocess.CalledProcessError):
        found = []
        for folder, dirs, files in os.walk(root):
            dirs[:] = [d for d in dirs if not d.startswith(".") and d != "__pycache__"]
            found += [os.path.relpath(os.path.join(folder, f), root).replace(os.sep, "/")
                      for f in files]
        return found


def plugin_files(root: str = ROOT) -> List[str]:
    """The files that run, relative to ``root`` with ``/``, sorted."""
    keep = []
    for path in _candidates(root):
        parts = path.split("/")
        if path in TOP_FILES or (parts[0] in RUNTIME_DIRS and path.endswith(RUNTIME_SUFFIXES)
                                 and "__pycache__" not in parts):
            if os.path.isfile(os.path.join(root, path)):
                keep.append(path)
    return sorted(keep)


def _commit_time(root: str):
    try:
        out = subprocess.run(["git", "-C", root, "log", "-1", "--format=%ct"],
                             capture_output=True, text=True, check=True)
        import time
        return time.gmtime(int(out.stdout.strip()))[:6]
    except (OSError, subprocess.CalledProcessError, ValueError):
        return (2026, 1, 1, 0, 0, 0)


def build(output_dir: str, root: str = ROOT, strict: bool = False) -> Tuple[str, List[str]]:
    """Write the zip; returns (its path, warnings). Raises ValueError listing the errors."""
    with open(os.path.join(root, "metadata.txt"), encoding="utf-8") as fh:
        meta = read_metadata(fh.read())
    names = plugin_files(root)
    errors, warnings = check_metadata(meta, names)
    if os.path.isfile(os.path.join(root, "CHANGELOG.md")):
        current, wanted = expected_metadata(Path(root))
        if current != wanted:
            errors.append("metadata.txt's version or changelog is out of step with "
                          "core.__version__ and CHANGELOG.md: run make changelog")
    for ts in (n for n in _candidates(root) if n.startswith("i18n/") and n.endswith(".ts")):
        if ts[:-3] + ".qm" not in names:
            errors.append(f"{ts} has no compiled {os.path.basename(ts)[:-3]}.qm (run "
                          "python -m easyidp_toolbox.scripts.update_translations)")
    if strict:
        errors, warnings = errors + warnings, []
    if errors:
        raise ValueError("the plugin cannot be packaged:\n  " + "\n  ".join(errors))
    os.makedirs(output_dir, exist_ok=True)
    path = os.path.join(output_dir, f"{PLUGIN_ID}-{meta['version'].strip()}.zip")
    stamp = _commit_time(root)
    folders = sorted({"/".join(n.split("/")[:i]) for n in names for i in range(1, n.count("/") + 1)})
    with atomic_output(path) as tmp:       # the one atomic writer of the project
        with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED, compresslevel=9) as zf:
            for entry in [""] + folders:
                info = zipfile.ZipInfo(f"{PLUGIN_ID}/{entry}/".replace("//", "/"), stamp)
                info.external_attr = (0o40755 << 16) | 0x10
                zf.writestr(info, b"")
            for name in names:
                info = zipfile.ZipInfo(f"{PLUGIN_ID}/{name}", stamp)
                info.external_attr = 0o100644 << 16
                info.compress_type = zipfile.ZIP_DEFLATED
                with open(os.path.join(root, name), "rb") as fh:
                    zf.writestr(info, fh.read())
        problems = check_zip(str(tmp))
        if problems:
            raise ValueError("the zip fails the repository's checks:\n  " + "\n  ".join(problems))
        problems, notes = security_scan(str(tmp))
        if problems:
            raise ValueError("the plugin repository's scan would refuse the zip:\n  "
                             + "\n  ".join(problems))
        warnings += notes
    return path, warnings


def security_scan(path: str) -> Tuple[List[str], List[str]]:
    """The repository's scan over the zip's contents: (errors, warnings).

    Errors: Bandit findings of ``BANDIT_RULES`` at any severity (``file:line rule: text``),
    ``# nosec`` comments without a rule and a reason, detect-secrets findings, and what
    qgis-plugin-analyzer says the repository would refuse. Warnings: the analyzer's notes on
    addresses it could not check. Raises ValueError when a scanner cannot run."""
    import tempfile
    with tempfile.TemporaryDirectory(prefix="easyidp-scan-") as tmp:
        with zipfile.ZipFile(path) as zf:
            zf.extractall(tmp)
        folder = os.path.join(tmp, PLUGIN_ID)
        errors = _bandit(folder) + _unjustified_nosec(folder) + _detect_secrets(folder)
        more, warnings = _plugin_analyzer(folder)
    return errors + more, warnings


def _run_json(argv: List[str], what: str, cwd: Optional[str] = None) -> dict:
    proc = subprocess.run(argv, capture_output=True, text=True, cwd=cwd)
    try:
        return json.loads(proc.stdout)
    except ValueError:
        raise ValueError(f"{what} could not scan the zip (make env installs it from "
                         f"requirements/qgis.txt): {proc.stderr.strip()[-500:]}") from None


def _bandit(folder: str) -> List[str]:
    report = _run_json([sys.executable, "-m", "bandit", "-r", "-q", "-f", "json", "-t",
                        ",".join(BANDIT_RULES), folder], "Bandit")
    return [f"Bandit: {os.path.relpath(r['filename'], folder)}:{r['line_number']} "
            f"{r['test_id']} ({r['issue_severity']}): {r['issue_text']}"
            for r in report.get("results", [])]


def _unjustified_nosec(folder: str) -> List[str]:
    bad = []
    for base, _dirs, files in os.walk(folder):
        for name in sorted(f for f in files if f.endswith(".py")):
            file = os.path.join(base, name)
            with open(file, encoding="utf-8") as fh:
                for number, line in enumerate(fh, 1):
                    match = NOSEC.search(line)
                    if match and not NOSEC_JUSTIFIED.match(match.group("rest").strip()):
                        bad.append(f"{os.path.relpath(file, folder)}:{number}: a # nosec must "
                                   "name its rule and say why, e.g. '# nosec B603 -- the "
                                   "command is this Python with fixed arguments'")
    return bad


def _detect_secrets(folder: str) -> List[str]:
    report = _run_json([sys.executable, "-m", "detect_secrets", "scan", "--all-files", "."],
                       "detect-secrets", cwd=folder)
    return [f"detect-secrets: {name}:{hit.get('line_number')} {hit.get('type')}"
            for name, hits in sorted(report.get("results", {}).items()) for hit in hits]


def _plugin_analyzer(folder: str) -> Tuple[List[str], List[str]]:
    """qgis-plugin-analyzer's repository checks: structure, metadata, binaries, constraints.
    Its style and translation findings (thousands, most in core/, which has no Qt) and its
    Bandit-like findings (it does not honour ``# nosec``; Bandit itself runs above) are not the
    repository's rules and are not reported."""
    import shutil
    import tempfile
    exe = shutil.which("qgis-analyzer", path=os.path.dirname(sys.executable))
    if exe is None:
        raise ValueError("qgis-plugin-analyzer is not installed (make env installs it from "
                         "requirements/qgis.txt)")
    with tempfile.TemporaryDirectory(prefix="easyidp-analyzer-") as out:
        report = _run_json([exe, "analyze", folder, "--json", "--linters", "none", "--no-cache",
                            "-o", out], "qgis-plugin-analyzer")
    compliance = report.get("repository_compliance", {})
    standards = report.get("qgis_compliance", {}).get("repository_standards", {})
    errors = [f"qgis-plugin-analyzer: {e}" for e in compliance.get("constraint_errors", [])]
    errors += [f"qgis-plugin-analyzer: binary file {b}" for b in compliance.get("binaries", [])]
    if not compliance.get("folder_name_valid", True):
        errors.append("qgis-plugin-analyzer: the folder name is not valid for the repository")
    for part in ("structure", "metadata"):
        section = standards.get(part, {})
        if not section.get("is_valid", True):
            errors.append(f"qgis-plugin-analyzer: the plugin's {part} is not valid: missing "
                          f"{section.get('missing') or section.get('missing_files')}")
    if not errors and compliance.get("is_compliant") is False:
        errors.append("qgis-plugin-analyzer: the plugin is not compliant with the repository")
    warnings = [f"qgis-plugin-analyzer: {w}" for w in compliance.get("constraint_warnings", [])]
    warnings += [f"qgis-plugin-analyzer: {url} could not be checked ({state})"
                 for url, state in sorted(compliance.get("url_validation", {}).items())
                 if state not in ("ok", "valid")]
    return errors, warnings


def check_zip(path: str) -> List[str]:
    """What the plugin repository's validator would refuse in the zip (empty: nothing)."""
    problems = []
    if os.path.getsize(path) > MAX_SIZE:
        problems.append(f"larger than {MAX_SIZE // 1_000_000} MB")
    with zipfile.ZipFile(path) as zf:
        names = zf.namelist()
        bad = zf.testzip()
        if bad:
            problems.append(f"bad zip entry {bad}")
        for name in names:
            parts = name.split("/")
            if ".." in name or name.startswith(("/", "\\")):
                problems.append(f"path information in {name}")
            if ".pyc" in name:
                problems.append(f"compiled Python file {name}")
            if {"__MACOSX", ".git", "__pycache__"} & set(parts):
                problems.append(f"forbidden folder in {name}")
        tops = {n.split("/")[0] for n in names}
        if tops != {PLUGIN_ID}:
            problems.append(f"one top folder {PLUGIN_ID}/ expected, found {sorted(tops)}")
        if not names or "/" not in names[0] or not re.fullmatch(r"[a-z_][a-z0-9_]*",
                                                                   names[0].split("/")[0]):
            problems.append("the first entry must be inside a PEP 8 named folder")
        for required in ("__init__.py", "metadata.txt", "LICENSE"):
            if f"{PLUGIN_ID}/{required}" not in names:
                problems.append(f"{PLUGIN_ID}/{required} is missing")
        if f"{PLUGIN_ID}/metadata.txt" in names:
            meta = read_metadata(zf.read(f"{PLUGIN_ID}/metadata.txt").decode("utf-8"))
            inner = [n[len(PLUGIN_ID) + 1:] for n in names if not n.endswith("/")]
            problems += check_metadata(meta, inner)[0]
    return problems


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output", default=os.path.join(ROOT, "dist"))
    parser.add_argument("--root", default=ROOT, help="the plugin's source tree (default: this one)")
    parser.add_argument("--strict", action="store_true",
                        help="placeholders (example.org) are errors: for a release upload")
    args = parser.parse_args(argv)
    try:
        path, warnings = build(args.output, root=args.root, strict=args.strict)
    except ValueError as exc:
        print(f"ERROR: {exc}", file=sys.stderr)
        return 1
    with zipfile.ZipFile(path) as zf:
        count = sum(1 for n in zf.namelist() if not n.endswith("/"))
    print(f"{path}: {count} files, {os.path.getsize(path) / 1024:.0f} KiB")
    for warning in warnings:
        print(f"WARNING: {warning}", file=sys.stderr)
    if warnings:
        print("WARNING: not ready for plugins.qgis.org until the placeholders above are filled in "
              "(make package STRICT=1 checks that).", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
