"""Tiles of photos: where each tile of a training set sits in its photo.

:func:`core.projection.training_set.export_training_set` cuts photos into tiles and writes
their offsets to ``tiles.json`` at the set's root (:data:`TILE_INDEX`)::

    {"format": "easyidp-tiles", "version": 1,
     "tiles": {"DJI_0001_r00000_c00512": {"photo": "DJI_0001", "window": [512, 0, 640, 640]}}}

keyed by the tile's file stem (the image, its YOLO label file and its LabelMe file share it);
``window`` is [x0, y0, width, height] in the photo's pixels (project convention: origin at the
photo's top-left corner). A shape on a tile is on the photo at (x + x0, y + y0). Detections a
model makes on the tiles (YOLO label files named after the tiles, LabelMe files) are brought
back to the photo with :func:`TileIndex.to_photo` before forward projection.
"""
import os
from dataclasses import dataclass
from typing import Dict, Optional, Tuple

import numpy as np

from ..errors import InputError
from ..files import load_json
from ..photos import photo_key
from .model import PhotoAnnotations

TILE_INDEX = "tiles.json"
TILE_FORMAT = "easyidp-tiles"


def tile_index_document(tiles: Dict[str, Tuple[str, Tuple[int, int, int, int]]]) -> dict:
    """The ``tiles.json`` document of {tile stem: (photo label, (x0, y0, width, height))}."""
    return {"format": TILE_FORMAT, "version": 1,
            "pixels": "window = [x0, y0, width, height] of the tile in its photo's pixels (origin "
                      "at the photo's top-left corner); a tile pixel (x, y) is the photo's "
                      "(x + x0, y + y0)",
            "tiles": {stem: {"photo": p, "window": [int(v) for v in w]}
                      for stem, (p, w) in sorted(tiles.items())}}


def _key(name: str) -> str:
    """A tile's stem from an image name, a label file's name or a path, any case."""
    key = photo_key(os.path.basename(str(name).replace("\\", "/")))
    stem, ext = os.path.splitext(key)
    return stem if ext else key


@dataclass
class TileIndex:
    """{tile stem (lower case): (photo label, (x0, y0, width, height))} from ``tiles.json``."""
    source: str
    tiles: Dict[str, Tuple[str, Tuple[int, int, int, int]]]

    def find(self, *names: str) -> Optional[Tuple[str, Tuple[int, int, int, int]]]:
        """(photo, window) of the first of ``names`` (image names or label file paths) that is
        a tile of the index; None when none is."""
        for n in names:
            if n and _key(n) in self.tiles:
                return self.tiles[_key(n)]
        return None

    def to_photo(self, ann: PhotoAnnotations, *names: str) -> PhotoAnnotations:
        """``ann`` moved from its tile to its photo (shapes shifted by the window's corner, the
        image named after the photo, no declared size) when its image, or one of ``names``,
        is a tile of the index; else ``ann`` unchanged. A declared size that is not the
        tile's raises :class:`InputError`."""
        hit = self.find(ann.image, *names)
        if hit is None:
            return ann
        photo, (x0, y0, w, h) = hit
        if (ann.width, ann.height) not in ((None, None), (w, h)):
            raise InputError(f"{ann.source}: the image is declared {ann.width}×{ann.height} px, "
                             f"but tile {_key(ann.image or names[0])!r} of {self.source} is "
                             f"{w}×{h} px. Give the tile index of the set these tiles come from.")
        off = np.array([x0, y0], np.float64)
        for s in ann.shapes:
            s.rings = [np.asarray(r, np.float64) + off for r in s.rings]
            s.attributes = {**s.attributes, "tile": _key(ann.image or names[0])}
        return PhotoAnnotations(ann.source, photo, None, None, ann.shapes)


def read_tile_index(path) -> TileIndex:
    """The :class:`TileIndex` of a ``tiles.json`` file, or of the training-set folder that
    holds one. :class:`InputError` naming the file when it is not one."""
    path = os.fspath(path)
    if os.path.isdir(path):
        path = os.path.join(path, TILE_INDEX)
    if not os.path.isfile(path):
        raise InputError(f"Tile index not found: {path}. A training set exported as tiles has "
                         f"{TILE_INDEX} at its root; whole photos need no tile index.")
    doc = load_json(path, "tile index")
    if not isinstance(doc, dict) or doc.get("format") != TILE_FORMAT or \
            not isinstance(doc.get("tiles"), dict):
        raise InputError(f"{path} is not a tile index (format {TILE_FORMAT!r} with 'tiles').")
    tiles = {}
    for stem, t in doc["tiles"].items():
        win = t.get("window") if isinstance(t, dict) else None
        if not isinstance(win, list) or len(win) != 4 or not t.get("photo"):
            raise InputError(f"{path}: tile {stem!r} needs 'photo' and 'window' [x0, y0, w, h].")
        try:
            x0, y0, w, h = (int(v) for v in win)
        except (TypeError, ValueError):
            raise InputError(f"{path}: tile {stem!r}: window {win!r} is not whole pixels.") from None
        if w <= 0 or h <= 0:
            raise InputError(f"{path}: tile {stem!r}: a window of {w}×{h} px.")
        tiles[_key(stem)] = (str(t["photo"]), (x0, y0, w, h))
    return TileIndex(path, tiles)


__all__ = ["TILE_INDEX", "TileIndex", "read_tile_index", "tile_index_document"]
