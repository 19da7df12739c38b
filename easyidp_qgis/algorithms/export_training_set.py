"""Processing tool: Export a training set (easyidp:exporttrainingset)."""
from qgis.core import (QgsCoordinateTransform, QgsFeatureRequest, QgsProcessingException,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProcessingParameterFile,
                       QgsProcessingParameterFolderDestination, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer, QgsWkbTypes)

from ..compat import (GeometryType, MessageLevel, ProcessingFileParameterBehavior,
                      ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType)
from ..crs import crs_string
from ..parameters import translatable
from ..physical_values import add_value_parameters, value_parameters
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import geotiff_source
from ..rois import rois_from_source
from ..values import is_null
from .base import CoreStep, EasyIDPAlgorithm


def show_lasting_warning(title: str, text: str, bar=None) -> bool:
    """A warning in the message bar (default the desktop's) that stays until dismissed
    (duration 0); False without a desktop (qgis_process: the log's WARNING lines say it)."""
    if bar is None:
        try:
            from qgis.utils import iface
        except ImportError:
            return False
        if iface is None or not hasattr(iface, "messageBar"):
            return False
        bar = iface.messageBar()
    bar.pushMessage(title, text, MessageLevel.Warning, 0)
    return True

SPLITS = ("region", "photo")


class ExportTrainingSet(EasyIDPAlgorithm):
    OBJECTS = "OBJECTS"
    CLASS_FIELD = "CLASS_FIELD"
    INSTANCE_FIELD = "INSTANCE_FIELD"
    POINT_RADIUS = "POINT_RADIUS"
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    DSM = "DSM"
    PHOTOS = "PHOTOS"
    BEST_K = "BEST_K"
    MIN_VISIBLE = "MIN_VISIBLE"
    TILE_SIZE = "TILE_SIZE"
    TILE_OVERLAP = "TILE_OVERLAP"
    SPLIT = "SPLIT"
    VAL_FRACTION = "VAL_FRACTION"
    REGION_SIZE = "REGION_SIZE"
    SEED = "SEED"
    OUTPUT_FOLDER = "OUTPUT_FOLDER"

    NAME = "exporttrainingset"
    REQUIRES = ("tifffile", "imagecodecs", "PIL")  # orthomosaic tiles; photos, headers
    DISPLAY = "Export a training set"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Turns objects labelled once on the map (polygons, or points with a radius) into a "
        "deep-learning training set on the raw photos: COCO instances (polygons and boxes), "
        "YOLO segment and detect labels with their data.yaml, and LabelMe files.\n\n"
        "Each object is back-projected into every photo that sees it (heights from the DSM, "
        "lens distortion, occlusion tested on the DSM, photos ranked as Back-project ROIs does). "
        "An object is labelled in a photo when at least the minimum visible share of it is in the "
        "frame and not hidden by anything outside it (what its own canopy hides of it, such as "
        "the soil between its rows, does not count); its outline is clipped to the frame (hidden parts are "
        "not cut out). Best photos per object: keep only the k best-ranked (0 = all).\n\n"
        "Tiles: with a tile size, photos are cut into tiles of that size (pixels) overlapping by "
        "the overlap; outlines are clipped to each tile and a part smaller than the minimum "
        "visible share of the object is dropped. Without, whole photos are copied.\n\n"
        "Photos that do not decode (truncated, or not images) are named in the log and left "
        "out with their labels.\n\n"
        "Values of the images: as stored (the default: the photos copied, tiles as PNG), "
        "temperature in °C or reflectance, as in Plot statistics from photos. PNG and JPEG "
        "cannot hold these values, so every image, whole photo or tile, is then a float32 TIFF "
        "(NAME.tif; the labels name it) with the unit in its GDAL metadata and NaN where a "
        "pixel is saturated or unreadable; a photo that holds no such values is left out with "
        "its labels. Networks train on either.\n\n"
        "Split: whole images go to train or validation, none is left out: by field region "
        "(square cells of the region size, in the DSM's map units; an image goes with the region "
        "of most of its objects) or by photo. The log gives the images and labels of each set "
        "and warns when validation is empty or under half the fraction asked. An object seen in "
        "images of both sets is counted.\n\n"
        "Tiles: a tile size that cuts a photo into more than 4096 tiles is refused.\n\n"
        "Output folder: images/{train,val}, labels/{train,val} and data.yaml (YOLO segment), "
        "yolo_detect/ (YOLO detect), coco/instances_{train,val}.json, labelme/{train,val} and "
        "training_set.json (counts, rules and the list of files written). The folder holds only "
        "the set: other files in it are refused, with a list of them; an older set is replaced "
        "only with 'Overwrite existing files', which removes exactly the files its "
        "training_set.json lists.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.OBJECTS, self.tr("Labelled objects (polygons or points)"),
            [ProcessingSourceType.VectorPolygon, ProcessingSourceType.VectorPoint]))
        self.addParameter(QgsProcessingParameterField(
            self.CLASS_FIELD, self.tr("Class field"), parentLayerParameterName=self.OBJECTS))
        self.addParameter(QgsProcessingParameterField(
            self.INSTANCE_FIELD, self.tr("Instance id field (default: feature id)"),
            parentLayerParameterName=self.OBJECTS, optional=True))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.POINT_RADIUS, self.tr("Radius of the disc around labelled points (map units)"),
            ProcessingNumberParameterType.Double, 0.1, minValue=0.0), 3))
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterRasterLayer(self.DSM, self.tr("DSM (GeoTIFF)")))
        self.addParameter(QgsProcessingParameterFile(
            self.PHOTOS, self.tr("Photos folder (when the photos moved; matched by file name)"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        self.addParameter(QgsProcessingParameterNumber(
            self.BEST_K, self.tr("Best photos per object (0 = all)"),
            ProcessingNumberParameterType.Integer, 0, minValue=0))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.MIN_VISIBLE, self.tr("Minimum visible, unoccluded share of an object"),
            ProcessingNumberParameterType.Double, 0.5, minValue=0.0, maxValue=1.0), 2))
        self.addParameter(QgsProcessingParameterNumber(
            self.TILE_SIZE, self.tr("Tile size (pixels; 0 = whole photos)"),
            ProcessingNumberParameterType.Integer, 0, minValue=0))
        self.addParameter(QgsProcessingParameterNumber(
            self.TILE_OVERLAP, self.tr("Tile overlap (pixels)"),
            ProcessingNumberParameterType.Integer, 0, minValue=0))
        self.addParameter(QgsProcessingParameterEnum(
            self.SPLIT, self.tr("Train/validation split"),
            options=[self.tr("By field region"), self.tr("By photo")], defaultValue=0))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.VAL_FRACTION, self.tr("Validation fraction"),
            ProcessingNumberParameterType.Double, 0.2, minValue=0.0, maxValue=0.95), 2))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.REGION_SIZE, self.tr("Region size for the split (map units of the DSM)"),
            ProcessingNumberParameterType.Double, 10.0, minValue=0.0), 2))
        p = QgsProcessingParameterNumber(self.SEED, self.tr("Random seed of the split"),
                                         ProcessingNumberParameterType.Integer, 0, minValue=0)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Training set folder")))
        self.add_overwrite_parameter()
        add_value_parameters(self, translatable("Values of the images"))

    def core_step(self, parameters, context, feedback):
        from ...core.projection import export_training_set

        source = self.parameterAsSource(parameters, self.OBJECTS, context)
        if source is None:
            raise QgsProcessingException(self.tr("Labelled objects: no layer given, or it could "
                                                 "not be loaded."))
        class_field = self.parameterAsString(parameters, self.CLASS_FIELD, context)
        id_field = self.parameterAsString(parameters, self.INSTANCE_FIELD, context)
        for f in (class_field, id_field):
            if f and source.fields().indexFromName(f) < 0:
                raise QgsProcessingException(self.tr("Labelled objects: the layer has no field "
                                                     "'{f}'.").format(f=f))
        recon = open_project_parameter(self, parameters, context, feedback)
        dsm_layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        dsm = geotiff_source(dsm_layer, self.tr("DSM"))
        crs = dsm_layer.crs()
        rois, classes = self._objects(parameters, context, feedback, source, class_field,
                                      id_field, crs)
        return CoreStep(export_training_set, dict(
            rois=rois, classes=classes, recon=recon, dsm=dsm,
            output_folder=self.parameterAsString(parameters, self.OUTPUT_FOLDER, context),
            source_crs=crs_string(crs),
            photos_folder=self.parameterAsFile(parameters, self.PHOTOS, context) or None,
            max_views=self.parameterAsInt(parameters, self.BEST_K, context),
            min_visible=self.parameterAsDouble(parameters, self.MIN_VISIBLE, context),
            tile_size=self.parameterAsInt(parameters, self.TILE_SIZE, context),
            tile_overlap=self.parameterAsInt(parameters, self.TILE_OVERLAP, context),
            split=SPLITS[self.parameterAsEnum(parameters, self.SPLIT, context)],
            val_fraction=self.parameterAsDouble(parameters, self.VAL_FRACTION, context),
            region_size=self.parameterAsDouble(parameters, self.REGION_SIZE, context),
            seed=self.parameterAsInt(parameters, self.SEED, context),
            overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback, 5, 100), is_cancelled=feedback.isCanceled,
            **value_parameters(self, parameters, context)), {})

    def write_outputs(self, parameters, context, feedback, step, result):
        for label, why in result.skipped_photos.items():
            feedback.pushWarning(self.tr("Photo {label} skipped: {why}").format(label=label, why=why))
        for name, why in list(result.unseen.items())[:50]:
            feedback.pushWarning(self.tr("Object '{name}': {why}").format(name=name, why=why))
        for note in result.notes:
            feedback.pushInfo(note)
        if result.removed:
            feedback.pushInfo(self.tr("Removed {n} file(s) of the older training set in the "
                                      "folder.").format(n=len(result.removed)))
        for split in ("train", "val"):
            feedback.pushInfo(self.tr("{split}: {images} images, {labels} labels of {objects} "
                                      "objects").format(
                split=split, images=result.images.get(split, 0),
                labels=result.annotations.get(split, 0), objects=result.objects.get(split, 0)))
        feedback.pushInfo(result.summary())
        self._warnings = []
        for w in result.warnings:
            text = self.tr("Training set: {warning}").format(warning=w)
            feedback.pushWarning(text)
            self._warnings.append(text)
        return {self.OUTPUT_FOLDER: result.folder}

    def postProcessAlgorithm(self, context, feedback):  # noqa: N802 (QGIS API)
        """In the desktop, the split's warnings also go to the message bar, where they stay
        until dismissed (the log scrolls away)."""
        warnings = getattr(self, "_warnings", [])
        if warnings:
            show_lasting_warning(self.tr("EasyIDP"), " ".join(warnings))
        return {}

    def _objects(self, parameters, context, feedback, source, class_field, id_field, crs):
        """(ROISet in the DSM's CRS, classes): polygons as they are, points as discs."""
        from ...core.projection import point_discs
        kind = QgsWkbTypes.geometryType(source.wkbType())
        if kind == GeometryType.Polygon:
            rois, features = rois_from_source(source, id_field, self.tr("Labelled objects"),
                                              feedback, crs, context)
        elif kind == GeometryType.Point:
            radius = self.parameterAsDouble(parameters, self.POINT_RADIUS, context)
            if not radius > 0:
                raise QgsProcessingException(self.tr(
                    "Labelled points need a positive disc radius (map units)."))
            tr = QgsCoordinateTransform(source.sourceCrs(), crs, context.transformContext())
            names, xy, features = [], [], []
            for feat in source.getFeatures(QgsFeatureRequest()):
                g = feat.geometry()
                if g is None or g.isEmpty():
                    continue
                g.transform(tr)
                for p in (g.asMultiPoint() if g.isMultipart() else [g.asPoint()]):
                    name = feat[id_field] if id_field else feat.id()
                    names.append(str(feat.id()) if is_null(name) else str(name))
                    xy.append((p.x(), p.y()))
                    features.append(feat)
            rois = point_discs(names, xy, radius, crs=crs_string(crs))
        else:
            raise QgsProcessingException(self.tr(
                "Labelled objects: polygons or points are needed, not lines."))
        classes = []
        for feat, roi in zip(features, rois):
            v = feat[class_field]
            if is_null(v) or str(v) == "":
                raise QgsProcessingException(self.tr(
                    "Labelled objects: object '{name}' has no class in the field '{f}'. Fill it "
                    "or filter the layer.").format(name=roi.name, f=class_field))
            classes.append(str(v))
        return rois, classes
