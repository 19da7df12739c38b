"""Processing tool: Forward-project polygons (easyidp:forwardprojectpolygons)."""
import os

from qgis.core import (QgsProcessingException, QgsProcessingParameterEnum,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterFile, QgsProcessingParameterNumber,
                       QgsProcessingParameterRasterLayer)

from .. import presentation
from ..compat import (FieldType, ProcessingFileParameterBehavior, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType, WkbType)
from ..crs import crs_string
from ..geometries import multipolygon
from ..parameters import with_help
from ..photo_layers import photo_layer_annotations
from ..progress import feedback_progress
from ..projects import add_project_parameters, open_project_parameter
from ..rasters import geotiff_source
from ..sinks import fields_of, write_features
from .base import CoreStep, EasyIDPAlgorithm

MERGE_OPTIONS = ("none", "union", "best", "fuse")


class ForwardProjectPolygons(EasyIDPAlgorithm):
    INPUT = "INPUT"
    INPUT_FOLDER = "INPUT_FOLDER"
    INPUT_LAYER = "INPUT_LAYER"
    PROJECT = "PROJECT"
    CHUNK = "CHUNK"
    PROJECT_CRS = "PROJECT_CRS"
    DSM = "DSM"
    MERGE = "MERGE"
    COCO_IMAGES = "COCO_IMAGES"
    TILES = "TILES"
    DENSIFY = "DENSIFY"
    OUTPUT = "OUTPUT"

    NAME = "forwardprojectpolygons"
    # the DSM; merging the views, fused contours
    REQUIRES = ("tifffile", "imagecodecs", "shapely", "skimage", "PIL")
    DISPLAY = "Forward-project polygons"
    GROUP = "Projection"
    GROUP_ID = "projection"
    HELP = (
        "Brings polygons drawn or detected on the raw photos (LabelMe, COCO, YOLO, or the "
        "photo-pixel layer written by Back-project ROIs) to the map, with their true position, "
        "area and perimeter: every vertex's pixel becomes a ray through the solved camera "
        "(lens distortion included) and its first hit on the DSM is the vertex on the map. "
        "Exact on any terrain and canopy (not a flat-ground homography).\n\n"
        "Input, one of: a file (LabelMe .json, COCO .json, YOLO .txt); a folder (LabelMe .json "
        "files or YOLO .txt files, with classes.txt or data.yaml for class names); or a "
        "photo-pixel layer (x = column, y = −row, field 'photo'). Each image is matched to a "
        "photo of the project by file name; an image that is not in the project, or whose size "
        "differs from the camera's, is refused with its name. Detections on the tiles of a "
        "tiled training set (YOLO or LabelMe files named after the tiles) need its tile index "
        "(tiles.json): they are shifted back into their photo's pixels; COCO files of the set "
        "carry their tile windows themselves.\n\n"
        "Edges are densified in the photo (a vertex every few pixels) so that long edges follow "
        "the surface. A vertex whose ray misses the DSM, leaves it or enters nodata is dropped "
        "and its polygon marked complete = false (and reported), never silently reshaped.\n\n"
        "Merge: 'none' keeps one polygon per photo; 'union' merges the overlapping polygons "
        "of one label from several photos into one; 'best' keeps the best view (complete, "
        "highest score, most nadir); 'fuse' is for detections with scores (COCO results with "
        "the COCO images file, YOLO with confidence, LabelMe): duplicates in a photo are "
        "suppressed, the views of one object grouped by overlap and distance, and each object "
        "gets the outline most of its views agree on, its number of views, the photos that "
        "could have seen it (expected_views), mean and max score, its position and DSM height, "
        "and a confidence (mean score × views / expected views). Fields: photo, label, score, area_m2 and perimeter_m "
        "(planimetric, metres), views, complete, missing (vertices without a hit), and for "
        "'fuse' expected_views, max_score and confidence. Output in "
        "the DSM's CRS, heights from the DSM.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        # one of three inputs is needed: QGIS marks each [optional], so each label says so
        one_of = self.tr("Give exactly one of the three annotation inputs: a file, a folder or a "
                         "photo-pixel layer.")
        self.addParameter(with_help(QgsProcessingParameterFile(
            self.INPUT, self.tr("Annotations, 1 of 3: a LabelMe, COCO or YOLO file"),
            behavior=ProcessingFileParameterBehavior.File, optional=True,
            fileFilter="Annotations (*.json *.txt);;All files (*.*)"), one_of))
        self.addParameter(with_help(QgsProcessingParameterFile(
            self.INPUT_FOLDER, self.tr("Annotations, 2 of 3: a LabelMe or YOLO folder"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True), one_of))
        self.addParameter(with_help(QgsProcessingParameterFeatureSource(
            self.INPUT_LAYER, self.tr("Annotations, 3 of 3: a photo-pixel polygon layer"),
            [ProcessingSourceType.VectorPolygon], optional=True),
            one_of + " " + self.tr("Layer coordinates: x = column, y = −row.")))
        add_project_parameters(self)
        self.addParameter(QgsProcessingParameterRasterLayer(self.DSM, self.tr("DSM (GeoTIFF)")))
        self.addParameter(QgsProcessingParameterEnum(
            self.MERGE, self.tr("Merge the same object seen in several photos"),
            options=[self.tr("None (one polygon per photo)"), self.tr("Union of the views"),
                     self.tr("Best view"),
                     self.tr("Fuse detections (NMS, consensus outline, confidence)")],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterFile(
            self.COCO_IMAGES, self.tr("COCO images file that a COCO results list refers to"),
            behavior=ProcessingFileParameterBehavior.File, optional=True,
            fileFilter="COCO (*.json)"))
        self.addParameter(QgsProcessingParameterFile(
            self.TILES, self.tr("Tile index (tiles.json), for annotations on tiles"),
            behavior=ProcessingFileParameterBehavior.File, optional=True,
            fileFilter="Tile index (tiles.json);;JSON (*.json)"))
        p = self.decimals(QgsProcessingParameterNumber(
            self.DENSIFY, self.tr("Densify edges: a vertex every … photo pixels (0: off)"),
            ProcessingNumberParameterType.Double, 4.0, minValue=0.0, maxValue=1000.0), 1)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("Polygons on the map"), ProcessingSourceType.VectorPolygon))
        self.add_overwrite_parameter()

    def core_step(self, parameters, context, feedback):
        from ...core.annotations import PhotoIndex, read_annotations
        from ...core.projection import forward_project_photos
        from ...core.raster import DSM

        path = self.parameterAsFile(parameters, self.INPUT, context)
        folder = self.parameterAsFile(parameters, self.INPUT_FOLDER, context)
        layer = self.parameterAsSource(parameters, self.INPUT_LAYER, context) \
            if parameters.get(self.INPUT_LAYER) not in (None, "") else None
        given = [x for x in (path, folder, layer) if x]
        if len(given) != 1:
            raise QgsProcessingException(self.tr(
                "Give exactly one input: an annotation file, a folder of annotation files, or a "
                "photo-pixel layer."))
        recon = open_project_parameter(self, parameters, context, feedback)
        dsm_layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        dsm = DSM(geotiff_source(dsm_layer, self.tr("DSM")), crs=crs_string(dsm_layer.crs()))
        if layer is not None:
            index = PhotoIndex(recon)
            items = [(a, index.find(a.image, a.source)) for a in photo_layer_annotations(layer, feedback)]
        else:
            notes = []
            items = read_annotations(path or folder, recon,
                                     self.parameterAsFile(parameters, self.COCO_IMAGES, context) or None,
                                     tiles=self.parameterAsFile(parameters, self.TILES, context) or None,
                                     notes=notes)
            for note in notes:              # which photo a LabelMe file was put on, and why
                feedback.pushWarning(note)
        what = layer.sourceName() if layer is not None else os.path.basename((path or folder).rstrip("/\\"))
        return CoreStep(forward_project_photos, dict(
            items=items, recon=recon, dsm=dsm,
            merge=MERGE_OPTIONS[self.parameterAsEnum(parameters, self.MERGE, context)],
            densify=self.parameterAsDouble(parameters, self.DENSIFY, context),
            progress=feedback_progress(feedback, 0, 90)),
            dict(dsm_layer=dsm_layer, what=what))

    def write_outputs(self, parameters, context, feedback, step, result):
        dsm_layer = step.inputs["dsm_layer"]
        if result.skipped:
            feedback.pushWarning(self.tr("{n} lines or points skipped: only polygons are "
                                         "forward-projected by this tool.").format(n=result.skipped))
        fields = fields_of((("photo", FieldType.QString), ("label", FieldType.QString),
                            ("score", FieldType.Double), ("area_m2", FieldType.Double),
                            ("perimeter_m", FieldType.Double), ("views", FieldType.Int),
                            ("complete", FieldType.Bool), ("missing", FieldType.Int),
                            ("expected_views", FieldType.Int), ("max_score", FieldType.Double),
                            ("confidence", FieldType.Double)))
        counts = {"written": 0, "incomplete": 0}

        def rows():
            for m in result.polygons:
                geom = multipolygon(m.parts, z=True, min_vertices=3)
                missing = sum(f.missing for f in m.members)
                if not m.complete:
                    counts["incomplete"] += 1
                    reasons = "; ".join(f"{f.photo}: {f.why_incomplete()}" for f in m.members
                                        if not f.complete)
                    feedback.pushWarning(self.tr("'{label}' is incomplete ({why}).").format(
                        label=m.label, why=reasons))
                if geom.isEmpty():
                    continue
                counts["written"] += 1
                yield ([";".join(m.photos), m.label, m.score, _num(m.area_m2),
                        _num(m.perimeter_m), m.views, bool(m.complete), missing,
                        getattr(m, "expected_views", None), getattr(m, "max_score", None),
                        getattr(m, "confidence", None)], geom)
        dest = write_features(self, parameters, self.OUTPUT, context, fields,
                              WkbType.MultiPolygonZ, dsm_layer.crs(), rows())
        project = os.path.basename(self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        presentation.present(self, context, dest, self.OUTPUT, detection_style(),
                             self.tr("{what} on the map (through {project} onto {dsm})").format(
                                 what=step.inputs["what"], project=project, dsm=dsm_layer.name()))
        feedback.pushInfo(self.tr("{n} polygons from {p} photos written to the map "
                                  "({i} incomplete).").format(n=counts["written"],
                                                              p=len(step.kwargs["items"]),
                                                              i=counts["incomplete"]))
        return {self.OUTPUT: dest}


def detection_style():
    """Polygons brought from the photos: magenta outlines over a faint fill, labelled; dashed
    where a vertex's ray found no DSM (complete = false)."""
    return presentation.outline_style("#ff00c8", 0.5, dashed_when='NOT "complete"',
                                      legend=(presentation.tr("Incomplete: a vertex found no DSM"),
                                              presentation.tr("Complete")),
                                      label='"label"', fill_alpha=40,
                                      tip='<b>[% "label" %]</b><br>[% round("area_m2", 3) %] m², '
                                          '[% "views" %] view(s)')


def _num(v):
    import math
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)
