"""Processing tool: Camera positions and footprints (easyidp:camerafootprints)."""
import math

import numpy as np
from qgis.core import (QgsCoordinateReferenceSystem, QgsFeature, QgsFeatureSink, QgsField,
                       QgsFields, QgsGeometry, QgsLineString, QgsPoint, QgsPolygon, QgsProcessing,
                       QgsProcessingException, QgsProcessingParameterCrs,
                       QgsProcessingParameterDefinition, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFile, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString, QgsWkbTypes)
from qgis.PyQt.QtCore import QVariant

from ..layers import crs_string, geotiff_source
from .base import EasyIDPAlgorithm


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
    DISPLAY = "Camera positions and footprints"
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
        "footprints the area (m²) and whether the whole border reached the ground.\n\n"
        "Metashape projects with rolling-shutter compensation: each photo has one pose per "
        "image row (the motion Metashape estimated during the readout); the footprints, like "
        "every projection, use it, and the log says when it is applied.\n\n"
        "Outputs are in the project CRS, or the output CRS if one is chosen. A Pix4D params "
        "folder without *_wkt.prj needs the project CRS. ODM projects bring ODM's CRS (that of "
        "its orthophoto and DSM); an OpenSfM dataset without ODM uses the WGS 84 / UTM zone of "
        "its reference point unless a project CRS is set. Heights of the DSM or the ground "
        "height must be in the project's vertical reference (for a Metashape chunk in a "
        "geographic CRS: ellipsoidal heights; for ODM: the heights of its DSM).")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterFile(
            self.PROJECT, self.tr("Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d or a file of its params folder; ODM opensfm/reconstruction.json)"),
            behavior=QgsProcessingParameterFile.File,
            fileFilter="Photogrammetry projects (*.psx *.psz *.xml *.p4d *_pmatrix.txt *.json);;All files (*.*)"))
        self.addParameter(QgsProcessingParameterString(
            self.CHUNK, self.tr("Chunk: Metashape chunk (label or index) or OpenSfM reconstruction index"),
            optional=True))
        self.addParameter(QgsProcessingParameterCrs(
            self.PROJECT_CRS, self.tr("Project CRS (Pix4D without a *_wkt.prj file; OpenSfM without ODM)"),
            optional=True))
        self.addParameter(QgsProcessingParameterRasterLayer(
            self.DSM, self.tr("DSM (GeoTIFF) for the footprints"), optional=True))
        self.addParameter(QgsProcessingParameterNumber(
            self.GROUND_HEIGHT, self.tr("Ground height when no DSM is given (project vertical reference)"),
            QgsProcessingParameterNumber.Double, optional=True))
        p = QgsProcessingParameterCrs(self.OUTPUT_CRS, self.tr("Output CRS (default: the project CRS)"),
                                      optional=True)
        p.setFlags(p.flags() | QgsProcessingParameterDefinition.FlagAdvanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_CAMERAS, self.tr("Camera positions"), QgsProcessing.TypeVectorPoint))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_FOOTPRINTS, self.tr("Camera footprints"), QgsProcessing.TypeVectorPolygon))
        self.add_overwrite_parameter()

    def run_tool(self, parameters, context, feedback):
        from ...core.reconstruction import camera_footprints, open_reconstruction

        path = self.parameterAsFile(parameters, self.PROJECT, context)
        chunk = self.parameterAsString(parameters, self.CHUNK, context) or None
        pcrs = self.parameterAsCrs(parameters, self.PROJECT_CRS, context)
        recon = open_reconstruction(path, chunk, crs_string(pcrs) if pcrs.isValid() and
                                    not path.lower().endswith((".psx", ".psz", ".xml")) else None)
        feedback.pushInfo(recon.summary())
        for note in recon.notes:
            feedback.pushWarning(note)
        if recon.crs is None:
            raise QgsProcessingException(
                f"{path}: the project has no CRS (no *_wkt.prj): set 'Project CRS'.")
        if recon.unaligned_cameras:
            feedback.pushWarning(self.tr(
                f"{len(recon.unaligned_cameras)} cameras are not aligned and have no position: "
                + ", ".join(c.label for c in recon.unaligned_cameras[:20])
                + (" …" if len(recon.unaligned_cameras) > 20 else "")))

        layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        if layer is not None:
            from ...core.projection import DSMSurface
            ground = DSMSurface(geotiff_source(layer, self.tr("DSM")), crs=crs_string(layer.crs()))
        elif parameters.get(self.GROUND_HEIGHT) not in (None, ""):
            ground = self.parameterAsDouble(parameters, self.GROUND_HEIGHT, context)
        else:
            raise QgsProcessingException(self.tr(
                "Give a DSM or a ground height: the footprints are where the photos meet the ground."))

        out_crs = self.parameterAsCrs(parameters, self.OUTPUT_CRS, context)
        if recon.is_local:
            qcrs = QgsCoordinateReferenceSystem.fromWkt(recon.crs.to_wkt())
            feedback.pushWarning(self.tr("The project is in a local coordinate system ({name}): "
                                         "the outputs will not line up with map layers.").format(
                                     name=recon.crs.name))
            target = None
        elif out_crs.isValid():
            qcrs, target = out_crs, crs_string(out_crs)
        else:
            qcrs = QgsCoordinateReferenceSystem.fromWkt(recon.crs.to_wkt())
            target = None
        cams = [c for c in recon.cameras if c.aligned]
        prints = camera_footprints(recon, ground, crs=target, cameras=cams,
                                   progress=lambda p: feedback.setProgress(0.95 * p),
                                   is_cancelled=feedback.isCanceled)

        fields = QgsFields()
        for name, kind in (("label", QVariant.String), ("photo_path", QVariant.String),
                           ("enabled", QVariant.Bool), ("height_above_ground", QVariant.Double),
                           ("view_angle", QVariant.Double)):
            fields.append(QgsField(name, kind))
        fp_fields = QgsFields(fields)
        fp_fields.append(QgsField("area", QVariant.Double))
        fp_fields.append(QgsField("complete", QVariant.Bool))
        cam_sink, cam_id = self.parameterAsSink(parameters, self.OUTPUT_CAMERAS, context, fields,
                                                QgsWkbTypes.PointZ, qcrs)
        fp_sink, fp_id = self.parameterAsSink(parameters, self.OUTPUT_FOOTPRINTS, context, fp_fields,
                                              QgsWkbTypes.PolygonZ, qcrs)
        if cam_sink is None or fp_sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT_CAMERAS))
        partial = 0
        for fp in prints:
            attrs = [fp.label, fp.photo_path or "", bool(fp.enabled), _num(fp.height_above_ground),
                     _num(fp.view_angle)]
            f = QgsFeature(fields)
            f.setAttributes(attrs)
            f.setGeometry(QgsGeometry(QgsPoint(*map(float, fp.centre))))
            cam_sink.addFeature(f, QgsFeatureSink.FastInsert)
            if fp.ring is None or len(fp.ring) < 3:
                partial += 1
                continue
            ring = np.vstack([fp.ring, fp.ring[:1]])
            g = QgsFeature(fp_fields)
            g.setAttributes(attrs + [_num(fp.area), bool(fp.complete)])
            g.setGeometry(QgsGeometry(QgsPolygon(QgsLineString(*[list(map(float, ring[:, k]))
                                                                 for k in range(3)]))))
            fp_sink.addFeature(g, QgsFeatureSink.FastInsert)
            partial += not fp.complete
        if partial:
            feedback.pushWarning(self.tr("{partial} footprints are partial: some of the photo "
                                         "border does not reach the ground (oblique views or the "
                                         "DSM edge).").format(partial=partial))
        feedback.pushInfo(self.tr("{n_prints} cameras written.").format(n_prints=len(prints)))
        return {self.OUTPUT_CAMERAS: cam_id, self.OUTPUT_FOOTPRINTS: fp_id}


def _num(v):
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)
