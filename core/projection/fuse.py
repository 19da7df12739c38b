"""Fusion of detections across views: one map object per real object (merge mode ``fuse``).

Input: forward-projected polygons (:func:`.forward.forward_project`) of detections, with
scores, from several photos. Steps:

1. **NMS within a photo**: per photo and label, by decreasing score, a polygon whose map IoU
   with a kept one exceeds ``nms_iou``, or that lies more than ``NMS_WITHIN`` inside it (or it
   inside the polygon), is suppressed. Tiles of one photo count as one photo, so an object cut
   by the overlap of two tiles is one detection.
2. **Grouping**: polygons of one label from *different* photos are linked when their map IoU
   is at least ``group_iou`` and their centroids are at most ``max_distance`` apart (default,
   per pair: half the mean of the two equivalent diameters, sqrt(area)), or when at least
   ``group_overlap`` of the smaller one lies in the other (a view clipped by the frame or
   partly hidden); a group is a connected component.
3. **One object per group**: the *consensus* outline is voted on a grid of ``VOTE_CELLS``
   cells across the group. A photo votes only on the cells it can see: where the photos
   disagree, the cells (on the DSM surface) are tested for being in the photo's frame (each
   cell) and on its line of sight (one test per ``SIGHT_BLOCK``² cells, as :mod:`.occlusion`
   tests samples). An oblique view that cannot see the far
   flank of a plant puts its outline on the plant's near side; it has no say on the far side,
   so the vote is not pulled towards the camera. A cell is in the outline when more than half
   of the (weighted) photos that see it cover it; with at least ``ROBUST_MIN_PHOTOS`` photos
   the votes are reweighted ``ROBUST_ROUNDS`` times by each photo's IoU with the last
   outline. The outline is sub-cell (:meth:`_Vote.outline`): the zero level of the weighted
   median of the photos' signed distances to their own outlines, whose sign is the vote's
   (but for even splits, where it decides) and which is linear along a straight edge, so an edge lands where the photos put it, not on the
   cells; and where more than half of the photos whose frame holds the place put a vertex
   within one cell of it, the outline has that vertex (their median). Identical views give back their own polygon.
   The outermost ring of the largest piece. Not the union, so a misplaced view neither grows
   nor moves it. ``position`` is the outline's centroid, its
   height the DSM there (bilinear; outline vertices off the DSM or on nodata take the median
   of the outline's other heights, else of its members'); ``views`` the number of photos in the group;
   ``mean_score``/``max_score``. ``visibility=False``: every photo votes on every cell.
4. **Lone views**: an object of one view whose detection, in its photo, overlaps by IoU ≥
   ``ATTACH_IOU`` the outline of a nearby object (same label, not yet seen in that photo)
   projected into that photo joins that object: views, photos and scores, not the outline. On
   the map such a view can lie far off, because the part of the object its photo cannot see is
   drawn on what hides it; in the photo it still covers the object.
5. **Confidence**: the outline is back-projected (:func:`.backward.back_project`, DSM heights,
   occlusion tested as :mod:`.occlusion` does, ``min_visible``) into the photos that were
   searched; ``expected_views`` is the number of those that could have seen it, with the photos
   that found it (an outline a little off may miss ``min_visible`` in a photo that did see the
   object; they are not tested): never below ``views``. The lines of sight are cast
   ``COARSE_SAMPLES`` per outline first, and ``OCCLUSION_SAMPLES`` where the share is close to
   ``min_visible`` or the frame cuts the outline (:func:`_could_see`). ``confidence = mean score (1 when there are no scores) × views /
   expected_views``: an object found in 1 of 9 photos that could see it gets 1/9 of its score.

Map coordinates: those of the shapes (the DSM's CRS unless forward projection was given
another); areas in m² by the members' own planimetric ratio, as :mod:`.merge` does.
"""
from dataclasses import dataclass
from typing import List, Optional, Sequence

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError
from ..geometry import rasterize
from ..progress import as_progress
from ..raster import HIT, as_dsm, first_hits
from ..reconstruction import INSIDE
from ..roi import ROI, ROISet
from .backward import back_project
from .forward import ForwardShape
from .map_polygon import MapPolygon, shapely_polygons
from .occlusion import RAYS_AT_ONCE, _tolerance, occluded_fractions

VOTE_CELLS = 48          # vote grid cells across a group's extent (longer side)
SIGHT_BLOCK = 2          # vote cells per side of a block tested by one line of sight
LINK_BATCH = 4096         # candidate links intersected at once
NMS_WITHIN = 0.8         # a polygon this much inside a kept one of its photo is a duplicate
ROBUST_ROUNDS = 2        # reweightings of the consensus vote
ROBUST_MIN_PHOTOS = 4    # photos a group needs to be reweighted
ATTACH_IOU = 0.5         # photo-space IoU for a lone view to join an object seen elsewhere
SNAP_CELLS = 2.0         # outline vertices within this many cells of a voted corner become it
SIMPLIFY = 0.1           # outline simplification tolerance, cells
MEDIAN_ROUNDS = 3        # times the region takes the median's side where it differs from the vote
DIST_CAP = 1.5           # cells: distances to the views' outlines are measured up to this
MAX_CORNER_VERTICES = 20000  # vertices as drawn in a group above which corners are not voted
OCCLUSION_SAMPLES = 256  # lines of sight per outline and photo for expected views (back_project's)
COARSE_SAMPLES = 48      # the first, coarse test of them
COARSE_MARGIN = 0.25     # coarse visible shares this close to min_visible are tested again in full


@dataclass
class FusedObject(MapPolygon):
    """A :class:`MapPolygon` with the fusion's figures: ``position`` (x, y, z) map units and DSM
    height; ``expected_views`` photos searched that could see it; ``mean_score``,
    ``max_score`` (None without scores); ``confidence`` in [0, 1]."""
    position: tuple = (float("nan"),) * 3
    expected_views: int = 0
    mean_score: Optional[float] = None
    max_score: Optional[float] = None
    confidence: float = 0.0


