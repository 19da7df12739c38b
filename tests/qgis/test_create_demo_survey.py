"""Create demo survey in real QGIS: outputs open as layers and are queued for the map."""
from qgis.core import (QgsProcessingContext, QgsProcessingFeedback, QgsProject, QgsRasterLayer,
                       QgsVectorLayer)


def test_create_demo_survey(provider, tmp_path):
    import processing
    context = QgsProcessingContext()
    context.setProject(QgsProject.instance())
    res = processing.run("easyidp:createdemosurvey", {"OUTPUT_FOLDER": str(tmp_path / "survey"),
                                                      "SEASON_DATES": 1},
                         context=context, feedback=QgsProcessingFeedback())
    assert QgsRasterLayer(res["ORTHOMOSAIC"], "o").bandCount() == 3
    dsm = QgsRasterLayer(res["DSM"], "d")
    assert dsm.isValid() and dsm.crs().authid() == "EPSG:32654"
    plots = QgsVectorLayer(res["PLOTS"], "p", "ogr")
    assert plots.featureCount() == 40 and plots.fields().indexFromName("plot_id") >= 0
    for key in ("POINT_CLOUD", "METASHAPE_PROJECT", "PIX4D_PROJECT", "TRUTH"):
        assert (tmp_path / "survey").as_posix() in res[key]
    assert (tmp_path / "survey" / "season" / "surveys.csv").read_text().count("\n") == 2
    assert res["SEASON_SURVEYS"] == str(tmp_path / "survey" / "season" / "surveys.csv")
    names = sorted(d.name for d in context.layersToLoadOnCompletion().values())
    assert names == ["Demo DSM", "Demo orthomosaic", "Demo plots"]
