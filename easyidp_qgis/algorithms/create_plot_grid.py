"""Processing tool: Create plot grid (easyidp:createplotgrid)."""
import os

from qgis.core import (QgsCoordinateTransform, QgsFeature,
                       QgsField, QgsFields, QgsPointXY, QgsProcessingException, QgsProcessingParameterCrs,
                       QgsProcessingParameterEnum,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProcessingParameterNumber,
                       QgsProcessingParameterPoint, QgsProcessingParameterString)

from ..compat import (FeatureSinkFlag, FieldType, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType, WkbType)
from .. import presentation
from ..crs import crs_string
from ..geometries import polygon
from ..parameters import optional_number
from ..sinks import close_sink
from ..values import is_null
from .base import CoreStep, EasyIDPAlgorithm, translatable

ANCHORS = [("corners", translatable("Four corner points (any order)")),
           ("boundary", translatable("Field boundary polygon (its minimum-area rectangle)")),
           ("origin", translatable("Origin point (upper-left corner) and bearing"))]
ORDERS = [("row-major", translatable("Row by row")),
          ("serpentine", translatable("Serpentine rows (back and forth)")),
          ("column-major", translatable("Column by column")),
          ("serpentine-columns", translatable("Serpentine columns"))]
STARTS = [("top-left", translatable("Top left")), ("top-right", translatable("Top right")),
          ("bottom-left", translatable("Bottom left")),
          ("bottom-right", translatable("Bottom right"))]
JOINS = [("plot_id", translatable("Plot id (the name)")),
         ("plot_no", translatable("Plot number")),
         ("row_col", translatable("Row and column"))]


def qvariant_type(values):
    """The field type of a column of Python values (None ignored)."""
    kinds = {type(v) for v in values if v is not None}
    if kinds and kinds <= {int, bool}:
        return FieldType.Int
    if kinds and kinds <= {int, bool, float}:
        return FieldType.Double
    return FieldType.QString


