"""GeoTIFF metadata and segment (tile or strip) decoding, with tifffile.

Georeferencing follows GDAL: the affine geotransform ``(c, a, b, f, d, e)`` maps the pixel
*corner* (col, row) to map coordinates ``x = c + a*col + b*row``, ``y = f + d*col + e*row``;
pixel (0, 0) is the top-left corner of the top-left pixel, its centre is (0.5, 0.5).
Rotated geotransforms (b or d non-zero) are refused with a clear message.
"""
import logging
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Tuple

import numpy as np
from pyproj import CRS

from ..crs import as_crs
from ..errors import InputError

# GeoTIFF and GDAL private tags
TAG_PIXEL_SCALE = 33550
TAG_TIEPOINT = 33922
TAG_TRANSFORMATION = 34264
TAG_GEOKEYS = 34735
TAG_GEODOUBLES = 34736
TAG_GEOASCII = 34737
TAG_GDAL_METADATA = 42112
TAG_GDAL_NODATA = 42113

EXTRASAMPLE_ALPHA = (1, 2)  # associated, unassociated
PHOTOMETRIC_RGB, PHOTOMETRIC_YCBCR = 2, 6


@dataclass
class GeoTiff:
    """What the engine needs to know about one GeoTIFF (first IFD). Open files via :func:`open_geotiff`."""

    path: str
    width: int
    height: int
    bands: int
    dtype: np.dtype
    geotransform: Tuple[float, float, float, float, float, float]  # GDAL order (c, a, b, f, d, e)
    crs: Optional[CRS]
    nodata: Optional[float]
    nodata_text: Optional[str]
    alpha_band: Optional[int]          # 0-based band index of an alpha extra sample
    photometric: int
    planar_separate: bool
    tiled: bool
    block_height: int                  # tile height, or rows per strip
    block_width: int                   # tile width, or image width for strips
    compression: str
    geo_tags: Dict[int, tuple] = field(default_factory=dict)  # raw GeoKey tags to copy to outputs
    notes: List[str] = field(default_factory=list)  # problems met while reading (e.g. the CRS)
    _page: object = field(default=None, repr=False)

    # ---- layout -----------------------------------------------------------------------------
    @property
    def blocks_down(self) -> int:
        return -(-self.height // self.block_height)

    @property
    def blocks_across(self) -> int:
        return -(-self.width // self.block_width)

    @property
    def kind(self) -> str:
        """'rgb', 'rgba', 'single' (DSM and other one-band rasters) or 'multiband'. JPEG YCbCr
        rasters are decoded to RGB (as GDAL does), so they are 'rgb' too."""
        if self.alpha_band is not None:
            return "rgba"
        if self.bands == 3 and self.photometric in (PHOTOMETRIC_RGB, PHOTOMETRIC_YCBCR) and \
                self.dtype == np.uint8:
            return "rgb"
        return "single" if self.bands == 1 else "multiband"

    @property
    def is_colour(self) -> bool:
        """Whether the first three bands are red, green and blue (photometric RGB, or JPEG
        YCbCr decoded to RGB), whatever their sample type: a 16-bit or float RGB orthomosaic is
        colour too, while :attr:`kind` is 'rgb' for 8-bit only (crops add an 8-bit alpha). Three
        bands, or four with an alpha extra sample: RGB photometric with more bands (a
        multispectral stack) is not taken for colour."""
        return self.bands - (self.alpha_band is not None) == 3 and \
            self.photometric in (PHOTOMETRIC_RGB, PHOTOMETRIC_YCBCR)

    # ---- pixel <-> map ----------------------------------------------------------------------
    def pixel_to_map(self, col, row):
        """Map (x, y) of pixel coordinates (col, row); (0.5, 0.5) is the first pixel's centre."""
        c, a, _, f, _, e = self.geotransform
        return c + a * np.asarray(col, float), f + e * np.asarray(row, float)

    def map_to_pixel(self, x, y):
        """Pixel coordinates (col, row), float, corner origin, of map points (x, y)."""
        c, a, _, f, _, e = self.geotransform
        return (np.asarray(x, float) - c) / a, (np.asarray(y, float) - f) / e

    def window_geotransform(self, row0: int, col0: int):
        """Geotransform of a crop whose top-left pixel is (row0, col0) of this raster."""
        c, a, b, f, d, e = self.geotransform
        return (c + a * col0, a, b, f + e * row0, d, e)

    # ---- data -------------------------------------------------------------------------------
    def block_index(self, block_row: int, block_col: int, band: int = 0) -> int:
        per_band = self.blocks_down * self.blocks_across
        return (band * per_band if self.planar_separate else 0) + block_row * self.blocks_across + block_col

    def read_block(self, fd: int, block_row: int, block_col: int) -> np.ndarray:
        """Decode one tile or strip: array (rows, cols, bands), clipped to the image edge.

        ``fd`` is an ``os.open`` descriptor of :attr:`path` (``os.pread`` is thread-safe).
        """
        page = self._page
        bands = range(self.bands) if self.planar_separate else (0,)
        parts = []
        for band in bands:
            index = int(self.block_index(block_row, block_col, band))
            offset, count = page.dataoffsets[index], page.databytecounts[index]
            data = os.pread(fd, count, offset) if count else b""
            if count and len(data) < count:
                raise InputError(f"{self.path} is truncated: block {index} ends past the end of the "
                                 "file. Re-export or re-download the raster.")
            try:
                seg, _, shape = page.decode(data or None, index, jpegtables=page.jpegtables)
                if seg is None:  # sparse block: GDAL reads it as nodata (or 0)
                    fill = self.nodata if self.nodata is not None else 0
                    seg = np.full(shape, fill, dtype=self.dtype)
                parts.append(seg.reshape(seg.shape[-3:]))
            except Exception as exc:
                raise InputError(f"{self.path} is corrupt: block {index} cannot be decoded "
                                 f"({type(exc).__name__}: {exc}). Re-export the raster.") from None
        block = parts[0] if len(parts) == 1 else np.concatenate(parts, axis=-1)
        r0, c0 = block_row * self.block_height, block_col * self.block_width
        rows, cols = min(self.block_height, self.height - r0), min(self.block_width, self.width - c0)
        if block.shape[0] < rows or block.shape[1] < cols or block.shape[2] != self.bands:
            raise InputError(f"{self.path} is corrupt: block {index} decodes to "
                             f"{block.shape[1]} × {block.shape[0]} × {block.shape[2]} values where "
                             f"{cols} × {rows} × {self.bands} are declared. Re-export the raster.")
        return block[:rows, :cols]


def open_geotiff(path: str, crs=None) -> GeoTiff:
    """Read the metadata of a GeoTIFF. ``crs`` (anything pyproj accepts) overrides the GeoKeys.

    Raises :class:`InputError` for a missing file, a file that is not a TIFF, a TIFF without
    georeferencing, or a rotated geotransform.
    """
    import tifffile                 # optional (raster tools): core imports without it
    if not os.path.isfile(path):
        raise InputError(f"Raster not found: {path}")
    log = logging.getLogger("tifffile")
    level = log.level
    log.setLevel(logging.CRITICAL)  # tifffile logs what it cannot parse; we raise or note it
    try:
        try:
            tif = tifffile.TiffFile(path)
            page = tif.pages.first if hasattr(tif.pages, "first") else tif.pages[0]
            tags = page.tags
        except Exception as exc:
            raise InputError(f"{path} is not a readable GeoTIFF ({type(exc).__name__}: {exc}). "
                             "Convert it with gdal_translate (QGIS: Raster ▸ Conversion ▸ "
                             "Translate) to GeoTIFF.") from None
        try:
            info = _metadata(path, tif, page, tags, crs)
        except InputError:
            raise
        except Exception as exc:       # a damaged tag: name the file, never a numpy traceback
            raise InputError(f"{path} is damaged: its TIFF tags cannot be read "
                             f"({type(exc).__name__}: {exc}). Re-export the raster.") from None
        finally:
            tif.close()
    finally:
        log.setLevel(level)
    _check_layout(info, page)
    return info


def _metadata(path: str, tif, page, tags, crs) -> "GeoTiff":
    geo_tags = {code: tags[code].value for code in
                (TAG_GEOKEYS, TAG_GEODOUBLES, TAG_GEOASCII, TAG_GDAL_METADATA) if code in tags}
    notes: List[str] = []
    geokeys = _geokeys(tif, page, path, notes)
    gt = _geotransform(path, tags, geokeys)
    nodata_text = tags[TAG_GDAL_NODATA].value.strip("\x00 ") if TAG_GDAL_NODATA in tags else None
    nodata = _parse_nodata(nodata_text, page.dtype)
    extras = tuple(int(v) for v in (page.extrasamples or ()))
    alpha = None
    if extras and extras[-1] in EXTRASAMPLE_ALPHA:
        alpha = page.samplesperpixel - 1
    if crs is not None:
        crs = as_crs(crs, f"CRS of {path}")
    else:
        crs, problem = crs_from_geokeys(geokeys)
        if problem:
            notes.append(f"{path}: {problem}; it is treated as having no CRS. Give the raster's "
                         "CRS (in QGIS: set the layer's CRS).")
    if page.imagedepth > 1:
        raise InputError(f"{path} is a volumetric TIFF; only 2-D rasters are supported.")
    if page.dtype is None or min(page.imagewidth, page.imagelength) < 1:
        raise InputError(f"{path} is damaged: it declares a {page.imagewidth} × {page.imagelength} "
                         "image without a pixel type. Re-export the raster.")
    tiled = bool(page.is_tiled)
    bh = int(page.tilelength if tiled else min(page.rowsperstrip or page.imagelength, page.imagelength))
    bw = int(page.tilewidth if tiled else page.imagewidth)
    if bh < 1 or bw < 1:
        raise InputError(f"{path} is damaged: it declares blocks of {bw} × {bh} pixels.")
    info = GeoTiff(
        path=path, width=int(page.imagewidth), height=int(page.imagelength),
        bands=int(page.samplesperpixel), dtype=np.dtype(page.dtype), geotransform=gt, crs=crs,
        nodata=nodata, nodata_text=nodata_text, alpha_band=alpha, photometric=int(page.photometric),
        planar_separate=int(page.planarconfig) == 2 and page.samplesperpixel > 1,
        tiled=tiled, block_height=bh, block_width=bw,
        compression=page.compression.name if hasattr(page.compression, "name") else str(page.compression),
        geo_tags=geo_tags, notes=notes, _page=page,
    )
    page.decode  # noqa: B018 (build the decoder while the file is open; blocks are read via os.pread)
    if info.photometric == PHOTOMETRIC_YCBCR and info.compression.upper() not in ("JPEG", "7"):
        raise InputError(f"{path} stores YCbCr colours without JPEG compression, which is not "
                         "supported. Convert it to RGB (gdal_translate -co PHOTOMETRIC=RGB).")
    return info


MAX_BLOCK_BYTES = 512 * 2**20
"""The largest decoded tile or strip the engine accepts (it decodes whole blocks)."""


def _check_layout(tif: "GeoTiff", page) -> None:
    """Refuse declared sizes that the file cannot hold or the sweep cannot decode in bounded
    memory, before anything is allocated by them."""
    path = tif.path
    per_band = 1 if tif.planar_separate else tif.bands
    block = tif.block_height * tif.block_width * per_band * tif.dtype.itemsize
    if block > MAX_BLOCK_BYTES:
        raise InputError(
            f"{path} declares {'tiles' if tif.tiled else 'strips'} of {tif.block_width} × "
            f"{tif.block_height} pixels ({block / 2**30:.1f} GiB each, decoded whole). Re-save it "
            "tiled (gdal_translate -co TILED=YES, or QGIS: Raster ▸ Conversion ▸ Translate with "
            "TILED=YES) and run again.")
    n = tif.blocks_down * tif.blocks_across * (tif.bands if tif.planar_separate else 1)
    offsets, counts = page.dataoffsets, page.databytecounts
    if len(offsets) != n or len(counts) != n:
        raise InputError(f"{path} is damaged: its {tif.width} × {tif.height} pixels need {n} "
                         f"blocks but it lists {len(offsets)}. Re-export the raster.")
    size = os.path.getsize(path)
    ends = np.asarray(offsets, np.int64) + np.asarray(counts, np.int64)
    if len(ends) and int(ends.max()) > size:
        raise InputError(f"{path} is truncated: its blocks end {int(ends.max()):,} bytes into a "
                         f"file of {size:,} bytes. Re-export or re-download the raster.")
    pixels = tif.width * tif.height * tif.bands * tif.dtype.itemsize
    if tif.compression.upper() in ("NONE", "1") and int(np.sum(counts)) < pixels:
        raise InputError(f"{path} is damaged: it declares {tif.width} × {tif.height} uncompressed "
                         f"pixels ({pixels:,} bytes) but holds {int(np.sum(counts)):,} bytes of "
                         "them. Re-export the raster.")


def _geokeys(tif, page, path: str, notes: List[str]) -> dict:
    """The parsed GeoKeys of the first page; a parse failure is noted, not raised (the
    geotransform comes from other tags and may still be usable)."""
    try:
        return dict(tif.geotiff_metadata or {}) if page.index == 0 else {}
    except Exception as exc:
        notes.append(f"{path}: its GeoKeys cannot be parsed ({type(exc).__name__}: {exc})")
        return {}


def _geotransform(path, tags, geokeys):
    if TAG_TRANSFORMATION in tags:
        m = np.asarray(tags[TAG_TRANSFORMATION].value, float).reshape(4, 4)
        a, b, c, d, e, f = m[0, 0], m[0, 1], m[0, 3], m[1, 0], m[1, 1], m[1, 3]
    elif TAG_PIXEL_SCALE in tags and TAG_TIEPOINT in tags:
        sx, sy = tags[TAG_PIXEL_SCALE].value[:2]
        tp = tags[TAG_TIEPOINT].value
        if len(tp) > 6:
            raise InputError(f"{path} is georeferenced by {len(tp) // 6} ground control points, not "
                             "a geotransform. Warp it first (QGIS: Raster ▸ Projections ▸ Warp).")
        i, j, x, y = tp[0], tp[1], tp[3], tp[4]
        a, b, d, e = sx, 0.0, 0.0, -sy
        c, f = x - i * sx, y + j * sy
    else:
        raise InputError(f"{path} has no georeferencing (no GeoTIFF ModelTiepoint/ModelPixelScale or "
                         "ModelTransformation tags). Georeference it first (QGIS: Raster ▸ "
                         "Georeferencer) or assign a world file with gdal_translate.")
    if b != 0.0 or d != 0.0:
        raise InputError(f"{path} has a rotated geotransform (rotation terms {b:g}, {d:g}); rotated "
                         "rasters are not supported. Warp it north-up first (QGIS: Raster ▸ "
                         "Projections ▸ Warp, or gdalwarp).")
    if a == 0.0 or e == 0.0:
        raise InputError(f"{path} has a zero pixel size in its georeferencing.")
    if int(geokeys.get("GTRasterTypeGeoKey", 1)) == 2:  # PixelIsPoint: GDAL shifts by half a pixel
        c, f = c - a / 2, f - e / 2
    return (float(c), float(a), float(b), float(f), float(d), float(e))


def _parse_nodata(text: Optional[str], dtype) -> Optional[float]:
    if not text:
        return None
    try:
        value = float(text)
    except ValueError:
        return None
    if np.dtype(dtype).kind == "f":
        return float(np.asarray(value).astype(dtype))  # e.g. 3.4028234663852886e+38 → float32 max
    return value


def crs_from_geokeys(keys: dict) -> Tuple[Optional[CRS], Optional[str]]:
    """(pyproj CRS, problem) from parsed GeoKeys: EPSG projected/geographic codes, or an ESRI PE
    string. ``problem`` says why GeoKeys that declare a CRS could not be turned into one (None
    when there was no CRS to read, or it was read)."""
    problem = None
    for key in ("ProjectedCSTypeGeoKey", "GeographicTypeGeoKey"):
        code = keys.get(key)
        if code is None:
            continue
        try:
            if 1024 <= int(code) < 32767:
                return CRS.from_epsg(int(code)), None
        except Exception as exc:
            problem = f"its {key} {code} is not a CRS PROJ knows ({exc})"
    for key in ("PCSCitationGeoKey", "GTCitationGeoKey", "GeogCitationGeoKey"):
        text = str(keys.get(key, ""))
        if "ESRI PE String = " in text:
            try:
                return CRS.from_wkt(text.split("ESRI PE String = ", 1)[1]), None
            except Exception as exc:
                problem = f"the ESRI PE string of its {key} cannot be read ({exc})"
    if problem is None and any(int(keys.get(k) or 0) == 32767 for k in
                               ("ProjectedCSTypeGeoKey", "GeographicTypeGeoKey")):
        problem = "its CRS is user-defined in the GeoKeys, which this reader cannot decode"
    return None, problem
