"""The demo survey: a complete synthetic drone survey with known truth, written from a seed.

``make_demo_survey(folder, seed=0, size="small")`` writes, into ``folder``::

    orthomosaic.tif       RGB, 1 cm, tiled 256, deflate                (EPSG:32654)
    dsm.tif               float32, 2 cm, nodata -9999, ellipsoidal heights (WGS 84)
    plots.geojson         40 rotated plot rectangles, fields plot_id, row, col
    plots.gpkg            the same plots as a GeoPackage layer "plots"
    pointcloud.laz        the surface with colours (LAS 1.2, point format 2, CRS in the file)
    pointcloud.ply        the same points (binary PLY, x y z double, red green blue uchar)
    photos/DJI_0001.JPG…  36 raw photos of a lawnmower flight (800×600 or 1600×1200)
    metashape/demo_survey.psx + demo_survey.files/        the flight as a Metashape 1.x project
    pix4d/demo_survey.p4d + demo_survey/1_initial/params/ the flight as a Pix4D project
    odm/                  the flight as an OpenDroneMap project (``odm_writer.py``)
    opf/project.opf …     the flight as an Open Photogrammetry Format project (``opf_writer.py``)
    labelme/DJI_xxxx.json LabelMe polygons around plots on four photos
    truth.json            truth points and their pixels in every photo that sees them, the
                          photos that see each plot whole, the map coordinates of the LabelMe
                          vertices, the camera and every photo's pose (see ``truth.py`` for the
                          conventions; ``tests/support/independent_camera.py`` recomputes the
                          pixels from them without ``core`` code)

The field is as messy as real ones (``field_mess``, :class:`.field.FieldMess`, every feature with
its parameter, drawn from the seed): margin grass at least half as green as the crop, weeds in
the plots and the alleys, uneven vigour, missing row segments, empty plots, lodged patches, cast
shadows, a soil-colour gradient, rows that hide the soil between them in oblique views, and a
block of plots without alleys. ``field_mess=NO_MESS`` gives the tidy field of earlier versions.

Same seed and size → identical files (in one software environment). Pixels have their origin
at the top-left image corner; the centre of the top-left pixel is (0.5, 0.5).

``rolling_shutter=True`` makes the drone move during each exposure (:mod:`.readout_motion`):
photos are rendered row by row, the Metashape project carries the motion, the truth follows it,
and no Pix4D project is written.

The truth gives every plot its colour truth (:mod:`.plot_colour`: mean ExG and canopy cover,
from the generator's closed-form model). ``ortho_defects=True`` writes an orthomosaic with the
faults real ones show, ghosting and blur over the plots of two field columns (named in the
truth's ``ortho_defects``); the photos, and everything else, are those of the default survey.
"""
import os
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import asdict, dataclass, field
from typing import List, Optional

import numpy as np

from .field import (DOM_PIXEL, DSM_PIXEL, EDGE, TOUCHING_BLOCK, FieldMess, _inside_plot, plot_corners,
                    write_plots_geojson)
from ..errors import InputError
from ..files import OutputFolder, write_bytes
from ..gpkg import GpkgTable, write_geopackage
from ..raster import epsg_geo_tags, write_geotiff
from ..progress import as_progress
from .flight import ALTITUDE, SIZES, make_camera, plan_flight
from ..pointcloud import PointCloud, write_point_cloud
from . import readout_motion
from .labelme_writer import write_labelme
from .metashape_writer import write_metashape
from .odm_writer import write_odm
from .opf_writer import write_opf
from .photo_tags_writer import noise_note, photo_tag_segments, tag_jpeg
from .pix4d_writer import write_pix4d
from .plot_colour import BLUR_SIGMA, GHOST_OFFSET, add_ortho_defects, plot_colour_truth
from .render import level_for, packed_level, pixel_rays, render_photo
from .scene import make_scene, surface_cloud
from .truth import Truth, observations, plot_visibility, truth_points, write_truth

PROJECT_NAME = "demo_survey"
JPEG_QUALITY = 92
LAS_DATE = (153, 2024)          # file creation day of year and year written in LAS headers
__all__ = ["make_demo_survey", "DemoSurvey", "SIZES"]
DEFECTS_NOTE = (f"orthomosaic.tif only (the photos see the true texture): 'ghosting' plots are a "
                f"50/50 blend with the texture {GHOST_OFFSET[0]:g} m east, {-GHOST_OFFSET[1]:g} m "
                f"south; 'blur' plots a Gaussian blur of sigma {BLUR_SIGMA:g} m")


