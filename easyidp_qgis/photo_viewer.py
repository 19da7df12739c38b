"""The raw-photo viewer (issue 37): a dock and a map tool. Which photos see this point, these
plots? Click a point on the map, or select plots in a polygon layer: the photos that see them are
listed, ranked as *Back-project ROIs* ranks them (one ``core.projection.PhotoFinder`` query),
as thumbnails in a strip, and the selected photo large with the point or the plot outline drawn
(wheel: zoom; drag: pan; ←/→: previous/next photo). Hovering over the photo puts a marker in
the map where that pixel lands (forward projection on the DSM). Layers in photo pixels (the
output of *Back-project ROIs*) open here over their photos, never in the map.

The project and the DSM are read once and kept while they stay the same; photos are decoded in
background tasks (thumbnails first), cancelled by the next query.
"""
import os

from qgis.core import QgsApplication, QgsFeatureRequest, QgsPointXY, QgsProject
from qgis.gui import QgsFileWidget, QgsMapLayerComboBox, QgsVertexMarker
from qgis.PyQt.QtCore import QCoreApplication, QPointF, QRectF, QSize, Qt, QTimer
from qgis.PyQt.QtGui import QBrush, QColor, QIcon, QPainter, QPen, QPixmap, QPolygonF
from qgis.PyQt.QtWidgets import (QAbstractItemView, QComboBox, QDockWidget, QDoubleSpinBox,
                                 QFileDialog, QFormLayout, QGraphicsScene, QGraphicsView,
                                 QHBoxLayout, QLabel, QListView, QListWidget, QListWidgetItem,
                                 QPushButton, QSplitter, QTableWidget, QTableWidgetItem,
                                 QVBoxLayout, QWidget)

from . import presentation
from .compat import LayerFilter
from .crs import crs_string
from .geometries import pixel_polygons
from .photo_tasks import DecodeTask, PointTool
from .rasters import geotiff_source
from .values import is_null

THUMB = 120                      # thumbnail size, pixels (longer side)
COLUMNS = ("photo", "roi", "rank", "score", "view_angle", "gsd", "visible", "occluded")
STEP_KEYS = {Qt.Key.Key_Right: 1, Qt.Key.Key_PageDown: 1, Qt.Key.Key_Space: 1,
             Qt.Key.Key_Left: -1, Qt.Key.Key_PageUp: -1, Qt.Key.Key_Backspace: -1}


def tr(text: str) -> str:
    return QCoreApplication.translate("EasyIDP", text)


