"""Forward projection of the polygons of many photos, merged: what *Forward-project photo
polygons* runs (one call: photos → map polygons)."""
from dataclasses import dataclass, field
from typing import List

from ..annotations import POLYGON
from ..progress import as_progress
from .forward import forward_project
from ..raster import DSM
from .map_polygon import MapPolygon
from .merge import merge_views


@dataclass
class PhotosToMap:
    """The merged map polygons, the shapes that are not polygons (skipped) and the photos read."""
    polygons: List[MapPolygon]
    skipped: int = 0
    photos: List[str] = field(default_factory=list)


def forward_project_photos(items, recon, dsm: DSM, merge: str = "none", densify=True, *,
                           progress=None, is_cancelled=None) -> PhotosToMap:
    """Forward-project the polygons of annotated photos onto the DSM, photo by photo, and merge
    the views of each object.

    Lines and points are counted in ``skipped``. A cancellation stops after the current photo;
    what was projected is merged.

    Parameters
    ----------
    items : list of (PhotoAnnotations, camera)
        The annotations of each photo with its camera, as :func:`read_annotations` gives them.
    recon : Reconstruction
        The opened project.
    dsm : DSM
        The DSM the rays meet.
    merge : {"none", "union", "best", "fuse"}
        How the views of one object are merged (:func:`merge_views`; ``"fuse"`` uses the project
        and the DSM, :func:`fuse_views`).
    densify : bool or float
        As :func:`forward_project`: True a vertex every few pixels along edges, a number that
        spacing in pixels, 0 or False off.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).

    Returns
    -------
    PhotosToMap
        The polygons on the map, the photos used and what was skipped.
    """
    prog = as_progress(progress, is_cancelled)
    shapes, skipped = [], 0
    for k, (ann, cam) in enumerate(items):
        if prog.cancelled():
            break
        polys = [s for s in ann.shapes if s.kind == POLYGON]
        skipped += len(ann.shapes) - len(polys)
        shapes += forward_project(polys, cam, recon, dsm, densify=densify or False,
                                  is_cancelled=prog.cancelled)
        prog.set(100.0 * (k + 1) / max(len(items), 1))
    photos = [cam.label for _, cam in items]
    merged = merge_views(shapes, merge, recon=recon, dsm=dsm, cameras=photos) \
        if merge == "fuse" else merge_views(shapes, merge)
    return PhotosToMap(merged, skipped, photos)
