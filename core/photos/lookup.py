"""Finding a project's raw photos on disk: the one lookup every tool uses.

A photo is known by its **key**, :func:`photo_key`: the file name of a POSIX or Windows path,
lower-cased, without a photo extension. ``DJI_0018``, ``DJI_0018.JPG``, ``dji_0018.jpg`` and
``C:\\Flights\\A\\DJI_0018.JPG`` are one photo; so are an OpenSfM shot key without extension
(``100_0005_0018``) and ``100_0005_0018.tif``.

:func:`resolve_photos` finds the file of each camera: in the given photos folders (each searched
with its subfolders) when there are any, else at the path the project stores, else (the photo
renamed in another case, a shot key without its extension) by key in that path's folder.
"""
import ntpath
import os
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Tuple, Union

from ..errors import InputError
from ..naming import unique_names

PHOTO_EXTENSIONS = (".jpg", ".jpeg", ".tif", ".tiff", ".png", ".dng", ".jp2", ".webp", ".bmp")
"""Photo file extensions (lower case), in the order preferred when one folder holds a photo
under several (DJI's ``.JPG`` beside its ``.DNG``)."""


def file_name(path: str) -> str:
    """The last component of a POSIX or Windows path (``C:\\a\\DJI_0001.JPG`` → ``DJI_0001.JPG``)."""
    return ntpath.basename(str(path).replace("\\", "/").rstrip("/")) if path else ""


def photo_key(name: str) -> str:
    """The key a photo is matched by: file name, lower case, photo extension dropped."""
    base = file_name(name).lower()
    stem, ext = os.path.splitext(base)
    return stem if ext in PHOTO_EXTENSIONS else base


def is_windows_path(path: str) -> bool:
    """A path written on Windows (``C:\\…``, ``C:/…``, ``\\\\server\\…``), not usable here."""
    return os.name != "nt" and bool(path) and (
        (len(path) > 2 and path[1] == ":" and path[0].isalpha() and path[2] in "\\/")
        or path.startswith("\\\\") or "\\" in path)


def _rank(path: str) -> int:
    ext = os.path.splitext(path)[1].lower()
    return PHOTO_EXTENSIONS.index(ext) if ext in PHOTO_EXTENSIONS else len(PHOTO_EXTENSIONS)


class PhotoFiles:
    """The files under one or more folders (with their subfolders; hidden ones skipped), by
    :func:`photo_key`: photos by their stem, other files by their whole name."""

    def __init__(self, folders: Union[str, os.PathLike, Sequence], recursive: bool = True):
        if isinstance(folders, (str, os.PathLike)):
            folders = [folders]
        self.folders = [Path(f) for f in folders]
        self.by_key: Dict[str, List[str]] = {}
        for folder in self.folders:
            if not folder.is_dir():
                raise InputError(f"The photos folder {folder} does not exist: choose the folder "
                                 "that holds the raw photos.")
            for root, dirs, files in os.walk(folder):
                dirs[:] = sorted(d for d in dirs if not d.startswith(".")) if recursive else []
                for name in sorted(files):        # any file: a photo of an unlisted type
                    if not name.startswith("."):     # (.ARW…) is then found by its full name
                        self.by_key.setdefault(photo_key(name), []).append(os.path.join(root, name))

    def __len__(self) -> int:
        return len(self.photos())

    def photos(self) -> List[str]:
        """The files with a photo extension (:data:`PHOTO_EXTENSIONS`), one per key."""
        return [p[0] for p in self.by_key.values()
                if os.path.splitext(p[0])[1].lower() in PHOTO_EXTENSIONS]

    def find(self, label: str, project_path: Optional[str] = None) -> Tuple[Optional[str], str]:
        """(path, "") of the photo of camera ``label`` (stored path ``project_path``), or
        (None, why). Among several files with the key: the one with the stored file name
        (any case), else the one in a folder of the stored folder's name, else, in one folder,
        the preferred extension; files in different folders that cannot be told apart are
        refused, naming them."""
        for key in dict.fromkeys(k for k in (photo_key(project_path or ""), photo_key(label)) if k):
            hits = self.by_key.get(key)
            if not hits:
                continue
            if len(hits) == 1:
                return hits[0], ""
            name = file_name(project_path or "").lower()
            same = [h for h in hits if os.path.basename(h).lower() == name]
            if len(same) == 1:
                return same[0], ""
            parent = file_name(ntpath.dirname((project_path or "").replace("\\", "/"))).lower()
            near = [h for h in (same or hits) if parent and
                    os.path.basename(os.path.dirname(h)).lower() == parent]
            if len(near) == 1:
                return near[0], ""
            pool = near or same or hits
            if len({os.path.dirname(h) for h in pool}) == 1:
                return min(pool, key=_rank), ""
            return None, (f"{file_name(project_path or '') or label} is ambiguous: "
                          f"{', '.join(pool[:4])} are all this photo; give the one folder it is in")
        where = ", ".join(str(f) for f in self.folders)
        return None, f"{file_name(project_path or '') or label} is not in {where} (nor its subfolders)"


