"""Processing tool: Plot traits over a season (easyidp:seasontraits)."""
import os

from qgis.core import (QgsFeature, QgsField, QgsFields, QgsProcessingException,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFeatureSource, QgsProcessingParameterField,
                       QgsProcessingParameterFileDestination,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString,
                       QgsProcessingParameterVectorLayer, QgsProviderRegistry)
from qgis.PyQt.QtCore import QDate, QDateTime

from .. import presentation
from ..compat import (DateFormat, FeatureSinkFlag, FieldType, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType, WkbType)
from ..layers import (crs_string, geotiff_source, parse_percentiles, rois_parameter)
from ..outputs import close_sink
from .base import EasyIDPAlgorithm

TRAITS = ["height", "cover", "bands", "index", "cloud"]


class SeasonTraits(EasyIDPAlgorithm):
    SURVEYS = "SURVEYS"
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    GROUP_FIELD = "GROUP_FIELD"
    TRAITS = "TRAITS"
    GROUND = "GROUND"
    GROUND_PERCENTILE = "GROUND_PERCENTILE"
    PERCENTILES = "PERCENTILES"
    COVER_THRESHOLD = "COVER_THRESHOLD"
    WORKERS = "WORKERS"
    DASK_SCHEDULER = "DASK_SCHEDULER"
    CROPS = "CROPS"
    OUTPUT_TABLE = "OUTPUT_TABLE"
    OUTPUT_LAYER = "OUTPUT_LAYER"
    OUTPUT_CURVES = "OUTPUT_CURVES"

    NAME = "seasontraits"
    DISPLAY = "Plot traits over a season"
    GROUP = "Time series"
    GROUP_ID = "timeseries"
    HELP = (
        "Traits of every ROI (plot, tree) on every date of a season of surveys: plant height from "
        "the DSMs, canopy cover, band means and a vegetation index from the orthomosaics, heights "
        "from the point clouds. Each file is read once for all ROIs; the files are shared out to "
        "worker processes on this computer, or to a Dask cluster.\n\n"
        "Survey table: a CSV file or a table layer with the columns date (YYYY-MM-DD), "
        "orthomosaic, dsm, point_cloud and project (file paths, absolute or relative to the "
        "table's folder; empty cells allowed); optional: bands (the orthomosaic's band names in "
        "order, e.g. blue,green,red,rededge,nir: NDVI needs red and nir) and crs (for files "
        "without one, e.g. PLY). Rows with a missing file, an unreadable raster or a CRS that "
        "cannot be related to the ROIs are reported by row and left out; the rest completes. The "
        "project column is read but not used by the traits yet.\n\n"
        "Traits: height_pNN (percentiles of the DSM above the ground, metres); cover (share of "
        "the ROI whose vegetation index is above the threshold, 0-1; Otsu's automatic threshold "
        "per orthomosaic, or a given one); exg (excess green, RGB) or ndvi (named bands); "
        "mean_<band> (band means); cloud_points and cloud_height_pNN (point clouds).\n\n"
        "Ground: a bare-soil DSM or DTM of the season (a flight before emergence): a plane is "
        "fitted to it under each ROI. Without one, each ROI's ground is the plane through the "
        "lowest heights (the given percentile) in a 3 × 3 grid over it, which needs bare soil "
        "between the plants.\n\n"
        "Workers: processes on this computer. Dask scheduler (advanced): tcp://host:8786 to run on "
        "a Dask cluster (the files must be at the same paths on every worker), or 'local' for a "
        "Dask cluster of 'Workers' processes on this computer.\n\n"
        "Outputs: the long table (roi, date, trait, value); the ROIs with the traits of their "
        "latest date (styled by height); growth curves as a PNG (a panel per ROI, or per group "
        "when there are many ROIs and a group field); optionally the crops, in "
        "<date>/<orthomosaic|dsm|point_cloud>/ folders.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterVectorLayer(
            self.SURVEYS, self.tr("Survey table (CSV file or table layer)"),
            [ProcessingSourceType.Vector]))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.ROIS, self.tr("ROIs (polygons)"), [ProcessingSourceType.VectorPolygon]))
        self.addParameter(QgsProcessingParameterField(
            self.NAME_FIELD, self.tr("Name field (unique; default: feature id)"),
            parentLayerParameterName=self.ROIS, optional=True))
        self.addParameter(QgsProcessingParameterField(
            self.GROUP_FIELD, self.tr("Group field (treatment, variety: colours the curves)"),
            parentLayerParameterName=self.ROIS, optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.TRAITS, self.tr("Traits"),
            options=[self.tr("Height from the DSM"), self.tr("Canopy cover"),
                     self.tr("Band means"), self.tr("Vegetation index (ExG or NDVI)"),
                     self.tr("Heights from the point cloud")],
            allowMultiple=True, defaultValue=list(range(len(TRAITS)))))
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.GROUND, self.tr("Ground: bare-soil DSM or DTM of the season (optional)"),
            optional=True))
        p = self.decimals(QgsProcessingParameterNumber(
            self.GROUND_PERCENTILE,
            self.tr("Ground without a DTM: percentile of each ROI's lowest heights"),
            ProcessingNumberParameterType.Double, defaultValue=2.0, minValue=0.0, maxValue=50.0), 1)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = QgsProcessingParameterString(
            self.PERCENTILES, self.tr("Height percentiles (comma separated)"),
            defaultValue="50,95,99", optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = self.decimals(QgsProcessingParameterNumber(
            self.COVER_THRESHOLD,
            self.tr("Cover threshold on the vegetation index (empty: Otsu per orthomosaic)"),
            ProcessingNumberParameterType.Double, optional=True, minValue=-1.0, maxValue=2.0), 3)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterNumber(
            self.WORKERS, self.tr("Worker processes"), ProcessingNumberParameterType.Integer,
            defaultValue=min(os.cpu_count() or 1, 8), minValue=1, maxValue=256))
        p = QgsProcessingParameterString(
            self.DASK_SCHEDULER,
            self.tr("Dask scheduler (tcp://host:port, or 'local'; empty: processes here)"),
            optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.CROPS, self.tr("Crops per date (optional folder)"), optional=True,
            createByDefault=False))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_TABLE, self.tr("Traits per ROI and date (long table)"),
            ProcessingSourceType.Vector))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_LAYER, self.tr("ROIs with their latest traits"),
            ProcessingSourceType.VectorPolygon))
        self.addParameter(QgsProcessingParameterFileDestination(
            self.OUTPUT_CURVES, self.tr("Growth curves (PNG)"), self.tr("PNG files (*.png)"),
            optional=True, createByDefault=True))
        self.add_overwrite_parameter()

    # ---- run --------------------------------------------------------------------------------
    def run_tool(self, parameters, context, feedback):
        from ...core.season import plot_growth_curves, run_season

        table_layer = self.parameterAsVectorLayer(parameters, self.SURVEYS, context)
        if table_layer is None:
            raise QgsProcessingException(self.tr("Survey table: no table given, or it could not "
                                                 "be loaded."))
        table = _survey_table(table_layer, context)
        group_field = self.parameterAsString(parameters, self.GROUP_FIELD, context)
        source, rois, features = rois_parameter(self, parameters, context, feedback)
        traits = [TRAITS[i] for i in self.parameterAsEnums(parameters, self.TRAITS, context)]
        if not traits:
            raise QgsProcessingException(self.tr("Traits: choose at least one."))
        ground_layer = self.parameterAsRasterLayer(parameters, self.GROUND, context)
        ground = geotiff_source(ground_layer, self.tr("Ground")) if ground_layer else None
        threshold = None
        if parameters.get(self.COVER_THRESHOLD) not in (None, ""):
            threshold = self.parameterAsDouble(parameters, self.COVER_THRESHOLD, context)
        scheduler = (self.parameterAsString(parameters, self.DASK_SCHEDULER, context) or "").strip()
        crops = self.parameterAsString(parameters, self.CROPS, context) or None
        workers = self.parameterAsInt(parameters, self.WORKERS, context)
        for problem in table.problems:
            feedback.pushWarning(self.tr("Survey {p}").format(p=problem))
        self._check_outputs(parameters, context, table, ground)
        feedback.pushInfo(self.tr("{n} surveys, {r} ROIs, traits: {t}").format(
            n=len(table.surveys), r=len(rois), t=", ".join(traits)))

        result = run_season(
            table, rois, traits=traits,
            percentiles=parse_percentiles(self, self.parameterAsString(
                parameters, self.PERCENTILES, context), default=(50.0, 95.0, 99.0)),
            ground=ground, ground_crs=crs_string(ground_layer.crs()) if ground_layer else None,
            ground_percentile=self.parameterAsDouble(parameters, self.GROUND_PERCENTILE, context),
            cover_threshold=threshold, crops=crops, overwrite=self.overwrite(parameters, context),
            workers=workers,
            scheduler=scheduler if scheduler and scheduler.lower() != "local" else None,
            local_cluster=scheduler.lower() == "local",
            progress=lambda p: feedback.setProgress(5 + 0.9 * p),
            is_cancelled=feedback.isCanceled, log=feedback.pushInfo)
        for problem in result.problems[len(table.problems):]:
            feedback.pushWarning(self.tr("Left out: {p}").format(p=problem))
        for note in result.notes:
            feedback.pushInfo(note)
        if not result.rows:
            raise QgsProcessingException(self.tr(
                "No trait could be computed: every survey row was left out (see the messages "
                "above)."))

        out = {self.OUTPUT_TABLE: self._long_table(result, parameters, context),
               self.OUTPUT_LAYER: self._wide_layer(result, source, features, parameters, context)}
        curves = self.parameterAsFileOutput(parameters, self.OUTPUT_CURVES, context)
        if curves:
            groups = None
            if group_field:
                groups = {r.name: _value_text(f[group_field]) for r, f in zip(rois, features)}
            plot_growth_curves(result, curves, groups=groups)
            out[self.OUTPUT_CURVES] = curves
        if crops:
            out[self.CROPS] = crops
        self._present(out, result, context, source)
        feedback.setProgress(100)
        feedback.pushInfo(self.tr("{v} values of {k} traits for {r} ROIs on {d} dates in {s:.0f} s "
                                  "({e}); {p} rows or files left out.").format(
            v=len(result.rows), k=len(result.traits), r=len(rois), d=len(result.dates),
            s=result.seconds, e=result.executor, p=len(result.problems)))
        return out

    def _check_outputs(self, parameters, context, table, ground):
        """Refuse output files that are inputs (the table, a raster, a cloud, the ground)."""
        from ...core.files import check_not_inputs
        inputs = [p for p in [table.source, ground, _source_path_of(parameters, self.SURVEYS,
                                                                      self, context)] if p]
        inputs += [p for s in table.surveys for p in (*s.files().values(), s.project) if p]
        from ..outputs import scratch_context
        scratch = scratch_context(context)
        for name in (self.OUTPUT_TABLE, self.OUTPUT_LAYER):
            dest = self.parameterAsOutputLayer(parameters, name, scratch) or ""
            path = dest.split("|")[0]
            if path.startswith("ogr:"):
                continue
            if path and os.path.splitext(path)[1]:
                check_not_inputs(path, inputs)
        curves = self.parameterAsFileOutput(parameters, self.OUTPUT_CURVES, context)
        if curves:
            check_not_inputs(curves, inputs)

    def _long_table(self, result, parameters, context):
        fields = QgsFields()
        for name, kind in (("roi", FieldType.QString), ("date", FieldType.QString),
                           ("trait", FieldType.QString), ("value", FieldType.Double)):
            fields.append(QgsField(name, kind))
        sink, dest = self.parameterAsSink(parameters, self.OUTPUT_TABLE, context, fields,
                                          WkbType.NoGeometry)
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT_TABLE))
        for row in result.rows:
            f = QgsFeature(fields)
            f.setAttributes(list(row))
            sink.addFeature(f, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        return dest

    def _wide_layer(self, result, source, features, parameters, context):
        new = {"date", *result.traits}
        kept = [i for i, f in enumerate(source.fields()) if f.name().lower() not in
                {n.lower() for n in new}]
        fields = QgsFields()
        for i in kept:
            fields.append(source.fields().at(i))
        fields.append(QgsField("date", FieldType.QString))
        for t in result.traits:
            fields.append(QgsField(t, FieldType.Double))
        sink, dest = self.parameterAsSink(parameters, self.OUTPUT_LAYER, context, fields,
                                          source.wkbType(), source.sourceCrs())
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT_LAYER))
        for feat, (date, values) in zip(features, result.latest()):
            attrs = feat.attributes()
            f = QgsFeature(fields)
            f.setAttributes([attrs[i] for i in kept] + [date] +
                            [values.get(t) for t in result.traits])
            f.setGeometry(feat.geometry())
            sink.addFeature(f, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        return dest

    def _present(self, out, result, context, source):
        """Name the outputs that are loaded; colour the wide layer by height (graduated)."""
        from ...core.season.curves import main_trait
        attr = main_trait([t for t in result.traits if "height" in t])
        presentation.present(
            self, context, out[self.OUTPUT_LAYER], self.OUTPUT_LAYER,
            presentation.graduated_style(attr, decimals=2, ramp="Viridis") if attr else None,
            self.tr("{rois}: latest traits").format(rois=source.sourceName()))
        presentation.present(self, context, out[self.OUTPUT_TABLE], self.OUTPUT_TABLE, None,
                             self.tr("{rois}: traits per date").format(rois=source.sourceName()))


def _value_text(v) -> str:
    if isinstance(v, (QDate, QDateTime)):
        return v.toString(DateFormat.ISODate)
    return "" if v is None or str(v) == "NULL" else str(v)


def _survey_table(layer, context):
    """The surveys of a table layer. A CSV file is read as text by the core (QGIS's type
    detection reads a path like '2024-06-01/dsm.tif' as a date); any other table through its
    features, with relative paths taken from its file's folder or the project's."""
    from ...core.season import read_survey_table, surveys_from_rows
    path = _source_path(layer)
    if path and os.path.splitext(path)[1].lower() in (".csv", ".txt", ".tsv") and \
            not layer.subsetString():
        return read_survey_table(path)
    return surveys_from_rows(_rows(layer), os.path.dirname(path) if path else
                             _project_folder(context), label=layer.name())


def _rows(layer):
    """The table's features as {field name: value} dicts (dates as ISO text, NULL as None)."""
    names = layer.fields().names()
    rows = []
    for f in layer.getFeatures():
        rows.append({n: (_value_text(v) if isinstance(v, (QDate, QDateTime)) else
                         None if v is None or str(v) == "NULL" else v)
                     for n, v in zip(names, f.attributes())})
    return rows


def _source_path(layer) -> str:
    """The file behind a layer ('' when there is none)."""
    parts = QgsProviderRegistry.instance().decodeUri(layer.providerType(), layer.source())
    path = parts.get("path") or ""
    if path.startswith("file://"):
        from urllib.parse import unquote, urlparse
        path = unquote(urlparse(path).path)
    return os.path.abspath(path) if path and os.path.isfile(path) else ""


def _source_path_of(parameters, name, alg, context) -> str:
    layer = alg.parameterAsVectorLayer(parameters, name, context)
    return _source_path(layer) if layer is not None else ""


def _project_folder(context) -> str:
    project = context.project()
    if project is not None and project.homePath():
        return project.homePath()
    return os.getcwd()