class CreatePlotGrid(EasyIDPAlgorithm):
    ANCHOR = "ANCHOR"
    CORNERS = "CORNERS"
    BOUNDARY = "BOUNDARY"
    ORIGIN = "ORIGIN"
    BEARING = "BEARING"
    ROWS = "ROWS"
    COLS = "COLS"
    SIZE_X = "SIZE_X"
    SIZE_Y = "SIZE_Y"
    GAP_X = "GAP_X"
    GAP_Y = "GAP_Y"
    SPACING_X = "SPACING_X"
    SPACING_Y = "SPACING_Y"
    BLOCKS_X = "BLOCKS_X"
    BLOCKS_Y = "BLOCKS_Y"
    BLOCK_GAP_X = "BLOCK_GAP_X"
    BLOCK_GAP_Y = "BLOCK_GAP_Y"
    BUFFER = "BUFFER"
    ORDER = "ORDER"
    START = "START"
    START_ID = "START_ID"
    PATTERN = "PATTERN"
    TOLERANCE = "TOLERANCE"
    CRS = "CRS"
    FIELD_BOOK = "FIELD_BOOK"
    JOIN_BY = "JOIN_BY"
    BOOK_ID = "BOOK_ID"
    BOOK_ROW = "BOOK_ROW"
    BOOK_COL = "BOOK_COL"
    OUTPUT = "OUTPUT"

    NAME = "createplotgrid"
    REQUIRES = ()  # numpy and pyproj only (the plugin's own)
    DISPLAY = "Create plot grid"
    GROUP = "ROIs"
    GROUP_ID = "rois"
    HELP = (
        "Makes the plot polygons of a trial from its field layout: rows (ranges) × columns "
        "(passes) of plots, in blocks, numbered and joined to the field book.\n\n"
        "Anchor: four corner points of the field in any order (they are sorted clockwise from the "
        "upper-left corner, the one whose edge to the next points closest to east; the log says "
        "the order used), a field-boundary polygon (its minimum-area rectangle), or an origin "
        "(the upper-left corner) and the bearing of the top edge (90 = east). Columns are counted "
        "along the top edge (x), rows down the left edge (y).\n\n"
        "Layout, per axis: plot size, gap between plots (or the spacing, centre to centre), "
        "blocks and the gap between blocks. With corners or a boundary, a size or gap left empty "
        "is solved so that the plots fill the field. A negative buffer shrinks every plot on each "
        "side (a positive one grows it); plots stay rectangles.\n\n"
        "Numbering: row by row, column by column or serpentine, from any corner, from the start "
        "id; the name pattern takes {plot_no}, {row}, {col}, {block}, {block_row}, {block_col}, "
        "{row_letter}, {range} and {pass}, e.g. {block}-{row:02d}-{col:02d}.\n\n"
        "Field book: a table (e.g. a CSV layer) joined by plot id, plot number, or row and "
        "column; rows that match no plot and plots without a row are listed in the log.\n\n"
        "The CRS must be projected in metres: a geographic CRS is refused with the UTM zone to "
        "use. Corners that are not a rectangle, and plots that would overlap, are refused with "
        "the amount.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterEnum(
            self.ANCHOR, self.tr("Anchor"), options=[self.tr(a[1]) for a in ANCHORS],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.CORNERS, self.tr("Field corners (4 points)"), [ProcessingSourceType.VectorPoint],
            optional=True))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.BOUNDARY, self.tr("Field boundary (a polygon)"), [ProcessingSourceType.VectorPolygon],
            optional=True))
        self.addParameter(QgsProcessingParameterPoint(
            self.ORIGIN, self.tr("Origin (upper-left corner of the field)"), optional=True))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.BEARING, self.tr("Bearing of the top edge (degrees clockwise from north)"),
            ProcessingNumberParameterType.Double, defaultValue=90.0, minValue=-360.0,
            maxValue=360.0), 3))
        self.addParameter(QgsProcessingParameterNumber(
            self.ROWS, self.tr("Rows (ranges)"), ProcessingNumberParameterType.Integer,
            defaultValue=4, minValue=1))
        self.addParameter(QgsProcessingParameterNumber(
            self.COLS, self.tr("Columns (passes)"), ProcessingNumberParameterType.Integer,
            defaultValue=4, minValue=1))
        for name, text in ((self.SIZE_X, translatable("Plot size along a row (m; empty: fill the field)")),
                           (self.SIZE_Y, translatable("Plot size down a column (m; empty: fill the field)")),
                           (self.GAP_X, translatable("Gap between columns of plots (m; empty: solved)")),
                           (self.GAP_Y, translatable("Alley between rows of plots (m; empty: solved)"))):
            self.addParameter(self.decimals(QgsProcessingParameterNumber(
                name, self.tr(text), ProcessingNumberParameterType.Double, optional=True,
                minValue=0.0), 3))
        advanced = []
        for name, text in ((self.SPACING_X, translatable("Column spacing, centre to centre (m; not the gap)")),
                           (self.SPACING_Y, translatable("Row spacing, centre to centre (m; not the alley)"))):
            advanced.append(self.decimals(QgsProcessingParameterNumber(
                name, self.tr(text), ProcessingNumberParameterType.Double, optional=True,
                minValue=0.0), 3))
        for name, text in ((self.BLOCKS_X, translatable("Blocks along a row")),
                           (self.BLOCKS_Y, translatable("Blocks down a column"))):
            self.addParameter(QgsProcessingParameterNumber(
                name, self.tr(text), ProcessingNumberParameterType.Integer, defaultValue=1,
                minValue=1))
        for name, text in ((self.BLOCK_GAP_X, translatable("Gap between blocks along a row (m; empty: the plot gap)")),
                           (self.BLOCK_GAP_Y, translatable("Gap between blocks down a column (m; empty: the alley)"))):
            self.addParameter(self.decimals(QgsProcessingParameterNumber(
                name, self.tr(text), ProcessingNumberParameterType.Double, optional=True,
                minValue=0.0), 3))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.BUFFER, self.tr("Buffer (m; negative shrinks every plot on each side)"),
            ProcessingNumberParameterType.Double, defaultValue=0.0), 3))
        self.addParameter(QgsProcessingParameterEnum(
            self.ORDER, self.tr("Numbering order"), options=[self.tr(o[1]) for o in ORDERS],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum(
            self.START, self.tr("Numbering starts at"), options=[self.tr(s[1]) for s in STARTS],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterNumber(
            self.START_ID, self.tr("Start id (first plot number)"),
            ProcessingNumberParameterType.Integer, defaultValue=1))
        self.addParameter(QgsProcessingParameterString(
            self.PATTERN, self.tr("Name pattern"), defaultValue="{plot_no}"))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.FIELD_BOOK, self.tr("Field book (a table, e.g. a CSV layer)"),
            [ProcessingSourceType.Vector], optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.JOIN_BY, self.tr("Join the field book by"), options=[self.tr(j[1]) for j in JOINS],
            defaultValue=0))
        for name, text in ((self.BOOK_ID, translatable("Field-book column of the plot id or number")),
                           (self.BOOK_ROW, translatable("Field-book column of the row (default: row)")),
                           (self.BOOK_COL, translatable("Field-book column of the column (default: col)"))):
            self.addParameter(QgsProcessingParameterField(
                name, self.tr(text), parentLayerParameterName=self.FIELD_BOOK, optional=True))
        tolerance = self.decimals(QgsProcessingParameterNumber(
            self.TOLERANCE, self.tr("Corner tolerance (m)"),
            ProcessingNumberParameterType.Double, defaultValue=0.25, minValue=0.0), 3)
        tolerance.setHelp(self.tr("How far the given corners may be from a rectangle"))
        advanced.append(tolerance)
        advanced.append(QgsProcessingParameterCrs(
            self.CRS, self.tr("Output CRS (projected, in metres; default: the anchor's)"),
            optional=True))
        for p in advanced:
            p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
            self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("Plot grid"), ProcessingSourceType.VectorPolygon))

    def checkParameterValues(self, parameters, context):  # noqa: N802 (QGIS API)
        """A field book given as a file that is empty, binary or damaged is named with what is
        wrong with it (QGIS would only say that the layer was not found)."""
        from ...core.plotgrid import field_book_problem
        book = parameters.get(self.FIELD_BOOK)
        if isinstance(book, str) and book:
            path = book.split("|")[0]
            if os.path.isfile(path):
                problem = field_book_problem(path)
                if problem:
                    return False, problem
        return super().checkParameterValues(parameters, context)

    # ---- reading the anchor -----------------------------------------------------------------

    def _anchor(self, parameters, context):
        """(kind, core keyword, value in the output CRS, output CRS)."""
        kind = ANCHORS[self.parameterAsEnum(parameters, self.ANCHOR, context)][0]
        target = self.parameterAsCrs(parameters, self.CRS, context)
        if kind == "origin":
            if parameters.get(self.ORIGIN) in (None, ""):
                raise QgsProcessingException(self.tr(
                    "Origin: give the upper-left corner of the field (or choose another anchor)."))
            src_crs = self.parameterAsPointCrs(parameters, self.ORIGIN, context)
            if not src_crs.isValid():
                src_crs = context.project().crs() if context.project() else src_crs
            if not src_crs.isValid():
                if not target.isValid():
                    raise QgsProcessingException(self.tr(
                        "Origin '{value}' has no CRS: type it with its CRS in square brackets, "
                        "e.g. '320000.0,3956100.0 [EPSG:32654]', or set the output CRS (the "
                        "origin is then taken in it).").format(value=parameters.get(self.ORIGIN)))
                src_crs = target
            pt = self.parameterAsPoint(parameters, self.ORIGIN, context)
            points = [(pt.x(), pt.y())]
        else:
            name = self.CORNERS if kind == "corners" else self.BOUNDARY
            source = self.parameterAsSource(parameters, name, context)
            if source is None:
                raise QgsProcessingException(
                    self.tr("Field corners: give a point layer with the four corners of the "
                            "field (or choose another anchor).") if kind == "corners" else
                    self.tr("Field boundary: give a polygon layer with the field's outline "
                            "(or choose another anchor)."))
            src_crs = source.sourceCrs()
            points = []
            for feat in source.getFeatures():
                g = feat.geometry()
                if g.isNull():
                    continue
                if kind == "corners":
                    points += [(p.x(), p.y()) for p in
                               (g.asMultiPoint() if g.isMultipart() else [g.asPoint()])]
                else:
                    polys = g.asMultiPolygon() if g.isMultipart() else [g.asPolygon()]
                    points += [(p.x(), p.y()) for poly in polys for ring in poly[:1] for p in ring]
            if kind == "corners" and len(points) != 4:
                raise QgsProcessingException(self.tr(
                    "Field corners: the layer '{layer}' has {n} points; exactly four are needed, "
                    "one per corner of the field.").format(layer=source.sourceName(), n=len(points)))
            if kind == "boundary" and len(points) < 3:
                raise QgsProcessingException(self.tr(
                    "Field boundary: the layer '{layer}' has no polygon.").format(
                        layer=source.sourceName()))
        out_crs = src_crs
        if target.isValid() and src_crs.isValid() and target != src_crs:
            tr = QgsCoordinateTransform(src_crs, target, context.transformContext())
            points = [(q.x(), q.y()) for q in (tr.transform(QgsPointXY(*p)) for p in points)]
            out_crs = target
        value = points[0] if kind == "origin" else (points if kind == "corners" else [points])
        return kind, value, out_crs

    def _field_book(self, parameters, context):
        source = self.parameterAsSource(parameters, self.FIELD_BOOK, context)
        if source is None:
            return None, ""
        names = source.fields().names()
        rows = []
        for feat in source.getFeatures():
            rows.append({n: (None if is_null(v) else v)
                         for n, v in zip(names, feat.attributes())})
        return rows, source.sourceName()

    def core_step(self, parameters, context, feedback):
        from ...core.plotgrid import (FieldBookJoin, GridAnchor, GridLayout, Numbering,
                                      create_plot_grid)

        kind, value, crs = self._anchor(parameters, context)
        book, book_name = self._field_book(parameters, context)
        num = lambda n: optional_number(self, parameters, n, context)  # noqa: E731
        text = lambda n: self.parameterAsString(parameters, n, context) or None  # noqa: E731
        anchor = GridAnchor(**{kind: value},
                            bearing=self.parameterAsDouble(parameters, self.BEARING, context),
                            tolerance=self.parameterAsDouble(parameters, self.TOLERANCE, context))
        layout = GridLayout(
            size_x=num(self.SIZE_X), size_y=num(self.SIZE_Y), gap_x=num(self.GAP_X),
            gap_y=num(self.GAP_Y), spacing_x=num(self.SPACING_X), spacing_y=num(self.SPACING_Y),
            blocks_x=self.parameterAsInt(parameters, self.BLOCKS_X, context),
            blocks_y=self.parameterAsInt(parameters, self.BLOCKS_Y, context),
            block_gap_x=num(self.BLOCK_GAP_X), block_gap_y=num(self.BLOCK_GAP_Y),
            buffer=self.parameterAsDouble(parameters, self.BUFFER, context))
        numbering = Numbering(
            order=ORDERS[self.parameterAsEnum(parameters, self.ORDER, context)][0],
            start=STARTS[self.parameterAsEnum(parameters, self.START, context)][0],
            start_id=self.parameterAsInt(parameters, self.START_ID, context),
            pattern=self.parameterAsString(parameters, self.PATTERN, context) or "{plot_no}")
        field_book = None if book is None else FieldBookJoin(
            book, join_by=JOINS[self.parameterAsEnum(parameters, self.JOIN_BY, context)][0],
            book_id=text(self.BOOK_ID), book_row=text(self.BOOK_ROW), book_col=text(self.BOOK_COL))
        return CoreStep(create_plot_grid, dict(
            crs=crs_string(crs), rows=self.parameterAsInt(parameters, self.ROWS, context),
            cols=self.parameterAsInt(parameters, self.COLS, context), anchor=anchor,
            layout=layout, numbering=numbering, field_book=field_book),
            dict(crs=crs, book_name=book_name))

    def write_outputs(self, parameters, context, feedback, step, result):
        grid, report = result
        crs, book_name = step.inputs["crs"], step.inputs["book_name"]
        for note in grid.notes:
            feedback.pushInfo(note)
        if report is not None:
            feedback.pushInfo(self.tr("Field book '{name}': {n} columns joined ({fields}).").format(
                name=book_name, n=len(report.fields), fields=", ".join(report.fields)))
            for line in report.messages():
                feedback.pushWarning(line)

        fields = QgsFields()
        fields.append(QgsField("plot_id", FieldType.QString))
        for name in ("plot_no", "row", "col", "block"):
            fields.append(QgsField(name, FieldType.Int))
        for name, values in grid.fields.items():
            fields.append(QgsField(name, qvariant_type(values)))
        sink, dest_id = self.parameterAsSink(parameters, self.OUTPUT, context, fields,
                                             WkbType.Polygon, crs)
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT))
        names = grid.field_names()
        for i in range(len(grid)):
            if i % 1000 == 0:
                if feedback.isCanceled():
                    break
                feedback.setProgress(100.0 * i / len(grid))
            feat = QgsFeature(fields)
            attrs = grid.attributes(i)
            feat.setAttributes([attrs[n] for n in names])
            feat.setGeometry(polygon([grid.corners[i]]))
            sink.addFeature(feat, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        presentation.present(
            self, context, dest_id, self.OUTPUT,
            grid_style(),
            self.tr("Plot grid {rows} × {cols}").format(rows=int(grid.row.max()),
                                                       cols=int(grid.col.max())))
        feedback.pushInfo(self.tr("{n} plots in {crs}.").format(n=len(grid), crs=crs.authid() or
                                                               crs.description()))
        feedback.setProgress(100)
        return {self.OUTPUT: dest_id}


def grid_style():
    """A new plot grid: blue outlines (not the yellow of the demo plots, so that a grid laid
    over existing plots stands apart), labelled with plot_id when zoomed in beyond 1:2000."""
    return presentation.outline_style("#3d8bff", 0.5, label='"plot_id"', label_scale=2000)
