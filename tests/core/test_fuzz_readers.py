"""Property-based fuzzing of every reader (hypothesis): truncated, bit-flipped, spliced and random
versions of real files. Only the project's own exceptions may come out, with a message, in
bounded time and memory. The budget is set by EASYIDP_FUZZ_EXAMPLES (per reader, default 100)."""
import io
import json
import os
import shutil
import signal
import tracemalloc
import zipfile

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from easyidp_toolbox.core.annotations import read_labelme
from easyidp_toolbox.core.errors import EasyIDPError, InputError, reads_file
from easyidp_toolbox.core.pointcloud import read_point_cloud
from easyidp_toolbox.core.raster.geotiff import open_geotiff
from easyidp_toolbox.core.reconstruction import open_reconstruction
from easyidp_toolbox.core.roi import read_geojson

EXAMPLES = int(os.environ.get("EASYIDP_FUZZ_EXAMPLES", "100"))
MAX_BYTES = 256 * 2**20        # peak Python/numpy allocation allowed for one damaged file
MAX_SECONDS = 20               # per damaged file, generous for a loaded 2-core machine
FUZZ = settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
                suppress_health_check=list(HealthCheck))


@st.composite
def damaged(draw, data: bytes):
    """A damaged copy of ``data``: truncated, bits flipped, a span replaced, or random bytes."""
    kind = draw(st.sampled_from(["truncate", "flip", "splice", "random"]))
    n = len(data)
    if kind == "truncate":
        return data[:draw(st.integers(0, max(n - 1, 0)))]
    if kind == "random":
        return draw(st.binary(min_size=0, max_size=512))
    buf = bytearray(data)
    if kind == "flip":
        for _ in range(draw(st.integers(1, 16))):
            i = draw(st.integers(0, n - 1))
            buf[i] ^= 1 << draw(st.integers(0, 7))
        return bytes(buf)
    i = draw(st.integers(0, n - 1))
    j = min(n, i + draw(st.integers(1, 64)))
    return bytes(buf[:i]) + draw(st.binary(min_size=0, max_size=64)) + bytes(buf[j:])


class _TooSlow(Exception):
    pass


def _alarm(signum, frame):
    raise _TooSlow(f"a damaged file took more than {MAX_SECONDS} s")


def _only_our_errors(read, path):
    """Run ``read(path)``: it returns, or raises an EasyIDPError with a message; memory and time
    bounded (a reader that loops over what a damaged header announces fails here)."""
    tracemalloc.start()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(MAX_SECONDS)
    try:
        read(path)
    except EasyIDPError as exc:
        assert str(exc).strip(), "an error without a message"
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    assert peak < MAX_BYTES, f"{peak / 2**20:.0f} MiB for one damaged file"


