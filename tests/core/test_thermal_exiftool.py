"""FLIR photos we write, read by exiftool (Debian's libimage-exiftool-perl, ``make apt``): the
raw image of both encodings and the Planck constants and object parameters."""
import io
import json
import subprocess

import numpy as np
import pytest
import tifffile
from PIL import Image

from easyidp_toolbox.core.demo.flir_writer import write_flir_jpeg
from easyidp_toolbox.core.radiometry import ThermalParameters, celsius_to_raw, read_flir

TAGS = ["PlanckR1", "PlanckR2", "PlanckB", "PlanckF", "PlanckO", "Emissivity", "ObjectDistance",
        "ReflectedApparentTemperature", "AtmosphericTemperature", "RelativeHumidity",
        "IRWindowTemperature", "IRWindowTransmission", "RawThermalImageWidth",
        "RawThermalImageHeight", "CameraModel"]


def exiftool(*args):
    return subprocess.run(["exiftool", *args], check=True, capture_output=True).stdout


@pytest.mark.parametrize("encoding", ["png", "tiff"])
def test_exiftool_reads_what_we_write(tmp_path, encoding):
    """[independent] exiftool extracts the raw thermal image (PNG: its bytes swapped, as FLIR
    writes it; TIFF: the XT2's) and the CameraInfo tags; they equal what our reader takes."""
    p = ThermalParameters(r1=15000.0, r2=0.0125, b=1400.0, f=1.0, o=-7000.0, emissivity=0.97,
                          object_distance=25.0, reflected_temperature=10.0,
                          atmospheric_temperature=28.0, relative_humidity=0.45,
                          ir_window_temperature=30.0, ir_window_transmission=0.9)
    yy, xx = np.mgrid[0:60, 0:80]
    raw = np.round(celsius_to_raw(20 + xx / 8.0 + np.sin(yy / 5.0), p)).astype(np.uint16)
    path = tmp_path / f"x_{encoding}.jpg"
    write_flir_jpeg(path, raw, p, encoding=encoding, model="XT2" if encoding == "tiff" else
                    "FLIR Duo Pro R")
    blob = exiftool("-b", "-RawThermalImage", str(path))
    if encoding == "png":
        theirs = np.asarray(Image.open(io.BytesIO(blob))).astype(np.uint16).byteswap()
    else:
        theirs = tifffile.imread(io.BytesIO(blob))
    np.testing.assert_array_equal(theirs, raw)
    tags = json.loads(exiftool("-j", "-n", *[f"-{t}" for t in TAGS], str(path)))[0]
    ours = read_flir(path, path.read_bytes())
    q = ours.parameters
    np.testing.assert_array_equal(ours.raw, theirs)
    assert (tags["RawThermalImageWidth"], tags["RawThermalImageHeight"]) == (80, 60)
    assert tags["CameraModel"] == ours.model
    for tag, mine in [("PlanckR1", q.r1), ("PlanckR2", q.r2), ("PlanckB", q.b), ("PlanckF", q.f),
                      ("PlanckO", q.o), ("Emissivity", q.emissivity),
                      ("ObjectDistance", q.object_distance),
                      ("ReflectedApparentTemperature", q.reflected_temperature),
                      ("AtmosphericTemperature", q.atmospheric_temperature),
                      ("RelativeHumidity", q.relative_humidity),
                      ("IRWindowTemperature", q.ir_window_temperature),
                      ("IRWindowTransmission", q.ir_window_transmission)]:
        assert tags[tag] == pytest.approx(mine, rel=1e-6, abs=1e-4), tag
    assert q.o == -7000.0 and q.emissivity == pytest.approx(0.97, abs=1e-6)
