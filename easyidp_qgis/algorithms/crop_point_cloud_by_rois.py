"""Processing tool: Crop point cloud by ROIs (easyidp:croppointcloudbyrois)."""
import os

from qgis.core import (QgsProcessingException, QgsProcessingOutputMultipleLayers,
                       QgsProcessingOutputNumber, QgsProcessingParameterBoolean,
                       QgsProcessingParameterEnum, QgsProcessingParameterFolderDestination,
                       QgsProviderRegistry)

from .. import presentation
from ..compat import FieldType, ProcessingParameterFlag
from ..crs import qgis_crs
from ..parameters import add_z_range_parameters, z_range
from ..point_clouds import add_point_cloud_parameters, read_point_cloud_parameter
from ..progress import feedback_progress
from ..rois import add_roi_parameters, rois_parameter
from ..sinks import add_index_parameter, write_index
from .base import CoreStep, EasyIDPAlgorithm, translatable

FORMATS = [("same", translatable("Same as input")), ("las", "LAS"),
           ("laz", translatable("LAZ (compressed LAS)")), ("ply", "PLY")]


def point_cloud_provider_available() -> bool:
    """True when this QGIS can open LAS/LAZ files as layers (it has the PDAL provider)."""
    return "pdal" in QgsProviderRegistry.instance().providerList()


