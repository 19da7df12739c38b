"""A :class:`~.model.Reconstruction` read from the photos alone: one camera per photo from its
EXIF and XMP tags (:mod:`.photo_poses`), for photos flown without a photogrammetry project.

The map CRS is the UTM zone of the photos' mean position (WGS 84), or the ``crs`` given; the
model frame is that CRS minus the cameras' mean centre (:class:`~.geodesy.OffsetFrame`), with
the tags' heights taken as heights of that map. The notes say where every part came from and
how rough it is: the position's standard deviation (RTK or GNSS), the stated angle uncertainty
(:data:`~.photo_poses.ANGLE_STD_DEG`) and, per photo, what both amount to in pixels at the
ground (``Reconstruction.uncertainty_px``).
"""
import os
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
from pyproj import CRS

from ..crs import as_crs, transformer
from ..errors import InputError
from ..photos import PHOTO_EXTENSIONS, read_photo_tags
from .geodesy import OffsetFrame
from .model import Camera, Reconstruction, Sensor
from .photo_poses import ANGLE_STD_DEG, CAMERA_HEIGHTS, PhotoPose, gimbal_rotation, photo_pose
from .project_reader import OpenOptions, ProjectReader

__all__ = ["open_photos", "is_photo_input", "list_photo_files", "utm_crs", "convergence"]

WGS84 = CRS.from_epsg(4326)
TAGGED_EXTENSIONS = (".jpg", ".jpeg", ".tif", ".tiff")
"""Photo kinds whose tags are read (:func:`~..photos.read_photo_tags`)."""
PROJECT_MARKERS = (".p4d", ".psx", ".psz", ".opf")


def list_photo_files(folder: Path) -> List[Path]:
    """The JPEG and TIFF photos directly in ``folder`` (not its subfolders), sorted by name."""
    return sorted((p for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")
                   and p.suffix.lower() in TAGGED_EXTENSIONS), key=lambda p: p.name.lower())


def is_photo_input(path) -> bool:
    """A list of photo paths, or a folder that holds photos (or nothing at all) and no project
    file (no .p4d, .psx, .psz, .opf, Pix4D ``1_initial`` folder or params files)."""
    if isinstance(path, (list, tuple)):
        return True
    p = Path(path)
    if not p.is_dir():
        return False
    names = [n.lower() for n in os.listdir(p)]
    if any(n.endswith(PROJECT_MARKERS) or n.endswith("_pmatrix.txt") or n == "1_initial"
           for n in names):
        return False
    visible = [n for n in names if not n.startswith(".")]
    return any(n.endswith(PHOTO_EXTENSIONS) for n in visible) or not visible   # empty: say so


def utm_crs(lon: float, lat: float) -> CRS:
    """WGS 84 / UTM of the zone of (lon, lat) (the standard 6° zones; no Norway exceptions)."""
    zone = int(np.floor((lon + 180.0) / 6.0)) % 60 + 1
    return CRS.from_epsg((32600 if lat >= 0 else 32700) + zone)


def convergence(to_map, lon: float, lat: float) -> float:
    """Azimuth of true north in the map grid at (lon, lat), degrees clockwise from grid north."""
    d = 1e-5
    (x0, x1), (y0, y1) = to_map.transform([lon, lon], [lat - d, lat + d])
    return float(np.degrees(np.arctan2(x1 - x0, y1 - y0)))


def _short(paths: Sequence[str]) -> str:
    names = [os.path.basename(p) for p in paths]
    return ", ".join(names[:5]) + (f" and {len(names) - 5} more" if len(names) > 5 else "")


