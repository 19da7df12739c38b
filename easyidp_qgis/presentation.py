"""How results land in the map: which outputs load, their names, styles and layer-tree groups.

Only the desktop loads layers (``qgis_process`` never does). Whether a layer is to be loaded is
the user's choice, and QGIS tells an algorithm only through a *layer* destination (feature sink,
vector or raster destination): its value is a ``QgsProcessingOutputLayerDefinition`` whose
``destinationProject`` is set when "Open output file after running algorithm" is ticked (toolbox),
"Load layers on completion" is ticked (batch), or a model output is set to open (modeler); QGIS
then queues it (``context.willLoadLayerOnCompletion``). Folder and file destinations carry no such
flag (their value is a plain path, in every dialog), so a tool that writes many files loads them
only when its index layer (``OUTPUT_INDEX``) is to be loaded: :func:`load_project`.

API (every tool uses it the same way; new tools too):

- :func:`load_project` (parameters, name): the project a layer destination is to be loaded into,
  or None.
- :func:`present` (alg, context, dest, output, style, name, group, rank, in_map): when ``dest``
  will be loaded, give it a descriptive name (unless a model named it), a style and a place; a
  layer in photo pixels (``in_map=False``) goes into the project for the photo viewer, never into
  the map (:func:`load_off_map`, :func:`photo_pixel_layers`).
- :func:`load_files` (alg, context, feedback, project, files, names, hint, group): queue many
  files (rasters, point clouds) with their layer type, into one collapsed :class:`MapGroup`;
  nothing above :data:`MAX_LAYERS_TO_LOAD`. Tools that write many files ask first:
  :func:`add_open_files_parameter` (OPEN_FILES, default off) and :func:`files_project`.
- :class:`MapGroup` (name, anchor_layer_id, expanded): one layer-tree group per run, placed
  below the anchor (the ROI layer) or at the top.
- Styles, callables ``style(layer)``: :func:`outline_style`, :func:`points_style`,
  :func:`graduated_style`, :func:`rank_style`.

Styling and tree changes happen in ``postProcessLayer``, which QGIS runs in the main thread after
adding the layer to the project; ``processAlgorithm`` (a worker thread) only records what to do.
"""
import collections
import os

from qgis.core import (QgsCategorizedSymbolRenderer, QgsClassificationQuantile,
                       QgsCoordinateReferenceSystem, QgsFillSymbol,
                       QgsGraduatedSymbolRenderer, QgsLayerTreeLayer, QgsMarkerSymbol,
                       QgsPalLayerSettings, QgsProcessingContext,
                       QgsProcessingLayerPostProcessorInterface, QgsProcessingParameterBoolean,
                       QgsProcessingOutputLayerDefinition, QgsProject, QgsRendererCategory,
                       QgsRuleBasedRenderer, QgsSingleSymbolRenderer, QgsStyle,
                       QgsTextBufferSettings, QgsTextFormat, QgsVectorLayer,
                       QgsVectorLayerSimpleLabeling, QgsWkbTypes)
from qgis.PyQt.QtCore import QCoreApplication, QThread
from qgis.PyQt.QtGui import QColor

from .compat import INTEGER_TYPES, GeometryType, LabelPlacement, LayerHint

MAX_LAYERS_TO_LOAD = 100
"""Above this many files a run loads none of them (the log says where they are)."""


OPEN_FILES = "OPEN_FILES"
"""The parameter of the tools that write many files (crops, images): open them too."""


def tr(text: str) -> str:
    """A legend label or help text translated (the tools' context, ``EasyIDP``)."""
    return QCoreApplication.translate("EasyIDP", text)

RASTER = LayerHint.Raster
POINT_CLOUD = LayerHint.PointCloud
VECTOR = LayerHint.Vector

# QGIS deletes a post-processor with its context, but the Python side of one must stay
# referenced until then, or its postProcessLayer is lost (the QGIS cookbook keeps a class
# attribute). Bounded: one run queues at most MAX_LAYERS_TO_LOAD files plus a few layers.
_ALIVE = collections.deque(maxlen=4096)


# ---- whether and how to load ----------------------------------------------------------------

def load_project(parameters, name: str):
    """The project the layer destination ``name`` is to be loaded into, or None (not asked, a
    plain path, or headless)."""
    value = parameters.get(name)
    if isinstance(value, QgsProcessingOutputLayerDefinition):
        return value.destinationProject
    return None


