"""A season of surveys: traits per plot per date, on local processes and on a real Dask cluster.

Independent truths: the demo season's heights and covers are analytic, by construction
(``core/demo/season.py``: logistic heights, row bands clipped to the plot); band means and the
vegetation index are checked against a brute force with matplotlib's point-in-polygon on every
pixel centre; Otsu's threshold against scikit-image on the raw pixel values; ground planes
against synthetic planes.
"""
import csv
import json
import os
import shutil
import signal
import threading
import time

import numpy as np
import pytest
import tifffile

from easyidp_toolbox.core.errors import Cancelled, EasyIDPError, InputError, ROIError
from easyidp_toolbox.core.roi import ROI, ROISet, read_geojson
from easyidp_toolbox.core.season import (plot_growth_curves, read_survey_table, run_season,
                                         surveys_from_rows, write_long_csv,
                                         write_season_geopackage)
from easyidp_toolbox.core.season import executors
from easyidp_toolbox.core.season.ground import fit_plane, low_plane
from easyidp_toolbox.core.indices import INDEX_BINS, index_histogram, otsu_threshold

from easyidp_toolbox.tests.support.season_helpers import small_season
from easyidp_toolbox.tests.support.synthetic import write_tif

TIMEOUT = 600   # seconds: generous, for a loaded 2-core machine


@pytest.fixture(scope="module")
def season(tmp_path_factory):
    return small_season(tmp_path_factory.mktemp("season"))


@pytest.fixture(scope="module")
def rois(season):
    return read_geojson(season.plots, name_field="plot_id")


@pytest.fixture(scope="module")
def truth(season):
    with open(season.truth) as fh:
        return json.load(fh)


@pytest.fixture(scope="module")
def local_result(season, rois):
    return run_season(season.surveys, rois, ground=season.ground, workers=2)


# ---- the survey table ---------------------------------------------------------------------------

def test_survey_table_paths_dates_and_bad_rows(tmp_path):
    (tmp_path / "d1").mkdir()
    (tmp_path / "d1" / "ortho.tif").write_bytes(b"x")
    (tmp_path / "dsm.tif").write_bytes(b"x")
    (tmp_path / "surveys.csv").write_text(
        "Date;Orthomosaic;DSM;point_cloud;project;bands\n"
        "2024-06-01;d1/ortho.tif;;;;blue green red nir\n"
        "01/06/2024;d1/ortho.tif;;;;\n"
        f"2024-06-08T10:30;;{tmp_path / 'dsm.tif'};missing.laz;;\n"
        "2024-06-15;;;;;\n"
        "2024-06-22;gone.tif;NULL;;;\n", encoding="utf-8")
    t = read_survey_table(str(tmp_path / "surveys.csv"))
    assert [(s.row, s.date) for s in t.surveys] == [(1, "2024-06-01"), (3, "2024-06-08T10:30")]
    assert t.surveys[0].orthomosaic == str(tmp_path / "d1" / "ortho.tif")
    assert t.surveys[0].bands == ("blue", "green", "red", "nir")
    assert t.surveys[1].dsm == str(tmp_path / "dsm.tif") and t.surveys[1].point_cloud is None
    msgs = [str(p) for p in t.problems]
    assert msgs[0].startswith("row 2, date: '01/06/2024' is not a date")
    assert msgs[1].startswith("row 3 (2024-06-08T10:30), point_cloud: file not found")
    assert msgs[2] == ("row 4 (2024-06-15): no orthomosaic, DSM or point cloud given; the row "
                       "is left out.")
    assert msgs[3].startswith("row 5 (2024-06-22), orthomosaic: file not found")
    assert len(msgs) == 4


def test_survey_table_without_date_or_files_is_refused(tmp_path):
    with pytest.raises(InputError, match="no 'date' column"):
        surveys_from_rows([{"when": "2024-06-01", "dsm": "a.tif"}], str(tmp_path))
    with pytest.raises(InputError, match="none of the columns"):
        surveys_from_rows([{"date": "2024-06-01", "photos": "a"}], str(tmp_path))
    with pytest.raises(InputError, match="not found"):
        read_survey_table(str(tmp_path / "nope.csv"))


