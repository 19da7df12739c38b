"""Small synthetic GeoTIFFs for tests, written with tifffile (not with the code under test)."""
import numpy as np
import tifffile

UTM54 = 32654


def geokeys(epsg=UTM54, geographic=False, pixel_is_point=False):
    return (1, 1, 0, 3, 1024, 0, 1, 2 if geographic else 1, 1025, 0, 1, 2 if pixel_is_point else 1,
            2048 if geographic else 3072, 0, 1, epsg)


def write_tif(path, data, origin=(368000.0, 3956000.0), pixel=0.5, epsg=UTM54, nodata=None,
              tile=None, rowsperstrip=None, photometric=None, extrasamples=None,
              transformation=None, georef=True, pixel_is_point=False, compression="zlib"):
    """Write ``data`` (rows, cols[, bands]) as a GeoTIFF with origin = top-left corner (x, y)."""
    tags = []
    if georef and transformation is None:
        tags += [(33550, "d", 3, (pixel, pixel, 0.0), True),
                 (33922, "d", 6, (0, 0, 0, origin[0], origin[1], 0), True)]
    if transformation is not None:
        tags.append((34264, "d", 16, tuple(np.asarray(transformation, float).ravel()), True))
    if georef:
        tags.append((34735, "H", 16, geokeys(epsg, epsg == 4326, pixel_is_point), True))
    if nodata is not None:
        tags.append((42113, "s", 0, str(nodata), True))
    kw = {"tile": (tile, tile)} if tile else {"rowsperstrip": rowsperstrip or 16}
    if photometric is None:
        photometric = "rgb" if data.ndim == 3 and data.shape[2] in (3, 4) and data.dtype == np.uint8 \
            else "minisblack"
    tifffile.imwrite(path, data, photometric=photometric, planarconfig="contig",
                     extrasamples=extrasamples, compression=compression, extratags=tags,
                     metadata=None, **kw)
    return path


def rect(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], float)
