"""What a project reader is: its name, what it expects, whether a path is its, how it opens one.

Each reader module (``metashape.py``, ``odm.py``, ``opf.py``, ``photo_folder.py``, ``pix4d.py``)
defines one :class:`ProjectReader` named ``READER``; ``readers.py`` lists them in the order they
are asked.
"""
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, NamedTuple, Optional

from .model import Reconstruction


class OpenOptions(NamedTuple):
    """What ``open_reconstruction`` passes on to a reader's ``open``."""

    chunk: Any = None                 # Metashape chunk id or label; OpenSfM reconstruction index
    source_crs: Any = None            # the project's CRS where it has none usable
    camera_heights: str = "absolute"  # photos only
    takeoff_height: Optional[Any] = None  # photos only


@dataclass(frozen=True)
class ProjectReader:
    """One kind of project ``open_reconstruction`` reads.

    ``recognises(path)`` says, from names and folder layout only (no parsing), whether ``path``
    (a :class:`~pathlib.Path`) is this reader's; it may claim a path that does not exist (a
    ``.psx`` by its suffix) so that the reader's own message says what is missing.
    ``open(path, options)`` reads it (``options``: :class:`OpenOptions`). ``photo_tags``: the
    cameras come from the photos' own tags, so the reader also takes a list of photo paths and
    the camera-height options, and its sensors are not fitted to the photos afterwards.
    """

    name: str                                             # "Metashape"
    expects: str                                          # what to give, for the error message
    recognises: Callable[[Path], bool]
    open: Callable[[Path, OpenOptions], Reconstruction]
    photo_tags: bool = False

    def claims(self, path) -> bool:
        """Whether this reader takes ``path``: a :class:`~pathlib.Path`, or a list of photo paths
        (only a ``photo_tags`` reader takes those)."""
        if isinstance(path, (list, tuple)):
            return self.photo_tags
        return self.recognises(path)
