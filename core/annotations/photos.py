"""Annotation files and folders → shapes per photo of a project.

:func:`read_annotations` recognises a LabelMe JSON file or folder, a COCO JSON file, or a YOLO
label file or folder, reads them with their reader, matches every image to a photo of the
project (by :func:`..photo_files.photo_key`: file name, any case, photo extension ignored: LabelMe ``imagePath`` or the JSON
file's own name, COCO ``file_name``, the YOLO file's stem) and checks the declared image size
against the camera's.
"""
import json
import os
from typing import Dict, List, Tuple

from ..errors import InputError
from ..photo_files import photo_key
from .coco import read_coco
from .labelme import read_labelme
from .model import PhotoAnnotations
from .tiles import read_tile_index
from .yolo import read_yolo, read_yolo_folder

FORMATS = ("labelme", "coco", "yolo")


def _stem(name: str) -> str:
    """The photo key of an annotated image name or of an annotation file's own name
    (``DJI_0018.json`` → ``dji_0018``): :func:`..photo_files.photo_key`."""
    key = photo_key(name)
    return os.path.splitext(key)[0] if key.endswith((".json", ".txt")) else key


class PhotoIndex:
    """The project's aligned photos by name: label, photo file name, their stems."""

    def __init__(self, recon):
        self.recon = recon
        self.by_name: Dict[str, object] = {}
        for cam in recon.cameras:
            for key in (cam.label, cam.photo_path):
                if key:
                    self.by_name.setdefault(_stem(key), cam)

    def find(self, name: str, source: str, alt: str = ""):
        """The camera of image ``name`` (or ``alt``, e.g. the JSON file's own name)."""
        for key in (name, alt):
            if key and _stem(key) in self.by_name:
                cam = self.by_name[_stem(key)]
                if not cam.aligned:
                    raise InputError(f"{source}: the photo {cam.label!r} is not aligned in the "
                                     "project, so it has no pose to project from.")
                return cam
        some = ", ".join(sorted(c.label for c in self.recon.aligned_cameras)[:5])
        raise InputError(f"{source}: the image {name or alt!r} is not a photo of the project "
                         f"{self.recon.label!r} (its photos are e.g. {some}). Check that the "
                         "annotations belong to this project, or rename the image.")


def detect_format(path) -> str:
    """'labelme', 'coco' or 'yolo' for a file or folder."""
    path = os.fspath(path)
    if os.path.isdir(path):
        names = [n.lower() for n in os.listdir(path)]
        if any(n.endswith(".json") for n in names):
            return "labelme"
        if any(n.endswith(".txt") and n != "classes.txt" for n in names):
            return "yolo"
        raise InputError(f"{path}: no LabelMe .json or YOLO .txt files in this folder.")
    if not os.path.isfile(path):
        raise InputError(f"Annotation file or folder not found: {path}")
    if path.lower().endswith(".txt"):
        return "yolo"
    try:
        with open(path, "rb") as fh:
            doc = json.loads(fh.read().decode("utf-8-sig"))
    except (ValueError, UnicodeDecodeError) as exc:
        raise InputError(f"{path} is neither valid JSON ({exc}) nor a YOLO .txt file.") from None
    if isinstance(doc, dict) and "shapes" in doc:
        return "labelme"
    if isinstance(doc, (dict, list)) and (isinstance(doc, list) or "images" in doc):
        return "coco"
    raise InputError(f"{path}: not a LabelMe file (no 'shapes') nor a COCO file (no 'images').")


def read_annotations(path, recon, dataset=None, tiles=None) -> List[Tuple[PhotoAnnotations, object]]:
    """(annotations, camera) for every annotated image of a LabelMe file or folder, a COCO
    file or a YOLO file or folder. ``dataset``: the COCO file a COCO *results* list refers to
    (:func:`.coco.read_coco`). ``tiles``: the tile index (``tiles.json``, or the training-set
    folder holding it) when the images are tiles of the photos: a YOLO or LabelMe file named
    after a tile is read at the tile's size and shifted into its photo's pixels
    (:mod:`.tiles`); COCO images carry their window themselves (``photo_window``), and a COCO
    image named after a tile without one is shifted the same way. Raises
    :class:`InputError` for an image that is not a photo of the project or whose declared size
    differs from its camera's."""
    path = os.fspath(path)
    fmt = detect_format(path)
    index = PhotoIndex(recon)
    tix = read_tile_index(tiles) if tiles is not None else None
    out = []
    if fmt == "labelme":
        files = [os.path.join(path, n) for n in sorted(os.listdir(path))
                 if n.lower().endswith(".json")] if os.path.isdir(path) else [path]
        for f in files:
            ann = read_labelme(f)
            if tix is not None:
                ann = tix.to_photo(ann, os.path.basename(f))
            out.append((ann, index.find(ann.image, f, os.path.basename(f))))
    elif fmt == "coco":
        for ann in read_coco(path, dataset):
            if tix is not None:
                ann = tix.to_photo(ann)
            out.append((ann, index.find(ann.image, path)))
    else:
        def size(stem):
            tile = tix.find(stem) if tix is not None else None
            if tile is not None:
                return tile[1][2], tile[1][3]
            cam = index.find(stem, os.path.join(path, stem + ".txt") if os.path.isdir(path) else path)
            s = recon.sensors[cam.sensor_id]
            return s.width, s.height
        anns = read_yolo_folder(path, size) if os.path.isdir(path) else \
            [read_yolo(path, size(_stem(path)))]
        if tix is not None:
            anns = [tix.to_photo(a) for a in anns]
        out = [(a, index.find(a.image, a.source)) for a in anns]
    for ann, cam in out:
        s = recon.sensors[cam.sensor_id]
        if (ann.width, ann.height) != (None, None) and (ann.width, ann.height) != (s.width, s.height):
            raise InputError(f"{ann.source}: the image {ann.image!r} is declared {ann.width}×"
                             f"{ann.height} px, but photo {cam.label!r} of the project is "
                             f"{s.width}×{s.height} px. Annotate the original photo (not a "
                             "resized copy), or rescale the annotations.")
    return out
