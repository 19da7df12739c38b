"""Preview sheets of the plot statistics: per ROI, the views used side by side with their values.

The tiles are those of the crop previews (:mod:`.photo_crops`: the view around the polygon, the
outside dimmed, the polygon in red), collected during the one pass over the photos for the best
``views`` candidates of each ROI (by rank, among those whose visible share reaches the minimum),
and composed once the statistics are known: a header with the ROI's across-view values, and
under each tile its photo, its values, its pixel count and occluded share. Views measured but
not used are left out. Text is drawn with Pillow's built-in font.
"""
import os
from typing import List

import numpy as np

from ..files import write_bytes
from ..naming import unique_names
from .photo_crops import PNG_FAST, PREVIEW_GAP, PreviewSheets
from .result import BackProjection

CAPTION_LINES = 3


class StatSheets(PreviewSheets):
    """Tiles of the candidate views, kept (spilled to disk beyond the cache) until the end."""

    def __init__(self, result: BackProjection, folder, views: int, min_visible: float,
                 max_images: int):
        names = unique_names(result.roi_names)
        super().__init__(result, os.fspath(folder), views, names)
        self.names = names
        share = result.visible_fraction * (1.0 - np.nan_to_num(result.occluded_fraction, nan=0.0))
        limit = max(1, views) if not max_images else max(1, min(views, max_images))
        self.wanted = {}
        count = {}
        for i in np.lexsort((result.rank, result.roi)):
            r = int(result.roi[i])
            if share[i] >= min_visible and count.get(r, 0) < limit:
                count[r] = count.get(r, 0) + 1
                self.wanted.setdefault(r, set()).add(int(i))

    def _ready(self, r: int):
        return []                       # composed at the end, when the values are known

    def write(self, stats) -> List[str]:
        """Write one sheet per ROI with a used view; returns the paths."""
        from PIL import Image, ImageDraw, ImageFont
        font = ImageFont.load_default()
        line = _line_height(font)
        primary = _primary(stats)
        out = []
        for r in sorted(self.tiles):
            tiles = self.tiles.pop(r)
            order = [i for i in sorted(tiles, key=lambda i: self.result.rank[i]) if stats.used[i]]
            if not order:
                continue
            arrays = []
            for i in order:
                t = tiles[i]
                arrays.append(np.load(t) if isinstance(t, str) else t)
            head = _roi_caption(stats, r, primary)
            caps = [_view_caption(stats, i, primary) for i in order]
            top = line + 2 * PREVIEW_GAP
            below = CAPTION_LINES * line + PREVIEW_GAP
            height = max(a.shape[0] for a in arrays)
            width = max(sum(a.shape[1] for a in arrays) + PREVIEW_GAP * (len(arrays) + 1),
                        font_width(font, _latin1(head)) + 2 * PREVIEW_GAP)
            sheet = np.full((top + height + below + PREVIEW_GAP, width, 3), 32, np.uint8)
            x = PREVIEW_GAP
            spots = []
            for a, cap in zip(arrays, caps):
                sheet[top:top + a.shape[0], x:x + a.shape[1]] = a
                spots.append((x, top + height + PREVIEW_GAP // 2, cap))
                x += a.shape[1] + PREVIEW_GAP
            im = Image.fromarray(sheet)
            draw = ImageDraw.Draw(im)
            draw.text((PREVIEW_GAP, PREVIEW_GAP), _latin1(head), fill=(255, 255, 255), font=font)
            for x, y, cap in spots:
                for k, text in enumerate(cap[:CAPTION_LINES]):
                    draw.text((x, y + k * line), _latin1(text), fill=(230, 230, 230), font=font)
            import imagecodecs
            path = os.path.join(self.folder, self.names[r] + ".png")
            write_bytes(path, imagecodecs.png_encode(np.asarray(im), **PNG_FAST))
            out.append(path)
        return sorted(out)


def _latin1(text: str) -> str:
    """Text Pillow's built-in bitmap font can draw (Latin-1; other characters become '?')."""
    return text.replace("—", "-").replace("–", "-").encode("latin-1", "replace").decode("latin-1")


def _line_height(font) -> int:
    try:
        box = font.getbbox("Ag")
        return int(box[3] - box[1]) + 4
    except AttributeError:              # very old Pillow
        return font.getsize("Ag")[1] + 4


def font_width(font, text: str) -> int:
    try:
        box = font.getbbox(text)
        return int(box[2] - box[0])
    except AttributeError:
        return font.getsize(text)[0]


def _primary(stats) -> List[str]:
    """The columns a caption shows: the cover index's mean (else the first band's), the cover."""
    cols = []
    for name in ([f"{stats.cover_index}_mean"] if stats.cover_index else []) + \
            [f"{b}_mean" for b in stats.bands[:1]]:
        if name in stats.columns:
            cols.append(name)
            break
    if "cover" in stats.columns:
        cols.append("cover")
    return cols


def _fmt(name: str, v: float) -> str:
    if not np.isfinite(v):
        return f"{name.replace('_mean', '')} -"
    return f"{name.replace('_mean', '')} {v:.3f}" if abs(v) < 100 else \
        f"{name.replace('_mean', '')} {v:.0f}"


def _roi_caption(stats, r: int, cols) -> str:
    parts = []
    for c in cols:
        q = stats.columns.index(c)
        parts.append(_fmt(c, stats.median[r, q]) + (f" (MAD {stats.mad[r, q]:.3f})"
                                                    if np.isfinite(stats.mad[r, q]) else ""))
    extra = f", disagreement {stats.disagreement[r]:.1f}" if np.isfinite(stats.disagreement[r]) else ""
    return (f"{stats.roi_names[r]}: " + ", ".join(parts) +
            f" — median of {int(stats.views[r])} view(s){extra}")


def _view_caption(stats, i: int, cols) -> List[str]:
    vals = "  ".join(_fmt(c, stats.values[i, stats.columns.index(c)]) for c in cols)
    occ = stats.occluded_share[i]
    occ_txt = f", occluded {100 * occ:.0f} %" if np.isfinite(occ) else ""
    return [f"{stats.photo[i]} (rank {int(stats.rank[i])})", vals,
            f"{int(stats.pixels[i]):,} px{occ_txt}"]
