"""Training sets on the raw photos from labels drawn once on the map (map → photos).

:func:`export_training_set` back-projects labelled map polygons (:func:`.backward.back_project`:
heights from the DSM at every vertex, clipped to the frame, occlusion tested on the DSM, photos
ranked) and writes, into one folder::

    images/{train,val}/NAME.ext          whole photos (copied byte for byte) or tiles (PNG)
    labels/{train,val}/NAME.txt          YOLO segment labels;  data.yaml (Ultralytics)
    yolo_detect/images/…, labels/…       YOLO detect labels (images hard-linked, else copied);
                                         yolo_detect/data.yaml
    coco/instances_{train,val}.json      COCO instances (polygons, boxes, categories)
    labelme/{train,val}/NAME.json        LabelMe files (imagePath relative to the JSON)
    tiles.json                           tiles only: each tile's photo and window in it
                                         (:mod:`core.annotations.tiles`)
    training_set.json                    what was written, the split and the rules below

NAME is the photo file's own stem (:func:`photo_stem`: ``DJI_0002`` for ``DJI_0002.JPG``,
whatever the project kind's photo label) and ``.ext`` its extension in lower case, so every file
matches its photo again in Forward-project; a tile is ``NAME_rROW_cCOL.png``.

Pixels: the project convention (origin at the top-left image corner, centre of the top-left
pixel (0.5, 0.5)), which COCO, YOLO and LabelMe share: no shift.

Rules (stated once, here):

* **Hidden or outside.** An object is labelled in a photo when at least ``min_visible`` of its
  ground area is inside the frame *and* not hidden by anything outside itself
  (:mod:`.object_occlusion`: samples on the object's top surface; what its own canopy hides of
  it, tall rows hiding the soil between them included, does not count): share = in-frame
  fraction × (1 − hidden fraction). A kept object's outline is its whole projected outline
  clipped to the frame: hidden parts are not cut out (a 2 cm DSM cannot draw a leaf's edge).
* **Photos that do not decode.** Every photo is decoded before it goes into the set (a JPEG
  must also end with its end-of-image marker: libjpeg fills a truncated one with grey without
  an error). One that does not is left out with all its labels and named in
  ``skipped_photos``.
* **Tiles.** With ``tile_size`` > 0, photos are cut into tiles of that size (pixels) that
  overlap by ``tile_overlap`` pixels; the last tile of a row or column is aligned with the
  photo's edge. An object's outline is clipped exactly to each tile; the part is kept when its
  area is at least ``min_visible`` of the object's area in the photo, else it is dropped from
  that tile. Tiles without objects are not written. ``tiles.json`` records each tile's photo
  and window ([x0, y0, width, height] photo pixels), keyed by the tile's file stem; COCO images
  carry the same as ``photo`` and ``photo_window``. Forward projection reads detections on the
  tiles (YOLO, LabelMe) back into the photo's pixels with it (``read_annotations(tiles=)``).
* **Split.** Whole images go to train or val, none is lost (:mod:`.training_split`: by photo,
  or by square field regions of ``region_size`` map units); validation gets ``val_fraction`` of
  the images, at least one when there are two. ``warnings`` says when validation is empty or
  under half the fraction asked. An object seen in images of both splits is counted
  (``shared_objects``).
* **Best k.** ``best_k`` > 0 keeps the best k photos of each object (back-projection's rank
  among the photos that keep it).
* **Tiles per photo.** A tile size that cuts a photo into more than :data:`MAX_TILES_PER_PHOTO`
  tiles is refused (the number is said). Only tiles that hold an object are cut and written.

* **Values.** ``values`` temperature or reflectance (:func:`..radiometry.read_photo_values`):
  every image, whole photo or tile, is a float32 TIFF (``NAME.tif``: PNG and JPEG cannot hold
  those values) with the unit and what was applied in GDAL's metadata and NaN where a pixel
  is not valid (saturated, unreadable); a photo that holds no such values is left out with
  its labels, as one that does not decode. Networks train on either.

Whole photos are decoded once (the check) and copied byte for byte; tiled photos (and every
photo in physical values) are decoded at the check and again to cut them
(:mod:`.training_images`). Every file is written atomically. The folder holds only the set: what
it lists in ``training_set.json``; OVERWRITE removes exactly that, foreign files are refused, a
killed run's leftovers are removed by the next (:mod:`.training_folder`).
"""
import dataclasses
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..annotations import (TILE_INDEX, LabelledImage, LabelledShape, tile_index_document,
                           write_coco, write_labelme, write_yolo_labels, yolo_data_yaml)
