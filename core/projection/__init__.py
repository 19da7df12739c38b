"""Projection between raw photos and the map: the exact first hit of rays on a DSM
(:mod:`.ray_surface`), shared by forward projection, occlusion and orthorectification."""
from .ray_surface import HIT, LEFT, MISS, NODATA, DSMSurface, RayHits, first_hits

__all__ = ["DSMSurface", "RayHits", "first_hits", "HIT", "MISS", "LEFT", "NODATA"]
