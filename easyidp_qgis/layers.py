"""Adapters from QGIS layers and parameters to the core's plain data."""
import math
import os
import re

from qgis.core import (QgsCoordinateReferenceSystem, QgsCoordinateTransform, QgsCsException,
                       QgsFeatureRequest, QgsGeometry, QgsProcessingException,
                       QgsProcessingParameterCrs, QgsProcessingParameterFeatureSource,
                       QgsProcessingParameterField, QgsProcessingParameterFile,
                       QgsProcessingParameterNumber, QgsProcessingParameterString, QgsProject,
                       QgsWkbTypes)

from ..core.roi import ROISet, roi_from_coordinates
from .compat import (CrsWktVariant, FeatureSinkFlag, GeometryType,
                     ProcessingFieldParameterDataType, ProcessingFileParameterBehavior,
                     ProcessingNumberParameterType, ProcessingParameterFlag, ProcessingSourceType)


def crs_string(crs: QgsCoordinateReferenceSystem):
    """An EPSG code when QGIS knows one, else WKT; None for an invalid CRS."""
    if crs is None or not crs.isValid():
        return None
    if crs.authid().upper().startswith("EPSG:"):
        return crs.authid()
    return crs.toWkt(CrsWktVariant.Preferred)


def pixel_crs() -> QgsCoordinateReferenceSystem:
    """The CRS photo-pixel layers are written with: an undefined engineering (Cartesian) CRS
    (GeoPackage srs_id −1), see ``core.projection.PIXEL_CRS_WKT``."""
    from ..core.projection import PIXEL_CRS_WKT
    return QgsCoordinateReferenceSystem.fromWkt(PIXEL_CRS_WKT)


def qgis_crs(crs) -> QgsCoordinateReferenceSystem:
    """A QgsCoordinateReferenceSystem from a pyproj CRS (by EPSG code when it has one), or an
    invalid one for None."""
    if crs is None:
        return QgsCoordinateReferenceSystem()
    code = crs.to_epsg(min_confidence=100)
    if code:
        return QgsCoordinateReferenceSystem(f"EPSG:{code}")
    return QgsCoordinateReferenceSystem.fromWkt(crs.to_wkt())


def geotiff_source(layer, label: str) -> str:
    """The GeoTIFF file behind a raster layer; refuses layers that are not a local GeoTIFF."""
    if layer is None:
        raise QgsProcessingException(f"{label}: no raster layer given, or it could not be loaded.")
    path = layer.source().split("|")[0]
    if layer.providerType() != "gdal" or not os.path.isfile(path):
        raise QgsProcessingException(
            f"{label}: layer '{layer.name()}' is not a local raster file ({layer.source()}). "
            "EasyIDP reads GeoTIFF files: save it as GeoTIFF first (Export ▸ Save As…).")
    with open(path, "rb") as fh:
        magic = fh.read(4)
    if magic not in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):  # classic and BigTIFF
        raise QgsProcessingException(
            f"{label}: {path} is not a GeoTIFF. Convert it to GeoTIFF first (Raster ▸ Conversion "
            "▸ Translate).")
    return path


def dsm_ground(layer, label: str, points_crs=None):
    """``ground(x, y) -> z``: bilinear heights of a DSM/DTM raster layer (NaN outside it or on
    nodata) at points given in ``points_crs`` (a pyproj CRS), transformed to the DSM's CRS when
    they differ; ``points_crs=None`` takes the points to be in the DSM's own frame."""
    from ..core.raster import DSM

    dsm = DSM(geotiff_source(layer, label), crs=crs_string(layer.crs()))
    return lambda x, y: dsm.heights(x, y, crs=points_crs)


def optional_number(alg, parameters, name: str, context):
    """The value of an optional number parameter, or None when it is not set."""
    if parameters.get(name) in (None, ""):
        return None
    return alg.parameterAsDouble(parameters, name, context)


