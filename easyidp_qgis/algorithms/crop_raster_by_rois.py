"""Processing tool: Crop raster by ROIs (easyidp:croprasterbyrois)."""
import os

from qgis.core import (QgsProcessingContext, QgsProcessingOutputMultipleLayers,
                       QgsProcessingOutputNumber, QgsProcessingParameterBoolean,
                       QgsProcessingParameterDefinition, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProcessingParameterFolderDestination,
                       QgsProcessingParameterRasterLayer, QgsProcessing)

from ..layers import crs_string, geotiff_source, rois_from_source
from .base import EasyIDPAlgorithm

MAX_LAYERS_TO_LOAD = 100


class CropRasterByROIs(EasyIDPAlgorithm):
    INPUT = "INPUT"
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    ALL_TOUCHED = "ALL_TOUCHED"
    OUTPUT_FOLDER = "OUTPUT_FOLDER"
    OUTPUT_FILES = "OUTPUT_FILES"
    CROPPED = "CROPPED"
    SKIPPED = "SKIPPED"

    NAME = "croprasterbyrois"
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

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.INPUT, self.tr("Raster (GeoTIFF: orthomosaic, DSM or multispectral)")))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.ROIS, self.tr("ROIs (polygons)"), [QgsProcessing.TypeVectorPolygon]))
        self.addParameter(QgsProcessingParameterField(
            self.NAME_FIELD, self.tr("Name field (default: feature id)"),
            parentLayerParameterName=self.ROIS, optional=True))
        p = QgsProcessingParameterBoolean(
            self.ALL_TOUCHED, self.tr("All touched (include every pixel the ROI touches)"), False)
        p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        self.add_overwrite_parameter()
        self.addOutput(QgsProcessingOutputMultipleLayers(self.OUTPUT_FILES, self.tr("Cropped rasters")))
        self.addOutput(QgsProcessingOutputNumber(self.CROPPED, self.tr("Number of ROIs cropped")))
        self.addOutput(QgsProcessingOutputNumber(self.SKIPPED, self.tr("Number of ROIs skipped")))

    def run_tool(self, parameters, context, feedback):
        from ...core.raster.crop import crop_raster_by_rois

        layer = self.parameterAsRasterLayer(parameters, self.INPUT, context)
        raster = geotiff_source(layer, self.tr("Raster"))
        source = self.parameterAsSource(parameters, self.ROIS, context)
        name_field = self.parameterAsString(parameters, self.NAME_FIELD, context)
        rois, _ = rois_from_source(source, name_field, self.tr("ROIs"), feedback, layer.crs(),
                                   context)
        folder = self.parameterAsString(parameters, self.OUTPUT_FOLDER, context)
        all_touched = self.parameterAsBool(parameters, self.ALL_TOUCHED, context)
        feedback.pushInfo(self.tr("Cropping {n_rois} ROIs out of {raster} into {folder}").format(
                              n_rois=len(rois), raster=raster, folder=folder))
        result = crop_raster_by_rois(
            raster, rois, folder, all_touched=all_touched, raster_crs=crs_string(layer.crs()),
            overwrite=self.overwrite(parameters, context),
            progress=lambda p: feedback.setProgress(5 + 0.95 * p), is_cancelled=feedback.isCanceled)
        for note in result.notes:
            feedback.pushWarning(note)
        for i, reason in result.skipped.items():
            feedback.pushWarning(self.tr("ROI '{name}' skipped: {reason}").format(
                name=rois[i].name, reason=reason))
        feedback.pushInfo(self.tr("{n_files} GeoTIFFs written, {n_skipped} ROIs skipped.").format(
                              n_files=len(result.files), n_skipped=len(result.skipped)))
        self._load(result, layer.name(), context, feedback)
        return {self.OUTPUT_FOLDER: folder, self.OUTPUT_FILES: result.files,
                self.CROPPED: len(result.files), self.SKIPPED: len(result.skipped)}

    def _load(self, result, raster_name, context, feedback):
        """Queue the crops for loading into the map (the GUI does it; qgis_process ignores it)."""
        if context.project() is None:
            return
        if len(result.files) > MAX_LAYERS_TO_LOAD:
            feedback.pushInfo(self.tr("More than {limit} crops: they are not loaded "
                                      "into the map; open them from the output folder.").format(
                                  limit=MAX_LAYERS_TO_LOAD))
            return
        for path, name in zip(result.files, result.names):
            details = QgsProcessingContext.LayerDetails(f"{raster_name} – {name}", context.project(),
                                                        self.OUTPUT_FILES)
            context.addLayerToLoadOnCompletion(os.path.abspath(path), details)