class PhotoView(QGraphicsView):
    """A photo at full resolution with outlines (pixels: x = column, y = row); wheel zooms,
    dragging pans; ``hovered(column, row)`` follows the mouse."""

    def __init__(self, on_hover, on_step, parent=None):
        super().__init__(parent)
        self.setScene(QGraphicsScene(self))
        self.setDragMode(QGraphicsView.DragMode.ScrollHandDrag)
        self.setTransformationAnchor(QGraphicsView.ViewportAnchor.AnchorUnderMouse)
        self.setRenderHint(QPainter.RenderHint.SmoothPixmapTransform)
        self.setMouseTracking(True)
        self.setBackgroundBrush(QBrush(QColor("#202020")))
        self.on_hover, self.on_step = on_hover, on_step
        self.pixmap_item = None

    def show_photo(self, image, size, polygons, point=None, focus=None, others=()):
        """``image`` (QImage, may be a thumbnail or null) stretched over the photo's ``size``
        (width, height); ``polygons`` [[ring (n, 2)], …] outlined in green, ``others`` (the
        other ROIs on this photo) in thin white; ``point`` (x, y) marked; the view fitted to
        ``focus`` (x0, y0, x1, y1), else the photo."""
        scene = self.scene()
        scene.clear()
        w, h = size
        scene.setSceneRect(QRectF(0, 0, w, h))
        self.pixmap_item = None
        if image is not None and not image.isNull():
            self.set_image(image, size)
        for shapes, colour, width in ((others, "#f0f0f0", 1), (polygons, "#33ff33", 2.5)):
            pen = QPen(QColor(colour), width)
            pen.setCosmetic(True)
            for poly in shapes:
                for ring in poly:
                    scene.addPolygon(QPolygonF([QPointF(float(x), float(y)) for x, y in ring]),
                                     pen)
        if point is not None:
            red = QPen(QColor("#ff2020"), 2)
            red.setCosmetic(True)
            x, y = point
            r = max(w, h) / 150
            scene.addLine(x - r, y, x + r, y, red)
            scene.addLine(x, y - r, x, y + r, red)
        self.fitInView(QRectF(*focus[:2], focus[2] - focus[0], focus[3] - focus[1]) if focus
                       else scene.sceneRect(), Qt.AspectRatioMode.KeepAspectRatio)

    def set_image(self, image, size):
        """Put ``image`` (a thumbnail or the full photo) under the outlines."""
        pixmap = QPixmap.fromImage(image)
        if self.pixmap_item is not None:
            self.scene().removeItem(self.pixmap_item)
        self.pixmap_item = self.scene().addPixmap(pixmap)
        self.pixmap_item.setZValue(-1)
        self.pixmap_item.setTransformationMode(Qt.TransformationMode.SmoothTransformation)
        if pixmap.width():
            self.pixmap_item.setScale(size[0] / pixmap.width())

    def wheelEvent(self, event):  # noqa: N802 (Qt API)
        factor = 1.25 if event.angleDelta().y() > 0 else 0.8
        self.scale(factor, factor)

    def keyPressEvent(self, event):  # noqa: N802 (Qt API)
        if not _step_key(event, self.on_step):
            super().keyPressEvent(event)

    def mouseMoveEvent(self, event):  # noqa: N802 (Qt API)
        super().mouseMoveEvent(event)
        p = self.mapToScene(event.pos())
        rect = self.scene().sceneRect()
        if rect.contains(p):
            self.on_hover(p.x(), p.y())


def _step_key(event, step) -> bool:
    """Next/previous photo on a key of :data:`STEP_KEYS`: whether the key was one."""
    by = STEP_KEYS.get(event.key())
    if by:
        step(by)
    return bool(by)


def _alive(task) -> bool:
    try:
        return task.status() not in (task.TaskStatus.Complete, task.TaskStatus.Terminated)
    except RuntimeError:                   # finished, and deleted by QGIS's task manager
        return False


def _cancel(task) -> None:
    if _alive(task):
        task.cancel()