def open_photos(path: Union[str, os.PathLike, Sequence], crs=None, *,
                camera_heights: str = "absolute", takeoff_height=None) -> Reconstruction:
    """Cameras from the photos' own tags: a folder of JPEG/TIFF photos, or a list of paths.

    ``crs``: the map CRS (projected, metres); default the UTM zone of the photos.
    ``camera_heights``: ``"absolute"`` (the tags' GNSS altitude) or ``"relative"`` (DJI's
    ``RelativeAltitude`` + ``takeoff_height``). ``takeoff_height``: metres in the map's
    vertical, or a :class:`~..raster.DSM`: the DSM under the first photo (by name), for a flight
    whose first photo was taken over the take-off point. Raises :class:`~..errors.InputError`
    with one line per cause (no position, no attitude, no focal length, mixed cameras, no
    photos) naming the photos and the tags.
    """
    if camera_heights not in CAMERA_HEIGHTS:
        raise InputError(f"camera_heights {camera_heights!r} is not one of {', '.join(CAMERA_HEIGHTS)}.")
    if camera_heights == "relative" and takeoff_height is None:
        raise InputError("Heights above the take-off point need the take-off height "
                         "(takeoff_height: metres in the map's vertical, or a DSM).")
    if isinstance(path, (list, tuple)):
        files = [Path(p) for p in path]
        source = Path(os.path.commonpath([str(f.parent) for f in files])) if files else Path(".")
        for f in files:
            if not f.is_file():
                raise InputError(f"{f}: photo not found.")
    else:
        source = Path(path)
        files = list_photo_files(source)
    if not files:
        other = [n for n in os.listdir(source) if n.lower().endswith(PHOTO_EXTENSIONS)] \
            if source.is_dir() else []
        raise InputError(f"{source}: no JPEG or TIFF photos in this folder"
                         + (f" (only {_short(other)}, whose tags are not read)" if other else "")
                         + ": choose the folder that holds the drone's photos, or a project.")
    problems: List[Tuple[str, str]] = []
    poses: List[PhotoPose] = []
    tags = [read_photo_tags(f) for f in files]
    if camera_heights == "relative" and not isinstance(takeoff_height, (int, float)):
        takeoff_height = _ground_under_first(tags[0], takeoff_height)
    for t in tags:
        pose = photo_pose(t, camera_heights, takeoff_height, problems)
        if pose is not None:
            poses.append(pose)
    if problems:
        causes: Dict[str, List[str]] = {}
        for cause, p in problems:
            causes.setdefault(cause, []).append(p)
        raise InputError(f"{source}: cameras cannot be made from the photos' tags:\n" + "\n".join(
            f"- {cause}: {_short(paths)}" for cause, paths in causes.items()))
    kinds: Dict[str, List[str]] = {}
    for p in poses:
        kinds.setdefault(p.camera, []).append(p.path)
    if len(kinds) > 1:
        raise InputError(f"{source}: the photos come from {len(kinds)} cameras (EXIF Make, "
                         "Model and image size): " + "; ".join(
                             f"{k}: {_short(v)}" for k, v in kinds.items())
                         + ". Give each camera's photos as a folder of its own.")
    return _reconstruction(source, poses, as_crs(crs), takeoff_height)


def _ground_under_first(first, dsm) -> float:
    """The DSM height under the first photo's GPS position (the take-off point's ground)."""
    problems: List[Tuple[str, str]] = []
    pose = photo_pose(first, "absolute", None, problems)
    if pose is None:
        raise InputError(f"{first.path}: the first photo gives no position to read the DSM under "
                         f"({problems[0][0] if problems else 'no tags'}).")
    z = float(dsm.heights([pose.lon], [pose.lat], crs="EPSG:4326")[0])
    if not np.isfinite(z):
        raise InputError(f"{first.path}: the DSM {dsm.path} has no height under the first photo "
                         f"(lon {pose.lon:.6f}, lat {pose.lat:.6f}); give the take-off height "
                         "as a number.")
    return z


