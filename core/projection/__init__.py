"""Projection between raw photos and the map.

* :mod:`.ray_surface`: the exact first hit of rays on a DSM, shared by forward projection,
  occlusion and orthorectification.
* :mod:`.forward`: shapes on a raw photo → the map (``forward_project``).
* :mod:`.merge`: the same object seen in several photos → one map polygon.
"""
from .forward import ForwardShape, densify_ring, forward_project
from .merge import MERGE_MODES, MapPolygon, merge_views
from .ray_surface import HIT, LEFT, MISS, NODATA, DSMSurface, RayHits, first_hits

__all__ = ["DSMSurface", "RayHits", "first_hits", "HIT", "MISS", "LEFT", "NODATA",
           "ForwardShape", "forward_project", "densify_ring", "MapPolygon", "merge_views",
           "MERGE_MODES"]
