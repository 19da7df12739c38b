"""Processing tool: Back-project ROIs (easyidp:backprojectrois)."""
import math
import os

import numpy as np

from qgis.core import (QgsCoordinateReferenceSystem, QgsProcessingParameterBoolean,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFile, QgsProcessingParameterFileDestination,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterString)

from .. import presentation
from ..compat import (FieldType, ProcessingFileParameterBehavior,
                      ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType, WkbType)
from ..crs import pixel_crs
from ..geometries import pixel_geometries
from ..parameters import optional_destination, translatable
from ..physical_values import add_value_parameters, value_parameters
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import dsm_parameter
from ..rois import add_roi_parameters, rois_parameter
from ..sinks import fields_of, geopackage_file, gpkg_fields, write_features, write_roi_layer
from ..vertex_heights import add_height_parameters, height_source_parameter
from .base import CoreStep, EasyIDPAlgorithm


PIXEL_FIELDS = (("roi", FieldType.QString), ("photo", FieldType.QString),
                ("photo_path", FieldType.QString), ("rank", FieldType.Int),
                ("score", FieldType.Double), ("view_angle", FieldType.Double),
                ("gsd", FieldType.Double), ("visible_fraction", FieldType.Double),
                ("occluded_fraction", FieldType.Double), ("centre_distance", FieldType.Double),
                ("clipped", FieldType.Bool), ("photo_width", FieldType.Int),
                ("photo_height", FieldType.Int), ("uncertainty_px", FieldType.Double))
