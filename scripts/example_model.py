"""Write the example model ``tests/qgis/data/heights_then_crop.model3`` with QGIS's own model API
(so it is valid for the QGIS that writes it: every child parameter set, laid out, with help).

    python -m easyidp_toolbox.scripts.example_model [OUT.model3]

The plots get their canopy height (95th percentile of the DSM); the DSM is then cropped by the
plots with heights, each crop named by the plot name field. Outputs: the plots with heights, the
crops' folder and their index (opening the index loads the crops, in one group).
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "tests", "qgis", "data", "heights_then_crop.model3")


def build():
    """The model (QgsProcessingModelAlgorithm); the EasyIDP provider must be registered."""
    from qgis.core import (QgsProcessing, QgsProcessingModelAlgorithm,
                           QgsProcessingModelChildAlgorithm,
                           QgsProcessingModelChildParameterSource as Source,
                           QgsProcessingModelOutput, QgsProcessingModelParameter,
                           QgsProcessingParameterFeatureSource, QgsProcessingParameterField,
                           QgsProcessingParameterRasterLayer)
    from qgis.PyQt.QtCore import QPointF, QSizeF

    model = QgsProcessingModelAlgorithm("ROI heights then crop", "EasyIDP examples")
    model.setHelpContent({
        "ALG_DESC": "Gives every plot its canopy height (95th percentile of the DSM) and crops "
                    "the DSM by the plots, one GeoTIFF per plot named by the name field.",
        "plots": "Plot polygons.", "dsm": "Surface model (GeoTIFF).",
        "name_field": "Field with the plot names, for the crop file names (optional).",
    })
    inputs = (
        (QgsProcessingParameterFeatureSource("plots", "Plots", [QgsProcessing.TypeVectorPolygon]),
         QPointF(120, 80)),
        (QgsProcessingParameterField("name_field", "Plot name field",
                                     parentLayerParameterName="plots", optional=True),
         QPointF(120, 170)),
        (QgsProcessingParameterRasterLayer("dsm", "DSM"), QPointF(120, 260)),
    )
    for definition, where in inputs:
        component = QgsProcessingModelParameter(definition.name())
        component.setPosition(where)
        component.setSize(QSizeF(200, 30))
        model.addModelParameter(definition, component)

    def child(child_id, alg_id, description, where, params, outputs):
        c = QgsProcessingModelChildAlgorithm(alg_id)
        c.setChildId(child_id)
        c.setDescription(description)
        c.setPosition(where)
        c.setSize(QSizeF(200, 30))
        for name, source in params.items():
            c.addParameterSources(name, [source])
        kept = {}
        for k, (name, output, label) in enumerate(outputs):   # named as the modeler names them
            out = QgsProcessingModelOutput(name, label)
            out.setChildId(child_id)
            out.setChildOutputName(output)
            out.setPosition(QPointF(where.x() + 260, where.y() - 30 + 60 * k))
            out.setSize(QSizeF(200, 30))
            kept[name] = out
        c.setModelOutputs(kept)
        model.addChildAlgorithm(c)

    child("heights", "easyidp:roiheightsfromdsm", "Plot heights (p95)",
          QPointF(420, 125), {
              "ROIS": Source.fromModelParameter("plots"), "DSM": Source.fromModelParameter("dsm"),
              "MODE": Source.fromStaticValue(0), "STATISTIC": Source.fromStaticValue(4),
              "PERCENTILE": Source.fromStaticValue(95.0), "BUFFER": Source.fromStaticValue(0.0),
              "SAMPLING": Source.fromStaticValue(0), "OVERWRITE": Source.fromStaticValue(False)},
          [("Plots with heights", "OUTPUT", "Plots with heights")])
    child("crop", "easyidp:croprasterbyrois", "Crop the DSM", QPointF(420, 290), {
        "INPUT": Source.fromModelParameter("dsm"),
        "ROIS": Source.fromChildOutput("heights", "OUTPUT"),
        "NAME_FIELD": Source.fromModelParameter("name_field"),
        "ALL_TOUCHED": Source.fromStaticValue(False), "OVERWRITE": Source.fromStaticValue(False)},
        [("Crops", "OUTPUT_FOLDER", "Crops"), ("Index of the crops", "OUTPUT_INDEX", "Index of the crops")])
    model.updateDestinationParameters()
    return model


def main(argv=None) -> int:
    """Start QGIS offscreen with the plugin's provider and write the model."""
    out = (argv or sys.argv[1:] or [MODEL])[0]
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    from qgis.core import QgsApplication
    app = QgsApplication([], False)
    app.initQgis()
    import easyidp_toolbox
    plugin = easyidp_toolbox.classFactory(None)
    plugin.initProcessing()
    model = build()
    ok, issues = model.validate()
    if not ok:
        raise SystemExit("the example model is not valid: " + "; ".join(issues))
    if not model.toFile(out):
        raise SystemExit(f"cannot write {out}")
    print(out)
    plugin.unload()
    return 0


if __name__ == "__main__":
    sys.exit(main())