class MapGroup:
    """One layer-tree group for the layers of one run: created on the first layer, placed just
    below ``anchor_layer_id`` (the ROI layer) when it is in the tree, else at the top; its
    layers kept in their rank order; collapsed unless ``expanded``."""

    def __init__(self, name: str, anchor_layer_id: str = None, expanded: bool = False):
        self.name = name
        self.anchor_layer_id = anchor_layer_id or None
        self.expanded = expanded
        self.node = None
        self.ranks = {}

    def _create(self, root):
        anchor = root.findLayer(self.anchor_layer_id) if self.anchor_layer_id else None
        parent = anchor.parent() if anchor is not None else root
        index = 0
        if anchor is not None:
            index = 1 + next(i for i, ch in enumerate(parent.children())
                             if isinstance(ch, QgsLayerTreeLayer)
                             and ch.layerId() == self.anchor_layer_id)
        self.node = parent.insertGroup(index, self.name)
        self.node.setExpanded(self.expanded)
        return self.node

    def add(self, layer, rank: float, project=None, visible: bool = True) -> None:
        """Move ``layer`` (already in the project's tree) into the group, at its rank."""
        root = (project or QgsProject.instance()).layerTreeRoot()
        node = root.findLayer(layer.id())
        if node is None:
            return
        group = self.node if self.node is not None else self._create(root)
        self.ranks[layer.id()] = rank
        position = sum(1 for ch in group.children() if isinstance(ch, QgsLayerTreeLayer)
                       and self.ranks.get(ch.layerId(), rank) < rank)
        clone = node.clone()
        clone.setExpanded(False)                 # a raster's bands or a legend stay folded
        clone.setItemVisibilityChecked(visible)
        group.insertChildNode(position, clone)
        node.parent().removeChildNode(node)


PHOTO_PIXELS = "easyidp/photo_pixels"
"""Custom property of a layer in photo pixels (x = column, y = −row) that a tool loaded: it is
in the project, for the photo viewer, but not in the layer tree (not drawn in the map)."""


def photo_pixel_layers(project=None) -> list:
    """The layers in photo pixels the tools loaded into ``project`` (see :data:`PHOTO_PIXELS`)."""
    project = project or QgsProject.instance()
    return [v for v in project.mapLayers().values() if v.customProperty(PHOTO_PIXELS)]


class _Presenter(QgsProcessingLayerPostProcessorInterface):
    """Applies a style and a place to a layer QGIS has just added to the project."""

    def __init__(self, style=None, group: MapGroup = None, rank: float = 0, project=None,
                 visible: bool = True):
        super().__init__()
        self.style, self.group, self.rank = style, group, rank
        self.project, self.visible = project, visible

    def postProcessLayer(self, layer, context, feedback):  # noqa: N802 (QGIS API)
        if self.style is not None:
            self.style(layer)
        if self.group is not None:
            self.group.add(layer, self.rank, self.project or context.project(), self.visible)
        layer.triggerRepaint()


def _presenter(**kw) -> _Presenter:
    p = _Presenter(**kw)
    _ALIVE.append(p)
    return p


def add_open_files_parameter(alg, description: str) -> None:
    """OPEN_FILES (default off): open the files a run writes too, not only its index. A run of
    2,000 plots must not bury the map, so the files load only when asked, in one collapsed
    group, and none above :data:`MAX_LAYERS_TO_LOAD`."""
    # optional, so that models saved before this parameter existed stay valid
    p = QgsProcessingParameterBoolean(OPEN_FILES, description, False, optional=True)
    p.setHelp(tr("Off: only the index opens (when it is set to open). On: the files too, in one "
                 "collapsed group below the ROI layer; none when there are more than {n} (the "
                 "log says where they are).").format(n=MAX_LAYERS_TO_LOAD))
    alg.addParameter(p)


def files_project(alg, parameters, context, index_output: str = "OUTPUT_INDEX"):
    """The project to open a run's files in: with OPEN_FILES on, the index's project when the
    index is to be opened, else the run's project; None when OPEN_FILES is off."""
    if not alg.parameterAsBool(parameters, OPEN_FILES, context):
        return None
    return load_project(parameters, index_output) or context.project()


