"""File names from ROI names: safe on Windows, macOS and Linux, and unique in one folder."""
import re
from typing import Iterable, List

_BAD = re.compile(r'[<>:"/\\|?*\x00-\x1f]+')
_RESERVED = {"CON", "PRN", "AUX", "NUL", *(f"COM{i}" for i in range(1, 10)),
             *(f"LPT{i}" for i in range(1, 10))}


def safe_name(name: object, max_len: int = 120) -> str:
    """A file-system-safe stem for ``name``: forbidden characters become ``_``."""
    s = _BAD.sub("_", str(name)).strip().strip(".")
    s = s[:max_len].rstrip(" .")
    if not s:
        s = "roi"
    if s.split(".")[0].upper() in _RESERVED:
        s = "_" + s
    return s


def unique_names(names: Iterable[object]) -> List[str]:
    """Safe, unique stems (case-insensitively, for Windows and macOS): ``a``, ``a_2``, ``a_3``…"""
    out: List[str] = []
    seen = set()
    for name in names:
        base = safe_name(name)
        cand, k = base, 1
        while cand.lower() in seen:
            k += 1
            cand = f"{base}_{k}"
        seen.add(cand.lower())
        out.append(cand)
    return out
