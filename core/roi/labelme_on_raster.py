"""ROIs from LabelMe polygons drawn on a georeferenced raster (an orthomosaic or DSM).

LabelMe pixels (origin at the image corner, as ours) go through the raster's geotransform to
map coordinates, in the raster's CRS — what EasyIDP's ``ROI.read_labelme_json`` does. Polygons,
rectangles and circles become ROIs named by their label; points and lines are refused. The
caller opens the raster (``core.raster.open_geotiff``): ROIs sit below the raster engine.
"""
import os
from typing import Optional

import numpy as np

from ..annotations import POLYGON, read_labelme
from ..errors import InputError
from .model import ROI, ROISet


def read_labelme_rois(path, raster, crs=None) -> ROISet:
    """ROIs from the LabelMe file ``path`` drawn on the georeferenced ``raster``, already open:
    any object with ``path``, ``width``, ``height``, ``crs`` and ``pixel_to_map(cols, rows)``,
    such as :class:`core.raster.GeoTiff` (``core.raster.open_geotiff(tif)``). ``crs`` overrides
    the raster's CRS."""
    doc = read_labelme(path)
    if raster is None or isinstance(raster, (str, os.PathLike)):
        raise InputError(_needs_raster(os.fspath(path), doc.image, raster))
    size = (doc.width, doc.height)
    if size != (None, None) and size != (raster.width, raster.height):
        raise InputError(f"{path} was drawn on a {doc.width} × {doc.height} image, but "
                         f"{raster.path} is {raster.width} × {raster.height}: give the raster the "
                         "polygons were drawn on.")
    rois = []
    for k, shape in enumerate(doc.shapes):
        if shape.kind != POLYGON:
            raise InputError(f"{path}: shape {k} ({shape.label!r}) is a {shape.source_type}, not "
                             "a polygon: ROIs must be polygons, rectangles or circles.")
        rings = [np.column_stack(raster.pixel_to_map(r[:, 0], r[:, 1])) for r in shape.rings]
        rois.append(ROI(shape.label, [rings], {"label": shape.label, **shape.attributes}))
    if not rois:
        raise InputError(f"{path} holds no shapes: it is empty.")
    return ROISet(rois, raster.crs if crs is None else crs)


def _needs_raster(path: str, image: Optional[str], given) -> str:
    """What to say when the raster is missing or given as a path (it must be opened)."""
    if given is not None:
        return (f"{path} holds LabelMe polygons in pixels: give the georeferenced raster they "
                f"were drawn on opened, raster=open_geotiff({os.fspath(given)!r}), not its path "
                "(easyidp_toolbox.core.open_rois opens a path itself).")
    cand = os.path.join(os.path.dirname(path), image) if image else None
    beside = cand and os.path.isfile(cand) and cand.lower().endswith((".tif", ".tiff"))
    return (f"{path} holds LabelMe polygons in pixels: give the georeferenced raster they were "
            f"drawn on (raster=open_geotiff(…))" + (
                f"; its image {image!r} is the GeoTIFF beside it" if beside else
                f"; its image {image!r} is not a GeoTIFF beside it" if image else "") + ".")
