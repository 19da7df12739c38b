"""Cameras and footprints in real QGIS on goya_test (rolling-shutter compensation on in
Metashape): the log says that the compensation is applied. (The footprint rings of moving
cameras are checked on the rolling-shutter demo survey in tests/core.)"""
from qgis.core import QgsProcessingContext, QgsProcessingFeedback


class _Log(QgsProcessingFeedback):
    def __init__(self):
        super().__init__()
        self.lines = []

    def pushInfo(self, info):  # noqa: N802 (QGIS API)
        self.lines.append(info)
        super().pushInfo(info)

    def pushWarning(self, warning):  # noqa: N802 (QGIS API)
        self.lines.append(warning)
        super().pushWarning(warning)


def test_goya_log_says_compensation_is_applied(provider, realdata):
    import processing
    log = _Log()
    res = processing.run("easyidp:camerafootprints",
                         {"PROJECT": str(realdata / "easyidp/metashape/goya_test.psx"),
                          "GROUND_HEIGHT": 0, "OUTPUT_CAMERAS": "memory:",
                          "OUTPUT_FOOTPRINTS": "memory:"},
                         context=QgsProcessingContext(), feedback=log)
    text = "\n".join(log.lines)
    assert "rolling-shutter compensation applied: 256 of 256 aligned camera(s)" in text
    assert "rolling-shutter compensation on 256" in text           # the summary line
    assert res["OUTPUT_CAMERAS"].featureCount() == 256


def test_wheat_log_does_not_mention_it(provider, realdata):
    import processing
    log = _Log()
    processing.run("easyidp:camerafootprints",
                   {"PROJECT": str(realdata / "easyidp/metashape/wheat_tanashi.psx"),
                    "GROUND_HEIGHT": 97, "OUTPUT_CAMERAS": "memory:", "OUTPUT_FOOTPRINTS": "memory:"},
                   context=QgsProcessingContext(), feedback=log)
    assert not any("rolling" in line for line in log.lines)
