"""Runs started together into one output, and runs killed with SIGKILL, through the real
qgis_process (issue 40; README "Files and safety").

- Runs started together into one GeoPackage or one output folder: exactly one succeeds, the
  others are refused naming the output, and the file holds the winner's result (its feature
  count checked against the winner's own log).
- ``kill -9`` at random moments while Forward-project and Back-project (with photo crops) write:
  what is left is either complete (a GeoPackage GDAL opens) or removed by the next run; the
  re-run leaves nothing of the plugin's temporary files (``.part`` files, locks, SQLite
  journals) anywhere in the output tree. The truths are GDAL's reading of the files and a clean
  run's list of crops.
"""
import json
import os
import random
import re
import subprocess
import time
from pathlib import Path

import pytest

from easyidp_toolbox.scripts.qgis_process import EXE, run

# runs' own temporary names: .<stem>.<pid>-<thread>.part<ext>, .<name>.easyidp.lock, journals
TEMPORARY = re.compile(r"(\.part(\.\w+)?$|easyidp\.lock$|-journal$|-wal$|-shm$)")


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    from easyidp_toolbox.core.demo import make_demo_survey
    return make_demo_survey(str(tmp_path_factory.mktemp("together_survey")), seed=0, size="small")


def _args(alg, params):
    return [EXE, "--json", "run", alg, "--"] + [f"{k}={v}" for k, v in params.items()]


