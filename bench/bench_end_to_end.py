"""Benchmark: every tool end to end, as users wait for it (issue 23).

    python -m easyidp_toolbox.bench.bench_end_to_end [--quick] [--repeat N] [--only NAME ...] [--no-ref]

Each tool runs through the real ``qgis_process.bin run`` (the plugin enabled in an isolated
profile, as scripts/qgis_process.py sets it up) with GeoPackage outputs side by side in one
folder, as a user writes them; the engine runs the same call in the core (``easyidp_toolbox.core``)
in its own Python child, timed from the core opening its inputs (project, DSM, point cloud) to
the end of its work, its modules imported and the ROIs read before the clock starts (in the
tool QGIS reads them; the column 'engine script' is the child's whole run). Both
are medians of ``--repeat`` runs (fresh output folders each time).

``qgis_process`` start-up is measured in the same run: ``qgis_process.bin run native:buffer`` on
a one-point layer with a GeoPackage output (QGIS, its providers and this plugin loaded, next to
nothing to do). The goal per tool: tool <= 1.1 x engine + start-up. The log of every tool run is
searched for 'database is locked' and any other ERROR line (a tool that opens an output it is
still writing shows them; see tests/qgis/test_geopackage_outputs.py).

Workloads: back-projection on the real wheat_tanashi project (138 photos) with 1,600 plots
(bench_backward's grid, written as a 3-D GeoPackage), once with geometry Z, whole ROIs only and
no occlusion (the issue's user case, against easyidp 2.0.4 ``back2raw`` in the same run) and
once with DSM heights, clipping and occlusion (with the engine's share per step); camera
footprints of the same project; DSM heights, raster and point cloud crops and point cloud
statistics of 1,600 small plots over the demo survey (medium: 1 cm orthomosaic, 2 cm DSM);
plot grids: 10,000 plots created, and bench_plot_grid's 20000² orthomosaic fitted with its
start grid (1,600 plots); a training set of 1,000 labelled discs on the demo survey's photos.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import sys
from pathlib import Path

import numpy as np

from .bench_backward import OUT as BACKWARD_OUT
from .bench_backward import (_LOAD_ROIS, REF_PROJECT, REF_PYTHON, WHEAT, _grid_plots, demo_inputs,
                             wheat_inputs)
from .common import Run, print_targets, ratio, reference_env, run_child, run_json_child, table, target

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = ROOT / "bench_output" / "end_to_end"
TIMEOUT = 3600
EPSG = 32654

# --- the engine: the same calls in the core, in a child ------------------------------------------
# argv: CASE ARGS_JSON; prints {"seconds": ..., "steps": {...}, ...} on its last line.
_IMPORTS = r"""
from easyidp_toolbox.core import open_reconstruction
from easyidp_toolbox.core.pointcloud import canopy_summary, crop_point_cloud, read_point_cloud
from easyidp_toolbox.core.projection import back_project
from easyidp_toolbox.core.raster.crop import crop_raster_by_rois
from easyidp_toolbox.core.raster import DSM, dsm_roi_heights
from easyidp_toolbox.core.annotations import read_annotations
from easyidp_toolbox.core.projection import camera_footprints, forward_project, merge_views, photo_statistics
from easyidp_toolbox.core.projection.ortho import orthorectify_rois
from easyidp_toolbox.core.season import read_survey_table, run_season
from easyidp_toolbox.core.plotgrid import (GridAnchor, GridLayout, Numbering, create_plot_grid,
                                           fit_plot_grid)