# ---- traits against the truth -------------------------------------------------------------------

def _errors(result, truth, trait, key):
    table = result.table()
    out = []
    for pid, t in truth["plots"].items():
        for k, d in enumerate(truth["dates"]):
            out.append(table[(pid, d)][trait] - t[key][k])
    return np.abs(out)


def test_heights_and_cover_match_the_truth(local_result, truth):
    """Truth by construction (analytic). Issue: heights within 5 cm, cover within 5 %."""
    r = local_result
    assert r.problems == [] and r.dates == truth["dates"]
    assert len(r.rows) == 6 * 4 * len(r.traits)
    assert _errors(r, truth, "height_p99", "height").max() < 0.01       # DTM ground
    assert _errors(r, truth, "cloud_height_p99", "height").max() < 0.01
    assert _errors(r, truth, "cover", "cover").max() < 0.01
    # heights grow, and p50 < p95 < p99
    t = r.table()
    for pid in truth["plots"]:
        h = [t[(pid, d)]["height_p99"] for d in r.dates]
        assert h == sorted(h)
        v = t[(pid, r.dates[-1])]
        assert v["height_p50"] < v["height_p95"] < v["height_p99"]
        assert v["cloud_points"] > 500


def test_heights_without_a_dtm_use_each_plots_low_points(season, rois, truth):
    r = run_season(season.surveys, rois, traits=["height", "cloud"], workers=1)
    assert r.traits == ["height_p50", "height_p95", "height_p99", "cloud_points",
                        "cloud_height_p50", "cloud_height_p95", "cloud_height_p99"]
    assert _errors(r, truth, "height_p99", "height").max() < 0.02    # sloped ground: 2 cm/m
    assert _errors(r, truth, "cloud_height_p99", "height").max() < 0.02


def test_band_means_and_exg_agree_with_a_brute_force(season, rois, local_result):
    """Brute force: matplotlib's point-in-polygon on every pixel centre, numpy means."""
    from matplotlib.path import Path
    img = tifffile.imread(season.orthomosaics[1])
    with tifffile.TiffFile(season.orthomosaics[1]) as tif:
        x0, y0 = tif.pages[0].tags["ModelTiepointTag"].value[3:5]
        px = tif.pages[0].tags["ModelPixelScaleTag"].value[0]
    t = local_result.table()
    d = local_result.dates[1]
    all_exg = []
    for roi in rois:
        xmin, ymin, xmax, ymax = roi.bounds
        c0, c1 = int((xmin - x0) / px), int((xmax - x0) / px) + 1
        r0, r1 = int((y0 - ymax) / px), int((y0 - ymin) / px) + 1
        cc, rr = np.meshgrid(np.arange(c0, c1), np.arange(r0, r1))
        centres = np.column_stack([x0 + (cc.ravel() + 0.5) * px, y0 - (rr.ravel() + 0.5) * px])
        inside = Path(roi.rings[0]).contains_points(centres).reshape(cc.shape)
        v = img[r0:r1, c0:c1][inside].astype(np.float64)
        for k, band in enumerate(("red", "green", "blue")):
            assert t[(roi.name, d)][f"mean_{band}"] == pytest.approx(v[:, k].mean(), rel=1e-9)
        exg = (2 * v[:, 1] - v[:, 0] - v[:, 2]) / v.sum(axis=1)
        assert t[(roi.name, d)]["exg"] == pytest.approx(exg.mean(), rel=1e-9)
        all_exg.append(exg)
    # Otsu over the pooled histogram agrees with scikit-image on the raw values to a bin
    from skimage.filters import threshold_otsu
    values = np.concatenate(all_exg)
    ours = otsu_threshold("exg", np.bincount(_bins(values), minlength=INDEX_BINS))
    assert abs(ours - threshold_otsu(values, nbins=INDEX_BINS)) < 0.01
    note = [n for j in local_result.jobs if j.row == 2 and j.kind == "orthomosaic" for n in j.notes]
    assert note and f"cover threshold {ours:.3f}" in note[0]


