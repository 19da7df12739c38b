"""The test suites of EasyIDP for QGIS (not shipped in the plugin)."""
