"""Create demo survey in real QGIS: outputs open as layers and are queued for the map."""
from qgis.core import (NULL, QgsProcessingContext, QgsProcessingFeedback, QgsProject,
                       QgsRasterLayer, QgsVectorLayer)

from easyidp_toolbox.core.demo import NO_MESS, FieldMess


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
    for key in ("POINT_CLOUD", "METASHAPE_PROJECT", "PIX4D_PROJECT", "ODM_PROJECT", "OPF_PROJECT",
                "TRUTH"):
        assert (tmp_path / "survey").as_posix() in res[key]
    assert (tmp_path / "survey" / "season" / "surveys.csv").read_text().count("\n") == 2
    assert res["SEASON_SURVEYS"] == str(tmp_path / "survey" / "season" / "surveys.csv")
    names = sorted(d.name for d in context.layersToLoadOnCompletion().values())
    assert names == ["Demo DSM", "Demo orthomosaic", "Demo plots"]
    assert _field_mess(res) == _asdict(FieldMess())          # the default: the messy field
    _odm_footprints_match_metashape(res)


def test_the_tidy_field(provider, tmp_path):
    """FIELD_MESS 1 writes the tidy field (the core's NO_MESS), as truth.json records it."""
    import processing
    res = processing.run("easyidp:createdemosurvey", {"OUTPUT_FOLDER": str(tmp_path / "tidy"),
                                                      "FIELD_MESS": 1},
                         context=QgsProcessingContext(), feedback=QgsProcessingFeedback())
    assert _field_mess(res) == _asdict(NO_MESS)
    assert QgsVectorLayer(res["PLOTS"], "p", "ogr").featureCount() == 40


def _asdict(mess):
    from dataclasses import asdict
    return asdict(mess)


def _field_mess(res):
    import json
    with open(res["TRUTH"]) as fh:
        doc = json.load(fh)["field_mess"]
    doc.pop("description", None)
    return doc


def _odm_footprints_match_metashape(res):
    """Camera footprints of the demo's OpenDroneMap project (its opensfm/reconstruction.json)
    and OPF project on the DSM: the same cameras, places and areas as through the Metashape
    project (OPF: areas to 1 %, as it has no affinity term b1)."""
    import processing
    out = {}
    for name, project in (("odm", res["ODM_PROJECT"] + "/opensfm/reconstruction.json"),
                          ("opf", res["OPF_PROJECT"]), ("metashape", res["METASHAPE_PROJECT"])):
        r = processing.run("easyidp:camerafootprints", {
            "PROJECT": project, "DSM": res["DSM"], "OUTPUT_CRS": "EPSG:32654",
            "OUTPUT_CAMERAS": "memory:", "OUTPUT_FOOTPRINTS": "memory:"},
            context=QgsProcessingContext(), feedback=QgsProcessingFeedback())
        out[name] = {f["label"].split(".")[0]: f for f in r["OUTPUT_FOOTPRINTS"].getFeatures()}
        assert r["OUTPUT_FOOTPRINTS"].crs().authid() == "EPSG:32654"
    assert sorted(out["odm"]) == sorted(out["metashape"]) == sorted(out["opf"]) and len(out["odm"]) == 36
    for label, f in out["opf"].items():
        g = out["metashape"][label]
        assert f["complete"] == g["complete"] and abs(f["area"] - g["area"]) < 1e-2 * g["area"]
    for label, f in out["odm"].items():
        g = out["metashape"][label]
        assert f["complete"] == g["complete"] and abs(f["area"] - g["area"]) < 1e-3 * g["area"]
        hf, hg = f["height_above_ground"], g["height_above_ground"]
        assert (hf == NULL) == (hg == NULL)            # NULL where the DSM has no data below
        assert hf == NULL or abs(hf - hg) < 1e-3
        # ring vertices: the skew (< 0.15 px, about 5 mm here) moves them a little, except
        # where a border ray grazes a plant and lands on its other side
        a = [(v.x(), v.y()) for v in f.geometry().vertices()]
        b = [(v.x(), v.y()) for v in g.geometry().vertices()]
        d = sorted(((xa - xb) ** 2 + (ya - yb) ** 2) ** 0.5 for (xa, ya), (xb, yb) in zip(a, b))
        assert len(a) == len(b) and d[len(d) // 2] < 0.005
        assert f["photo_path"].endswith("/odm/images/" + label + ".JPG")