from ..deprecation import renamed_parameters
from ..errors import InputError
from ..files import OutputFolder, write_bytes, write_json
from ..geometry import orient, polygons_area
from ..naming import unique_names
from ..photos import PHOTO_EXTENSIONS, file_name, resolve_photos
from ..progress import as_progress
from ..radiometry import UNITS, photo_decoder
from ..raster import as_dsm
from ..roi import ROI, ROISet
from .backward import back_project
from .clip import clip_convex, rectangle
from .object_occlusion import outside_hidden_fractions
from .training_folder import MANIFEST, TrainingFolder
from .training_images import decodable_photos, write_images
from .training_split import SPLIT_MODES, SPLITS, assign_images, split_warnings

HIDDEN_SAMPLES = 64
"""Samples per object for the hiding test (:mod:`.object_occlusion`): the share is known to
1/64, ample beside ``min_visible``; Back-project ROIs uses 256."""
MAX_TILES_PER_PHOTO = 4096
"""Tiles one photo may be cut into; a smaller tile size is refused (a 20 MP photo in 64 px
tiles gives about 4,900)."""


@dataclass
class TrainingSet:
    """What :func:`export_training_set` wrote. ``images``/``annotations``/``objects``: counts
    per split; ``shared_objects``: objects in images of both splits; ``object_split``:
    {instance: "train", "val" or "both"} of every object labelled at least once; ``unseen``:
    {instance: why no photo keeps it}; ``skipped_photos``: {photo: why it was left out};
    ``warnings``: what the user should know (an empty or small validation set);
    ``removed``: an older set's files removed (overwrite); ``files``: every path written."""
    folder: str
    images: Dict[str, int] = field(default_factory=dict)
    annotations: Dict[str, int] = field(default_factory=dict)
    objects: Dict[str, int] = field(default_factory=dict)
    shared_objects: int = 0
    dropped_in_tiles: int = 0
    object_split: Dict[str, str] = field(default_factory=dict)
    unseen: Dict[str, str] = field(default_factory=dict)
    skipped_photos: Dict[str, str] = field(default_factory=dict)
    categories: List[str] = field(default_factory=list)
    warnings: List[str] = field(default_factory=list)
    notes: List[str] = field(default_factory=list)
    removed: List[str] = field(default_factory=list)
    files: List[str] = field(default_factory=list)

    def summary(self) -> str:
        per = "; ".join(f"{s}: {self.images.get(s, 0)} images, {self.annotations.get(s, 0)} "
                        f"labels of {self.objects.get(s, 0)} objects" for s in SPLITS)
        return (f"{per}; {self.shared_objects} objects in images of both splits; "
                f"{len(self.skipped_photos)} photos left out; "
                f"{len(self.unseen)} objects seen by no photo")


def photo_stem(path: str) -> str:
    """The stem exported images and labels of a photo are named after: the photo file's own
    name without its photo extension, case kept (``…/DJI_0002.JPG`` → ``DJI_0002``), so that
    ``DJI_0002.jpg``, ``.json`` and ``.txt`` match the photo again by
    :func:`..photos.photo_key`; never ``DJI_0002.JPG.jpg``."""
    base = file_name(path)
    stem, ext = os.path.splitext(base)
    return stem if ext.lower() in PHOTO_EXTENSIONS else base


