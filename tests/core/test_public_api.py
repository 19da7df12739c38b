"""The public API of ``easyidp_toolbox.core`` (the facade: every tool's entry point) reads as one
vocabulary with complete docstrings, and the renames of the glossary keep their old names for one
release.

* every public function of the facade has a numpydoc docstring whose Parameters section names
  every parameter and nothing else, and a Returns section (numpydoc's own validator, not ours);
* no parameter of the facade has a name the glossary bans (``docs/developer/glossary.md``, "One
  name per concept in the API"; a synonym banned only in one sense is allowed where the function
  uses it in the other, listed below with the reason);
* every renamed parameter and every renamed name of a package face still works under its old name
  for one release, and warns ``DeprecationWarning`` (``core/deprecation.py``).

Kind: [independent] for the docstrings (numpydoc's validation) and the banned names (the
glossary's table, parsed); [consistency only] for the shims (the same call under the old and the
new name must give the same outcome).
"""
import importlib
import inspect
import re
import warnings
from pathlib import Path

import pytest
from numpydoc.validate import get_doc_object, validate

import easyidp_toolbox.core as core
from easyidp_toolbox.core.deprecation import renamed_parameters

ROOT = Path(__file__).resolve().parents[2]
GLOSSARY = ROOT / "docs" / "developer" / "glossary.md"

# numpydoc's checks that make a docstring complete: it exists (GL08), has a summary (SS01), names
# every parameter (PR01), no unknown one (PR02), in the signature's order (PR03), each with a type
# (PR04) and a description (PR07), and says what it returns (RT01).
REQUIRED = {"GL08", "SS01", "PR01", "PR02", "PR03", "PR04", "PR07", "RT01"}

# Facade functions whose docstrings may still fail, with the reason (none today). Each listed
# must still fail, so this list only shrinks: when one passes, remove it here.
PENDING = {}

# A synonym the glossary bans in one sense only, used here in the other sense.
ALLOWED = {
    ("dsm_roi_heights", "buffer"): "map units of the DSM's CRS, the glossary's buffer",
    ("cloud_roi_heights", "buffer"): "map units of the cloud's CRS, the glossary's buffer",
    ("create_plot_grid", "buffer"): "metres around each plot, the glossary's buffer",
    ("create_plot_grid", "crs"): "the CRS the grid is made in (an object's CRS)",
    ("crop_photos", "margin"): "photo pixels, the glossary's margin",
}


def _functions():
    return sorted(name for name in core.__all__ if inspect.isfunction(getattr(core, name)))


def _renames():
    """(function name, old, new) of every renamed parameter of the facade."""
    return sorted((name, old, new) for name in _functions()
                  for old, new in getattr(getattr(core, name), "renamed_parameters", {}).items())


def _banned_synonyms():
    """{banned name: [its qualifier or None]} from the glossary's table."""
    text = GLOSSARY.read_text(encoding="utf-8")
    table = text.split("## One name per concept in the API", 1)[1].split("\n## ", 1)[0]
    banned = {}
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) != 3 or cells[0] in ("concept", "---"):
            continue
        for m in re.finditer(r"`([A-Za-z_]\w*)`(\s*\(([^)]*)\))?", cells[2]):
            banned.setdefault(m.group(1), []).append(m.group(3))
    return banned


def _docstring_errors(name):
    report = validate(f"easyidp_toolbox.core.{name}")
    return [f"{code} {text}" for code, text in report["errors"] if code in REQUIRED]


def test_the_facade_holds_every_tool_entry_point():
    """[independent] the functions every QGIS tool runs (their ``CoreStep``) are in the facade,
    with ``__version__``."""
    steps = set()
    for path in sorted((ROOT / "easyidp_qgis" / "algorithms").glob("*.py")):
        steps.update(re.findall(r"CoreStep\((\w+),", path.read_text(encoding="utf-8")))
    steps -= {"make_demo_survey", "vertex_heights"}   # the demo sits above core; a helper
    assert steps, "no CoreStep found: the tools' pattern changed"
    assert steps <= set(core.__all__), sorted(steps - set(core.__all__))
    assert "__version__" in core.__all__ and re.fullmatch(r"\d+\.\d+\.\d+", core.__version__)


