"""The real OpenDroneMap survey (realdata/orthority_odm) for the tests: ROIs where its photos
overlap, the cameras as OpenCV reads them straight from reconstruction.json (independent of our
readers), and the image-alignment measure of the two-view check."""
import itertools
import json
from pathlib import Path

import numpy as np

UTM51N = 32651
OFFSET = (292632.0, 2731169.0)        # reference_lla in UTM 51N (SOURCES.md), whole metres
PHOTOS = ("100_0005_0018", "100_0005_0136", "100_0005_0140", "100_0005_0142")
# one ROI centre per pair of photos that overlap (0018 and 0140 do not): the middle of the
# pair's common ground, found once from a grid of DSM points projected into both photos
PAIR_CENTRES = {
    ("100_0005_0018", "100_0005_0142"): (292785.0, 2731141.0),
    ("100_0005_0136", "100_0005_0142"): (292681.0, 2731069.0),
    ("100_0005_0140", "100_0005_0142"): (292657.0, 2731093.0),
    ("100_0005_0018", "100_0005_0136"): (292777.0, 2731037.0),
    ("100_0005_0136", "100_0005_0140"): (292665.0, 2730973.0),
}


def roi_name(pair) -> str:
    return "plot_" + "_".join(p[-4:] for p in pair)


def square(cx, cy, half):
    return [[cx - half, cy - half], [cx + half, cy - half], [cx + half, cy + half],
            [cx - half, cy + half], [cx - half, cy - half]]


def roi_set(half=8.0):
    """The five pair ROIs (squares of side 2·half m) as a core ROISet in UTM 51N."""
    from easyidp_toolbox.core.roi.model import ROISet, roi_from_coordinates
    return ROISet([roi_from_coordinates(roi_name(p), "Polygon", [square(*c, half)])
                   for p, c in PAIR_CENTRES.items()], f"EPSG:{UTM51N}")


def write_rois_geojson(path, half=8.0):
    feats = [{"type": "Feature", "properties": {"name": roi_name(p)},
              "geometry": {"type": "Polygon", "coordinates": [square(*c, half)]}}
             for p, c in PAIR_CENTRES.items()]
    Path(path).write_text(json.dumps({
        "type": "FeatureCollection", "features": feats,
        "crs": {"type": "name", "properties": {"name": f"urn:ogc:def:crs:EPSG::{UTM51N}"}}}))
    return Path(path)


class OpenCVCamera:
    """One shot of reconstruction.json as OpenCV takes it: rvec, tvec (world → camera, the
    file's own axis-angle and translation), K and D (OpenSfM brown: p1, p2 in OpenCV order;
    normalised by max(w, h) about the image centre, OpenCV pixel centres at integers)."""

    def __init__(self, folder, key):
        rec = json.loads((Path(folder) / "opensfm" / "reconstruction.json").read_text())[0]
        shot = rec["shots"][key]
        c = rec["cameras"][shot["camera"]]
        w, h = c["width"], c["height"]
        s = max(w, h)
        self.width, self.height = w, h
        self.rvec = np.array(shot["rotation"], float)
        self.tvec = np.array(shot["translation"], float)
        self.K = np.array([[c["focal_x"] * s, 0, w / 2 + c["c_x"] * s - 0.5],
                           [0, c["focal_y"] * s, h / 2 + c["c_y"] * s - 0.5], [0, 0, 1.0]])
        self.D = np.array([c["k1"], c["k2"], c["p1"], c["p2"], c["k3"]])

    def project(self, xyz_map, offset=OFFSET):
        """Map points (n, 3) in UTM 51N → our pixels (corner origin): subtract ODM's offset
        (the map frame of ODM's export) and project with cv2.projectPoints."""
        import cv2
        X = np.asarray(xyz_map, float) - [offset[0], offset[1], 0.0]
        uv, _ = cv2.projectPoints(X.reshape(-1, 1, 3), self.rvec, self.tvec, self.K, self.D)
        return uv.reshape(-1, 2) + 0.5


def dsm_bilinear(dsm_path, x, y):
    """Heights at map (x, y), bilinear between pixel centres (brute force, tifffile)."""
    import tifffile
    from easyidp_toolbox.core.raster.geotiff import open_geotiff
    g = open_geotiff(str(dsm_path))
    x0, dx, _, y0, _, dy = g.geotransform
    z = tifffile.imread(str(dsm_path)).astype(np.float64)
    c = (np.asarray(x) - x0) / dx - 0.5
    r = (np.asarray(y) - y0) / dy - 0.5
    c0, r0 = np.floor(c).astype(int), np.floor(r).astype(int)
    fc, fr = c - c0, r - r0
    return ((1 - fr) * ((1 - fc) * z[r0, c0] + fc * z[r0, c0 + 1])
            + fr * ((1 - fc) * z[r0 + 1, c0] + fc * z[r0 + 1, c0 + 1]))


# --- two views, one ground: how far two orthorectified images are apart ------------------------
def _apodised(a, mask):
    """Mean-free ``a`` faded to 0 outside ``mask`` (eroded, Gaussian edge) and by a Hann window:
    no step at the mask border or the frame for the Fourier transform to lock on to."""
    import cv2
    er = cv2.erode(mask.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(np.float64)
    ap = cv2.GaussianBlur(er, (0, 0), 1.5) * er
    win = cv2.createHanningWindow(a.shape[::-1], cv2.CV_64F)
    return (a - a[mask].mean()) * ap * win


def phase_shift(a, b, mask, rounds=6):
    """(dx, dy) in pixels (x right, y down) by which ``b``'s content is ``a``'s moved, by phase
    correlation (skimage, peak upsampled ×100) on the common ``mask``, repeated with ``b``
    shifted back by the running estimate (one pass underestimates sub-pixel shifts by about a
    quarter; the repeats converge, checked by construction in the test)."""
    from scipy.ndimage import shift as nd_shift
    from skimage.registration import phase_cross_correlation
    total = np.zeros(2)                                  # (dy, dx)
    fa = _apodised(a, mask)
    for _ in range(rounds):
        bb = nd_shift(b, -total, order=3, mode="nearest")
        s, _, _ = phase_cross_correlation(fa, _apodised(bb, mask), upsample_factor=100)
        total -= s
        if np.abs(s).max() < 0.005:
            break
    return float(total[1]), float(total[0])


def ncc(a, b, mask) -> float:
    return float(np.corrcoef(a[mask], b[mask])[0, 1])


def overlapping_pairs():
    return list(PAIR_CENTRES)


def all_pairs():
    return list(itertools.combinations(PHOTOS, 2))
