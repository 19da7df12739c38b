"""Processing tool: ROI heights from DSM (easyidp:roiheightsfromdsm)."""
import math

import numpy as np
from qgis.core import (QgsCoordinateTransform, QgsFeature, QgsField, QgsFields, QgsGeometry,
                       QgsPointXY,
                       QgsProcessingException, QgsProcessingParameterEnum,
                       QgsProcessingParameterFeatureSink, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterLayer,
                       QgsWkbTypes)

from .. import presentation
from ..compat import (FeatureSinkFlag, FieldType, ProcessingNumberParameterType,
                      ProcessingParameterFlag, ProcessingSourceType, WkbType)
from ..crs import crs_string
from ..geometries import from_wkb, multipolygon
from ..progress import feedback_progress
from ..rasters import geotiff_source
from ..rois import PLAIN_POLYGONS, rois_parameter
from ..sinks import BATCH, close_sink
from .base import CoreStep, EasyIDPAlgorithm, translatable

MODES = [("polygon", translatable("Per polygon: one statistic of the DSM pixels inside")),
         ("vertex", translatable("Per vertex: the DSM height at each vertex"))]
# the statistics of core.height_statistics, in the order of the tool's menu
STATS = ["mean", "median", "min", "max", "percentile", "std", "pmin", "pmax"]
SAMPLING = ["bilinear", "nearest"]