def rois_from_source(source, name_field: str, label: str, feedback=None, crs=None, context=None):
    """ROIs from a feature source: (ROISet, list of the features, untouched, in the same order).

    Names come from ``name_field``, else the feature id. With ``crs`` (a
    QgsCoordinateReferenceSystem) the ROIs are transformed by QGIS into it, with the transform
    context of ``context`` (the project's datum transformation choices, as QGIS's own tools
    and ``QgsFeatureRequest.setDestinationCrs`` do); otherwise they stay in the layer's CRS. A Z
    coordinate is kept as the ROI's vertex heights.
    """
    if source is None:
        raise QgsProcessingException(f"{label}: no ROI layer given, or it could not be loaded.")
    if QgsWkbTypes.geometryType(source.wkbType()) != GeometryType.Polygon:
        kind = QgsWkbTypes.geometryDisplayString(QgsWkbTypes.geometryType(source.wkbType()))
        raise QgsProcessingException(
            f"{label}: the ROI layer '{source.sourceName()}' has {kind} geometries; ROIs must be "
            "polygons. Buffer points or lines first (Vector geometry ▸ Buffer).")
    if name_field and source.fields().indexFromName(name_field) < 0:
        raise QgsProcessingException(f"{label}: the ROI layer has no field '{name_field}'.")
    transform, out_crs = None, source.sourceCrs()
    if crs is not None and crs.isValid() and crs != source.sourceCrs():
        if not source.sourceCrs().isValid():
            raise QgsProcessingException(
                f"{label}: the ROI layer '{source.sourceName()}' has no CRS, so it cannot be "
                f"placed on {crs.authid() or crs.description()}. Set the layer's CRS (Layer "
                "Properties ▸ Source, or Vector general ▸ Assign projection) and run again.")
        # QGIS's own transformation, with the project's datum transformation choices
        transform = QgsCoordinateTransform(source.sourceCrs(), crs, context.transformContext()
                                           if context is not None else
                                           QgsProject.instance().transformContext())
        out_crs = crs
    rois, features = [], []
    total = max(source.featureCount(), 1)
    for k, feat in enumerate(source.getFeatures(QgsFeatureRequest())):
        if feedback is not None and feedback.isCanceled():
            break
        name = feat[name_field] if name_field else feat.id()
        name = str(feat.id()) if name is None or str(name) == "NULL" else str(name)
        geom = QgsGeometry(feat.geometry())
        if transform is not None and not geom.isNull():
            try:
                geom.transform(transform)
            except QgsCsException as exc:
                raise QgsProcessingException(
                    f"{label}: ROI '{name}' of the layer '{source.sourceName()}' cannot be "
                    f"transformed from {source.sourceCrs().authid() or source.sourceCrs().description()}"
                    f" to {crs.authid() or crs.description()} ({exc}). Check that the layer's CRS "
                    "is set correctly.") from None
        rois.append(roi_from_coordinates(name, "MultiPolygon", _polygon_coordinates(geom)))
        features.append(feat)
        if feedback is not None:
            feedback.setProgress(5.0 * k / total)
    return ROISet(rois, crs_string(out_crs)), features



def rois_parameter(alg, parameters, context, feedback, crs=None):
    """The ROIs of a tool's ``ROIS`` parameter, named by its ``NAME_FIELD`` when the tool has
    one: (source, ROISet, features), as :func:`rois_from_source`; with ``crs`` they are
    transformed into it with the project's transform context."""
    source = alg.parameterAsSource(parameters, alg.ROIS, context)
    name_field = alg.parameterAsString(parameters, alg.NAME_FIELD, context) \
        if hasattr(alg, "NAME_FIELD") else ""
    rois, features = rois_from_source(source, name_field, alg.tr("ROIs"), feedback, crs, context)
    return source, rois, features


