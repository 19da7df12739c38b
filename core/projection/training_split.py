"""The train/validation split of a training set: whole images, none lost.

Every image (a whole photo, or a tile) goes to one split, with all its labels; no image is left
out. The unit that is drawn (seeded) decides:

* ``"photo"``: photos drawn at random; a photo's tiles go with it.
* ``"region"``: square field cells of ``region_size`` map units. An image belongs to the cell
  that holds the centres of most of its objects (ties: the cell that comes first in x, then y).
  Cells are drawn at random into validation until it holds ``val_fraction`` of the images.
  When one cell holds every image, photos are drawn instead (said in the warnings).

Validation is filled to ``round(val_fraction × images)``, at least one image and at most all but
one, when ``val_fraction`` > 0 and there are two images or more. An object seen in images of both
splits is *shared* (counted): in region splits only objects near a cell's border, seen from
photos centred across it; in photo splits most objects, since photos overlap.
"""
from typing import List, Sequence, Tuple

import numpy as np

SPLITS = ("train", "val")
SPLIT_MODES = ("photo", "region")


def assign_images(photo_of: Sequence[str], centres_of: Sequence[np.ndarray], mode: str,
                  val_fraction: float, region_size: float, seed: int) -> Tuple[np.ndarray, List[str]]:
    """(n,) 0 = train / 1 = val per image, and warnings. ``photo_of[k]``: the photo of image k;
    ``centres_of[k]``: (m, 2) map centres of its objects."""
    n = len(photo_of)
    out = np.zeros(n, np.int8)
    warnings: List[str] = []
    if val_fraction <= 0 or n == 0:
        return out, warnings
    rng = np.random.default_rng(seed)
    target = min(max(int(round(val_fraction * n)), 1), n - 1)
    if target <= 0:
        return out, warnings
    if mode == "region":
        cells = []
        for c in centres_of:
            cell = np.floor(np.asarray(c, float).reshape(-1, 2) / region_size).astype(np.int64)
            u, counts = np.unique(cell, axis=0, return_counts=True)
            cells.append(tuple(u[int(np.argmax(counts))]))
        keys = sorted(set(cells))
        if len(keys) > 1:
            index = {k: i for i, k in enumerate(keys)}
            unit = np.array([index[c] for c in cells])
            return _fill(unit, len(keys), target, rng), warnings
        warnings.append(f"every image lies in one field region of {region_size:g} map units: "
                        "the split is by photo; choose a smaller region size to split by region")
    labels = sorted(set(photo_of))
    index = {p: i for i, p in enumerate(labels)}
    unit = np.array([index[p] for p in photo_of])
    return _fill(unit, len(labels), target, rng), warnings


def _fill(unit: np.ndarray, n_units: int, target: int, rng) -> np.ndarray:
    """Units drawn at random into validation while it stays within all images but one, until it
    holds ``target`` images."""
    count = np.bincount(unit, minlength=n_units)
    total, val = int(count.sum()), 0
    is_val = np.zeros(n_units, bool)
    for u in rng.permutation(n_units):
        if val >= target:
            break
        if val + count[u] <= total - 1:
            is_val[u] = True
            val += int(count[u])
    return is_val[unit].astype(np.int8)


def split_warnings(val_images: int, images: int, val_fraction: float, objects: int) -> List[str]:
    """Warnings when validation came out empty or under half the fraction asked."""
    if val_fraction <= 0:
        return []
    if images and val_images == 0:
        why = "only one image was written" if images == 1 else \
            f"{objects} object(s): too few to split" if objects < 10 else "no unit could be drawn"
        return [f"the validation set is empty ({why}); a model trained on this set cannot be "
                "validated. Label more objects, use tiles, or give validation data separately."]
    if images and val_images < 0.5 * val_fraction * images:
        return [f"the validation set holds {val_images} of {images} images "
                f"({100.0 * val_images / images:.0f} %), under half the {100 * val_fraction:.0f} % "
                "asked: the field regions are large compared with the flight; choose a smaller "
                "region size or split by photo."]
    return []
