"""Individual objects in the demo survey's plots: plants and weeds as discs of known position
and size, for the deep-learning round trip (training sets out, detections back).

The objects are *not* drawn in the orthomosaic or the photos (every survey file stays as it
was; the field's own weeds, ``field.make_weeds``, are another thing, drawn in every file): they are a truth list derived deterministically from the survey's plot corners
(``truth.json``) and a seed. ``plant`` discs (radius 0.20–0.28 m) sit centred on crop rows,
``weed`` discs (radius 0.12–0.16 m) in the furrows between rows, where the rows beside them
hide them from oblique views. Map coordinates in the survey's CRS (EPSG:32654), metres.

:func:`object_visibility` says which photos see each object, by the generator's own model
(true poses, ``truth.project``, the point → camera segment tested against the surface by
``truth.hidden``): independent of the core's back-projection, occlusion and ray casting, but
the same camera model, so agreement proves consistency, not the camera model.
"""
from typing import Dict, List

import numpy as np

from .field import ROW_SPACING
from ..reconstruction import INSIDE
from .truth import hidden, project

PLANT_SLOTS_U = (-1.5, -0.9, -0.3, 0.3, 0.9, 1.5)    # m along a plot's long axis
PLANT_ROWS_V = (-1.0, 0.0, 1.0)                       # m across it (crop rows, 1 m apart)
WEED_ROWS_V = (-0.75, 0.75)                           # furrows
PLANTS_PER_PLOT, WEEDS_PER_PLOT = 4, 2
VISIBILITY_GRID = 0.02        # m between the samples of a disc tested for visibility


def demo_objects(truth_doc: dict, seed: int = 0) -> List[dict]:
    """Discs per plot: ``id`` (plot id + P/W + number), ``plot_id``, ``class`` (plant, weed),
    ``centre`` (x, y) map metres, ``radius`` m. Same truth and seed → same list."""
    rng = np.random.default_rng([seed, 26])
    out = []
    for pid in sorted(truth_doc["plots"]):
        c = np.asarray(truth_doc["plots"][pid]["corners"], float)[:, :2]
        centre = c.mean(axis=0)
        e = c[1] - c[0]                          # the long edge (corners from the lower left)
        ang = np.arctan2(e[1], e[0])
        ca, sa = np.cos(ang), np.sin(ang)
        slots = [(u, v) for u in PLANT_SLOTS_U for v in PLANT_ROWS_V]
        pick = rng.permutation(len(slots))[:PLANTS_PER_PLOT]
        items = [("plant", slots[k], rng.uniform(0.20, 0.28)) for k in sorted(pick)]
        wslots = [(u, v) for u in PLANT_SLOTS_U for v in WEED_ROWS_V]
        pick = rng.permutation(len(wslots))[:WEEDS_PER_PLOT]
        items += [("weed", wslots[k], rng.uniform(0.12, 0.16)) for k in sorted(pick)]
        for k, (cls, (u, v), r) in enumerate(items):
            xy = centre + np.array([u * ca - v * sa, u * sa + v * ca])
            out.append({"id": f"{pid}_{cls[0].upper()}{k + 1}", "plot_id": pid, "class": cls,
                        "centre": xy.tolist(), "radius": float(r)})
    # the furrows above are half-way between 0.5 m rows
    assert ROW_SPACING == 0.5  # nosec B101 -- a constant of this module, not input
    return out


def disc_ring(obj: dict, vertices: int = 64) -> np.ndarray:
    """(vertices, 2) counter-clockwise polygon of the disc (vertices on the circle)."""
    t = np.linspace(0.0, 2 * np.pi, int(vertices), endpoint=False)
    return np.asarray(obj["centre"]) + obj["radius"] * np.column_stack([np.cos(t), np.sin(t)])


def object_visibility(scene, camera, shots, objects: List[dict],
                      min_visible: float = 0.5) -> Dict[str, dict]:
    """Per object id: ``share`` (m,) the fraction of its disc (samples on a VISIBILITY_GRID
    grid, on the surface) that each shot sees (in front, in the frame, not hidden), and
    ``photos`` the shots whose share is at least ``min_visible``."""
    off = scene.offset
    names = [s.label for s in shots]
    C = np.array([s.C for s in shots])
    out = {}
    for o in objects:
        r = o["radius"]
        g = np.arange(-r, r + 1e-9, VISIBILITY_GRID)
        gx, gy = [a.ravel() for a in np.meshgrid(g, g)]
        keep = gx ** 2 + gy ** 2 <= r * r
        x = o["centre"][0] - off[0] + gx[keep]
        y = o["centre"][1] - off[1] + gy[keep]
        pts = np.column_stack([x, y, scene.surface_local(x, y)])
        _, st = project(camera, shots, pts)
        inside = st == INSIDE
        mi, pi = np.nonzero(inside)
        seen = inside.copy()
        if len(mi):
            seen[mi, pi] = ~hidden(scene, C[mi], pts[pi])
        share = seen.mean(axis=1)
        out[o["id"]] = {"share": share, "photos": [names[i] for i in np.flatnonzero(share >= min_visible)]}
    return out


__all__ = ["demo_objects", "disc_ring", "object_visibility"]
