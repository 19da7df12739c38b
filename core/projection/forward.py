"""Forward projection: shapes drawn or detected on a raw photo → the map, on the DSM.

Each vertex's pixel becomes a ray (``Reconstruction.pixel_to_ray``, lens distortion inverted)
whose first hit on the DSM (:func:`core.raster.first_hits`) is the vertex on the map: exact
on any terrain or canopy. Polygon and line edges are densified *in the photo* first, so that a
long edge follows the surface instead of cutting across it. A vertex whose ray misses the DSM,
leaves it or enters nodata is reported (``status``); its polygon is marked incomplete and keeps
only the vertices that hit, never silently reshaped.

Areas and perimeters are planimetric: measured in the model frame's horizontal plane at the
shape (true metres, free of map-projection scale), over all rings (holes subtract from the area
and add to the perimeter).
"""
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np

from .. import geometry
from ..annotations import LINE, POINT, POLYGON, PhotoShape
from ..crs import as_crs, same_crs, transform_columns, transformer
from ..deprecation import renamed_parameters
from ..errors import EasyIDPError
from ..progress import as_progress
from ..ragged import cyclic_next, offsets
from ..raster import HIT, STATUS_NAMES, as_dsm, first_hits

DENSIFY_PX = 4.0     # default spacing of densified vertices along edges, photo pixels


@dataclass
class ForwardShape:
    """One shape of a photo on the map.

    ``points``: per ring, (k, 3) map coordinates of every (densified) vertex, NaN where its ray
    did not hit; ``status``: per ring, (k,) uint8 ray status (``core.raster.HIT`` …);
    ``original``: per ring, (k,) bool, True for the vertices of the input shape (False for
    those added by densification). ``rings``: per ring, the vertices that hit (the geometry).
    ``area_m2``/``perimeter_m``: planimetric, NaN for lines and points or with < 3 vertices.
    ``view_angle``: degrees between the ray to the shape's centre and the vertical.
    """
    photo: str
    label: str
    kind: str
    points: List[np.ndarray]
    status: List[np.ndarray]
    original: List[np.ndarray]
    score: Optional[float] = None
    group_id: Optional[object] = None
    attributes: dict = field(default_factory=dict)
    area_m2: float = float("nan")
    perimeter_m: float = float("nan")
    view_angle: float = float("nan")
    pixel_area: float = float("nan")

    @property
    def rings(self) -> List[np.ndarray]:
        return [p[s == HIT] for p, s in zip(self.points, self.status)]

    @property
    def missing(self) -> int:
        """Number of vertices (densified ones included) whose ray did not hit the DSM."""
        return int(sum(int((s != HIT).sum()) for s in self.status))

    @property
    def complete(self) -> bool:
        return self.missing == 0

    def why_incomplete(self) -> str:
        counts = {}
        for s in self.status:
            for v in s[s != HIT].tolist():
                counts[STATUS_NAMES[v]] = counts.get(STATUS_NAMES[v], 0) + 1
        return ", ".join(f"{n} {k}" for k, n in sorted(counts.items()))


def _as_shapes(polygons_px) -> List[PhotoShape]:
    out = []
    for k, p in enumerate(polygons_px):
        if isinstance(p, PhotoShape):
            out.append(p)
            continue
        rings = [np.asarray(p, np.float64)] if np.ndim(p) == 2 else [np.asarray(r, np.float64) for r in p]
        for r in rings:
            if r.ndim != 2 or r.shape[1] != 2 or len(r) < 3:
                raise EasyIDPError(f"polygon {k}: rings must be (n ≥ 3, 2) arrays of pixels.")
        out.append(PhotoShape(str(k), POLYGON, rings))
    return out


