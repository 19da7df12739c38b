"""Writing cropped GeoTIFFs: georeferencing copied from the source, deflate-compressed, atomic."""
from typing import Callable, Iterator, Optional, Sequence

import numpy as np
from pyproj import CRS

from ..errors import Cancelled
from ..files import atomic_output

from .geotiff import (TAG_GDAL_METADATA, TAG_GDAL_NODATA, TAG_GEOASCII, TAG_GEODOUBLES, TAG_GEOKEYS,
                      TAG_PIXEL_SCALE, TAG_TIEPOINT)

# Deflate level 1 with the horizontal (integers) or floating-point predictor: on orthomosaic crops
# both faster and smaller than level 6 without a predictor (GDAL's default).
DEFLATE_LEVEL = 1


def epsg_geo_tags(epsg: int) -> dict:
    """Minimal GeoKey tags for an EPSG CRS (projected or geographic), pixel-is-area."""
    geographic = CRS.from_epsg(epsg).is_geographic
    keys = [1, 1, 0, 3,
            1024, 0, 1, 2 if geographic else 1,          # GTModelTypeGeoKey
            1025, 0, 1, 1,                               # GTRasterTypeGeoKey: PixelIsArea
            2048 if geographic else 3072, 0, 1, epsg]    # Geographic/ProjectedCSTypeGeoKey
    return {TAG_GEOKEYS: tuple(keys)}


def geotiff_tags(geo_tags: dict, geotransform, nodata_text: Optional[str]) -> list:
    """tifffile ``extratags``: a north-up geotransform, GeoKey tags (as read by
    :func:`open_geotiff` into ``GeoTiff.geo_tags``, or from :func:`epsg_geo_tags`) and nodata."""
    c, a, _, f, _, e = geotransform
    tags = [(TAG_PIXEL_SCALE, "d", 3, (a, -e, 0.0), True),
            (TAG_TIEPOINT, "d", 6, (0.0, 0.0, 0.0, c, f, 0.0), True)]
    g = geo_tags
    if TAG_GEOKEYS in g:
        keys = list(g[TAG_GEOKEYS])
        # the crop is always PixelIsArea: the source's half-pixel shift is already in the geotransform
        for k in range(4, len(keys), 4):
            if keys[k] == 1025:  # GTRasterTypeGeoKey
                keys[k + 3] = 1
        tags.append((TAG_GEOKEYS, "H", len(keys), keys, True))
    if TAG_GEODOUBLES in g:
        tags.append((TAG_GEODOUBLES, "d", len(g[TAG_GEODOUBLES]), g[TAG_GEODOUBLES], True))
    if TAG_GEOASCII in g:
        tags.append((TAG_GEOASCII, "s", 0, g[TAG_GEOASCII], True))
    if TAG_GDAL_METADATA in g:
        tags.append((TAG_GDAL_METADATA, "s", 0, g[TAG_GDAL_METADATA], True))
    if nodata_text is not None:
        tags.append((TAG_GDAL_NODATA, "s", 0, nodata_text, True))
    return tags


def write_geotiff(path: str, data: np.ndarray, geotransform, geo_tags: dict,
                  nodata_text: Optional[str] = None, rgb: bool = False,
                  extrasamples: Sequence[int] = (), tile: Optional[int] = None,
                  rowsperstrip: Optional[int] = None,
                  is_cancelled: Optional[Callable[[], bool]] = None) -> str:
    """Write ``data`` (rows, cols[, bands]) to ``path`` atomically (:func:`..files.atomic_output`).

    ``geotransform`` in GDAL order (north-up); ``rgb``: photometric RGB (the first three
    bands), else min-is-black; ``extrasamples``: TIFF ExtraSamples codes of the bands after the
    colour bands (2 = unassociated alpha). Layout: ``tile`` (square tiles of that size), or
    ``rowsperstrip``, or by default strips of about 64 KiB (tiles of 256 above 1 Mpixel).
    ``is_cancelled`` is polled between tiles: a cancel stops a large write within a tile's time,
    removes the temporary file and raises :class:`~..errors.Cancelled`.
    """
    import tifffile                 # optional (raster tools): core imports without it
    if data.ndim == 2:
        data = data[..., None]
    rows, cols, bands = data.shape
    if tile is None and rowsperstrip is None and rows * cols > 1024 * 1024:
        tile = 256
    if tile:
        kw = {"tile": (tile, tile)}
        body = _tiles(data, tile, is_cancelled)      # tile by tile: cancel stays responsive
    else:                                             # strips: small images, written at once
        kw = {"rowsperstrip": rowsperstrip or
              max(1, 65536 // max(1, cols * bands * data.dtype.itemsize))}
        body = data if bands > 1 else data[..., 0]
    with atomic_output(path) as tmp:
        tifffile.imwrite(
            tmp, body, shape=(rows, cols, bands) if bands > 1 else (rows, cols), dtype=data.dtype,
            photometric="rgb" if rgb else "minisblack", planarconfig="contig",
            extrasamples=tuple(extrasamples) or None,
            compression="zlib", compressionargs={"level": DEFLATE_LEVEL}, predictor=True,
            extratags=geotiff_tags(geo_tags, geotransform, nodata_text), metadata=None, **kw)
    return path


def _tiles(data: np.ndarray, tile: int, is_cancelled) -> Iterator[np.ndarray]:
    """The (tile, tile[, bands]) tiles of ``data`` in row-major order, zero-padded at the edges."""
    rows, cols, bands = data.shape
    for r in range(0, rows, tile):
        for c in range(0, cols, tile):
            if is_cancelled is not None and is_cancelled():
                raise Cancelled("Cancelled by the user.")
            part = data[r:r + tile, c:c + tile]
            if part.shape[:2] != (tile, tile):
                pad = np.zeros((tile, tile, bands), data.dtype)
                pad[:part.shape[0], :part.shape[1]] = part
                part = pad
            yield part if bands > 1 else part[..., 0]
