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
