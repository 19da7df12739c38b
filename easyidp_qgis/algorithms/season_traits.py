"""Processing tool: Plot traits over a season (easyidp:seasontraits)."""
import os

from qgis.core import (QgsCoordinateReferenceSystem, QgsProcessingException,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFeatureSource, QgsProcessingParameterField,
                       QgsProcessingParameterFileDestination,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString,
                       QgsProcessingParameterVectorLayer)

from .. import presentation
from ..compat import (FieldType, ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType, WkbType)
from ..crs import crs_string
from ..layer_files import layer_file, uri_file
from ..outputs import scratch_context
from ..parameters import optional_number, parse_percentiles
from ..progress import feedback_progress
from ..rasters import geotiff_source
from ..rois import rois_parameter
from ..sinks import fields_of, write_features, write_roi_layer
from ..values import plain_value, value_text
from .base import CoreStep, EasyIDPAlgorithm

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
    # rasters, clouds; Otsu; growth curves
    REQUIRES = ("tifffile", "imagecodecs", "laspy", "lazrs", "plyfile", "skimage", "matplotlib")
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
            self.GROUND, self.tr("Ground: bare-soil DSM or DTM of the season"),
            optional=True))
        p = self.decimals(QgsProcessingParameterNumber(
            self.GROUND_PERCENTILE,
            self.tr("Ground without a DTM: percentile of the lowest heights"),
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
            self.tr("Cover threshold on the vegetation index (empty: Otsu)"),
            ProcessingNumberParameterType.Double, optional=True, minValue=-1.0, maxValue=2.0), 3)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterNumber(
            self.WORKERS, self.tr("Worker processes"), ProcessingNumberParameterType.Integer,
            defaultValue=min(os.cpu_count() or 1, 8), minValue=1, maxValue=256))
        p = QgsProcessingParameterString(
            self.DASK_SCHEDULER,
            self.tr("Dask scheduler (tcp://host:port or 'local')"),
            optional=True)
        p.setHelp(self.tr("Empty: processes on this computer"))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.CROPS, self.tr("Crops per date (folder)"), optional=True,
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
    def core_step(self, parameters, context, feedback):
        from ...core.season import check_season_outputs, run_season

        table_layer = self.parameterAsVectorLayer(parameters, self.SURVEYS, context)
        if table_layer is None:
            raise QgsProcessingException(self.tr("Survey table: no table given, or it could not "
                                                 "be loaded."))
        table = _survey_table(table_layer, context)
        source, rois, features = rois_parameter(self, parameters, context, feedback)
        traits = [TRAITS[i] for i in self.parameterAsEnums(parameters, self.TRAITS, context)]
        if not traits:
            raise QgsProcessingException(self.tr("Traits: choose at least one."))
        ground_layer = self.parameterAsRasterLayer(parameters, self.GROUND, context)
        ground = geotiff_source(ground_layer, self.tr("Ground")) if ground_layer else None
        scheduler = (self.parameterAsString(parameters, self.DASK_SCHEDULER, context) or "").strip()
        for problem in table.problems:
            feedback.pushWarning(self.tr("Survey {p}").format(p=problem))
        check_season_outputs(table, self._output_files(parameters, context), ground,
                             also=[layer_file(table_layer)])
        feedback.pushInfo(self.tr("{n} surveys, {r} ROIs, traits: {t}").format(
            n=len(table.surveys), r=len(rois), t=", ".join(traits)))
        return CoreStep(run_season, dict(
            table=table, rois=rois, traits=traits,
            percentiles=parse_percentiles(self, self.parameterAsString(
                parameters, self.PERCENTILES, context), default=(50.0, 95.0, 99.0)),
            ground=ground, ground_source_crs=crs_string(ground_layer.crs()) if ground_layer else None,
            ground_percentile=self.parameterAsDouble(parameters, self.GROUND_PERCENTILE, context),
            cover_threshold=optional_number(self, parameters, self.COVER_THRESHOLD, context),
            crops=self.parameterAsString(parameters, self.CROPS, context) or None,
            overwrite=self.overwrite(parameters, context),
            workers=self.parameterAsInt(parameters, self.WORKERS, context),
            scheduler=scheduler if scheduler and scheduler.lower() != "local" else None,
            local_cluster=scheduler.lower() == "local",
            progress=feedback_progress(feedback, 5, 95), is_cancelled=feedback.isCanceled,
            log=feedback.pushInfo),
            dict(source=source, features=features, table=table))

    def write_outputs(self, parameters, context, feedback, step, result):
        from ...core.season import plot_growth_curves
        source, features, table = (step.inputs[k] for k in ("source", "features", "table"))
        rois, crops = step.kwargs["rois"], step.kwargs["crops"]
        for problem in result.problems[len(table.problems):]:
            feedback.pushWarning(self.tr("Left out: {p}").format(p=problem))
        for note in result.notes:
            feedback.pushInfo(note)
        if not result.rows:
            raise QgsProcessingException(self.tr(
                "No trait could be computed: every survey row was left out (see the messages "
                "above)."))

        out = {self.OUTPUT_TABLE: write_features(
                   self, parameters, self.OUTPUT_TABLE, context,
                   fields_of((("roi", FieldType.QString), ("date", FieldType.QString),
                              ("trait", FieldType.QString), ("value", FieldType.Double))),
                   WkbType.NoGeometry, QgsCoordinateReferenceSystem(),
                   ((row, None) for row in result.rows)),
               self.OUTPUT_LAYER: write_roi_layer(
                   self, parameters, self.OUTPUT_LAYER, context, source,
                   [(feat, [date] + [values.get(t) for t in result.traits])
                    for feat, (date, values) in zip(features, result.latest())],
                   [("date", FieldType.QString)] + [(t, FieldType.Double) for t in result.traits],
                   replace=True)}
        curves = self.parameterAsFileOutput(parameters, self.OUTPUT_CURVES, context)
        if curves:
            groups = None
            group_field = self.parameterAsString(parameters, self.GROUP_FIELD, context)
            if group_field:
                groups = {r.name: value_text(f[group_field]) for r, f in zip(rois, features)}
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

    def _output_files(self, parameters, context):
        """The files of the outputs (the two tables when written to files, and the curves)."""
        scratch = scratch_context(context)
        files = [uri_file(self.parameterAsOutputLayer(parameters, name, scratch) or "")
                 for name in (self.OUTPUT_TABLE, self.OUTPUT_LAYER)]
        files = [f for f in files if os.path.splitext(f)[1]]
        return files + [self.parameterAsFileOutput(parameters, self.OUTPUT_CURVES, context)]

    def _present(self, out, result, context, source):
        """Name the outputs that are loaded; colour the wide layer by height (graduated)."""
        from ...core.season import main_trait
        attr = main_trait([t for t in result.traits if "height" in t])
        presentation.present(
            self, context, out[self.OUTPUT_LAYER], self.OUTPUT_LAYER,
            presentation.graduated_style(attr, decimals=2, ramp="Viridis") if attr else None,
            self.tr("{rois}: latest traits").format(rois=source.sourceName()))
        presentation.present(self, context, out[self.OUTPUT_TABLE], self.OUTPUT_TABLE, None,
                             self.tr("{rois}: traits per date").format(rois=source.sourceName()))


def _survey_table(layer, context):
    """The surveys of a table layer. A CSV file is read as text by the core (QGIS's type
    detection reads a path like '2024-06-01/dsm.tif' as a date); any other table through its
    features (dates as ISO text, NULL as None), with relative paths taken from its file's
    folder or the project's."""
    from ...core.season import read_survey_table, surveys_from_rows
    path = layer_file(layer)
    path = os.path.abspath(path) if path and os.path.isfile(path) else ""
    if path and os.path.splitext(path)[1].lower() in (".csv", ".txt", ".tsv") and \
            not layer.subsetString():
        return read_survey_table(path)
    names = layer.fields().names()
    rows = [dict(zip(names, map(plain_value, f.attributes()))) for f in layer.getFeatures()]
    return surveys_from_rows(rows, os.path.dirname(path) if path else _project_folder(context),
                             label=layer.name())


def _project_folder(context) -> str:
    project = context.project()
    if project is not None and project.homePath():
        return project.homePath()
    return os.getcwd()