def resolve_photos(labels: Sequence[str], project_paths: Sequence[Optional[str]],
                   folder=None) -> Tuple[Dict[str, str], Dict[str, str]]:
    """({label: path} of the photos found, {label: why missing}) for the cameras ``labels``.

    ``folder``: a folder or a list of folders to look in instead of the stored paths (with
    their subfolders, by :func:`photo_key`). Raises :class:`InputError` when a folder does not
    exist or holds none of the photos. Without it, the stored path; if that file is not there,
    a file with the same key in the same folder (renamed case, missing extension).
    """
    found, missing = {}, {}
    if folder is not None and folder != [] and folder != "":
        files = PhotoFiles(folder)
        for label, path in zip(labels, project_paths):
            hit, why = files.find(label, path)
            if hit:
                found[label] = hit
            else:
                missing[label] = why
        if not found and labels:
            sample = ", ".join(sorted(os.path.basename(p) for p in files.photos()
                                      or [q[0] for q in files.by_key.values()])[:5])
            raise InputError(f"The photos folder {', '.join(str(f) for f in files.folders)} "
                             f"holds none of the project's {len(labels)} photos (looked for "
                             f"e.g. {file_name(project_paths[0] or '') or labels[0]}; it has "
                             f"{sample or 'no files'}). Choose the folder of this project's "
                             "raw photos.")
        return found, missing
    folders: Dict[str, Optional[PhotoFiles]] = {}
    for label, path in zip(labels, project_paths):
        if not path:
            missing[label] = "the project stores no path for it (give the photos folder)"
            continue
        if os.path.isfile(path):
            found[label] = path
            continue
        if is_windows_path(path):
            missing[label] = (f"{path} is a Windows path, not found on this computer (give the "
                              "photos folder: photos are then found by file name)")
            continue
        parent = os.path.dirname(path)
        if parent not in folders:
            folders[parent] = PhotoFiles(parent, recursive=False) if os.path.isdir(parent) else None
        hit = None
        if folders[parent] is not None:
            hit, _why = folders[parent].find(label, path)
        if hit:
            found[label] = hit
        elif folders[parent] is None:
            missing[label] = (f"{path} not found: its folder {parent} does not exist (the photos "
                              "moved? give the photos folder)")
        else:
            missing[label] = f"{path} not found (the photo moved or was deleted? give the photos folder)"
    return found, missing


def photo_stems(labels: List[str]) -> List[str]:
    """Safe, unique file stems for photo labels (``DJI_0001.JPG`` → ``DJI_0001``)."""
    stems = []
    for lab in labels:
        stem, ext = os.path.splitext(lab)
        stems.append(stem if ext.lower() in PHOTO_EXTENSIONS else lab)
    return unique_names(stems)
