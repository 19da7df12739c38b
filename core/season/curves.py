"""Growth curves: one PNG of small multiples, drawn with matplotlib (no pyplot, no GUI backend,
so it works inside QGIS and on servers).

A panel per ROI (up to ``max_panels``), the main trait (a height) as a solid line on the left
axis and cover (%) dashed on the right axis; with groups (treatment, variety) the lines take the
group's colour. With more ROIs than panels and groups given, a panel per group: every ROI of the
group thin, the group's median bold. Without groups, the first ``max_panels`` ROIs, and the title
says so.
"""
import datetime as dt
import math
import warnings
from typing import Dict, List, Optional, Sequence

import numpy as np

from ..errors import EasyIDPError
from ..files import atomic_output, check_not_inputs
from .season import SeasonResult

MAX_PANELS = 48
PANEL_INCHES = (2.6, 1.9)
COLOURS = ("#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d",
           "#666666", "#1f78b4", "#b2df8a")


def main_trait(traits: Sequence[str]) -> Optional[str]:
    """The trait drawn first: the highest DSM height percentile, else the highest point-cloud
    one, else the first trait."""
    for prefix in ("height_p", "cloud_height_p"):
        hs = [t for t in traits if t.startswith(prefix)]
        if hs:
            return max(hs, key=lambda t: float(t[len(prefix):].replace("_", ".")))
    return traits[0] if traits else None


def plot_growth_curves(result: SeasonResult, path: str, groups: Optional[Dict[str, str]] = None,
                       trait: Optional[str] = None, max_panels: int = MAX_PANELS,
                       title: Optional[str] = None) -> str:
    """Write the growth curves of ``result`` to the PNG ``path`` (atomically).

    ``groups``: ROI name → group label (e.g. a treatment field), or None. ``trait``: the main
    trait (default :func:`main_trait`); cover is added on a second axis when present.
    """
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.dates import AutoDateLocator, ConciseDateFormatter
        from matplotlib.figure import Figure
    except ImportError as exc:
        raise EasyIDPError(f"Growth curves need matplotlib ({exc}): pip install matplotlib "
                           "(Debian/Ubuntu: apt install python3-matplotlib).") from None
    check_not_inputs(path, result.inputs)
    trait = trait or main_trait(result.traits)
    if trait is None:
        raise EasyIDPError("No trait has a value: there is nothing to draw.")
    second = "cover" if "cover" in result.traits and trait != "cover" else None
    table = result.table()
    dates = [_date(d) for d in result.dates]

    def series(name: str, t: str, scale: float = 1.0) -> List[float]:
        return [table.get((name, d), {}).get(t, math.nan) * scale for d in result.dates]

    names = [r.name for r in result.rois]
    group_names = sorted({groups.get(n, "") for n in names}) if groups else []
    colour = {g: COLOURS[k % len(COLOURS)] for k, g in enumerate(group_names)}
    by_group = bool(groups) and len(names) > max_panels
    if by_group:
        panels = [(g, [n for n in names if groups.get(n, "") == g]) for g in group_names][:max_panels]
    else:
        panels = [(n, [n]) for n in names[:max_panels]]
    ncols = min(len(panels), max(1, math.ceil(math.sqrt(len(panels) * 1.4))))
    nrows = math.ceil(len(panels) / ncols)
    fig = Figure(figsize=(PANEL_INCHES[0] * ncols, PANEL_INCHES[1] * nrows + 0.8), dpi=100)
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False)
    right_axes = []
    for ax, (label, members) in zip(axes.ravel(), panels):
        ax.set_title(label if len(str(label)) <= 24 else str(label)[:23] + "…", fontsize=8)
        ax2 = ax.twinx() if second else None
        if ax2 is not None:
            right_axes.append(ax2)
        for n in members:
            c = colour.get(groups.get(n, ""), COLOURS[0]) if groups else COLOURS[0]
            lw = 0.6 if by_group else 1.6
            ax.plot(dates, series(n, trait), "-o", color=c, lw=lw, ms=2.5 if not by_group else 0)
            if ax2 is not None and not by_group:
                ax2.plot(dates, series(n, second, 100.0), "--", color=c, lw=1.0, alpha=0.8)
        if by_group:
            with warnings.catch_warnings():   # all-NaN dates of a group: no point drawn
                warnings.simplefilter("ignore", RuntimeWarning)
                med = np.nanmedian([series(n, trait) for n in members], axis=0)
                ax.plot(dates, med, "-o", color=colour[label], lw=2.2, ms=3)
                if ax2 is not None:
                    cov = np.nanmedian([series(n, second, 100.0) for n in members], axis=0)
                    ax2.plot(dates, cov, "--", color=colour[label], lw=1.6)
        ax.tick_params(labelsize=7)
        if ax2 is not None:
            ax2.set_ylim(0, 100)
            ax2.tick_params(labelsize=7, colors="0.4")
    for ax in axes.ravel()[len(panels):]:
        ax.set_visible(False)
    for k, ax2 in enumerate(right_axes):   # cover labels on the last column only
        if (k + 1) % ncols and k + 1 != len(right_axes):
            ax2.set_yticklabels([])
    locator = AutoDateLocator(maxticks=4)
    for ax in axes.ravel():
        ax.xaxis.set_major_locator(locator)
        ax.xaxis.set_major_formatter(ConciseDateFormatter(locator))
        ax.xaxis.get_offset_text().set_fontsize(7)
    unit = " (m)" if "height" in trait else ""
    for ax in axes[:, 0]:
        ax.set_ylabel(trait + unit, fontsize=8)
    head = title or "Growth curves"
    what = f"{trait} (solid)" + (", cover % (dashed, right axis)" if second else "")
    if by_group:
        what += f"; a panel per group, median bold, {len(names)} ROIs"
    elif len(names) > len(panels):
        what += f"; the first {len(panels)} of {len(names)} ROIs"
    fig.suptitle(f"{head}: {what}", fontsize=9)
    if groups and not by_group:
        from matplotlib.lines import Line2D
        fig.legend([Line2D([], [], color=colour[g], lw=2) for g in group_names],
                   [g or "(none)" for g in group_names], loc="lower center",
                   ncol=min(len(group_names), 8), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0.04 if groups and not by_group else 0, 1, 0.97))
    with atomic_output(path) as tmp:
        fig.savefig(tmp, format="png")
    return path


def _date(text: str):
    return dt.datetime.fromisoformat(text) if "T" in text else dt.date.fromisoformat(text)