MESS_NOTE = ("what real fields have (core/demo/field.py FieldMess): margin grass, weeds in plots "
             "and alleys, uneven vigour, missing row segments, empty plots, lodged patches, cast "
             "shadows, a soil-colour gradient, rows that hide the soil between them obliquely, a "
             "block of plots without alleys; per plot under plots.<id>.field")


def field_features(scene) -> dict:
    """Per plot id: which of the field's features it has (for truth.json)."""
    out = {}
    weeds = scene.weeds if scene.weeds is not None else np.zeros((0, 4))
    for p in scene.plots:
        inside = _inside_plot(p, weeds[:, 0], weeds[:, 1]) if len(weeds) else np.zeros(0, bool)
        out[p["plot_id"]] = {"empty": bool(p.get("empty", False)), "weeds": int(inside.sum()),
                             "gaps": len(p.get("gaps", ())),
                             "gaps_at_row_end": sum(abs(u0) >= end or abs(u1) >= end
                                                    for _, u0, u1 in p.get("gaps", ())
                                                    for end in [p["size"][0] / 2 - EDGE - 1e-9]),
                             "lodged": "lodged" in p,
                             "no_alley": bool(scene.mess.touching and p["row"] in TOUCHING_BLOCK[0]
                                              and p["col"] in TOUCHING_BLOCK[1])}
    return out


@dataclass
class DemoSurvey:
    """Absolute paths of everything :func:`make_demo_survey` wrote, and a few facts.

    ``crs``: map CRS of the rasters, plots, point clouds and truth (heights ellipsoidal);
    ``metashape_project``: the .psx; ``pix4d_project``: the .p4d; ``pix4d_params``: its
    ``1_initial/params`` folder; ``odm_project``: the ODM project folder; ``opf_project``: the
    ``project.opf`` (the four None for a rolling-shutter survey: only the Metashape project
    models the motion); ``seconds``: generation time.
    """
    folder: str
    seed: int
    size: str
    crs: str
    orthomosaic: str
    dsm: str
    plots_geojson: str
    plots_gpkg: str
    point_cloud_laz: str
    point_cloud_ply: str
    photo_folder: str
    photos: List[str]
    metashape_project: str
    pix4d_project: Optional[str]
    pix4d_params: Optional[str]
    labelme: List[str]
    truth: str
    plot_ids: List[str] = field(default_factory=list)
    seconds: float = 0.0
    odm_project: Optional[str] = ""
    rolling_shutter: bool = False
    opf_project: Optional[str] = ""
    field_mess: FieldMess = FieldMess()


SURVEY_ENTRIES = ("orthomosaic.tif", "dsm.tif", "plots.geojson", "plots.gpkg", "pointcloud.laz",
                  "pointcloud.ply", "photos", "metashape", "pix4d", "odm", "opf", "labelme",
                  "truth.json")
"""What :func:`make_demo_survey` writes into its folder (files and folders)."""


def make_demo_survey(folder: str, seed: int = 0, size: str = "small", overwrite: bool = False,
                     progress=None, is_cancelled=None, rolling_shutter: bool = False,
                     ortho_defects: bool = False, field_mess: FieldMess = FieldMess()) -> DemoSurvey:
    """Write the demo survey into ``folder`` (created if needed) and return its paths.

    ``size``: "small" (36 photos of 800×600) or "medium" (36 photos of 1600×1200); the field,
    flight and truth points are the same. When any of :data:`SURVEY_ENTRIES` already exists in
    ``folder`` the run stops before writing anything, unless ``overwrite``.
    ``progress(percent)`` and ``is_cancelled()`` are optional callables; on cancellation
    :class:`core.errors.Cancelled` is raised and the folder may hold a partial survey (every
    file in it complete). ``rolling_shutter``: photos taken while the drone moves (see the
    module docstring). ``ortho_defects``: ghosting and blur in the written orthomosaic over
    some plots (see the module docstring). ``field_mess``: what the field has (weeds, grass,
    …; see the module docstring).
    """
    if size not in SIZES:
        raise InputError(f"Demo survey size {size!r}: choose one of {', '.join(SIZES)}.")
    with OutputFolder(folder, overwrite=overwrite, what="Demo survey folder") as out:
        out.claim(SURVEY_ENTRIES)
        return _write_survey(str(out.folder), seed, size, as_progress(progress, is_cancelled),
                             rolling_shutter, ortho_defects, field_mess)


