"""ROIs from LabelMe polygons drawn on a georeferenced raster (an orthomosaic or DSM).

LabelMe pixels (origin at the image corner, as ours) go through the raster's geotransform to
map coordinates, in the raster's CRS — what EasyIDP's ``ROI.read_labelme_json`` does. Polygons,
rectangles and circles become ROIs named by their label; points and lines are refused.
"""
import os
from typing import Optional

import numpy as np

from ..annotations import read_labelme
from ..annotations.model import POLYGON
from ..errors import InputError
from .model import ROI, ROISet


def read_labelme_rois(path, raster=None, crs=None) -> ROISet:
    """ROIs from the LabelMe file ``path`` drawn on the GeoTIFF ``raster`` (a path or an opened
    :class:`~..raster.geotiff.GeoTiff`; default: the file's ``imagePath`` when it is a GeoTIFF).
    ``crs`` overrides the raster's CRS."""
    from ..raster.geotiff import GeoTiff, open_geotiff

    doc = read_labelme(path)
    if raster is None:
        raster = _image_raster(os.fspath(path), doc.image)
    tif = raster if isinstance(raster, GeoTiff) else open_geotiff(os.fspath(raster), crs=crs)
    if (doc.width, doc.height) != (None, None) and (doc.width, doc.height) != (tif.width, tif.height):
        raise InputError(f"{path} was drawn on a {doc.width} × {doc.height} image, but "
                         f"{tif.path} is {tif.width} × {tif.height}: give the raster the "
                         "polygons were drawn on.")
    rois = []
    for k, shape in enumerate(doc.shapes):
        if shape.kind != POLYGON:
            raise InputError(f"{path}: shape {k} ({shape.label!r}) is a {shape.source_type}, not "
                             "a polygon: ROIs must be polygons, rectangles or circles.")
        rings = [np.column_stack(tif.pixel_to_map(r[:, 0], r[:, 1])) for r in shape.rings]
        rois.append(ROI(shape.label, [rings], {"label": shape.label, **shape.attributes}))
    if not rois:
        raise InputError(f"{path} holds no shapes: it is empty.")
    return ROISet(rois, tif.crs if crs is None else crs)


def _image_raster(path: str, image: Optional[str]) -> str:
    cand = os.path.join(os.path.dirname(path), image) if image else None
    if cand and os.path.isfile(cand) and cand.lower().endswith((".tif", ".tiff")):
        return cand
    raise InputError(f"{path} holds LabelMe polygons in pixels: give the georeferenced raster they "
                     f"were drawn on (raster=…){'' if not image else f'; its image {image!r} is not a GeoTIFF beside it'}.")