@pytest.fixture(scope="module")
def seeds(realdata, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fuzz")
    ply = tmp / "seed.ply"
    from easyidp_toolbox.core import PointCloud, write_point_cloud
    xyz = np.random.default_rng(0).uniform(0, 10, (50, 3))
    write_point_cloud(PointCloud.from_arrays(xyz, {"red": np.arange(50, dtype=np.uint8)}), ply)
    with zipfile.ZipFile(realdata / "easyidp/metashape/wheat_tanashi.files/0/chunk.zip") as z:
        chunk_xml = z.read("doc.xml")
    return {"tif": (realdata / "data-to-science/test.tif").read_bytes(),
            "tif_tiled": (realdata / "d2spy/dsm.tif").read_bytes()[:300_000],
            "las": (realdata / "laspy/simple.las").read_bytes(),
            "laz": (realdata / "laspy/simple.laz").read_bytes(),
            "ply": ply.read_bytes(),
            "geojson": (realdata / "data-to-science/zones_inside_test_tif.geojson").read_bytes(),
            "labelme": (realdata / "easyidp/labelme/labelme_demo_img.json").read_bytes(),
            "chunk_xml": chunk_xml,
            "chunk_zip": (realdata / "easyidp/metashape/wheat_tanashi.files/0/chunk.zip").read_bytes()}


def _file(tmp_path, name, data):
    p = tmp_path / name
    p.write_bytes(data)
    return p


@pytest.mark.parametrize("kind, name, read", [
    ("tif", "x.tif", lambda p: open_geotiff(str(p))),
    ("las", "x.las", read_point_cloud),
    ("laz", "x.laz", read_point_cloud),
    ("ply", "x.ply", lambda p: read_point_cloud(p, source_crs="EPSG:32654")),
    ("geojson", "x.geojson", read_geojson),
    ("labelme", "x.json", read_labelme),
    ("chunk_xml", "cameras.xml", open_reconstruction),
])
def test_single_file_readers(seeds, tmp_path_factory, kind, name, read):
    tmp = tmp_path_factory.mktemp(kind)

    @FUZZ
    @given(data=damaged(seeds[kind]))
    def run(data):
        _only_our_errors(read, _file(tmp, name, data))
    run()


def test_geotiff_block_decoding(seeds, tmp_path_factory):
    """Damaged files that still open must fail on their blocks with our error, not numpy's."""
    from easyidp_toolbox.core.progress import Progress
    from easyidp_toolbox.core.raster.sweep import Window, sweep_windows
    tmp = tmp_path_factory.mktemp("blocks")

    def read(p):
        tif = open_geotiff(str(p))
        sweep_windows(tif, [Window(0, 0, tif.height, tif.width)], lambda k, a: None, Progress())

    @FUZZ
    @given(data=damaged(seeds["tif"]))
    def run(data):
        _only_our_errors(read, _file(tmp, "x.tif", data))
    run()


def test_metashape_project_chunk(seeds, realdata, tmp_path_factory):
    """The chunk.zip of a real .psx project, damaged."""
    tmp = tmp_path_factory.mktemp("psx")
    src = realdata / "easyidp/metashape"
    shutil.copy(src / "wheat_tanashi.psx", tmp / "w.psx")
    shutil.copytree(src / "wheat_tanashi.files", tmp / "w.files")

    @FUZZ
    @given(data=damaged(seeds["chunk_zip"]))
    def run(data):
        (tmp / "w.files/0/chunk.zip").write_bytes(data)
        _only_our_errors(open_reconstruction, tmp / "w.psx")
    run()


def test_metashape_chunk_document_inside_its_zip(seeds, realdata, tmp_path_factory):
    tmp = tmp_path_factory.mktemp("psxdoc")
    src = realdata / "easyidp/metashape"
    shutil.copy(src / "wheat_tanashi.psx", tmp / "w.psx")
    shutil.copytree(src / "wheat_tanashi.files", tmp / "w.files")

    @FUZZ
    @given(data=damaged(seeds["chunk_xml"]))
    def run(data):
        buf = io.BytesIO()
        with zipfile.ZipFile(buf, "w") as z:
            z.writestr("doc.xml", data)
        (tmp / "w.files/0/chunk.zip").write_bytes(buf.getvalue())
        _only_our_errors(open_reconstruction, tmp / "w.psx")
    run()


@pytest.mark.parametrize("suffix", ["_calibrated_camera_parameters.txt", "_pmatrix.txt",
                                    "_offset.xyz", "_pix4d_calibrated_internal_camera_parameters.cam"])
def test_pix4d_params_files(realdata, tmp_path_factory, suffix):
    tmp = tmp_path_factory.mktemp("p4d")
    params = tmp / "params"
    shutil.copytree(realdata / "easyidp/pix4d_origin/1_initial/params", params)
    target = params / f"pix4d.origin{suffix}"
    seed = target.read_bytes()

    @FUZZ
    @given(data=damaged(seed))
    def run(data):
        target.write_bytes(data)
        _only_our_errors(lambda p: open_reconstruction(p, source_crs="EPSG:32654"), params)
    run()


# ---- valid JSON of the wrong shape: a clear error, not a TypeError from deep in the reader -----
WRONG_SHAPES = {
    "geojson": [
        {"type": "FeatureCollection", "features": [1]},
        {"type": "FeatureCollection", "features": [
            {"type": "Feature", "geometry": {"type": "Polygon", "coordinates": 5}}]},
        {"type": "FeatureCollection", "features": [
            {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [[7]]}}]},
        {"type": "FeatureCollection", "features": [
            {"type": "Feature", "properties": 5, "geometry": {
                "type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 0]]]}}]},
        {"type": "Polygon", "coordinates": "abc"},
    ],
    "labelme": [
        {"shapes": 5}, {"shapes": [5]}, {"shapes": [{"points": 5}]},
        {"shapes": [{"points": [[1, 2], [3, 4], [5, "a"]], "shape_type": "polygon", "label": 1}]},
    ],
}
JSON_READERS = {"geojson": read_geojson, "labelme": read_labelme}


@pytest.mark.parametrize("fmt, i", [(f, i) for f, docs in WRONG_SHAPES.items()
                                    for i in range(len(docs))])
def test_json_of_the_wrong_shape_is_a_clear_error(tmp_path, fmt, i):
    """The reader checks the structure it walks: a wrong type anywhere is an EasyIDPError naming
    the file (TypeError and AttributeError are reader bugs and are not turned into errors)."""
    path = tmp_path / f"wrong_{fmt}_{i}.json"
    path.write_text(json.dumps(WRONG_SHAPES[fmt][i]))
    with pytest.raises(EasyIDPError) as err:
        JSON_READERS[fmt](path)
    assert str(err.value)


def test_a_reader_bug_is_not_reported_as_a_damaged_file(tmp_path):
    """reads_file turns parse errors into InputError, but lets a reader's TypeError through."""
    @reads_file("advice")
    def buggy(path):
        return len(5)

    @reads_file("advice")
    def parses(path):
        return int("not a number")

    with pytest.raises(TypeError):
        buggy(tmp_path / "x")
    with pytest.raises(InputError, match="damaged.*advice"):
        parses(tmp_path / "x")
