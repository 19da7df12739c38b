"""Every Qt and QGIS enum the plugin uses, in one place, under its scoped name.

QGIS 3.36 moved the Processing enums into ``Qgis`` (``Qgis.ProcessingSourceType.VectorPolygon``),
3.30 the geometry ones, and 3.38 declares fields with ``QMetaType`` types; Qt6 builds of QGIS
(4.x) have no unscoped aliases (``QgsProcessing.TypeVectorPolygon``) and no ``QVariant`` types.
Each name here is the scoped enum where the running QGIS has it, else the old enum of QGIS
3.22–3.34 with its members under the new names. The rest of the plugin uses only these names (a test checks it:
``tests/qgis/test_qt6_names.py``); the old names are strings, read only on an old QGIS.
"""
from types import SimpleNamespace

from qgis.core import (Qgis, QgsCoordinateReferenceSystem, QgsFeatureSink, QgsMapLayerProxyModel,
                       QgsPalLayerSettings,
                       QgsProcessing, QgsProcessingParameterDefinition, QgsProcessingParameterField,
                       QgsProcessingParameterFile, QgsProcessingParameterNumber,
                       QgsProcessingUtils, QgsTask, QgsWkbTypes)
from qgis.PyQt.QtCore import QMetaType, Qt, QVariant


def _scoped(name: str, old_owner, old_enum: str, **old_names):
    """``Qgis.<name>`` where this QGIS has it; else ``old_owner.<old_enum>``, its members named
    as in the new enum (``old_names``: new name = old name, for those that differ)."""
    new = getattr(Qgis, name, None)
    if new is not None:
        return new
    old = getattr(old_owner, old_enum)
    if not old_names:
        return old
    return SimpleNamespace(**{n: getattr(old, o) for n, o in old_names.items()})


# ---- QGIS: Processing (scoped in Qgis since 3.36)
ProcessingSourceType = _scoped("ProcessingSourceType", QgsProcessing, "SourceType",
                               Vector="TypeVector", VectorPoint="TypeVectorPoint",
                               VectorPolygon="TypeVectorPolygon")
ProcessingNumberParameterType = _scoped("ProcessingNumberParameterType",
                                        QgsProcessingParameterNumber, "Type")
ProcessingParameterFlag = _scoped("ProcessingParameterFlag", QgsProcessingParameterDefinition,
                                  "Flag", Advanced="FlagAdvanced")
ProcessingFileParameterBehavior = _scoped("ProcessingFileParameterBehavior",
                                          QgsProcessingParameterFile, "Behavior")
ProcessingFieldParameterDataType = _scoped("ProcessingFieldParameterDataType",
                                           QgsProcessingParameterField, "DataType")
LayerHint = QgsProcessingUtils.LayerHint          # scoped on every version
FeatureSinkFlag = QgsFeatureSink.Flag

# ---- QGIS: geometry (3.30), labels (3.26), CRS (3.36), messages, tasks
GeometryType = _scoped("GeometryType", QgsWkbTypes, "GeometryType", Polygon="PolygonGeometry",
                       Point="PointGeometry")
WkbType = _scoped("WkbType", QgsWkbTypes, "Type")
LabelPlacement = _scoped("LabelPlacement", QgsPalLayerSettings, "Placement")
CrsWktVariant = _scoped("CrsWktVariant", QgsCoordinateReferenceSystem, "WktVariant",
                        Preferred="WKT_PREFERRED")
MessageLevel = Qgis.MessageLevel
LayerFilter = _scoped("LayerFilter", QgsMapLayerProxyModel, "Filter")      # Qgis since 3.34
TaskFlag = QgsTask.Flag

# ---- field types: QMetaType since QGIS 3.38 (QgsField(name, QVariant.X) is deprecated there)
if Qgis.versionInt() >= 33800:
    FieldType = QMetaType.Type
else:
    FieldType = SimpleNamespace(**{n: getattr(QVariant, o) for n, o in dict(
        Bool="Bool", Int="Int", UInt="UInt", LongLong="LongLong", ULongLong="ULongLong",
        Double="Double", QString="String").items()})
INTEGER_TYPES = (FieldType.Int, FieldType.UInt, FieldType.LongLong, FieldType.ULongLong)

# ---- Qt
DateFormat = Qt.DateFormat