class CropPointCloudByROIs(EasyIDPAlgorithm):
    INPUT = "INPUT"
    INPUT_CRS = "INPUT_CRS"
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    Z_MIN = "Z_MIN"
    Z_MAX = "Z_MAX"
    WRITE_EMPTY = "WRITE_EMPTY"
    FORMAT = "FORMAT"
    OUTPUT_FOLDER = "OUTPUT_FOLDER"
    OUTPUT_FILES = "OUTPUT_FILES"
    OUTPUT_INDEX = "OUTPUT_INDEX"
    CROPPED = "CROPPED"
    EMPTY = "EMPTY"
    MISSED = "MISSED"

    NAME = "croppointcloudbyrois"
    REQUIRES = ("laspy", "lazrs", "plyfile")  # LAS/LAZ, PLY
    DISPLAY = "Crop point cloud by ROIs"
    GROUP = "Cropping"
    GROUP_ID = "cropping"
    HELP = (
        "Cuts every ROI (plot, tree, plant polygon) out of a point cloud (.las, .laz or .ply, e.g. "
        "the dense cloud of Pix4D or Metashape) into one file per ROI in the output folder, named "
        "after the name field (made safe for file names and unique).\n\n"
        "A point belongs to an ROI when its x, y is inside the polygon (holes and multipart "
        "polygons honoured) and, if set, its Z is within the Z range (advanced: e.g. to drop noise "
        "below the ground or above the canopy). A point inside overlapping ROIs goes to each. The "
        "cloud is read once and every point is tested only against the ROIs near it, so thousands "
        "of ROIs on a large cloud are fast.\n\n"
        "Every point attribute is kept (colour, intensity, classification, returns, GPS time, "
        "normals, extra dimensions) with the exact coordinates. LAS/LAZ files carry their CRS; a "
        "PLY file has none, so give the 'Point cloud CRS' for it (and for a LAS file without a "
        "CRS). ROIs in another CRS are reprojected to the cloud's.\n\n"
        "ROIs outside the cloud are named in the log and skipped; ROIs over the cloud without any "
        "point are reported and get no file unless 'Write empty files' is checked. Cropped LAS/LAZ "
        "files load into the map when this QGIS can display point clouds (PDAL provider).")

    def shortHelpString(self):  # noqa: N802 (QGIS API)
        return super().shortHelpString() + "\n\n" + self.tr(
            "Index of the crops (optional): the ROIs with the file ('crop_file'), the number of "
            "points ('points') and the outcome ('crop_status') of each. 'Open the crops in the "
            "map too' (off by default) opens up to 100 LAS/LAZ crops in one collapsed group below "
            "the ROI layer, where this QGIS can display point clouds (PDAL provider); a larger "
            "run opens the index only.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_point_cloud_parameters(self)
        add_roi_parameters(self)
        add_z_range_parameters(self)
        p = QgsProcessingParameterBoolean(
            self.WRITE_EMPTY, self.tr("Write empty files for ROIs without any point"), False)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterEnum(
            self.FORMAT, self.tr("Output format"), options=[self.tr(f[1]) for f in FORMATS],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        add_index_parameter(self, self.tr("Index of the crops"))
        presentation.add_open_files_parameter(self, self.tr("Open the crops in the map too"))
        self.add_overwrite_parameter()
        self.addOutput(QgsProcessingOutputMultipleLayers(self.OUTPUT_FILES,
                                                         self.tr("Cropped point clouds")))
        self.addOutput(QgsProcessingOutputNumber(self.CROPPED, self.tr("Number of ROIs cropped")))
        self.addOutput(QgsProcessingOutputNumber(self.EMPTY, self.tr("Number of ROIs without points")))
        self.addOutput(QgsProcessingOutputNumber(self.MISSED,
                                                 self.tr("Number of ROIs outside the cloud")))

    def core_step(self, parameters, context, feedback):
        from ...core.pointcloud import crop_point_cloud

        cloud = read_point_cloud_parameter(self, parameters, context, feedback)
        source, rois, features = rois_parameter(self, parameters, context, feedback,
                                                qgis_crs(cloud.crs))
        z_min, z_max = z_range(self, parameters, context)
        fmt = FORMATS[self.parameterAsEnum(parameters, self.FORMAT, context)][0]
        folder = self.parameterAsString(parameters, self.OUTPUT_FOLDER, context)
        write_empty = self.parameterAsBool(parameters, self.WRITE_EMPTY, context)
        feedback.pushInfo(self.tr("Cropping {n_rois} ROIs into {folder}").format(
                              n_rois=len(rois), folder=folder))
        return CoreStep(crop_point_cloud, dict(
            cloud=cloud, rois=rois, output_folder=folder, fmt=fmt, z_min=z_min, z_max=z_max,
            write_empty=write_empty, overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback, 5, 100), is_cancelled=feedback.isCanceled),
            dict(source=source, features=features))

    def write_outputs(self, parameters, context, feedback, step, result):
        source, features = step.inputs["source"], step.inputs["features"]
        cloud, folder = step.kwargs["cloud"], step.kwargs["output_folder"]
        if result.items and len(result.missed) == len(result.items):
            raise QgsProcessingException(self.tr("None of the {n_items} ROIs overlaps the point "
                                                 "cloud: check that the ROIs and the cloud are in "
                                                 "the right CRS (set 'Point cloud CRS' if the "
                                                 "file has none or a wrong one).").format(
                                             n_items=len(result.items)))
        for message in result.messages:
            feedback.pushWarning(message)
        written = [item for item in result.items if item.file is not None]
        cropped = sum(item.status == "written" for item in result.items)
        points = sum(item.count for item in result.items if item.status == "written")
        index = write_index(self, parameters, context, source, [
            (f, [str(item.file) if item.file is not None else None, int(item.count), item.status])
            for f, item in zip(features, result.items)],
            [("crop_file", FieldType.QString), ("points", FieldType.LongLong),
             ("crop_status", FieldType.QString)])
        name = os.path.splitext(os.path.basename(str(cloud.path)))[0]
        group = presentation.MapGroup(
            self.tr("Point cloud crops of {cloud} ({n})").format(cloud=name, n=len(written)),
            presentation.anchor_id(self, parameters, self.ROIS, context))
        presentation.present(self, context, index, self.OUTPUT_INDEX, presentation.index_style(),
                             self.tr("Index of the point cloud crops"), group, rank=-1)
        self._load(written, group, presentation.files_project(self, parameters, context),
                   context, feedback)
        feedback.pushInfo(self.tr("{cropped} ROIs cropped ({points:,} points), {n_empty} without "
                                  "points, {n_missed} outside the cloud.").format(
                              cropped=cropped, points=points, n_empty=len(result.empty),
                              n_missed=len(result.missed)))
        out = {self.OUTPUT_FOLDER: folder, self.OUTPUT_FILES: [str(i.file) for i in written],
               self.CROPPED: cropped, self.EMPTY: len(result.empty),
               self.MISSED: len(result.missed)}
        if index:
            out[self.OUTPUT_INDEX] = index
        return out

    def _load(self, written, group, project, context, feedback):
        """Queue LAS/LAZ crops for loading where QGIS has a point cloud provider."""
        if not written or project is None:
            return
        if not point_cloud_provider_available():
            feedback.pushInfo(self.tr("The cropped point clouds are not loaded into the map: this "
                                      "QGIS has no point cloud provider (PDAL). Open them from the "
                                      "output folder (e.g. in CloudCompare)."))
            return
        las = [i for i in written if i.file.suffix.lower() in (".las", ".laz")]
        if len(las) < len(written):
            feedback.pushInfo(self.tr("PLY crops are not loaded into the map; open them from the "
                                      "output folder."))
        presentation.load_files(self, context, feedback, project, [i.file for i in las],
                                [i.stem for i in las], presentation.POINT_CLOUD, group,
                                self.OUTPUT_FILES)