def _bins(values):
    start, counts = index_histogram("exg", values)
    return np.repeat(np.arange(start, start + len(counts)), counts)


def test_ndvi_and_band_names_from_gdal_metadata(tmp_path):
    """A 4-band uint16 raster whose bands GDAL named: NDVI and cover from red and nir."""
    nir = np.full((40, 60), 3000, np.uint16)
    red = np.full((40, 60), 1000, np.uint16)
    nir[:, 30:] = 1200                       # the east half is soil: NDVI ≈ 0.09, west 0.5
    data = np.stack([red // 2, red, red, nir], axis=-1)
    meta = ("<GDALMetadata>" + "".join(
        f'<Item name="DESCRIPTION" sample="{k}" role="description">{n}</Item>'
        for k, n in enumerate(("Blue", "Green", "Red", "NIR"))) + "</GDALMetadata>")
    path = str(tmp_path / "ms.tif")
    tifffile.imwrite(path, data, photometric="minisblack", planarconfig="contig", tile=(16, 16),
                     extratags=[(33550, "d", 3, (0.5, 0.5, 0.0), True),
                                (33922, "d", 6, (0, 0, 0, 368000.0, 3956000.0, 0), True),
                                (34735, "H", 16, (1, 1, 0, 3, 1024, 0, 1, 1, 1025, 0, 1, 1,
                                                  3072, 0, 1, 32654), True),
                                (42112, "s", 0, meta, True)], metadata=None)
    roi = ROI("west_and_east", [[np.array([[368005.0, 3955990.0], [368025.0, 3955990.0],
                                           [368025.0, 3955995.0], [368005.0, 3955995.0]])]])
    table = surveys_from_rows([{"date": "2024-06-01", "orthomosaic": path}], str(tmp_path))
    r = run_season(table, ROISet([roi], "EPSG:32654"), traits=["bands", "index", "cover"],
                   cover_threshold=0.3, workers=1)
    v = r.table()[("west_and_east", "2024-06-01")]
    assert v["mean_nir"] == pytest.approx(2100.0) and v["mean_blue"] == pytest.approx(500.0)
    assert v["ndvi"] == pytest.approx((0.5 + 0.2 / 2.2) / 2)
    assert v["cover"] == pytest.approx(0.5)


def test_ground_planes_follow_a_slope():
    rng = np.random.default_rng(1)
    x, y = rng.uniform(0, 4, 500), rng.uniform(0, 2.5, 500)
    z = 10.0 + 0.03 * x - 0.02 * y
    p = fit_plane(x, y, z, (2.0, 1.25))
    assert p.at(1.0, 2.0) == pytest.approx(10.03 - 0.04)
    canopy = np.where((np.round(y / 0.5) * 0.5 - y) ** 2 < 0.01, 0.4, 0.0)   # rows, soil between
    low = low_plane(x, y, z + canopy, 2.0, (2.0, 1.25))
    assert abs(low.bx - 0.03) < 0.005 and abs(low.by + 0.02) < 0.005
    assert abs(low.at(2.0, 1.25) - (10.0 + 0.06 - 0.025)) < 0.01


# ---- executors ----------------------------------------------------------------------------------

def test_local_processes_and_a_dask_local_cluster_give_identical_tables(season, rois, local_result):
    dask = run_season(season.surveys, rois, ground=season.ground, workers=2, local_cluster=True)
    assert dask.executor.startswith("Dask LocalCluster")
    assert dask.rows == local_result.rows and dask.traits == local_result.traits
    assert len({j.worker for j in dask.jobs}) == 2      # two worker processes did the work


def _trim_threshold():
    return os.environ.get("MALLOC_TRIM_THRESHOLD_")


def test_the_local_cluster_workers_keep_the_default_allocator():
    """Dask's nannies set MALLOC_TRIM_THRESHOLD_=65536 by default, which made every season job
    twice as slow in a LocalCluster (measured in bench_season); ours start without it."""
    with executors.open_runner(2, local_cluster=True) as runner:
        assert list(runner.client.run(_trim_threshold).values()) == [None, None]


@pytest.fixture(scope="module")
def cluster():
    """A real Dask LocalCluster: a scheduler and two worker processes (nannies restart them)."""
    import logging
    from dask.distributed import Client, LocalCluster
    executors.python_executable()
    c = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                     dashboard_address=None, silence_logs=logging.ERROR)
    client = Client(c)
    yield c, client
    client.close()
    c.close()


def test_a_worker_killed_during_a_job_still_gives_the_full_identical_table(cluster, season, rois,
                                                                          local_result):
    """The test watches the workers' call stacks, SIGKILLs the worker running the first job
    it sees, and checks that the job's result came from another process."""
    c, client = cluster
    for attempt in range(3):
        client.wait_for_workers(2, timeout=TIMEOUT)
        pids = client.run(os.getpid)
        box = {}

        def go():
            box["result"] = run_season(season.surveys, rois, ground=season.ground,
                                       scheduler=c.scheduler_address)
        th = threading.Thread(target=go, daemon=True)
        th.start()
        killed = None
        deadline = time.monotonic() + TIMEOUT
        while killed is None and th.is_alive() and time.monotonic() < deadline:
            for worker, tasks in client.call_stack().items():
                keys = [k for k in tasks if str(k).startswith("easyidp-")]
                if keys and worker in pids:
                    os.kill(pids[worker], signal.SIGKILL)
                    killed = (pids[worker], str(keys[0]))
                    break
            time.sleep(0.002)
        th.join(TIMEOUT)
        assert not th.is_alive()
        result = box["result"]
        assert result.rows == local_result.rows and result.problems == []
        if killed is None:
            continue
        job = [j for j in result.jobs if killed[1].endswith("-" + j.key)]
        assert len(job) == 1
        if not job[0].worker.endswith(f":{killed[0]}"):
            return          # computed again by another worker after the kill
    pytest.fail("no job could be caught running on a worker in 3 attempts")


def test_cancel_stops_the_season_and_leaves_only_complete_crops(season, rois, tmp_path):
    calls = {"n": 0}

    def cancelled():
        calls["n"] += 1
        return calls["n"] > 3
    with pytest.raises(Cancelled):
        run_season(season.surveys, rois, ground=season.ground, workers=2,
                   crops=str(tmp_path / "crops"), is_cancelled=cancelled)
    parts = [p for p in (tmp_path / "crops").rglob("*") if ".part" in p.name]
    assert parts == []


def test_unreachable_scheduler_is_a_clear_error(season, rois, monkeypatch):
    monkeypatch.setattr(executors, "CONNECT_TIMEOUT", "2s")
    with pytest.raises(EasyIDPError, match="Cannot reach the Dask scheduler"):
        run_season(season.surveys, rois, scheduler="tcp://127.0.0.1:9")


# ---- bad rows -----------------------------------------------------------------------------------

def test_bad_rows_are_reported_by_row_and_the_rest_completes(season, rois, local_result, tmp_path):
    """Row 2: a missing DSM; row 3: a corrupt DSM (valid header, garbage tiles); row 4: an
    orthomosaic that is not a TIFF, a DSM in another CRS far away, a DSM without CRS."""
    d = season.dates
    corrupt = tmp_path / "corrupt.tif"
    shutil.copy(season.dsms[2], corrupt)
    with tifffile.TiffFile(corrupt) as tif:
        offsets, counts = tif.pages[0].dataoffsets, tif.pages[0].databytecounts
    with open(corrupt, "r+b") as fh:
        for o, n in zip(offsets, counts):
            fh.seek(o)
            fh.write(b"\xff" * n)
    (tmp_path / "text.tif").write_text("not a raster")
    dsm = tifffile.imread(season.dsms[3])
    write_tif(str(tmp_path / "far.tif"), dsm, origin=(10.0, 40.0), pixel=2e-7, epsg=4326,
              nodata=-9999, tile=256)
    write_tif(str(tmp_path / "nocrs.tif"), dsm, origin=(319800.0, 3956050.0), pixel=0.02,
              georef=True, nodata=-9999, tile=256, epsg=32767)
    rows = [
        {"date": d[0], "orthomosaic": season.orthomosaics[0], "dsm": season.dsms[0],
         "point_cloud": season.point_clouds[0]},
        {"date": d[1], "orthomosaic": season.orthomosaics[1], "dsm": "missing/dsm.tif",
         "point_cloud": season.point_clouds[1]},
        {"date": d[2], "orthomosaic": season.orthomosaics[2], "dsm": str(corrupt),
         "point_cloud": season.point_clouds[2]},
        {"date": d[3], "orthomosaic": str(tmp_path / "text.tif"), "dsm": str(tmp_path / "far.tif"),
         "point_cloud": season.point_clouds[3]},
        {"date": d[3], "dsm": str(tmp_path / "nocrs.tif")},
    ]
    table = surveys_from_rows(rows, str(tmp_path))
    r = run_season(table, rois, ground=season.ground, workers=2)
    msgs = [str(p) for p in r.problems]
    assert len(msgs) == 5, msgs
    assert msgs[0].startswith(f"row 2 ({d[1]}), dsm: file not found")
    assert msgs[1].startswith(f"row 3 ({d[2]}), dsm: ") and "corrupt" in msgs[1]
    assert msgs[2].startswith(f"row 4 ({d[3]}), dsm: None of the 6 ROIs overlaps")
    assert msgs[3].startswith(f"row 4 ({d[3]}), orthomosaic: ") and "not a readable GeoTIFF" in msgs[3]
    assert msgs[4].startswith(f"row 5 ({d[3]}), dsm: The CRS of") and "cannot be read" in msgs[4]
    good = set(local_result.rows)
    lost = {(d[1], "height"), (d[2], "height"), (d[3], "height"), (d[3], "mean_"),
            (d[3], "cover"), (d[3], "exg")}
    expected = [row for row in local_result.rows
                if not any(row[1] == dd and row[2].startswith(t) for dd, t in lost)]
    assert r.rows == expected and set(r.rows) <= good


def test_bad_arguments_are_refused(season, rois):
    dup = ROISet([rois[0], rois[0]], rois.crs)
    with pytest.raises(ROIError, match="unique"):
        run_season(season.surveys, dup, workers=1)
    with pytest.raises(EasyIDPError, match="Unknown trait"):
        run_season(season.surveys, rois, traits=["biomass"], workers=1)
    with pytest.raises(EasyIDPError, match="Ground raster not found"):
        run_season(season.surveys, rois, ground="/nowhere/dtm.tif", workers=1)
    with pytest.raises(EasyIDPError, match="percentiles"):
        run_season(season.surveys, rois, percentiles=[50, 120], workers=1)


def test_a_missing_package_is_named(season, rois, local_result, tmp_path, monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "skimage.filters", None)
    with pytest.raises(EasyIDPError, match="needs scikit-image.*pip install scikit-image"):
        run_season(season.surveys, rois, traits=["cover"], workers=1)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(EasyIDPError, match="pip install .dask.distributed.."):
        run_season(season.surveys, rois, traits=["height"], local_cluster=True)
    monkeypatch.setitem(sys.modules, "matplotlib.backends.backend_agg", None)
    with pytest.raises(EasyIDPError, match="need matplotlib.*pip install matplotlib"):
        plot_growth_curves(local_result, str(tmp_path / "c.png"))


# ---- outputs ------------------------------------------------------------------------------------

def test_outputs_csv_geopackage_and_curves(local_result, rois, tmp_path):
    import sqlite3
    csv_path = write_long_csv(local_result, str(tmp_path / "traits.csv"))
    with open(csv_path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(local_result.rows)
    assert {k: rows[0][k] for k in ("roi", "date", "trait")} == \
        dict(zip(("roi", "date", "trait"), local_result.rows[0][:3]))
    assert float(rows[0]["value"]) == pytest.approx(local_result.rows[0][3], rel=1e-9)

    gpkg = write_season_geopackage(local_result, str(tmp_path / "season.gpkg"))
    con = sqlite3.connect(gpkg)
    assert con.execute("PRAGMA application_id").fetchone()[0] == 0x47504B47
    assert con.execute('SELECT count(*) FROM "traits"').fetchone()[0] == len(local_result.rows)
    latest = con.execute('SELECT plot_id, variety, date, height_p99 FROM "latest" ORDER BY fid').fetchall()
    assert [r[0] for r in latest] == [r.name for r in rois]
    assert all(r[2] == local_result.dates[-1] and r[3] > 0.3 for r in latest)
    assert con.execute("SELECT srs_id FROM gpkg_geometry_columns").fetchone()[0] == 32654
    con.close()
    try:
        from osgeo import ogr
    except ImportError:   # the current-stack environment has no GDAL; sqlite3 checked it above
        ogr = None
    if ogr is not None:
        ds = ogr.Open(gpkg)
        lyr = ds.GetLayerByName("latest")
        assert lyr.GetFeatureCount() == 6 and lyr.GetSpatialRef().GetAuthorityCode(None) == "32654"
        f = lyr.GetNextFeature()
        assert f.GetGeometryRef().GetArea() == pytest.approx(rois[0].area, rel=1e-9)
        assert ds.GetLayerByName("traits").GetFeatureCount() == len(local_result.rows)

    with pytest.raises(InputError, match="inputs are never overwritten"):
        write_long_csv(local_result, local_result.inputs[0])
    with pytest.raises(InputError, match="inputs are never overwritten"):
        write_season_geopackage(local_result, local_result.inputs[-1])
    png = plot_growth_curves(local_result, str(tmp_path / "curves.png"),
                             groups={r.name: r.attributes["variety"] for r in rois})
    from matplotlib.image import imread
    img = imread(png)
    assert img.shape[0] > 300 and img.shape[1] > 500
    many = plot_growth_curves(local_result, str(tmp_path / "groups.png"), max_panels=2,
                              groups={r.name: r.attributes["variety"] for r in rois})
    assert imread(many).shape[1] < img.shape[1]           # a panel per group: fewer panels


def test_crops_per_date(season, rois, tmp_path):
    table = read_survey_table(season.surveys)
    table.surveys = table.surveys[:1]
    r = run_season(table, rois, traits=["height", "cover"], ground=season.ground, workers=1,
                   crops=str(tmp_path / "crops"))
    d = r.dates[0]
    assert sorted(p.name for p in (tmp_path / "crops" / d / "orthomosaic").iterdir()) == \
        sorted(f"{n}.tif" for n in rois.names)
    assert len(list((tmp_path / "crops" / d / "dsm").iterdir())) == 6
    assert not (tmp_path / "crops" / d / "point_cloud").exists()   # cloud traits not asked


def test_demo_season_is_deterministic(season, tmp_path):
    again = small_season(tmp_path / "again", dates=2)
    for a, b in ((season.plots, again.plots), (season.ground, again.ground),
                 (season.orthomosaics[0], again.orthomosaics[0]), (season.dsms[0], again.dsms[0]),
                 (season.point_clouds[0], again.point_clouds[0])):
        with open(a, "rb") as fa, open(b, "rb") as fb:
            assert fa.read() == fb.read(), os.path.basename(a)


def test_season_outputs_are_never_its_inputs(season, tmp_path):
    from easyidp_toolbox.core.season import check_season_outputs, season_inputs
    table = read_survey_table(season.surveys)
    inputs = season_inputs(table, season.ground)
    assert season.surveys in inputs and season.ground in inputs and season.dsms[0] in inputs
    check_season_outputs(table, [str(tmp_path / "t.gpkg"), None], season.ground)
    for target in (season.dsms[0], season.ground, season.surveys, str(tmp_path / "extra.csv")):
        with pytest.raises(InputError, match="is the input file itself"):
            check_season_outputs(table, [None, target], season.ground,
                                 also=[str(tmp_path / "extra.csv")])