def present(alg, context, dest, output: str, style=None, name: str = None,
            group: MapGroup = None, rank: float = 0, in_map: bool = True) -> bool:
    """When the output ``dest`` (the id ``parameterAsSink`` returned for the parameter
    ``output``) will be loaded: name it ``name`` unless a model gave it a name, and style and
    place it after loading; ``in_map`` False (a layer in photo pixels): into the project for the
    photo viewer, not into the layer tree. Returns whether it will be loaded."""
    if not dest or not context.willLoadLayerOnCompletion(dest):
        return False
    details = context.layerToLoadOnCompletionDetails(dest)
    definition = alg.parameterDefinition(output)
    named_by_model = definition is not None and details.name not in ("", definition.description())
    if name and not named_by_model:
        details.name = name
    if not in_map:
        _hold_off_map(alg, context, dest, details, style)
        return True
    details.setPostProcessor(_presenter(style=style, group=group, rank=rank,
                                        project=details.project))
    return True


def _hold_off_map(alg, context, dest, details, style) -> None:
    """Take ``dest`` off QGIS's list of layers to load (QGIS would add it to the layer tree, and
    one in photo pixels makes the map report "No transform available"); :func:`load_off_map`
    adds it to the project, off the map, when the run has ended."""
    pending = getattr(alg, "_easyidp_off_map", [])
    pending.append((dest, details.name, style, details.project))   # before ``details`` goes
    alg._easyidp_off_map = pending
    layers = context.layersToLoadOnCompletion()
    layers.pop(dest, None)
    context.setLayersToLoadOnCompletion(layers)


def load_off_map(alg, context, feedback) -> list:
    """The layers :func:`present` held off the map (``in_map=False``), added to their project
    without a place in the layer tree, without a CRS, marked :data:`PHOTO_PIXELS`: the photo
    viewer shows them. Run in the main thread when the run has ended (``postProcessAlgorithm``);
    in a model's worker thread nothing is loaded (the log says where the file is). Returns the
    layers added."""
    pending = getattr(alg, "_easyidp_off_map", [])
    alg._easyidp_off_map = []
    app = QCoreApplication.instance()
    if not pending or app is None or QThread.currentThread() != app.thread():
        for dest, _, _, _ in pending:
            feedback.pushInfo(alg.tr("In photo pixels, not loaded into the map: {path}").format(
                path=dest))
        return []
    added = []
    for dest, name, style, project in pending:
        store = context.temporaryLayerStore()
        layer = store.mapLayer(dest)
        if layer is not None:
            store.takeMapLayer(layer)
        else:
            layer = QgsVectorLayer(dest, name, "ogr")
        if not layer.isValid():
            continue
        layer.setName(name)
        layer.setCrs(QgsCoordinateReferenceSystem())    # pixels: no place on any map
        layer.setCustomProperty(PHOTO_PIXELS, True)
        if style is not None:
            style(layer)
        (project or context.project() or QgsProject.instance()).addMapLayer(layer, False)
        added.append(layer)
    return added


def load_files(alg, context, feedback, project, files, names, hint, group: MapGroup,
               output: str = "", style=None, limit: int = None,
               first_rank: int = 0) -> int:
    """Queue ``files`` (named ``names``, e.g. :func:`stems`) for loading into ``project`` as
    layers of type ``hint`` (so QGIS opens a .tif as a raster at once, not first as a vector),
    into ``group`` in this order (ranks from ``first_rank``). Nothing when ``project`` is None, or above ``limit``
    files (said in the log). Returns how many were queued."""
    if project is None or not files:
        return 0
    limit = MAX_LAYERS_TO_LOAD if limit is None else limit
    if len(files) > limit:
        feedback.pushInfo(alg.tr("{n} files are more than the {limit} loaded into the map: open "
                                 "them from the output folder.").format(n=len(files), limit=limit))
        return 0
    for k, (path, name) in enumerate(zip(files, names)):
        details = QgsProcessingContext.LayerDetails(str(name), project, output)
        details.layerTypeHint = hint
        details.forceName = True                 # the ROI's name, not the file's
        details.setPostProcessor(_presenter(style=style, group=group, rank=first_rank + k,
                                            project=project))
        context.addLayerToLoadOnCompletion(os.path.abspath(str(path)), details)
    return len(files)


def stems(files):
    """Layer names for files: their names without the suffix (unique, as the tools write
    them, and what the user finds in the folder)."""
    return [os.path.splitext(os.path.basename(str(f)))[0] for f in files]


def anchor_id(alg, parameters, name: str, context) -> str:
    """The id of the layer given as the parameter ``name`` when it is a layer of the project
    (the group of a run goes below it), else ''."""
    try:
        layer = alg.parameterAsVectorLayer(parameters, name, context)
    except Exception:          # a parameter that is not a layer (a file, a table): no anchor
        return ""
    project = context.project()
    if layer is None or project is None:
        return ""
    if project.mapLayer(layer.id()) is not None:
        return layer.id()
    # given by its source (batch mode passes layers so): the project's layer of that source
    same = [v for v in project.mapLayers().values() if v.source() == layer.source()]
    return same[0].id() if same else ""


