"""Translations: the compiled catalogues load and translate the tool names."""
from pathlib import Path

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
