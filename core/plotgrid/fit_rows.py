"""Crop rows on the plot-grid fit's vegetation image: what tells the crop from weeds and grass.

Conventions: a *frame* is a pair of unit map vectors ``axes`` (rows: along the crop rows,
across them); ``u`` is the coordinate along the rows, ``v`` across, in metres from a plot's
centre. The crop rows are periodic across (period ``s``, the row spacing); weeds, grass,
lodged patches and soil are not, so every measurement here is of the component of the
vegetation weights at the row frequency, over a whole number of periods across the rows (a
constant or a slow change contributes exactly nothing there).

* :func:`row_spectrum`: the rows' direction and spacing from the power spectrum of the field.
* :func:`block_search`: the grid's spacing scale and shift along the rows, from the row
  amplitude projected on that axis and correlated with the plots' own projection (all plots at
  once: a consensus that the margins, outside every plot, cannot win), and its shift across.
* :func:`row_consensus`: the offset and spacing across from every plot's row phase at once.
* :func:`measure_plots`: each plot's rows: the phase of the row component across (the rows'
  positions, hence the plot's centre across), each row's own ends along (the plot's middle is
  where most of its rows' ends agree, given the crop length the plots agree on), the row
  amplitude and how much of the row signal lies within the crop's length.
"""
import math
from typing import Tuple

import numpy as np

from .fit_ends import plot_ends

BATCH_SAMPLES = 1_000_000      # lattice samples per batch of plots
PER_PERIOD = 8                 # samples per row period across the rows
END_SMOOTHING = 0.025          # m: sigma of the Gaussian along a row before its ends are found


def rot(t: float) -> np.ndarray:
    return np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])


def row_spectrum(img, centre, max_period: float):
    """(direction of the rows (radians from east, counter-clockwise), spacing m, strength) of
    the strongest periodic pattern with a period below ``max_period`` in a 1024² window of the
    image around ``centre`` (Hann window; the peak refined by a parabola), or None."""
    h, wd = img.w.shape
    n = 1024
    r0 = int(np.clip((img.y0 - centre[1]) / img.py - n / 2, 0, max(h - n, 0)))
    c0 = int(np.clip((centre[0] - img.x0) / img.px - n / 2, 0, max(wd - n, 0)))
    a = img.w[r0:r0 + n, c0:c0 + n].astype(np.float64)
    if min(a.shape) < 32:
        return None
    a = a - a.mean()
    a *= np.hanning(a.shape[0])[:, None] * np.hanning(a.shape[1])[None, :]
    P = np.abs(np.fft.fft2(a)) ** 2
    fy = np.fft.fftfreq(a.shape[0], img.py)
    fx = np.fft.fftfreq(a.shape[1], img.px)
    FX, FY = np.meshgrid(fx, -fy)                       # map y is up, the row index down
    f = np.hypot(FX, FY)
    band = (f > 1.0 / max_period) & (f < 1.0 / (3 * max(img.px, img.py))) & (FX >= 0)
    if not band.any():
        return None
    i = np.unravel_index(int(np.argmax(np.where(band, P, 0))), P.shape)
    peak = P[i]
    strength = float(peak / (np.median(P[band]) + 1e-12))

    def interp(lft, mid, rgt):
        d = lft - 2 * mid + rgt
        return 0.0 if d == 0 else 0.5 * (lft - rgt) / d

    dy = interp(P[(i[0] - 1) % P.shape[0], i[1]], peak, P[(i[0] + 1) % P.shape[0], i[1]])
    dx = interp(P[i[0], (i[1] - 1) % P.shape[1]], peak, P[i[0], (i[1] + 1) % P.shape[1]])
    ky = np.fft.fftfreq(a.shape[0])[i[0]] + dy / a.shape[0]
    kx = np.fft.fftfreq(a.shape[1])[i[1]] + dx / a.shape[1]
    wx, wy = kx / img.px, -ky / img.py
    return math.atan2(wy, wx) + math.pi / 2, 1.0 / math.hypot(wx, wy), strength


def _across(s: float, extent: float, step: float) -> np.ndarray:
    """Sample positions across the rows: a whole number of periods ``s`` (at least one) centred
    on 0, no wider than ``extent`` (m) but for 5 % of a period, ``step`` apart or a little less, each period sampled
    evenly (so that a constant has no row component)."""
    periods = max(1, int(math.floor(extent / s + 0.05)))
    per = max(4, int(math.ceil(s / step)))
    n = periods * per
    return (np.arange(n) + 0.5) * (periods * s / n) - periods * s / 2


