"""Crop a point cloud by many ROIs in one pass and write one file per ROI.

A point belongs to an ROI when its (x, y) is inside the polygon by the even-odd rule over all
rings (holes and multipart honoured; see ``geometry.points_in_rings``) and, if given,
z_min ≤ z ≤ z_max. ROIs are reprojected to the cloud's CRS; ROIs without a CRS are taken to be in
the cloud's frame. A point inside several overlapping ROIs goes to each of them.
"""
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple, Union

import numpy as np

from .. import geometry
from ..deprecation import renamed_parameters
from ..errors import Cancelled, InputError
from ..naming import unique_names
from ..progress import as_progress
from ..roi import ROISet
from .cloud import PointCloud
from ..files import OutputFolder
from .formats import read_point_cloud, write_point_cloud
from .index import one_pass

EXT = {"las": ".las", "laz": ".laz", "ply": ".ply"}


def cloud_name(cloud: PointCloud) -> str:
    return repr(cloud.path.name) if cloud.path is not None else "the point cloud"


def as_cloud(cloud: Union[PointCloud, str, Path], crs=None) -> PointCloud:
    """A :class:`PointCloud` from a cloud or a path (read with ``crs``)."""
    return cloud if isinstance(cloud, PointCloud) else read_point_cloud(cloud, crs)


def rois_in_cloud_crs(cloud: PointCloud, rois: ROISet) -> ROISet:
    """The validated ROIs in the cloud's CRS (unchanged when the ROIs have no CRS)."""
    rois.validate()
    if rois.crs is None:
        return rois
    if cloud.crs is None:
        raise InputError(f"Point cloud {cloud_name(cloud)} has no coordinate reference system "
                         "(a PLY file, or a LAS file without a CRS record): give its CRS "
                         "(INPUT_CRS in QGIS, crs= in Python).")
    return rois.to_crs(cloud.crs)


def roi_boxes(rois: ROISet) -> np.ndarray:
    return np.array([r.bounds for r in rois], dtype=np.float64).reshape(-1, 4)


def crop_indices(cloud: PointCloud, rois: ROISet, z_min: Optional[float] = None,
                 z_max: Optional[float] = None, progress=None, is_cancelled=None,
                 chunk_size: int = 2_000_000) -> Tuple[List[np.ndarray], np.ndarray, ROISet]:
    """One pass: ascending point indices inside each ROI (in ROI order), the cloud's xy bounds
    (xmin, ymin, xmax, ymax) and the ROIs in the cloud CRS."""
    prog = as_progress(progress, is_cancelled)
    rois = rois_in_cloud_crs(cloud, rois)
    rings = [r.rings for r in rois]
    idx, bounds = one_pass(cloud, roi_boxes(rois),
                           lambda k, x, y: geometry.points_in_rings(x, y, rings[k]),
                           (z_min, z_max), prog, chunk_size)
    return idx, bounds, rois


@dataclass
class CropItem:
    """One ROI's outcome: ``status`` is 'written', 'empty' (over the cloud, no point inside) or
    'missed' (entirely outside the cloud's extent); ``stem`` is its unique safe file stem."""
    name: str
    stem: str
    count: int
    status: str
    file: Optional[Path] = None


@dataclass
class CloudCropResult:
    """What a crop did, one :class:`CropItem` per ROI in ROI order. The dict views are keyed by
    the unique file stem (the ROI name itself when it is unique and file-safe)."""
    folder: Optional[Path]
    items: List[CropItem] = field(default_factory=list)

    @property
    def counts(self) -> Dict[str, int]:
        return {i.stem: i.count for i in self.items}

    @property
    def files(self) -> Dict[str, Path]:
        return {i.stem: i.file for i in self.items if i.file is not None}

    @property
    def missed(self) -> List[str]:
        return [i.name for i in self.items if i.status == "missed"]

    @property
    def empty(self) -> List[str]:
        return [i.name for i in self.items if i.status == "empty"]

    @property
    def messages(self) -> List[str]:
        out = []
        if self.missed:
            out.append(f"{len(self.missed)} ROI(s) lie outside the point cloud and were skipped: "
                       f"{', '.join(self.missed)}. Check that the ROIs and the cloud are in the "
                       "right CRS.")
        if self.empty:
            out.append(f"{len(self.empty)} ROI(s) contain no point (check the Z range or the "
                       f"cloud's holes): {', '.join(self.empty)}.")
        return out


