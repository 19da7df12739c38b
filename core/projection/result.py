"""The result of :func:`core.projection.back_project`: one record per ROI × photo, plain arrays.

Pixels: origin at the top-left *corner* of the photo, x = column to the right, y = row down;
the centre of the top-left pixel is (0.5, 0.5) (the same numbers EasyIDP 2.0.4 gives for
Metashape and Pix4D). Polygons are stored flat (:class:`core.geometry.FlatPolygons`, one
record per ROI × photo).
"""
import json
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

import numpy as np

from ..errors import EasyIDPError
from ..files import write_json
from ..geometry import FlatPolygons

DROP_REASONS = {"partly_outside": "partly outside the frame (whole ROIs only)",
                "below_min_visible": "below the minimum visible, unoccluded share",
                "beyond_max_images": "beyond the maximum number of photos per ROI"}
"""Keys of :attr:`BackProjection.dropped` (ROI × photo pairs not kept) and what they mean."""

PIXEL_CONVENTION = ("pixels: origin at the top-left corner of the photo, x = column to the "
                    "right, y = row down; the centre of the top-left pixel is (0.5, 0.5)")
PIXEL_CRS_WKT = ('ENGCRS["Undefined cartesian SRS",EDATUM["Unknown engineering datum"],'
                 'CS[Cartesian,2],AXIS["x",east,ORDER[1],LENGTHUNIT["unknown",1]],'
                 'AXIS["y",north,ORDER[2],LENGTHUNIT["unknown",1]]]')
"""The CRS of photo-pixel layers (x = column, y = −row): an undefined engineering (Cartesian)
CRS, which GeoPackage stores as its "Undefined cartesian SRS" (srs_id −1), not as the undefined
*geographic* one; QGIS draws it without reprojection, over the raw photo (which has no CRS)."""


