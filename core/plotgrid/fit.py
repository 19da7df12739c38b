"""Fit a plot grid to the crop rows of an orthomosaic.

The crop is told from weeds, grass, lodged patches and soil by its structure, not by greenness
alone: rows at the planted spacing along the known row direction (:mod:`.fit_rows`).

1. **Vegetation image.** One sweep of the orthomosaic over the plots' box
   (:func:`.fit_image.read_vegetation`: ``core.raster.sweep``, ``core.indices``' ExG or NDVI and
   Otsu's threshold), averaged to at most ``fit_image.MAX_WORK_PIXELS`` pixels, as weights in
   [0, 1] between the soil and leaf levels. No vegetation: a clear error, nothing fitted.
2. **Crop rows.** The strongest peak of the power spectrum of the field, among periods under
   half a plot, gives the rows' direction and spacing. The rows run along the nearest grid
   axis; the angle between them is the first rotation.
3. **Global correction, from the plot block only.** (a) Along the rows, the row amplitude
   (the rows' component, coherent over a metre along them, less the other frequencies, so that
   grass, weeds and straight edges do not count) projected on that axis is correlated with the
   plots' own projection over spacing scales 0.95–1.05 and shifts within the search reach: all
   plots vote at once, and the margins, outside every plot, cannot win. Across the rows, where
   touching plots show no boundary, the middle of the crop's extent gives the shift, and then
   the phases of every plot's rows, by consensus (:func:`.fit_rows.row_consensus`), the offset
   and spacing across to a fraction of a row. (b) Each plot is then measured on its rows (4.),
   and a least-squares similarity (rotation, a spacing scale per axis, a shift) from the
   grid's plot centres to the measured ones, with bare plots and outliers (3 × the median
   residual) left out, is the global correction. (c) The plots are measured again from the
   windows (b) laid on the rows, each plot's vote now held near its place (within
   ``max_shift``), and the similarity fitted again: that is the global correction, and that
   measurement each plot's own.
4. **Per plot** (:func:`.fit_rows.measure_plots`, :mod:`.fit_ends`), each plot is centred on
   its rows: across the rows, on the rows' positions (the phase, at the row period, of the
   median along the rows at each offset across, so that weeds, lodged patches and missing
   segments, each on a minority of a row's length, do not pull it; the plot's centre is on a
   row or midway between two, whichever the plots agree on); along the rows, on the row ends
   (each row's two ends give two estimates of the plot's middle given the crop length the
   plots agree on, and the plot takes the largest group that agrees within 0.8 cm (or half
   a working pixel), a vote weighing less the further it would move the plot, so that a
   missing segment, a lodged end or a weed at one row end is outvoted). Never on the
   centroid of green. The shift is kept when it is within ``max_shift``; plots without rows
   (row amplitude under ``min_cover`` × the median: empty or bare), whose rows go on beyond
   the crop's length (score under ``min_score``) or whose shift would exceed the bound are
   *left in place*: they keep the global correction and no shift.

Plots keep their shape and size; they turn by the global rotation about their centre. The
score of a plot is 1 − the rows' level outside the crop's length (within the plot's window)
over their level inside it, the level at each point along the rows being the median over the
rows of each row's signal over its plateau (1: the rows stop at the plot's ends; 0: they go on
beyond them).
"""
import math
import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import List, Optional, Sequence, Tuple

import numpy as np

from ..deprecation import renamed_parameters
from ..errors import EasyIDPError
from ..geometry import ring_moments
from ..progress import as_progress
from ..ragged import offsets
from ..raster import GeoTiff, open_geotiff
from .fit_image import NO_VEGETATION, read_vegetation
from .fit_rows import (block_search, measure_plots, rot as _rot, row_consensus,
                       row_spectrum)

FLAG_BARE = "bare soil or missing"
FLAG_WEAK = "crop rows go on beyond the plot's ends"
FLAG_BOUND = "shift beyond the bound"
MIN_ROW_STRENGTH = 20.0     # the row peak over the spectrum's median, for rows to be found


