"""A user's session in the real QGIS desktop, run inside it by ``desktop_driver.py`` (spec key
``session``): the demo survey, the tools through their own dialogs, batch mode and a model,
as a user would; what the map shows is recorded (layers, groups, renderers, the message log)
and, when asked, screenshots are saved. ``qgis_desktop.run_session`` starts it;
``make screenshots`` and ``tests/qgis/test_desktop.py`` use it.

Spec: ``work`` (a folder for the survey and outputs), ``model`` (the example model file),
``shots`` (folder for PNGs, optional).
"""
import inspect
import os
import shutil
from collections import Counter
import time
import traceback

from qgis.core import (QgsApplication, QgsLayerTreeGroup, QgsMapLayerType,
                       QgsProcessingModelAlgorithm, QgsProject, QgsRenderContext, QgsVectorLayer,
                       QgsWkbTypes)
from qgis.PyQt.QtCore import QPoint, Qt
from qgis.PyQt.QtWidgets import QAction, QCheckBox, QDockWidget, QMenu, QTextEdit, QToolBar
from qgis.utils import iface

WIDTH, HEIGHT = 1280, 800
EXTRA_WAIT = 0.3


def _pump(seconds: float) -> None:
    end = time.time() + seconds
    while time.time() < end:
        QgsApplication.processEvents()
        time.sleep(0.02)


def _wait(condition, timeout: float) -> bool:
    end = time.time() + timeout
    while time.time() < end:
        QgsApplication.processEvents()
        if condition():
            return True
        time.sleep(0.05)
    return False


# ---- what the user sees ---------------------------------------------------------------------

def _fill_alpha(layer) -> int:
    """The most opaque fill of a polygon layer's symbols (0: outlines only)."""
    if QgsWkbTypes.geometryType(layer.wkbType()) != QgsWkbTypes.PolygonGeometry:
        return -1
    alphas = []
    for symbol in layer.renderer().symbols(QgsRenderContext()):
        for k in range(symbol.symbolLayerCount()):
            sl = symbol.symbolLayer(k)
            if hasattr(sl, "fillColor"):
                no_brush = hasattr(sl, "brushStyle") and int(sl.brushStyle()) == 0
                alphas.append(0 if no_brush else sl.fillColor().alpha() * symbol.opacity())
    return int(max(alphas)) if alphas else 0


def _layer_entry(node) -> dict:
    layer = node.layer()
    kinds = {QgsMapLayerType.VectorLayer: "vector", QgsMapLayerType.RasterLayer: "raster"}
    entry = {"name": node.name(), "type": kinds.get(layer.type(), str(layer.type())),
             "provider": layer.providerType(), "visible": node.itemVisibilityChecked(),
             "expanded": node.isExpanded(), "crs": layer.crs().authid(), "valid": layer.isValid()}
    if isinstance(layer, QgsVectorLayer):
        entry.update(renderer=layer.renderer().type(), fill_alpha=_fill_alpha(layer),
                     labels=layer.labelsEnabled(), features=layer.featureCount(),
                     geometry=QgsWkbTypes.geometryDisplayString(layer.geometryType()))
        if entry["renderer"] == "graduatedSymbol":
            entry["class_attribute"] = layer.renderer().classAttribute()
    return entry


def tree(node=None) -> list:
    """The layer tree as the Layers panel shows it: groups with their children, layers."""
    node = node or QgsProject.instance().layerTreeRoot()
    out = []
    for ch in node.children():
        if isinstance(ch, QgsLayerTreeGroup):
            out.append({"group": ch.name(), "expanded": ch.isExpanded(),
                        "visible": ch.itemVisibilityChecked(), "children": tree(ch)})
        else:
            out.append(_layer_entry(ch))
    return out


