"""Processing tool: Plot statistics from photos (easyidp:photostatistics)."""
import os

from qgis.core import (QgsCoordinateReferenceSystem,
                       QgsProcessingParameterBoolean, QgsProcessingParameterEnum,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFile,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterString, QgsProcessingParameterVectorLayer)

from .. import presentation
from ..compat import (FieldType, ProcessingFileParameterBehavior,
                      ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType, WkbType)
from ..parameters import optional_destination, optional_number, parse_percentiles
from ..photo_layers import backprojection_from_layer
from ..physical_values import add_value_parameters, value_parameters
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import dsm_parameter
from ..rois import add_roi_parameters, rois_parameter
from ..sinks import fields_of, write_features, write_roi_layer
from ..vertex_heights import add_height_parameters, height_source_parameter
from .base import CoreStep, EasyIDPAlgorithm, translatable

STATISTIC_CHOICES = ("mean", "median", "std")
INDEX_CHOICES = ("exg", "exgr", "vari", "gli", "ndvi", "ndre")


class PhotoStatisticsAlgorithm(EasyIDPAlgorithm):
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    BACKPROJECTION = "BACKPROJECTION"
    HEIGHT_SOURCE = "HEIGHT_SOURCE"
    DSM = "DSM"
    HEIGHT_FIELD = "HEIGHT_FIELD"
    GROUND_HEIGHT = "GROUND_HEIGHT"
    PHOTOS = "PHOTOS"
    OCCLUSION = "OCCLUSION"
    STATISTICS = "STATISTICS"
    PERCENTILES = "PERCENTILES"
    INDICES = "INDICES"
    COVER_THRESHOLD = "COVER_THRESHOLD"
    MIN_VISIBLE = "MIN_VISIBLE"
    MAX_IMAGES = "MAX_IMAGES"
    WEIGHTED = "WEIGHTED"
    BANDS = "BANDS"
    DISTORTION = "DISTORTION"
    VALUES = "VALUES"
    TEMPERATURE_PRESET = "TEMPERATURE_PRESET"
    TEMPERATURE_SCALE = "TEMPERATURE_SCALE"
    TEMPERATURE_OFFSET = "TEMPERATURE_OFFSET"
    UTC_OFFSET = "UTC_OFFSET"
    OUTPUT_VIEWS = "OUTPUT_VIEWS"
    OUTPUT = "OUTPUT"
    PREVIEW_FOLDER = "PREVIEW_FOLDER"

    NAME = "photostatistics"
    REQUIRES = ("tifffile", "imagecodecs", "skimage", "PIL")  # photos; Otsu; preview captions
    DISPLAY = "Plot statistics from photos"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Measures every ROI (plot) in every raw photo that sees it, and gives each ROI one "
        "robust value across its views. Raw photos have no ghosting or seamlines and true "
        "colour from near-nadir views.\n\n"
        "Inputs as Back-project ROIs: the ROI polygons, the photogrammetry project, the heights "
        "of the ROI vertices and a DSM; the backward projection runs here, unless its photo-pixel "
        "layer (the OUTPUT of Back-project ROIs) is given, which is then used as it is.\n\n"
        "Per ROI and photo, the pixels whose centre is inside the ROI's polygon (clipped to the "
        "frame) give: per band the mean, median, standard deviation and chosen percentiles, in "
        "the photo's own values (8-bit, 16-bit or float; never converted to 8-bit); the "
        "vegetation indices ExG, ExGR, VARI, GLI (red, green, blue) and NDVI, NDRE (for "
        "multispectral photos, name the bands, e.g. 'blue,green,red,rededge,nir'); the canopy "
        "cover (share of pixels whose NDVI, else ExG, is at or above the threshold: the one "
        "given, or Otsu's over all views); the pixel count and the GSD. With a DSM, pixels "
        "whose line of sight meets the surface outside the ROI (hidden by a tree, a neighbour, "
        "a wall) are left out and their share is reported.\n\n"
        "Across views, per ROI: the median of each statistic (score-weighted if asked), its "
        "MAD, minimum and maximum over the views used (visible share at least the minimum; "
        "the best ones by score when a maximum is set), their number, each view's deviation "
        "from its ROI's value and each ROI's largest (the disagreement; about 1 is typical for "
        "the field, several times more flags a shadow, wind, a bad pose). "
        "Oblique views see the sides of tall canopy, so cover and indices grow with the view "
        "angle: the default keeps the 3 best views.\n\n"
        "Values: as stored (the photos' own numbers), temperature in °C (FLIR radiometric JPEGs "
        "of the Zenmuse XT/XT2, Vue Pro R, Duo Pro R and FLIR handhelds, converted by the "
        "Planck curve with the photo's constants and object parameters, each of which can be "
        "overridden; or temperature TIFFs with a stated scale and offset; DJI R-JPEGs must be "
        "converted with DJI's tool first) or reflectance (MicaSense and DJI multispectral band "
        "files, from their irradiance sensor). The band files of one capture are one view: each "
        "band is measured through its own camera, one row per ROI × capture with a column per "
        "band, and indices come from the band means and medians of the same ROI. Temperature "
        "and reflectance put the "
        "unit in the column names (temp_c_mean, nir_refl_median); saturated pixels are left "
        "out. Each view also gets its photo's acquisition time and the sun's zenith, azimuth "
        "and phase angle (sun–plot–camera).\n\n"
        "Outputs: a table of every ROI × photo with its statistics; the ROIs with the "
        "across-view values; optionally one PNG per ROI with the views used side by side and "
        "their values.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_roi_parameters(self)
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterVectorLayer(
            self.BACKPROJECTION, self.tr("Back-projection (photo-pixel layer; empty: run it here)"),
            [ProcessingSourceType.VectorPolygon], optional=True))
        add_height_parameters(self)
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Photos folder (when the photos moved; matched by file name)"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        self.addParameter(QgsProcessingParameterBoolean(
            self.OCCLUSION, self.tr("Leave out pixels hidden by the DSM (when a DSM is given)"),
            True))
        self.addParameter(QgsProcessingParameterEnum(
            self.STATISTICS, self.tr("Statistics of every band and index"),
            [self.tr("Mean"), self.tr("Median"), self.tr("Standard deviation")],
            allowMultiple=True, defaultValue=[0, 1, 2]))
        self.addParameter(QgsProcessingParameterString(
            self.PERCENTILES, self.tr("Percentiles (comma-separated, 0–100; empty: none)"),
            defaultValue="5,95", optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.INDICES, self.tr("Vegetation indices (those the bands allow)"),
            ["ExG", "ExGR", "VARI", "GLI", "NDVI", "NDRE"], allowMultiple=True,
            defaultValue=list(range(len(INDEX_CHOICES)))))
        self.addParameter(QgsProcessingParameterNumber(
            self.COVER_THRESHOLD, self.tr("Cover threshold on NDVI or ExG (empty: Otsu's)"),
            ProcessingNumberParameterType.Double, optional=True, minValue=-3.0, maxValue=3.0))
        self.addParameter(QgsProcessingParameterNumber(
            self.MIN_VISIBLE, self.tr("Minimum visible share of a ROI in a view used"),
            ProcessingNumberParameterType.Double, 0.5, minValue=0.0, maxValue=1.0))
        self.addParameter(QgsProcessingParameterNumber(
            self.MAX_IMAGES, self.tr("Best views used per ROI (0 = all)"),
            ProcessingNumberParameterType.Integer, 3, minValue=0))
        self.addParameter(QgsProcessingParameterBoolean(
            self.WEIGHTED, self.tr("Weight the views by their score (weighted median)"), False))
        p = QgsProcessingParameterString(
            self.BANDS, self.tr("Band names of the photos (comma-separated)"),
            optional=True)
        p.setHelp(self.tr("Default: red,green,blue for 3 bands; e.g. blue,green,red,rededge,nir"))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = QgsProcessingParameterBoolean(
            self.DISTORTION, self.tr("Apply the lens distortion (off for undistorted photos)"), True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        add_value_parameters(self, translatable("Values measured"))
        p = QgsProcessingParameterNumber(
            self.UTC_OFFSET, self.tr("UTC offset of the photos' clock (hours)"),
            ProcessingNumberParameterType.Double, optional=True)
        p.setHelp(self.tr("For photos that do not state it (the sun's angles need UTC); "
                          "empty: none"))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_VIEWS, self.tr("Statistics of every ROI × photo"),
            ProcessingSourceType.Vector))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("ROIs with their across-view statistics"),
            ProcessingSourceType.VectorPolygon))
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.PREVIEW_FOLDER, self.tr("Preview per ROI (the views used, with their values)"),
            optional=True, createByDefault=False))
        self.add_overwrite_parameter()

    # --- running ----------------------------------------------------------------------------
    def core_step(self, parameters, context, feedback):
        from ...core.projection import roi_photo_statistics

        recon = open_project_parameter(self, parameters, context, feedback)
        source, rois, features = rois_parameter(self, parameters, context, feedback)
        dsm = dsm_parameter(self, parameters, context)
        occlusion = self.parameterAsBool(parameters, self.OCCLUSION, context)
        if occlusion and dsm is None:
            feedback.pushInfo(self.tr("No DSM given: hidden pixels are not left out."))
        distortion = self.parameterAsBool(parameters, self.DISTORTION, context)
        stats = [STATISTIC_CHOICES[k] for k in
                 self.parameterAsEnums(parameters, self.STATISTICS, context)]
        percentiles = parse_percentiles(self, self.parameterAsString(parameters, self.PERCENTILES,
                                                                      context))
        indices = [INDEX_CHOICES[k] for k in self.parameterAsEnums(parameters, self.INDICES, context)]
        bands_text = self.parameterAsString(parameters, self.BANDS, context)
        bands = [b.strip() for b in bands_text.split(",") if b.strip()] if bands_text else None
        previews = optional_destination(self, parameters, self.PREVIEW_FOLDER, context)

        layer = self.parameterAsVectorLayer(parameters, self.BACKPROJECTION, context)
        backprojection = heights = None
        if layer is not None:
            backprojection = backprojection_from_layer(layer, self.tr("Back-projection"),
                                                       rois.names, recon, feedback)
            backprojection.settings["distortion"] = distortion
            feedback.pushInfo(self.tr("Back-projection from the layer '{name}': {k} ROI × photo "
                                      "pairs.").format(name=layer.name(), k=len(backprojection)))
        else:
            heights = height_source_parameter(self, parameters, context, features, dsm)
            feedback.pushInfo(self.tr("Projecting {n} ROIs into {m} photos ({h})").format(
                n=len(rois), m=len(recon.aligned_cameras), h=heights.describe()))
        return CoreStep(roi_photo_statistics, dict(
            rois=rois, recon=recon, photos_folder=self.parameterAsFile(parameters, self.PHOTOS, context)
            or None, backprojection=backprojection, heights=heights, distortion=distortion,
            occlusion_dsm=dsm, occlusion=occlusion, bands=bands, statistics=stats,
            percentiles=percentiles, indices=indices,
            cover_threshold=optional_number(self, parameters, self.COVER_THRESHOLD, context),
            min_visible=self.parameterAsDouble(parameters, self.MIN_VISIBLE, context),
            max_views=self.parameterAsInt(parameters, self.MAX_IMAGES, context),
            weighted=self.parameterAsBool(parameters, self.WEIGHTED, context),
            previews_folder=previews, overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback, 0, 100), is_cancelled=feedback.isCanceled,
            **value_parameters(self, parameters, context),
            utc_offset=optional_number(self, parameters, self.UTC_OFFSET, context)),
            dict(source=source, features=features, previews=previews))

    def write_outputs(self, parameters, context, feedback, step, stats_result):
        source, features, previews = (step.inputs[k] for k in ("source", "features", "previews"))
        for note in stats_result.warnings:
            feedback.pushWarning(note)
        for note in stats_result.notes:
            feedback.pushInfo(note)
        for label, why in list(stats_result.skipped_photos.items())[:50]:
            feedback.pushWarning(self.tr("Photo {label} skipped: {why}").format(label=label, why=why))
        unused = [n for n, v in zip(stats_result.roi_names, stats_result.views) if not v]
        if unused:
            feedback.pushWarning(self.tr("{n} ROI(s) without a view used: {names}").format(
                n=len(unused), names=", ".join(unused[:20]) + (" …" if len(unused) > 20 else "")))

        outputs = {self.OUTPUT_VIEWS: self._write_views(parameters, context, stats_result),
                   self.OUTPUT: self._write_rois(parameters, context, source, features,
                                                 stats_result)}
        project = os.path.basename(
            self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        shown = shown_field(stats_result.roi_fields())
        presentation.present(
            self, context, outputs[self.OUTPUT], self.OUTPUT,
            presentation.graduated_style(shown, decimals=2, ramp="Viridis") if shown else None,
            self.tr("{rois}: plot statistics from the photos of {project}").format(
                rois=source.sourceName(), project=project))
        presentation.present(
            self, context, outputs[self.OUTPUT_VIEWS], self.OUTPUT_VIEWS, None,
            self.tr("{rois}: statistics per photo").format(rois=source.sourceName()))
        if previews:
            outputs[self.PREVIEW_FOLDER] = previews
        feedback.setProgress(100)
        feedback.pushInfo(stats_result.summary())
        return outputs

    def _write_views(self, parameters, context, st):
        kinds = {"roi": FieldType.QString, "photo": FieldType.QString, "rank": FieldType.Int,
                 "polygon_pixels": FieldType.LongLong, "pixels": FieldType.LongLong,
                 "used": FieldType.Bool, "why": FieldType.QString, "acquired": FieldType.QString}
        names = list(st.VIEW_FIELDS) + list(st.columns)
        return write_features(self, parameters, self.OUTPUT_VIEWS, context,
                              fields_of((n, kinds.get(n, FieldType.Double)) for n in names),
                              WkbType.NoGeometry, QgsCoordinateReferenceSystem(),
                              (([row[n] for n in names], None) for row in st.view_rows()))

    def _write_rois(self, parameters, context, source, features, st):
        names = st.roi_fields()
        return write_roi_layer(
            self, parameters, self.OUTPUT, context, source,
            [(feat, [row[n] for n in names]) for feat, row in zip(features, st.roi_rows())],
            [(n, FieldType.Int if n == "views" else FieldType.Double) for n in names])


def shown_field(names):
    """The field the ROI layer is coloured by: the canopy cover, else mean ExG or NDVI."""
    return presentation.first_field(names, ["cover", "exg_mean", "ndvi_mean", "exg_median",
                                            "ndvi_median", "temp_c_median", "temp_c_mean"])
