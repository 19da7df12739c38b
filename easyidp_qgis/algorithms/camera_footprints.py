"""Processing tool: Cameras and footprints (easyidp:camerafootprints)."""
import math
import os

from qgis.core import (QgsCoordinateReferenceSystem, QgsFeature, QgsField, QgsFields, QgsGeometry,
                       QgsPoint, QgsProcessingException,
                       QgsProcessingParameterCrs, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterLayer)

from .. import presentation
from ..compat import (FeatureSinkFlag, FieldType, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType, WkbType)
from ..crs import crs_string
from ..geometries import polygon
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import geotiff_source
from ..sinks import close_sink
from .base import CoreStep, EasyIDPAlgorithm


class CameraFootprints(EasyIDPAlgorithm):
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    DSM = "DSM"
    GROUND_HEIGHT = "GROUND_HEIGHT"
    OUTPUT_CRS = "OUTPUT_CRS"
    OUTPUT_CAMERAS = "OUTPUT_CAMERAS"
    OUTPUT_FOOTPRINTS = "OUTPUT_FOOTPRINTS"

    NAME = "camerafootprints"
    REQUIRES = ("tifffile", "imagecodecs", "PIL")  # the DSM; the photos' headers
    DISPLAY = "Cameras and footprints"
    GROUP = "Photogrammetry projects"
    GROUP_ID = "projects"
    HELP = (
        "Reads the solved cameras of an Agisoft Metashape project (.psx with its .files folder, "
        ".psz, or an exported cameras .xml), a Pix4D project (.p4d, the project folder or its "
        "1_initial/params folder: choose any file in it, e.g. *_pmatrix.txt) or an "
        "OpenDroneMap/OpenSfM project (choose opensfm/reconstruction.json in the ODM project "
        "folder; Python scripts may give the folder itself) and draws, for "
        "every aligned camera, its position and the part of the ground its photo sees. Run it "
        "first to check that a project was read right.\n\n"
        "Chunk: the Metashape chunk (label or index), or the OpenSfM reconstruction (index of a "
        "partial model; by default the largest, as the log says).\n\n"
        "The footprint is the photo border (densified, with the lens distortion) cast onto the "
        "DSM, or onto a constant ground height when no DSM is given. Attributes: label, photo "
        "path, enabled, height above ground (m), view angle from nadir (degrees), and for "
        "footprints the area (m²) and whether the whole border reached the ground's data "
        "(complete; where the DSM ends the footprint continues on a plane at the ground height "
        "under the camera). A camera at or below the ground gets no footprint and is named in "
        "the log.\n\n"
        "Metashape projects with rolling-shutter compensation: each photo has one pose per "
        "image row (the motion Metashape estimated during the readout); the footprints, like "
        "every projection, use it, and the log says when it is applied.\n\n"
        "Outputs are in the output CRS if one is chosen, else in the DSM's CRS, else in the "
        "map's CRS, else in the photogrammetry project's (the log says which). A Pix4D params "
        "folder without *_wkt.prj needs the project CRS. ODM projects bring ODM's CRS (that of "
        "its orthophoto and DSM); an OpenSfM dataset without ODM uses the WGS 84 / UTM zone of "
        "its reference point unless a project CRS is set. Heights of the DSM or the ground "
        "height must be in the project's vertical reference (for a Metashape chunk in a "
        "geographic CRS: ellipsoidal heights; for ODM: the heights of its DSM).")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.DSM, self.tr("DSM (GeoTIFF) for the footprints"), optional=True))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.GROUND_HEIGHT, self.tr("Ground height when no DSM is given"),
            ProcessingNumberParameterType.Double, optional=True), 3))
        p = QgsProcessingParameterCrs(self.OUTPUT_CRS, self.tr("Output CRS"), optional=True)
        p.setHelp(self.tr("Default: the DSM's, else the map's, else the photogrammetry "
                          "project's"))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_CAMERAS, self.tr("Camera positions"), ProcessingSourceType.VectorPoint))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_FOOTPRINTS, self.tr("Camera footprints"), ProcessingSourceType.VectorPolygon))
        self.add_overwrite_parameter()

    def core_step(self, parameters, context, feedback):
        from ...core.projection import camera_footprints
        from ...core.raster import DSM

        recon = open_project_parameter(self, parameters, context, feedback)
        layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        if layer is not None:
            ground = DSM(geotiff_source(layer, self.tr("DSM")), crs=crs_string(layer.crs()))
        elif parameters.get(self.GROUND_HEIGHT) not in (None, ""):
            ground = self.parameterAsDouble(parameters, self.GROUND_HEIGHT, context)
        else:
            raise QgsProcessingException(self.tr(
                "Give a DSM or a ground height: the footprints are where the photos meet the ground."))
        qcrs, target = self._output_crs(parameters, context, feedback, recon, layer)
        return CoreStep(camera_footprints, dict(
            recon=recon, ground=ground, output_crs=target,
            cameras=[c for c in recon.cameras if c.aligned],
            progress=feedback_progress(feedback, 0, 95), is_cancelled=feedback.isCanceled),
            dict(qcrs=qcrs))

    def write_outputs(self, parameters, context, feedback, step, prints):
        qcrs = step.inputs["qcrs"]
        fields = QgsFields()
        for name, kind in (("label", FieldType.QString), ("photo_path", FieldType.QString),
                           ("enabled", FieldType.Bool), ("height_above_ground", FieldType.Double),
                           ("view_angle", FieldType.Double)):
            fields.append(QgsField(name, kind))
        fp_fields = QgsFields(fields)
        fp_fields.append(QgsField("area", FieldType.Double))
        fp_fields.append(QgsField("complete", FieldType.Bool))
        cam_sink, cam_id = self.parameterAsSink(parameters, self.OUTPUT_CAMERAS, context, fields,
                                                WkbType.PointZ, qcrs)
        fp_sink, fp_id = self.parameterAsSink(parameters, self.OUTPUT_FOOTPRINTS, context, fp_fields,
                                              WkbType.PolygonZ, qcrs)
        if cam_sink is None or fp_sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT_CAMERAS))
        beyond, below = 0, []
        for fp in prints:
            attrs = [fp.label, fp.photo_path or "", bool(fp.enabled), _num(fp.height_above_ground),
                     _num(fp.view_angle)]
            f = QgsFeature(fields)
            f.setAttributes(attrs)
            f.setGeometry(QgsGeometry(QgsPoint(*map(float, fp.centre))))
            cam_sink.addFeature(f, FeatureSinkFlag.FastInsert)
            if fp.below_ground:
                below.append(fp.label)
            if fp.ring is None or len(fp.ring) < 3:
                continue
            g = QgsFeature(fp_fields)
            g.setAttributes(attrs + [_num(fp.area), bool(fp.complete)])
            g.setGeometry(polygon([fp.ring], z=True))
            fp_sink.addFeature(g, FeatureSinkFlag.FastInsert)
            beyond += not fp.complete
        close_sink(cam_sink)
        close_sink(fp_sink)
        project = os.path.basename(self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        presentation.present(self, context, fp_id, self.OUTPUT_FOOTPRINTS, footprint_style(),
                             self.tr("Camera footprints of {project}").format(project=project))
        presentation.present(self, context, cam_id, self.OUTPUT_CAMERAS, camera_style(),
                             self.tr("Cameras of {project}").format(project=project))
        self._report(prints, beyond, below, feedback)
        return {self.OUTPUT_CAMERAS: cam_id, self.OUTPUT_FOOTPRINTS: fp_id}

    def _output_crs(self, parameters, context, feedback, recon, dsm_layer):
        """(QGIS CRS, core CRS or None) of the outputs: the one chosen, else the DSM's, else the
        map's, else the photogrammetry project's; the choice goes to the log."""
        chosen = self.parameterAsCrs(parameters, self.OUTPUT_CRS, context)
        project = context.project()
        if recon.is_local:
            feedback.pushWarning(self.tr("The project is in a local coordinate system ({name}): "
                                         "the outputs will not line up with map layers.").format(
                                     name=recon.crs.name))
            return QgsCoordinateReferenceSystem.fromWkt(recon.crs.to_wkt()), None
        for crs, why in ((chosen, self.tr("the output CRS chosen")),
                         (dsm_layer.crs() if dsm_layer is not None else None, self.tr("the DSM's CRS")),
                         (project.crs() if project is not None else None, self.tr("the map's CRS"))):
            if crs is not None and crs.isValid():
                feedback.pushInfo(self.tr("Outputs in {crs} ({why}).").format(
                    crs=crs.authid() or crs.description(), why=why))
                return crs, crs_string(crs)
        qcrs = QgsCoordinateReferenceSystem.fromWkt(recon.crs.to_wkt())
        feedback.pushInfo(self.tr("Outputs in {crs} (the photogrammetry project's CRS).").format(
            crs=qcrs.authid() or recon.crs.name))
        return qcrs, None

    def _report(self, prints, beyond, below, feedback):
        """Calm, true messages: what is information, what needs the user."""
        from ...core.projection import FootprintStatus
        if below:
            feedback.pushWarning(self.tr(
                "{n} camera(s) are at or below the ground, so they have no footprint: {names}. "
                "Check the ground height or the DSM and its vertical reference.").format(
                    n=len(below), names=", ".join(below[:20]) + (" …" if len(below) > 20 else "")))
        for status, text in ((FootprintStatus.GROUND_FROM_FOOTPRINT, self.tr(
                "{n} camera(s) have no DSM right under them: their height above ground is taken "
                "from the DSM where their photo sees the ground.")),
                (FootprintStatus.GROUND_FROM_OTHERS, self.tr(
                    "{n} camera(s) see no DSM at all: their height above ground is taken from the "
                    "median ground under the other cameras."))):
            n = sum(fp.status is status for fp in prints)
            if n:
                feedback.pushInfo(text.format(n=n))
        if beyond:
            feedback.pushInfo(self.tr(
                "{n} footprint(s) reach beyond the DSM's data: there they continue on a plane at "
                "the ground height under the camera (attribute complete = false).").format(n=beyond))
        drawn = sum(fp.ring is not None for fp in prints)
        feedback.pushInfo(self.tr("{n} cameras and {f} footprints written.").format(
            n=len(prints), f=drawn))


def footprint_style():
    """Footprints as thin outlines of one colour, no fill: the orthomosaic and the plots stay
    visible through the overlapping footprints of a whole flight."""
    return presentation.outline_style("#ff6a00", 0.25,
                                      tip='<b>[% "label" %]</b><br>[% round("view_angle", 1) %]° '
                                          'from nadir, [% round("area", 0) %] m²')


def camera_style():
    """Cameras as small dots, labelled when zoomed in (beyond 1:300) and on hover (map tips)."""
    return presentation.points_style("#1f4e9c", 1.6, label='"label"', label_scale=300,
                                     tip='<b>[% "label" %]</b><br>[% round("height_above_ground", '
                                         '1) %] m above ground')


def _num(v):
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)
