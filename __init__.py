"""QGIS entry point of the EasyIDP Toolbox plugin (installed as the folder ``easyidp_toolbox``).

Nothing is imported at module level, so ``import easyidp_toolbox.core`` works without QGIS.
"""


def classFactory(iface):  # noqa: N802 (QGIS API name)
    from .easyidp_qgis.plugin import EasyIDPPlugin
    return EasyIDPPlugin(iface)