def block_search(img, centres, axes, half, s, reach, prog) -> Tuple[np.ndarray, np.ndarray]:
    """((scale_u, scale_v), (shift_u, shift_v)): the spacing scale about the mean centre and the
    shift (m) along each frame axis that best lay the plots (``centres`` (n, 2), half sizes
    ``half`` (n, 2) along the axes) on the row amplitude within ``reach`` (m) of their place.

    The row amplitude, on a lattice over the plots' box grown by ``reach``, is the magnitude of
    the row component over two periods across (2 cycles per window) less those at 1 and 3
    cycles (a straight edge has all three, rows only the second), each averaged as complex
    numbers over a metre along the rows. Along the rows, its projection is correlated with
    each plot's box laid at each scale (0.95–1.05) and shift, coarse then fine. Across, the
    scale stays 1 and the shift lays the plots' middle on the middle of the crop's extent
    (where the projection crosses half-way between the field and the outside); the phases of
    the rows do the rest (:func:`row_consensus`).
    """
    c0 = centres.mean(axis=0)
    pu, pv = (centres - c0) @ axes[0], (centres - c0) @ axes[1]
    lo_u, hi_u = (pu - half[:, 0]).min() - reach, (pu + half[:, 0]).max() + reach
    lo_v, hi_v = (pv - half[:, 1]).min() - reach, (pv + half[:, 1]).max() + reach
    du, per = max(img.px, s / 2), 16          # the windows across: two periods, 16 samples
    nb = max(1, int(round(min(1.0, float(np.median(half[:, 0]))) / du)))   # ≤ 1 m along
    dv = 2 * s / per
    u = np.arange(lo_u, hi_u, du)
    v = np.arange(lo_v, hi_v, dv)
    amp = np.zeros((len(v) - per + 1, len(u)))
    j = np.arange(len(v))
    rows = max(1, BATCH_SAMPLES // max(len(u), 1))
    for a in range(0, len(amp), rows):
        prog.check()
        b = min(a + rows, len(amp))
        S = img.sample_frame(c0[None], axes, u, v[a:b + per - 1])[0].astype(np.float64)
        mags = []
        for cyc in (1, 2, 3):         # cycles per window: the rows are 2, an edge is all three
            ph = np.exp(-2j * np.pi * cyc * j[a:b + per - 1] / per)
            z = np.cumsum(np.vstack([np.zeros((1, len(u))), S * ph[:, None]]), axis=0)
            z = (z[per:] - z[:-per]) * np.exp(2j * np.pi * cyc * j[a:b, None] / per)
            # along the rows, complex means: the rows keep their phase, grass and weeds do not
            zc = np.cumsum(np.hstack([np.zeros((len(z), 1)), z]), axis=1)
            mags.append(np.abs(zc[:, nb:] - zc[:, :-nb]) / nb)
        amp[a:b, nb // 2:nb // 2 + mags[0].shape[1]] = np.clip(mags[1] - mags[0] - mags[2], 0, None)
    vc = v[:len(amp)] + (per - 1) * dv / 2
    scale, shift = np.ones(2), np.zeros(2)
    for k, (prof, x, pos, h) in enumerate(((amp.sum(0), u, pu, half[:, 0]),
                                           (amp.sum(1), vc, pv, half[:, 1]))):
        step = x[1] - x[0]
        # each plot's box against the profile less its middle level: plot boundaries (alleys,
        # or where the rows of touching plots change phase) and the outside are below it
        level = 0.5 * (np.percentile(prof, 90) + np.percentile(prof, 10))
        cum = np.concatenate([[0.0], np.cumsum(prof - level)])
        edges = np.concatenate([[x[0] - step / 2], x + step / 2])

        def score(sc, t):
            p = sc[:, None, None] * pos[None, None, :] + t[None, :, None]
            return (np.interp(p + h, edges, cum) - np.interp(p - h, edges, cum)).sum(-1)
        if k == 1:
            # across the rows: the middle of the crop's extent (touching plots show no
            # boundary there; the spacing comes from the rows' phases, row_consensus)
            over = np.flatnonzero(prof > level)
            if len(over):
                i0, i1 = over[0], over[-1]
                lo = x[i0] if i0 == 0 else x[i0 - 1] + step * (level - prof[i0 - 1]) / (prof[i0] - prof[i0 - 1])
                hi = x[i1] if i1 == len(x) - 1 else x[i1] + step * (prof[i1] - level) / (prof[i1] - prof[i1 + 1])
                shift[k] = 0.5 * (lo + hi) - 0.5 * ((pos - h).min() + (pos + h).max())
            continue
        scs = np.linspace(0.95, 1.05, 41)
        ts = np.arange(-reach, reach + 1e-9, max(step / 2, 0.01))
        S = score(scs, ts)
        i, j = np.unravel_index(int(np.argmax(S)), S.shape)
        for _ in range(2):          # finer around the best
            dsc, dt = (scs[1] - scs[0]), ts[1] - ts[0]
            scs = scs[i] + np.linspace(-dsc, dsc, 21)
            ts = ts[j] + np.linspace(-dt, dt, 21)
            S = score(scs, ts)
            i, j = np.unravel_index(int(np.argmax(S)), S.shape)
        scale[k], shift[k] = scs[i], ts[j]
    return scale, shift


def row_consensus(row: np.ndarray, v: np.ndarray, weight: np.ndarray, s: float,
                  max_scale: float = 0.06) -> Tuple[float, float]:
    """(a, b): the offset across a + b·v (m; v the plots' positions across from the grid's
    middle) that best explains every plot's nearest-row offset ``row`` (mod ``s``), weighted;
    ``b`` within ±``max_scale`` (a spacing error), ``a`` in (−s/2, s/2] — known up to whole
    rows, and up to half a row when the plots' row counts may be even."""
    bs = np.arange(-max_scale, max_scale + 1e-12, min(0.0005, 0.05 * s / max(np.abs(v).max(), 1e-9)))
    e = np.exp(2j * np.pi * (row[None, :] - bs[:, None] * v[None, :]) / s) * weight[None, :]
    z = e.sum(1)
    i = int(np.argmax(np.abs(z)))
    for _ in range(2):
        step = (bs[1] - bs[0]) if len(bs) > 1 else 1e-4
        bs = bs[i] + np.linspace(-step, step, 21)
        z = (np.exp(2j * np.pi * (row[None, :] - bs[:, None] * v[None, :]) / s) * weight[None, :]).sum(1)
        i = int(np.argmax(np.abs(z)))
    return float(np.angle(z[i]) * s / (2 * np.pi)), float(bs[i])


def measure_plots(img, centres, axes, half, s, margin_u, length, reach, pool, prog) -> dict:
    """Each plot's crop rows around ``centres`` (n, 2) in the frame ``axes`` (plots of one size:
    ``half`` (2,) half sizes along, across the rows; ``margin_u`` m searched beyond each end).

    Returns arrays: ``row`` (the offset across of the nearest row to the centre, in
    (−s/2, s/2], from the phase of the row component over a whole number of periods), ``amp``
    (that component's magnitude per sample), ``ends`` (the offset along of the crop's middle:
    each row's own ends — where its signal crosses half its plateau — give two estimates of
    the middle, its start + ``length``/2 and its end − ``length``/2, and the plot takes the
    largest group of estimates that agree, so that a row missing at one end, lodged or
    lengthened by a weed is outvoted; with ``length`` None, the median of the rows' middles),
    ``span`` (the median row length, m) and ``score`` (1 − the rows' level outside the crop's
    length over their level inside it: 1 when the rows stop at the plot's ends, 0 when they go
    on beyond them; the level at each u is the median over the rows of each row's signal over
    its plateau, and the levels the medians along the inside and the outside)."""
    from scipy.ndimage import gaussian_filter1d
    n = len(centres)
    step = min(img.px, img.py)
    v = _across(s, 2 * half[1], max(step, s / PER_PERIOD))
    v1 = (np.arange(PER_PERIOD) + 0.5) * (s / PER_PERIOD) - s / 2
    ext = half[0] + margin_u
    nu = max(int(math.ceil(2 * ext / step)), 4)
    u = (np.arange(nu) + 0.5) * (2 * ext / nu) - ext
    du = u[1] - u[0]
    ph = np.exp(-2j * np.pi * v / s)
    inner = np.abs(u) <= half[0]
    sig = max(END_SMOOTHING / du, 0.5)
    K = int(math.floor(half[1] / s + 0.5))
    ks = np.arange(-K, K + 1)
    out = {k: np.zeros(n) for k in ("row", "amp", "ends", "span", "score")}

    def smooth(a):
        return gaussian_filter1d(a, sig, axis=-1, mode="constant")

    def batch(sl):
        prog.check()
        c = centres[sl]
        S = img.sample_frame(c, axes, u, v)                                   # (m, nv, nu)
        inside = S[:, :, inner]
        # across: the median along the rows at each offset across (weeds, lodged patches and
        # missing segments cover a minority of a row's length), its phase at the row period
        row = -np.angle(np.median(inside, axis=2) @ ph) * s / (2 * np.pi)
        out["row"][sl] = row
        out["amp"][sl] = np.abs(inside.sum(2) @ ph) / inside.shape[2] / len(v)
        # each row on its own: one period across it, projected on its phase
        vk = row[:, None] + ks[None, :] * s                                  # (m, rows)
        ck = (c[:, None, :] + vk[..., None] * axes[1][None, None, :]).reshape(-1, 2)
        S1 = img.sample_frame(ck, axes, u, v1)
        ak = smooth(np.einsum("kvu,v->ku", S1, np.cos(2 * np.pi * v1 / s).astype(np.float32))
                    / PER_PERIOD)
        out["ends"][sl], out["span"][sl], out["score"][sl] = plot_ends(
            ak.reshape(len(c), len(ks), nu), np.abs(vk) < half[1], u, inner, length, reach)

    b = max(1, BATCH_SAMPLES // max(len(u) * (len(v) + len(ks) * PER_PERIOD), 1))
    slices = [slice(i, min(n, i + b)) for i in range(0, n, b)]
    if pool is None or len(slices) < 2:
        for sl in slices:
            batch(sl)
    else:
        for _ in pool.map(batch, slices):
            pass
    return out
