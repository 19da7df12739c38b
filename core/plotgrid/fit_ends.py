"""The crop rows' ends of many plots at once: where each plot's crop begins and ends along its
rows, for the plot-grid fit (:mod:`.fit_rows` samples the rows; this module reads their ends).

Conventions as in :mod:`.fit_rows`: ``u`` (m) runs along the rows from a plot's window centre,
sampled evenly; a row's *signal* is the vegetation weight's component at the row period over
one period across that row, along ``u``. Arrays run over plots (P), their rows (R) and ``u``.
Every step is vectorised over plots and rows: a 20000² orthomosaic has 1,600 plots of about
ten rows.
"""
from typing import Optional, Tuple

import numpy as np

END_AGREEMENT = 0.008      # m: row-end estimates of a plot this close agree
LOCAL_BAND = (0.05, 0.25)  # m inside a first crossing: where a row's local level is taken
CROSS_REACH = 0.15         # m: the local level's crossing is looked for this close to the first


def masked_median(x: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """The median along the last axis of ``x`` over the entries where ``keep``; NaN where none
    is kept."""
    y = np.sort(np.where(keep, x, np.inf), axis=-1)
    cnt = keep.sum(-1)
    lo = np.take_along_axis(y, np.maximum((cnt - 1) // 2, 0)[..., None], -1)[..., 0]
    hi = np.take_along_axis(y, np.maximum(cnt // 2, 0)[..., None], -1)[..., 0]
    with np.errstate(invalid="ignore"):
        return np.where(cnt > 0, 0.5 * (lo + hi), np.nan)


def _cross(a: np.ndarray, u: np.ndarray, rows: np.ndarray, i: np.ndarray, j: np.ndarray,
           level) -> np.ndarray:
    """Where each row's signal crosses ``level`` between samples ``i`` and ``j`` (linear)."""
    ai, aj = a[rows, i] - level, a[rows, j] - level
    same = ai == aj
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(same, 0.0, ai / np.where(same, 1.0, ai - aj))
    return u[i] + (u[j] - u[i]) * t


def _edge(a: np.ndarray, plateau: np.ndarray, u: np.ndarray, first: np.ndarray,
          inward: int) -> np.ndarray:
    """Each row's end whose outermost sample over half its plateau is ``first`` (``inward`` +1
    at the start, −1 at the end): the crossing of half the plateau, then of half the local
    level just inside it (so that an end of low vigour ends where it ends), if one is near."""
    n, nu = a.shape
    rows = np.arange(n)
    du = u[1] - u[0]
    out = first - inward
    inside = (out >= 0) & (out < nu)
    pos = np.where(inside, _cross(a, u, rows, np.clip(out, 0, nu - 1), first, 0.5 * plateau),
                   u[first])
    # the local level: the median over LOCAL_BAND inside the first crossing
    nb = int(np.ceil((LOCAL_BAND[1] - LOCAL_BAND[0]) / du)) + 2
    if inward > 0:
        j0 = np.floor((pos + LOCAL_BAND[0] - u[0]) / du).astype(np.int64) + 1
        J = j0[:, None] + np.arange(nb)
    else:
        j0 = np.ceil((pos - LOCAL_BAND[0] - u[0]) / du).astype(np.int64) - 1
        J = j0[:, None] - np.arange(nb)
    Jc = np.clip(J, 0, nu - 1)
    off = inward * (u[Jc] - pos[:, None])
    band = (J >= 0) & (J < nu) & (off > LOCAL_BAND[0]) & (off < LOCAL_BAND[1])
    local = masked_median(a[rows[:, None], Jc], band)
    local = np.where(band.any(1), local, plateau)
    # the crossing of half the local level nearest the first crossing
    m = int(np.ceil(CROSS_REACH / du)) + 1
    J = np.rint((pos - u[0]) / du).astype(np.int64)[:, None] + np.arange(-m, m + 1)
    Jc, Jp = np.clip(J, 0, nu - 1), np.clip(J - inward, 0, nu - 1)
    half = 0.5 * local[:, None]
    dist = np.abs(u[Jc] - pos[:, None])
    hit = ((dist < CROSS_REACH) & (J >= 0) & (J < nu) & (J - inward >= 0) & (J - inward < nu)
           & (a[rows[:, None], Jc] >= half) & (a[rows[:, None], Jp] < half))
    k = np.argmin(np.where(hit, dist, np.inf), axis=1)
    j = Jc[rows, k]
    refined = _cross(a, u, rows, np.clip(j - inward, 0, nu - 1), j, 0.5 * local)
    use = inside & (local > 0) & hit.any(1)
    return np.where(use, refined, pos)


def row_ends(a: np.ndarray, plateau: np.ndarray, u: np.ndarray):
    """(start, end, found) of each row's signal ``a`` (rows, u): where it crosses half its level
    just inside each end, found from its first and last crossings of half ``plateau`` (missing
    segments inside bridged); ``found`` False for a row with no such crossing."""
    above = a > 0.5 * plateau[:, None]
    found = above.any(1)
    first = np.argmax(above, axis=1)
    last = a.shape[1] - 1 - np.argmax(above[:, ::-1], axis=1)
    return _edge(a, plateau, u, first, 1), _edge(a, plateau, u, last, -1), found


def consensus(cand: np.ndarray, ok: np.ndarray, tol: float, reach: float) -> np.ndarray:
    """Per plot, the middle (m from the window's centre) most of the rows' end estimates
    ``cand`` (P, C; where ``ok``) agree on: the largest group within ``tol`` of one of them
    (ties: the tightest, then the one nearest the median), averaged. A vote weighs less the
    further it would move the plot, 1 − (d / ``reach``)², and nothing beyond ``reach``: two
    rows lodged or missing at the same end outvote one clean end only close to the plot's
    place. With no vote within reach, the median."""
    d = np.abs(cand[:, :, None] - cand[:, None, :])
    near = (d <= tol) & ok[:, :, None] & ok[:, None, :]
    w = np.clip(1 - (cand / reach) ** 2, 0, None) * ok
    support = np.where(ok, np.round((near * w[:, None, :]).sum(2), 9), -np.inf)
    spread = np.where(near, d, 0).sum(2)
    med = masked_median(cand, ok)
    best = support.max(1)
    tie = ok & (support == best[:, None])
    sp = np.where(tie, spread, np.inf)
    tie &= sp == sp.min(1)[:, None]
    pick = np.argmin(np.where(tie, np.abs(cand - med[:, None]), np.inf), axis=1)
    group = near[np.arange(len(cand)), pick]
    with np.errstate(invalid="ignore", divide="ignore"):
        mid = (cand * group).sum(1) / group.sum(1)
    return np.where(best > 0, mid, med)


def plot_ends(ak: np.ndarray, valid: np.ndarray, u: np.ndarray, inner: np.ndarray,
              length: Optional[float], reach: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(middle, span, score) of each plot (P,) from its rows' signals ``ak`` (P, R, u) (rows
    within the plot: ``valid``; ``inner``: the samples within the plot's half length).

    Each row's ends give two estimates of the plot's middle, its start + ``length``/2 and its
    end − ``length``/2 (:func:`consensus`; with ``length`` None, the median of the rows'
    middles); ``span`` is the median row length (m). The ``score`` is 1 − the rows' level
    outside the crop's length over their level inside it (1: the rows stop at the plot's
    ends; 0: they go on beyond them), the level at each u being the median over the rows of
    each row's signal over its plateau, and the levels the medians along the inside and the
    outside. Rows under 0.4 × the strongest row's plateau are left out; a plot without rows
    gets zeros."""
    P, R, nu = ak.shape
    plateau = np.percentile(ak[..., inner], 75, axis=-1)                  # (P, R)
    top = np.where(valid, plateau, -np.inf).max(1) if R else np.full(P, -np.inf)
    use = valid & (plateau > 0.4 * top[:, None]) & (top[:, None] > 0)
    lo, hi, found = row_ends(ak.reshape(-1, nu), plateau.ravel(), u)
    lo, hi = lo.reshape(P, R), hi.reshape(P, R)
    ok = use & found.reshape(P, R)
    span = masked_median(hi - lo, ok)
    if length is None:
        mid = masked_median(0.5 * (lo + hi), ok)
    else:
        tol = max(END_AGREEMENT, 0.5 * (u[1] - u[0]))
        mid = consensus(np.concatenate([lo + length / 2, hi - length / 2], axis=1),
                        np.concatenate([ok, ok], axis=1), tol, max(reach, 4 * tol))
    has = ok.any(1)
    mid, span = np.where(has, mid, 0.0), np.where(has, span, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        norm = ak / np.where(use, plateau, 1.0)[..., None]
    prof = np.clip(masked_median(np.moveaxis(norm, 1, 2), use[:, None, :]), 0, None)
    crop = span if length is None else np.full(P, float(length))
    box = np.abs(u[None, :] - mid[:, None]) <= 0.5 * crop[:, None]
    level = masked_median(prof, box)
    outside = masked_median(prof, ~box)
    with np.errstate(invalid="ignore", divide="ignore"):
        score = np.clip(1 - outside / level, 0, 1)
    score = np.where(has & (level > 0) & (~box).any(1), score, 0.0)
    return mid, span, np.nan_to_num(score)
