"""Processing tool: Back-project ROIs to raw photos (easyidp:backprojectrois)."""
import math
import os

from qgis.core import (QgsCoordinateReferenceSystem, QgsFeature, QgsField, QgsFields, QgsGeometry,
                       QgsLineString, QgsMultiPolygon, QgsPolygon, QgsProcessingException,
                       QgsProcessingParameterBoolean, QgsProcessingParameterEnum,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFile,
                       QgsProcessingParameterFileDestination,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingUtils)

from .. import presentation
from ..compat import (FeatureSinkFlag, FieldType, ProcessingFileParameterBehavior,
                      ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType, WkbType)
from ..layers import (add_height_parameters, add_project_parameters, add_roi_parameters,
                     dsm_parameter, height_source_parameter, open_project_parameter,
                     optional_destination, pixel_crs, rois_parameter)
from ..outputs import close_sink
from .base import EasyIDPAlgorithm


class BackProjectROIs(EasyIDPAlgorithm):
    ROIS = "ROIS"
    NAME_FIELD = "NAME_FIELD"
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    HEIGHT_SOURCE = "HEIGHT_SOURCE"
    DSM = "DSM"
    HEIGHT_FIELD = "HEIGHT_FIELD"
    GROUND_HEIGHT = "GROUND_HEIGHT"
    PHOTOS = "PHOTOS"
    DISTORTION = "DISTORTION"
    CLIP = "CLIP"
    OCCLUSION = "OCCLUSION"
    MIN_VISIBLE = "MIN_VISIBLE"
    MAX_IMAGES = "MAX_IMAGES"
    MARGIN = "MARGIN"
    OUTPUT = "OUTPUT"
    OUTPUT_SUMMARY = "OUTPUT_SUMMARY"
    OUTPUT_JSON = "OUTPUT_JSON"
    CROPS_FOLDER = "CROPS_FOLDER"
    PREVIEW_FOLDER = "PREVIEW_FOLDER"

    NAME = "backprojectrois"
    DISPLAY = "Back-project ROIs to raw photos"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Finds every ROI (plot, tree, plant polygon) in every raw photo of a Metashape or Pix4D "
        "project that sees it, using the cameras the project solved (EasyIDP's back2raw). Raw "
        "photos are sharper than the orthomosaic and free of its seamlines.\n\n"
        "Inputs: the ROI polygons; the project (Metashape .psx/.psz/cameras .xml, Pix4D .p4d or "
        "any file of its 1_initial/params folder); the height of the ROI vertices, from the "
        "geometry's Z (e.g. the output of ROI heights from DSM), a DSM sampled at every vertex, a "
        "numeric attribute, or one ground height (heights in the project's vertical reference; "
        "for a Metashape chunk in a geographic CRS: ellipsoidal). Photos folder: where the photos "
        "are when they moved (matched by file name).\n\n"
        "Each ROI is densified, projected with the lens distortion, and clipped to the photo "
        "frame (or, with 'whole ROIs only', kept only where the whole ROI is in the photo). With "
        "a DSM, lines of sight to points on the surface inside the ROI are tested for "
        "occlusion. Photos showing less than the minimum visible, unoccluded share are "
        "dropped; the others are ranked by a score (view angle, ground resolution, distance from "
        "the photo centre, visible share).\n\n"
        "Outputs: the ROIs in photo pixels (x = column, y = −row: they lie on a raw photo "
        "opened in QGIS without georeference; filter by 'photo'), one feature per ROI × photo "
        "with score, rank, view angle, GSD and fractions; a summary of the ROIs in the map with "
        "their photo count and best photo; optionally EasyIDP's JSON "
        "{roi: {photo: [[x, y], ...]}}, the crops of the raw photos (PNG with the ROI as alpha, "
        "TIFF for 16-bit or multiband photos, each with a JSON sidecar) and one preview PNG "
        "per ROI showing its best photos.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_roi_parameters(self)
        add_project_parameters(self)
        add_height_parameters(self)
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Photos folder (when the photos moved; matched by file name)"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            self.CLIP, self.tr("ROIs partly outside a photo"),
            [self.tr("Clip them to the photo frame"), self.tr("Drop the photo (whole ROIs only)")],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterBoolean(
            self.OCCLUSION, self.tr("Test occlusion against the DSM (when a DSM is given)"), True))
        p = self.decimals(QgsProcessingParameterNumber(
            self.MIN_VISIBLE, self.tr("Minimum visible, unoccluded share of a ROI in a photo"),
            ProcessingNumberParameterType.Double, 0.5, minValue=0.0, maxValue=1.0), 2)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterNumber(
            self.MAX_IMAGES, self.tr("Best photos to keep per ROI (0 = all)"),
            ProcessingNumberParameterType.Integer, 0, minValue=0))
        p = QgsProcessingParameterBoolean(
            self.DISTORTION, self.tr("Apply the lens distortion (off for undistorted photos)"), True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = QgsProcessingParameterNumber(
            self.MARGIN, self.tr("Margin around the crops (pixels)"),
            ProcessingNumberParameterType.Integer, 0, minValue=0, maxValue=10000)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("ROIs in photo pixels (x = column, y = −row)"),
            ProcessingSourceType.VectorPolygon))
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT_SUMMARY, self.tr("ROIs with their photo count and best photo"),
            ProcessingSourceType.VectorPolygon))
        self.addParameter(QgsProcessingParameterFileDestination(
            self.OUTPUT_JSON, self.tr("EasyIDP back2raw JSON"), fileFilter="JSON files (*.json)",
            optional=True, createByDefault=False))
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.CROPS_FOLDER, self.tr("Crops of the raw photos"), optional=True,
            createByDefault=False))
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.PREVIEW_FOLDER, self.tr("Preview per ROI (its best photos)"), optional=True,
            createByDefault=False))
        self.add_overwrite_parameter()

    # --- running ----------------------------------------------------------------------------
    def run_tool(self, parameters, context, feedback):
        from ...core.projection import back_project, crop_photos, resolve_photos

        recon = open_project_parameter(self, parameters, context, feedback)
        source, rois, features = rois_parameter(self, parameters, context, feedback)

        dsm = dsm_parameter(self, parameters, context)
        heights = height_source_parameter(self, parameters, context, features, dsm)

        occlusion = self.parameterAsBool(parameters, self.OCCLUSION, context) and dsm is not None
        if self.parameterAsBool(parameters, self.OCCLUSION, context) and dsm is None:
            feedback.pushInfo(self.tr("No DSM given: occlusion is not tested."))
        photos = self.parameterAsFile(parameters, self.PHOTOS, context) or None
        crops = optional_destination(self, parameters, self.CROPS_FOLDER, context)
        previews = optional_destination(self, parameters, self.PREVIEW_FOLDER, context)
        json_path = optional_destination(self, parameters, self.OUTPUT_JSON, context)
        span = 60.0 if (crops or previews) else 95.0

        feedback.pushInfo(self.tr("Projecting {n} ROIs into {m} photos ({h})").format(
            n=len(rois), m=len(recon.aligned_cameras), h=heights.describe()))
        result = back_project(
            rois, recon, heights=heights,
            distortion=self.parameterAsBool(parameters, self.DISTORTION, context),
            clip=self.parameterAsEnum(parameters, self.CLIP, context) == 0,
            occlusion_dsm=dsm if occlusion else None,
            min_visible=self.parameterAsDouble(parameters, self.MIN_VISIBLE, context),
            max_images=self.parameterAsInt(parameters, self.MAX_IMAGES, context),
            progress=lambda p: feedback.setProgress(5 + span * p / 100.0),
            is_cancelled=feedback.isCanceled)
        for note in result.notes:
            feedback.pushWarning(note)
        for name, why in list(result.unseen.items())[:50]:
            feedback.pushWarning(self.tr("ROI '{name}': {why}").format(name=name, why=why))
        if len(result.unseen) > 50:
            feedback.pushWarning(self.tr("… and {n} more ROIs without a photo").format(
                n=len(result.unseen) - 50))

        found, missing = resolve_photos(result.photo_labels, result.photo_paths, photos or None)
        paths = [found.get(lab, p) for lab, p in zip(result.photo_labels, result.photo_paths)]
        out = self._write_pixels(parameters, context, result, paths)
        summary = self._write_summary(parameters, context, source, features, result)
        outputs = {self.OUTPUT: out, self.OUTPUT_SUMMARY: summary}
        if json_path:
            outputs[self.OUTPUT_JSON] = result.write_easyidp_json(json_path)
        if crops or previews:
            feedback.pushInfo(self.tr("Cutting the ROIs out of the photos…"))
            written = crop_photos(
                result, crops, photos, previews_folder=previews,
                margin=self.parameterAsInt(parameters, self.MARGIN, context),
                overwrite=self.overwrite(parameters, context),
                progress=lambda p: feedback.setProgress(5 + span + (95 - span) * p / 100.0),
                is_cancelled=feedback.isCanceled)
            for label, why in written.skipped_photos.items():
                feedback.pushWarning(self.tr("Photo {label} skipped: {why}").format(label=label, why=why))
            feedback.pushInfo(self.tr("{n} crops and {p} previews written.").format(
                n=len(written.files), p=len(written.previews)))
            if crops:
                outputs[self.CROPS_FOLDER] = crops
            if previews:
                outputs[self.PREVIEW_FOLDER] = previews
        project = os.path.basename(self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        presentation.present(self, context, out, self.OUTPUT, pixel_style(),
                             self.tr("{rois} in the photos of {project} (photo pixels)").format(
                                 rois=source.sourceName(), project=project))
        presentation.present(self, context, summary, self.OUTPUT_SUMMARY, summary_style(),
                             self.tr("{rois}: photos of {project} that see them").format(
                                 rois=source.sourceName(), project=project))
        feedback.setProgress(100)
        seen = int((result.photos_per_roi() > 0).sum())
        feedback.pushInfo(self.tr("{k} ROI × photo pairs for {seen} of {n} ROIs; {u} ROIs in no photo.").format(
            k=len(result), seen=seen, n=len(rois), u=len(result.unseen)))
        return outputs

    def _write_pixels(self, parameters, context, result, paths):
        fields = QgsFields()
        for name, kind in (("roi", FieldType.QString), ("photo", FieldType.QString),
                           ("photo_path", FieldType.QString), ("rank", FieldType.Int),
                           ("score", FieldType.Double), ("view_angle", FieldType.Double),
                           ("gsd", FieldType.Double), ("visible_fraction", FieldType.Double),
                           ("occluded_fraction", FieldType.Double),
                           ("centre_distance", FieldType.Double), ("clipped", FieldType.Bool),
                           ("photo_width", FieldType.Int), ("photo_height", FieldType.Int)):
            fields.append(QgsField(name, kind))
        sink, dest = self.parameterAsSink(parameters, self.OUTPUT, context, fields,
                                          WkbType.MultiPolygon, pixel_crs())
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT))
        for i in range(len(result)):
            j = int(result.photo_index[i])
            f = QgsFeature(fields)
            f.setAttributes([result.roi_names[int(result.roi[i])], str(result.photo[i]),
                             paths[j] or "", int(result.rank[i]), _num(result.score[i]),
                             _num(result.view_angle[i]), _num(result.gsd[i]),
                             _num(result.visible_fraction[i]), _num(result.occluded_fraction[i]),
                             _num(result.centre_distance[i]), bool(result.clipped[i]),
                             int(result.image_sizes[j][0]), int(result.image_sizes[j][1])])
            f.setGeometry(pixel_geometry(result.polygons_of(i)))
            sink.addFeature(f, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        # a file gets the undefined Cartesian CRS (GeoPackage srs_id -1). A photo opened without
        # georeference has no CRS; QGIS gives memory layers EPSG:4326 by default, which would
        # reproject the pixels: make the memory layer (held by the context) CRS-less like the
        # photo. A file is not opened here: that would cost a second connection to the file just
        # written (and waits on its lock while a sink is open).
        layer = context.temporaryLayerStore().mapLayer(dest)
        if layer is not None and layer.crs().isValid():
            layer.setCrs(QgsCoordinateReferenceSystem())
        return dest

    def _write_summary(self, parameters, context, source, features, result):
        extra = QgsFields()
        extra.append(QgsField("photos", FieldType.Int))
        extra.append(QgsField("best_photo", FieldType.QString))
        extra.append(QgsField("best_score", FieldType.Double))
        fields = QgsProcessingUtils.combineFields(source.fields(), extra)
        sink, dest = self.parameterAsSink(parameters, self.OUTPUT_SUMMARY, context, fields,
                                          source.wkbType(), source.sourceCrs())
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT_SUMMARY))
        counts = result.photos_per_roi()
        best = result.best()
        for k, feat in enumerate(features):
            i = best.get(result.roi_names[k])
            f = QgsFeature(fields)
            f.setGeometry(feat.geometry())
            f.setAttributes(list(feat.attributes()) + [
                int(counts[k]), None if i is None else str(result.photo[i]),
                None if i is None else _num(result.score[i])])
            sink.addFeature(f, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        return dest


def pixel_style():
    """ROIs in photo pixels: each ROI's best photo bold green, the other photos thin white,
    labelled with the ROI name (filter by 'photo' to see one photo's ROIs)."""
    return presentation.rank_style("#33dd33", "#f0f0f0", label='"roi"')


def summary_style():
    """ROIs on the map coloured by how many photos see them (the legend gives the counts)."""
    return presentation.graduated_style("photos", decimals=0, ramp="YlGnBu", label=False)


def pixel_geometry(polys) -> QgsGeometry:
    """Photo-pixel polygons → a MultiPolygon with x = column, y = −row (how QGIS places a
    photo opened without georeference)."""
    mp = QgsMultiPolygon()
    for p in polys:
        poly = QgsPolygon()
        rings = [QgsLineString(list(map(float, r[:, 0])) + [float(r[0, 0])],
                               list(map(float, -r[:, 1])) + [float(-r[0, 1])]) for r in p]
        poly.setExteriorRing(rings[0])
        for h in rings[1:]:
            poly.addInteriorRing(h)
        mp.addGeometry(poly)
    return QgsGeometry(mp)


def _num(v):
    v = float(v)
    return None if math.isnan(v) or math.isinf(v) else v
