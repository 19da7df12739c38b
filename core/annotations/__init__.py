"""Annotations drawn or detected on raw photos (pixel space): LabelMe files.

Every reader returns :class:`PhotoAnnotations` with shapes in the project pixel convention
(origin at the image's top-left corner, x = column right, y = row down; the centre of the
top-left pixel is (0.5, 0.5)).
"""
from .labelme import read_labelme
from .model import PhotoAnnotations, PhotoShape

__all__ = ["PhotoAnnotations", "PhotoShape", "read_labelme"]