@dataclass
class FitResult:
    """Per plot (input order): ``rings`` (fitted exterior rings), ``shift`` (n, 2) per-plot
    shift after the global correction (m; 0 for plots left in place), ``score``, ``cover`` (row amplitude over the median plot's),
    ``flag`` ('' when fitted), ``moved`` (the per-plot shift was applied); global: ``rotation``
    (degrees, counter-clockwise), ``scale`` (spacing along the grid's x and y axes),
    ``translation`` (m, of the grid centre ``centre``), ``row_bearing`` (degrees, 0–180) and
    ``row_spacing`` (m) of the crop rows, or None; ``work_pixel`` (m); ``notes``."""
    rings: List[np.ndarray]
    shift: np.ndarray
    score: np.ndarray
    cover: np.ndarray
    flag: List[str]
    moved: np.ndarray
    rotation: float
    scale: Tuple[float, float]
    translation: Tuple[float, float]
    centre: Tuple[float, float]
    row_bearing: Optional[float]
    row_spacing: Optional[float]
    work_pixel: float
    notes: List[str] = field(default_factory=list)
    centres_in: Optional[np.ndarray] = None
    centres_out: Optional[np.ndarray] = None
    seconds: dict = field(default_factory=dict)     # wall time of each stage

    def move(self, i: int, xy) -> np.ndarray:
        """Points (n, 2) of plot ``i`` moved as the plot was (turned about its centre by the
        global rotation, then to its fitted centre): holes and other parts follow it."""
        t = math.radians(self.rotation)
        return (np.asarray(xy, float)[:, :2] - self.centres_in[i]) @ _rot(t).T + self.centres_out[i]

    @property
    def shift_m(self) -> np.ndarray:
        return np.hypot(self.shift[:, 0], self.shift[:, 1])

    def moved_over(self, threshold: float) -> int:
        return int(np.sum(self.moved & (self.shift_m > threshold)))

    def summary(self, threshold: float = 0.05) -> str:
        rows = "" if self.row_bearing is None else \
            f" Crop rows: bearing {self.row_bearing:.2f}°, spacing {self.row_spacing:.3f} m."
        left = len(self.flag) - int(self.moved.sum())
        return (f"Global correction: rotation {self.rotation:+.3f}°, spacing scale "
                f"{self.scale[0]:.4f} (x) {self.scale[1]:.4f} (y), shift "
                f"({self.translation[0]:+.3f}, {self.translation[1]:+.3f}) m.{rows} "
                f"{self.moved_over(threshold)} of {len(self.flag)} plots moved by more than "
                f"{threshold:g} m; {left} left in place.")


# ---- plot geometry ----------------------------------------------------------------------------

def _centroids(rings: Sequence[np.ndarray]) -> np.ndarray:
    """Area centroids (R, 2) of the plot rings; a ring without area gives its vertex mean."""
    area, moment = ring_moments(np.concatenate(rings), offsets([len(r) for r in rings]))
    flat = np.abs(area) < 1e-12
    with np.errstate(invalid="ignore", divide="ignore"):
        centres = moment / area[:, None]
    for i in np.flatnonzero(flat):
        centres[i] = rings[i].mean(axis=0)
    return centres


def _grid_axis(rings: Sequence[np.ndarray]) -> float:
    """The grid's x-axis angle (radians): the plots' edges, mod 90°, weighted by length."""
    s = c = 0.0
    for r in rings:
        d = np.roll(r, -1, axis=0) - r
        L = np.hypot(d[:, 0], d[:, 1])
        t = 4 * np.arctan2(d[:, 1], d[:, 0])
        s += float((L * np.sin(t)).sum())
        c += float((L * np.cos(t)).sum())
    return math.atan2(s, c) / 4


def _pitch(values: np.ndarray, tol: float) -> float:
    """The smallest spacing between distinct clusters of ``values``."""
    v = np.sort(values)
    d = np.diff(v)
    d = d[d > tol]
    return float(d.min()) if d.size else math.inf


def _groups(half: np.ndarray):
    """Indices of the plots of each size (half sizes to the millimetre)."""
    keys = {}
    for i, h in enumerate(np.round(half, 3)):
        keys.setdefault((h[0], h[1]), []).append(i)
    return [np.array(v) for v in keys.values()]