def optional_destination(alg, parameters, name: str, context):
    """The path of an optional file or folder output, or None when it was left empty."""
    if parameters.get(name) in (None, ""):
        return None
    return alg.parameterAsFileOutput(parameters, name, context) or None

def _polygon_coordinates(g) -> list:
    """MultiPolygon coordinates [[[(x, y[, z]), …] ring …] polygon …] of a QgsGeometry."""
    if g is None or g.isNull() or g.isEmpty():
        return []
    geom = g.constGet()
    polys = [geom.geometryN(i) for i in range(geom.numGeometries())] if g.isMultipart() else [geom]
    has_z = QgsWkbTypes.hasZ(geom.wkbType())

    def ring(r):
        return [(p.x(), p.y(), p.z()) if has_z else (p.x(), p.y()) for p in r.points()]
    return [[ring(p.exteriorRing())] + [ring(p.interiorRing(k)) for k in range(p.numInteriorRings())]
            for p in polys if p is not None and p.exteriorRing() is not None]


# ---- point clouds: the INPUT / INPUT_CRS / Z_MIN / Z_MAX parameters the point-cloud tools share

POINT_CLOUD_FILTER = "Point clouds (*.las *.laz *.ply *.LAS *.LAZ *.PLY);;All files (*.*)"


def add_point_cloud_parameters(alg):
    """INPUT (a .las/.laz/.ply file: no point cloud layers on QGIS without PDAL) and INPUT_CRS."""
    alg.addParameter(QgsProcessingParameterFile(
        alg.INPUT, alg.tr("Point cloud (.las, .laz or .ply)"),
        behavior=ProcessingFileParameterBehavior.File, fileFilter=POINT_CLOUD_FILTER))
    alg.addParameter(QgsProcessingParameterCrs(
        alg.INPUT_CRS, alg.tr("Point cloud CRS (needed for PLY and for LAS without a CRS; "
                              "otherwise read from the file)"), optional=True))


def read_point_cloud_parameter(alg, parameters, context, feedback):
    """The INPUT point cloud, read with INPUT_CRS when given (it replaces a LAS file's own CRS)."""
    from ..core.crs import same_crs
    from ..core.pointcloud import read_point_cloud

    path = alg.parameterAsFile(parameters, alg.INPUT, context)
    if not path:
        raise QgsProcessingException("Point cloud: no file given.")
    qcrs = alg.parameterAsCrs(parameters, alg.INPUT_CRS, context)
    cloud = read_point_cloud(path, crs_string(qcrs))
    name = os.path.basename(path)
    if qcrs.isValid() and cloud.file_crs is not None and not same_crs(cloud.file_crs, cloud.crs):
        feedback.pushWarning(f"The point cloud CRS given ({qcrs.authid() or qcrs.description()}) "
                             f"replaces the CRS stored in {name} ({cloud.file_crs.name}).")
    for note in cloud.notes:
        feedback.pushWarning(note)
    crs = cloud.crs.name if cloud.crs is not None else "no CRS"
    feedback.pushInfo(f"{name}: {len(cloud):,} points ({cloud.fmt.upper()}), {crs}.")
    return cloud