def _write_survey(folder: str, seed: int, size: str, prog, rolling_shutter: bool,
                  ortho_defects: bool = False, field_mess: FieldMess = FieldMess()) -> DemoSurvey:
    t0 = time.perf_counter()
    prog.check()
    camera = make_camera(size)
    photo_dir = os.path.join(folder, "photos")
    os.makedirs(photo_dir, exist_ok=True)
    rng = np.random.default_rng([seed, 1])

    scene = make_scene(seed, mess=field_mess)
    lay = scene.layout
    shots = plan_flight(scene, rng)
    if rolling_shutter:                    # own random stream: everything else stays the same
        shots = readout_motion.add_motion(shots, np.random.default_rng([seed, 2]))
    photos = [os.path.join(photo_dir, s.filename) for s in shots]
    cloud_xyz, cloud_rgb = surface_cloud(scene, rng)
    prog.set(10)
    prog.check()

    rays = pixel_rays(camera)
    level = level_for(camera, ALTITUDE)
    level_img = packed_level(scene.ortho, level)

    tags = photo_tag_segments(scene, camera, shots, seed)

    def shoot(i: int) -> None:
        prog.check()
        render = render_photo if shots[i].motion is None else readout_motion.render_photo
        _write_jpeg(photos[i], render(scene, camera, shots[i], rays, level_img, level),
                    tags[shots[i].label])

    ortho, defects = scene.ortho, None
    if ortho_defects:            # the written orthomosaic only: photos see the true texture
        ortho, defects = add_ortho_defects(scene.ortho, scene)
    with ThreadPoolExecutor(2) as pool:
        jobs = [pool.submit(write_geotiff, os.path.join(folder, "orthomosaic.tif"), ortho,
                            lay.geotransform(DOM_PIXEL), epsg_geo_tags(lay.epsg), rgb=True, tile=256),
                pool.submit(write_geotiff, os.path.join(folder, "dsm.tif"), scene.dsm,
                            lay.geotransform(DSM_PIXEL), epsg_geo_tags(lay.epsg),
                            nodata_text="-9999", tile=256),
                pool.submit(_write_clouds, folder, cloud_xyz, cloud_rgb, lay.epsg)]
        jobs += [pool.submit(shoot, i) for i in range(len(shots))]
        try:
            # meanwhile, on this thread: vectors, truth, the two projects, LabelMe
            geojson, gpkg = _write_plots(folder, scene)
            truth, ms, p4d = _truth_and_projects(folder, scene, camera, shots, photos, rng)
            for pid, colour in plot_colour_truth(scene, seed).items():
                truth.plots[pid].update(colour)
            for pid, feats in field_features(scene).items():
                truth.plots[pid]["field"] = feats
            prog.set(25)
            for k, job in enumerate(as_completed(jobs)):
                job.result()
                prog.set(25 + 75 * (k + 1) / len(jobs))
                prog.check()
        except BaseException:
            for job in jobs:
                job.cancel()
            raise
    odm = None if rolling_shutter else \
        write_odm(os.path.join(folder, "odm"), scene, camera, shots, photos, truth.points,
                  os.path.join(folder, "dsm.tif"), os.path.join(folder, "orthomosaic.tif"))
    opf = None if rolling_shutter else \
        write_opf(os.path.join(folder, "opf"), camera, shots, scene.offset, photos, lay.epsg)
    # last, so that a truth file means a complete survey
    meta = {"seed": seed, "size": size, "metashape_pose_fit_max_px": ms["max_fit_px"],
            "field_mess": {**asdict(scene.mess), "description": MESS_NOTE},
            "photo_tags": noise_note()}
    if rolling_shutter:
        meta["rolling_shutter"] = True
    if defects is not None:
        meta["ortho_defects"] = {**defects, "description": DEFECTS_NOTE}
    truth_path = write_truth(os.path.join(folder, "truth.json"), truth, scene, camera, shots, meta)

    return DemoSurvey(
        folder=folder, seed=seed, size=size, crs=f"EPSG:{lay.epsg}",
        orthomosaic=os.path.join(folder, "orthomosaic.tif"), dsm=os.path.join(folder, "dsm.tif"),
        plots_geojson=geojson, plots_gpkg=gpkg,
        point_cloud_laz=os.path.join(folder, "pointcloud.laz"),
        point_cloud_ply=os.path.join(folder, "pointcloud.ply"),
        photo_folder=photo_dir, photos=photos, metashape_project=ms["psx"],
        pix4d_project=p4d and p4d["p4d"], pix4d_params=p4d and p4d["params"],
        labelme=[os.path.join(folder, k) for k in truth.labelme], truth=truth_path,
        plot_ids=[p["plot_id"] for p in scene.plots], seconds=time.perf_counter() - t0,
        odm_project=odm and odm["project"], rolling_shutter=rolling_shutter,
        opf_project=opf and opf["project"], field_mess=scene.mess)