def _similarity(nominal, measured, ok, c0, axes):
    """(rotation, (su, sv), t) with measured ≈ c0 + t + R·G·S·Gᵀ·(nominal − c0)."""
    P = nominal[ok] - c0
    Q = measured[ok] - c0
    X = np.column_stack([P, np.ones(len(P))])
    coef, *_ = np.linalg.lstsq(X, Q, rcond=None)
    A = coef[:2].T                                 # Q ≈ A·P + t
    G = np.column_stack([axes[0], -axes[1]])       # right-handed: ux, and ux turned left
    Ag = G.T @ A @ G
    theta = math.atan2(Ag[1, 0] - Ag[0, 1], Ag[0, 0] + Ag[1, 1])
    S = _rot(-theta) @ Ag
    su, sv = float(S[0, 0]), float(S[1, 1])
    M = _rot(theta) @ G @ np.diag([su, sv]) @ G.T
    t = (Q - P @ M.T).mean(axis=0)
    return theta, (su, sv), t, M


def _robust_similarity(nominal, measured, good, c0, axes, px):
    """:func:`_similarity` over the ``good`` plots, outliers (over 3 × the median residual)
    left out until none changes."""
    ok = good.copy()
    for _ in range(5):
        if ok.sum() < 3:
            raise EasyIDPError("Plot grid: fewer than three plots have crop rows where the "
                               "grid puts them: check that the grid belongs to this "
                               "orthomosaic (or lower the cover threshold).")
        theta, scale, t, M = _similarity(nominal, measured, ok, c0, axes)
        res = np.hypot(*(measured - (c0 + t + (nominal - c0) @ M.T)).T)
        lim = max(3 * np.median(res[ok]), 2 * px, 0.02)
        new_ok = good & (res <= lim)
        if (new_ok == ok).all():
            break
        ok = new_ok
    return theta, scale, t, M


def _check_index(tif, index, bands):
    """(index, 0-based bands) checked against the raster."""
    if index == "auto":
        if tif.kind in ("rgb", "rgba") or tif.is_colour or (bands is not None and len(bands) == 3):
            index = "exg"
        elif bands is not None and len(bands) == 2:
            index = "ndvi"
        else:
            raise EasyIDPError(f"Orthomosaic {tif.path}: a {tif.bands}-band raster is not RGB: "
                               "choose the NDVI index and give the red and NIR band numbers.")
    if index not in ("exg", "ndvi"):
        raise EasyIDPError(f"Vegetation index {index!r}: choose exg or ndvi.")
    if bands is None:
        if index == "ndvi":
            raise EasyIDPError("NDVI: give the band numbers of the red and the NIR bands.")
        bands = (1, 2, 3)
    need = 3 if index == "exg" else 2
    if len(bands) != need or any(not 1 <= int(b) <= tif.bands for b in bands):
        raise EasyIDPError(f"Band numbers {list(bands)}: {index.upper()} needs {need} band "
                           f"numbers between 1 and {tif.bands} (the orthomosaic's bands).")
    return index, [int(b) - 1 for b in bands]