from easyidp_toolbox.core.raster import open_geotiff
from easyidp_toolbox.core.projection import export_training_set
"""
IMPORT_TIME = "import json, time\nt0 = time.perf_counter()\n" + _IMPORTS + \
    "print(json.dumps({'seconds': time.perf_counter() - t0}))\n"
"""Times the import of the core modules the tools call (the tools import them inside the run:
it is part of every tool's time and of no start-up)."""

ENGINE = _LOAD_ROIS + r"""
import json, sys, time
case, a = sys.argv[1], json.loads(sys.argv[2])
if "rois_json" in a:
    rois = load_rois(a["rois_json"])
elif "rois" in a:
    from easyidp_toolbox.core.roi import open_rois
    rois = open_rois(a["rois"], name_field=a.get("name_field"))
# the core modules every case uses, imported before the clock starts (the call is timed)
""" + _IMPORTS + r"""marks = []
def progress(p):
    marks.append((float(p), time.perf_counter()))
out = {}
t0 = time.perf_counter()
if case.startswith("backproject"):
    recon = open_reconstruction(a["project"])
    t_open = time.perf_counter()
    if a.get("dsm"):
        dsm = DSM(a["dsm"], crs=a["crs"])
        res = back_project(rois, recon, heights=dsm, clip=True, occlusion_dsm=dsm,
                           min_visible=a["min_visible"], progress=progress)
    else:
        res = back_project(rois, recon, heights="geometry", clip=False,
                           min_visible=a["min_visible"], progress=progress)
    t1 = time.perf_counter()
    def at(p):
        return next((t for q, t in marks if q >= p), t1)
    # back_project's progress: 2 vertex heights, 15 densified, 75 projected and clipped,
    # 95 occlusion tested, 100 ranked
    b = [t0, t_open, at(2), at(15), at(75), at(95), t1]
    names = ["open project", "vertex heights", "densify", "project + clip", "occlusion",
             "rank + finish"]
    out["steps"] = {n: b[k + 1] - b[k] for k, n in enumerate(names)}
    out["kept"] = len(res)
elif case == "camerafootprints":
    recon = open_reconstruction(a["project"])
    cams = [c for c in recon.cameras if c.aligned]
    prints = camera_footprints(recon, a["ground"], output_crs=a["crs"], cameras=cams)
    out["kept"] = len(prints)
elif case == "roiheightsfromdsm":
    dsm = DSM(a["dsm"], crs=a["crs"])
    rois.validate()
    res = dsm_roi_heights(dsm, rois, "polygon", "mean", 50.0, 0.0)
elif case == "croprasterbyrois":
    res = crop_raster_by_rois(a["raster"], rois, a["folder"], all_touched=False,
                              source_crs=a["crs"])
    out["kept"] = len(res.files)
elif case == "croppointcloudbyrois":
    cloud = read_point_cloud(a["cloud"], None)
    res = crop_point_cloud(cloud, rois, a["folder"], fmt="same", z_min=None, z_max=None,
                           write_empty=False)
    out["kept"] = sum(item.status == "written" for item in res.items)
elif case == "pointcloudroistatistics":
    cloud = read_point_cloud(a["cloud"], None)
    res = canopy_summary(cloud, rois, ground=None, percentiles=a["percentiles"],
                         ground_percentile=a["ground_percentile"], z_min=None, z_max=None)
    out["kept"] = len(res)
elif case == "photostatistics":
    recon = open_reconstruction(a["project"])
    dsm = DSM(a["dsm"], crs=a["crs"])
    res = back_project(rois, recon, heights=dsm, distortion=True, occlusion_dsm=dsm,
                       min_visible=0.0)
    st = photo_statistics(res, None, bands=None, statistics=["mean", "median", "std"],
                          percentiles=[5.0, 95.0],
                          indices=["exg", "exgr", "vari", "gli", "ndvi", "ndre"],
                          cover_threshold=None, min_visible=0.5, max_views=3, weighted=False,
                          recon=recon, rois=rois, occlusion_dsm=dsm, distortion=True,
                          previews_folder=None, overwrite=False)
    out["kept"] = len(st.record)
elif case == "orthorectifyrois":
    recon = open_reconstruction(a["project"])
    res = orthorectify_rois(rois, recon, a["dsm"], a["folder"], selection="best", photo=None,
                            photos_folder=None, gsd=None, source_crs=a["crs"])
elif case == "forwardprojectpolygons":
    recon = open_reconstruction(a["project"])
    dsm = DSM(a["dsm"], crs=a["crs"])
    shapes = []
    for ann, cam in read_annotations(a["folder_in"], recon):
        polys = [s for s in ann.shapes if s.kind == "polygon"]
        shapes += forward_project(polys, cam, recon, dsm, densify=4.0)
    out["kept"] = len(merge_views(shapes, "none"))
elif case == "seasontraits":
    table = read_survey_table(a["surveys"])
    res = run_season(table, rois, traits=["height", "cover", "bands", "index", "cloud"],
                     percentiles=[50.0, 95.0, 99.0], ground=a["ground"], ground_source_crs=a["crs"],
                     ground_percentile=2.0, cover_threshold=None, crops=None, workers=1)
    out["kept"] = len(res.rows)
elif case == "createplotgrid":
    grid, _ = create_plot_grid(
        a["crs"], a["rows"], a["cols"],
        anchor=GridAnchor(origin=tuple(a["origin"]), bearing=a["bearing"]),
        layout=GridLayout(size_x=3.0, size_y=1.5, gap_x=0.5, gap_y=1.0, blocks_x=2,
                          block_gap_x=1.0),
        numbering=Numbering(order="serpentine", pattern=a["pattern"]))
    out["kept"] = len(grid)
elif case == "fitplotgrid":
    tif = open_geotiff(a["raster"], crs=a["crs"])
    res = fit_plot_grid([r.parts[0][0] for r in rois], tif, index="exg", bands=(1, 2, 3),
                        max_shift=0.25, search=None, min_cover=0.3, min_score=0.6)
    out["kept"] = int(sum(res.moved))
elif case == "exporttrainingset":
    recon = open_reconstruction(a["project"])
    classes = [str(r.attributes["class"]) for r in rois]
    res = export_training_set(rois, classes, recon, a["dsm"], a["folder"], source_crs=a["crs"])
    out["kept"] = int(sum(res.annotations.values()))
else:
    raise SystemExit(f"unknown case {case}")
out["seconds"] = time.perf_counter() - t0
print(json.dumps(out))
"""


# --- inputs ---------------------------------------------------------------------------------------
def _write_gpkg(path: Path, rois: dict, crs: str, z: bool, classes=None) -> Path:
    """{name: closed ring [[x, y(, z)], ...]} → a GeoPackage polygon layer (field 'name', and
    'class' from ``classes``, one per ROI), atomically (written beside, then renamed)."""
    from osgeo import ogr, osr
    tmp = path.with_suffix(".tmp.gpkg")
    if tmp.exists():
        tmp.unlink()
    srs = osr.SpatialReference()
    srs.SetFromUserInput(crs)
    ds = ogr.GetDriverByName("GPKG").CreateDataSource(str(tmp))
    layer = ds.CreateLayer(path.stem, srs, ogr.wkbPolygon25D if z else ogr.wkbPolygon)
    layer.CreateField(ogr.FieldDefn("name", ogr.OFTString))
    if classes is not None:
        layer.CreateField(ogr.FieldDefn("class", ogr.OFTString))
    layer.StartTransaction()
    for k, (name, ring) in enumerate(rois.items()):
        r = ogr.Geometry(ogr.wkbLinearRing)
        for p in ring:
            if z:
                r.AddPoint(float(p[0]), float(p[1]), float(p[2]))
            else:
                r.AddPoint_2D(float(p[0]), float(p[1]))
        g = ogr.Geometry(ogr.wkbPolygon)
        g.AddGeometry(r)
        f = ogr.Feature(layer.GetLayerDefn())
        f.SetField("name", name)
        if classes is not None:
            f.SetField("class", classes[k])
        f.SetGeometry(g)
        layer.CreateFeature(f)
    layer.CommitTransaction()
    ds = None
    os.replace(tmp, path)
    return path


def wheat_case_inputs(quick: bool) -> dict:
    w = wheat_inputs(quick)                     # bench_backward's plots and DSM (cached)
    gpkg = OUT / (Path(w["rois"]).stem + ".gpkg")
    if not gpkg.exists():
        d = json.loads(Path(w["rois"]).read_text())
        _write_gpkg(gpkg, d["rois"], d["crs"], z=True)
    return {"rois_json": w["rois"], "rois": gpkg, "dsm": w["dsm"]}


def demo_case_inputs(quick: bool) -> dict:
    """The demo survey (bench_backward's copy) and a grid of small plots over its field."""
    size = "small" if quick else "medium"
    demo_inputs(size)
    folder = BACKWARD_OUT / f"demo_{size}"
    n = 20 if quick else 40
    gpkg = OUT / f"demo_{size}_grid_{n}.gpkg"
    if not gpkg.exists():
        with open(folder / "plots.geojson") as fh:
            feats = json.load(fh)["features"]
        xy = np.array([p for f in feats for r in f["geometry"]["coordinates"] for p in r])
        (x0, y0), (x1, y1) = xy.min(axis=0), xy.max(axis=0)
        cell = ((x1 - x0) / n, (y1 - y0) / n)
        rois = _grid_plots(x0, y0, x1, y1, n, n, (0.75 * cell[0], 0.75 * cell[1]),
                           lambda x, y: np.zeros(len(x)), 5)
        _write_gpkg(gpkg, {k: [p[:2] for p in v] for k, v in rois.items()}, f"EPSG:{EPSG}", z=False)
    return {"folder": folder, "rois": gpkg, "n": n * n}


PLOTS, PHOTOS = 40, 36        # the demo survey's


def season_inputs(quick: bool) -> dict:
    """The demo season (its 40 plots), generated once."""
    from easyidp_toolbox.core.demo import make_demo_season
    dates = 2 if quick else 4
    folder = OUT / f"season_{dates}"
    if not (folder / "season_truth.json").exists():
        make_demo_season(str(folder), dates=dates, seed=0)
    return {"surveys": folder / "surveys.csv", "plots": folder / "plots.geojson",
            "ground": folder / "bare_soil_dsm.tif", "dates": dates}


def plot_grid_inputs(quick: bool) -> dict:
    """bench_plot_grid's orthomosaic (6000² quick, else 20000²; generated once) and the start
    grid its fit starts from (the layout turned by 1°, shifted by 0.25 m, spacing 1 % off) as a
    GeoPackage."""
    import math
    from easyidp_toolbox.core.plotgrid import create_plot_grid, grid_options, write_plot_grid
    from .bench_plot_grid import BEARING, ensure_raster, grid_kwargs, layout, truth
    from .bench_plot_grid import EPSG as GRID_EPSG
    size = 6000 if quick else 20000
    raster = ensure_raster(size)
    gpkg = OUT / f"plotgrid_start_{size}.gpkg"
    if not gpkg.exists():
        grid, _, _ = truth(size)
        start, _ = create_plot_grid(f"EPSG:{GRID_EPSG}", **grid_options(
            origin=grid.frame.origin, bearing=BEARING, **grid_kwargs(int(grid.row.max()), 1.01)))
        c = start.corners.reshape(-1, 2).mean(axis=0)
        t = math.radians(1.0)
        rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
        start.corners = np.array([(q - c) @ rot.T + c + (0.25, 0.0) for q in start.corners])
        write_plot_grid(str(gpkg), start)
    return {"raster": raster, "grid": gpkg, "size": size, "crs": f"EPSG:{GRID_EPSG}",
            "n": layout(size)[0] ** 2}


def training_objects(quick: bool, demo: Path) -> dict:
    """Labelled discs (radius 0.1–0.3 m, 32 vertices, classes a and b) at random over the demo
    survey's field, as bench_training_set makes them, in a GeoPackage (fields name, class)."""
    from easyidp_toolbox.core.demo.scene import SURVEY_FIELD
    n = 200 if quick else 1000
    gpkg = OUT / f"training_objects_{demo.name}_{n}.gpkg"
    if not gpkg.exists():
        rng = np.random.default_rng(0)
        t = np.linspace(0, 2 * np.pi, 32, endpoint=False)
        x0, y1 = SURVEY_FIELD.origin
        c = np.column_stack([rng.uniform(x0 + 2, x0 + SURVEY_FIELD.size[0] - 2, n),
                             rng.uniform(y1 - SURVEY_FIELD.size[1] + 2, y1 - 2, n)])
        r = rng.uniform(0.1, 0.3, n)
        rings = c[:, None, :] + r[:, None, None] * np.stack([np.cos(t), np.sin(t)], -1)[None]
        _write_gpkg(gpkg, {f"o{k}": np.vstack([q, q[:1]]) for k, q in enumerate(rings)},
                    f"EPSG:{EPSG}", z=False, classes=["a" if k % 2 else "b" for k in range(n)])
    return {"rois": gpkg, "n": n}


def startup_input() -> Path:
    path = OUT / "one_point.geojson"
    if not path.exists():
        path.write_text(json.dumps({"type": "FeatureCollection", "features": [{
            "type": "Feature", "properties": {"id": 1},
            "geometry": {"type": "Point", "coordinates": [139.54, 35.74]}}]}))
    return path


# --- the cases ------------------------------------------------------------------------------------
def cases(quick: bool, only=None):
    """(name, tool, workload, tool parameters with outputs relative to the run folder, engine
    arguments with the folder as '{out}'). The plot-grid and training-set inputs are made only
    for the cases in ``only`` (default all): the fit's orthomosaic takes minutes to generate."""
    def want(name):
        return not only or name in only

    w = wheat_case_inputs(quick)
    d = demo_case_inputs(quick)
    n_w = 400 if quick else 1600
    demo = d["folder"]
    out = []
    out.append(("backproject", "backprojectrois",
                f"{n_w} plots × 138 photos (wheat), geometry Z, whole ROIs, no occlusion",
                {"ROIS": w["rois"], "NAME_FIELD": "name", "PROJECT": WHEAT, "HEIGHT_SOURCE": 0,
                 "CLIP": 1, "MIN_VISIBLE": 0, "OCCLUSION": "false",
                 "OUTPUT": "pixels.gpkg", "OUTPUT_SUMMARY": "summary.gpkg"},
                {"rois_json": w["rois_json"], "project": WHEAT, "min_visible": 0.0}))
    out.append(("backproject_dsm", "backprojectrois",
                f"{n_w} plots × 138 photos (wheat), DSM heights, clipped, occlusion",
                {"ROIS": w["rois"], "NAME_FIELD": "name", "PROJECT": WHEAT, "HEIGHT_SOURCE": 1,
                 "DSM": w["dsm"], "CLIP": 0, "OCCLUSION": "true", "MIN_VISIBLE": 0.5,
                 "OUTPUT": "pixels.gpkg", "OUTPUT_SUMMARY": "summary.gpkg"},
                {"rois_json": w["rois_json"], "project": WHEAT, "dsm": w["dsm"],
                 "crs": f"EPSG:{EPSG}", "min_visible": 0.5}))
    out.append(("camerafootprints", "camerafootprints", "138 cameras (wheat), one ground height",
                {"PROJECT": WHEAT, "GROUND_HEIGHT": 96.8, "OUTPUT_CRS": f"EPSG:{EPSG}",
                 "OUTPUT_CAMERAS": "cameras.gpkg", "OUTPUT_FOOTPRINTS": "footprints.gpkg"},
                {"project": WHEAT, "ground": 96.8, "crs": f"EPSG:{EPSG}"}))
    grid = {"rois": d["rois"], "name_field": "name"}
    out.append(("roiheightsfromdsm", "roiheightsfromdsm",
                f"{d['n']} plots, demo DSM (2 cm), mean",
                {"ROIS": d["rois"], "DSM": demo / "dsm.tif", "MODE": 0, "STATISTIC": 0,
                 "OUTPUT": "heights.gpkg"},
                dict(grid, dsm=demo / "dsm.tif", crs=f"EPSG:{EPSG}")))
    out.append(("croprasterbyrois", "croprasterbyrois",
                f"{d['n']} plots, demo orthomosaic (1 cm RGB)",
                {"INPUT": demo / "orthomosaic.tif", "ROIS": d["rois"], "NAME_FIELD": "name",
                 "OUTPUT_FOLDER": "crops", "OUTPUT_INDEX": "crops_index.gpkg"},
                dict(grid, raster=demo / "orthomosaic.tif", crs=f"EPSG:{EPSG}",
                     folder="{out}/crops")))
    out.append(("croppointcloudbyrois", "croppointcloudbyrois",
                f"{d['n']} plots, demo point cloud (LAZ)",
                {"INPUT": demo / "pointcloud.laz", "ROIS": d["rois"], "NAME_FIELD": "name",
                 "FORMAT": 0, "OUTPUT_FOLDER": "clouds", "OUTPUT_INDEX": "clouds_index.gpkg"},
                dict(grid, cloud=demo / "pointcloud.laz", folder="{out}/clouds")))
    out.append(("pointcloudroistatistics", "pointcloudroistatistics",
                f"{d['n']} plots, demo point cloud (LAZ)",
                {"INPUT": demo / "pointcloud.laz", "ROIS": d["rois"], "PERCENTILES": "50,95,99",
                 "GROUND_PERCENTILE": 1, "OUTPUT": "cloud_stats.gpkg"},
                dict(grid, cloud=demo / "pointcloud.laz", percentiles=[50.0, 95.0, 99.0],
                     ground_percentile=1.0)))
    project = demo / "metashape" / "demo_survey.psx"
    plots = {"rois": demo / "plots.gpkg", "name_field": "plot_id"}
    out.append(("photostatistics", "photostatistics",
                f"{PLOTS} plots × {PHOTOS} photos (demo), DSM heights, occlusion, 3 best views",
                {"ROIS": demo / "plots.gpkg", "NAME_FIELD": "plot_id", "PROJECT": project,
                 "HEIGHT_SOURCE": 1, "DSM": demo / "dsm.tif", "OUTPUT_VIEWS": "views.gpkg",
                 "OUTPUT": "statistics.gpkg"},
                dict(plots, project=project, dsm=demo / "dsm.tif", crs=f"EPSG:{EPSG}")))
    out.append(("orthorectifyrois", "orthorectifyrois",
                f"{PLOTS} plots from their best photo (demo), native resolution",
                {"ROIS": demo / "plots.gpkg", "NAME_FIELD": "plot_id", "PROJECT": project,
                 "DSM": demo / "dsm.tif", "OUTPUT_FOLDER": "ortho",
                 "OUTPUT_INDEX": "ortho_index.gpkg"},
                dict(plots, project=project, dsm=demo / "dsm.tif", crs=f"EPSG:{EPSG}",
                     folder="{out}/ortho")))
    out.append(("forwardprojectpolygons", "forwardprojectpolygons",
                "the demo's LabelMe polygons on 4 photos, densified every 4 px",
                {"INPUT_FOLDER": demo / "labelme", "PROJECT": project, "DSM": demo / "dsm.tif",
                 "OUTPUT": "on_map.gpkg"},
                {"project": project, "dsm": demo / "dsm.tif", "crs": f"EPSG:{EPSG}",
                 "folder_in": demo / "labelme"}))
    n_grid = 100
    out.append(("createplotgrid", "createplotgrid",
                f"{n_grid * n_grid:,} plots ({n_grid} × {n_grid}, two blocks, serpentine, a name "
                "pattern)",
                {"ANCHOR": 2, "ORIGIN": f"500000,4000000 [EPSG:{EPSG}]", "BEARING": 80,
                 "ROWS": n_grid, "COLS": n_grid, "SIZE_X": 3, "SIZE_Y": 1.5, "GAP_X": 0.5,
                 "GAP_Y": 1.0, "BLOCKS_X": 2, "BLOCK_GAP_X": 1.0, "ORDER": 1,
                 "PATTERN": "{block}-{row:03d}-{col:03d}", "OUTPUT": "grid.gpkg"},
                {"crs": f"EPSG:{EPSG}", "rows": n_grid, "cols": n_grid,
                 "origin": [500000.0, 4000000.0], "bearing": 80.0,
                 "pattern": "{block}-{row:03d}-{col:03d}"}))
    pg = plot_grid_inputs(quick) if want("fitplotgrid") else None
    if pg is not None:
        out.append(("fitplotgrid", "fitplotgrid",
                    f"{pg['n']:,} plots on a {pg['size']}² RGB orthomosaic (1 cm), from a grid "
                    "turned by 1°, shifted 0.25 m, spacing 1 % off",
                    {"GRID": pg["grid"], "NAME_FIELD": "plot_id", "ORTHOMOSAIC": pg["raster"],
                     "OUTPUT": "fitted.gpkg"},
                    {"rois": pg["grid"], "name_field": "plot_id", "raster": pg["raster"],
                     "crs": pg["crs"]}))
    if want("exporttrainingset"):
        objects = training_objects(quick, demo)
        out.append(("exporttrainingset", "exporttrainingset",
                    f"{objects['n']:,} labelled discs × {PHOTOS} photos (demo), whole photos, "
                    "COCO + YOLO + LabelMe",
                    {"OBJECTS": objects["rois"], "CLASS_FIELD": "class", "INSTANCE_FIELD": "name",
                     "PROJECT": project, "DSM": demo / "dsm.tif", "OUTPUT_FOLDER": "training_set"},
                    {"rois": objects["rois"], "name_field": "name", "project": project,
                     "dsm": demo / "dsm.tif", "crs": f"EPSG:{EPSG}",
                     "folder": "{out}/training_set"}))
    season = season_inputs(quick)
    out.append(("seasontraits", "seasontraits",
                f"{season['dates']} dates × {PLOTS} plots (demo season), all traits, 1 worker",
                {"SURVEYS": season["surveys"], "ROIS": season["plots"], "NAME_FIELD": "plot_id",
                 "GROUND": season["ground"], "WORKERS": 1, "OUTPUT_TABLE": "traits.gpkg",
                 "OUTPUT_LAYER": "latest.gpkg"},
                {"rois": season["plots"], "name_field": "plot_id", "surveys": season["surveys"],
                 "ground": season["ground"], "crs": f"EPSG:{EPSG}"}))
    return out


# --- running --------------------------------------------------------------------------------------
LOCK = "database is locked"


def _errors(run: Run):
    """(lock messages, other ERROR lines) in a qgis_process log."""
    lines = (run.stderr + "\n" + run.stdout).splitlines()
    locks = sum(LOCK in line for line in lines)
    errors = [line for line in lines if re.search(r"\bERROR\b", line) and LOCK not in line]
    return locks, errors


def _fresh(folder: Path) -> Path:
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    return folder


def run_tool(exe, env, alg, params, folder: Path) -> Run:
    args = []
    for k, v in params.items():
        if k.startswith("OUTPUT") and isinstance(v, str) and not os.path.isabs(v):
            v = folder / v
        args.append(f"{k}={v}")
    return run_child([exe, "run", alg, "--", *args], env=env, timeout=TIMEOUT)


def run_engine(case, eargs, folder: Path):
    eargs = {k: (str(v).replace("{out}", str(folder)) if isinstance(v, (str, Path)) else v)
             for k, v in eargs.items()}
    return run_json_child([sys.executable, "-c", ENGINE, case, json.dumps(eargs)],
                          timeout=TIMEOUT, label=f"engine {case}", strict=True)


def _median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def startup_run(exe, env) -> float:
    """Wall of ``qgis_process.bin run native:buffer`` on one point (GeoPackage output)."""
    folder = _fresh(OUT / "startup")
    r = run_child([exe, "run", "native:buffer", "--", f"INPUT={startup_input()}",
                   "DISTANCE=0.001", f"OUTPUT={folder / 'buffer.gpkg'}"], env=env, timeout=600)
    if not r.ok:
        raise RuntimeError(f"qgis_process native:buffer failed:\n{r.stderr[-2000:]}")
    return r.wall


def measure_startup(exe, env, repeat: int):
    """Median walls of :func:`startup_run` and of ``qgis_process.bin --version``."""
    walls = [startup_run(exe, env) for _ in range(repeat)]
    version = [run_child([exe, "--version"], env=env, timeout=600).wall for _ in range(repeat)]
    return _median(walls), _median(version)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smaller inputs (400 wheat plots, the "
                                                         "small demo survey, 400 grid plots)")
    ap.add_argument("--repeat", type=int, default=None, help="runs per figure (default 3; 1 quick)")
    ap.add_argument("--only", nargs="*", default=None, help="case names (see the table)")
    ap.add_argument("--no-ref", action="store_true", help="skip easyidp 2.0.4")
    a = ap.parse_args(argv)
    repeat = a.repeat or (1 if a.quick else 3)
    for folder in (OUT, BACKWARD_OUT):
        folder.mkdir(parents=True, exist_ok=True)
    from ..scripts.qgis_process import EXE, qgis_process_env
    env = qgis_process_env(str(_fresh(OUT / "profile")))

    startup_all, version = measure_startup(EXE, env, repeat)
    print(f"\nqgis_process start-up (median of {repeat}): run native:buffer on one point "
          f"{startup_all:.2f} s; --version {version:.2f} s. Each tool run below is paired with "
          "a start-up run just before it (the machine is shared: its load drifts)", flush=True)
    imports = _median([run_json_child([sys.executable, "-c", IMPORT_TIME], timeout=600,
                                      label="imports", strict=True)[1]["seconds"]
                       for _ in range(repeat)])
    print(f"Importing the core modules the tools call (inside each tool's run, so in neither "
          f"the start-up nor the engine figures): {imports:.2f} s", flush=True)

    ref = REF_PYTHON.exists() and not a.no_ref
    ref_env = reference_env(dict(os.environ))
    ref_env.update(HOME=str(OUT), XDG_DATA_HOME=str(OUT))
    ref_runs = []
    rows, goals, shares, figures = [], [], {}, {}
    for name, alg, workload, params, eargs in cases(a.quick, a.only):
        if a.only and name not in a.only:
            continue
        tool_walls, cpu, locks, errors, eng, scripts, starts = [], [], 0, [], [], [], []
        load = os.getloadavg()[0]          # the machine is shared: how busy it was
        for k in range(repeat):
            starts.append(startup_run(EXE, env))
            folder = _fresh(OUT / "runs" / name)
            r = run_tool(EXE, env, f"easyidp:{alg}", params, folder)
            if not r.ok:
                raise RuntimeError(f"qgis_process {alg} failed ({r.returncode}):\n{r.stderr[-3000:]}")
            n_locks, errs = _errors(r)
            locks += n_locks
            errors += errs
            tool_walls.append(r.wall)
            cpu.append(r.cpu)
            folder = _fresh(OUT / "runs" / name)
            run, info = run_engine(alg if not alg.startswith("backproject") else name, eargs, folder)
            eng.append(info)
            scripts.append(run.wall)
            if name == "backproject" and ref:   # easyidp in the same rounds (the load drifts)
                ref_runs.append(run_json_child(
                    [str(REF_PYTHON), "-c", REF_PROJECT, str(WHEAT), str(eargs["rois_json"])],
                    env=ref_env, timeout=TIMEOUT, label="easyidp", strict=True))
        tool = _median(tool_walls)
        startup = _median(starts)
        engine = _median([e["seconds"] for e in eng])
        if eng[0].get("steps"):
            shares[name] = {s: _median([e["steps"][s] for e in eng]) for s in eng[0]["steps"]}
        figures[name] = {"tool": tool, "engine": engine, "startup": startup}
        over = tool - startup - engine
        goal = 1.1 * engine + startup
        rows.append([name, workload, startup, tool, _median(cpu), engine, _median(scripts),
                     ratio(tool, engine),
                     ratio(tool - startup, engine), over, goal,
                     "PASS" if tool <= goal else "MISS", locks, len(errors), load])
        for line in errors[:3]:
            print(f"    {name}: {line}")
        print(f"  {name}: tool {tool:.2f} s, engine {engine:.2f} s", flush=True)

    print(f"\nEnd to end, median of {repeat} (s), start-up paired with each run; goal: tool <= "
          "1.1 × engine + start-up")
    print("(engine: the core call timed in its child; engine script: that child's whole run, "
          "Python start, imports and ROI reading included)")
    print(table(["case", "workload", "start-up", "tool", "tool CPU", "engine", "engine script", "tool/engine",
                 "(tool-start)/engine", "tool-start-engine", "goal", "verdict", "locks",
                 "ERROR lines", "load avg"], rows))

    for name, steps in shares.items():
        total = figures[name]["tool"]
        qgis_side = total - figures[name]["startup"] - figures[name]["engine"]
        parts = [["qgis_process start-up", figures[name]["startup"]]] + \
                [[f"engine: {s}", v] for s, v in steps.items()] + \
                [["QGIS side: ROIs read, outputs written", qgis_side]]
        print(f"\nShare per step, {name} (tool {total:.2f} s)")
        print(table(["step", "seconds", "share %"], [[p, v, 100.0 * v / total] for p, v in parts]))

    if ref_runs:
        runs = ref_runs
        back2raw = _median([info["seconds"] for _, info in runs])
        script = _median([run.wall for run, _ in runs])
        tool = figures["backproject"]["tool"]
        print(f"\nBack-projection against easyidp 2.0.4 (median of {repeat}, each run next to "
              f"one of the tool's): back2raw "
              f"{back2raw:.2f} s (the call), {script:.2f} s (its whole script: import, open "
              f"the project, back2raw); the tool {tool:.2f} s end to end, start-up "
              f"{figures['backproject']['startup']:.2f} s, engine "
              f"{figures['backproject']['engine']:.2f} s")
        goals.append(target("back2raw call / tool end to end (issue's row)",
                            ratio(back2raw, tool), 2.0))
        goals.append(target("back2raw call / (tool − start-up)",
                            ratio(back2raw, tool - figures["backproject"]["startup"]), 2.0))
        goals.append(target("easyidp script / tool end to end (both from process start)",
                            ratio(script, tool), 2.0))
        goals.append(target("back2raw call / engine (the same work, in process)",
                            ratio(back2raw, figures["backproject"]["engine"]), 2.0))
    print_targets(goals)
    return 0


if __name__ == "__main__":
    sys.exit(main())