"""The fields of the ROIs in photo pixels (OUTPUT), one feature per ROI × photo."""


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
    PHOTO = "PHOTO"
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
    REQUIRES = ("tifffile", "imagecodecs", "PIL")  # the DSM; the photos and their headers
    DISPLAY = "Back-project ROIs"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Finds every ROI (plot, tree, plant polygon) in every raw photo of a Metashape or Pix4D "
        "project that sees it, using the cameras the project solved (EasyIDP's back2raw). Raw "
        "photos are sharper than the orthomosaic and free of its seamlines.\n\n"
        "Inputs: the ROI polygons; the project (Metashape .psx/.psz/cameras .xml, Pix4D .p4d or "
        "any file of its 1_initial/params folder, or a folder of drone photos whose EXIF and XMP "
        "tags give rough cameras: each pixel feature then carries its expected error, "
        "uncertainty_px); the height of the ROI vertices, from the "
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
        "per ROI showing its best photos.\n\n"
        "Values of the crops: as stored (the photos' own pixels, the default), temperature in "
        "°C (FLIR radiometric JPEGs by the Planck curve, with the photo's object parameters "
        "unless given; temperature TIFFs by their preset or scale and offset) or reflectance "
        "(MicaSense and DJI multispectral band files), as in Plot statistics from photos. "
        "Temperature and reflectance crops are float32 TIFFs with the unit and what was "
        "applied in their GDAL metadata; saturated or unreadable pixels are NaN (nodata). A "
        "photo that holds no such values is skipped with why.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        add_roi_parameters(self)
        add_project_parameters(self)
        add_height_parameters(self)
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Photos folder (when the photos moved; matched by file name)"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        p = QgsProcessingParameterString(self.PHOTO, self.tr("Only this photo"), optional=True)
        p.setHelp(self.tr("Its file name or camera label; empty: every photo"))
        self.addParameter(p)
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
        add_value_parameters(self, translatable("Values of the crops"))

    # --- running ----------------------------------------------------------------------------
    def core_step(self, parameters, context, feedback):
        from ...core.projection import back_project

        recon = open_project_parameter(self, parameters, context, feedback)
        source, rois, features = rois_parameter(self, parameters, context, feedback)

        dsm = dsm_parameter(self, parameters, context)
        heights = height_source_parameter(self, parameters, context, features, dsm)

        occlusion = self.parameterAsBool(parameters, self.OCCLUSION, context) and dsm is not None
        if self.parameterAsBool(parameters, self.OCCLUSION, context) and dsm is None:
            feedback.pushInfo(self.tr("No DSM given: occlusion is not tested."))
        crops = optional_destination(self, parameters, self.CROPS_FOLDER, context)
        previews = optional_destination(self, parameters, self.PREVIEW_FOLDER, context)
        span = 60.0 if (crops or previews) else 95.0
        photo = self.parameterAsString(parameters, self.PHOTO, context).strip()
        cameras = recon.select_cameras([photo]) if photo else recon.aligned_cameras
        feedback.pushInfo(self.tr("Projecting {n} ROIs into {m} photos ({h})").format(
            n=len(rois), m=len(cameras), h=heights.describe()))
        return CoreStep(back_project, dict(
            rois=rois, recon=recon, heights=heights, cameras=[c.label for c in cameras],
            distortion=self.parameterAsBool(parameters, self.DISTORTION, context),
            clip=self.parameterAsEnum(parameters, self.CLIP, context) == 0,
            occlusion_dsm=dsm if occlusion else None,
            min_visible=self.parameterAsDouble(parameters, self.MIN_VISIBLE, context),
            max_views=self.parameterAsInt(parameters, self.MAX_IMAGES, context),
            progress=feedback_progress(feedback, 5, 5 + span), is_cancelled=feedback.isCanceled),
            dict(source=source, features=features, crops=crops, previews=previews, span=span))

    def write_outputs(self, parameters, context, feedback, step, result):
        from ...core.projection import crop_photos, resolve_photos
        source, features, crops, previews, span = (step.inputs[k] for k in (
            "source", "features", "crops", "previews", "span"))
        rois = step.kwargs["rois"]
        photos = self.parameterAsFile(parameters, self.PHOTOS, context) or None
        json_path = optional_destination(self, parameters, self.OUTPUT_JSON, context)
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
        values = value_parameters(self, parameters, context)
        if values["values"] != "stored" and not (crops or previews):
            feedback.pushWarning(self.tr("The values chosen apply to the crops and previews "
                                         "only, and neither folder was given."))
        if crops or previews:
            feedback.pushInfo(self.tr("Cutting the ROIs out of the photos…"))
            written = crop_photos(
                result, crops, photos, previews_folder=previews,
                margin=self.parameterAsInt(parameters, self.MARGIN, context),
                overwrite=self.overwrite(parameters, context),
                progress=feedback_progress(feedback, 5 + span, 100),
                is_cancelled=feedback.isCanceled, **values)
            for label, why in written.skipped_photos.items():
                feedback.pushWarning(self.tr("Photo {label} skipped: {why}").format(label=label, why=why))
            feedback.pushInfo(self.tr("{n} crops and {p} previews written.").format(
                n=len(written.files), p=len(written.previews)))
            if crops:
                outputs[self.CROPS_FOLDER] = crops
            if previews:
                outputs[self.PREVIEW_FOLDER] = previews
        project = os.path.basename(self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        if presentation.present(self, context, out, self.OUTPUT, pixel_style(),
                                self.tr("{rois} in the photos of {project} (photo pixels)").format(
                                    rois=source.sourceName(), project=project), in_map=False):
            feedback.pushInfo(self.tr("The ROIs in photo pixels open in the EasyIDP photo "
                                      "viewer (toolbar), over their photos, not in the map."))
        presentation.present(self, context, summary, self.OUTPUT_SUMMARY, summary_style(),
                             self.tr("{rois}: photos of {project} that see them").format(
                                 rois=source.sourceName(), project=project))
        feedback.setProgress(100)
        seen = int((result.photos_per_roi() > 0).sum())
        feedback.pushInfo(self.tr("{k} ROI × photo pairs for {seen} of {n} ROIs; {u} ROIs in no photo.").format(
            k=len(result), seen=seen, n=len(rois), u=len(result.unseen)))
        return outputs

    def _write_pixels(self, parameters, context, result, paths):
        # column by column: numpy → Python values once per column, geometries in one pass
        sizes = np.asarray(result.image_sizes, np.int64).reshape(-1, 2)[result.photo_index]
        paths = [p or "" for p in paths]
        photos = [str(p) for p in result.photo.tolist()]
        uncertainty = {p: _num(result.uncertainty_px.get(p)) for p in set(photos)}
        columns = [[result.roi_names[k] for k in result.roi.tolist()], photos,
                   [paths[j] for j in result.photo_index.tolist()],
                   np.asarray(result.rank).astype(int).tolist(),
                   *(_numbers(c) for c in (result.score, result.view_angle, result.gsd,
                                           result.visible_fraction, result.occluded_fraction,
                                           result.centre_distance)),
                   np.asarray(result.clipped, bool).tolist(),
                   sizes[:, 0].tolist(), sizes[:, 1].tolist(),
                   [uncertainty[p] for p in photos]]
        path = geopackage_file(self, parameters, self.OUTPUT, context)
        if path:
            # a new GeoPackage file: the engine writes it (atomically, no QgsFeature per pair,
            # no spatial index; 47,477 pairs: about 0.2 s of CPU, the sink about 0.8 s). QGIS's
            # sink would give it the undefined Cartesian CRS too (srs_id -1).
            from ...core.gpkg import GpkgTable, encoded_multipolygons, write_geopackage
            write_geopackage(path, [GpkgTable(
                os.path.splitext(os.path.basename(path))[0], gpkg_fields(PIXEL_FIELDS),
                list(zip(*columns)), encoded_multipolygons(result.polygons, flip_y=True))])
            return path
        fields = fields_of(PIXEL_FIELDS)
        rows = zip(map(list, zip(*columns)), pixel_geometries(result.polygons))
        dest = write_features(self, parameters, self.OUTPUT, context, fields, WkbType.MultiPolygon,
                              pixel_crs(), rows)
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
        counts = result.photos_per_roi()
        best = result.best()
        rows = []
        for k, feat in enumerate(features):
            i = best.get(result.roi_names[k])
            rows.append((feat, [int(counts[k]), None if i is None else str(result.photo[i]),
                                None if i is None else _num(result.score[i])]))
        return write_roi_layer(self, parameters, self.OUTPUT_SUMMARY, context, source, rows,
                               [("photos", FieldType.Int), ("best_photo", FieldType.QString),
                                ("best_score", FieldType.Double)])


def pixel_style():
    """ROIs in photo pixels: each ROI's best photo bold green, the other photos thin white,
    labelled with the ROI name (filter by 'photo' to see one photo's ROIs)."""
    return presentation.rank_style("#33dd33", "#f0f0f0", label='"roi"')


def summary_style():
    """ROIs on the map coloured by how many photos see them (the legend gives the counts)."""
    return presentation.graduated_style("photos", decimals=0, ramp="YlGnBu", label=False,
                                        unit=presentation.tr("photos"))


def _numbers(values) -> list:
    """Floats as a list, NaN and infinities as None (NULL), as :func:`_num` of each."""
    a = np.asarray(values, np.float64)
    out = a.tolist()
    for k in np.flatnonzero(~np.isfinite(a)).tolist():
        out[k] = None
    return out


def _num(v):
    if v is None:
        return None
    v = float(v)
    return None if math.isnan(v) or math.isinf(v) else v
