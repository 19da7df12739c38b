"""The deep-learning round trip on the demo survey: simulated detections and their score.

:func:`simulate_detections` turns the labels of an exported COCO training set
(:func:`core.projection.training_set.export_training_set`) into the COCO *results* a detector
would give: every label is missed with probability ``miss``; the others keep their outline
with every vertex moved towards or away from the outline's centre by Gaussian noise of
``noise_px`` pixels (standard deviation; radial, so that the outline stays a simple polygon
as a segmenter's contour is) and a score in [0.6, 0.95]; each label also spawns, with probability
``false_positive``, a false detection elsewhere in its photo (a disc of the label's size at a
uniform random place in the frame whose box overlaps no label's box, drawn again up to
FALSE_TRIES times; score in [0.3, 0.9]): 5 % false positives per photo on average (a false
detection on a labelled object would be one more view of it). Seeded: same input and seed,
same detections.

:func:`score_objects` matches map objects to the truth discs (one to one, nearest centre of
the same class first, within ``match_radius`` of the disc's radius) and gives recall,
precision and position errors. :func:`score_outlines` matches outlines to truth polygons one to
one by IoU and gives recall, precision, IoU and corner errors (the read-back of a training set).
"""
import json
from typing import Dict, List, Optional

import numpy as np

from ..files import write_json


FALSE_TRIES = 50     # places drawn for a false detection until one is clear of every label


def simulate_detections(coco_path, out_path, seed: int = 0, noise_px: float = 3.0,
                        miss: float = 0.1, false_positive: float = 0.05) -> Dict[str, object]:
    """Write a COCO results list for the images of ``coco_path`` to ``out_path``. Returns
    ``detected`` {instance: [photo, ...]} (the true detections kept), ``false`` (count) and
    ``missed`` (count)."""
    rng = np.random.default_rng([seed, 2026])
    again = np.random.default_rng([seed, 2026, 1])   # redraws: the main stream stays as it was
    doc = json.load(open(coco_path, encoding="utf-8"))
    images = {im["id"]: im for im in doc["images"]}
    results, detected, missed, false = [], {}, 0, 0
    boxes = {k: [] for k in images}
    for a in doc["annotations"]:
        x, y, w, h = a["bbox"]
        boxes[a["image_id"]].append([x, y, x + w, y + h])
    boxes = {k: np.array(v, float).reshape(-1, 4) for k, v in boxes.items()}
    for a in doc["annotations"]:
        im = images[a["image_id"]]
        photo = im.get("photo", im["file_name"])
        rings = [np.asarray(p, float).reshape(-1, 2) for p in a["segmentation"]]
        fp = rng.random() < false_positive
        if rng.random() < miss:
            missed += 1
        else:
            noisy = [_radial_noise(r, noise_px, rng) for r in rings]
            results.append(_result(a["image_id"], a["category_id"], noisy, rng.uniform(0.6, 0.95)))
            detected.setdefault(a["attributes"]["instance"], []).append(photo)
        if fp:
            false += 1
            r = rings[0]
            c = r.mean(axis=0)
            size = np.array([im["width"], im["height"]], float)
            span = r.max(axis=0) - r.min(axis=0)
            at = rng.uniform(span, size - span)
            for _ in range(FALSE_TRIES):          # elsewhere: clear of every label's box
                lo, hi = at - c + r.min(axis=0), at - c + r.max(axis=0)
                box = boxes[a["image_id"]]
                if not ((box[:, :2] < hi) & (box[:, 2:] > lo)).all(axis=1).any():
                    break
                at = again.uniform(span, size - span)
            fake = _radial_noise(r - c + at, noise_px, rng)
            results.append(_result(a["image_id"], a["category_id"], [fake], rng.uniform(0.3, 0.9)))
    write_json(out_path, results, separators=(",", ":"))
    return {"detected": detected, "missed": missed, "false": false, "results": len(results)}


def _radial_noise(ring: np.ndarray, sd: float, rng) -> np.ndarray:
    """Each vertex moved along the ray from the ring's vertex mean by N(0, sd) pixels (never
    past the centre)."""
    c = ring.mean(axis=0)
    d = ring - c
    r = np.hypot(d[:, 0], d[:, 1])
    k = np.maximum(r + rng.normal(0.0, sd, len(r)), 0.1 * r) / np.maximum(r, 1e-12)
    return c + d * k[:, None]


def _result(image_id, category_id, rings, score) -> dict:
    xy = np.vstack(rings)
    x0, y0 = xy.min(axis=0)
    x1, y1 = xy.max(axis=0)
    return {"image_id": image_id, "category_id": category_id,
            "segmentation": [np.round(r, 3).ravel().tolist() for r in rings],
            "bbox": [round(float(x0), 3), round(float(y0), 3), round(float(x1 - x0), 3),
                     round(float(y1 - y0), 3)], "score": round(float(score), 4)}