def point_discs(names: Sequence[str], xy, radius: float, vertices: int = 32,
                attributes: Optional[Sequence[dict]] = None, crs=None) -> ROISet:
    """ROIs for labelled points: a regular ``vertices``-gon of circumradius ``radius`` (map
    units) around each (x, y), counter-clockwise."""
    if not radius > 0:
        raise InputError(f"The radius of the discs around labelled points must be positive, "
                         f"not {radius}.")
    t = np.linspace(0.0, 2 * np.pi, int(vertices), endpoint=False)
    ring = radius * np.column_stack([np.cos(t), np.sin(t)])
    xy = np.asarray(xy, np.float64).reshape(-1, 2)
    attrs = attributes or [{} for _ in names]
    return ROISet([ROI(str(n), [[ring + p]], dict(a)) for n, p, a in zip(names, xy, attrs)], crs)


def tile_origins(length: int, size: int, overlap: int) -> List[int]:
    """Start pixels of tiles of ``size`` along ``length`` overlapping by ``overlap``; the last
    aligned with the end. One tile (0) when ``size`` is 0 or at least ``length``."""
    if size <= 0 or size >= length:
        return [0]
    step = size - overlap
    starts = list(range(0, length - size, step)) + [length - size]
    return sorted(set(starts))


def _check_tiles(tile_size: int, tile_overlap: int, sizes) -> None:
    if tile_size < 0 or tile_overlap < 0 or (tile_size and tile_overlap >= tile_size):
        raise InputError(f"Tiles of {tile_size} px with {tile_overlap} px overlap: the size must "
                         "be 0 (whole photos) or more than the overlap, both ≥ 0.")
    if not tile_size:
        return
    for w, h in {(int(a), int(b)) for a, b in sizes}:
        n = len(tile_origins(w, tile_size, tile_overlap)) * len(tile_origins(h, tile_size, tile_overlap))
        if n > MAX_TILES_PER_PHOTO:
            raise InputError(
                f"Tiles of {tile_size} px with {tile_overlap} px overlap cut a {w} × {h} px photo "
                f"into {n} tiles, more than {MAX_TILES_PER_PHOTO} per photo. Choose a larger tile "
                "size or a smaller overlap.")


def _visible_pairs(bp, rois, recon, dsm, min_visible: float, best_k: int, prog):
    """The back-projection records kept by the rule of the module docstring: the in-frame share
    times the share not hidden by anything outside the object; the best ``best_k`` per object."""
    cams = [recon.camera(lab) for lab in bp.photo_labels]
    hidden, notes = outside_hidden_fractions(rois, bp.roi, bp.photo_index, recon, cams, dsm,
                                             samples=HIDDEN_SAMPLES, progress=prog)
    share = bp.visible_fraction * (1.0 - np.nan_to_num(hidden, nan=0.0))
    keep = np.flatnonzero(share >= min_visible)          # records are sorted by ROI, then rank
    roi = bp.roi[keep]
    first = np.ones(len(keep), bool)
    first[1:] = roi[1:] != roi[:-1]
    start = np.maximum.accumulate(np.where(first, np.arange(len(keep)), 0))
    rank = np.arange(len(keep)) - start + 1
    if best_k > 0:
        keep, rank = keep[rank <= best_k], rank[rank <= best_k]
    out = dataclasses.replace(
        bp, roi=bp.roi[keep], photo=bp.photo[keep], photo_index=bp.photo_index[keep],
        polygons=bp.polygons.take(keep), visible_fraction=bp.visible_fraction[keep],
        occluded_fraction=hidden[keep], score=bp.score[keep], view_angle=bp.view_angle[keep],
        gsd=bp.gsd[keep], centre_distance=bp.centre_distance[keep],
        rank=rank.astype(np.int32), clipped=bp.clipped[keep], unseen=dict(bp.unseen))
    seen = np.bincount(bp.roi, minlength=len(rois))
    kept = np.bincount(out.roi, minlength=len(rois))
    for r in np.flatnonzero((seen > 0) & (kept == 0)):
        out.unseen[rois.names[r]] = (f"in the frame of {seen[r]} photo(s), but less than "
                                     f"{min_visible:g} of it in the frame and not hidden by "
                                     "anything outside it in each")
    return out, notes


