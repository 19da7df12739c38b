"""A plot trial of row crops tall enough to hide the soil between their rows in oblique views,
built from boxes, with its own geometry for truths (no ``easyidp_toolbox.core`` code).

The world (map = local + OFFSET, metres, UTM 54N): 4 × 3 plots of 2 m × 3 m with 1 m alleys;
each plot has 4 rows along y (0.15 m wide, 0.5 m apart, ``ROW_HEIGHT`` tall; one plot with a
lower, uneven row), weeds (small boxes) in some plots and alleys, a margin of grass tufts, and
an 8 m tall shed east of the trial that hides plots from the eastern cameras. Seven pinhole
cameras look at the trial: six around it at about 40° off nadir, one at nadir.

The truth is analytic: rays against the boxes (a slab test written here), cameras projected with
the pinhole formula written here. The DSM is the boxes rasterised at 2 cm (tifffile); photos are
plain grey JPEGs (imagecodecs) of the cameras' size.
"""
from pathlib import Path

import imagecodecs
import numpy as np

from .synthetic import write_tif

OFFSET = np.array([368000.0, 3956000.0, 0.0])
W, H, F = 800, 600, 700.0
ROW_HEIGHT = 1.2
PLOT_W, PLOT_L, ALLEY = 2.0, 3.0, 1.0
SHED = (12.5, 2.5, 14.5, 8.5, 10.0)         # x0, y0, x1, y1, height (local)


def plots():
    """{name: (x0, y0, x1, y1)} local plot outlines."""
    out = {}
    for i in range(4):
        for j in range(3):
            x0, y0 = i * (PLOT_W + ALLEY), j * (PLOT_L + ALLEY)
            out[f"P{j + 1}{i + 1}"] = (x0, y0, x0 + PLOT_W, y0 + PLOT_L)
    return out


def boxes(seed=0):
    """[(owner, (x0, y0, z0, x1, y1, z1))]: owner = the plot the box belongs to, or ''."""
    rng = np.random.default_rng(seed)
    out = []
    for name, (x0, y0, x1, y1) in plots().items():
        for k in range(4):
            cx = x0 + 0.25 + 0.5 * k
            h = ROW_HEIGHT * (0.8 if name == "P22" and k == 1 else 1.0)   # uneven vigour
            out.append((name, (cx - 0.075, y0 + 0.1, 0.0, cx + 0.075, y1 - 0.1, h)))
        if rng.random() < 0.4:                                           # a weed in the plot
            wx, wy = x0 + rng.uniform(0.3, 1.7), y0 + rng.uniform(0.3, 2.7)
            out.append((name, (wx - 0.05, wy - 0.05, 0.0, wx + 0.05, wy + 0.05, 0.3)))
    for _ in range(8):                                                    # weeds in the alleys
        wx = rng.choice([2.5, 5.5, 8.5]) + rng.uniform(-0.2, 0.2)
        wy = rng.uniform(0, 11)
        out.append(("", (wx - 0.05, wy - 0.05, 0.0, wx + 0.05, wy + 0.05, 0.25)))
    for _ in range(40):                                                   # margin grass
        gx, gy = rng.uniform(-4, 15), rng.choice([-2.0, 13.0]) + rng.uniform(-1, 1)
        out.append(("", (gx - 0.1, gy - 0.1, 0.0, gx + 0.1, gy + 0.1, 0.15)))
    x0, y0, x1, y1, h = SHED
    out.append(("", (x0, y0, 0.0, x1, y1, h)))
    return out


def look_at(C, target):
    """R with x_cam = R (X − C): z towards the target, y down in the image."""
    z = np.asarray(target, float) - C
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    if np.linalg.norm(x) < 1e-9:
        x = np.array([1.0, 0.0, 0.0])
    x /= np.linalg.norm(x)
    return np.array([x, np.cross(z, x), z])


def cameras():
    """[(label, R, C)] local."""
    centre = np.array([5.5, 5.5, 0.0])
    out = []
    for k, a in enumerate(np.radians([0, 60, 120, 180, 240, 300])):
        C = centre + np.array([19.0 * np.cos(a), 19.0 * np.sin(a), 22.0])
        out.append((f"ROW_{k:04d}", look_at(C, centre), C))
    C = centre + np.array([0.3, 0.2, 24.0])
    out.append(("ROW_0006", look_at(C, centre), C))
    return out


