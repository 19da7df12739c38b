"""Which raw photos see this point or these plots, and where a photo's pixel lands on the map:
the queries of the photo viewer (issue 37), with the project and the ground read once and kept.

A query is one call of :func:`~core.projection.back_project`, with the settings *Back-project
ROIs* uses by default, so the viewer lists and ranks the photos as that tool does (score, view
angle, GSD, visible and occluded share; see :mod:`.ranking`). A clicked point is a square ROI of
:data:`POINT_SIDE` metres around it. Pixels follow the project convention (x = column, y = row,
origin at the top-left corner of the photo; ``docs/background/conventions.md``).
"""
from typing import Optional, Sequence, Tuple

import numpy as np

from ..crs import as_crs, same_crs, transform_columns, transformer
from ..errors import EasyIDPError
from ..raster import as_dsm, first_hits
from ..roi import ROI, ROISet
from .backward import back_project
from .result import BackProjection

POINT_SIDE = 0.5
"""Side (metres) of the square ROI a clicked point stands for."""

POINT_SAMPLES = 16
"""Occlusion samples of a clicked point's square (a plot takes Back-project ROIs' 256)."""

METRES_PER_DEGREE = 111_320.0


class PhotoFinder:
    """A photogrammetry project and its ground, kept for many queries.

    Parameters
    ----------
    recon : Reconstruction
        The project (``core.reconstruction.open_reconstruction``).
    dsm : DSM, GeoTiff or str, optional
        The surface: vertex heights and the occlusion test of every query, and where a pixel's
        ray lands (:meth:`map_point`). Its tiles stay cached between queries.
    ground : float, optional
        Without a DSM: one ground height, in the project's vertical reference (no occlusion
        test).
    distortion, occlusion, min_visible, max_views
        As *Back-project ROIs* (defaults: its defaults).
    """

    def __init__(self, recon, *, dsm=None, ground: Optional[float] = None,
                 distortion: bool = True, occlusion: bool = True, min_visible: float = 0.5,
                 max_views: int = 0):
        if dsm is None and ground is None:
            raise EasyIDPError("The photo finder needs a DSM or a ground height.")
        self.recon = recon
        self.dsm = as_dsm(dsm) if dsm is not None else None
        self.ground = None if ground is None else float(ground)
        self.distortion, self.occlusion = bool(distortion), bool(occlusion)
        self.min_visible, self.max_views = float(min_visible), int(max_views)

    @property
    def heights(self):
        """The height source of the queries: the DSM, else the ground height."""
        return self.dsm if self.dsm is not None else self.ground

    def rois(self, rois: ROISet, *, occlusion_samples: int = 256, progress=None,
             is_cancelled=None) -> BackProjection:
        """The photos that see each ROI, ranked: one :func:`back_project` call
        (``occlusion_samples`` per ROI, as there)."""
        return back_project(rois, self.recon, heights=self.heights, distortion=self.distortion,
                            clip=True, occlusion_dsm=self.dsm if self.occlusion else None,
                            min_visible=self.min_visible, max_views=self.max_views,
                            occlusion_samples=occlusion_samples, progress=progress,
                            is_cancelled=is_cancelled)

    def point(self, x: float, y: float, crs=None, *, side: float = POINT_SIDE,
              name: str = "point", is_cancelled=None) -> BackProjection:
        """The photos that see the map point (``x``, ``y``) in ``crs`` (default: the DSM's, else
        the project's): a square ROI of ``side`` metres around it (in degrees for a geographic
        CRS), its occlusion tested at :data:`POINT_SAMPLES` points."""
        if crs is not None:
            crs = as_crs(crs)
        else:
            crs = self.dsm.crs if self.dsm is not None else self.recon.crs
        h = side / 2.0
        if crs is not None and crs.is_geographic:
            h /= METRES_PER_DEGREE
        ring = np.array([[x - h, y - h], [x + h, y - h], [x + h, y + h], [x - h, y + h]])
        return self.rois(ROISet([ROI(name, [[ring]])], crs), occlusion_samples=POINT_SAMPLES,
                         is_cancelled=is_cancelled)

    def map_points(self, photo: str, pixels: Sequence[Sequence[float]],
                   crs=None) -> np.ndarray:
        """Where the pixels (column, row) of ``photo`` land on the ground: (n, 3) x, y, z in
        ``crs`` (default: the DSM's, else the project's; heights in its vertical reference), NaN where a ray misses the DSM. With a
        ground height instead of a DSM: on the level surface at that height."""
        cam = self.recon.select_cameras([photo])[0]
        uv = np.asarray(pixels, np.float64).reshape(-1, 2)
        origin, d = self.recon.pixel_to_ray(cam, uv, self.distortion)
        if self.dsm is not None:
            surface = self.dsm.ray_surface()
            xyz = first_hits(surface, self.recon.frame, origin, d).xyz
            source = surface.crs
        else:
            xyz, source = self._on_level(origin, d), self.recon.crs
        out = as_crs(crs) if crs is not None else None
        ok = np.isfinite(xyz).all(axis=1)
        if out is None or source is None or same_crs(out, source) or not ok.any():
            return xyz
        moved = xyz.copy()
        moved[ok] = np.column_stack(transform_columns(transformer(source, out), *xyz[ok].T))
        return moved

    def map_point(self, photo: str, column: float, row: float,
                  crs=None) -> Optional[Tuple[float, float, float]]:
        """:meth:`map_points` of one pixel: (x, y, z), or None where its ray misses."""
        xyz = self.map_points(photo, [[column, row]], crs)[0]
        return tuple(float(v) for v in xyz) if np.isfinite(xyz).all() else None

    def _on_level(self, origin: np.ndarray, d: np.ndarray) -> np.ndarray:
        """Rays (model frame) to the level surface z = ground of the project's CRS: the
        height along a ray is nearly linear over a flight's distances; two secant steps."""
        h = self.ground
        t0, t1 = np.zeros(len(origin)), np.ones(len(origin))
        for _ in range(3):
            z0 = self.recon.from_model(origin + t0[:, None] * d)[:, 2]
            z1 = self.recon.from_model(origin + t1[:, None] * d)[:, 2]
            slope = np.where(z1 != z0, z1 - z0, np.nan) / (t1 - t0)
            t_new = t0 + (h - z0) / slope
            t0, t1 = t_new, t_new + np.maximum(np.abs(t_new) * 1e-3, 1e-3)
        t0[~(t0 > 0)] = np.nan                                # behind the camera, or level
        return self.recon.from_model(origin + t0[:, None] * d)
