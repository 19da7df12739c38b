"""Processing tool: Crop raster by ROIs (easyidp:croprasterbyrois)."""
from qgis.core import (QgsProcessingOutputMultipleLayers, QgsProcessingOutputNumber,
                       QgsProcessingParameterBoolean, QgsProcessingParameterFolderDestination,
                       QgsProcessingParameterRasterLayer)

from .. import presentation
from ..compat import FieldType, ProcessingParameterFlag
from ..crs import crs_string
from ..progress import feedback_progress
from ..rasters import geotiff_source
from ..rois import add_roi_parameters, rois_parameter
from ..sinks import add_index_parameter, write_index
from .base import CoreStep, EasyIDPAlgorithm


class CropRasterByROIs(EasyIDPAlgorithm):
    INPUT = "INPUT"
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    ALL_TOUCHED = "ALL_TOUCHED"
    OUTPUT_FOLDER = "OUTPUT_FOLDER"
    OUTPUT_FILES = "OUTPUT_FILES"
    OUTPUT_INDEX = "OUTPUT_INDEX"
    CROPPED = "CROPPED"
    SKIPPED = "SKIPPED"

    NAME = "croprasterbyrois"
    REQUIRES = ("tifffile", "imagecodecs")  # GeoTIFF reading, writing
    DISPLAY = "Crop raster by ROIs"
    GROUP = "Cropping"
    GROUP_ID = "cropping"
    HELP = (
        "Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), "
        "a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output "
        "folder, named after the name field (made safe for file names and unique).\n\n"
        "The raster is read in a single pass, each tile or strip once, so thousands of ROIs on "
        "rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data "
        "type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, "
        "DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the "
        "type's extreme for integers when it has none). A pixel belongs to an ROI when its centre "
        "is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and "
        "multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the "
        "raster are reported and skipped.")

    def shortHelpString(self):  # noqa: N802 (QGIS API)
        return super().shortHelpString() + "\n\n" + self.tr(
            "Index of the crops (optional): the ROIs with the file of each ('crop_file', empty "
            "for a skipped ROI) and 'crop_status'. 'Open the crops in the map too' (off by "
            "default) opens up to 100 crops in one collapsed group below the ROI layer; a larger "
            "run opens the index only.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.INPUT, self.tr("Raster (GeoTIFF: orthomosaic, DSM or multispectral)")))
        add_roi_parameters(self)
        p = QgsProcessingParameterBoolean(
            self.ALL_TOUCHED, self.tr("All touched (include every pixel the ROI touches)"), False)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        add_index_parameter(self, self.tr("Index of the crops"))
        presentation.add_open_files_parameter(self, self.tr("Open the crops in the map too"))
        self.add_overwrite_parameter()
        self.addOutput(QgsProcessingOutputMultipleLayers(self.OUTPUT_FILES, self.tr("Cropped rasters")))
        self.addOutput(QgsProcessingOutputNumber(self.CROPPED, self.tr("Number of ROIs cropped")))
        self.addOutput(QgsProcessingOutputNumber(self.SKIPPED, self.tr("Number of ROIs skipped")))

    def core_step(self, parameters, context, feedback):
        from ...core.raster import crop_raster_by_rois

        layer = self.parameterAsRasterLayer(parameters, self.INPUT, context)
        raster = geotiff_source(layer, self.tr("Raster"))
        source, rois, features = rois_parameter(self, parameters, context, feedback, layer.crs())
        folder = self.parameterAsString(parameters, self.OUTPUT_FOLDER, context)
        feedback.pushInfo(self.tr("Cropping {n_rois} ROIs out of {raster} into {folder}").format(
                              n_rois=len(rois), raster=raster, folder=folder))
        return CoreStep(crop_raster_by_rois, dict(
            raster=raster, rois=rois, output_folder=folder,
            all_touched=self.parameterAsBool(parameters, self.ALL_TOUCHED, context),
            source_crs=crs_string(layer.crs()), overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback, 5, 100)),
            dict(layer=layer, source=source, features=features))

    def write_outputs(self, parameters, context, feedback, step, result):
        layer, source, features = (step.inputs[k] for k in ("layer", "source", "features"))
        rois, folder = step.kwargs["rois"], step.kwargs["output_folder"]
        for note in result.notes:
            feedback.pushWarning(note)
        for i, reason in result.skipped.items():
            feedback.pushWarning(self.tr("ROI '{name}' skipped: {reason}").format(
                name=rois[i].name, reason=reason))
        file_of = dict(zip(result.rois, result.files))
        index = write_index(self, parameters, context, source, [
            (f, [file_of.get(i), "written" if i in file_of else result.skipped.get(i, "")])
            for i, f in enumerate(features)],
            [("crop_file", FieldType.QString), ("crop_status", FieldType.QString)])
        group = presentation.MapGroup(
            self.tr("Crops of {raster} ({n})").format(raster=layer.name(), n=len(result.files)),
            presentation.anchor_id(self, parameters, self.ROIS, context))
        presentation.present(self, context, index, self.OUTPUT_INDEX, presentation.index_style(),
                             self.tr("Index of the crops"), group, rank=-1)
        presentation.load_files(self, context, feedback,
                                presentation.files_project(self, parameters, context),
                                result.files, presentation.stems(result.files),
                                presentation.RASTER, group, self.OUTPUT_FILES)
        feedback.pushInfo(self.tr("{n_files} GeoTIFFs written, {n_skipped} ROIs skipped.").format(
                              n_files=len(result.files), n_skipped=len(result.skipped)))
        out = {self.OUTPUT_FOLDER: folder, self.OUTPUT_FILES: result.files,
               self.CROPPED: len(result.files), self.SKIPPED: len(result.skipped)}
        if index:
            out[self.OUTPUT_INDEX] = index
        return out

