"""Write the tutorials' graphical-modeler models (``docs/tutorials/models/*.model3``) with QGIS's
own model API, as ``scripts/example_model.py`` writes the example model: every child parameter
set, laid out, with help, and checked by QGIS's ``validate()``.

    python -m easyidp_toolbox.scripts.tutorial_models [FOLDER]

Each model is the chain of tools its tutorial runs (``docs/tutorials/*.md``), and
``tests/qgis/test_docs.py`` runs each through ``qgis_process`` on the demo survey. Model outputs
are named ``<child>:<output>`` without spaces, so they are easy to pass on a command line.
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOLDER = os.path.join(ROOT, "docs", "tutorials", "models")

# name → (title, help, inputs, children). An input is (name, kind, label[, parent]); kind is
# polygons, vector, field, raster, file, folder or string. A child is (id, algorithm, description,
# {parameter: source}, [(output name, child output)]); a source is ("in", input name),
# ("out", child id, output), ("expr", expression, the child id it reads) or a static value.
MODELS = {
    "crop_plots": (
        "Crop plots out of the orthomosaic, DSM and point cloud",
        "Gives every plot its canopy height (95th percentile of the DSM), then crops the "
        "orthomosaic, the DSM and the point cloud by the plots, one file per plot named by the "
        "name field.",
        [("plots", "polygons", "Plots"), ("name_field", "field", "Plot name field", "plots"),
         ("orthomosaic", "raster", "Orthomosaic"), ("dsm", "raster", "DSM"),
         ("cloud", "file", "Point cloud (LAS, LAZ, PLY)")],
        [("heights", "easyidp:roiheightsfromdsm", "Plot heights (p95)",
          {"ROIS": ("in", "plots"), "DSM": ("in", "dsm"), "MODE": 0, "STATISTIC": 4,
           "PERCENTILE": 95.0, "BUFFER": 0.0, "SAMPLING": 0, "OVERWRITE": False},
          [("plots_with_heights", "OUTPUT")]),
         ("crop_ortho", "easyidp:croprasterbyrois", "Crop the orthomosaic",
          {"INPUT": ("in", "orthomosaic"), "ROIS": ("out", "heights", "OUTPUT"),
           "NAME_FIELD": ("in", "name_field"), "ALL_TOUCHED": False, "OVERWRITE": False},
          [("ortho_crops", "OUTPUT_FOLDER")]),
         ("crop_dsm", "easyidp:croprasterbyrois", "Crop the DSM",
          {"INPUT": ("in", "dsm"), "ROIS": ("in", "plots"), "NAME_FIELD": ("in", "name_field"),
           "ALL_TOUCHED": False, "OVERWRITE": False},
          [("dsm_crops", "OUTPUT_FOLDER")]),
         ("crop_cloud", "easyidp:croppointcloudbyrois", "Crop the point cloud",
          {"INPUT": ("in", "cloud"), "ROIS": ("in", "plots"), "NAME_FIELD": ("in", "name_field"),
           "WRITE_EMPTY": False, "FORMAT": 0, "OVERWRITE": False},
          [("cloud_crops", "OUTPUT_FOLDER")])]),
    "plots_in_photos": (
        "Plots in the raw photos and their best views",
        "Finds every plot in every raw photo that sees it (heights from the DSM, occlusion "
        "tested), keeps the 3 best views, and measures each plot in them.",
        [("plots", "polygons", "Plots"), ("name_field", "field", "Plot name field", "plots"),
         ("project", "file", "Photogrammetry project"), ("dsm", "raster", "DSM")],
        [("back", "easyidp:backprojectrois", "Plots in the raw photos",
          {"ROIS": ("in", "plots"), "NAME_FIELD": ("in", "name_field"),
           "PROJECT": ("in", "project"), "HEIGHT_SOURCE": 1, "DSM": ("in", "dsm"), "CLIP": 0,
           "OCCLUSION": True, "MIN_VISIBLE": 0.5, "MAX_IMAGES": 3, "DISTORTION": True,
           "MARGIN": 0, "OVERWRITE": False},
          [("plots_in_photos", "OUTPUT"), ("best_views", "OUTPUT_SUMMARY")]),
         ("stats", "easyidp:photostatistics", "Plot statistics from the best views",
          {"ROIS": ("in", "plots"), "NAME_FIELD": ("in", "name_field"),
           "PROJECT": ("in", "project"), "BACKPROJECTION": ("out", "back", "OUTPUT"),
           "HEIGHT_SOURCE": 1, "DSM": ("in", "dsm"), "OCCLUSION": True,
           "STATISTICS": [0, 1, 2], "INDICES": [0, 1, 2, 3], "MIN_VISIBLE": 0.5,
           "MAX_IMAGES": 3, "WEIGHTED": False, "DISTORTION": True, "OVERWRITE": False},
          [("plot_statistics", "OUTPUT"), ("views", "OUTPUT_VIEWS")])]),
    "detections_to_map": (
        "Detections on photos back to the map",
        "Brings the polygons of a folder of LabelMe (or YOLO) files drawn on raw photos to the "
        "map through the DSM, one polygon per object (the union of its views).",
        [("annotations", "folder", "Folder of LabelMe or YOLO files"),
         ("project", "file", "Photogrammetry project"), ("dsm", "raster", "DSM")],
        [("forward", "easyidp:forwardprojectpolygons", "Polygons to the map",
          {"INPUT_FOLDER": ("in", "annotations"), "PROJECT": ("in", "project"),
           "DSM": ("in", "dsm"), "MERGE": 1, "DENSIFY": 4.0, "OVERWRITE": False},
          [("on_map", "OUTPUT")])]),
    "training_round_trip": (
        "A training set out, fused detections in",
        "Writes a training set on the raw photos from labelled polygons on the map, then brings "
        "the training split's LabelMe labels back to the map, fused: one object per labelled "
        "polygon.",
        [("objects", "polygons", "Labelled objects"),
         ("class_field", "field", "Class field", "objects"),
         ("project", "file", "Photogrammetry project"), ("dsm", "raster", "DSM"),
         ("training_folder", "string", "Folder for the training set (new)")],
        [("export", "easyidp:exporttrainingset", "Training set on the raw photos",
          {"OBJECTS": ("in", "objects"), "CLASS_FIELD": ("in", "class_field"),
           "PROJECT": ("in", "project"), "DSM": ("in", "dsm"), "BEST_K": 0, "MIN_VISIBLE": 0.5,
           "TILE_SIZE": 0, "TILE_OVERLAP": 0, "SPLIT": 1, "VAL_FRACTION": 0.2,
           "REGION_SIZE": 10.0, "SEED": 0, "POINT_RADIUS": 0.1, "OVERWRITE": False,
           "OUTPUT_FOLDER": ("in", "training_folder")},
          []),
         ("fuse", "easyidp:forwardprojectpolygons", "Fuse the labels back on the map",
          {"INPUT_FOLDER": ("expr", "@training_folder || '/labelme/train'", "export"),
           "PROJECT": ("in", "project"), "DSM": ("in", "dsm"), "MERGE": 3, "DENSIFY": 4.0,
           "OVERWRITE": False},
          [("fused", "OUTPUT")])]),
    "season": (
        "A season of surveys",
        "Measures every plot on every date of a survey table (height, cover, indices, band "
        "means, point-cloud heights) and draws the growth curves.",
        [("surveys", "vector", "Survey table (CSV)"), ("plots", "polygons", "Plots"),
         ("name_field", "field", "Plot name field", "plots")],
        [("season", "easyidp:seasontraits", "Plot traits over the season",
          {"SURVEYS": ("in", "surveys"), "ROIS": ("in", "plots"),
           "NAME_FIELD": ("in", "name_field"), "TRAITS": [0, 1, 2, 3, 4],
           "GROUND_PERCENTILE": 2.0, "WORKERS": 1, "OVERWRITE": False},
          [("traits", "OUTPUT_TABLE"), ("latest", "OUTPUT_LAYER"),
           ("curves", "OUTPUT_CURVES")])]),
}


def build(name):
    """The model ``name`` of :data:`MODELS` (QgsProcessingModelAlgorithm); the EasyIDP provider
    must be registered."""
    from qgis.core import (QgsProcessing, QgsProcessingModelAlgorithm,
                           QgsProcessingModelChildAlgorithm, QgsProcessingModelChildDependency,
                           QgsProcessingModelChildParameterSource as Source,
                           QgsProcessingModelOutput, QgsProcessingModelParameter,
                           QgsProcessingParameterFeatureSource, QgsProcessingParameterField,
                           QgsProcessingParameterFile, QgsProcessingParameterRasterLayer,
                           QgsProcessingParameterString,
                           QgsProcessingParameterVectorLayer)
    from qgis.PyQt.QtCore import QPointF, QSizeF

    title, help_text, inputs, children = MODELS[name]
    model = QgsProcessingModelAlgorithm(title, "EasyIDP tutorials")
    model.setHelpContent({"ALG_DESC": help_text})
    for k, spec in enumerate(inputs):
        pname, kind, label = spec[:3]
        if kind == "polygons":
            definition = QgsProcessingParameterFeatureSource(
                pname, label, [QgsProcessing.TypeVectorPolygon])
        elif kind == "vector":
            definition = QgsProcessingParameterVectorLayer(pname, label,
                                                           [QgsProcessing.TypeVector])
        elif kind == "field":
            definition = QgsProcessingParameterField(pname, label, parentLayerParameterName=spec[3],
                                                     optional=True)
        elif kind == "raster":
            definition = QgsProcessingParameterRasterLayer(pname, label)
        elif kind == "string":
            definition = QgsProcessingParameterString(pname, label)
        elif kind == "file":
            definition = QgsProcessingParameterFile(pname, label)
        else:
            definition = QgsProcessingParameterFile(pname, label,
                                                    QgsProcessingParameterFile.Folder)
        component = QgsProcessingModelParameter(pname)
        component.setPosition(QPointF(120, 80 + 90 * k))
        component.setSize(QSizeF(200, 30))
        model.addModelParameter(definition, component)

    for k, (child_id, alg_id, description, params, outputs) in enumerate(children):
        where = QPointF(420, 110 + 160 * k)
        c = QgsProcessingModelChildAlgorithm(alg_id)
        c.setChildId(child_id)
        c.setDescription(description)
        c.setPosition(where)
        c.setSize(QSizeF(200, 30))
        depends = []
        for pname, source in params.items():
            if isinstance(source, tuple) and source[0] == "in":
                s = Source.fromModelParameter(source[1])
            elif isinstance(source, tuple) and source[0] == "out":
                s = Source.fromChildOutput(source[1], source[2])
            elif isinstance(source, tuple) and source[0] == "expr":
                s = Source.fromExpression(source[1])
                depends.append(QgsProcessingModelChildDependency(source[2]))
            else:
                s = Source.fromStaticValue(source)
            c.addParameterSources(pname, [s])
        c.setDependencies(depends)
        kept = {}
        for j, (out_name, child_output) in enumerate(outputs):
            out = QgsProcessingModelOutput(out_name, out_name)
            out.setChildId(child_id)
            out.setChildOutputName(child_output)
            out.setPosition(QPointF(where.x() + 260, where.y() - 30 + 60 * j))
            out.setSize(QSizeF(200, 30))
            kept[out_name] = out
        c.setModelOutputs(kept)
        model.addChildAlgorithm(c)
    model.updateDestinationParameters()
    return model


def main(argv=None) -> int:
    """Start QGIS offscreen with the plugin's provider and write every model."""
    folder = (argv or sys.argv[1:] or [FOLDER])[0]
    os.makedirs(folder, exist_ok=True)
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from qgis.core import QgsApplication
    app = QgsApplication([], False)
    app.initQgis()
    import easyidp_toolbox
    plugin = easyidp_toolbox.classFactory(None)
    plugin.initProcessing()
    for name in MODELS:
        model = build(name)
        ok, issues = model.validate()
        if not ok:
            raise SystemExit(f"the model {name} is not valid: " + "; ".join(issues))
        out = os.path.join(folder, name + ".model3")
        if not model.toFile(out):
            raise SystemExit(f"cannot write {out}")
        print(out)
    plugin.unload()
    return 0


if __name__ == "__main__":
    sys.exit(main())
