"""The tools run again and again in QGIS's task threads, as the desktop's dialogs and batch mode run
them (``QgsProcessingAlgRunnerTask`` on QGIS's thread pool, threads Python did not create).

pyproj 3.7.0 and 3.7.1 (Debian 13's) crashed QGIS there on the second run in a pooled thread
(pyproj#1509): ``algorithms/base.py`` keeps each thread's PROJ context alive."""
import time

from qgis.core import (QgsApplication, QgsProcessingAlgRunnerTask, QgsProcessingContext,
                       QgsProcessingFeedback)

ZONES = "data-to-science/zones_inside_test_tif.geojson"
DSM = "data-to-science/test.tif"


def _run_in_task(alg_id, params):
    """(ok, results) of one run in a task of QGIS's task manager."""
    alg = QgsApplication.processingRegistry().createAlgorithmById(alg_id)
    context, feedback = QgsProcessingContext(), QgsProcessingFeedback()
    done = {}
    task = QgsProcessingAlgRunnerTask(alg, params, context, feedback)
    task.executed.connect(lambda ok, results: done.update(ok=ok, results=results))
    QgsApplication.taskManager().addTask(task)
    end = time.time() + 300
    while not done and time.time() < end:
        QgsApplication.processEvents()
        time.sleep(0.02)
    assert done, f"{alg_id} did not finish in its task"
    return done["ok"], done["results"], feedback.textLog()


def test_tools_run_many_times_in_task_threads(provider, realdata, tmp_path):
    for k in range(6):
        ok, results, log = _run_in_task("easyidp:croprasterbyrois", {
            "INPUT": str(realdata / DSM), "ROIS": str(realdata / ZONES), "NAME_FIELD": "row",
            "OUTPUT_FOLDER": str(tmp_path / f"crops{k}")})
        assert ok, log
        assert results["CROPPED"] == 20 and len(list((tmp_path / f"crops{k}").glob("*.tif"))) == 20
