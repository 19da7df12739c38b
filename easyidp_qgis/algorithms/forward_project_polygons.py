"""Processing tool: Forward-project photo polygons to the map (easyidp:forwardprojectpolygons)."""
import os

from qgis.core import (QgsFeature, QgsField, QgsFields, QgsGeometry, QgsLineString,
                       QgsMultiPolygon, QgsPolygon, QgsProcessingException,
                       QgsProcessingParameterEnum, QgsProcessingParameterFeatureSink,
                       QgsProcessingParameterFeatureSource, QgsProcessingParameterFile,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterLayer,
                       QgsWkbTypes)

from .. import presentation
from ..compat import (FeatureSinkFlag, FieldType, GeometryType, ProcessingFileParameterBehavior,
                      ProcessingNumberParameterType, ProcessingParameterFlag,
                      ProcessingSourceType, WkbType)
from ..layers import add_project_parameters, crs_string, geotiff_source, open_project_parameter
from ..outputs import close_sink
from .base import EasyIDPAlgorithm

MERGE_OPTIONS = ("none", "union", "best", "fuse")


def photo_layer_annotations(source, feedback=None):
    """PhotoAnnotations per photo from a photo-pixel layer (x = column, y = −row), e.g. the one
    *Back-project ROIs* writes: fields ``photo`` (required), ``roi`` or ``label``, ``score``."""
    from ...core.annotations.model import POLYGON, PhotoAnnotations, PhotoShape
    import numpy as np
    names = source.fields().names()
    if "photo" not in names:
        raise QgsProcessingException(
            f"Photo-pixel layer '{source.sourceName()}': it has no 'photo' field naming the photo "
            "of each polygon (as Back-project ROIs writes).")
    if QgsWkbTypes.geometryType(source.wkbType()) != GeometryType.Polygon:
        raise QgsProcessingException(
            f"Photo-pixel layer '{source.sourceName()}': polygons are needed.")
    label_field = "roi" if "roi" in names else ("label" if "label" in names else None)
    by_photo = {}
    for feat in source.getFeatures():
        if feedback is not None and feedback.isCanceled():
            break
        g = feat.geometry()
        if g is None or g.isEmpty():
            continue
        geom = g.constGet()
        polys = [geom.geometryN(i) for i in range(geom.numGeometries())] if g.isMultipart() else [geom]
        label = str(feat[label_field]) if label_field else str(feat.id())
        score = feat["score"] if "score" in names else None
        try:
            score = None if score is None or str(score) == "NULL" else float(score)
        except (TypeError, ValueError):
            score = None
        for p in polys:
            rings = [p.exteriorRing()] + [p.interiorRing(k) for k in range(p.numInteriorRings())]
            px = [np.array([(q.x(), -q.y()) for q in r.points()])[:-1] for r in rings]
            photo = str(feat["photo"])
            ann = by_photo.setdefault(photo, PhotoAnnotations(source.sourceName(), photo, None,
                                                              None, []))
            ann.shapes.append(PhotoShape(label, POLYGON, px, "layer", score, feat.id()))
    return list(by_photo.values())


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
    DENSIFY = "DENSIFY"
    OUTPUT = "OUTPUT"

    NAME = "forwardprojectpolygons"
    DISPLAY = "Forward-project photo polygons to the map"
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
        "differs from the camera's, is refused with its name.\n\n"
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
        self.addParameter(QgsProcessingParameterFile(
            self.INPUT, self.tr("Annotation file (LabelMe .json, COCO .json or YOLO .txt)"),
            behavior=ProcessingFileParameterBehavior.File, optional=True,
            fileFilter="Annotations (*.json *.txt);;All files (*.*)"))
        self.addParameter(QgsProcessingParameterFile(
            self.INPUT_FOLDER, self.tr("…or a folder of LabelMe .json or YOLO .txt files"),
            behavior=ProcessingFileParameterBehavior.Folder, optional=True))
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.INPUT_LAYER, self.tr("…or a photo-pixel polygon layer (x = column, y = −row)"),
            [ProcessingSourceType.VectorPolygon], optional=True))
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
        p = self.decimals(QgsProcessingParameterNumber(
            self.DENSIFY, self.tr("Densify edges: a vertex every … photo pixels (0: off)"),
            ProcessingNumberParameterType.Double, 4.0, minValue=0.0, maxValue=1000.0), 1)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("Polygons on the map"), ProcessingSourceType.VectorPolygon))
        self.add_overwrite_parameter()

    def run_tool(self, parameters, context, feedback):
        from ...core.annotations import PhotoIndex, read_annotations
        from ...core.projection import forward_project, merge_views
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
            items = read_annotations(path or folder, recon,
                                     self.parameterAsFile(parameters, self.COCO_IMAGES, context) or None)
        merge = MERGE_OPTIONS[self.parameterAsEnum(parameters, self.MERGE, context)]
        densify = self.parameterAsDouble(parameters, self.DENSIFY, context)
        shapes, skipped = [], 0
        for k, (ann, cam) in enumerate(items):
            if feedback.isCanceled():
                break
            polys = [s for s in ann.shapes if s.kind == "polygon"]
            skipped += len(ann.shapes) - len(polys)
            shapes += forward_project(polys, cam, recon, dsm, densify=densify or False,
                                      is_cancelled=feedback.isCanceled)
            feedback.setProgress(90.0 * (k + 1) / max(len(items), 1))
        if skipped:
            feedback.pushWarning(self.tr("{n} lines or points skipped: only polygons are "
                                         "forward-projected by this tool.").format(n=skipped))
        merged = merge_views(shapes, merge, recon=recon, dsm=dsm,
                             photos=[cam.label for _, cam in items]) if merge == "fuse" \
            else merge_views(shapes, merge)

        fields = QgsFields()
        for name, kind in (("photo", FieldType.QString), ("label", FieldType.QString),
                           ("score", FieldType.Double), ("area_m2", FieldType.Double),
                           ("perimeter_m", FieldType.Double), ("views", FieldType.Int),
                           ("complete", FieldType.Bool), ("missing", FieldType.Int),
                           ("expected_views", FieldType.Int), ("max_score", FieldType.Double),
                           ("confidence", FieldType.Double)):
            fields.append(QgsField(name, kind))
        sink, dest = self.parameterAsSink(parameters, self.OUTPUT, context, fields,
                                          WkbType.MultiPolygonZ, dsm_layer.crs())
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT))
        written = incomplete = 0
        for m in merged:
            geom = QgsMultiPolygon()
            for part in m.parts:
                rings = [r for r in part if len(r) >= 3]
                if not rings:
                    continue
                poly = QgsPolygon()
                for j, r in enumerate(rings):
                    closed = [list(map(float, r[:, k])) + [float(r[0, k])] for k in range(3)]
                    line = QgsLineString(*closed)
                    poly.setExteriorRing(line) if j == 0 else poly.addInteriorRing(line)
                geom.addGeometry(poly)
            missing = sum(f.missing for f in m.members)
            if not m.complete:
                incomplete += 1
                reasons = "; ".join(f"{f.photo}: {f.why_incomplete()}" for f in m.members
                                    if not f.complete)
                feedback.pushWarning(self.tr("'{label}' is incomplete ({why}).").format(
                    label=m.label, why=reasons))
            if geom.numGeometries() == 0:
                continue
            f = QgsFeature(fields)
            f.setAttributes([";".join(m.photos), m.label, m.score, _num(m.area_m2),
                             _num(m.perimeter_m), m.views, bool(m.complete), missing,
                             getattr(m, "expected_views", None), getattr(m, "max_score", None),
                             getattr(m, "confidence", None)])
            f.setGeometry(QgsGeometry(geom))
            sink.addFeature(f, FeatureSinkFlag.FastInsert)
            written += 1
        close_sink(sink)
        what = layer.sourceName() if layer is not None else os.path.basename((path or folder).rstrip("/\\"))
        project = os.path.basename(self.parameterAsFile(parameters, self.PROJECT, context).rstrip("/\\"))
        presentation.present(self, context, dest, self.OUTPUT, detection_style(),
                             self.tr("{what} on the map (through {project} onto {dsm})").format(
                                 what=what, project=project, dsm=dsm_layer.name()))
        feedback.pushInfo(self.tr("{n} polygons from {p} photos written to the map "
                                  "({i} incomplete).").format(n=written, p=len(items), i=incomplete))
        return {self.OUTPUT: dest}


def detection_style():
    """Polygons brought from the photos: magenta outlines over a faint fill, labelled; dashed
    where a vertex's ray found no DSM (complete = false)."""
    return presentation.outline_style("#ff00c8", 0.5, dashed_when='NOT "complete"',
                                      label='"label"', fill_alpha=40,
                                      tip='<b>[% "label" %]</b><br>[% round("area_m2", 3) %] m², '
                                          '[% "views" %] view(s)')


def _num(v):
    import math
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)