def _status(roi, ii: np.ndarray, bounds: np.ndarray) -> str:
    if len(ii):
        return "written"
    x0, y0, x1, y1 = roi.bounds
    outside = (not np.all(np.isfinite(bounds)) or x1 < bounds[0] or x0 > bounds[2]
               or y1 < bounds[1] or y0 > bounds[3])
    return "missed" if outside else "empty"


@renamed_parameters(crs="source_crs")
def crop_point_cloud(cloud: Union[PointCloud, str, Path], rois: ROISet,
                     output_folder: Union[str, Path], fmt: str = "same",
                     z_min: Optional[float] = None, z_max: Optional[float] = None,
                     write_empty: bool = False, source_crs=None, overwrite: bool = False,
                     progress=None, is_cancelled=None,
                     chunk_size: int = 4_000_000) -> CloudCropResult:
    """Crop a point cloud by every ROI: one file per ROI.

    Files are named from the ROI names (safe and unique) and written atomically; LAS → LAS/LAZ
    copies the point records bit for bit with the source header. The folder is checked and
    locked first (:class:`..files.OutputFolder`). On cancellation every file this call wrote is
    removed and :class:`Cancelled` is raised.

    Parameters
    ----------
    cloud : PointCloud or path
        The point cloud, or a .las/.laz/.ply path.
    rois : ROISet
        The ROIs.
    output_folder : str or path
        The folder the crops are written into.
    fmt : {"same", "las", "laz", "ply"}
        The output format; ``"same"`` is the input's (LAS for an in-memory cloud).
    z_min, z_max : float, optional
        Only the points in this Z range are kept.
    write_empty : bool
        Also write a file for an ROI that holds no point.
    source_crs : CRS, optional
        The cloud's CRS when it is a path (required for PLY; overrides the LAS record).
    overwrite : bool
        Replace this run's earlier outputs; without it an existing file stops the run before
        writing, listing the names taken. The input is never replaced.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    chunk_size : int
        Points read per chunk (memory bound).

    Returns
    -------
    CloudCropResult
        One :class:`CropItem` per ROI in ROI order.
    """
    prog = as_progress(progress, is_cancelled)
    cloud = as_cloud(cloud, source_crs)
    fmt = (fmt or "same").lower()
    if fmt == "same":
        fmt = cloud.fmt if cloud.fmt in EXT else "las"
    if fmt not in EXT:
        raise InputError(f"Output format {fmt!r} is not supported: use same, las, laz or ply.")
    with OutputFolder(output_folder, overwrite=overwrite, inputs=[cloud.path]) as out:
        stems = unique_names(r.name for r in rois)
        out.check_not_inputs(s + EXT[fmt] for s in stems)       # before any work
        idx, bounds, rois = crop_indices(cloud, rois, z_min, z_max, prog.sub(0, 50), None,
                                         chunk_size)
        result = CloudCropResult(out.folder, [CropItem(r.name, s, len(ii), _status(r, ii, bounds))
                                         for r, s, ii in zip(rois, stems, idx)])
        todo = [(item, ii) for item, ii in zip(result.items, idx)
                if len(ii) or (write_empty and item.status == "empty")]
        targets = out.claim(item.stem + EXT[fmt] for item, _ in todo)
        _write(cloud, [(item, t, ii) for (item, ii), t in zip(todo, targets)], result,
               prog.sub(50, 100))
    return result


def _write(cloud: PointCloud, todo, result: CloudCropResult, prog) -> None:
    """Write each (item, target, point indices); on cancel remove what was written."""
    if todo and len(cloud.records) and any(len(ii) for _, _, ii in todo):
        # gather every kept record once, in file order, then serve each ROI from that copy:
        # a point's place in the copy is the count of kept points before it (a mark per point
        # and its running count, 5 bytes a point; one searchsorted per ROI cost 4× more)
        marked = np.zeros(len(cloud.records), bool)
        for _, _, ii in todo:
            marked[ii] = True
        kept = np.flatnonzero(marked)
        place = np.cumsum(marked, dtype=np.int64 if len(marked) >= 2**31 else np.int32)
        del marked
        place -= 1
        todo = [(item, t, place[ii]) for item, t, ii in todo]
        del place
        cloud = cloud.take_sorted(kept)
    try:
        for i, (item, target, ii) in enumerate(todo):
            prog.check()
            write_point_cloud(cloud, target, index=ii)
            item.file = target
            prog.set(100.0 * (i + 1) / len(todo))
    except Cancelled:
        for f in result.files.values():
            try:
                f.unlink()
            except FileNotFoundError:
                pass
        raise
