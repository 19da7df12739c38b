"""A training-set folder holds what the plugin wrote there, and nothing else.

``training_set.json`` lists every file of the set (``files``: paths relative to the folder,
``/``-separated). A set written before that list (version 1) is known by its layout: the
images of its COCO files under ``images/``, ``labels/``, ``yolo_detect/`` and ``labelme/``.

An export into a folder, before writing anything:

1. removes the temporary files (``.part``) that killed runs left, in the folder and every
   subfolder;
2. refuses the folder if it holds a **foreign** file (one no set of the plugin lists), naming
   them: a trainer reading ``images/train`` would read it too (OS clutter such as
   ``.DS_Store`` and the run lock are ignored);
3. refuses a folder that holds a set unless ``overwrite``.

Then it writes ``training_set.json`` with ``"complete": false`` listing the old and the new
files together, so that a kill at any moment leaves only listed files (and ``.part`` files of a
dead process); writes the new files; removes the old set's files the new one does not have (and
the folders that this empties); and writes the final ``training_set.json``. An OVERWRITE
re-run after a kill therefore removes everything the killed run left.
"""
import json
import os
from pathlib import Path
from typing import Iterable, List, Set

from ..errors import InputError
from ..files import LOCK_NAME, is_part_name, remove_leftovers, write_json

MANIFEST = "training_set.json"
FORMAT = "easyidp-training-set"
VERSION = 2
CLUTTER = {".DS_Store", "Thumbs.db", "desktop.ini", LOCK_NAME}
SUBFOLDERS = ("images", "labels", "yolo_detect", "labelme", "coco")


def _rel(folder: Path, path: str) -> str:
    return Path(os.path.relpath(path, folder)).as_posix()


def _safe(rel: str) -> bool:
    """A listed path that stays inside the folder (never ``..`` or absolute)."""
    p = Path(rel)
    return bool(rel) and not p.is_absolute() and ".." not in p.parts and "\\" not in rel


def _v1_files(folder: Path) -> Set[str]:
    """The files of a version-1 set, from its layout and COCO files."""
    out = {MANIFEST, "data.yaml", "yolo_detect/data.yaml", "tiles.json"}
    for s in ("train", "val"):
        coco = f"coco/instances_{s}.json"
        out.add(coco)
        try:
            with open(folder / coco, encoding="utf-8") as fh:
                doc = json.load(fh)
            names = [str(im["file_name"]) for im in doc.get("images", [])]
        except (OSError, ValueError, KeyError, TypeError, AttributeError):
            continue
        for name in names:
            stem = os.path.splitext(name)[0]
            out.update({f"images/{s}/{name}", f"labels/{s}/{stem}.txt",
                        f"yolo_detect/images/{s}/{name}", f"yolo_detect/labels/{s}/{stem}.txt",
                        f"labelme/{s}/{stem}.json"})
    return out


class TrainingFolder:
    """The plan of one export into ``folder`` (an :class:`~core.files.OutputFolder`'s, locked)."""

    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self.leftovers: List[Path] = []
        for root, _, _ in os.walk(self.folder):
            self.leftovers += remove_leftovers(root)
        self.present = set()
        for root, dirs, files in os.walk(self.folder):
            dirs.sort()
            for name in files:
                if name in CLUTTER or is_part_name(name):
                    continue
                self.present.add(_rel(self.folder, os.path.join(root, name)))
        self.owned: Set[str] = set()
        self.incomplete = False
        man = self.folder / MANIFEST
        if MANIFEST in self.present:
            try:
                with open(man, encoding="utf-8") as fh:
                    doc = json.load(fh)
            except (OSError, ValueError):
                doc = None
            if isinstance(doc, dict) and doc.get("format") == FORMAT:
                listed = doc.get("files")
                if isinstance(listed, list):
                    self.owned = {str(p) for p in listed if isinstance(p, str) and _safe(p)}
                    self.owned.add(MANIFEST)
                else:
                    self.owned = _v1_files(self.folder)
                self.incomplete = doc.get("complete") is False
        self.foreign = sorted(self.present - self.owned)
        self.old = sorted(self.present & self.owned)

    def check(self, overwrite: bool) -> None:
        """Raise :class:`InputError` for foreign files, or for a set without ``overwrite``."""
        if self.foreign:
            shown = ", ".join(self.foreign[:10]) + \
                (f" and {len(self.foreign) - 10} more" if len(self.foreign) > 10 else "")
            raise InputError(
                f"The training set folder {str(self.folder)!r} holds {len(self.foreign)} file(s) "
                f"that EasyIDP did not write: {shown}. A trainer would read them with the set. "
                "Nothing was written or removed. Choose an empty folder, or move those files out.")
        if self.old and not overwrite:
            state = "an unfinished training set (a run was stopped)" if self.incomplete \
                else "a training set"
            raise InputError(
                f"The training set folder {str(self.folder)!r} already holds {state} of "
                f"{len(self.old)} file(s) ({', '.join(self.old[:3])} …). Nothing was written. "
                "Choose an empty folder, or allow replacing existing outputs (overwrite; in "
                "QGIS the advanced option 'Overwrite existing files'): the old set is removed.")

    def begin(self, names: Iterable[str]) -> None:
        """Record the old and the new files as the plugin's before writing any."""
        self.new = sorted({Path(n).as_posix() for n in names} | {MANIFEST})
        write_json(self.folder / MANIFEST, {"format": FORMAT, "version": VERSION,
                                            "complete": False,
                                            "files": sorted(set(self.old) | set(self.new))},
                   indent=1)

    def finish(self, manifest: dict) -> List[str]:
        """Remove the old set's files the new one has not, then write the final manifest
        (``manifest`` plus the file list). Returns the removed files (relative)."""
        stale = sorted(set(self.old) - set(self.new))
        dirs = set()
        for rel in stale:
            p = self.folder / rel
            try:
                os.remove(p)
            except FileNotFoundError:
                pass
            dirs.add(p.parent)
        for d in sorted(dirs, key=lambda q: -len(q.parts)):
            while self.folder in d.parents:
                try:
                    d.rmdir()
                except OSError:
                    break
                d = d.parent
        doc = dict(manifest, format=FORMAT, version=VERSION, complete=True, files=self.new)
        write_json(self.folder / MANIFEST, doc, indent=1)
        return stale
