"""Paths of the plugin's files (icons, translations)."""
import os

PLUGIN_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ICON = os.path.join(PLUGIN_DIR, "icons", "easyidp.svg")
I18N_DIR = os.path.join(PLUGIN_DIR, "i18n")
