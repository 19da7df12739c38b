"""Shapes on one photo, in pixels, as the annotation readers return them."""
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np

from ..errors import InputError

POLYGON, LINE, POINT = "polygon", "line", "point"


@dataclass
class PhotoShape:
    """One annotated object on a photo.

    ``kind``: ``polygon`` (``rings`` = [exterior, hole, …], open (n, 2) rings), ``line`` (one
    open (n, 2) polyline) or ``point`` (one (1, 2) array). Pixels in the project convention.
    ``source_type``: the shape type as the file names it (e.g. LabelMe ``rectangle``).
    """
    label: str
    kind: str
    rings: List[np.ndarray]
    source_type: str = ""
    score: Optional[float] = None
    group_id: Optional[object] = None
    attributes: dict = field(default_factory=dict)


@dataclass
class PhotoAnnotations:
    """The shapes of one photo. ``image``: the image name or path as the file gives it;
    ``width``/``height``: the image size the file declares (None when it says nothing)."""
    source: str
    image: str
    width: Optional[int]
    height: Optional[int]
    shapes: List[PhotoShape] = field(default_factory=list)


def image_size(doc: dict, keys: Tuple[str, str], where: str) -> Tuple[Optional[int], Optional[int]]:
    """(width, height) an annotation file declares under ``keys`` (None where it says nothing);
    :class:`InputError` naming ``where`` for a size that is not a positive whole number."""
    out = []
    for key in keys:
        v = doc.get(key)
        if v is None:
            out.append(None)
            continue
        try:
            n = int(v)
        except (TypeError, ValueError):
            raise InputError(f"{where}: {key} is {v!r}, not a whole number of pixels.") from None
        if n <= 0:
            raise InputError(f"{where}: {key} is {n}; an image has a positive size.")
        out.append(n)
    return out[0], out[1]