@pytest.mark.parametrize("name", _functions())
def test_numpydoc_docstring(name):
    """[independent] numpydoc's validation of each facade function's docstring."""
    errors = _docstring_errors(name)
    if name in PENDING:
        assert errors, f"{name} passes now: remove it from PENDING ({PENDING[name]})"
    else:
        assert not errors, f"{name}: " + "; ".join(errors)


def test_pixel_convention_is_linked_not_restated():
    """[independent] the facade's docstrings link to the Conventions page; none restates the
    pixel convention (its 'top-left pixel is (0.5, 0.5)')."""
    for name in _functions():
        doc = inspect.getdoc(getattr(core, name)) or ""
        assert "(0.5, 0.5)" not in doc, f"{name} restates the pixel convention: link to it"
    assert "background/conventions.md" in core.__doc__


def test_no_banned_synonym_in_the_facade():
    """[independent] no facade parameter has a name the glossary bans."""
    banned = _banned_synonyms()
    assert {"out_folder", "dsm_crs", "max_images", "crs"} <= set(banned), "table not parsed"
    found = []
    for name in _functions():
        for param in inspect.signature(getattr(core, name)).parameters:
            if param in banned and (name, param) not in ALLOWED:
                found.append(f"{name}({param}): banned {banned[param]}")
            if param in banned and (name, param) in ALLOWED:
                assert any(banned[param]), f"{param} is banned outright; {name} cannot keep it"
    assert not found, "; ".join(found)


def test_checks_can_fail():
    """[independent] the validator flags a prose docstring, and the glossary bans its name."""
    def bad(out_folder, crs=None):
        """Do something with ``out_folder``."""
        return out_folder
    codes = {code for code, _ in validate(get_doc_object(bad))["errors"]}
    assert {"PR01", "RT01"} <= codes
    assert "out_folder" in _banned_synonyms()


# ---- the shims -----------------------------------------------------------------------------------

