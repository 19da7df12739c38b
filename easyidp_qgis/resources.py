"""Paths of the plugin's files (icons, translations)."""
import os

PLUGIN_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ICON = os.path.join(PLUGIN_DIR, "icons", "easyidp.svg")
I18N_DIR = os.path.join(PLUGIN_DIR, "i18n")
METADATA = os.path.join(PLUGIN_DIR, "metadata.txt")


def help_url(anchor: str) -> str:
    """The README section ``#anchor`` on the plugin's homepage (``metadata.txt``), where each
    tool's help is (the README names its anchors ``easyidp-<tool name>``); '' without a
    homepage."""
    import configparser
    parser = configparser.ConfigParser(interpolation=None)
    try:
        parser.read(METADATA, encoding="utf-8")
        home = parser.get("general", "homepage", fallback="").strip()
    except configparser.Error:
        home = ""
    return f"{home.rstrip('/')}#{anchor}" if home else ""