@renamed_parameters(crs="output_crs")
def forward_project(polygons_px, photo, recon, dsm, densify=True, *, output_crs=None,
                    progress=None, is_cancelled=None) -> List[ForwardShape]:
    """Shapes in the pixels of one photo → the map, by their rays' first hits on the DSM.

    Photo pixels follow the one convention of [Conventions](../background/conventions.md).
    Heights are in the output CRS's vertical reference (the DSM's).

    Parameters
    ----------
    polygons_px : sequence
        :class:`PhotoShape` objects (polygons, lines, points; from the annotation readers) or
        plain polygons ((n, 2) pixel arrays, or lists of rings).
    photo : str or Camera
        The camera label (or a ``Camera``).
    recon : Reconstruction
        The opened project.
    dsm : DSM, GeoTiff or path
        A :class:`~core.raster.DSM` (its ray surface keeps the tiles read for the next call), a
        GeoTIFF path or an opened GeoTiff.
    densify : bool or float
        True: a vertex every :data:`DENSIFY_PX` pixels along edges; a number: that spacing in
        pixels; False: the vertices as given.
    output_crs : CRS, optional
        The CRS of the output (default: the DSM's).
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    list of ForwardShape
        One per shape, in the input order.
    """
    prog = as_progress(progress, is_cancelled)
    surface = as_dsm(dsm).ray_surface()
    cam = recon.select_cameras([photo])[0]
    recon.calibrated_sensor(cam)                 # a clear error for an uncalibrated sensor
    step = DENSIFY_PX if densify is True else float(densify or 0)
    shapes = _as_shapes(polygons_px)
    # all vertices of all shapes in one batch of rays
    parts, index = [], []
    for i, s in enumerate(shapes):
        for j, ring in enumerate(s.rings):
            if s.kind == POINT:
                pts, orig = np.asarray(ring, np.float64)[:1], np.ones(1, bool)
            else:
                pts = np.asarray(ring, np.float64)
                if len(pts) >= 2 and step > 0:
                    pts, _, orig = geometry.densify(pts, np.array([0, len(pts)]), step,
                                                    closed=s.kind == POLYGON)
                else:
                    pts, orig = pts.copy(), np.ones(len(pts), bool)
            parts.append(pts)
            index.append((i, j, orig))
    if not parts:
        return []
    uv = np.vstack(parts)
    if not np.all(np.isfinite(uv)):
        raise EasyIDPError(f"photo {cam.label}: some shape vertices are not finite numbers.")
    origin, d = recon.pixel_to_ray(cam, uv)
    hits = first_hits(surface, recon.frame, origin, d, progress=prog.sub(0, 90))
    xyz = hits.xyz
    out_crs = as_crs(output_crs)
    if out_crs is not None and surface.crs is not None and not same_crs(out_crs, surface.crs):
        ok = hits.hit
        if ok.any():
            x, y, z = transform_columns(transformer(surface.crs, out_crs), *xyz[ok].T)
            xyz = xyz.copy()
            xyz[ok] = np.column_stack([x, y, z])
    model = origin + np.where(hits.hit, hits.distance, np.nan)[:, None] * d
    # rings are consecutive runs of vertices: ring k is [start[k], start[k] + count[k])
    counts = np.array([len(p) for p in parts])
    starts = offsets(counts)[:-1]
    ring_shape = np.array([i for i, _, _ in index])
    ring_first = np.array([j == 0 for _, j, _ in index])
    vert_ring = np.repeat(np.arange(len(parts)), counts)
    vert_shape = ring_shape[vert_ring]
    hit = hits.status == HIT
    # per shape: centre of its hits, the vertical there, the view angle
    n_hit = np.bincount(vert_shape[hit], minlength=len(shapes))
    centre = np.column_stack([np.bincount(vert_shape[hit], model[hit, k], len(shapes))
                              for k in range(3)]) / np.maximum(n_hit, 1)[:, None]
    seen = n_hit > 0
    up = np.zeros((len(shapes), 3))
    if seen.any():
        up[seen] = recon.frame.up(centre[seen])
    ray = centre - origin
    with np.errstate(invalid="ignore"):
        cosang = -(ray * up).sum(axis=1) / np.linalg.norm(ray, axis=1)
    angle = np.where(seen, np.degrees(np.arccos(np.clip(cosang, -1, 1))), np.nan)
    # planimetric rings: hit vertices in the plane normal to the shape's vertical
    e1 = np.where(np.abs(up[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    e1 = e1 - (e1 * up).sum(axis=1, keepdims=True) * up
    e1 /= np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-300)
    e2 = np.cross(up, e1)
    hv = np.flatnonzero(hit)
    hr = vert_ring[hv]
    rel = model[hv] - centre[vert_shape[hv]]
    x = (rel * e1[vert_shape[hv]]).sum(axis=1)
    y = (rel * e2[vert_shape[hv]]).sum(axis=1)
    # the hit vertices of each ring, in order, as ragged rings
    ring_hits = np.bincount(hr, minlength=len(parts))
    hit_rings = offsets(ring_hits)
    nxt = cyclic_next(hit_rings)
    edge = np.bincount(hr, np.hypot(x[nxt] - x, y[nxt] - y), len(parts)) if len(hv) else np.zeros(len(parts))
    ok_ring = ring_hits >= 3
    planar = np.abs(geometry.ring_moments(np.column_stack([x, y]), hit_rings)[0])
    ring_area = np.where(ok_ring, planar, 0.0)
    signed = np.where(ring_first, ring_area, -ring_area)
    area = np.bincount(ring_shape, signed, len(shapes))
    perim = np.bincount(ring_shape, np.where(ok_ring, edge, 0.0), len(shapes))
    outer_ok = np.zeros(len(shapes), bool)
    outer_ok[ring_shape[ring_first]] = ok_ring[ring_first]
    result: List[ForwardShape] = []
    by_shape = [[] for _ in shapes]
    for k, (i, _, orig) in enumerate(index):
        by_shape[i].append((slice(starts[k], starts[k] + counts[k]), orig))
    for i, s in enumerate(shapes):
        sl = by_shape[i]
        f = ForwardShape(cam.label, s.label, s.kind, [xyz[a] for a, _ in sl],
                         [hits.status[a] for a, _ in sl], [o for _, o in sl],
                         s.score, s.group_id, dict(s.attributes), view_angle=float(angle[i]))
        if s.kind == POLYGON:
            if outer_ok[i]:
                f.area_m2, f.perimeter_m = float(area[i]), float(perim[i])
            f.pixel_area = abs(geometry.ring_area(np.asarray(s.rings[0], np.float64)))
        result.append(f)
    prog.set(100)
    return result


__all__ = ["ForwardShape", "forward_project", "DENSIFY_PX", "LINE", "POINT",
           "POLYGON"]
