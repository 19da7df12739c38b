"""Processing tool: Orthorectify ROIs from raw photos (easyidp:orthorectifyrois)."""
import os

from qgis.core import (QgsProcessing, QgsProcessingContext, QgsProcessingOutputMultipleLayers,
                       QgsProcessingOutputNumber,
                       QgsProcessingParameterDefinition,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProcessingParameterFile,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString)

from ..layers import (add_project_parameters, crs_string, geotiff_source, open_project_parameter,
                     rois_from_source)
from .base import EasyIDPAlgorithm

SELECTIONS = ("best", "all", "photo")
MAX_LAYERS_TO_LOAD = 100


class OrthorectifyROIs(EasyIDPAlgorithm):
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    DSM = "DSM"
    PHOTOS = "PHOTOS"
    SELECTION = "SELECTION"
    PHOTO = "PHOTO"
    GSD = "GSD"
    OUTPUT_FOLDER = "OUTPUT_FOLDER"
    OUTPUT_FILES = "OUTPUT_FILES"
    WRITTEN = "WRITTEN"

    NAME = "orthorectifyrois"
    DISPLAY = "Orthorectify ROIs from raw photos"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Makes, for every ROI, a georeferenced image from a raw photo instead of the "
        "orthomosaic: sharper (no blending, ghosting or seamlines) and with true geometry. Each "
        "output pixel's ground point (its height from the DSM) is projected into the photo "
        "with the solved camera (lens distortion included) and the photo is sampled there "
        "(bilinear).\n\n"
        "Photos: 'best' takes the best-scored photo of each ROI (the backward projection's "
        "score: visible share, view angle, resolution, distance from the centre); 'all' writes "
        "one image per photo that sees the ROI; 'named photo' uses the photo given. Pixel size: "
        "the GSD given (DSM CRS units), or 0 for the photo's native resolution at the ROI.\n\n"
        "Output pixels outside the ROI, on DSM nodata, outside the photo, or hidden from the "
        "camera by the DSM (occlusion) are transparent (alpha 0). One GeoTIFF per ROI (and "
        "photo, for 'all') in the output folder, in the DSM's CRS, with the photo's bands plus "
        "alpha. The photos are read from the paths stored in the project, or from the photos "
        "folder when given (matched by file name).")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.ROIS, self.tr("ROIs (polygons)"), [QgsProcessing.TypeVectorPolygon]))
        self.addParameter(QgsProcessingParameterField(
            self.NAME_FIELD, self.tr("Name field (default: feature id)"),
            parentLayerParameterName=self.ROIS, optional=True))
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterRasterLayer(self.DSM, self.tr("DSM (GeoTIFF)")))
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Folder of the raw photos (default: the paths in the project)"),
            behavior=QgsProcessingParameterFile.Folder, optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.SELECTION, self.tr("Photos"),
            options=[self.tr("Best photo of each ROI"), self.tr("Every photo that sees the ROI"),
                     self.tr("A named photo")], defaultValue=0))
        self.addParameter(QgsProcessingParameterString(
            self.PHOTO, self.tr("Photo label (for 'A named photo')"), optional=True))
        p = QgsProcessingParameterNumber(
            self.GSD, self.tr("Pixel size (DSM CRS units; 0: the photo's native resolution)"),
            QgsProcessingParameterNumber.Double, 0.0, minValue=0.0, maxValue=1e6)
        p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        self.add_overwrite_parameter()
        self.addOutput(QgsProcessingOutputMultipleLayers(self.OUTPUT_FILES,
                                                         self.tr("Orthorectified ROI images")))
        self.addOutput(QgsProcessingOutputNumber(self.WRITTEN, self.tr("Number of images written")))

    def run_tool(self, parameters, context, feedback):
        from ...core.projection.ortho import orthorectify_rois

        source = self.parameterAsSource(parameters, self.ROIS, context)
        name_field = self.parameterAsString(parameters, self.NAME_FIELD, context)
        rois, _ = rois_from_source(source, name_field, self.tr("ROIs"), feedback, context=context)
        recon = open_project_parameter(self, parameters, context, feedback)
        layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        dsm = geotiff_source(layer, self.tr("DSM"))
        selection = SELECTIONS[self.parameterAsEnum(parameters, self.SELECTION, context)]
        photo = self.parameterAsString(parameters, self.PHOTO, context) or None
        photos = self.parameterAsFile(parameters, self.PHOTOS, context) or None
        gsd = self.parameterAsDouble(parameters, self.GSD, context) or None
        folder = self.parameterAsString(parameters, self.OUTPUT_FOLDER, context)
        result = orthorectify_rois(rois, recon, dsm, folder, selection=selection, photo=photo,
                                   photos_folder=photos, gsd=gsd, dsm_crs=crs_string(layer.crs()),
                                   overwrite=self.overwrite(parameters, context),
                                   progress=feedback.setProgress, is_cancelled=feedback.isCanceled)
        for what, why in result.skipped.items():
            feedback.pushWarning(self.tr("{what}: no image ({why}).").format(what=what, why=why))
        feedback.pushInfo(self.tr("{n} orthorectified ROI images written to {folder}; {s} "
                                  "skipped.").format(n=len(result.files), folder=folder,
                                                     s=len(result.skipped)))
        if context.project() is not None and len(result.files) <= MAX_LAYERS_TO_LOAD:
            for path, roi, ph in zip(result.files, result.rois, result.photos):
                details = QgsProcessingContext.LayerDetails(f"{roi} – {ph}", context.project(),
                                                            self.OUTPUT_FILES)
                context.addLayerToLoadOnCompletion(os.path.abspath(path), details)
        elif context.project() is not None:
            feedback.pushInfo(self.tr("More than {n} images: they are not loaded into the map; "
                                      "open them from the output folder.").format(n=MAX_LAYERS_TO_LOAD))
        return {self.OUTPUT_FOLDER: folder, self.OUTPUT_FILES: result.files,
                self.WRITTEN: len(result.files)}
