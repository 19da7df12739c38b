"""QGIS side of EasyIDP: plugin class, Processing provider, algorithms and layer adapters.

Only translation between QGIS and the core happens here; the work is done in ``..core``.
"""