def _write_plots(folder: str, scene):
    lay = scene.layout
    geojson = write_plots_geojson(os.path.join(folder, "plots.geojson"), scene.plots, lay.epsg)
    table = GpkgTable("plots", [("plot_id", "TEXT"), ("row", "INTEGER"), ("col", "INTEGER")],
                      [(p["plot_id"], p["row"], p["col"]) for p in scene.plots],
                      [[[plot_corners(p)]] for p in scene.plots], f"EPSG:{lay.epsg}")
    gpkg = write_geopackage(os.path.join(folder, "plots.gpkg"), [table])
    return geojson, gpkg


def _truth_and_projects(folder: str, scene, camera, shots, photos, rng):
    """Truth (points, observations, plots, LabelMe) and the Metashape and Pix4D projects; the
    ground control targets become Metashape markers with their exact pixels."""
    pts, ids, kinds = truth_points(scene, rng)
    seen_p, seen_m, seen_uv, hid_p, hid_m = observations(scene, camera, shots, pts)
    truth = Truth(pts + scene.offset, ids, kinds, seen_p, seen_m, seen_uv, hid_p, hid_m,
                  plot_visibility(scene, camera, shots))
    markers = []
    for label in scene.gcp_labels:
        sel = seen_p == ids.index(label)
        markers.append({"label": label, "xyz": truth.points[ids.index(label)],
                        "pixels": {int(m): tuple(uv) for m, uv in zip(seen_m[sel], seen_uv[sel])}})
    ms = write_metashape(os.path.join(folder, "metashape"), PROJECT_NAME, scene, camera, shots,
                         photos, markers, rng)
    p4d = None if any(s.motion is not None for s in shots) else \
        write_pix4d(os.path.join(folder, "pix4d"), PROJECT_NAME, camera, shots, scene.offset, photos)
    truth.labelme = write_labelme(os.path.join(folder, "labelme"), os.path.dirname(photos[0]),
                                  scene, camera, shots,
                                  {k: v["photos_whole"] for k, v in truth.plots.items()}, rng)
    return truth, ms, p4d


def _write_jpeg(path: str, img: np.ndarray, tags: bytes = b"") -> None:
    """The photo as a JPEG, with ``tags`` (APP1 EXIF and XMP segments) after its SOI."""
    import imagecodecs
    data = imagecodecs.jpeg8_encode(np.ascontiguousarray(img), level=JPEG_QUALITY)
    write_bytes(path, tag_jpeg(data, tags))


def _write_clouds(folder: str, xyz: np.ndarray, rgb: np.ndarray, epsg: int) -> None:
    """pointcloud.laz and pointcloud.ply; the LAS creation date is fixed (same seed → same bytes)."""
    cloud = PointCloud.from_arrays(xyz, {"red": rgb[:, 0], "green": rgb[:, 1], "blue": rgb[:, 2]},
                                   crs=f"EPSG:{epsg}")
    laz = write_point_cloud(cloud, os.path.join(folder, "pointcloud.laz"))
    with open(laz, "r+b") as fh:                 # LAS header: creation day of year, year
        fh.seek(90)
        fh.write(np.array(LAS_DATE, "<u2").tobytes())
    write_point_cloud(cloud, os.path.join(folder, "pointcloud.ply"))