@renamed_parameters(out_folder="output_folder", dsm_crs="source_crs", best_k="max_views")
def export_training_set(rois: ROISet, classes: Sequence[str], recon, dsm, output_folder, *,
                        source_crs=None, photos_folder=None, cameras=None, max_views: int = 0,
                        min_visible: float = 0.5, tile_size: int = 0, tile_overlap: int = 0,
                        split: str = "region", val_fraction: float = 0.2,
                        region_size: float = 10.0, seed: int = 0, overwrite: bool = False,
                        progress=None, is_cancelled=None, values: str = "stored",
                        value_options: Optional[dict] = None) -> TrainingSet:
    """Write a COCO, YOLO (detect and segment) and LabelMe training set of ``rois`` on the raw
    photos of ``recon`` (layout and rules: the module docstring).

    Parameters
    ----------
    rois : ROISet
        The labelled objects (ROI names are the instance names, unique).
    classes : sequence of str
        The class of each ROI, in the order of ``rois``.
    recon : Reconstruction
        The opened project (:func:`open_reconstruction`).
    dsm : str or path
        GeoTIFF of the DSM: vertex heights and the occlusion test.
    output_folder : str or path
        The folder the training set is written into.
    source_crs : CRS, optional
        The CRS to assume for the DSM, instead of the one its GeoKeys give.
    photos_folder : str or path, optional
        Where the photos are when they moved (matched by file name).
    cameras : sequence of str, optional
        Photo labels to use (default: every aligned photo).
    max_views : int
        Label each object in its best k photos only (0: every photo that sees it).
    min_visible : float
        An object is labelled in a photo when at least this share (0–1) of it is in the frame
        and not hidden by anything outside itself.
    tile_size : int
        Tiles of this many pixels (0: whole photos).
    tile_overlap : int
        Overlap of neighbouring tiles, pixels.
    split : {"region", "photo"}
        How whole images go to train and validation: by map regions, or photo by photo.
    val_fraction : float
        The share of objects asked for in validation (0–1).
    region_size : float
        The side of a split region, in map units of the ROIs' CRS.
    seed : int
        The seed of the split's random draw.
    overwrite : bool
        Replace this run's earlier outputs; without it existing files stop the run before any
        work. The input is never replaced.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    values : {"stored", "temperature", "reflectance"}
        The images as the photos store them (default), or float32 TIFFs in °C or reflectance
        (the module docstring's rule *Values*).
    value_options : dict, optional
        The options of ``values`` (object parameters, temperature TIFF scale:
        :func:`..radiometry.read_photo_values`).

    Returns
    -------
    TrainingSet
        The files written, images and labels per split, the objects left out and the warnings.
    """
    decoding = (values, photo_decoder(values, value_options))
    image_ext = ".png" if values == "stored" else ".tif"       # tiles; every image in values
    prog = as_progress(progress, is_cancelled)
    if not isinstance(rois, ROISet):
        rois = ROISet(list(rois))
    classes = [str(c) for c in classes]
    if len(classes) != len(rois):
        raise InputError(f"{len(classes)} classes for {len(rois)} objects: give one class per object.")
    if any(not c.strip() for c in classes):
        bad = [r.name for r, c in zip(rois, classes) if not c.strip()][:5]
        raise InputError(f"Objects without a class ({', '.join(bad)}): fill the class field.")
    if len(set(rois.names)) != len(rois):
        raise InputError("Object (instance) names must be unique: give an instance id field "
                         "with one value per object, or leave it empty to number them.")
    if split not in SPLIT_MODES:
        raise InputError(f"split must be one of {SPLIT_MODES}, not {split!r}.")
    if not 0.0 <= val_fraction < 1.0:
        raise InputError(f"The validation fraction must be in [0, 1), not {val_fraction}.")
    if split == "region" and not region_size > 0:
        raise InputError(f"The region size must be positive map units, not {region_size}.")
    tile_size, tile_overlap = int(tile_size), int(tile_overlap)
    cams = recon.select_cameras(cameras)
    _check_tiles(tile_size, tile_overlap,
                 [(recon.sensors[c.sensor_id].width, recon.sensors[c.sensor_id].height) for c in cams])
    dsm = as_dsm(dsm, source_crs)
    bp = back_project(rois, recon, heights=dsm, cameras=cameras, occlusion_dsm=None,
                      min_visible=min_visible, max_views=0, progress=prog.sub(0, 40))
    bp, notes = _visible_pairs(bp, rois, recon, dsm, float(min_visible), int(max_views),
                               prog.sub(40, 60))
    categories = sorted(set(classes))
    result = TrainingSet(os.path.abspath(os.fspath(output_folder)), categories=categories,
                         unseen=dict(bp.unseen), notes=notes)

    used = sorted(set(bp.photo_index.tolist()), key=lambda j: bp.photo_labels[j])
    labels = [bp.photo_labels[j] for j in used]
    found, missing = resolve_photos(labels, [bp.photo_paths[j] for j in used], photos_folder)
    result.skipped_photos.update(missing)
    if labels and not found:
        raise InputError(f"None of the {len(labels)} photos is available: "
                         f"{'; '.join(list(missing.values())[:3])}. Give the photos folder.")
    stems = dict(zip(labels, unique_names(photo_stem(found.get(lab) or lab) for lab in labels)))
    centres = np.array([[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in (r.bounds for r in rois)]) \
        if len(rois) else np.zeros((0, 2))

    # every image and its labels, before anything is written
    roi_names = rois.names
    images = []          # [split, LabelledImage, photo label, (r0, c0) or None, roi indices]
    by_photo = {}
    for i in range(len(bp)):
        by_photo.setdefault(int(bp.photo_index[i]), []).append(i)
    for j in used:
        label = bp.photo_labels[j]
        if label not in found:
            continue
        prog.check()
        w, h = (int(v) for v in bp.image_sizes[j])
        recs = by_photo[j]
        polys = {i: orient(bp.polygons_of(i)) for i in recs}
        ext = os.path.splitext(found[label])[1].lower() \
            if not tile_size and values == "stored" else image_ext
        if not tile_size:
            im = LabelledImage(stems[label] + ext, w, h,
                               attributes={"photo": label, "photo_window": [0, 0, w, h]})
            for i in recs:
                im.shapes.append(_shape(bp, i, polys[i], classes, roi_names))
            images.append([None, im, label, None, [int(bp.roi[i]) for i in recs]])
            continue
        for (r0, c0), parts in _tile_parts(polys, w, h, tile_size, tile_overlap, min_visible,
                                           result):
            tw, th = min(tile_size, w), min(tile_size, h)
            im = LabelledImage(f"{stems[label]}_r{r0:05d}_c{c0:05d}{image_ext}", tw, th,
                               attributes={"photo": label, "photo_window": [c0, r0, tw, th]})
            for i, p in parts:
                im.shapes.append(_shape(bp, i, p, classes, roi_names))
            images.append([None, im, label, (r0, c0), [int(bp.roi[i]) for i, _ in parts]])
    prog.set(65)

    names = {"data.yaml", os.path.join("yolo_detect", "data.yaml")}
    if tile_size:
        names.add(TILE_INDEX)
    for s in SPLITS:
        names.add(os.path.join("coco", f"instances_{s}.json"))
    for s in SPLITS:               # the split is not drawn yet: either may hold an image
        for x in images:
            names.update(_image_files(s, x[1].file_name))
    root = os.path.realpath(os.fspath(output_folder)) + os.sep
    inputs = [p for p in [dsm.path] + list(found.values())         # an output can only be an
              if p and os.path.realpath(p).startswith(root)]         # input inside the folder
    with OutputFolder(output_folder, overwrite=overwrite, inputs=inputs,
                      what="Training set folder") as out:
        plan = TrainingFolder(out.folder)
        plan.check(overwrite)
        if inputs:
            raise InputError(f"The training set folder {str(out.folder)!r} holds inputs of this "
                             f"export ({inputs[0]}…): it would replace them. Choose another "
                             "folder.")
        # photos that do not decode are found while writing; their files are not written
        planned = {"data.yaml", os.path.join("yolo_detect", "data.yaml"), TILE_INDEX} | \
            {os.path.join("coco", f"instances_{s}.json") for s in SPLITS}
        plan.begin(sorted(names & planned) + sorted(n for x in images for s in SPLITS
                                                    for n in _image_files(s, x[1].file_name)))
        for s in SPLITS:
            for sub in ("images", "labels", os.path.join("yolo_detect", "images"),
                        os.path.join("yolo_detect", "labels"), "labelme"):
                os.makedirs(out.folder / sub / s, exist_ok=True)
        os.makedirs(out.folder / "coco", exist_ok=True)
        good = decodable_photos(images, found, bp, result, prog, decoding[1])
        images = [x for x in images if x[2] in good]
        split_of, warn = assign_images([x[2] for x in images],
                                       [centres[x[4]] for x in images], split,
                                       float(val_fraction), float(region_size), int(seed))
        for x, k in zip(images, split_of):
            x[0] = SPLITS[int(k)]
        write_images(out.folder, images, found, good, result, prog, decoding)
        _write_labels(out.folder, images, categories, result)
        for s in SPLITS:
            result.images[s] = sum(1 for x in images if x[0] == s)
            result.annotations[s] = sum(len(x[1].shapes) for x in images if x[0] == s)
        splits_of = {}
        for s, im, *_ in images:
            for sh in im.shapes:
                splits_of.setdefault(sh.instance, set()).add(s)
        for s in SPLITS:
            result.objects[s] = sum(1 for v in splits_of.values() if s in v)
        result.object_split = {k: (next(iter(v)) if len(v) == 1 else "both")
                               for k, v in splits_of.items()}
        result.shared_objects = sum(1 for v in result.object_split.values() if v == "both")
        result.warnings = warn + split_warnings(result.images["val"], len(images),
                                                float(val_fraction), len(result.object_split))
        manifest = {
            "pixels": "origin at the top-left corner of the image, x right, y down; the centre of "
                      "the top-left pixel is (0.5, 0.5) (COCO, YOLO and LabelMe alike)",
            "rules": {"min_visible": float(min_visible), "best_k": int(max_views),
                      "tile_size": tile_size, "tile_overlap": tile_overlap, "split": split,
                      "val_fraction": float(val_fraction), "region_size": float(region_size),
                      "seed": int(seed),
                      "hidden": "an object is labelled in a photo when at least min_visible of it "
                                "is in the frame and not hidden by anything outside it (samples "
                                "on its top surface; its own canopy does not count); hidden "
                                "parts of a kept object are not cut out",
                      "tiles": "outlines clipped to the tile; a part smaller than min_visible of "
                               "the object's area in the photo is dropped",
                      "split_rule": "whole images go to one split, none is left out; objects "
                                    "seen in images of both splits are counted as shared"},
            "categories": categories, "images": result.images, "annotations": result.annotations,
            "objects": result.objects, "shared_objects": result.shared_objects,
            "dropped_in_tiles": result.dropped_in_tiles, "object_split": result.object_split,
            "unseen": result.unseen, "skipped_photos": result.skipped_photos,
            "warnings": result.warnings, "back_projection": bp.settings}
        if values != "stored":
            manifest["values"] = {"values": values, "unit": UNITS[values]}
        if tile_size:
            tiles = {os.path.splitext(im.file_name)[0]: (label, im.attributes["photo_window"])
                     for _, im, label, *_ in images}
            write_json(out.folder / TILE_INDEX, tile_index_document(tiles), indent=1)
            result.files.append(str(out.folder / TILE_INDEX))
        written = [os.path.relpath(f, out.folder) for f in result.files] + [MANIFEST]
        plan.new = sorted({n.replace(os.sep, "/") for n in written})
        result.removed = plan.finish(manifest)
        result.files.append(str(out.folder / MANIFEST))
    result.files.sort()
    prog.set(100)
    return result


def _image_files(s: str, file_name_: str) -> List[str]:
    stem = os.path.splitext(file_name_)[0]
    return [os.path.join("images", s, file_name_), os.path.join("labels", s, stem + ".txt"),
            os.path.join("yolo_detect", "images", s, file_name_),
            os.path.join("yolo_detect", "labels", s, stem + ".txt"),
            os.path.join("labelme", s, stem + ".json")]


def _shape(bp, i: int, polygons, classes, names) -> LabelledShape:
    r = int(bp.roi[i])
    return LabelledShape(classes[r], names[r], polygons,
                         {"photo": str(bp.photo[i]), "rank": int(bp.rank[i]),
                          "visible_fraction": round(float(bp.visible_fraction[i]), 4),
                          "occluded_fraction": round(float(np.nan_to_num(bp.occluded_fraction[i])), 4)})


def _tile_parts(polys, w: int, h: int, size: int, overlap: int, min_visible: float, result):
    """[((r0, c0), [(record, clipped polygons)])] of the tiles of one photo that hold a part of
    an object: each outline is clipped only to the tiles its bounding box meets."""
    rows = np.array(tile_origins(h, size, overlap))
    cols = np.array(tile_origins(w, size, overlap))
    tw, th = min(size, w), min(size, h)
    tiles = {}
    for i, p in polys.items():
        xy = np.concatenate([ring for q in p for ring in q])
        x0, y0 = xy.min(axis=0)
        x1, y1 = xy.max(axis=0)
        cs = cols[(cols < x1) & (cols + tw > x0)]
        rs = rows[(rows < y1) & (rows + th > y0)]
        full = polygons_area(p)
        for r0 in rs:
            for c0 in cs:
                off = np.array([c0, r0], float)
                q = [[ring - off for ring in part] for part in p]
                if not (x0 >= c0 and y0 >= r0 and x1 <= c0 + tw and y1 <= r0 + th):
                    q = clip_convex(q, rectangle(tw, th))
                if not q:
                    continue
                if polygons_area(q) < min_visible * full:
                    result.dropped_in_tiles += 1
                    continue
                tiles.setdefault((int(r0), int(c0)), []).append((i, q))
    return sorted(tiles.items())


def _write_labels(folder, images, categories, result):
    index = {c: k for k, c in enumerate(categories)}
    present = [s for s in SPLITS]
    for s in SPLITS:
        ims = [im for sp, im, *_ in images if sp == s]
        result.files.append(write_coco(folder / "coco" / f"instances_{s}.json", ims, categories,
                                       f"EasyIDP training set, {s}"))
        for im in ims:
            stem = os.path.splitext(im.file_name)[0]
            result.files.append(write_yolo_labels(folder / "labels" / s / f"{stem}.txt", im,
                                                  index, segment=True))
            result.files.append(write_yolo_labels(folder / "yolo_detect" / "labels" / s /
                                                  f"{stem}.txt", im, index, segment=False))
            result.files.append(write_labelme(folder / "labelme" / s / f"{stem}.json", im,
                                              f"../../images/{s}/{im.file_name}"))
    for root, task in ((folder, "segment"), (folder / "yolo_detect", "detect")):
        write_bytes(root / "data.yaml", yolo_data_yaml(categories, present, task).encode())
        result.files.append(str(root / "data.yaml"))


__all__ = ["export_training_set", "TrainingSet", "point_discs", "photo_stem", "tile_origins",
           "SPLIT_MODES", "MAX_TILES_PER_PHOTO"]
