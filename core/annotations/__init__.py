"""Annotations drawn or detected on raw photos (pixel space): LabelMe, COCO and YOLO files.

Every reader returns :class:`PhotoAnnotations` with shapes in the project pixel convention
(origin at the image's top-left corner, x = column right, y = row down; the centre of the
top-left pixel is (0.5, 0.5)). :func:`read_annotations` reads a file or folder of any of them
and matches each image to a photo of a project.
"""
from .coco import read_coco
from .labelme import read_labelme
from .model import PhotoAnnotations, PhotoShape
from .photos import PhotoIndex, detect_format, read_annotations
from .yolo import read_yolo, read_yolo_folder

from .model import LINE, POINT, POLYGON
__all__ = ["PhotoAnnotations", "PhotoShape", "read_labelme", "read_coco", "read_yolo",
           "read_yolo_folder", "read_annotations", "detect_format", "PhotoIndex"]
__all__ += ["POLYGON", "LINE", "POINT"]