class ROIHeightsFromDSM(EasyIDPAlgorithm):
    ROIS = "ROIS"
    DSM = "DSM"
    MODE = "MODE"
    STATISTIC = "STATISTIC"
    PERCENTILE = "PERCENTILE"
    BUFFER = "BUFFER"
    SAMPLING = "SAMPLING"
    OUTPUT = "OUTPUT"

    NAME = "roiheightsfromdsm"
    REQUIRES = ("tifffile", "imagecodecs")  # the DSM
    DISPLAY = "ROI heights from DSM"
    GROUP = "Heights"
    GROUP_ID = "heights"
    HELP = (
        "Gives every ROI its height from a surface model (DSM), as the Z of its vertices and as "
        "the attribute 'height' (in the DSM's units and vertical reference). The result is the "
        "ROI layer as PolygonZ, ready for backward projection into raw photos.\n\n"
        "Per polygon: the statistic (mean, median, min, max, a percentile, e.g. 90 for canopy "
        "top, 5 for ground, the standard deviation, or EasyIDP's pmin/pmax: the mean of the "
        "values below the percentile / above 100 minus the percentile) of the DSM pixels whose "
        "centres are inside the ROI, grown by a "
        "positive buffer or shrunk by a negative one (map units of the DSM). Every vertex gets "
        "that height.\n"
        "Per vertex: the DSM height at each vertex (bilinear or nearest pixel), or, with a buffer, "
        "the statistic of the pixels within the buffer distance of the vertex; 'height' is then "
        "the mean of the vertex heights.\n\n"
        "Nodata pixels are ignored. An ROI without any valid pixel keeps an empty (NULL) height "
        "and NaN Z, and is listed in the log; it never gets 0.")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterFeatureSource(
            self.ROIS, self.tr("ROIs (polygons)"), [ProcessingSourceType.VectorPolygon]))
        self.addParameter(QgsProcessingParameterRasterLayer(self.DSM, self.tr("DSM (GeoTIFF)")))
        self.addParameter(QgsProcessingParameterEnum(
            self.MODE, self.tr("Mode"), options=[self.tr(m[1]) for m in MODES], defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum(
            self.STATISTIC, self.tr("Statistic"), options=STATS, defaultValue=0))
        self.addParameter(self.decimals(QgsProcessingParameterNumber(
            self.PERCENTILE, self.tr("Percentile (0–100; for percentile, pmin and pmax)"),
            ProcessingNumberParameterType.Double, defaultValue=50.0, minValue=0.0, maxValue=100.0), 1))
        self.addParameter(QgsProcessingParameterNumber(
            self.BUFFER, self.tr("Buffer (DSM map units; negative shrinks the polygon)"),
            ProcessingNumberParameterType.Double, defaultValue=0.0))
        p = QgsProcessingParameterEnum(self.SAMPLING, self.tr("Vertex sampling"),
                                       options=SAMPLING, defaultValue=0)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addParameter(QgsProcessingParameterFeatureSink(
            self.OUTPUT, self.tr("ROIs with heights"), ProcessingSourceType.VectorPolygon))
        self.add_overwrite_parameter()

    def run_tool(self, parameters, context, feedback):
        """The run with Python's cyclic collector paused (``core.gc_pause``): reading,
        placing and writing 100,000 plots builds that many features and ROIs."""
        from ...core.gc_pause import paused_gc
        with paused_gc():
            return super().run_tool(parameters, context, feedback)

    def core_step(self, parameters, context, feedback):
        from ...core.raster import DSM, dsm_roi_heights, vertex_heights

        layer = self.parameterAsRasterLayer(parameters, self.DSM, context)
        dsm = DSM(geotiff_source(layer, self.tr("DSM")), crs=crs_string(layer.crs()))
        # the ROIs on the DSM's CRS, transformed by QGIS; the features keep their own geometry
        source, rois, features = rois_parameter(self, parameters, context, feedback, layer.crs())
        for note in dsm.notes:
            feedback.pushWarning(note)
        mode = MODES[self.parameterAsEnum(parameters, self.MODE, context)][0]
        stats = dict(statistic=STATS[self.parameterAsEnum(parameters, self.STATISTIC, context)],
                     percentile=self.parameterAsDouble(parameters, self.PERCENTILE, context),
                     buffer=self.parameterAsDouble(parameters, self.BUFFER, context),
                     progress=feedback_progress(feedback, 5, 95), is_cancelled=feedback.isCanceled)
        rois.validate()
        inputs = dict(layer=layer, source=source, features=features, rois=rois)
        if mode == "polygon":
            return CoreStep(dsm_roi_heights, dict(dsm=dsm, rois=rois, mode="polygon", **stats), inputs)
        # sample at the layer's own vertices (closing vertices included), in the DSM CRS
        rings = [_rings(f.geometry()) for f in features]
        to_dsm = QgsCoordinateTransform(source.sourceCrs(), layer.crs(), context.transformContext())
        xy = np.array([(q.x(), q.y()) for q in (to_dsm.transform(QgsPointXY(*pt)) for polys
                       in rings for poly in polys for ring in poly for pt in ring)],
                      dtype=float).reshape(-1, 2)
        return CoreStep(vertex_heights, dict(
            dsm=dsm, x=xy[:, 0], y=xy[:, 1],
            sampling=SAMPLING[self.parameterAsEnum(parameters, self.SAMPLING, context)], **stats),
            dict(inputs, rings=rings))

    def write_outputs(self, parameters, context, feedback, step, result):
        layer, source, features, rois = (step.inputs[k] for k in ("layer", "source", "features",
                                                                   "rois"))
        stat, pct = step.kwargs["statistic"], step.kwargs["percentile"]
        if "rings" not in step.inputs:
            per_feature = [(v, None) for v in result.values]
            missing = result.missing
        else:
            per_feature, k, missing = [], 0, {}
            for i, (roi, polys) in enumerate(zip(rois, step.inputs["rings"])):
                n = sum(len(r) for poly in polys for r in poly)
                zs = result[k:k + n]
                k += n
                if np.isnan(zs).any():
                    missing[i] = "some vertices fall outside the DSM or on nodata"
                per_feature.append((float(np.nanmean(zs)) if np.isfinite(zs).any() else math.nan, zs))

        fields = QgsFields(source.fields())
        fields.append(QgsField("height", FieldType.Double))
        wkb = QgsWkbTypes.addZ(QgsWkbTypes.multiType(source.wkbType()))
        sink, dest_id = self.parameterAsSink(parameters, self.OUTPUT, context, fields, wkb,
                                             source.sourceCrs())
        if sink is None:
            raise QgsProcessingException(self.invalidSinkError(parameters, self.OUTPUT))
        geoms = _flat_z_all(features, [h for h, _ in per_feature]) \
            if "rings" not in step.inputs else \
            [_with_z(_rings(f.geometry()), h, zs) for f, (h, zs) in zip(features, per_feature)]
        batch = []
        for feat, (height, _), geom in zip(features, per_feature, geoms):
            out = QgsFeature(fields)
            out.setAttributes(feat.attributes() + [None if math.isnan(height) else height])
            out.setGeometry(geom)
            batch.append(out)
            if len(batch) == BATCH:
                sink.addFeatures(batch, FeatureSinkFlag.FastInsert)
                batch = []
        sink.addFeatures(batch, FeatureSinkFlag.FastInsert)
        close_sink(sink)
        for i, reason in missing.items():
            feedback.pushWarning(self.tr("ROI '{name}': {reason}; its height is left empty.").format(
                name=rois[i].name, reason=reason))
        what = f"p{pct:g}" if stat == "percentile" else \
            (f"{stat} {pct:g}" if stat in ("pmin", "pmax") else stat)
        presentation.present(
            self, context, dest_id, self.OUTPUT,
            presentation.graduated_style("height", decimals=2, ramp="Viridis"),
            self.tr("{rois}: height {what} from {dsm}").format(
                rois=source.sourceName(), what=what, dsm=layer.name()))
        values = [h for h, _ in per_feature if not math.isnan(h)]
        feedback.setProgress(100)
        if values:
            feedback.pushInfo(self.tr("Heights ({what}) of {n} ROIs: {lo:.3f} to {hi:.3f} (DSM "
                                      "units), {null} empty (NULL).").format(
                what=what, n=len(per_feature), lo=min(values), hi=max(values),
                null=len(per_feature) - len(values)))
        elif missing:               # each ROI's reason is in the warnings above
            reasons = sorted(set(missing.values()))
            feedback.pushInfo(self.tr("Heights of {n} ROIs: all empty (NULL): {reason}.").format(
                n=len(per_feature), reason=reasons[0] if len(reasons) == 1 else
                self.tr("see the warnings above for each ROI")))
        else:
            feedback.pushInfo(self.tr("Heights of {n} ROIs: all empty (NULL): the DSM has no valid "
                                      "pixel under any of them.").format(n=len(per_feature)))
        return {self.OUTPUT: dest_id}


def _rings(geom):
    """Polygons → rings → (x, y) tuples, closing vertices included, as QGIS stores them."""
    polys = geom.asMultiPolygon() if geom.isMultipart() else [geom.asPolygon()]
    return [[[(p.x(), p.y()) for p in ring] for ring in poly] for poly in polys]


def _flat_z_all(features, heights):
    """:func:`_flat_z` of every feature: the polygons' WKB made Z by the core in one pass
    (``core.roi.wkb_with_height``), curved geometries by QGIS one by one."""
    from ...core.roi import wkb_with_height
    geoms = [f.geometry() for f in features]
    flat = QgsWkbTypes.flatType
    plain = [g.isNull() or flat(g.wkbType()) in PLAIN_POLYGONS for g in geoms]
    wkbs = wkb_with_height([bytes(g.asWkb()) if ok else None for g, ok in zip(geoms, plain)],
                           heights)
    return [from_wkb(w) if ok else _flat_z(g, h)
            for g, h, ok, w in zip(geoms, heights, plain, wkbs)]


def _flat_z(geom, height):
    """The ROI's polygons as a MultiPolygonZ with Z = ``height`` at every vertex (M dropped),
    by QGIS's own geometry calls; a curved geometry goes through :func:`_with_z`."""
    if QgsWkbTypes.flatType(geom.wkbType()) not in (WkbType.Polygon, WkbType.MultiPolygon):
        return _with_z(_rings(geom), height, None)
    g = QgsGeometry(geom)
    g.convertToMultiType()
    part = g.get()
    part.dropZValue()
    part.dropMValue()
    part.addZValue(height)
    return g


def _with_z(polys, height, zs):
    """A MultiPolygonZ from closed rings, Z = ``zs`` per vertex (in order) or ``height``
    everywhere."""
    out, k = [], 0
    for poly in polys:
        rings = []
        for ring in poly:
            z = zs[k:k + len(ring)] if zs is not None else np.full(len(ring), height)
            k += len(ring)
            rings.append(np.column_stack([np.asarray(ring, np.float64).reshape(-1, 2), z]))
        out.append(rings)
    return multipolygon(out, z=True, close=False)