# ---- styles: callables that set a renderer (and labels) on a vector layer --------------------

def _label(layer, expression: str, size: float = 8.0, max_scale_denominator: float = 0.0,
           colour: str = "#111111", halo: str = "#ffffff", priority: int = 5) -> None:
    """Labels from ``expression`` with a halo (readable over an orthomosaic); with
    ``max_scale_denominator`` only when zoomed in beyond 1:that; ``priority`` 0–10 decides
    which label wins where labels of several layers collide (QGIS's default is 5)."""
    settings = QgsPalLayerSettings()
    settings.fieldName = expression
    settings.isExpression = True
    settings.priority = priority
    fmt = QgsTextFormat()
    fmt.setSize(size)
    fmt.setColor(QColor(colour))
    buffer = QgsTextBufferSettings()
    buffer.setEnabled(True)
    buffer.setSize(0.8)
    buffer.setColor(QColor(halo))
    fmt.setBuffer(buffer)
    settings.setFormat(fmt)
    if QgsWkbTypes.geometryType(layer.wkbType()) == GeometryType.Polygon:
        settings.placement = LabelPlacement.OverPoint
    if max_scale_denominator:
        settings.scaleVisibility = True
        settings.minimumScale = max_scale_denominator   # the most zoomed-out scale shown
        settings.maximumScale = 0.0
    layer.setLabeling(QgsVectorLayerSimpleLabeling(settings))
    layer.setLabelsEnabled(True)


def _outline_symbol(colour: str, width: float, dashed: bool = False, fill_alpha: int = 0):
    fill = QColor(colour)
    fill.setAlpha(fill_alpha)
    return QgsFillSymbol.createSimple({
        "color": f"{fill.red()},{fill.green()},{fill.blue()},{fill_alpha}",
        "style": "solid" if fill_alpha else "no",
        "outline_color": colour, "outline_width": str(width), "outline_width_unit": "MM",
        "outline_style": "dash" if dashed else "solid", "joinstyle": "round"})


def outline_style(colour: str, width: float = 0.4, dashed_when: str = None, label: str = None,
                  label_scale: float = 0.0, fill_alpha: int = 0, tip: str = None,
                  dashed_colour: str = None, label_priority: int = 5, legend=None):
    """Polygons as outlines of one colour (no fill, or a faint one with ``fill_alpha``),
    dashed (in ``dashed_colour``) where the expression ``dashed_when`` holds; optional labels
    (only when zoomed in beyond 1:``label_scale``) and map tip. With ``dashed_when``,
    ``legend`` is required: the (dashed, solid) legend entries' text, so that no entry of the
    layers panel is blank."""
    if dashed_when and not (legend and all(legend)):
        raise ValueError("outline_style: dashed_when needs legend=(dashed text, solid text)")

    def apply(layer):
        if not isinstance(layer, QgsVectorLayer):
            return
        if dashed_when:
            root = QgsRuleBasedRenderer.Rule(None)
            for expression, dashed, text in ((f"coalesce({dashed_when}, false)", True, legend[0]),
                                             (f"NOT coalesce({dashed_when}, false)", False,
                                              legend[1])):
                rule = QgsRuleBasedRenderer.Rule(
                    _outline_symbol(dashed_colour or colour if dashed else colour, width, dashed,
                                    fill_alpha), 0, 0, expression, text)
                root.appendChild(rule)
            layer.setRenderer(QgsRuleBasedRenderer(root))
        else:
            layer.setRenderer(QgsSingleSymbolRenderer(_outline_symbol(colour, width, False,
                                                                      fill_alpha)))
        if label:
            _label(layer, label, max_scale_denominator=label_scale, priority=label_priority)
        if tip:
            layer.setMapTipTemplate(tip)
    return apply


def points_style(colour: str, size: float = 1.8, label: str = None, label_scale: float = 0.0,
                 tip: str = None):
    """Small round markers with a white rim; labels only when zoomed in (``label_scale``),
    and a map tip (shown on hover when map tips are on)."""
    def apply(layer):
        if not isinstance(layer, QgsVectorLayer):
            return
        layer.setRenderer(QgsSingleSymbolRenderer(QgsMarkerSymbol.createSimple({
            "name": "circle", "color": colour, "size": str(size), "size_unit": "MM",
            "outline_color": "255,255,255,255", "outline_width": "0.3"})))
        if label:
            _label(layer, label, size=7.0, max_scale_denominator=label_scale)
        if tip:
            layer.setMapTipTemplate(tip)
    return apply