class Session:
    """``modal``: the list the driver keeps the dialogs it closed in; ``doing(what)``: tells the
    driver what the session is doing (named when its time limit is reached)."""

    def __init__(self, spec: dict, modal: list, doing):
        self.work = spec["work"]
        self.shots = spec.get("shots")
        self.model_file = spec.get("model")
        self.found = {"steps": {}, "log": [], "modal": modal, "shots": []}
        self.doing = doing
        self.survey = os.path.join(self.work, "survey")
        QgsApplication.messageLog().messageReceived.connect(self._log)

    # -- what goes wrong without asking: the message log (the driver closes modal dialogs) --
    def _log(self, message, tag, level):
        self.found["log"].append([tag, int(level), message])

    # -- the desktop --
    def setup(self):
        from processing.core.ProcessingConfig import ProcessingConfig
        ProcessingConfig.setSettingValue(ProcessingConfig.KEEP_DIALOG_OPEN, True)
        window = iface.mainWindow()
        window.showNormal()
        window.setGeometry(0, 0, WIDTH, HEIGHT)
        for dock in window.findChildren(QDockWidget):
            if dock.objectName() in ("Browser", "Browser2", "LayerOrder", "Overview"):
                dock.hide()
        self.toolbox = window.findChild(QDockWidget, "ProcessingToolbox")
        layers = window.findChild(QDockWidget, "Layers")
        if layers is not None:
            window.resizeDocks([layers], [340], Qt.Horizontal)
        _pump(1.0)

    def shot(self, name: str, widget=None) -> None:
        """A PNG of the window (or ``widget``) as the user sees it: the message bar as it is."""
        if not self.shots:
            return
        os.makedirs(self.shots, exist_ok=True)
        path = os.path.join(self.shots, name)
        _pump(EXTRA_WAIT)
        (widget or iface.mainWindow()).grab().save(path)
        self.found["shots"].append(path)

    def zoom_to(self, layer_name: str, scale: float = 1.1) -> None:
        layers = QgsProject.instance().mapLayersByName(layer_name)
        canvas = iface.mapCanvas()
        if layers:
            extent = canvas.mapSettings().layerExtentToOutputExtent(layers[0], layers[0].extent())
            extent.scale(scale)
            canvas.setExtent(extent)
        canvas.refreshAllLayers()
        _wait(lambda: not canvas.isDrawing(), 30)
        _pump(0.5)
        _wait(lambda: not canvas.isDrawing(), 30)

    def set_visible(self, names, visible: bool) -> None:
        root = QgsProject.instance().layerTreeRoot()
        for layer in QgsProject.instance().mapLayers().values():
            if layer.name() in names:
                root.findLayer(layer.id()).setItemVisibilityChecked(visible)

    # -- running tools as a user does --
    def run_dialog(self, step: str, alg_id: str, params: dict, open_outputs=None, shot=None):
        """The tool's dialog, filled in, Run clicked; ``open_outputs``: {output: ticked} for
        "Open output file after running algorithm"."""
        from processing.gui.AlgorithmDialog import AlgorithmDialog
        self.doing(f"running {alg_id} from its dialog (step {step})")
        alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
        dlg = AlgorithmDialog(alg, parent=iface.mainWindow())
        dlg.setParameters(params)
        _pump(0.2)
        dlg.setParameters(params)        # fields, once their layer is chosen (as a user does)
        for name, ticked in (open_outputs or {}).items():
            for box in dlg.mainWidget().wrappers[name].wrappedWidget().findChildren(QCheckBox):
                box.setChecked(ticked)
        dlg.show()
        _pump(0.5)
        if shot:
            dlg.resize(900, 640)          # the user's size for reading the help beside it
            _pump(0.5)
            self.shot(shot, dlg)
        done = {}
        dlg.algorithmFinished.connect(lambda ok, results: done.update(ok=ok, results=results))
        before = set(QgsProject.instance().mapLayers())
        started = time.time()
        dlg.runAlgorithm()
        _wait(lambda: bool(done), 600)
        _pump(0.5)
        text = dlg.findChild(QTextEdit, "txtLog")
        log = text.toPlainText() if text is not None else ""
        added = [QgsProject.instance().mapLayer(i).name()
                 for i in set(QgsProject.instance().mapLayers()) - before]
        found = {"ok": done.get("ok", False), "seconds": round(time.time() - started, 1),
                 "results": {k: str(v) for k, v in (done.get("results") or {}).items()},
                 "added": sorted(added), "log": log.splitlines(),
                 "help_url": alg.helpUrl()}
        self.found["steps"][step] = found
        dlg.close()
        dlg.deleteLater()
        _pump(0.2)
        return found

    def run_batch(self, step: str, alg_id: str, rows, load: bool):
        """Batch mode with ``rows`` ({parameter: value}) and "Load layers on completion"."""
        from processing.gui.BatchAlgorithmDialog import BatchAlgorithmDialog
        from processing.tools import dataobjects
        self.doing(f"running {alg_id} in batch mode (step {step})")
        alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
        dlg = BatchAlgorithmDialog(alg, parent=iface.mainWindow())
        panel = dlg.mainWidget()
        context = dataobjects.createContext()
        while panel.batchRowCount() < len(rows):
            panel.addRow()
        for row, params in enumerate(rows):
            for name, value in params.items():
                column = panel.parameter_to_column[name]
                if alg.parameterDefinition(name).isDestination():
                    panel.tblParameters.cellWidget(row + 1, column).setValue(str(value))
                else:
                    panel.wrappers[row][column].setParameterValue(value, context)
        panel.checkLoadLayersOnCompletion.setChecked(load)
        # QGIS 3.40 takes the context second (3.22 has destinationProject there)
        extra = {"context": context} if "context" in inspect.signature(
            panel.parametersForRow).parameters else {}
        self.found.setdefault("batch_values", []).append(
            {k: repr(v) for k, v in panel.parametersForRow(0, warnOnInvalid=False,
                                                           **extra)[0].items()})
        dlg.show()
        _pump(0.3)
        before = set(QgsProject.instance().mapLayers())
        groups_before = Counter(_group_names())
        dlg.runAlgorithm()
        # QGIS 3.40 runs a batch in a background task (3.22 in runAlgorithm itself): closing the
        # dialog before it ends crashes QGIS
        _wait(lambda: QgsApplication.taskManager().countActiveTasks() == 0, 600)
        _pump(0.5)
        added = [QgsProject.instance().mapLayer(i).name()
                 for i in set(QgsProject.instance().mapLayers()) - before]
        self.found["steps"][step] = {"added": sorted(added), "load": load,
                                     "groups": sorted((Counter(_group_names())
                                                       - groups_before).elements()),
                                     "written": [sorted(os.listdir(p[k])) for p in rows
                                                 for k in p if k == "OUTPUT_FOLDER"
                                                 and os.path.isdir(p[k])]}
        dlg.close()
        dlg.deleteLater()
        _pump(0.2)

    # -- the session --
    def run(self):
        self.setup()
        self.found["plugin_loaded"] = QgsApplication.processingRegistry().providerById("easyidp") is not None
        s = self.run_dialog("demo", "easyidp:createdemosurvey", {"OUTPUT_FOLDER": self.survey})
        r = s["results"]
        self.zoom_to("Demo plots", 1.15)
        self.found["tree_demo"] = tree()
        self.toolbox_open()
        self.found["toolbox_fit"] = self.toolbox_fit()
        self.shot("desktop_toolbox.png")
        if self.toolbox is not None:
            self.toolbox.hide()

        plots = QgsProject.instance().mapLayersByName("Demo plots")[0]
        ortho = QgsProject.instance().mapLayersByName("Demo orthomosaic")[0]
        dsm = QgsProject.instance().mapLayersByName("Demo DSM")[0]
        self.run_dialog("crop", "easyidp:croprasterbyrois", {
            "INPUT": ortho.id(), "ROIS": plots.id(), "NAME_FIELD": "plot_id",
            "OUTPUT_FOLDER": os.path.join(self.work, "crops"), "OPEN_FILES": True},
            shot="desktop_crop_dialog.png")
        self.run_dialog("heights", "easyidp:roiheightsfromdsm", {
            "ROIS": plots.id(), "DSM": dsm.id(), "MODE": 0, "STATISTIC": 4, "PERCENTILE": 95})
        self.run_dialog("footprints", "easyidp:camerafootprints", {
            "PROJECT": r["METASHAPE_PROJECT"], "DSM": dsm.id()})
        self.zoom_to("Demo plots", 1.6)
        self.found["tree_map"] = tree()
        self.shot("desktop_map.png")

        self.run_dialog("backward", "easyidp:backprojectrois", {    # GeoPackages, as users save
            "ROIS": plots.id(), "NAME_FIELD": "plot_id", "PROJECT": r["METASHAPE_PROJECT"],
            "DSM": dsm.id(), "OUTPUT": os.path.join(self.work, "rois_in_photos.gpkg"),
            "OUTPUT_SUMMARY": os.path.join(self.work, "photos_per_roi.gpkg")},
            open_outputs={"OUTPUT": True, "OUTPUT_SUMMARY": True})
        self.viewer(r["METASHAPE_PROJECT"], plots, dsm)
        labelme = os.path.join(self.survey, "labelme")
        self.run_dialog("forward", "easyidp:forwardprojectpolygons", {
            "INPUT_FOLDER": labelme, "PROJECT": r["METASHAPE_PROJECT"], "DSM": dsm.id(),
            "MERGE": 1})
        hidden = [v.name() for v in QgsProject.instance().mapLayers().values()
                  if v.name().startswith(("Camera", "Cameras", "Demo plots: height"))]
        self.set_visible(hidden, False)
        self.zoom_to("Demo plots", 1.15)
        self.found["tree_projection"] = tree()
        self.shot("desktop_projection.png")
        self.set_visible(hidden, True)

        crop_rows = [{"INPUT": layer.id(), "ROIS": plots.id(), "NAME_FIELD": "plot_id",
                      "OUTPUT_FOLDER": os.path.join(self.work, f"batch_{k}_{tag}"),
                      "OUTPUT_INDEX": "TEMPORARY_OUTPUT"}
                     for tag in ("off", "on") for k, layer in enumerate((ortho, dsm))]
        self.run_batch("batch_off", "easyidp:croprasterbyrois", crop_rows[:2], load=False)
        self.run_batch("batch_on", "easyidp:croprasterbyrois", crop_rows[2:], load=True)
        self.model(plots, dsm)
        self.found["tree_end"] = tree()
        self.found["help"] = {a.id(): a.helpUrl() for a in
                              QgsApplication.processingRegistry().providerById("easyidp").algorithms()}

    def viewer(self, project_file, plots, dsm):
        """The photo viewer as a user meets it: the EasyIDP toolbar button; the project and the
        DSM chosen; a plot selected and *Selected plots* clicked (the photos listed, recorded
        against Back-project ROIs' layer in photo pixels); the mouse over the plot on the photo
        (the map marker); a point clicked on the map; the layer in photo pixels shown over the
        photo that sees most plots. Screenshots: ``desktop_viewer.png``,
        ``desktop_raw_photo.png``."""
        from qgis.PyQt.QtCore import QPointF
        from qgis.PyQt.QtTest import QTest
        from qgis.utils import plugins
        from easyidp_toolbox.easyidp_qgis import presentation
        self.doing("opening the photo viewer from the EasyIDP toolbar")
        window = iface.mainWindow()
        toolbar = window.findChild(QToolBar, "EasyIDPToolbar")
        action = window.findChild(QAction, "mActionEasyIDPPhotoViewer")
        found = self.found["viewer"] = {
            "toolbar": toolbar is not None and action in toolbar.actions(),
            "menu": any(action in m.actions() for m in window.findChildren(QMenu)
                        if m.title().replace("&", "") == "EasyIDP")}
        action.trigger()
        dock = plugins["easyidp_toolbox"].viewer
        _pump(0.5)
        found["dock_visible"] = dock is not None and dock.isVisible()
        layers_dock = window.findChild(QDockWidget, "Layers")
        if layers_dock is not None:
            layers_dock.hide()                  # room for the map and the viewer side by side
        window.resizeDocks([dock], [720], Qt.Orientation.Horizontal)
        dock.project_widget.setFilePath(project_file)
        dock.dsm_combo.setLayer(dsm)
        pixel_layers = presentation.photo_pixel_layers()
        found["pixel_layers"] = [v.name() for v in pixel_layers]
        found["pixel_layers_in_tree"] = [v.name() for v in pixel_layers if
                                         QgsProject.instance().layerTreeRoot().findLayer(v.id())]
        found["pixel_layer_crs"] = [v.crs().authid() for v in pixel_layers]
        pixels = pixel_layers[0] if pixel_layers else None

        self.doing("listing the photos of plot C2 in the viewer")
        plot = "C2"
        plots.selectByExpression(f"\"plot_id\" = '{plot}'")
        iface.setActiveLayer(plots)
        started = time.time()
        dock.plots_button.click()
        found["plot_seconds"] = round(time.time() - started, 3)
        found["plot_rows"] = [[r["photo"], r["roi"], r["rank"], round(r["score"], 6)]
                              for r in dock.rows]
        found["status"] = dock.status.text()
        if not dock.rows:
            raise RuntimeError(f"the viewer listed no photo for {plot}: {dock.status.text()}")
        if pixels is not None:
            found["tool_rows"] = sorted(
                [f["photo"], f["roi"], f["rank"], round(f["score"], 6)]
                for f in pixels.getFeatures() if f["roi"] == plot)
        _wait(lambda: all(not dock.strip.item(k).icon().isNull()
                          for k in range(dock.strip.count())), 60)
        found["thumbnails"] = sum(not dock.strip.item(k).icon().isNull()
                                  for k in range(dock.strip.count()))
        _wait(lambda: getattr(dock, "full_loaded", None) == dock.current, 30)
        found["full_resolution"] = dock.view.pixmap_item is not None and \
            dock.view.pixmap_item.pixmap().width() == dock.rows[dock.current]["size"][0]
        dock.step(1)
        dock.step(-1)
        found["after_next_previous"] = dock.current

        self.doing("hovering over the plot on the photo")
        ring = dock.rows[dock.current]["polygons"][0][0]
        cx, cy = ring.mean(axis=0)
        view = dock.view
        QTest.mouseMove(view.viewport(), view.mapFromScene(QPointF(cx, cy)))
        _wait(lambda: dock.marker is not None and dock.marker.isVisible(), 5)
        if dock.marker is not None:
            centre = dock.marker.center()
            found["marker"] = [centre.x(), centre.y()]
            found["marker_in_plot"] = any(
                f.geometry().contains(centre) for f in plots.getFeatures()
                if f["plot_id"] == plot)
        self.zoom_to("Demo plots", 1.15)
        self.shot("desktop_viewer.png")

        self.doing("clicking a point on the map with the viewer's tool")
        dock.pick_button.click()
        canvas = iface.mapCanvas()
        found["map_tool"] = canvas.mapTool() is dock.tool
        target = next(f for f in plots.getFeatures() if f["plot_id"] == "B5")
        point = target.geometry().centroid().asPoint()
        pixel = canvas.getCoordinateTransform().transform(point)
        started = time.time()
        QTest.mouseClick(canvas.viewport(), Qt.MouseButton.LeftButton,
                         Qt.KeyboardModifier.NoModifier,
                         QPoint(int(pixel.x()), int(pixel.y())))
        found["point_seconds"] = round(time.time() - started, 3)
        found["point_rows"] = len(dock.rows)
        dock.pick_button.click()

        if pixels is not None:
            self.doing("showing the layer in photo pixels in the viewer")
            dock.refresh_pixel_layers()
            dock.pixel_layers.setCurrentIndex(dock.pixel_layers.findData(pixels.id()))
            dock.layer_button.click()
            counts = Counter(r["photo"] for r in dock.rows)
            photo, n = counts.most_common(1)[0]
            best = next(k for k, r in enumerate(dock.rows) if r["photo"] == photo)
            dock.select(best)
            dock.view.fitInView(dock.view.scene().sceneRect(), Qt.AspectRatioMode.KeepAspectRatio)
            _wait(lambda: getattr(dock, "full_loaded", None) == dock.current, 30)
            found["layer_rows"] = len(dock.rows)
            found["raw_photo"] = {"photo": photo, "rois": n}
            self.shot("desktop_raw_photo.png")
        plots.removeSelection()
        dock.close()                             # the map for the next steps; its marker gone
        if layers_dock is not None:
            layers_dock.show()
        _pump(0.3)

    def toolbox_open(self):
        """The Processing toolbox with the EasyIDP tools unfolded."""
        if self.toolbox is None:
            return
        self.toolbox.show()
        from qgis.gui import QgsProcessingToolboxTreeView
        view = self.toolbox.findChild(QgsProcessingToolboxTreeView)
        if view is None:
            return
        model = view.model()
        for row in range(model.rowCount()):
            index = model.index(row, 0)
            if "EasyIDP" in str(model.data(index)):
                view.expand(index)
                for child in range(model.rowCount(index)):
                    view.expand(model.index(child, 0, index))
                view.scrollTo(index, view.PositionAtTop)
        _pump(0.3)

    def toolbox_fit(self) -> list:
        """Whether each EasyIDP tool name fits the toolbox at its default dock width, without
        eliding: ``[language, name, text width, room]`` per tool, in pixels. The text width is
        the view font's ``QFontMetrics`` advance (CJK glyphs from the installed fonts, as the
        view draws them); the room is what the item's row leaves for text: from the item's left
        edge (after the tree's indentation) to the viewport's right edge, less the icon and the
        delegate's margins. The zh_CN and ja names (from ``i18n/*.ts``) are measured at the
        same place: the indentation and the font do not depend on the language."""
        from xml.etree import ElementTree   # the plugin's own translation files

        from qgis.gui import QgsProcessingToolboxTreeView
        from qgis.PyQt.QtGui import QFontMetrics
        from qgis.PyQt.QtWidgets import QStyle
        view = self.toolbox.findChild(QgsProcessingToolboxTreeView) if self.toolbox else None
        if view is None:
            return []
        model, items = view.model(), []

        def walk(parent):
            for row in range(model.rowCount(parent)):
                index = model.index(row, 0, parent)
                if model.rowCount(index):
                    walk(index)
                else:
                    items.append(index)
        for row in range(model.rowCount()):
            top = model.index(row, 0)
            if "EasyIDP" in str(model.data(top)):
                walk(top)
        i18n = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "i18n")
        names = {}
        for lang in ("zh_CN", "ja"):
            root = ElementTree.parse(os.path.join(i18n, f"easyidp_{lang}.ts")).getroot()
            names[lang] = {m.findtext("source"): m.findtext("translation")
                           for m in root.iter("message")}
        metrics = QFontMetrics(view.font())
        margin = view.style().pixelMetric(QStyle.PM_FocusFrameHMargin, None, view) + 1
        icon = view.iconSize().width() if view.iconSize().width() > 0 else \
            view.style().pixelMetric(QStyle.PM_SmallIconSize, None, view)
        out = []
        for index in items:
            rect = view.visualRect(index)
            room = min(rect.right(), view.viewport().width()) - rect.left() - icon - 3 * margin
            text = str(model.data(index))
            for lang, name in [("en", text)] + [(lang, names[lang].get(text)) for lang in names]:
                if name:
                    out.append([lang, name, metrics.horizontalAdvance(name), room])
        return out

    def model(self, plots, dsm):
        """The example model from the toolbox (the user's models folder), run with the crop
        index set to open and not; and opened in the modeler."""
        source = self.model_file
        if not source:
            return
        folder = os.path.join(QgsApplication.qgisSettingsDirPath(), "processing", "models")
        os.makedirs(folder, exist_ok=True)
        shutil.copy(source, folder)
        QgsApplication.processingRegistry().providerById("model").refreshAlgorithms()
        alg_id = "model:ROI heights then crop"
        found = QgsApplication.processingRegistry().algorithmById(alg_id) is not None
        self.found["model_in_toolbox"] = found
        if not found:
            return
        for tag, ticked in (("model_off", False), ("model_on", True)):
            self.run_dialog(tag, alg_id, {
                "plots": plots.id(), "dsm": dsm.id(), "name_field": "plot_id",
                "crop:Crops": os.path.join(self.work, f"model_crops_{tag}")},
                open_outputs={"heights:Plots with heights": ticked,
                              "crop:Index of the crops": ticked})
        self.doing("opening the example model in the modeler")
        model = QgsProcessingModelAlgorithm()
        model.fromFile(source)
        self.found["model_valid"] = list(model.validate())
        try:
            from processing.modeler.ModelerDialog import ModelerDialog
            dlg = ModelerDialog.create(model) if hasattr(ModelerDialog, "create") else ModelerDialog(model)
            dlg.show()
            dlg.resize(1100, 620)
            _pump(0.5)
            for action in dlg.findChildren(QAction):
                if action.objectName() == "mActionZoomToItems":
                    action.trigger()
            _pump(0.5)
            from qgis.gui import QgsMessageBarItem
            self.found["modeler_messages"] = [
                f"{i.title()}: {i.text()}" for i in dlg.findChildren(QgsMessageBarItem) if i.isVisible()]
            self.shot("desktop_modeler.png", dlg)
            dlg.setDirty(False) if hasattr(dlg, "setDirty") else None
            dlg.close()
        except Exception:
            self.found["modeler_error"] = traceback.format_exc()


def _group_names(node=None):
    node = node or QgsProject.instance().layerTreeRoot()
    out = []
    for ch in node.children():
        if isinstance(ch, QgsLayerTreeGroup):
            out += [ch.name()] + _group_names(ch)
    return out


def run_session(spec: dict, modal: list, doing) -> dict:
    """The session; ``modal`` and ``doing``: see :class:`Session`."""
    session = Session(spec, modal, doing)
    try:
        session.run()
    except Exception:
        session.found["session_error"] = traceback.format_exc()
    finally:
        QgsApplication.messageLog().messageReceived.disconnect(session._log)
    return session.found
