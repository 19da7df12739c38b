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
  ground area is inside the frame *and* not hidden by the DSM (back-projection's share =
  visible fraction × (1 − occluded fraction)); otherwise it is absent from that photo. A kept
  object's outline is its whole projected outline clipped to the frame: parts hidden by the
  DSM are not cut out (a 2 cm DSM cannot draw a leaf's edge).
* **Tiles.** With ``tile_size`` > 0, photos are cut into tiles of that size (pixels) that
  overlap by ``tile_overlap`` pixels; the last tile of a row or column is aligned with the
  photo's edge. An object's outline is clipped exactly to each tile; the part is kept when its
  area is at least ``min_visible`` of the object's area in the photo, else it is dropped from
  that tile. Tiles without objects are not written. ``tiles.json`` records each tile's photo
  and window ([x0, y0, width, height] photo pixels), keyed by the tile's file stem; COCO images
  carry the same as ``photo`` and ``photo_window``. Forward projection reads detections on the
  tiles (YOLO, LabelMe) back into the photo's pixels with it (``read_annotations(tiles=)``).
* **Split.** Every *object* goes to train or val (seeded): ``split="region"`` by square field
  cells of ``region_size`` map units that hold the object's centre; ``split="photo"`` by the
  split of the object's best photo, photos drawn at random. An image goes to the split of its
  objects; an image that holds objects of both splits is left out (counted), so no object is
  in both.
* **Best k.** ``best_k`` > 0 keeps the best k photos of each object (back-projection's rank).

One decode per photo (tiles only; whole photos are copied without decoding); every file is
written atomically, and none that exists is replaced unless ``overwrite``.
"""
import os
import shutil
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..annotations import (TILE_INDEX, LabelledImage, LabelledShape, tile_index_document,
                           write_coco, write_labelme, write_yolo_labels, yolo_data_yaml)
from ..errors import InputError
from ..files import OutputFolder, atomic_output, write_bytes, write_json
from ..geometry import orient, polygons_area
from ..naming import unique_names
from ..photo_files import PHOTO_EXTENSIONS, file_name
from ..progress import as_progress
from ..raster import as_dsm
from ..roi import ROI, ROISet
from .backward import back_project
from .clip import clip_convex, rectangle
from .photo_crops import PNG_FAST
from .photos import DecodedPhotos, resolve_photos

SPLITS = ("train", "val")
SPLIT_MODES = ("photo", "region")
MANIFEST = "training_set.json"


@dataclass
class TrainingSet:
    """What :func:`export_training_set` wrote. ``images``/``annotations``/``objects``: counts
    per split; ``left_out``: images holding objects of both splits (not written);
    ``object_split``: {instance: split} of every object labelled at least once; ``unseen``:
    {instance: why no photo keeps it}; ``files``: every path written."""
    folder: str
    images: Dict[str, int] = field(default_factory=dict)
    annotations: Dict[str, int] = field(default_factory=dict)
    objects: Dict[str, int] = field(default_factory=dict)
    left_out: int = 0
    dropped_in_tiles: int = 0
    object_split: Dict[str, str] = field(default_factory=dict)
    unseen: Dict[str, str] = field(default_factory=dict)
    skipped_photos: Dict[str, str] = field(default_factory=dict)
    categories: List[str] = field(default_factory=list)
    files: List[str] = field(default_factory=list)

    def summary(self) -> str:
        per = ", ".join(f"{s}: {self.images.get(s, 0)} images, {self.annotations.get(s, 0)} "
                        f"labels of {self.objects.get(s, 0)} objects" for s in SPLITS)
        return (f"{per}; {self.left_out} images left out (objects of both splits); "
                f"{len(self.unseen)} objects seen by no photo")


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


def photo_stem(path: str) -> str:
    """The stem exported images and labels of a photo are named after: the photo file's own
    name without its photo extension, case kept (``…/DJI_0002.JPG`` → ``DJI_0002``), so that
    ``DJI_0002.jpg``, ``.json`` and ``.txt`` match the photo again by
    :func:`..photo_files.photo_key`; never ``DJI_0002.JPG.jpg``."""
    base = file_name(path)
    stem, ext = os.path.splitext(base)
    return stem if ext.lower() in PHOTO_EXTENSIONS else base


def tile_origins(length: int, size: int, overlap: int) -> List[int]:
    """Start pixels of tiles of ``size`` along ``length`` overlapping by ``overlap``; the last
    aligned with the end. One tile (0) when ``size`` is 0 or at least ``length``."""
    if size <= 0 or size >= length:
        return [0]
    step = size - overlap
    starts = list(range(0, length - size, step)) + [length - size]
    return sorted(set(starts))


def _object_splits(rois: ROISet, bp, mode: str, val_fraction: float, region_size: float,
                   seed: int) -> np.ndarray:
    """(n,) 0 = train, 1 = val per ROI (see the module docstring)."""
    rng = np.random.default_rng(seed)
    n = len(rois)
    out = np.zeros(n, np.int8)
    if val_fraction <= 0 or n == 0:
        return out
    if mode == "region":
        centres = np.array([[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in (r.bounds for r in rois)])
        cells = np.floor(centres / region_size).astype(np.int64)
        uniq, inv = np.unique(cells, axis=0, return_inverse=True)
        inv = np.asarray(inv).ravel()
        k = int(round(val_fraction * len(uniq)))
        val_cells = rng.permutation(len(uniq))[:k]
        is_val = np.zeros(len(uniq), bool)
        is_val[val_cells] = True
        return is_val[inv].astype(np.int8)
    labels = bp.photo_labels
    k = int(round(val_fraction * len(labels)))
    val_photo = np.zeros(len(labels), bool)
    val_photo[rng.permutation(len(labels))[:k]] = True
    best = bp.rank == 1
    out[bp.roi[best]] = val_photo[bp.photo_index[best]].astype(np.int8)
    return out


def export_training_set(rois: ROISet, classes: Sequence[str], recon, dsm, out_folder, *,
                        dsm_crs=None, photos_folder=None, cameras=None, best_k: int = 0,
                        min_visible: float = 0.5, tile_size: int = 0, tile_overlap: int = 0,
                        split: str = "region", val_fraction: float = 0.2,
                        region_size: float = 10.0, seed: int = 0, overwrite: bool = False,
                        progress=None, is_cancelled=None) -> TrainingSet:
    """Write a COCO, YOLO (detect and segment) and LabelMe training set of ``rois`` on the raw
    photos of ``recon`` (layout and rules: the module docstring).

    ``rois``: the labelled objects (ROI names = instance names, unique); ``classes``: the class
    of each ROI; ``dsm``: GeoTIFF path of the DSM (vertex heights and occlusion; ``dsm_crs``
    overrides its GeoKeys); ``photos_folder``: where the photos are when they moved;
    ``cameras``: photo labels to use (default all aligned). ``tile_size``/``tile_overlap``:
    pixels (0: whole photos); ``region_size``: map units of the ROIs' CRS.
    """
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
    if tile_size < 0 or tile_overlap < 0 or (tile_size and tile_overlap >= tile_size):
        raise InputError(f"Tiles of {tile_size} px with {tile_overlap} px overlap: the size must "
                         "be 0 (whole photos) or more than the overlap, both ≥ 0.")
    dsm = as_dsm(dsm, dsm_crs)
    bp = back_project(rois, recon, heights=dsm, cameras=cameras, occlusion_dsm=dsm,
                      min_visible=min_visible, max_images=best_k, progress=prog.sub(0, 60))
    categories = sorted(set(classes))
    obj_split = _object_splits(rois, bp, split, val_fraction, region_size, seed)
    result = TrainingSet(os.path.abspath(os.fspath(out_folder)), categories=categories,
                         unseen=dict(bp.unseen))

    used = sorted(set(bp.photo_index.tolist()), key=lambda j: bp.photo_labels[j])
    labels = [bp.photo_labels[j] for j in used]
    found, missing = resolve_photos(labels, [bp.photo_paths[j] for j in used], photos_folder)
    result.skipped_photos.update(missing)
    if labels and not found:
        raise InputError(f"None of the {len(labels)} photos is available: "
                         f"{'; '.join(list(missing.values())[:3])}. Give the photos folder.")
    stems = dict(zip(labels, unique_names(photo_stem(found.get(lab) or lab) for lab in labels)))

    # every image and its labels, before anything is written
    images = []          # (split, LabelledImage, photo label, (r0, c0) or None)
    by_photo = {}
    for i in range(len(bp)):
        by_photo.setdefault(int(bp.photo_index[i]), []).append(i)
    for j in used:
        label = bp.photo_labels[j]
        if label not in found:
            continue
        w, h = (int(v) for v in bp.image_sizes[j])
        recs = by_photo[j]
        polys = {i: orient(bp.polygons_of(i)) for i in recs}
        full = {i: polygons_area(p) for i, p in polys.items()}
        ext = os.path.splitext(found[label])[1].lower() if not tile_size else ".png"
        for r0 in tile_origins(h, tile_size, tile_overlap):
            for c0 in tile_origins(w, tile_size, tile_overlap):
                tw, th = (min(tile_size, w), min(tile_size, h)) if tile_size else (w, h)
                name = stems[label] + (f"_r{r0:05d}_c{c0:05d}" if tile_size else "") + ext
                im = LabelledImage(name, tw, th, attributes={"photo": label,
                                                             "photo_window": [c0, r0, tw, th]})
                sp = set()
                for i in recs:
                    p = polys[i]
                    if tile_size:
                        off = np.array([c0, r0], float)
                        p = clip_convex([[ring - off for ring in q] for q in p], rectangle(tw, th))
                        if not p or polygons_area(p) < min_visible * full[i]:
                            if p:
                                result.dropped_in_tiles += 1
                            continue
                    r = int(bp.roi[i])
                    im.shapes.append(LabelledShape(
                        classes[r], rois.names[r], p,
                        {"photo": label, "rank": int(bp.rank[i]),
                         "visible_fraction": round(float(bp.visible_fraction[i]), 4),
                         "occluded_fraction": round(float(bp.occluded_fraction[i]), 4)}))
                    sp.add(int(obj_split[r]))
                if not im.shapes:
                    continue
                if len(sp) > 1:
                    result.left_out += 1
                    continue
                images.append((SPLITS[sp.pop()], im, label, (r0, c0) if tile_size else None))
    prog.set(65)

    names = {"data.yaml", MANIFEST, os.path.join("yolo_detect", "data.yaml")}
    if tile_size:
        names.add(TILE_INDEX)
    for s in SPLITS:
        names.add(os.path.join("coco", f"instances_{s}.json"))
    for s, im, _, _ in images:
        stem = os.path.splitext(im.file_name)[0]
        names.update({os.path.join("images", s, im.file_name),
                      os.path.join("labels", s, stem + ".txt"),
                      os.path.join("yolo_detect", "images", s, im.file_name),
                      os.path.join("yolo_detect", "labels", s, stem + ".txt"),
                      os.path.join("labelme", s, stem + ".json")})
    inputs = [dsm.path] + list(found.values())
    with OutputFolder(out_folder, overwrite=overwrite, inputs=inputs,
                      what="Training set folder") as out:
        out.claim(sorted(names))
        for s in SPLITS:
            for sub in ("images", "labels", os.path.join("yolo_detect", "images"),
                        os.path.join("yolo_detect", "labels"), "labelme"):
                os.makedirs(out.folder / sub / s, exist_ok=True)
        os.makedirs(out.folder / "coco", exist_ok=True)
        _write_images(out.folder, images, found, bp, used, result, prog)
        _write_labels(out.folder, images, categories, result)
        for s in SPLITS:
            result.images[s] = sum(1 for x in images if x[0] == s)
            result.annotations[s] = sum(len(x[1].shapes) for x in images if x[0] == s)
        for s, im, _, _ in images:
            for sh in im.shapes:
                result.object_split[sh.instance] = s
        for s in SPLITS:
            result.objects[s] = sum(1 for v in result.object_split.values() if v == s)
        manifest = {
            "format": "easyidp-training-set", "version": 1,
            "pixels": "origin at the top-left corner of the image, x right, y down; the centre of "
                      "the top-left pixel is (0.5, 0.5) (COCO, YOLO and LabelMe alike)",
            "rules": {"min_visible": float(min_visible), "best_k": int(best_k),
                      "tile_size": tile_size, "tile_overlap": tile_overlap, "split": split,
                      "val_fraction": float(val_fraction), "region_size": float(region_size),
                      "seed": int(seed),
                      "hidden": "an object is labelled in a photo when at least min_visible of it "
                                "is in the frame and not hidden by the DSM; hidden parts of a kept "
                                "object are not cut out",
                      "tiles": "outlines clipped to the tile; a part smaller than min_visible of "
                               "the object's area in the photo is dropped",
                      "split_rule": "objects go to one split; images holding both are left out"},
            "categories": categories, "images": result.images, "annotations": result.annotations,
            "objects": result.objects, "left_out_images": result.left_out,
            "dropped_in_tiles": result.dropped_in_tiles, "object_split": result.object_split,
            "unseen": result.unseen, "skipped_photos": result.skipped_photos,
            "back_projection": bp.settings}
        if tile_size:
            tiles = {os.path.splitext(im.file_name)[0]: (label, im.attributes["photo_window"])
                     for _, im, label, _ in images}
            write_json(out.folder / TILE_INDEX, tile_index_document(tiles), indent=1)
            result.files.append(str(out.folder / TILE_INDEX))
        write_json(out.folder / MANIFEST, manifest, indent=1)
        result.files.append(str(out.folder / MANIFEST))
    result.files.sort()
    prog.set(100)
    return result


def _write_images(folder, images, found, bp, used, result, prog):
    """Whole photos copied (no decode); tiles cut from one decode per photo."""
    import imagecodecs
    by_label = {}
    for s, im, label, win in images:
        by_label.setdefault(label, []).append((s, im, win))

    def place(s, im, data_writer):
        main = folder / "images" / s / im.file_name
        data_writer(main)
        link = folder / "yolo_detect" / "images" / s / im.file_name
        with atomic_output(link) as tmp:
            try:
                os.link(main, tmp)
            except OSError:
                shutil.copyfile(main, tmp)
        result.files += [str(main), str(link)]

    labels = [lab for lab in (bp.photo_labels[j] for j in used) if lab in by_label]
    tiled = [lab for lab in labels if by_label[lab][0][2] is not None]
    for lab in labels:
        if lab in tiled:
            continue
        for s, im, _ in by_label[lab]:
            def copy(dst, src=found[lab]):
                with atomic_output(dst) as tmp:
                    shutil.copyfile(src, tmp)
            place(s, im, copy)
        prog.check()
    if not tiled:
        return
    sizes = [tuple(int(v) for v in bp.image_sizes[bp.photo_labels.index(lab)]) for lab in tiled]
    with DecodedPhotos([found[lab] for lab in tiled], sizes) as decoded:
        for k, img, why in decoded:
            lab = tiled[k]
            if img is None:
                result.skipped_photos[lab] = why
                continue
            for s, im, (r0, c0) in by_label[lab]:
                tile = np.ascontiguousarray(img[r0:r0 + im.height, c0:c0 + im.width])
                if tile.dtype != np.uint8:
                    raise InputError(f"Photo {lab}: tiles are written as 8-bit PNG, but the photo "
                                     f"is {tile.dtype}; export whole photos (tile size 0).")
                place(s, im, lambda dst: write_bytes(dst, imagecodecs.png_encode(tile, **PNG_FAST)))
            prog.set(65 + 30 * (k + 1) / len(tiled))


def _write_labels(folder, images, categories, result):
    index = {c: k for k, c in enumerate(categories)}
    present = [s for s in SPLITS]
    for s in SPLITS:
        ims = [im for sp, im, _, _ in images if sp == s]
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


__all__ = ["export_training_set", "TrainingSet", "point_discs", "tile_origins", "SPLIT_MODES"]
