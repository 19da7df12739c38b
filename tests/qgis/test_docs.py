"""The README and the documentation site kept true (issue 36).

* Every Python block of the README and of the English pages runs, page by page in one namespace,
  in a working folder that holds the demo survey (``demo/``, made once) and the tutorials'
  models (``models/``). A block that cannot run (a sketch with the reader's own file names) is
  preceded by ``<!-- no-test: why -->``.
* Shell blocks run only when preceded by ``<!-- run -->``: the tutorials' ``qgis_process``
  commands and models, through the real ``qgis_process`` with the plugin enabled.
* Every repository path the README and the docs name exists (in backticks or as a link).
* The translated pages (zh, ja) exist for every page that must have them, with the same headings
  count and the same code blocks as the English page.

The truths: the demo survey's truth file (written by the generator, independent of the tools
under test) in the tutorials' own checks; the file tree for the names; the English page for the
translations. The site in a browser: ``test_docs_site.py``.
"""
import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
LANGS = ("zh", "ja")

FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```[ \t]*$", re.S | re.M)
MARK = re.compile(r"<!--\s*(run|no-test)\b[^>]*-->\s*$")


def english_pages():
    """README.md and every English page of docs/ (translations end in .zh.md / .ja.md)."""
    pages = [ROOT / "README.md"]
    pages += sorted(p for p in DOCS.rglob("*.md") if not re.search(r"\.(zh|ja)\.md$", p.name))
    return pages


def blocks(path):
    """[(language, code, mark)] of the fenced blocks of ``path``; mark is 'run', 'no-test' or ''
    (the HTML comment on the line before the fence)."""
    text = path.read_text(encoding="utf-8")
    found = []
    for m in FENCE.finditer(text):
        before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        mark = MARK.search(before)
        found.append((m.group(1), m.group(2), mark.group(1) if mark else ""))
    return found


def page_id(path):
    return str(path.relative_to(ROOT))


PY_PAGES = [p for p in english_pages() if any(lang == "python" and mark != "no-test"
                                              for lang, _, mark in blocks(p))]
SH_PAGES = [p for p in english_pages() if any(lang == "sh" and mark == "run"
                                              for lang, _, mark in blocks(p))]


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    """The working folder of the pages: the demo survey in demo/, the tutorials' models in
    models/ (as a reader saves them next to the survey)."""
    from easyidp_toolbox.core.demo import make_demo_survey
    work = tmp_path_factory.mktemp("docs")
    make_demo_survey(str(work / "demo"))
    shutil.copytree(DOCS / "tutorials" / "models", work / "models")
    return work


def test_the_pages_have_blocks_to_run():
    """The README's example and every tutorial run: none of them is marked away."""
    assert ROOT / "README.md" in PY_PAGES
    tutorials = sorted(p for p in (DOCS / "tutorials").glob("*.md")
                       if p.name != "index.md" and not re.search(r"\.(zh|ja)\.md$", p.name))
    assert len(tutorials) >= 5
    for page in tutorials:
        assert page in PY_PAGES, f"{page_id(page)}: no Python block runs"
        assert page in SH_PAGES, f"{page_id(page)}: no qgis_process block runs"
        assert any("qgis_process.bin run models/" in code for _, code, mark in blocks(page)
                   if mark == "run"), f"{page_id(page)}: its model is not run"


@pytest.mark.parametrize("page", PY_PAGES, ids=page_id)
def test_python_blocks_run(page, workdir, monkeypatch):
    monkeypatch.chdir(workdir)
    namespace = {"__name__": "__main__"}
    for k, (lang, code, mark) in enumerate(blocks(page)):
        if lang != "python" or mark == "no-test":
            continue
        try:
            exec(compile(code, f"{page_id(page)} block {k + 1}", "exec"), namespace)
        except Exception as exc:
            raise AssertionError(f"{page_id(page)}, Python block {k + 1} fails:\n{code}") from exc


@pytest.mark.parametrize("page", SH_PAGES, ids=page_id)
def test_marked_shell_blocks_run(page, workdir, tmp_path):
    from easyidp_toolbox.scripts.qgis_process import qgis_process_env
    env = qgis_process_env(str(tmp_path / "profile"))
    for k, (lang, code, mark) in enumerate(blocks(page)):
        if lang != "sh" or mark != "run":
            continue
        proc = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", code], cwd=workdir, env=env,
                              capture_output=True, text=True, timeout=900)
        assert proc.returncode == 0, (f"{page_id(page)}, shell block {k + 1} fails "
                                      f"({proc.returncode}):\n{code}\n{proc.stderr[-3000:]}")


def test_every_model_is_valid_and_run_by_a_tutorial():
    """The models are QGIS models (written by scripts/tutorial_models.py) and each tutorial's
    marked blocks run one."""
    from easyidp_toolbox.scripts.tutorial_models import MODELS
    models = sorted(p.stem for p in (DOCS / "tutorials" / "models").glob("*.model3"))
    assert models == sorted(MODELS)
    run = " ".join(code for p in SH_PAGES for _, code, mark in blocks(p) if mark == "run")
    for name in models:
        assert f"models/{name}.model3" in run, f"no tutorial runs {name}.model3"
        text = (DOCS / "tutorials" / "models" / f"{name}.model3").read_text(encoding="utf-8")
        assert "easyidp:" in text


# a path in backticks that starts with a folder of the repository (a <placeholder> or a glob
# is not a path), or a relative link
TREE_PATH = re.compile(r"`((?:core|easyidp_qgis|tests|scripts|bench|docs|requirements|i18n|"
                       r"icons|\.ci)/[\w./-]*)`")
LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def named_paths(page):
    text = page.read_text(encoding="utf-8")
    for m in TREE_PATH.finditer(text):
        yield m.group(1), ROOT / m.group(1).rstrip("/")
    for m in LINK.finditer(text):
        target = m.group(1)
        if re.match(r"[a-z]+:", target):
            continue
        yield target, (page.parent / target)


@pytest.mark.parametrize("page", english_pages() + [ROOT / "ARCHITECTURE.md"], ids=page_id)
def test_named_files_exist(page):
    missing = sorted({name for name, path in named_paths(page) if not path.exists()})
    assert not missing, f"{page_id(page)} names files that do not exist: {missing}"


def test_named_files_check_catches_a_missing_file(tmp_path):
    """The check itself: a page naming a file that is not in the tree is caught."""
    page = tmp_path / "page.md"
    page.write_text("See `core/no_such_module.py` and [this](no_such_page.md); "
                    "`core/roi/open.py` exists.\n", encoding="utf-8")
    missing = sorted(name for name, path in named_paths(page) if not path.exists())
    assert missing == ["core/no_such_module.py", "no_such_page.md"]


# the pages EasyIDP has in Chinese and Japanese too: getting started, the tools, the first tutorial
TRANSLATED = (["index.md"] + [f"getting-started/{p}" for p in ("install.md", "engine.md", "demo.md")]
              + [f"user-guide/tools/{p.name}" for p in sorted((DOCS / "user-guide/tools").glob("*.md"))
                 if not re.search(r"\.(zh|ja)\.md$", p.name)]
              + ["tutorials/crop-plots.md"])
HEADING = re.compile(r"^#{1,6} ", re.M)


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("page", TRANSLATED)
def test_translations_complete(page, lang):
    en = DOCS / page
    tr = en.with_name(en.stem + f".{lang}.md")
    assert tr.exists(), f"{page} has no {lang} translation ({tr.relative_to(ROOT)})"
    text_en, text_tr = en.read_text(encoding="utf-8"), tr.read_text(encoding="utf-8")
    assert len(HEADING.findall(FENCE.sub("", text_tr))) == len(HEADING.findall(FENCE.sub("", text_en))), \
        f"{tr.relative_to(ROOT)}: not the English page's sections"
    assert [c for _, c, _ in blocks(tr)] == [c for _, c, _ in blocks(en)], \
        f"{tr.relative_to(ROOT)}: its code blocks differ from the English page's"
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text_en)
    assert re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text_tr) == images


def test_readme_is_a_front_page():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) < 250
    assert "make demo" in text and "make test" in text

