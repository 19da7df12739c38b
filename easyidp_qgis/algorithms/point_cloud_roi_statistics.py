"""Processing tool: Point cloud statistics per ROI (easyidp:pointcloudroistatistics)."""
import math
import os

from qgis.core import (QgsProcessingException,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterLayer,
                       QgsProcessingParameterString)

from .. import presentation
from ..compat import (FieldType, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType)
from ..crs import qgis_crs
from ..parameters import add_z_range_parameters, optional_number, parse_percentiles, z_range
from ..point_clouds import add_point_cloud_parameters, read_point_cloud_parameter
from ..progress import feedback_progress
from ..rasters import dsm_ground
from ..rois import rois_parameter
from ..sinks import write_roi_layer
from .base import CoreStep, EasyIDPAlgorithm

FIXED_FIELDS = [("count", FieldType.LongLong), ("density", FieldType.Double),
                ("z_min", FieldType.Double), ("z_mean", FieldType.Double), ("z_max", FieldType.Double),
                ("ground", FieldType.Double), ("h_mean", FieldType.Double), ("h_max", FieldType.Double)]


def percentile_field(q: float) -> str:
    """The attribute name of a height percentile: h_p95, h_p99_5."""
    return f"h_p{q:g}".replace(".", "_")


class PointCloudROIStatistics(EasyIDPAlgorithm):
    INPUT = "INPUT"
    INPUT_CRS = "INPUT_CRS"
    ROIS = "ROIS"
    GROUND_DSM = "GROUND_DSM"
    GROUND_HEIGHT = "GROUND_HEIGHT"
    GROUND_PERCENTILE = "GROUND_PERCENTILE"
    PERCENTILES = "PERCENTILES"
    Z_MIN = "Z_MIN"
    Z_MAX = "Z_MAX"
    OUTPUT = "OUTPUT"

    NAME = "pointcloudroistatistics"
    REQUIRES = ("tifffile", "imagecodecs", "laspy", "lazrs", "plyfile")  # the DSM, the cloud
    DISPLAY = "Point cloud statistics per ROI"
    GROUP = "Heights"
    GROUP_ID = "heights"
    HELP = (
        "For every ROI (plot, tree, plant polygon), the points of a point cloud (.las, .laz or "
        ".ply) inside it and their heights above the ground: canopy height, its percentiles and "
        "the point density, e.g. for plant height or biomass models.\n\n"
        "The result is the ROI layer with its attributes and: count (points inside), density "
        "(points per square unit of the cloud's CRS: per m² for a cloud in metres), z_min, "
        "z_mean, z_max (the points' Z), ground (the mean ground Z under the points), h_mean, "
        "h_max and h_pNN (height above the ground: Z minus ground) for each height percentile "
        "asked (default 5, 50, 95, 99; p99 is a robust canopy top).\n\n"
        "Ground: a DSM/DTM raster sampled under every point (a bare-soil DSM flown before "
        "emergence, or a DTM); or a single ground height; or, with neither, each ROI's own "
        "lowest points: the given percentile of its Z (advanced, default 1). The raster and the "
        "height must be in the cloud's Z units and vertical reference.\n\n"
        "LAS/LAZ files carry their CRS; a PLY file has none, so give the 'Point cloud CRS' for it "
        "(and for a LAS file without a CRS). ROIs in another CRS are reprojected. ROIs without "
        "any point are named in the log; their count and density are 0 and their Z and heights "
        "empty (NULL), never 0.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_point_cloud_parameters(self)
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.ROIS, self.tr("ROIs (polygons)"), [ProcessingSourceType.VectorPolygon]))
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.GROUND_DSM, self.tr("Ground: DSM or DTM raster (GeoTIFF)"), optional=True))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.GROUND_HEIGHT, self.tr("Ground: one height for all ROIs (cloud Z units)"),
            ProcessingNumberParameterType.Double, optional=True), 3))
        p = self.decimals(QgsProcessingParameterNumber(
            self.GROUND_PERCENTILE,
            self.tr("Ground otherwise: percentile of each ROI's Z"),
            ProcessingNumberParameterType.Double, defaultValue=1.0, minValue=0.0, maxValue=100.0), 1)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterString(
            self.PERCENTILES, self.tr("Height percentiles (comma separated)"),
            defaultValue="5,50,95,99", optional=True))
        add_z_range_parameters(self)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("ROIs with point cloud statistics"),
            ProcessingSourceType.VectorPolygon))
        self.add_overwrite_parameter()

    def core_step(self, parameters, context, feedback):
        from ...core.pointcloud import canopy_summary

        percentiles = parse_percentiles(self, self.parameterAsString(parameters, self.PERCENTILES,
                                                                     context))
        cloud = read_point_cloud_parameter(self, parameters, context, feedback)
        source, rois, features = rois_parameter(self, parameters, context, feedback,
                                                qgis_crs(cloud.crs))
        z_min, z_max = z_range(self, parameters, context)
        layer = self.parameterAsRasterLayer(parameters, self.GROUND_DSM, context)
        height = optional_number(self, parameters, self.GROUND_HEIGHT, context)
        if layer is not None and height is not None:
            raise QgsProcessingException(self.tr(
                "Ground: give either a DSM/DTM raster or one ground height, not both."))
        if layer is not None:
            ground = dsm_ground(layer, self.tr("Ground DSM/DTM"), cloud.crs)
            feedback.pushInfo(self.tr("Ground: the raster {name} under every point.").format(
                                  name=layer.name()))
        elif height is not None:
            ground = height
            feedback.pushInfo(self.tr("Ground: {height:g} for every ROI.").format(height=height))
        else:
            ground = None
        ground_pct = self.parameterAsDouble(parameters, self.GROUND_PERCENTILE, context)
        if ground is None:
            feedback.pushInfo(self.tr("Ground: percentile {ground_pct:g} of each ROI's Z.").format(
                                  ground_pct=ground_pct))

        return CoreStep(canopy_summary, dict(
            cloud=cloud, rois=rois, ground=ground, percentiles=percentiles,
            ground_percentile=ground_pct, z_min=z_min, z_max=z_max,
            progress=feedback_progress(feedback, 5, 95), is_cancelled=feedback.isCanceled),
            dict(layer=layer, source=source, features=features))

    def write_outputs(self, parameters, context, feedback, step, summary):
        layer, source, features = (step.inputs[k] for k in ("layer", "source", "features"))
        cloud, rois, percentiles = (step.kwargs[k] for k in ("cloud", "rois", "percentiles"))
        stats = FIXED_FIELDS + [(percentile_field(q), FieldType.Double) for q in percentiles]
        keys = [name for name, _ in FIXED_FIELDS] + [f"h_p{q:g}" for q in percentiles]
        new = {name.lower() for name, _ in stats}
        if any(f.name().lower() in new for f in source.fields()):
            feedback.pushInfo(self.tr("The ROI layer's own fields with the names of the statistics "
                                      "are replaced by the new values."))
        empty = [roi.name for roi, row in zip(rois, summary) if not row["count"]]
        # before the sink exists: a run that fails leaves no output file behind
        if rois and len(empty) == len(rois):
            raise QgsProcessingException(self.tr("None of the {n_rois} ROIs contains a point of "
                                                 "the cloud: check that the ROIs and the cloud "
                                                 "are in the right CRS (set 'Point cloud CRS' if "
                                                 "the file has none or a wrong one) and the Z "
                                                 "range.").format(n_rois=len(rois)))
        dest_id = write_roi_layer(self, parameters, self.OUTPUT, context, source,
                                  [(feat, [_num(row[k]) for k in keys])
                                   for feat, row in zip(features, summary)], stats, replace=True)
        no_ground = sum(1 for row in summary if row["count"] and math.isnan(row["ground"]))
        if no_ground and layer is not None:
            feedback.pushWarning(self.tr(
                "The ground raster {name} has no data under the points of {n} of the {total} ROIs "
                "(outside it or nodata): their heights above ground are empty. Check that it "
                "covers the ROIs.").format(name=layer.name(), n=no_ground, total=len(rois)))
        if empty:
            feedback.pushWarning(self.tr(
                "{n} ROI(s) contain no point (outside the cloud, in a gap, or outside the Z "
                "range); their statistics are empty: feature id {ids}.").format(
                    n=len(empty), ids=", ".join(empty[:50]) + (" …" if len(empty) > 50 else "")))
        shown = height_field([name for name, _ in stats])
        presentation.present(
            self, context, dest_id, self.OUTPUT,
            presentation.graduated_style(shown, decimals=2, ramp="Viridis") if shown else None,
            self.tr("{rois}: point cloud heights of {cloud}").format(
                rois=source.sourceName(), cloud=os.path.basename(str(cloud.path))))
        feedback.setProgress(100)
        feedback.pushInfo(self.tr("Statistics of {n_rois} ROIs written, {n} with points{shown}.").format(
                              n_rois=len(rois), n=len(rois) - len(empty),
                              shown=self.tr(" (map colours: {field})").format(field=shown)
                              if shown else ""))
        return {self.OUTPUT: dest_id}


def height_field(names):
    """The height the map is coloured by: the canopy top h_p95 (else h_p99, the highest other
    percentile, or h_max)."""
    pct = sorted((n for n in names if n.startswith("h_p")),
                 key=lambda n: float(n[3:].replace("_", ".")), reverse=True)
    return presentation.first_field(names, ["h_p95", "h_p99"] + pct + ["h_max"])


def _num(v):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return None
    return int(v) if isinstance(v, int) else float(v)