def pixels(R, C, X):
    """Pinhole projection written here: (n, 2) pixels and (n,) depth."""
    Xc = (np.asarray(X, float) - C) @ R.T
    return np.column_stack([F * Xc[:, 0] / Xc[:, 2] + W / 2, F * Xc[:, 1] / Xc[:, 2] + H / 2]), Xc[:, 2]


def ray_hits_box(C, P, box):
    """Whether the segment C → P (n points P) passes through the box (slab test), before P."""
    lo, hi = np.array(box[:3]), np.array(box[3:])
    d = P - C
    with np.errstate(divide="ignore", invalid="ignore"):
        t1, t2 = (lo - C) / d, (hi - C) / d
    tmin = np.nanmax(np.minimum(t1, t2), axis=1)
    tmax = np.nanmin(np.maximum(t1, t2), axis=1)
    return (tmax >= tmin) & (tmin < 1.0 - 1e-6) & (tmax > 0)


def truth(seed=0, step=0.1):
    """{(plot, camera label): (in_frame, hidden_outside)}: in_frame: the plot's corners at the
    ground and at the rows' top all inside the frame; hidden_outside: share of points on the
    plot's top (a ``step`` grid at ROW_HEIGHT) whose line of sight meets a box that is not the
    plot's own."""
    bx = boxes(seed)
    out = {}
    for label, R, C in cameras():
        for name, (x0, y0, x1, y1) in plots().items():
            corners = np.array([[x, y, z] for z in (0.0, ROW_HEIGHT) for x, y in
                                ((x0, y0), (x1, y0), (x1, y1), (x0, y1))])
            uv, depth = pixels(R, C, corners)
            in_frame = bool((depth > 0).all() and (uv[:, 0] > 0).all() and (uv[:, 0] < W).all()
                            and (uv[:, 1] > 0).all() and (uv[:, 1] < H).all())
            gx, gy = np.meshgrid(np.arange(x0 + step / 2, x1, step), np.arange(y0 + step / 2, y1, step))
            P = np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, ROW_HEIGHT)])
            hidden = np.zeros(len(P), bool)
            for owner, b in bx:
                if owner != name:
                    hidden |= ray_hits_box(C, P, b)
            out[(name, label)] = (in_frame, float(hidden.mean()))
    return out


def write_world(folder, seed=0, pixel=0.02):
    """The DSM (GeoTIFF), the photos and what a Reconstruction needs: returns
    dict(dsm=path, photos=folder, cameras=[(label, R, C, photo path)], plots={name: map ring})."""
    folder = Path(folder)
    x0, y0, x1, y1 = -5.0, -5.0, 17.0, 16.0
    nx, ny = int(round((x1 - x0) / pixel)), int(round((y1 - y0) / pixel))
    xc = x0 + (np.arange(nx) + 0.5) * pixel
    yc = y1 - (np.arange(ny) + 0.5) * pixel
    z = np.zeros((ny, nx), np.float32)
    for _, (a, b, _, c, d, h) in boxes(seed):
        cols = (xc >= a) & (xc <= c)
        rows = (yc >= b) & (yc <= d)
        z[np.ix_(rows, cols)] = np.maximum(z[np.ix_(rows, cols)], h)
    dsm = write_tif(str(folder / "dsm.tif"), z, origin=(OFFSET[0] + x0, OFFSET[1] + y1),
                    pixel=pixel, tile=256)
    photos = folder / "photos"
    photos.mkdir(exist_ok=True)
    grey = np.full((H, W, 3), 120, np.uint8)
    jpeg = imagecodecs.jpeg_encode(grey)
    cams = []
    for label, R, C in cameras():
        path = photos / f"{label}.JPG"
        path.write_bytes(jpeg)
        cams.append((label, R, C, str(path)))
    rings = {name: np.array([[a, b], [c, b], [c, d], [a, d]]) + OFFSET[:2]
             for name, (a, b, c, d) in plots().items()}
    return dict(dsm=dsm, photos=str(photos), cameras=cams, plots=rings)