def _nms(ok: List[int], geoms, scores, keys, iou: float) -> List[int]:
    """Indices of ``ok`` kept by NMS within each key (photo, label): by decreasing score, a
    polygon whose IoU with a kept one exceeds ``iou``, or that lies more than NMS_WITHIN inside
    it (or it inside the polygon), is suppressed. One spatial query for all pairs."""
    import shapely
    if not ok:
        return []
    order = sorted(ok, key=lambda i: -scores[i])
    g = np.array([geoms[i] for i in order], object)
    ids = {}
    key = np.array([ids.setdefault(keys[i], len(ids)) for i in order], np.int64)
    a, b = shapely.STRtree(g).query(g, predicate="intersects")
    sel = (a < b) & (key[a] == key[b])          # a ranks before b
    a, b = a[sel], b[sel]
    suppressed = np.zeros(len(order), bool)
    if len(a):
        inter = shapely.area(shapely.intersection(g[a], g[b]))
        area = shapely.area(g)
        dup = (inter > iou * (area[a] + area[b] - inter)) | \
            (inter > NMS_WITHIN * np.minimum(area[a], area[b]))
        a, b = a[dup], b[dup]
        srt = np.lexsort((b, a))
        a, b = a[srt], b[srt]
        starts = np.searchsorted(a, np.arange(len(order) + 1))
        for k in range(len(order)):             # greedy: a kept polygon suppresses its duplicates
            if not suppressed[k] and starts[k] < starts[k + 1]:
                suppressed[b[starts[k]:starts[k + 1]]] = True
    return [order[k] for k in np.flatnonzero(~suppressed).tolist()]