def _outcome(fn, kwargs):
    """The result, or the exception's type and message, of ``fn`` with None for every argument
    it requires and ``kwargs``; and the deprecation warnings it gave."""
    params = inspect.signature(fn).parameters.values()
    required = [p for p in params if p.default is p.empty
                and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    args = [None for p in required if p.kind != p.KEYWORD_ONLY]
    kw = {p.name: None for p in required if p.kind == p.KEYWORD_ONLY}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            out = ("returned", repr(fn(*args, **kw, **kwargs))[:200])
        except Exception as exc:       # the same failure under both names is what is compared
            out = (type(exc).__name__, str(exc))
    return out, [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]


@pytest.mark.parametrize("name, old, new", _renames())
def test_renamed_parameter_still_works_and_warns(name, old, new):
    """[consistency only] the old name gives what the new one gives, with a DeprecationWarning
    naming both; the documented signature has only the new name."""
    fn = getattr(core, name)
    params = inspect.signature(fn).parameters
    assert new in params and old not in params
    value = -1 if new == "max_views" else "EPSG:32654"   # a value the function checks early
    with_new, warned_new = _outcome(fn, {new: value})
    with_old, warned_old = _outcome(fn, {old: value})
    assert with_old == with_new
    assert not any(old in w for w in warned_new)
    assert any(repr(old) in w and repr(new) in w for w in warned_old), warned_old
    assert "unexpected keyword" not in with_old[1]


def test_old_and_new_name_together_is_an_error():
    with pytest.raises(TypeError, match="'max_images' and its new name 'max_views'"):
        core.back_project(None, None, heights=None, max_images=1, max_views=1)


def test_renamed_parameter_passes_the_value():
    """[independent] the shim hands the old name's value to the new parameter."""
    @renamed_parameters(old="new")
    def f(new=None):
        """f."""
        return new
    with pytest.warns(DeprecationWarning, match="'old' is deprecated, use 'new'"):
        assert f(old=7) == 7
    assert f(new=8) == 8


@pytest.mark.parametrize("package, old, new", [
    ("raster", "roi_heights", "dsm_roi_heights"),
    ("raster", "CropResult", "RasterCropResult"),
    ("pointcloud", "roi_heights", "cloud_roi_heights"),
    ("pointcloud", "CropResult", "CloudCropResult"),
])
def test_renamed_name_of_a_package_still_works_and_warns(package, old, new):
    """[consistency only] the old name of a package face is the new object, with a warning."""
    face = importlib.import_module(f"easyidp_toolbox.core.{package}")
    assert old not in face.__all__ and new in face.__all__
    with pytest.warns(DeprecationWarning, match=f"'{old}' is deprecated, use '{new}'"):
        assert getattr(face, old) is getattr(face, new)
    with pytest.raises(AttributeError):
        face.no_such_name  # noqa: B018 (the access is the test)


def test_glossary_lists_every_rename_as_done():
    """[independent] the glossary's table of renames done names every shim's old name, and its
    table of renames waiting is empty."""
    text = GLOSSARY.read_text(encoding="utf-8")
    done = text.split("## Renames done", 1)[1].split("\n## ", 1)[0]
    for name, old, new in _renames():
        assert f"`{old}`" in done and f"`{new}`" in done, f"{name}: {old} → {new} not in the glossary"
    waiting = text.split("## Renames waiting", 1)[1].split("\n## ", 1)[0]
    assert "|" not in waiting, "a rename still waits in the glossary"


def test_create_plot_grid_old_keywords_still_work_and_warn():
    """[consistency only] the 0.2 keywords of create_plot_grid give the grid the options objects
    give, with a DeprecationWarning; mixing an object with its old keywords is an error."""
    from easyidp_toolbox.core import FieldBookJoin, GridAnchor, GridLayout, Numbering
    book = [{"plot_no": n, "genotype": f"G{n}"} for n in range(1, 7)]
    new, report = core.create_plot_grid(
        "EPSG:32654", 2, 3, anchor=GridAnchor(origin=(500000, 4000000), bearing=80),
        layout=GridLayout(size_x=2, size_y=1, gap_x=0.5, gap_y=1, buffer=-0.1),
        numbering=Numbering(order="serpentine", start_id=11),
        field_book=FieldBookJoin(book, join_by="plot_no"))
    with pytest.warns(DeprecationWarning, match="create_plot_grid\\(\\): the keywords .*origin"):
        old, old_report = core.create_plot_grid(
            "EPSG:32654", 2, 3, origin=(500000, 4000000), bearing=80, size_x=2, size_y=1,
            gap_x=0.5, gap_y=1, buffer=-0.1, order="serpentine", start_id=11, field_book=book,
            join_by="plot_no")
    assert old.plot_id == new.plot_id and (old.corners == new.corners).all()
    assert old_report.messages() == report.messages()
    with pytest.raises(TypeError, match="layout= and its fields size_x"), \
            pytest.warns(DeprecationWarning):
        core.create_plot_grid("EPSG:32654", 2, 3, anchor=GridAnchor(origin=(500000, 4000000)),
                              layout=GridLayout(size_x=2), size_x=3)


def test_an_error_with_a_message_id_keeps_it():
    """[consistency only] an error made from a message id says the English text, keeps the id
    and its fields for the plugin to translate, and keeps them through pickling (the season's
    process pools send errors back so)."""
    import pickle
    from easyidp_toolbox.core.errors import MESSAGES, InputError
    err = InputError.of("roi_file_not_found", path="plots.shp")
    assert str(err) == MESSAGES["roi_file_not_found"].format(path="plots.shp")
    back = pickle.loads(pickle.dumps(err))
    assert (type(back), str(back), back.key, back.fields) == \
        (InputError, str(err), "roi_file_not_found", {"path": "plots.shp"})
    assert InputError("plain").key is None