def add_z_range_parameters(alg):
    """Advanced, optional Z_MIN and Z_MAX."""
    for name, label in ((alg.Z_MIN, alg.tr("Lowest Z to keep (cloud Z units; empty: no limit)")),
                        (alg.Z_MAX, alg.tr("Highest Z to keep (cloud Z units; empty: no limit)"))):
        p = QgsProcessingParameterNumber(name, label, ProcessingNumberParameterType.Double,
                                         optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        alg.addParameter(p)


def z_range(alg, parameters, context):
    """(z_min, z_max) from Z_MIN / Z_MAX, None where not set."""
    z_min = optional_number(alg, parameters, alg.Z_MIN, context)
    z_max = optional_number(alg, parameters, alg.Z_MAX, context)
    if z_min is not None and z_max is not None and z_min > z_max:
        raise QgsProcessingException(f"Z range: the lowest Z to keep ({z_min:g}) is above the "
                                     f"highest ({z_max:g}).")
    return z_min, z_max


# ---- photogrammetry projects: the PROJECT / CHUNK / PROJECT_CRS parameters the tools share

PROJECT_HELP = ("Metashape .psx/.psz or cameras .xml; Pix4D .p4d, project folder or any file of "
                "its 1_initial/params folder; OpenDroneMap project folder or its "
                "opensfm/reconstruction.json")


def add_project_parameters(alg):
    """PROJECT (a file or a folder: no file filter, so folders are accepted too), CHUNK and
    PROJECT_CRS (advanced)."""
    alg.addParameter(QgsProcessingParameterFile(
        alg.PROJECT, alg.tr("Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d, "
                            "project or params folder; OpenDroneMap folder or reconstruction.json)"),
        behavior=ProcessingFileParameterBehavior.File))
    alg.addParameter(QgsProcessingParameterString(
        alg.CHUNK, alg.tr("Chunk: Metashape chunk (label or index) or OpenSfM reconstruction index "
                          "(needed when there are several)"), optional=True))
    p = QgsProcessingParameterCrs(
        alg.PROJECT_CRS, alg.tr("Project CRS (Pix4D without a *_wkt.prj file; OpenSfM without "
                                "OpenDroneMap; Metashape chunk CRS that PROJ cannot use)"),
        optional=True)
    p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
    alg.addParameter(p)


def open_project_parameter(alg, parameters, context, feedback, need_crs: bool = True):
    """The Reconstruction of PROJECT/CHUNK/PROJECT_CRS, its summary and notes in the log, and
    its unaligned cameras named. ``need_crs``: refuse a project whose CRS is unknown."""
    from ..core.reconstruction import open_reconstruction

    path = alg.parameterAsFile(parameters, alg.PROJECT, context)
    if not path:
        raise QgsProcessingException(alg.tr("Photogrammetry project: none given ({what}).").format(
            what=PROJECT_HELP))
    chunk = alg.parameterAsString(parameters, alg.CHUNK, context) or None
    pcrs = alg.parameterAsCrs(parameters, alg.PROJECT_CRS, context)
    recon = open_reconstruction(path, chunk, crs_string(pcrs) if pcrs.isValid() else None)
    feedback.pushInfo(recon.summary())
    for note in recon.notes:
        feedback.pushWarning(note)
    if need_crs and recon.crs is None:
        raise QgsProcessingException(alg.tr(
            "{path}: the project's CRS is unknown (a Pix4D project without *_wkt.prj, or an "
            "OpenSfM dataset without GPS): set 'Project CRS'.").format(path=path))
    if recon.unaligned_cameras:
        names = [c.label for c in recon.unaligned_cameras]
        feedback.pushWarning(alg.tr("{n} camera(s) are not aligned and have no pose: {names}").format(
            n=len(names), names=", ".join(names[:20]) + (" …" if len(names) > 20 else "")))
    return recon


# ---- backward projection: the heights of the ROI vertices, and the photo-pixel layer

HEIGHT_Z, HEIGHT_DSM, HEIGHT_FIELD, HEIGHT_CONSTANT = range(4)


def add_height_parameters(alg):
    """HEIGHT_SOURCE, DSM (vertex heights and the occlusion test), HEIGHT_FIELD, GROUND_HEIGHT."""
    from qgis.core import QgsProcessingParameterEnum, QgsProcessingParameterRasterLayer
    alg.addParameter(QgsProcessingParameterEnum(
        alg.HEIGHT_SOURCE, alg.tr("Heights of the ROI vertices"),
        [alg.tr("Geometry Z (3-D polygons)"), alg.tr("DSM, sampled at every vertex"),
         alg.tr("Attribute (one height per ROI)"), alg.tr("Constant ground height")],
        defaultValue=HEIGHT_DSM))
    alg.addParameter(QgsProcessingParameterRasterLayer(
        alg.DSM, alg.tr("DSM (GeoTIFF): vertex heights and occlusion test"), optional=True))
    alg.addParameter(QgsProcessingParameterField(
        alg.HEIGHT_FIELD, alg.tr("Height attribute"), parentLayerParameterName=alg.ROIS,
        type=ProcessingFieldParameterDataType.Numeric, optional=True))
    alg.addParameter(alg.decimals(QgsProcessingParameterNumber(
        alg.GROUND_HEIGHT, alg.tr("Constant ground height (project vertical reference)"),
        ProcessingNumberParameterType.Double, optional=True), 3))


def dsm_parameter(alg, parameters, context):
    """The DSM parameter as the core's :class:`DSM` (None when not given)."""
    from ..core.raster import DSM
    layer = alg.parameterAsRasterLayer(parameters, alg.DSM, context)
    if layer is None:
        return None
    return DSM(geotiff_source(layer, alg.tr("DSM")), crs=crs_string(layer.crs()))


def height_source_parameter(alg, parameters, context, features, dsm):
    """The core height source chosen by HEIGHT_SOURCE (``features``: the ROI features, for an
    attribute; ``dsm``: from :func:`dsm_parameter`)."""
    from ..core.projection import ConstantHeight, GeometryZ, PerROIHeights
    kind = alg.parameterAsEnum(parameters, alg.HEIGHT_SOURCE, context)
    if kind == HEIGHT_Z:
        return GeometryZ()
    if kind == HEIGHT_DSM:
        if dsm is None:
            raise QgsProcessingException(alg.tr(
                "Heights from the DSM: choose the DSM raster, or another height source."))
        return dsm
    if kind == HEIGHT_FIELD:
        field = alg.parameterAsString(parameters, alg.HEIGHT_FIELD, context)
        if not field:
            raise QgsProcessingException(alg.tr(
                "Heights from an attribute: choose the height attribute of the ROI layer."))
        return PerROIHeights([f[field] for f in features])
    h = optional_number(alg, parameters, alg.GROUND_HEIGHT, context)
    if h is None:
        raise QgsProcessingException(alg.tr(
            "Constant ground height: give the height, or choose another height source."))
    return ConstantHeight(h)


def pixel_polygons(geom) -> list:
    """Photo-pixel polygons [[exterior, hole, …], …] (x = column, y = row) of a geometry of the
    photo-pixel layer (x = column, y = −row): the inverse of ``pixel_geometry``."""
    import numpy as np
    out = []
    for poly in _polygon_coordinates(geom):
        rings = []
        for ring in poly:
            a = np.array([p[:2] for p in ring], np.float64) * [1.0, -1.0]
            if len(a) > 1 and np.all(a[0] == a[-1]):
                a = a[:-1]
            rings.append(a)
        out.append(rings)
    return out


def backprojection_from_layer(layer, label: str, roi_names, recon, feedback=None):
    """A core ``BackProjection`` from the photo-pixel layer of *Back-project ROIs* (its OUTPUT):
    fields ``roi`` and ``photo`` (and its others when present); photo sizes and paths from the
    layer, else from the project ``recon``."""
    from ..core.projection.result import BackProjection
    names = layer.fields().names()
    for need in ("roi", "photo"):
        if need not in names:
            raise QgsProcessingException(
                f"{label}: the layer '{layer.sourceName()}' has no field '{need}'. Give the "
                "photo-pixel layer (OUTPUT) of Back-project ROIs.")
    records, photos = [], {}
    for feat in layer.getFeatures():
        if feedback is not None and feedback.isCanceled():
            break
        rec = {k: (None if str(feat[k]) == "NULL" else feat[k]) for k in names}
        rec["roi"], rec["photo"] = str(rec["roi"]), str(rec["photo"])
        rec["polygons"] = pixel_polygons(feat.geometry())
        if not rec["polygons"]:
            continue
        records.append(rec)
        if rec["photo"] not in photos:
            try:
                cam = recon.camera(rec["photo"])
            except Exception:
                raise QgsProcessingException(
                    f"{label}: photo '{rec['photo']}' is not a camera of the project "
                    f"{recon.source}: give the project the back-projection was made with.") from None
            sensor = recon.sensors[cam.sensor_id]
            cal = sensor.calibration
            photos[rec["photo"]] = {
                "path": rec.get("photo_path") or cam.photo_path,
                "width": int(rec.get("photo_width") or sensor.width),
                "height": int(rec.get("photo_height") or sensor.height),
                "principal_point": (cal.cx, cal.cy) if cal is not None else None}
    return BackProjection.from_records(list(roi_names), records, photos)


# ---- the index layer of a tool that writes one file per ROI ------------------------------------

def add_index_parameter(alg, description: str):
    """OUTPUT_INDEX (optional, made by default): the ROIs with the file written for each. Loading
    it is the user's choice of loading the files too (see presentation.load_project)."""
    from qgis.core import QgsProcessingParameterFeatureSink
    alg.addParameter(QgsProcessingParameterFeatureSink(
        alg.OUTPUT_INDEX, description, ProcessingSourceType.VectorPolygon, optional=True,
        createByDefault=True))


def write_index(alg, parameters, context, source, rows, extra):
    """Write OUTPUT_INDEX when it is asked for: one feature per row ``(ROI feature, values)``,
    the ROI's geometry and attributes followed by the ``extra`` fields ``[(name,
    compat.FieldType member)]``. Returns the destination id, or None when the output is skipped."""
    from qgis.core import QgsFeature, QgsField, QgsFields, QgsProcessingUtils
    from .outputs import close_sink
    if parameters.get(alg.OUTPUT_INDEX) in (None, ""):
        return None
    more = QgsFields()
    for name, kind in extra:
        more.append(QgsField(name, kind))
    fields = QgsProcessingUtils.combineFields(source.fields(), more)
    sink, dest = alg.parameterAsSink(parameters, alg.OUTPUT_INDEX, context, fields,
                                     source.wkbType(), source.sourceCrs())
    if sink is None:
        return None
    for feat, values in rows:
        f = QgsFeature(fields)
        f.setGeometry(feat.geometry())
        f.setAttributes(list(feat.attributes()) + list(values))
        sink.addFeature(f, FeatureSinkFlag.FastInsert)
    close_sink(sink)
    return dest


# ---- ROIs and percentiles: parameters several tools share

def add_roi_parameters(alg, name_field: bool = True):
    """ROIS (a polygon layer) and, with ``name_field``, NAME_FIELD (names files and records)."""
    alg.addParameter(QgsProcessingParameterFeatureSource(
        alg.ROIS, alg.tr("ROIs (polygons)"), [ProcessingSourceType.VectorPolygon]))
    if name_field:
        alg.addParameter(QgsProcessingParameterField(
            alg.NAME_FIELD, alg.tr("Name field (default: feature id)"),
            parentLayerParameterName=alg.ROIS, optional=True))


def parse_percentiles(alg, text: str, default=()):
    """'5, 50 95;99' → [5.0, 50.0, 95.0, 99.0] (order kept, repeats dropped); ``default`` when
    empty; QgsProcessingException naming the token for anything that is not 0–100."""
    out = []
    for token in re.split(r"[,;\s]+", (text or "").strip()):
        if not token:
            continue
        try:
            q = float(token)
        except ValueError:
            q = math.nan
        if not 0 <= q <= 100:
            raise QgsProcessingException(alg.tr(
                "Percentiles: '{token}' is not a number from 0 to 100. Give percentiles "
                "separated by commas, e.g. 5,50,95.").format(token=token))
        if q not in out:
            out.append(q)
    return out or list(default)