def _start(alg, params, env):
    return subprocess.Popen(_args(alg, params), env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def _together(runs, env):
    """Start every (alg, params) at once; [(returncode, stdout, stderr)] in the same order."""
    procs = [_start(alg, params, env) for alg, params in runs]
    out = []
    for p in procs:
        stdout, stderr = p.communicate()
        out.append((p.returncode, stdout, stderr))
    return out


def _features(path) -> int:
    from osgeo import ogr
    ds = ogr.Open(str(path))
    assert ds is not None, f"{path} is not a GeoPackage GDAL opens"
    return ds.GetLayer(0).GetFeatureCount()


def _log(stdout) -> list:
    out = json.loads(stdout)
    return [line for lines in out.get("log", {}).values() for line in lines]


def _written(log) -> int:
    return [int(m.group(1)) for line in log for m in [re.match(r"(\d+) polygons from", line)] if m][-1]


def _leftovers(folder):
    return sorted(str(p.relative_to(folder)) for p in Path(folder).rglob("*") if TEMPORARY.search(p.name))


def _forward(survey, out, merge="none", **more):
    return {"INPUT_FOLDER": Path(survey.labelme[0]).parent, "PROJECT": survey.metashape_project,
            "DSM": survey.dsm, "MERGE": ("none", "union", "best", "fuse").index(merge),
            "OUTPUT": out, **more}


def test_fuse_and_union_into_one_geopackage_exactly_one_succeeds(qp_env, survey, tmp_path):
    """Two Forward-project runs (fuse and union) and a third (none) into one fp.gpkg, OVERWRITE
    off, started together, twice: one exits 0, the others exit 1 naming the output. Before the
    lock, two or three exited 0 and the file held one result."""
    for attempt in range(2):
        out = tmp_path / f"try{attempt}" / "fp.gpkg"
        out.parent.mkdir()
        runs = [("easyidp:forwardprojectpolygons", _forward(survey, out, m))
                for m in ("fuse", "union", "none")]
        results = _together(runs, qp_env)
        ok = [r for r in results if r[0] == 0]
        refused = [r for r in results if r[0] != 0]
        assert len(ok) == 1, [r[2][-300:] for r in results]
        for _, _, err in refused:
            assert str(out) in err and ("another run" in err or "already exists" in err), err
        assert _features(out) == _written(_log(ok[0][1]))
        assert _leftovers(out.parent) == []


def test_three_plot_grids_into_one_geopackage_exactly_one_succeeds(qp_env, tmp_path):
    out = tmp_path / "grid.gpkg"
    runs = [("easyidp:createplotgrid", {
        "ANCHOR": 2, "ORIGIN": "500000,4000000 [EPSG:32654]", "BEARING": b, "ROWS": 3 + k,
        "COLS": 4, "SIZE_X": 2, "SIZE_Y": 1, "GAP_X": 1, "GAP_Y": 0.5, "OUTPUT": out})
        for k, b in enumerate((0, 30, 60))]
    results = _together(runs, qp_env)
    ok = [k for k, r in enumerate(results) if r[0] == 0]
    assert len(ok) == 1, [r[2][-300:] for r in results]
    assert _features(out) == (3 + ok[0]) * 4            # the winner's grid, whole
    for k, (rc, _, err) in enumerate(results):
        if k != ok[0]:
            assert str(out) in err and ("another run" in err or "already exists" in err), err


def test_three_crops_into_one_folder_exactly_one_succeeds(qp_env, survey, tmp_path):
    out = tmp_path / "crops"
    runs = [("easyidp:croprasterbyrois", {"INPUT": survey.orthomosaic, "ROIS": survey.plots_gpkg,
                                    "NAME_FIELD": "plot_id", "OUTPUT_FOLDER": out,
                                          "OUTPUT_INDEX": ""})] * 3
    results = _together(runs, qp_env)
    assert sum(r[0] == 0 for r in results) == 1, [r[2][-300:] for r in results]
    for rc, _, err in results:
        if rc != 0:
            assert str(out) in err and ("Another EasyIDP run" in err or "already exist" in err), err
    assert sorted(os.listdir(out)) == sorted(f"{p}.tif" for p in survey.plot_ids)


def _kill_when(proc, path: Path, delay: float, limit: float = 120) -> None:
    """SIGKILL ``proc`` ``delay`` s after ``path`` appears (or when ``limit`` s have passed)."""
    t0 = time.time()
    while proc.poll() is None and not path.exists() and time.time() - t0 < limit:
        time.sleep(0.0005)
    time.sleep(delay)
    proc.kill()
    proc.communicate()


def test_forward_project_killed_at_random_moments(qp_env, survey, tmp_path):
    """Killed 0–40 ms after its GeoPackage appears (QGIS's writer: 0 bytes, then 64 KiB GDAL
    cannot open, then the whole file in one transaction), six times. What is left is either
    the whole file, or a leftover the next run (OVERWRITE off) replaces with a warning; nothing
    temporary stays."""
    rng = random.Random(40)
    out = tmp_path / "fp.gpkg"
    clean = run(_args("easyidp:forwardprojectpolygons", _forward(survey, tmp_path / "clean.gpkg"))[1:],
                qp_env)
    assert clean.returncode == 0, clean.stderr
    whole = _features(tmp_path / "clean.gpkg")
    replaced = 0
    for k in range(6):
        for p in tmp_path.glob("*fp.gpkg*"):
            p.unlink()
        proc = _start("easyidp:forwardprojectpolygons", _forward(survey, out), qp_env)
        _kill_when(proc, out, rng.uniform(0, 0.04))
        left = sorted(p.name for p in tmp_path.glob("*fp.gpkg*"))
        rerun = run(_args("easyidp:forwardprojectpolygons", _forward(survey, out))[1:], qp_env)
        if rerun.returncode == 0:           # the kill left a leftover, or nothing
            log = _log(rerun.stdout)
            replaced += any("not a valid GeoPackage" in line for line in log)
        else:                               # the kill came after the file was complete
            assert "already exists" in rerun.stderr, rerun.stderr
            assert [n for n in left if not TEMPORARY.search(n)] == ["fp.gpkg"], left
        assert _features(out) == whole, left
        assert _leftovers(tmp_path) == [], left
    print(f"\n{replaced} of 6 kills left a GeoPackage GDAL could not open; the re-run replaced it")


def _back(survey, folder, **more):
    return {"ROIS": survey.plots_gpkg, "NAME_FIELD": "plot_id",
            "PROJECT": survey.metashape_project, "HEIGHT_SOURCE": 1, "DSM": survey.dsm,
            "OUTPUT": folder / "bp.gpkg", "OUTPUT_SUMMARY": folder / "best.gpkg",
            "OUTPUT_JSON": folder / "bp.json",
            "CROPS_FOLDER": folder / "crops", **more}


def test_back_project_with_crops_killed_at_random_moments(qp_env, survey, tmp_path):
    """Killed at a random moment of writing its crops (after the first ROI folder appears),
    four times; the OVERWRITE re-run leaves the same crops as a clean run and nothing
    temporary (its ``crops/<roi>/.<photo>.<pid>-<tid>.part.json`` included)."""
    rng = random.Random(41)
    clean = tmp_path / "clean"
    res = run(_args("easyidp:backprojectrois", _back(survey, clean))[1:], qp_env)
    assert res.returncode == 0, res.stderr
    want = sorted(str(p.relative_to(clean)) for p in clean.rglob("*"))
    out = tmp_path / "killed"
    killed = 0
    for k in range(4):
        proc = _start("easyidp:backprojectrois", _back(survey, out, OVERWRITE="true"), qp_env)
        _kill_when(proc, out / "crops" / survey.plot_ids[0], rng.uniform(0, 1.5))
        killed += proc.returncode == -9
        res = run(_args("easyidp:backprojectrois", _back(survey, out, OVERWRITE="true"))[1:], qp_env)
        assert res.returncode == 0, res.stderr
        assert _leftovers(out) == []
        assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == want
        assert _features(out / "bp.gpkg") == _features(clean / "bp.gpkg")
    assert killed >= 2, "the runs ended before they could be killed: kill them earlier"