def _reconstruction(source: Path, poses: List[PhotoPose], crs: Optional[CRS],
                    takeoff: Optional[float]) -> Reconstruction:
    lon0 = float(np.mean([p.lon for p in poses]))
    lat0 = float(np.mean([p.lat for p in poses]))
    if crs is None:
        crs = utm_crs(lon0, lat0)
    elif not crs.is_projected:
        raise InputError(f"{crs.name}: cameras from photo tags need a projected CRS in metres "
                         "(the photos' UTM zone is used when none is given).")
    to_map = transformer(WGS84, crs)
    sensors: Dict[str, Sensor] = {}
    by_cal: Dict[object, str] = {}
    xyz = []
    for p in poses:
        x, y = to_map.transform(p.lon, p.lat)
        xyz.append((x, y, p.height))
    xyz = np.array(xyz, dtype=np.float64)
    offset = np.round(xyz.mean(axis=0))
    cameras: List[Camera] = []
    unc: Dict[str, float] = {}
    for p, c in zip(poses, xyz):
        key = (p.camera, p.calibration)
        if key not in by_cal:
            sid = str(len(by_cal))
            by_cal[key] = sid
            sensors[sid] = Sensor(sid, p.camera, p.size[0], p.size[1], p.calibration)
        label = Path(p.path).stem
        R = gimbal_rotation(p.yaw, p.pitch, p.roll, convergence(to_map, p.lon, p.lat))
        cameras.append(Camera(label, label, by_cal[key], photo_path=p.path, R=R, C=c - offset))
        unc[label] = _uncertainty_px(p)
    first = poses[0]
    rtk = sum("RTK" in p.position_source for p in poses)
    notes = [
        f"cameras from the photos' tags, not from a solved project: position from "
        f"{first.position_source.split(', RTK')[0]}"
        + (f" (RTK on {rtk} of {len(poses)} photos)" if rtk else "")
        + f"; height {first.camera_heights} ("
        + (f"DJI RelativeAltitude + the take-off height {takeoff:.2f} m"
           if first.camera_heights == "relative"
           else "DJI AbsoluteAltitude or EXIF GPSAltitude, used as heights of the map") + ")"
        + f"; attitude from {first.attitude_source}; interior from {first.interior_source}, "
        f"scaled to the stored size",
        "expected uncertainty: position {:.3g} m horizontal, {:.3g} m vertical (median standard "
        "deviation, from the tags); angles {:g}° (stated); in the photos {:.0f}–{:.0f} px "
        "(median {:.0f} px) at the ground".format(
            float(np.median([p.std_h for p in poses])), float(np.median([p.std_v for p in poses])),
            ANGLE_STD_DEG, min(unc.values()), max(unc.values()), float(np.median(list(unc.values())))),
    ]
    return Reconstruction(source=source, software="Photo tags", label=source.name, crs=crs,
                          frame=OffsetFrame(crs, offset), sensors=sensors, cameras=cameras,
                          notes=notes, uncertainty_px=unc)


def _uncertainty_px(p: PhotoPose) -> float:
    """One standard deviation (px) of where a ground point lands in the photo: the angle
    uncertainty as f·σθ, and the horizontal position's over the distance to the ground
    along the optical axis (the relative altitude over the cosine of the off-nadir angle, when
    the tags give it; else 100 m), added in quadrature."""
    f = p.calibration.f
    off_nadir = np.radians(90.0 + p.pitch)
    agl = p.relative_height if p.relative_height and p.relative_height > 1 else 100.0
    dist = agl / max(np.cos(off_nadir), 0.2)
    return float(f * np.hypot(np.radians(ANGLE_STD_DEG), p.std_h / dist))


# --- the reader of open_reconstruction (readers.py) ---------------------------------------------
def _open(path, options: OpenOptions) -> Reconstruction:
    return open_photos(path, options.source_crs, camera_heights=options.camera_heights,
                       takeoff_height=options.takeoff_height)


READER = ProjectReader("Photos", "a folder of JPEG/TIFF drone photos with no project file in "
                       "it, or a list of photo paths (cameras from their EXIF and XMP tags)",
                       is_photo_input, _open, photo_tags=True)