class PhotoViewer(QDockWidget):
    """The dock. ``rows``: the photos listed, dicts with ``photo``, ``roi``, ``path``, ``size``
    (w, h), ``polygons`` (pixels), ``point`` (or None) and the ranking's numbers."""

    def __init__(self, iface, parent=None):
        super().__init__(tr("EasyIDP photo viewer"), parent)
        self.setObjectName("EasyIDPPhotoViewer")
        self.iface = iface
        self.canvas = iface.mapCanvas()
        self.finder, self.finder_key = None, None
        self.rows, self.current, self.query, self.shown = [], -1, 0, 0
        self.tasks, self.full_task = [], None
        self.images = {}
        self.marker = None
        self.tool = PointTool(self.canvas)
        self.tool.picked.connect(self.query_point)
        self.hover_at = None
        self.hover_timer = QTimer(self)
        self.hover_timer.setSingleShot(True)
        self.hover_timer.setInterval(40)
        self.hover_timer.timeout.connect(self._hover_now)
        self._build()

    # ---- the widgets ----
    def _build(self):
        body = QWidget()
        layout = QVBoxLayout(body)
        form = QFormLayout()
        self.project_widget = QgsFileWidget()
        self.project_widget.setFilter(tr("Photogrammetry projects (*.psx *.psz *.xml *.p4d "
                                         "*.opf *.json);;All files (*)"))
        form.addRow(tr("Project"), self.project_widget)
        self.dsm_combo = QgsMapLayerComboBox()
        self.dsm_combo.setFilters(LayerFilter.RasterLayer)
        self.dsm_combo.setAllowEmptyLayer(True)
        form.addRow(tr("DSM"), self.dsm_combo)
        self.ground = QDoubleSpinBox()
        self.ground.setRange(-1000.0, 10000.0)
        self.ground.setDecimals(2)
        self.ground.setToolTip(tr("Used when no DSM is chosen: one ground height, in the "
                                  "project's vertical reference"))
        form.addRow(tr("Ground height without a DSM"), self.ground)
        self.pixel_layers = QComboBox()
        form.addRow(tr("Layer in photo pixels"), self.pixel_layers)
        layout.addLayout(form)
        buttons = QHBoxLayout()
        self.pick_button = QPushButton(tr("Click a point"))
        self.pick_button.setCheckable(True)
        self.pick_button.toggled.connect(self._pick)
        self.plots_button = QPushButton(tr("Selected plots"))
        self.plots_button.clicked.connect(self.query_selection)
        self.layer_button = QPushButton(tr("Show layer"))
        self.layer_button.clicked.connect(self.show_pixel_layer)
        for b in (self.pick_button, self.plots_button, self.layer_button):
            buttons.addWidget(b)
        layout.addLayout(buttons)
        split = QSplitter(Qt.Orientation.Vertical)
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels([tr("Photo"), tr("ROI"), tr("Rank"), tr("Score"),
                                              tr("View angle (°)"), tr("GSD"), tr("Visible"),
                                              tr("Occluded")])
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.currentCellChanged.connect(lambda row, *_: self.select(row))
        self.table.setMinimumHeight(70)
        self.strip = QListWidget()
        self.strip.setViewMode(QListView.ViewMode.IconMode)
        self.strip.setFlow(QListView.Flow.LeftToRight)
        self.strip.setWrapping(False)
        self.strip.setIconSize(QSize(THUMB, THUMB * 3 // 4))
        self.strip.setFixedHeight(THUMB * 3 // 4 + 44)
        self.strip.currentRowChanged.connect(self.select)
        self.view = PhotoView(self.hover, self.step)
        for w in (self.table, self.strip, self.view):
            split.addWidget(w)
        self.view.setMinimumHeight(150)
        split.setStretchFactor(0, 1)
        split.setStretchFactor(2, 5)
        split.setSizes([120, THUMB * 3 // 4 + 44, 600])
        layout.addWidget(split, 1)
        self.status = QLabel()
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        exports = QHBoxLayout()
        for text, slot in ((tr("Save the shown crop…"), self._save_crop),
                           (tr("Save the outline as LabelMe…"), self._save_labelme)):
            b = QPushButton(text)
            b.clicked.connect(slot)
            exports.addWidget(b)
        layout.addLayout(exports)
        self.setWidget(body)
        QgsProject.instance().layersAdded.connect(lambda _: self.refresh_pixel_layers())
        QgsProject.instance().layersRemoved.connect(lambda _: self.refresh_pixel_layers())
        self.refresh_pixel_layers()

    def refresh_pixel_layers(self):
        """The layers in photo pixels the tools loaded (not in the map)."""
        chosen = self.pixel_layers.currentData()
        self.pixel_layers.clear()
        for layer in presentation.photo_pixel_layers():
            self.pixel_layers.addItem(layer.name(), layer.id())
        at = self.pixel_layers.findData(chosen)
        if at >= 0:
            self.pixel_layers.setCurrentIndex(at)

    def _pick(self, on: bool):
        if on:
            self.canvas.setMapTool(self.tool)
        elif self.canvas.mapTool() is self.tool:
            self.canvas.unsetMapTool(self.tool)

    # ---- the project and the ground, kept ----
    def ensure_finder(self):
        """The PhotoFinder of the chosen project and DSM (or ground height), opened once."""
        path = self.project_widget.filePath()
        if not path:
            raise ValueError(tr("Choose the photogrammetry project first."))
        dsm_layer = self.dsm_combo.currentLayer()
        key = (path, dsm_layer.id() if dsm_layer else None,
               None if dsm_layer else self.ground.value())
        if self.finder is None or key != self.finder_key:
            from ..core.projection import PhotoFinder
            from ..core.raster import DSM
            from ..core.reconstruction import open_reconstruction
            recon = open_reconstruction(path)
            dsm = None
            if dsm_layer is not None:
                dsm = DSM(geotiff_source(dsm_layer, tr("DSM")), crs=crs_string(dsm_layer.crs()))
            self.finder = PhotoFinder(recon, dsm=dsm,
                                      ground=None if dsm else self.ground.value())
            self.finder_key = key
        return self.finder

    def _canvas_crs(self):
        return self.canvas.mapSettings().destinationCrs()

    # ---- queries ----
    def query_point(self, point):
        """The photos that see ``point`` (QgsPointXY, map canvas CRS)."""
        try:
            finder = self.ensure_finder()
            result = finder.point(point.x(), point.y(), crs_string(self._canvas_crs()))
        except Exception as exc:               # an input the user can mend: said in the dock
            self._say(str(exc))
            return
        self._show_result(result, point_query=True)

    def query_selection(self, layer=None):
        """The photos that see the selected features of ``layer`` (default: the active layer)."""
        from .rois import rois_from_source
        layer = layer or self.iface.activeLayer()
        try:
            if layer is None or not hasattr(layer, "selectedFeatureIds") or \
                    not layer.selectedFeatureIds():
                raise ValueError(tr("Select plots in a polygon layer first."))
            chosen = layer.materialize(QgsFeatureRequest().setFilterFids(
                layer.selectedFeatureIds()))
            name = presentation.first_field(layer.fields(), ("plot_id", "name", "id", "roi"))
            rois, _ = rois_from_source(chosen, name or "", layer.name())
            result = self.ensure_finder().rois(rois)
        except Exception as exc:
            self._say(str(exc))
            return
        self._show_result(result, point_query=False)

    def _show_result(self, result, point_query: bool):
        rows = []
        for i in range(len(result)):
            j = int(result.photo_index[i])
            polygons = result.polygons_of(i)
            ring = polygons[0][0] if polygons else None
            rows.append({
                "photo": str(result.photo[i]), "roi": result.roi_names[int(result.roi[i])],
                "path": result.photo_paths[j] or "",
                "size": tuple(int(v) for v in result.image_sizes[j]),
                "polygons": [] if point_query else polygons,
                "point": tuple(ring.mean(axis=0)) if point_query and ring is not None else None,
                "rank": int(result.rank[i]), "score": float(result.score[i]),
                "view_angle": float(result.view_angle[i]), "gsd": float(result.gsd[i]),
                "visible": float(result.visible_fraction[i]),
                "occluded": float(result.occluded_fraction[i])})
        self.show_rows(rows)
        self._say(tr("{n} photos see it.").format(n=len(rows)) if rows else
                  tr("No photo sees it: {why}").format(why="; ".join(result.unseen.values())))

    def show_pixel_layer(self):
        """The features of the chosen layer in photo pixels, over their photos (best first)."""
        layer = QgsProject.instance().mapLayer(self.pixel_layers.currentData() or "")
        if layer is None:
            self._say(tr("No layer in photo pixels: run Back-project ROIs first."))
            return
        names = layer.fields().names()
        rows = []
        for f in layer.getFeatures():
            def value(k, default=None):
                return default if k not in names or is_null(f[k]) else f[k]
            rows.append({"photo": str(value("photo", "")), "roi": str(value("roi", f.id())),
                         "path": str(value("photo_path", "")),
                         "size": (int(value("photo_width", 0)), int(value("photo_height", 0))),
                         "polygons": pixel_polygons(f.geometry()), "point": None,
                         "rank": value("rank", 0), "score": value("score", float("nan")),
                         "view_angle": value("view_angle", float("nan")),
                         "gsd": value("gsd", float("nan")),
                         "visible": value("visible_fraction", float("nan")),
                         "occluded": value("occluded_fraction", float("nan"))})
        rows.sort(key=lambda r: (r["roi"], r["rank"]))
        self.show_rows(rows)
        self._say(tr("{n} ROI × photo pairs of {layer}.").format(n=len(rows), layer=layer.name()))

    def show_rows(self, rows):
        """List ``rows`` in the table and the strip; thumbnails decoded in the background (the
        previous query's task cancelled); the first photo shown."""
        self.query += 1
        for task in self.tasks:
            _cancel(task)
        self.tasks, self.images = [], {}
        self.rows, self.current = rows, -1
        self.table.blockSignals(True)
        self.strip.blockSignals(True)
        self.table.setRowCount(len(rows))
        self.strip.clear()
        for k, r in enumerate(rows):
            for c, key in enumerate(COLUMNS):
                v = r[key]
                text = f"{v:.3g}" if isinstance(v, float) else str(v)
                self.table.setItem(k, c, QTableWidgetItem(text))
            item = QListWidgetItem(f"{r['photo']}\n{r['roi']}")
            item.setIcon(QIcon())
            self.strip.addItem(item)
        self.table.blockSignals(False)
        self.strip.blockSignals(False)
        if rows:
            self._decode(self.query, [r["path"] for r in rows], THUMB, self._thumbnail)
            self.select(0)

    def _decode(self, key, paths, longest, slot):
        task = DecodeTask(tr("EasyIDP viewer: decoding photos"), key, paths, longest)
        task.decoded.connect(slot)
        self.tasks = [t for t in self.tasks if _alive(t)] + [task]
        QgsApplication.taskManager().addTask(task)
        return task

    def _thumbnail(self, key, k, image):
        if key != self.query or k >= self.strip.count() or image.isNull():
            return
        self.images.setdefault(k, image)
        self.strip.item(k).setIcon(QIcon(QPixmap.fromImage(image)))
        if k == self.current and self.view.pixmap_item is None:
            self.view.set_image(image, self.rows[k]["size"])

    def _full(self, key, k, image):
        if key == self.shown and 0 <= self.current < len(self.rows) and not image.isNull():
            self.view.set_image(image, self.rows[self.current]["size"])
            self.full_loaded = self.current

    # ---- the selected photo ----
    def select(self, k: int):
        """Show photo ``k`` of the list large (thumbnail first, full resolution when decoded)."""
        if not 0 <= k < len(self.rows) or k == self.current:
            return
        self.current = k
        for widget, setter in ((self.table, self.table.selectRow),
                               (self.strip, self.strip.setCurrentRow)):
            widget.blockSignals(True)
            setter(k)
            widget.blockSignals(False)
        r = self.rows[k]
        w, h = r["size"]
        xy = [p for poly in r["polygons"] for ring in poly for p in ring]
        if r["point"] is not None:
            xy.append(r["point"])
        focus = None
        if xy:
            xs, ys = [p[0] for p in xy], [p[1] for p in xy]
            pad = max(max(xs) - min(xs), max(ys) - min(ys), max(w, h) / 8)
            focus = (min(xs) - pad, min(ys) - pad, max(xs) + pad, max(ys) + pad)
        self.full_loaded = None
        others = [poly for x in self.rows if x["photo"] == r["photo"] and x["roi"] != r["roi"]
                  for poly in x["polygons"]]
        self.view.show_photo(self.images.get(k), r["size"], r["polygons"], r["point"], focus,
                             others)
        self.shown += 1
        if self.full_task is not None:
            _cancel(self.full_task)
        if r["path"]:
            self.full_task = self._decode(self.shown, [r["path"]], 0, self._full)
        self._say(tr("{photo}: {roi}, rank {rank}, score {score:.2f}").format(
            photo=r["photo"], roi=r["roi"], rank=r["rank"], score=r["score"]))

    def step(self, by: int):
        """The next (``by`` = 1) or previous (−1) photo of the list."""
        if self.rows:
            self.select((self.current + by) % len(self.rows))

    # ---- hovering: where the pixel lands on the map ----
    def hover(self, column: float, row: float):
        self.hover_at = (column, row)
        self.hover_timer.start()

    def _hover_now(self):
        if self.hover_at is None or not 0 <= self.current < len(self.rows) or self.finder is None:
            return
        photo = self.rows[self.current]["photo"]
        try:
            hit = self.finder.map_point(photo, *self.hover_at,
                                        crs=crs_string(self._canvas_crs()))
        except Exception as exc:
            self._say(str(exc))
            return
        if hit is None:
            return
        if self.marker is None:
            self.marker = QgsVertexMarker(self.canvas)
            self.marker.setColor(QColor("#ff2020"))
            self.marker.setIconType(QgsVertexMarker.IconType.ICON_CROSS)
            self.marker.setIconSize(18)
            self.marker.setPenWidth(3)
        self.marker.setCenter(QgsPointXY(hit[0], hit[1]))
        self.marker.show()

    # ---- exports ----
    def save_crop(self, path: str) -> str:
        """The part of the photo the view shows, at full resolution, as an image file."""
        r = self.rows[self.current]
        from .photo_tasks import read_image
        image = read_image(r["path"])
        shown = self.view.mapToScene(self.view.viewport().rect()).boundingRect()
        rect = shown.toAlignedRect().intersected(image.rect())
        tmp = path + ".part" + os.path.splitext(path)[1]
        if rect.isEmpty() or not image.copy(rect).save(tmp):
            raise OSError(tr("Could not write {path}.").format(path=path))
        os.replace(tmp, path)
        return path

    def save_labelme(self, path: str) -> str:
        """The outline on the shown photo as a LabelMe file (pixels as the project's)."""
        from ..core.annotations import LabelledImage, LabelledShape, write_labelme
        r = self.rows[self.current]
        if not r["polygons"]:
            raise ValueError(tr("A clicked point has no outline: select plots."))
        image = LabelledImage(os.path.basename(r["path"]), *r["size"],
                              [LabelledShape(r["roi"], r["roi"], r["polygons"])])
        return write_labelme(path, image, os.path.relpath(r["path"], os.path.dirname(path)))

    def _save_crop(self):
        self._save(self.save_crop, tr("Images (*.png *.jpg *.tif)"), ".png")

    def _save_labelme(self):
        self._save(self.save_labelme, tr("LabelMe (*.json)"), ".json")

    def _save(self, write, filter_text, suffix):
        if not 0 <= self.current < len(self.rows):
            return
        r = self.rows[self.current]
        start = f"{os.path.splitext(r['photo'])[0]}_{r['roi']}{suffix}"
        path, _ = QFileDialog.getSaveFileName(self, tr("Save"), start, filter_text)
        if path:
            try:
                self._say(tr("Written: {path}").format(path=write(path)))
            except Exception as exc:
                self._say(str(exc))

    def _say(self, text: str):
        self.status.setText(text)

    def keyPressEvent(self, event):  # noqa: N802 (Qt API)
        if not _step_key(event, self.step):
            super().keyPressEvent(event)

    def closeEvent(self, event):  # noqa: N802 (Qt API)
        for task in self.tasks + [self.full_task]:
            if task is not None:
                _cancel(task)
        self.pick_button.setChecked(False)
        if self.marker is not None:
            self.canvas.scene().removeItem(self.marker)
            self.marker = None
        super().closeEvent(event)