@renamed_parameters(crs="source_crs")
def fit_plot_grid(rings: Sequence[np.ndarray], orthomosaic, *, source_crs=None,
                  index: str = "auto", bands: Optional[Sequence[int]] = None,
                  max_shift: float = 0.25, search: Optional[float] = None,
                  min_cover: float = 0.3, min_score: float = 0.6, progress=None,
                  is_cancelled=None, workers: Optional[int] = None) -> FitResult:
    """Fit plots to the crop rows of an orthomosaic (see the module docstring).

    Parameters
    ----------
    rings : sequence of ndarray
        The plots' exterior rings, (n, 2) map coordinates in the orthomosaic's CRS.
    orthomosaic : str, path or GeoTiff
        The orthomosaic, a path or an opened ``GeoTiff``.
    source_crs : CRS, optional
        The CRS to assume for the orthomosaic (a path), instead of the one its GeoKeys give.
    index : {"auto", "exg", "ndvi"}
        The vegetation index: ExG (RGB), NDVI (multispectral) or "auto" (ExG for an RGB
        raster).
    bands : sequence of int, optional
        1-based band numbers: (red, green, blue) for ExG, (red, nir) for NDVI (default 1, 2, 3
        for ExG).
    max_shift : float
        The per-plot bound, metres.
    search : float, optional
        How far (m) the grid is searched for as a whole (default 0.6 m + 9 % of the grid's
        half extent: ±3° of rotation, ±3 % of spacing and 0.5 m of shift).
    min_cover : float
        A plot whose row amplitude is under ``min_cover`` × the median plot's (empty or bare)
        keeps the grid's position.
    min_score : float
        A plot whose row signal lies mostly outside it (score under ``min_score``, 0–1) keeps
        the grid's position.
    progress : callable or Progress, optional
        Called with the percent done (0–100).
    is_cancelled : callable, optional
        Returns True to stop (:class:`Cancelled` is raised).
    workers : int, optional
        Threads that decode the orthomosaic.

    Returns
    -------
    FitResult
        The fitted rings, in the input order, with each plot's shift, score and flag.
    """
    prog = as_progress(progress, is_cancelled)
    tif = orthomosaic if isinstance(orthomosaic, GeoTiff) else open_geotiff(str(orthomosaic), crs=source_crs)
    rings = [np.asarray(r, float)[:, :2] for r in rings]
    if len(rings) < 3:
        raise EasyIDPError(f"Plot grid: {len(rings)} plots; the fit needs at least three (it "
                           "estimates the grid's rotation, spacing and shift from them).")
    index, bands = _check_index(tif, index, bands)

    # --- plot geometry in the grid frame
    alpha = _grid_axis(rings)
    ux = np.array([math.cos(alpha), math.sin(alpha)])
    uy = np.array([ux[1], -ux[0]])
    centres = _centroids(rings)
    half = np.array([[np.abs((r - c) @ ux).max(), np.abs((r - c) @ uy).max()]
                     for r, c in zip(rings, centres)])
    c0 = centres.mean(axis=0)
    extent = float(np.hypot(*(centres - c0).T).max() + half.max())
    reach = float(search) if search is not None and search > 0 else 0.6 + 0.09 * extent
    grow = reach + 2 * float(half.max())
    xs = np.concatenate([r[:, 0] for r in rings])
    ys = np.concatenate([r[:, 1] for r in rings])
    bbox = (xs.min() - grow, ys.min() - grow, xs.max() + grow, ys.max() + grow)
    clock = [time.perf_counter()]
    seconds = {}

    def lap(name):
        now = time.perf_counter()
        seconds[name] = now - clock[0]
        clock[0] = now

    img, k, levels = read_vegetation(tif, bbox, index, bands, prog.sub(0, 70), workers)
    lap("read")
    notes = [f"Vegetation index {index.upper()} averaged over {k}×{k} pixels "
             f"({img.px:.3f} m); soil {levels['soil']:.3f}, leaf {levels['leaf']:.3f}."]

    # --- crop rows: their direction (the first rotation) and spacing
    rows = row_spectrum(img, c0, 0.5 * float(2 * np.median(half, axis=0).min()))
    if rows is None or rows[2] < MIN_ROW_STRENGTH:
        raise EasyIDPError(NO_VEGETATION.format(
            why="no crop rows: no periodic pattern shorter than half a plot"))
    direction, s, strength = rows
    row_bearing = math.degrees(math.atan2(math.cos(direction), math.sin(direction))) % 180.0
    along = 0 if abs(math.sin(direction - alpha)) <= abs(math.cos(direction - alpha)) else 1
    base = np.array([ux, uy]) if along == 0 else np.array([uy, -ux])
    theta0 = (direction - math.atan2(base[0, 1], base[0, 0]) + math.pi / 2) % math.pi - math.pi / 2
    hf = half if along == 0 else half[:, ::-1]               # half sizes (along, across) the rows
    notes.append(f"Crop rows: bearing {row_bearing:.2f}°, spacing {s:.3f} m (spectrum peak "
                 f"{strength:.0f}× the median), along the grid's {'xy'[along]} axis.")
    lap("weights and crop rows")
    prog.set(72)

    pitch_u = _pitch((centres - c0) @ base[0], float(np.median(hf[:, 0])))
    gap_u = pitch_u - 2 * float(np.median(hf[:, 0])) if math.isfinite(pitch_u) else 1.0
    margin_u = float(np.clip(0.5 * gap_u, 2 * img.px, 0.5))
    groups = _groups(hf)
    n = len(rings)
    with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 2) as pool:
        def measure(pred, axes, lengths, reach=math.inf):
            out = {k: np.zeros(n) for k in ("row", "amp", "ends", "span", "score")}
            for g, idx in enumerate(groups):
                m = measure_plots(img, pred[idx], axes, hf[idx[0]], s, margin_u,
                                  None if lengths is None else lengths[g], reach, pool, prog)
                for key in out:
                    out[key][idx] = m[key]
            return out

        def locate(pred, axes, m, parity):
            """Measured centres: the row ends along, the rows' middle across."""
            across = m["row"] + parity * s / 2
            across = across - s * np.round(across / s)
            return pred + m["ends"][:, None] * axes[0] + across[:, None] * axes[1]

        # (a) the block: rotation from the rows, spacing and shift by consensus of all plots
        R0 = _rot(theta0)
        A0 = base @ R0.T
        pred = c0 + (centres - c0) @ R0.T
        sc, sh = block_search(img, pred, A0, hf, s, reach, prog)
        p = pred - c0
        pred = c0 + ((p @ A0[0]) * sc[0] + sh[0])[:, None] * A0[0] + \
            ((p @ A0[1]) * sc[1] + sh[1])[:, None] * A0[1]
        lap("block search")
        prog.set(80)
        # (b) the rows' phases, by consensus: the offset and spacing across
        m = measure(pred, A0, None)
        good = m["amp"] >= min_cover * np.median(m["amp"])
        if good.sum() < 3:
            raise EasyIDPError(NO_VEGETATION.format(why="fewer than three plots have crop rows "
                                                        "where the grid puts them"))
        pv = (pred - c0) @ A0[1]
        a, b = row_consensus(m["row"][good], pv[good], m["amp"][good], s)
        a_best = a - (s / 2) * np.round(a / (s / 2))        # whole or half rows: the nearest
        parity = int(round((a_best - a) / (s / 2))) % 2     # 1: the plots' centres between rows
        pred = pred + (a_best + b * pv)[:, None] * A0[1]
        lengths = [float(np.median(m["span"][idx][good[idx]])) if good[idx].any() else None
                   for idx in groups]
        # (c) each plot measured on its rows, then the similarity from the grid's centres to
        # the measured ones, twice: the second time from windows the first laid on the rows,
        # with each plot's vote held near its place (within the per-plot bound); that second
        # measurement is each plot's own
        axes = A0
        for hold in (math.inf, max_shift):
            m = measure(pred, axes, lengths, hold)
            meas = locate(pred, axes, m, parity)
            good = m["amp"] >= min_cover * np.median(m["amp"])
            theta, scale, t, M = _robust_similarity(centres, meas, good, c0, [ux, uy], img.px)
            pred = c0 + t + (centres - c0) @ M.T
            axes = base @ _rot(theta).T
            prog.set(90 if hold == max_shift else 85)
    lap("global fit and per plot")
    Rt = _rot(theta)
    cover = m["amp"] / max(float(np.median(m["amp"])), 1e-12)
    shift = meas - pred
    flags = []
    for i in range(n):
        if cover[i] < min_cover:
            flags.append(FLAG_BARE)
        elif m["score"][i] < min_score:
            flags.append(FLAG_WEAK)
        elif math.hypot(*shift[i]) > max_shift:
            flags.append(FLAG_BOUND)
        else:
            flags.append("")
    moved = np.array([f == "" for f in flags])
    shift[~moved] = 0.0
    final = pred + shift
    out_rings = [(r - centres[i]) @ Rt.T + final[i] for i, r in enumerate(rings)]
    lap("flags and rings")
    prog.set(100)
    return FitResult(out_rings, shift, m["score"], cover, flags, moved, math.degrees(theta),
                     scale, (float(t[0]), float(t[1])), (float(c0[0]), float(c0[1])),
                     row_bearing, s, img.px, notes, centres, final, seconds)