def graduated_style(field: str, decimals: int = 2, classes: int = 5, ramp: str = "Viridis",
                    fill_alpha: int = 150, label: bool = True, unit: str = ""):
    """Polygons coloured by ``field``, the fill translucent so that the orthomosaic shows
    through, the outline in the class colour, and the value as label (above other layers'
    labels). Quantile classes from a colour-blind-safe ramp; a field with no more distinct
    values than ``classes`` (or an integer field with at most 12: counts) gets one colour per
    value. NULL: no colour. ``unit`` follows every value in the legend (e.g. "3 photos") and,
    with ``label``, on the map."""
    def apply(layer):
        index = layer.fields().indexFromName(field) if isinstance(layer, QgsVectorLayer) else -1
        if index < 0:
            return
        colours = QgsStyle.defaultStyle().colorRamp(ramp)
        integers = layer.fields().at(index).type() in INTEGER_TYPES
        few = 12 if integers else classes       # counts: a colour per count up to 12
        values = sorted(v for v in layer.uniqueValues(index, few + 1)
                        if v is not None and str(v) != "NULL")
        if not values:
            return
        if len(values) <= few:
            renderer = QgsCategorizedSymbolRenderer(field, [
                QgsRendererCategory(v, _translucent(colours.color(k / max(len(values) - 1, 1))
                                                    if colours else QColor("#3182bd"), fill_alpha),
                                    (f"{v:.{decimals}f}" if isinstance(v, float) else str(v))
                                    + (f" {unit}" if unit else ""))
                for k, v in enumerate(values)])
        else:
            renderer = QgsGraduatedSymbolRenderer(field)
            renderer.setSourceSymbol(_outline_symbol("#000000", 0.5, False, fill_alpha))
            if colours is not None:
                renderer.setSourceColorRamp(colours)
            method = QgsClassificationQuantile()
            method.setLabelPrecision(decimals)
            method.setLabelTrimTrailingZeroes(False)
            if unit:
                method.setLabelFormat(f"%1 – %2 {unit}")
            renderer.setClassificationMethod(method)
            renderer.updateClasses(layer, classes)
            for i, r in enumerate(renderer.ranges()):
                renderer.updateRangeSymbol(i, _translucent(r.symbol().color(), fill_alpha))
        layer.setRenderer(renderer)
        if label:
            suffix = f" || ' {unit}'" if unit else ""
            value = f"format_number(\"{field}\", {decimals}){suffix}"
            _label(layer, f"if(\"{field}\" IS NULL, '', {value})", priority=8)
    return apply


def _translucent(colour: QColor, fill_alpha: int):
    """A polygon symbol: ``colour`` as outline, and as fill with ``fill_alpha``."""
    return _outline_symbol(colour.name(), 0.5, False, fill_alpha)


def rank_style(colour_best: str, colour_other: str, field: str = "rank", label: str = None):
    """Photo-pixel polygons: the best-ranked view (``field`` = 1) bold, the others thin; the
    legend says which is which."""
    def apply(layer):
        if not isinstance(layer, QgsVectorLayer):
            return
        root = QgsRuleBasedRenderer.Rule(None)
        root.appendChild(QgsRuleBasedRenderer.Rule(_outline_symbol(colour_other, 0.3), 0, 0,
                                                   f"\"{field}\" <> 1 OR \"{field}\" IS NULL",
                                                   tr("Other photos of the ROI")))
        root.appendChild(QgsRuleBasedRenderer.Rule(_outline_symbol(colour_best, 0.7), 0, 0,
                                                   f"\"{field}\" = 1",
                                                   tr("The ROI's best photo (rank 1)")))
        layer.setRenderer(QgsRuleBasedRenderer(root))
        if label:
            _label(layer, label)
    return apply


def index_style(file_field: str = "crop_file"):
    """The index of a tool's files: thin dark outlines; ROIs without a file dashed red."""
    return outline_style("#202020", 0.2, dashed_when=f"\"{file_field}\" IS NULL",
                         dashed_colour="#e31a1c",
                         legend=(tr("No file (skipped: see its status)"), tr("File written")))


def first_field(layer_fields, candidates):
    """The first of ``candidates`` that is a field name of ``layer_fields`` (QgsFields or
    names), else None."""
    names = set(layer_fields.names() if hasattr(layer_fields, "names") else layer_fields)
    return next((c for c in candidates if c in names), None)
