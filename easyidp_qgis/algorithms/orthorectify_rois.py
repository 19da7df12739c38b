"""Processing tool: Orthorectify ROIs (easyidp:orthorectifyrois)."""
from qgis.core import (QgsProcessingOutputMultipleLayers, QgsProcessingOutputNumber,
                       QgsProcessingParameterEnum, QgsProcessingParameterFile,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString)


from .. import presentation
from ..compat import (FieldType, ProcessingFileParameterBehavior, ProcessingNumberParameterType,
                      ProcessingParameterFlag)
from ..crs import crs_string
from ..parameters import translatable
from ..physical_values import add_value_parameters, value_parameters
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import geotiff_source
from ..rois import add_roi_parameters, rois_parameter
from ..sinks import add_index_parameter, write_index
from .base import CoreStep, EasyIDPAlgorithm

SELECTIONS = ("best", "all", "photo")


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
    OUTPUT_INDEX = "OUTPUT_INDEX"
    WRITTEN = "WRITTEN"
    MASK = "MASK"

    NAME = "orthorectifyrois"
    REQUIRES = ("tifffile", "imagecodecs", "scipy", "PIL")  # rasters; resampling; headers
    DISPLAY = "Orthorectify ROIs"
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
        "camera by the DSM (occlusion) are transparent (alpha 0).\n\n"
        "Mask: 'occlusion mask' (the default) casts a ray from every output pixel's ground "
        "point to the camera and makes the pixel transparent where the DSM blocks it (a tree "
        "or a wall between them), so no pixel shows what stands in front of it; 'none' skips "
        "the rays and keeps every pixel the photo frames, as Orthority does (faster; hidden "
        "ground then shows the object that hides it).\n\n"
        "One GeoTIFF per ROI (and "
        "photo, for 'all') in the output folder, in the DSM's CRS, with the photo's bands plus "
        "alpha. The photos are read from the paths stored in the project, or from the photos "
        "folder when given (matched by file name).\n\n"
        "Values: as stored (the photo's bands and data type, the default), temperature in °C "
        "(FLIR radiometric JPEGs by the Planck curve, with the photo's object parameters unless "
        "given; temperature TIFFs by their preset or scale and offset) or reflectance "
        "(MicaSense and DJI multispectral band files), as in Plot statistics from photos. "
        "Temperature and reflectance images are float32 GeoTIFFs with the unit and what was "
        "applied in their GDAL metadata; pixels without a value, and those whose bilinear "
        "sample touches a saturated or unreadable photo pixel, are NaN (nodata, alpha 0).")

    def shortHelpString(self):  # noqa: N802 (QGIS API)
        return super().shortHelpString() + "\n\n" + self.tr(
            "Index of the images (optional): one feature per image, the ROI with its file "
            "('image_file'), photo, visible share and pixel size. 'Open the images in the map too' "
            "(off by default) opens up to 100 images in one collapsed group below the ROI layer; "
            "a larger run opens the index only.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_roi_parameters(self)
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterRasterLayer(self.DSM, self.tr("DSM (GeoTIFF)")))
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Folder of the raw photos (default: the paths in the project)"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.SELECTION, self.tr("Photos"),
            options=[self.tr("Best photo of each ROI"), self.tr("Every photo that sees the ROI"),
                     self.tr("A named photo")], defaultValue=0))
        self.addParameter(QgsProcessingParameterString(
            self.PHOTO, self.tr("Photo label (for 'A named photo')"), optional=True))
        p = QgsProcessingParameterNumber(
            self.GSD, self.tr("Pixel size (DSM CRS units; 0: the photo's native resolution)"),
            ProcessingNumberParameterType.Double, 0.0, minValue=0.0, maxValue=1e6)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        add_index_parameter(self, self.tr("Index of the images"))
        presentation.add_open_files_parameter(self, self.tr("Open the images in the map too"))
        self.add_overwrite_parameter()
        self.addParameter(QgsProcessingParameterEnum(
            self.MASK, self.tr("Mask"),
            options=[self.tr("Occlusion mask (hide the ground the DSM hides from the camera)"),
                     self.tr("None (every pixel the photo frames, as Orthority)")],
            defaultValue=0, optional=True))
        add_value_parameters(self, translatable("Values"))
        self.addOutput(QgsProcessingOutputMultipleLayers(self.OUTPUT_FILES,
                                                         self.tr("Orthorectified ROI images")))
        self.addOutput(QgsProcessingOutputNumber(self.WRITTEN, self.tr("Number of images written")))

    def core_step(self, parameters, context, feedback):
        from ...core.projection import orthorectify_rois

        source, rois, features = rois_parameter(self, parameters, context, feedback)
        recon = open_project_parameter(self, parameters, context, feedback)
        layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        return CoreStep(orthorectify_rois, dict(
            rois=rois, recon=recon, dsm=geotiff_source(layer, self.tr("DSM")),
            output_folder=self.parameterAsString(parameters, self.OUTPUT_FOLDER, context),
            selection=SELECTIONS[self.parameterAsEnum(parameters, self.SELECTION, context)],
            photo=self.parameterAsString(parameters, self.PHOTO, context) or None,
            photos_folder=self.parameterAsFile(parameters, self.PHOTOS, context) or None,
            gsd=self.parameterAsDouble(parameters, self.GSD, context) or None,
            occlusion=self.parameterAsEnum(parameters, self.MASK, context) == 0,
            source_crs=crs_string(layer.crs()), overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback), is_cancelled=feedback.isCanceled,
            **value_parameters(self, parameters, context)),
            dict(source=source, features=features))

    def write_outputs(self, parameters, context, feedback, step, result):
        source, features = step.inputs["source"], step.inputs["features"]
        folder = step.kwargs["output_folder"]
        for what, why in result.skipped.items():
            feedback.pushWarning(self.tr("{what}: no image ({why}).").format(what=what, why=why))
        index = write_index(self, parameters, context, source, [
            (features[r], [path, photo, float(v), float(g)]) for path, r, photo, v, g in
            zip(result.files, result.indices, result.photos, result.visible, result.gsd)],
            [("image_file", FieldType.QString), ("photo", FieldType.QString),
             ("visible", FieldType.Double), ("gsd", FieldType.Double)])
        group = presentation.MapGroup(
            self.tr("{rois} from raw photos ({n})").format(rois=source.sourceName(),
                                                          n=len(result.files)),
            presentation.anchor_id(self, parameters, self.ROIS, context))
        presentation.present(self, context, index, self.OUTPUT_INDEX,
                             presentation.index_style("image_file"),
                             self.tr("Index of the images"), group, rank=-1)
        presentation.load_files(self, context, feedback,
                                presentation.files_project(self, parameters, context),
                                result.files, presentation.stems(result.files), presentation.RASTER,
                                group, self.OUTPUT_FILES)
        feedback.pushInfo(self.tr("{n} orthorectified ROI images written to {folder}; {s} "
                                  "skipped.").format(n=len(result.files), folder=folder,
                                                     s=len(result.skipped)))
        out = {self.OUTPUT_FOLDER: folder, self.OUTPUT_FILES: result.files,
               self.WRITTEN: len(result.files)}
        if index:
            out[self.OUTPUT_INDEX] = index
        return out