def score_objects(objects: List[dict], found: List[dict], match_radius: float = 0.5) -> dict:
    """Match ``found`` map objects ({class, x, y}) to the truth ``objects`` (demo discs): a pair
    matches when the classes agree and the centres are closer than ``match_radius`` × the
    disc's radius; greedy, nearest pairs first, one to one. Returns recall, precision, the
    median and maximum position error (m) of the matches, and ``matches`` {truth id: found
    index}."""
    if not objects:
        raise ValueError("no truth objects")
    t = np.array([o["centre"] for o in objects], float)
    f = np.array([[d["x"], d["y"]] for d in found], float).reshape(-1, 2)
    d = np.hypot(t[:, None, 0] - f[None, :, 0], t[:, None, 1] - f[None, :, 1])
    ok = d < match_radius * np.array([o["radius"] for o in objects])[:, None]
    ok &= np.array([[o["class"] == x["class"] for x in found] for o in objects], bool).reshape(d.shape)
    pairs = sorted(zip(*np.nonzero(ok)), key=lambda p: d[p])
    used_t, used_f, matches = set(), set(), {}
    for i, j in pairs:
        if i in used_t or j in used_f:
            continue
        used_t.add(i)
        used_f.add(j)
        matches[objects[i]["id"]] = int(j)
    err = np.array([d[objects.index(o), j] for o in objects if o["id"] in matches
                    for j in [matches[o["id"]]]])
    return {"recall": len(matches) / len(objects),
            "precision": len(matches) / len(found) if found else 0.0,
            "median_error_m": float(np.median(err)) if len(err) else float("nan"),
            "max_error_m": float(err.max()) if len(err) else float("nan"),
            "matched": len(matches), "found": len(found), "truth": len(objects),
            "matches": matches}


def score_outlines(truth: Dict[str, np.ndarray], found: List[np.ndarray],
                   min_iou: float = 0.5) -> dict:
    """Match fused outlines to truth polygons one to one by IoU (greedy, best pairs first,
    IoU ≥ ``min_iou``; each truth object to at most one outline). ``truth``: {name: (k, 2)
    ring}, ``found``: (k, 2+) rings, map units. Returns recall, precision, the matches' IoU
    (min, median) and the distance of each truth corner to the nearest vertex of its match
    (median, max; map units), and ``matches`` {truth name: found index}."""
    import shapely
    names = list(truth)
    tg = np.array([shapely.Polygon(np.asarray(truth[n])[:, :2]) for n in names], object)
    fg = np.array([shapely.Polygon(np.asarray(r)[:, :2]) for r in found], object)
    pairs = []
    if len(tg) and len(fg):
        a, b = shapely.STRtree(fg).query(tg, predicate="intersects")
        inter = shapely.area(shapely.intersection(tg[a], fg[b]))
        iou = inter / (shapely.area(tg[a]) + shapely.area(fg[b]) - inter)
        pairs = sorted(((v, i, j) for v, i, j in zip(iou.tolist(), a.tolist(), b.tolist())
                        if v >= min_iou), reverse=True)
    used_t, used_f, matches, ious, corners = set(), set(), {}, [], []
    for v, i, j in pairs:
        if i in used_t or j in used_f:
            continue
        used_t.add(i)
        used_f.add(j)
        matches[names[i]] = j
        ious.append(v)
        verts = np.asarray(fg[j].exterior.coords)[:-1]
        corners += [float(np.hypot(*(verts - c).T).min()) for c in np.asarray(truth[names[i]])[:, :2]]
    nan = float("nan")
    return {"recall": len(matches) / len(names) if names else nan,
            "precision": len(matches) / len(found) if found else 0.0,
            "iou_min": min(ious) if ious else nan, "iou_median": float(np.median(ious)) if ious else nan,
            "corner_median_m": float(np.median(corners)) if corners else nan,
            "corner_max_m": max(corners) if corners else nan,
            "matched": len(matches), "found": len(found), "truth": len(names), "matches": matches}


def position_of(obj) -> Optional[tuple]:
    """(x, y) of a fused or merged map object: its position, else its outline's centroid."""
    pos = getattr(obj, "position", None)
    if pos is not None and np.isfinite(pos[0]):
        return float(pos[0]), float(pos[1])
    import shapely
    polys = [shapely.Polygon(p[0][:, :2], [h[:, :2] for h in p[1:]]) for p in obj.parts if p and len(p[0]) >= 3]
    if not polys:
        return None
    c = shapely.unary_union(polys).centroid
    return float(c.x), float(c.y)


__all__ = ["simulate_detections", "score_objects", "score_outlines", "position_of"]
