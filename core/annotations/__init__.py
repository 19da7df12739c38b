"""Annotations drawn or detected on raw photos (pixel space): LabelMe, COCO and YOLO files,
read (:func:`read_annotations`) and written (:mod:`.writers`, for training sets).

Every reader returns :class:`PhotoAnnotations` with shapes in the project pixel convention
(origin at the image's top-left corner, x = column right, y = row down; the centre of the
top-left pixel is (0.5, 0.5)). :func:`read_annotations` reads a file or folder of any of them
and matches each image to a photo of a project; tiles of photos are mapped back to the photo
by the tile index a tiled training set writes (:mod:`.tiles`).
"""
from .coco import read_coco
from .labelme import read_labelme
from .model import LINE, POINT, POLYGON, PhotoAnnotations, PhotoShape
from .matching import PhotoIndex, detect_format, read_annotations
from .tiles import TILE_INDEX, TileIndex, read_tile_index, tile_index_document
from .writers import (LabelledImage, LabelledShape, write_coco, write_labelme, write_yolo_labels,
                      yolo_data_yaml)
from .yolo import read_yolo, read_yolo_folder

__all__ = ["PhotoAnnotations", "PhotoShape", "POLYGON", "LINE", "POINT", "read_labelme",
           "read_coco", "read_yolo", "read_yolo_folder", "read_annotations", "detect_format",
           "PhotoIndex", "LabelledImage", "LabelledShape", "write_coco", "write_labelme",
           "write_yolo_labels", "yolo_data_yaml", "TILE_INDEX", "TileIndex", "read_tile_index",
           "tile_index_document"]
