"""Annotation files and folders → shapes per photo of a project.

:func:`read_annotations` recognises a LabelMe JSON file or folder, a COCO JSON file, or a YOLO
label file or folder, reads them with their reader, matches every image to a photo of the
project (by :func:`..photos.photo_key`: file name, any case, photo extension ignored: LabelMe ``imagePath`` or the JSON
file's own name, COCO ``file_name``, the YOLO file's stem) and checks the declared image size
against the camera's.
"""
import json
import os
import re
from typing import Dict, List, Optional, Tuple

from ..errors import InputError
from ..photos import photo_key
from .coco import read_coco
from .labelme import read_labelme
from .model import PhotoAnnotations
from .tiles import TILE_INDEX, read_tile_index
from .yolo import read_yolo, read_yolo_folder

FORMATS = ("labelme", "coco", "yolo")
TILE_NAME = re.compile(r"^(.+)_r\d+_c\d+$", re.IGNORECASE)   # a training set's tile: STEM_rROW_cCOL


def _stem(name: str) -> str:
    """The photo key of an annotated image name or of an annotation file's own name
    (``DJI_0018.json`` → ``dji_0018``): :func:`..photos.photo_key`."""
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
        hint = self.tile_hint(name or alt, source)
        raise InputError(f"{source}: the image {name or alt!r} is not a photo of the project "
                         f"{self.recon.label!r} (its photos are e.g. {some}). " + (hint or
                         "Check that the annotations belong to this project, or rename the image."))

    def tile_hint(self, name: str, source: str) -> Optional[str]:
        """For an image named like a tile of a photo of the project (``STEM_rROW_cCOL``, as a
        tiled training set names them), what to do: give the set's tile index (the
        ``tiles.json`` found beside ``source`` or up to two folders above it, when there is
        one); else None."""
        m = TILE_NAME.match(_stem(os.path.basename(str(name).replace("\\", "/"))))
        if not m or m.group(1) not in self.by_name:
            return None
        photo = self.by_name[m.group(1)].label
        found = None
        folder = os.path.dirname(os.path.abspath(source))
        for _ in range(3):
            if os.path.isfile(os.path.join(folder, TILE_INDEX)):
                found = os.path.join(folder, TILE_INDEX)
                break
            folder = os.path.dirname(folder)
        where = f" ({found})" if found else " (at the root of the training set)"
        return (f"It is named like a tile of photo {photo!r} (…_rROW_cCOL, as a tiled training "
                f"set names them): give the set's tile index {TILE_INDEX}{where} as the tile "
                "index (TILES), so that each tile's shapes are shifted back into its photo.")


def _labelme_photo_note(index: PhotoIndex, ann: PhotoAnnotations, path: str, cam) -> Optional[str]:
    """A sentence when a LabelMe file's ``imagePath`` and its own name point at different
    photos (``cam`` is the one used), else None."""
    own = _stem(os.path.basename(path))
    named = _stem(os.path.basename(ann.image.replace("\\", "/"))) if ann.image else ""
    if not named or named == own:
        return None
    if named in index.by_name:
        other = index.by_name.get(own)
        if other is None or other is cam:
            return None
        return (f"{path}: its imagePath {ann.image!r} names photo {cam.label!r}, its file name "
                f"photo {other.label!r}; its shapes were put on {cam.label!r}, the photo its "
                "imagePath names (LabelMe records there the image the shapes were drawn on). "
                "Rename the file, or correct imagePath, if that is not the photo.")
    return (f"{path}: its imagePath {ann.image!r} is not a photo of the project; its shapes "
            f"were put on {cam.label!r}, the photo its file name names.")


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


def read_annotations(path, recon, dataset=None, tiles=None,
                     notes: Optional[List[str]] = None) -> List[Tuple[PhotoAnnotations, object]]:
    """(annotations, camera) for every annotated image of a LabelMe file or folder, a COCO
    file or a YOLO file or folder. ``dataset``: the COCO file a COCO *results* list refers to
    (:func:`.coco.read_coco`). ``tiles``: the tile index (``tiles.json``, or the training-set
    folder holding it) when the images are tiles of the photos: a YOLO or LabelMe file named
    after a tile is read at the tile's size and shifted into its photo's pixels
    (:mod:`.tiles`); COCO images carry their window themselves (``photo_window``), and a COCO
    image named after a tile without one is shifted the same way. ``notes``: a list that gets
    a sentence for each LabelMe file whose ``imagePath`` and own file name name different
    photos, saying which photo was used and why. Raises
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
            cam = index.find(ann.image, f, os.path.basename(f))
            note = _labelme_photo_note(index, ann, f, cam)
            if note and notes is not None:
                notes.append(note)
            out.append((ann, cam))
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