class _Vote:
    """One group's vote grid: ``cover`` (photos, rows, cols) bool, photo p's polygons cover the
    cell (its centre inside); the grid's corner ``ox``, ``oy`` and ``cell`` (map units; x right,
    rows down, north up)."""

    def __init__(self, members, photo_of, n_photos: int, corners=None):
        import shapely
        x0, y0, x1, y1 = shapely.total_bounds(members)
        self.cell = max(x1 - x0, y1 - y0) / VOTE_CELLS
        self.cover = None
        self._votes = self._seen = None
        self.weights, self.seen = None, None
        if not self.cell > 0:
            return
        cols = int(np.ceil((x1 - x0) / self.cell)) + 2
        rows = int(np.ceil((y1 - y0) / self.cell)) + 2
        self.ox, self.oy = x0 - self.cell, y1 + self.cell
        self.cover = np.zeros((n_photos, rows, cols), bool)
        seg_a, seg_b, seg_p = [], [], []
        for g, p in zip(members, photo_of):
            rings = []
            for part in getattr(g, "geoms", [g]):
                for ring in [part.exterior, *part.interiors]:
                    xy = np.asarray(ring.coords)[:-1]
                    rings.append(self.to_grid(xy))
            # photos, not polygons: a photo with two overlapping pieces votes once
            self.cover[p] |= rasterize(rings, self.cover.shape[1:])
            for r in rings:
                seg_a.append(r)
                seg_b.append(np.roll(r, -1, axis=0))
                seg_p.append(np.full(len(r), p, np.int64))
        # the photos' edges (grid units) and their vertices as drawn (no densified ones)
        self.segments = (np.vstack(seg_a), np.vstack(seg_b), np.concatenate(seg_p))
        self.corners = [(p, self.to_grid(np.asarray(c, np.float64).reshape(-1, 2)))
                        for c, p in zip(corners if corners is not None else [], photo_of)]
        self.corner_frame = None     # (vertices, photos): the vertex is in the photo's frame
        n = self.cover.sum(axis=0)
        self.disputed = np.flatnonzero(((n > 0) & (n < n_photos)).ravel())

    def to_grid(self, xy: np.ndarray) -> np.ndarray:
        """Map (x, y) → grid (column, row), continuous: cell (r, c) spans [c, c + 1) × [r, r + 1)."""
        return np.column_stack([(xy[:, 0] - self.ox) / self.cell, (self.oy - xy[:, 1]) / self.cell])

    def to_map(self, cr: np.ndarray) -> np.ndarray:
        """Grid (column, row) → map (x, y)."""
        return np.column_stack([self.ox + cr[:, 0] * self.cell, self.oy - cr[:, 1] * self.cell])

    def sight_points(self) -> np.ndarray:
        """(k, 2) map points whose lines of sight stand for the disputed cells: the centres of
        the SIGHT_BLOCK × SIGHT_BLOCK blocks of cells that hold one (``self.block`` maps each
        disputed cell to its block's row)."""
        r, c = np.divmod(self.disputed, self.cover.shape[2])
        key = (r // SIGHT_BLOCK) * (self.cover.shape[2] // SIGHT_BLOCK + 1) + c // SIGHT_BLOCK
        uniq, self.block = np.unique(key, return_inverse=True)
        self.block = np.asarray(self.block).ravel()
        br, bc = np.divmod(uniq, self.cover.shape[2] // SIGHT_BLOCK + 1)
        h = SIGHT_BLOCK * self.cell
        return np.column_stack([self.ox + (bc + 0.5) * h, self.oy - (br + 0.5) * h])

    def corner_points(self) -> np.ndarray:
        """(k, 2) map points of the photos' vertices as drawn, in :meth:`corner_votes`' order
        (none above MAX_CORNER_VERTICES)."""
        pts = [c for _, c in self.corners]
        if not pts or sum(len(c) for c in pts) > MAX_CORNER_VERTICES:
            return np.zeros((0, 2))
        return self.to_map(np.vstack(pts))

    def disputed_points(self) -> np.ndarray:
        """(k, 2) map centres of the disputed cells."""
        r, c = np.divmod(self.disputed, self.cover.shape[2])
        return np.column_stack([self.ox + (c + 0.5) * self.cell, self.oy - (r + 0.5) * self.cell])

    def share(self, seen: Optional[np.ndarray], weights: Optional[np.ndarray] = None) -> np.ndarray:
        """(rows, cols) weighted share of the photos that see a cell whose polygons cover it.
        ``seen`` (photos, disputed cells) bool: the line of sight test of the disputed cells
        (None: every photo sees every cell); a disputed cell no photo sees is voted on by all.
        ``weights`` (photos,): the weight of each photo's vote (default 1)."""
        k = len(self.cover)
        w = np.ones(k) if weights is None else np.asarray(weights, np.float64)
        if self._votes is None or self._seen is not seen:
            cov = self.cover.reshape(k, -1)
            c = cov[:, self.disputed]
            sn = np.ones_like(c) if seen is None else seen.copy()
            sn[:, ~sn.any(axis=0)] = True
            self._votes = (cov.astype(np.float64), (c & sn).astype(np.float64),
                           sn.astype(np.float64))
            self._seen = seen
        cov, got, sn = self._votes
        self.weights, self.seen = w, sn
        out = (w @ cov) / max(float(w.sum()), 1e-300)
        if len(self.disputed):
            den = w @ sn
            out[self.disputed] = np.where(den > 0, (w @ got) / np.maximum(den, 1e-300), 0.0)
        return out.reshape(self.cover.shape[1:])

    def robust_share(self, seen: Optional[np.ndarray], rounds: int = ROBUST_ROUNDS) -> np.ndarray:
        """:meth:`share`, reweighted: each photo's weight is the IoU (on the grid) of its
        polygons with the last majority region, so that a view far from the others (partly
        hidden, clipped or misplaced) loses its say. ``rounds`` reweightings, for groups of at
        least ROBUST_MIN_PHOTOS photos (with fewer, no view can be told an outlier)."""
        share = self.share(seen)
        k = len(self.cover)
        cov = self.cover.reshape(k, -1)
        for _ in range(rounds if k >= ROBUST_MIN_PHOTOS else 0):
            m = (share > 0.5).ravel()
            if not m.any():
                break
            inter = (cov & m).sum(axis=1)
            union = (cov | m).sum(axis=1)
            w = inter / np.maximum(union, 1)
            if not w.sum() > 0:
                break
            share = self.share(seen, w)
        return share

    def outline(self, share: np.ndarray):
        """(exterior ring (k, 2) map units, shapely polygon) of the region where ``share`` > ½,
        at sub-cell precision; (None, None) when there is none.

        The region's boundary is the zero level of the *vote's median distance*: at a cell
        centre, the weighted median (the weights and lines of sight of the last :meth:`share`)
        of each photo's signed distance to its own outline (negative inside; continuous in the
        weights, see :meth:`median_distance`). Its sign is the vote's (more than half inside ⇔
        the median is negative) except near even splits, where the median decides (so an even
        number of noisy views does not shrink the outline), and along a straight edge it
        is linear, so the contour (marching squares, between cell centres) lies on the edge
        however the grid falls. Where more than half of the photos that see it put a vertex
        within one cell of one place (:meth:`corner_votes`), the outline has that vertex, at the
        median of theirs: corners stay corners. The outermost ring of the largest piece,
        simplified by ``SIMPLIFY`` cell."""
        import shapely
        from skimage.measure import find_contours
        inside = share > 0.5
        if not inside.any():
            return None, None
        field = self.median_distance(inside)
        polys = []
        for c in find_contours(field, 0.0):
            if len(c) < 4:
                continue
            p = shapely.Polygon(self.to_map(c[:, ::-1] + 0.5))
            if not p.is_valid:
                p = shapely.make_valid(p)
            polys += _flat_polygons(p)
        if not polys:
            return None, None
        best = max(polys, key=lambda p: p.area)
        ring = np.asarray(best.exterior.coords)[:-1]
        snapped = _snap(self.to_grid(ring), self.corner_votes(), SNAP_CELLS)
        if len(snapped) >= 3:             # a piece smaller than the snapping keeps its contour
            ring = self.to_map(snapped)
        best = shapely.Polygon(ring)
        if not best.is_valid:
            best = max(_flat_polygons(shapely.make_valid(best)), key=lambda p: p.area, default=None)
            if best is None:
                return None, None
        best = best.simplify(SIMPLIFY * self.cell)
        if best.geom_type != "Polygon" or best.is_empty:
            return None, None
        ring = np.asarray(best.exterior.coords)[:-1]
        # the ring's first vertex, which simplification keeps: dropped if on a straight edge
        if len(ring) > 3 and _point_segment_distance(ring[:1], ring[-1:], ring[1:2])[0, 0] \
                <= SIMPLIFY * self.cell:
            ring = ring[1:]
        return ring, shapely.Polygon(ring)

    def median_distance(self, inside: np.ndarray) -> np.ndarray:
        """(rows, cols) float: minus the weighted median signed distance (cells; positive
        inside) at the cells next to the region's boundary (a 4-neighbour on the other side),
        ±1 elsewhere. The region starts as ``inside`` (the vote) and takes the median's side
        where the two differ (near even splits), up to MEDIAN_ROUNDS times."""
        inside = inside.copy()
        for _ in range(MEDIAN_ROUNDS):
            cells = _boundary_cells(inside)
            if not len(cells):
                return np.where(inside, 1.0, -1.0)
            val = self._median_at(cells, inside.shape)
            flip = (val > 0) != inside.flat[cells]
            if not flip.any():
                break
            inside.flat[cells[flip]] = val[flip] > 0
        field = np.where(inside, 1.0, -1.0)
        cells = _boundary_cells(inside)
        if len(cells):
            val = self._median_at(cells, inside.shape)
            ins = inside.flat[cells]
            field.flat[cells] = np.where(ins, np.maximum(val, 1e-9), np.minimum(val, -1e-9))
        return field

    def _median_at(self, cells: np.ndarray, shape) -> np.ndarray:
        """Minus the weighted median signed distance (cells) at the given flat cell indices."""
        rows, cols = shape
        k = len(self.cover)
        dist = self.edge_distances(cells, rows, cols)             # (cells, photos), ≤ DIST_CAP
        cov = self.cover.reshape(k, -1)[:, cells].T             # (cells, photos)
        signed = np.where(cov, -dist, dist)
        # the weights of the last vote: per photo, times its sight of the cell
        wt = self.cell_weights(cells)
        # the weighted median, continuous in the weights: each photo's value sits at the middle
        # of its share of the cumulated weight, interpolated at half the total (4 equal
        # weights: the mean of the 2nd and 3rd values); photos with no weight sort last
        order = np.argsort(np.where(wt > 0, signed, np.inf), axis=1)
        sv = np.take_along_axis(signed, order, axis=1)
        sw = np.take_along_axis(wt, order, axis=1)
        cw = np.cumsum(sw, axis=1)
        mid = cw - 0.5 * sw
        half = 0.5 * cw[:, -1:]
        j = np.argmax(mid >= half - 1e-12 * np.maximum(half, 1e-300), axis=1)
        j0 = np.maximum(j - 1, 0)
        rows_ = np.arange(len(cells))
        gap = mid[rows_, j] - mid[rows_, j0]
        frac = np.where((j > 0) & (gap > 0), (half[:, 0] - mid[rows_, j0]) / np.where(gap > 0, gap, 1.0), 1.0)
        med = sv[rows_, j0] + np.clip(frac, 0.0, 1.0) * (sv[rows_, j] - sv[rows_, j0])
        return np.where(np.isfinite(med), -med, 0.0)

    def cell_weights(self, cells: np.ndarray) -> np.ndarray:
        """(cells, photos) the weight of each photo's vote at the given flat cell indices: its
        weight in the last :meth:`share`, times whether it sees the cell."""
        k = len(self.cover)
        w = np.ones(k) if self.weights is None else self.weights
        wt = np.broadcast_to(w, (len(cells), k)).copy()
        if self.seen is not None and len(self.disputed):
            pos = np.searchsorted(self.disputed, cells)
            pos = np.minimum(pos, len(self.disputed) - 1)
            hit = self.disputed[pos] == cells
            wt[hit] *= self.seen[:, pos[hit]].T
        return wt

    def edge_distances(self, cells: np.ndarray, rows: int, cols: int) -> np.ndarray:
        """(cells, photos) distance (cells) of each given cell's centre to each photo's outline,
        capped at DIST_CAP. The median of capped distances is the capped median, and the median
        distance changes by at most one cell from a cell to its neighbour, so at the cells next
        to the region's boundary it is exact. The edges are cut into pieces of at most one cell
        and each piece is measured only to the cells within DIST_CAP of it."""
        a, b, seg_p = self.segments
        k = len(self.cover)
        out = np.full((len(cells), k), DIST_CAP)
        if not len(a):
            return out
        n = np.maximum(np.ceil(np.hypot(*(b - a).T)), 1).astype(np.int64)
        rep = np.repeat(np.arange(len(a)), n)
        step = (np.arange(len(rep)) - np.repeat(np.cumsum(n) - n, n)) / n[rep]
        d = (b - a)[rep]
        pa = a[rep] + step[:, None] * d
        pb = pa + d / n[rep][:, None]
        photo = seg_p[rep]
        lo = np.ceil(np.minimum(pa, pb) - DIST_CAP - 0.5).astype(np.int64)      # (col, row)
        hi = np.floor(np.maximum(pa, pb) + DIST_CAP - 0.5).astype(np.int64)
        where = np.full(rows * cols, -1, np.int64)
        where[cells] = np.arange(len(cells))
        span = int(np.ceil(2 * DIST_CAP)) + 2                 # stencil side: covers hi − lo + 1
        off = np.arange(span)
        oc, orow = [x.ravel() for x in np.meshgrid(off, off)]
        cc = lo[:, 0, None] + oc[None]
        rr = lo[:, 1, None] + orow[None]
        ok = (cc <= hi[:, 0, None]) & (rr <= hi[:, 1, None]) & (cc >= 0) & (rr >= 0) & \
            (cc < cols) & (rr < rows)
        piece, slot = np.nonzero(ok)
        flat = rr[piece, slot] * cols + cc[piece, slot]
        band = where[flat]
        keep = band >= 0
        piece, band, flat = piece[keep], band[keep], flat[keep]
        if not len(piece):
            return out
        q = np.column_stack([flat % cols + 0.5, flat // cols + 0.5])
        u = pb[piece] - pa[piece]
        v = q - pa[piece]
        t = np.clip((u * v).sum(axis=1) / np.maximum((u * u).sum(axis=1), 1e-300), 0.0, 1.0)
        dd = np.hypot(*(v - t[:, None] * u).T)
        np.minimum.at(out, (band, photo[piece]), dd)
        return out

    def corner_votes(self) -> np.ndarray:
        """(k, 2) grid points where more than half of the photos that see the place (the
        weights and lines of sight of the last vote) put a vertex of their outline as drawn
        within one cell of each other: the median of those vertices (per coordinate), strongest
        first, none within one cell of another. A photo whose frame cuts the object off before
        the corner has no say on it."""
        if not self.corners:
            return np.zeros((0, 2))
        k = len(self.cover)
        pts = np.vstack([c for _, c in self.corners] + [np.zeros((0, 2))])
        ph = np.concatenate([np.full(len(c), p, np.int64) for p, c in self.corners] +
                            [np.zeros(0, np.int64)])
        if len(pts) < 2 or len(pts) > MAX_CORNER_VERTICES:
            return np.zeros((0, 2))
        from scipy.spatial import cKDTree
        pairs = cKDTree(pts).query_pairs(1.0, output_type="ndarray").reshape(-1, 2)
        n = len(pts)
        ii = np.concatenate([pairs[:, 0], pairs[:, 1], np.arange(n)])
        jj = np.concatenate([pairs[:, 1], pairs[:, 0], np.arange(n)])
        # per vertex and photo: the photo has a vertex within a cell
        support = np.zeros((n, k), bool)
        support[ii, ph[jj]] = True
        rows, cols = self.cover.shape[1:]
        cr = np.clip(np.floor(pts).astype(np.int64), 0, [cols - 1, rows - 1])
        wt = self.cell_weights(cr[:, 1] * cols + cr[:, 0])           # (n, photos)
        if self.corner_frame is not None and len(self.corner_frame) == n:
            fr = self.corner_frame | ~self.corner_frame.any(axis=1, keepdims=True)
            wt = wt * fr                            # as for cells: in no frame, all have a say
        score = (support * wt).sum(axis=1)
        strong = np.flatnonzero(score > 0.5 * wt.sum(axis=1))
        out = []
        if not len(strong):
            return np.zeros((0, 2))
        srt = np.argsort(ii, kind="stable")
        ii, jj = ii[srt], jj[srt]
        start = np.searchsorted(ii, np.arange(n + 1))
        taken = np.zeros(n, bool)             # within a cell of a corner already voted
        for i in strong[np.argsort(-score[strong], kind="stable")].tolist():
            if taken[i]:
                continue
            js = jj[start[i]:start[i + 1]]
            dj = np.hypot(*(pts[js] - pts[i]).T)
            pick = []
            for p in np.unique(ph[js]).tolist():      # each photo's nearest vertex
                m = ph[js] == p
                pick.append(js[m][np.argmin(dj[m])])
            out.append(np.median(pts[pick], axis=0))
            taken |= np.hypot(*(pts - out[-1]).T) <= 1.0
        return np.array(out).reshape(-1, 2)


def _boundary_cells(inside: np.ndarray) -> np.ndarray:
    """Flat indices of the cells with a 4-neighbour on the other side of ``inside``."""
    rows = inside.shape[0]
    edge = np.zeros_like(inside)
    for a, b in ((inside[1:], inside[:-1]), (inside[:, 1:], inside[:, :-1])):
        d = a != b
        if a.shape[0] != rows:
            edge[1:] |= d
            edge[:-1] |= d
        else:
            edge[:, 1:] |= d
            edge[:, :-1] |= d
    return np.flatnonzero(edge.ravel())


def _point_segment_distance(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(n, m) distances of points (n, 2) to segments a→b (m, 2)."""
    ab = b - a
    ap = pts[:, None, :] - a[None, :, :]
    den = np.maximum((ab * ab).sum(axis=1), 1e-300)
    t = np.clip((ap * ab[None]).sum(axis=2) / den[None], 0.0, 1.0)
    q = ap - t[:, :, None] * ab[None]
    return np.hypot(q[:, :, 0], q[:, :, 1])


def _snap(ring: np.ndarray, corners: np.ndarray, radius: float) -> np.ndarray:
    """``ring`` (n, 2, grid units) with each run of its vertices within ``radius`` of a corner
    (k, 2) replaced by that corner; a corner the ring passes more than once (a run that is not
    one cyclic stretch), or not at all, or whose snap would change the area by more than one
    cell, is left out."""
    for q in corners:
        near = np.hypot(*(ring - q).T) <= radius
        if not near.any() or near.all():
            continue
        start = int(np.argmin(near))                    # a vertex outside: the runs don't wrap
        ring, near = np.roll(ring, -start, axis=0), np.roll(near, -start)
        idx = np.flatnonzero(near)
        if idx[-1] - idx[0] + 1 != len(idx):
            continue
        new = np.vstack([ring[:idx[0]], q[None], ring[idx[-1] + 1:]])
        # a corner restores what the contour cut off it: a change of at most one cell of area
        if len(new) >= 3 and abs(_shoelace(new) - _shoelace(ring)) <= 1.0:
            ring = new
    return ring


def _shoelace(ring: np.ndarray) -> float:
    """Signed area of a ring (k, 2)."""
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _lines_of_sight(votes: List[_Vote], cams_of: List[List[int]], cams, recon, dsm,
                    prog) -> List[Optional[np.ndarray]]:
    """Per vote, (photos, disputed cells) bool: the cell, on the DSM surface, is seen by the
    photo (in its frame, and not hidden: the line of sight from the camera centre meets the
    surface no earlier than one DSM pixel before the cell, as :mod:`.occlusion` tests it). A
    cell on DSM nodata is seen by none. Groups are taken in chunks of about RAYS_AT_ONCE
    (cell, photo) pairs, so memory stays bounded."""
    surface = dsm.ray_surface()
    tol = _tolerance(recon, dsm.tif, dsm.crs)
    C = np.array([c.C for c in cams], np.float64).reshape(-1, 3)
    pairs = np.array([len(v.disputed) * len(c) // 2 if v.cover is not None else 0
                      for v, c in zip(votes, cams_of)], np.int64)
    out: List[Optional[np.ndarray]] = []
    start, total, done = 0, max(int(pairs.sum()), 1), 0
    while start < len(votes):
        stop = start + max(1, int(np.searchsorted(np.cumsum(pairs[start:]), RAYS_AT_ONCE)))
        out += _sight_chunk(votes[start:stop], cams_of[start:stop], cams, C, recon, dsm,
                            surface, tol)
        done += int(pairs[start:stop].sum())
        start = stop
        prog.set(100.0 * done / total)
    return out


def _sight_chunk(votes, cams_of, cams, C, recon, dsm, surface, tol):
    """:func:`_lines_of_sight` for a few groups: each disputed cell is tested for being in the
    photo's frame at its own centre (a block's centre would give a photo that the frame cuts a
    say on the cells just beyond its edge, and cut the object's corner there), each block of
    cells for being on the line of sight at the block's centre (traced where one of its cells
    is in the frame)."""
    live = [v for v in votes if v.cover is not None]
    bxy = [v.sight_points() for v in live]
    cxy = [v.disputed_points() for v in live]
    vxy = [v.corner_points() for v in live]
    n_ph = np.array([len(c) for v, c in zip(votes, cams_of) if v.cover is not None], np.int64)
    cams_l = [np.asarray(c, np.int64) for v, c in zip(votes, cams_of) if v.cover is not None]
    in_frame = _in_frame([np.vstack([a, b]) for a, b in zip(cxy, vxy)], cams_l, cams, recon, dsm)
    for v, a, fr in zip(live, cxy, in_frame):      # the drawn vertices': for the corner votes
        v.corner_frame = fr[:, len(a):].T
    in_frame = [fr[:, :len(a)] for a, fr in zip(cxy, in_frame)]  # per group (photos, cells)
    # the blocks to trace: a cell of the block in the frame of the photo
    bsz = np.array([len(a) for a in bxy], np.int64)
    pair_blk, pair_cam, todo_g = [], [], []
    for g, (v, fr) in enumerate(zip(live, in_frame)):
        want = np.zeros((len(cams_l[g]), len(bxy[g])), bool)
        ph, cell = np.nonzero(fr)
        want[ph, v.block[cell]] = True
        pair_blk.append(want)
    allb = np.vstack(bxy) if len(bxy) else np.zeros((0, 2))
    z = dsm.heights(allb[:, 0], allb[:, 1]) if len(allb) else np.zeros(0)
    ok = np.isfinite(z)
    model = np.full((len(allb), 3), np.nan)
    if ok.any():
        model[ok] = recon.to_model(np.column_stack([allb, z])[ok], dsm.crs)
    off = np.concatenate([[0], np.cumsum(bsz)])
    for g, want in enumerate(pair_blk):
        ph, blk = np.nonzero(want & ok[off[g]:off[g + 1]][None, :])
        todo_g.append((ph, blk))
        pair_cam.append(cams_l[g][ph])
    blk = np.concatenate([off[g] + t[1] for g, t in enumerate(todo_g)] + [np.zeros(0, np.int64)])
    cam = np.concatenate(pair_cam + [np.zeros(0, np.int64)])
    clear = np.zeros(len(blk), bool)
    if len(blk):
        o = C[cam]
        d = model[blk] - o
        dist = np.linalg.norm(d, axis=1)
        hits = first_hits(surface, recon.frame, o, d / dist[:, None],
                          max_distance=np.maximum(dist - tol, 0.0))
        clear = hits.status != HIT
    out, k = [], 0
    for g, (ph, b) in enumerate(todo_g):
        sight = np.zeros((n_ph[g], bsz[g]), bool)
        sight[ph, b] = clear[k:k + len(ph)]
        k += len(ph)
        out.append(in_frame[g] & sight[:, live[g].block])
    it = iter(out)
    return [next(it) if v.cover is not None else None for v in votes]


def _in_frame(xy: List[np.ndarray], cams_of: List[np.ndarray], cams, recon, dsm) -> List[np.ndarray]:
    """Per group, (photos of the group, points) bool: the map point, at the DSM's height there,
    projects into the photo's frame (False on DSM nodata)."""
    sizes = np.array([len(a) for a in xy], np.int64)
    allxy = np.vstack(xy) if len(xy) else np.zeros((0, 2))
    z = dsm.heights(allxy[:, 0], allxy[:, 1]) if len(allxy) else np.zeros(0)
    xyz = np.column_stack([allxy, z])
    start = np.concatenate([[0], np.cumsum(sizes)])
    # each photo gets the points of the groups it belongs to, no others
    groups_of = {}
    for g, c in enumerate(cams_of):
        for j, cam in enumerate(c.tolist()):
            groups_of.setdefault(cam, []).append((g, j))
    out = [np.zeros((len(c), s), bool) for c, s in zip(cams_of, sizes.tolist())]
    for cam, gj in groups_of.items():
        idx = np.concatenate([np.arange(start[g], start[g + 1]) for g, _ in gj])
        idx = idx[np.isfinite(z[idx])]
        if not len(idx):
            continue
        st = recon.project_points(xyz[idx], dsm.crs, cameras=[cams[cam]]).status[0] == INSIDE
        hit = np.zeros(len(allxy), bool)
        hit[idx[st]] = True
        for g, j in gj:
            out[g][j] = hit[start[g]:start[g + 1]]
    return out


@renamed_parameters(photos="cameras", dsm_crs="source_crs")
def fuse_views(shapes: List[ForwardShape], recon, dsm, *, cameras: Optional[Sequence[str]] = None,
               nms_iou: float = 0.5, group_iou: float = 0.15, group_overlap: float = 0.6,
               max_distance: Optional[float] = None,
               min_visible: float = 0.5, occlusion: bool = True, visibility: bool = True,
               source_crs=None, progress=None) -> List[FusedObject]:
    """Fuse forward-projected detections into one map object per real object (the steps: the
    module docstring).

    Parameters
    ----------
    shapes : list of ForwardShape
        The detections, forward-projected photo by photo (:func:`forward_project`), with their
        labels and scores.
    recon : Reconstruction
        The opened project the shapes were projected with.
    dsm : DSM, GeoTiff or path
        The DSM the shapes were projected on: heights and the expected-views test; its CRS must
        be that of the shapes.
    cameras : sequence of str, optional
        Labels of every photo searched, also those without a detection (default: the photos of
        ``shapes``).
    nms_iou : float
        Within a photo, a detection whose map IoU with a kept one exceeds this is suppressed.
    group_iou : float
        Detections of different photos are grouped from this map IoU.
    group_overlap : float
        …or when this share of the smaller one lies in the other.
    max_distance : float, optional
        The largest distance between grouped centroids, map units (default: half the mean
        equivalent diameter of the pair).
    min_visible : float
        A photo is expected to see an object when this share (0–1) of it is in its frame and
        visible.
    occlusion : bool
        Test lines of sight on the DSM for the expected views.
    visibility : bool
        A photo votes only on the cells it can see; False: every photo votes on every cell.
    source_crs : CRS, optional
        The CRS to assume for the DSM, instead of the one its GeoKeys give.
    progress : callable or Progress, optional
        Called with the percent done (0–100).

    Returns
    -------
    list of FusedObject
        One per object: the outline, position, views, scores and confidence.
    """
    import shapely
    for name, v in (("nms_iou", nms_iou), ("group_iou", group_iou),
                    ("group_overlap", group_overlap)):
        if not 0.0 < v <= 1.0:
            raise EasyIDPError(f"{name} must be in (0, 1], not {v}.")
    prog = as_progress(progress)
    dsm = as_dsm(dsm, source_crs)
    polys = [f for f in shapes if f.kind == "polygon"]
    geoms = shapely_polygons(polys)
    ok = [i for i, g in enumerate(geoms) if g is not None and g.area > 0]
    scores = [f.score if f.score is not None else 1.0 for f in polys]
    keys = [(f.photo, f.label) for f in polys]
    kept = sorted(_nms(ok, geoms, scores, keys, nms_iou))
    prog.set(15)
    if not kept:
        return []
    kg = [geoms[i] for i in kept]
    areas = shapely.area(kg)
    cent = shapely.get_coordinates(shapely.centroid(kg))
    size = np.sqrt(areas)                    # equivalent diameter (× √π/2), map units
    tree = shapely.STRtree(kg)
    a, b = tree.query(kg, predicate="intersects")
    sel = a < b
    a, b = a[sel], b[sel]
    lab = np.array([polys[i].label for i in kept], object)
    pho = np.array([polys[i].photo for i in kept], object)
    same = (lab[a] == lab[b]) & (pho[a] != pho[b]) if len(a) else np.zeros(0, bool)
    a, b = a[same], b[same]
    if len(a):
        # cheap tests first: IoU ≥ group_iou needs the area ratio ≥ group_iou and the gate;
        # the part link needs the boxes' overlap ≥ group_overlap of the smaller area
        gate = np.full(len(a), float(max_distance)) if max_distance else \
            0.25 * (size[a] + size[b])
        near = np.hypot(*(cent[a] - cent[b]).T) <= gate
        small = np.minimum(areas[a], areas[b])
        near &= small >= group_iou * np.maximum(areas[a], areas[b])
        box = shapely.bounds(np.array(kg, object))
        bw = np.minimum(box[a, 2], box[b, 2]) - np.maximum(box[a, 0], box[b, 0])
        bh = np.minimum(box[a, 3], box[b, 3]) - np.maximum(box[a, 1], box[b, 1])
        maybe_part = np.clip(bw, 0, None) * np.clip(bh, 0, None) >= group_overlap * small
        test = near | maybe_part
        a, b, near, small = a[test], b[test], near[test], small[test]
        # nearest pairs first, in batches; a pair already joined by earlier links is not
        # intersected (only the components matter)
        srt = np.argsort(np.hypot(*(cent[a] - cent[b]).T), kind="stable")
        a, b, near, small = a[srt], b[srt], near[srt], small[srt]
        g = np.array(kg, object)
        uf = _UnionFind(len(kept))
        for k0 in range(0, len(a), LINK_BATCH):
            sl = slice(k0, k0 + LINK_BATCH)
            ra, rb = uf.roots(a[sl]), uf.roots(b[sl])
            todo = np.flatnonzero(ra != rb) + k0
            if not len(todo):
                continue
            inter = shapely.area(shapely.intersection(g[a[todo]], g[b[todo]]))
            iou = inter / (areas[a[todo]] + areas[b[todo]] - inter)
            link = ((iou >= group_iou) & near[todo]) | (inter >= group_overlap * small[todo])
            uf.union(a[todo[link]], b[todo[link]])
        comp = uf.roots(np.arange(len(kept)))
    else:
        comp = np.arange(len(kept))
    prog.set(30)
    groups = {}
    for k, c in enumerate(comp.tolist()):
        groups.setdefault(c, []).append(k)
    groups = list(groups.values())
    # the vote of each group's photos, then the lines of sight of its disputed cells
    cam_index = {c.label: j for j, c in enumerate(recon.select_cameras(
        list(dict.fromkeys(polys[i].photo for i in kept))))}
    cams = recon.select_cameras(list(cam_index))
    votes, cams_of, photos_of = [], [], []
    for members in groups:
        photos_g = list(dict.fromkeys(polys[kept[k]].photo for k in members))
        where = {p: j for j, p in enumerate(photos_g)}
        votes.append(_Vote([kg[k] for k in members], [where[polys[kept[k]].photo] for k in members],
                           len(photos_g), [_drawn_vertices(polys[kept[k]]) for k in members]))
        cams_of.append([cam_index[p] for p in photos_g])
        photos_of.append(photos_g)
    seen = _lines_of_sight(votes, cams_of, cams, recon, dsm, prog.sub(30, 50)) if visibility \
        else [None] * len(votes)
    out: List[FusedObject] = []
    rings = []
    for g_i, (members, vote, photos_g) in enumerate(zip(groups, votes, photos_of)):
        sn, seen[g_i] = seen[g_i], None
        fs = [polys[kept[k]] for k in members]
        ring, outline = vote.outline(vote.robust_share(sn)) if vote.cover is not None else (None, None)
        vote.cover = vote._votes = vote._seen = None          # memory: one group at a time
        if ring is None:                      # no majority region: the best-scored view
            best = max(members, key=lambda k: scores[kept[k]])
            outline = max(_flat_polygons(kg[best]), key=lambda p: p.area)
            ring = np.asarray(outline.exterior.coords)[:-1]
        a_scale = _mean([f.area_m2 / kg[k].area for f, k in zip(fs, members)])
        p_scale = _mean([f.perimeter_m / kg[k].length for f, k in zip(fs, members)])
        sc = [f.score for f in fs if f.score is not None]
        c = outline.centroid
        out.append(FusedObject(
            fs[0].label, [[ring]], photos_g, len(photos_g), all(f.complete for f in fs),
            float(outline.area * a_scale), float(outline.length * p_scale),
            float(np.mean(sc)) if sc else None, fs, position=(c.x, c.y, float("nan")),
            mean_score=float(np.mean(sc)) if sc else None,
            max_score=float(np.max(sc)) if sc else None))
        rings.append(ring)
    prog.set(60)
    # heights from the DSM: outline vertices and the position
    allxy = np.vstack(rings + [np.array([o.position[:2] for o in out])])
    z = dsm.heights(allxy[:, 0], allxy[:, 1])
    k = 0
    ring_z = []
    for o, r in zip(out, rings):
        rz = z[k:k + len(r)].copy()
        k += len(r)
        if not np.isfinite(rz).all():     # off the DSM or on nodata: the heights it has, else
            known = rz[np.isfinite(rz)]   # the members' (their rays hit the DSM)
            if not len(known):
                known = np.concatenate([p[np.isfinite(p[:, 2]), 2] for f in o.members
                                        for p in f.rings if len(p)] + [np.zeros(0)])
            rz[~np.isfinite(rz)] = float(np.median(known)) if len(known) else 0.0
        o.parts = [[np.column_stack([r, rz])]]
        ring_z.append(rz)
    for o, zz, rz in zip(out, z[k:], ring_z):
        zz = zz if np.isfinite(zz) else float(np.median(rz))
        o.position = (float(o.position[0]), float(o.position[1]), float(zz))
    out, rings, ring_z = _attach_lone_views(out, rings, ring_z, recon, dsm.crs)
    # expected views: the photos searched that could have seen each object
    searched = list(dict.fromkeys(cameras if cameras is not None else [f.photo for f in polys]))
    rois = ROISet([ROI(str(j), [[r]], z=[[rz]]) for j, (r, rz) in enumerate(zip(rings, ring_z))],
                  crs=dsm.crs)
    seen_by = _could_see(rois, [set(o.photos) for o in out], recon, searched, dsm, occlusion,
                         min_visible, prog.sub(60, 100))
    for o, sb in zip(out, seen_by):
        o.expected_views = e = len(sb | set(o.photos))     # a photo that found it could see it
        o.confidence = float((o.mean_score if o.mean_score is not None else 1.0) * o.views / e)
    prog.set(100)
    return out


def _could_see(rois: ROISet, found: List[set], recon, searched, dsm, occlusion: bool,
               min_visible: float, prog) -> List[set]:
    """Per ROI (the fused outlines), the photos searched that could have seen it: at least
    ``min_visible`` of it in the frame and, with ``occlusion``, not hidden, as
    :func:`.backward.back_project` decides with its default samples. Faster, same rule: the
    photos in ``found`` (that found it) are not tested; the others are tested with
    COARSE_SAMPLES lines of sight first, and again with the full OCCLUSION_SAMPLES where the
    coarse share lies within COARSE_MARGIN of ``min_visible`` or the frame cuts the outline
    (few coarse samples lie inside it)."""
    bp = back_project(rois, recon, heights="geometry", cameras=searched, occlusion_dsm=None,
                      min_visible=min_visible, progress=prog.sub(0, 40))
    roi, cam = bp.roi.astype(np.int64), bp.photo_index.astype(np.int64)
    labels = bp.photo_labels
    todo = np.array([labels[c] not in found[r] for r, c in zip(roi.tolist(), cam.tolist())], bool)
    seen = ~todo
    if occlusion and todo.any():
        by_label = {c.label: c for c in recon.cameras}
        cams = [by_label[lab] for lab in labels]
        idx = np.flatnonzero(todo)
        occ, _ = occluded_fractions(rois, roi[idx], cam[idx], recon, cams, dsm, COARSE_SAMPLES,
                                    progress=prog.sub(40, 80))
        share = bp.visible_fraction[idx] * (1.0 - np.nan_to_num(occ, nan=0.0))
        # near the threshold, or cut by the frame (few coarse samples inside it): in full
        unsure = (np.abs(share - min_visible) < COARSE_MARGIN) | (bp.visible_fraction[idx] < 1.0)
        if unsure.any():
            j = idx[unsure]
            occ2, _ = occluded_fractions(rois, roi[j], cam[j], recon, cams, dsm, OCCLUSION_SAMPLES,
                                         progress=prog.sub(80, 100))
            share[unsure] = bp.visible_fraction[j] * (1.0 - np.nan_to_num(occ2, nan=0.0))
        seen[idx] = share >= min_visible
    else:
        seen |= todo
    out = [set() for _ in found]
    for r, c in zip(roi[seen].tolist(), cam[seen].tolist()):
        out[r].add(labels[c])
    return out


def _attach_lone_views(out, rings, ring_z, recon, crs):
    """Objects of one view whose detection, in its photo, has an IoU of at least ATTACH_IOU
    with the outline of a nearby object of the same label seen in other photos, projected into
    that photo, join that object (best IoU first, one view per photo): its views, photos,
    members and scores, not its outline. On the map such a view can lie far off: the part of
    the object its photo cannot see is drawn on what hides it. Returns (objects, rings,
    ring heights) without the views that joined."""
    import shapely
    lone = [i for i, o in enumerate(out) if o.views == 1]
    multi = [i for i, o in enumerate(out) if o.views > 1]
    lone_set = set(lone)
    if not lone or not multi:
        return out, rings, ring_z
    mg = np.array([shapely.Polygon(rings[i]) for i in multi], object)
    lg = np.array([shapely.Polygon(rings[i]) for i in lone], object)
    reach = np.sqrt(shapely.area(lg)) + np.sqrt(np.median(shapely.area(mg)))
    a, b = shapely.STRtree(mg).query(shapely.buffer(lg, reach), predicate="intersects")
    pairs = [(lone[x], multi[y]) for x, y in zip(a.tolist(), b.tolist())
             if out[lone[x]].label == out[multi[y]].label
             and out[lone[x]].photos[0] not in out[multi[y]].photos]
    by_photo = {}
    for i, j in pairs:
        by_photo.setdefault(out[i].photos[0], []).append((i, j))
    found = []                                    # (IoU, lone, object)
    for photo, pp in by_photo.items():
        cam = recon.select_cameras([photo])[0]
        ids = list(dict.fromkeys([i for i, _ in pp] + [j for _, j in pp]))
        xyz = {i: (out[i].members[0].rings[0] if i in lone_set
                   else np.column_stack([rings[i], ring_z[i]])) for i in ids}
        allp = np.vstack([xyz[i] for i in ids])
        proj = recon.project_points(allp, crs, cameras=[cam])
        uv, ok = proj.pixels[0], proj.status[0] == INSIDE
        sensor = recon.sensors[cam.sensor_id]
        frame = shapely.box(0, 0, sensor.width, sensor.height)
        px, k = {}, 0
        for i in ids:
            n = len(xyz[i])
            if n < 3 or not np.isfinite(uv[k:k + n]).all():
                pass
            elif i in lone_set:   # the detection: its vertices that hit the DSM, back in the photo
                px[i] = shapely.make_valid(shapely.Polygon(uv[k:k + n]))
            elif ok[k:k + n].any():
                px[i] = shapely.make_valid(shapely.Polygon(uv[k:k + n])).intersection(frame)
            k += n
        pp = [(i, j) for i, j in pp if i in px and j in px]
        if not pp:
            continue
        ga = np.array([px[i] for i, _ in pp], object)
        gb = np.array([px[j] for _, j in pp], object)
        inter = shapely.area(shapely.intersection(ga, gb))
        iou = inter / np.maximum(shapely.area(ga) + shapely.area(gb) - inter, 1e-300)
        found += [(v, i, j) for v, (i, j) in zip(iou.tolist(), pp) if v >= ATTACH_IOU]
    joined = set()
    for _, i, j in sorted(found, reverse=True):
        o, lv = out[j], out[i]
        if i in joined or lv.photos[0] in o.photos:
            continue
        joined.add(i)
        o.photos.append(lv.photos[0])
        o.views += 1
        o.members += lv.members
        o.complete = o.complete and lv.complete
        sc = [f.score for f in o.members if f.score is not None]
        if sc:
            o.score = o.mean_score = float(np.mean(sc))
            o.max_score = float(np.max(sc))
    keep = [k for k in range(len(out)) if k not in joined]
    return [out[k] for k in keep], [rings[k] for k in keep], [ring_z[k] for k in keep]


def _drawn_vertices(f: ForwardShape) -> np.ndarray:
    """(k, 2) map x, y of a shape's vertices as drawn (not densified) that hit the DSM."""
    xy = [p[(st == HIT) & o, :2] for p, st, o in zip(f.points, f.status, f.original)]
    return np.vstack(xy) if xy else np.zeros((0, 2))


def _mean(values) -> float:
    """Mean of the finite values; NaN when there is none."""
    v = np.asarray(values, np.float64)
    v = v[np.isfinite(v)]
    return float(v.mean()) if len(v) else float("nan")


def _flat_polygons(g) -> list:
    """The polygons inside any shapely geometry (collections and multi-parts flattened)."""
    import shapely
    return [p for p in shapely.get_parts(shapely.get_parts(g)) if p.geom_type == "Polygon"
            and not p.is_empty]


class _UnionFind:
    """Connected components of ``n`` nodes, links added in batches."""

    def __init__(self, n: int):
        self.parent = np.arange(n)

    def _root(self, i: int) -> int:
        p = self.parent
        while p[i] != i:
            p[i] = p[p[i]]
            i = p[i]
        return i

    def roots(self, idx: np.ndarray) -> np.ndarray:
        return np.array([self._root(i) for i in np.asarray(idx).tolist()], np.int64)

    def union(self, a: np.ndarray, b: np.ndarray) -> None:
        for x, y in zip(np.asarray(a).tolist(), np.asarray(b).tolist()):
            rx, ry = self._root(x), self._root(y)
            if rx != ry:
                self.parent[rx] = ry


__all__ = ["fuse_views", "FusedObject"]