@dataclass
class BackProjection:
    """ROIs in raw photos: one record per kept ROI × photo, sorted by ROI then rank.

    Per record (arrays of length k): ``roi`` index into ``roi_names``; ``photo`` label (str);
    ``photo_index`` into ``photo_labels``; ``visible_fraction`` the share of the ROI's ground
    area inside the frame; ``occluded_fraction`` the share of the in-frame sample points whose
    line of sight the DSM blocks (NaN without an occlusion test); ``score`` in [0, 1] (see
    :func:`core.projection.ranking.score`); ``view_angle`` degrees off nadir at the ROI;
    ``gsd`` ground sampling distance at the ROI (map units per pixel, from the visible part's
    ground and pixel areas); ``centre_distance`` of the visible part's centroid from the
    principal point, 0 at the principal point and 1 at a frame corner's distance; ``rank``
    1 = best photo of the ROI; ``clipped`` True when the polygon was cut by the frame.
    ``polygons`` holds the pixel polygons (:class:`FlatPolygons`). ``uncertainty_px``: photo
    label → the expected error of its pixels (one standard deviation) for cameras read from photo
    tags (:attr:`~core.reconstruction.Reconstruction.uncertainty_px`); empty for solved projects.
    """
    roi_names: List[str]
    photo_labels: List[str]
    photo_paths: List[Optional[str]]
    image_sizes: np.ndarray                 # (m, 2) width, height of each photo
    principal_points: np.ndarray            # (m, 2) pixels
    roi: np.ndarray
    photo: np.ndarray
    photo_index: np.ndarray
    polygons: FlatPolygons
    visible_fraction: np.ndarray
    occluded_fraction: np.ndarray
    score: np.ndarray
    view_angle: np.ndarray
    gsd: np.ndarray
    centre_distance: np.ndarray
    rank: np.ndarray
    clipped: np.ndarray
    unseen: Dict[str, str] = field(default_factory=dict)       # ROI name -> why no photo is kept
    dropped: Dict[str, int] = field(default_factory=dict)       # reason -> ROI × photo pairs
    settings: Dict[str, object] = field(default_factory=dict)
    notes: List[str] = field(default_factory=list)
    uncertainty_px: Dict[str, float] = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.roi)

    def polygons_of(self, i: int) -> List[List[np.ndarray]]:
        """Record ``i``'s pixel polygons ``[[exterior, hole, ...], ...]`` (open rings)."""
        return self.polygons.polygons(i)

    def rings_of(self, i: int) -> List[np.ndarray]:
        return [r for p in self.polygons.polygons(i) for r in p]

    def records_of(self, roi_name: str) -> np.ndarray:
        """Record indices of one ROI, best first."""
        return np.flatnonzero(self.roi == self.roi_names.index(roi_name))

    def photos_per_roi(self) -> np.ndarray:
        return np.bincount(self.roi, minlength=len(self.roi_names))

    def best(self) -> Dict[str, int]:
        """{ROI name: index of its best record} for the ROIs seen by at least one photo."""
        out = {}
        for i in np.flatnonzero(self.rank == 1):
            out[self.roi_names[self.roi[i]]] = int(i)
        return out

    # --- EasyIDP compatibility ---------------------------------------------------------------
    def to_easyidp_dict(self) -> Dict[str, Dict[str, np.ndarray]]:
        """EasyIDP 2.0.4's ``back2raw`` structure ``{roi: {photo: (n, 2) array}}``.

        Every ROI is a key (empty dict when no photo keeps it), photos in rank order. A
        record with one ring gives that ring closed (first vertex repeated, as EasyIDP's ROI
        arrays are); several rings (holes, multipart, a ROI cut in pieces by the frame) are
        concatenated, each closed, as EasyIDP flattens multipart shapes.
        """
        out: Dict[str, Dict[str, np.ndarray]] = {n: {} for n in self.roi_names}
        for i in range(len(self)):
            rings = [np.vstack([r, r[:1]]) for r in self.rings_of(i)]
            out[self.roi_names[self.roi[i]]][str(self.photo[i])] = np.concatenate(rings)
        return out

    def write_easyidp_json(self, path) -> str:
        """Write :meth:`to_easyidp_dict` as EasyIDP's ``roi_image_order.json`` (atomically)."""
        d = {roi: {ph: np.round(a, 10).tolist() for ph, a in photos.items()}
             for roi, photos in self.to_easyidp_dict().items()}
        write_json(path, d, indent=1)
        return os.fspath(path)

    @classmethod
    def from_records(cls, roi_names: List[str], records: List[dict], photos: Dict[str, dict],
                     settings: Optional[dict] = None) -> "BackProjection":
        """A back-projection rebuilt from plain records, e.g. the features of the *Back-project
        ROIs* photo-pixel layer. ``records``: dicts with ``roi`` (a name of ``roi_names``),
        ``photo`` (a key of ``photos``), ``polygons`` ([[exterior, hole, …], …] in our pixel
        convention) and optionally ``rank``, ``score``, ``view_angle``, ``gsd``,
        ``visible_fraction``, ``occluded_fraction``, ``centre_distance``, ``clipped``
        (missing numbers: NaN; missing ranks: by score within each ROI). ``photos``: {label:
        {"path": …, "width": …, "height": …, "principal_point": (cx, cy) (optional)}}."""
        index = {n: k for k, n in enumerate(roi_names)}
        labels = sorted(photos)
        pidx = {lab: k for k, lab in enumerate(labels)}
        bad = sorted({str(r.get("roi")) for r in records if r.get("roi") not in index})
        if bad:
            raise EasyIDPError(f"{len(bad)} back-projected ROI name(s) are not among the ROIs "
                               f"({', '.join(bad[:5])}{' …' if len(bad) > 5 else ''}): give the "
                               "ROI layer and name field the back-projection was made with.")
        bad = sorted({str(r.get("photo")) for r in records if r.get("photo") not in pidx})
        if bad:
            raise EasyIDPError(f"Photo(s) {', '.join(bad[:5])} of the back-projection are not in "
                               "the project: give the project it was made with.")

        def num(r, key, default=float("nan")):
            v = r.get(key)
            try:
                return float(v) if v is not None else default
            except (TypeError, ValueError):
                return default
        roi = np.array([index[r["roi"]] for r in records], np.int64)
        cam = np.array([pidx[r["photo"]] for r in records], np.int64)
        score = np.array([num(r, "score") for r in records])
        rank = np.array([num(r, "rank", 0.0) for r in records])
        if (rank <= 0).any() or not np.isfinite(rank).all():     # by score within each ROI
            order = np.lexsort((-np.nan_to_num(score, nan=-1.0), roi))
            rank = np.zeros(len(records))
            first = np.r_[True, roi[order][1:] != roi[order][:-1]] if len(order) else []
            start = np.maximum.accumulate(np.where(first, np.arange(len(order)), 0))
            rank[order] = np.arange(len(order)) - start + 1
        order = np.lexsort((cam, rank, roi))
        polys = FlatPolygons.from_lists([records[i]["polygons"] for i in order])
        sizes = np.array([[photos[lab]["width"], photos[lab]["height"]] for lab in labels], float)
        pp = np.array([photos[lab].get("principal_point") or
                       (photos[lab]["width"] / 2, photos[lab]["height"] / 2) for lab in labels], float)
        col = {k: np.array([num(records[i], k) for i in order]) for k in
               ("visible_fraction", "occluded_fraction", "view_angle", "gsd", "centre_distance")}
        return cls(roi_names=list(roi_names), photo_labels=labels,
                   photo_paths=[photos[lab].get("path") for lab in labels],
                   image_sizes=sizes.astype(np.int64) if len(labels) else np.zeros((0, 2), np.int64),
                   principal_points=pp if len(labels) else np.zeros((0, 2)), roi=roi[order],
                   photo=np.array(labels, dtype=str)[cam[order]] if len(order) else np.zeros(0, str),
                   photo_index=cam[order], polygons=polys,
                   visible_fraction=np.nan_to_num(col["visible_fraction"], nan=1.0),
                   occluded_fraction=col["occluded_fraction"], score=score[order],
                   view_angle=col["view_angle"], gsd=col["gsd"],
                   centre_distance=col["centre_distance"], rank=rank[order].astype(np.int32),
                   clipped=np.array([bool(records[i].get("clipped") or False) for i in order]),
                   settings=dict(settings or {}))

    def summary(self) -> str:
        n = len(self.roi_names)
        seen = int((self.photos_per_roi() > 0).sum())
        drops = ", ".join(f"{v} {DROP_REASONS.get(k, k)}" for k, v in self.dropped.items() if v)
        return (f"{len(self)} ROI × photo pairs kept for {seen} of {n} ROIs over "
                f"{len(self.photo_labels)} photos" + (f"; dropped: {drops}" if drops else ""))


def read_easyidp_json(path) -> Dict[str, Dict[str, np.ndarray]]:
    """Read an EasyIDP ``roi_image_order.json`` back as ``{roi: {photo: (n, 2) array}}``."""
    with open(path, encoding="utf-8") as fh:
        d = json.load(fh)
    return {roi: {ph: np.asarray(v, np.float64).reshape(-1, 2) for ph, v in photos.items()}
            for roi, photos in d.items()}
