"""Translations: the compiled catalogues load and translate the tool names."""
from pathlib import Path

import pytest

from qgis.PyQt.QtCore import QCoreApplication, QTranslator

I18N = Path(__file__).resolve().parents[2] / "i18n"


def test_catalogues_translate_tool_names(qgis_app):
    for lang, name in (("zh_CN", "按感兴趣区裁剪栅格"), ("ja", "ROI でラスタを切り出し")):
        tr = QTranslator()
        assert tr.load(str(I18N / f"easyidp_{lang}.qm"))
        QCoreApplication.installTranslator(tr)
        try:
            assert QCoreApplication.translate("EasyIDP", "Crop raster by ROIs") == name
        finally:
            QCoreApplication.removeTranslator(tr)


def test_every_user_facing_string_is_in_both_catalogues():
    """The extraction finds every string (tr() literals, DISPLAY/GROUP/HELP, translatable()), no
    tr() receives an f-string, and zh_CN and ja translate all of them, placeholders intact."""
    import re
    from easyidp_toolbox.scripts import update_translations as ut
    assert ut.untranslatable_calls() == []
    strings = ut.source_strings()
    assert len(strings) > 200
    for lang in ut.LANGS:
        known = ut.read_catalogue(lang)
        missing = [s[:60] for s in strings if s not in known]
        assert not missing, (lang, missing[:5])
        for s in strings:
            assert set(re.findall(r"\{[^{}]*\}", s)) == set(re.findall(r"\{[^{}]*\}", known[s])), \
                (lang, s[:60])


def test_a_tool_speaks_chinese_and_japanese(plugin):
    from qgis.core import QgsApplication
    alg = QgsApplication.processingRegistry().algorithmById("easyidp:backprojectrois")
    for lang in ("zh_CN", "ja"):
        tr = QTranslator()
        assert tr.load(str(I18N / f"easyidp_{lang}.qm"))
        QCoreApplication.installTranslator(tr)
        try:
            assert alg.displayName() != "Back-project ROIs"
            assert not alg.shortHelpString().startswith(alg.HELP[:40])
        finally:
            QCoreApplication.removeTranslator(tr)


def test_core_message_ids_are_the_plugins():
    """[independent] the plugin's table of the core's message ids holds the core's English texts
    word for word (no translator installed: tr() returns its source), so a changed message in the
    core cannot leave a stale translation; every id is raised somewhere in the core."""
    import re
    from easyidp_toolbox.core.errors import MESSAGES
    from easyidp_toolbox.easyidp_qgis import messages
    assert messages.texts() == MESSAGES
    core = Path(__file__).resolve().parents[2] / "core"
    source = "\n".join(p.read_text(encoding="utf-8") for p in core.rglob("*.py"))
    used = set(re.findall(r"\.of\(\s*\"(\w+)\"", source))
    assert used == set(MESSAGES), set(MESSAGES) ^ used


def test_a_core_error_reaches_the_user_in_chinese_and_japanese(provider, tmp_path):
    """[independent] a real run whose ROIs miss the raster stops with the core's message in the
    user's language, its fields (the count, the raster's path) filled in; without a translator,
    in English."""
    import numpy as np
    import processing
    from qgis.core import QgsProcessingContext, QgsProcessingException, QgsProcessingFeedback
    from easyidp_toolbox.tests.support.qgis_layers import memory_layer
    from easyidp_toolbox.tests.support.synthetic import write_tif
    src = write_tif(str(tmp_path / "dom.tif"), np.zeros((50, 50), np.uint8))
    far = "POLYGON((500000 4000000, 500010 4000000, 500010 3999990, 500000 4000000))"

    def run(lang):
        tr = QTranslator()
        if lang:
            assert tr.load(str(I18N / f"easyidp_{lang}.qm"))
            QCoreApplication.installTranslator(tr)
        try:
            with pytest.raises(QgsProcessingException) as err:
                processing.run("easyidp:croprasterbyrois", {
                    "INPUT": src, "ROIS": memory_layer("EPSG:32654", [("p", far)]),
                    "OUTPUT_FOLDER": str(tmp_path / f"out_{lang}")},
                    context=QgsProcessingContext(), feedback=QgsProcessingFeedback())
            return str(err.value)
        finally:
            QCoreApplication.removeTranslator(tr)
    assert "None of the 1 ROIs overlaps the raster" in run(None)
    zh, ja = run("zh_CN"), run("ja")
    assert "1 个 ROI 都不与栅格" in zh and "dom.tif" in zh
    assert "1 個の ROI のどれもラスタ" in ja and "dom.tif" in ja
