"""The traversal behind :func:`.ray_surface.first_hits`: rays in DSM pixel space walked over the
tiles, blocks and cells of a :class:`.ray_surface.RaySurface` to their first hit.

A lockstep 2-D DDA (Amanatides & Woo, :func:`_walk`) per level: tiles (the unit read from the
file), blocks of :data:`BLOCK` cells (a max-mipmap level) and cells, where the bilinear height
along the ray is a quadratic solved exactly (:func:`_solve_cells`). A walk over blocks (cells)
starts where the ray comes down to the tile's (block's) highest height, not where it enters
the tile (block): the part above it cannot meet the ground, so it is not walked. Inside a
tile a ray walks block after block until it stops or leaves the tile; only then are the tiles
walked again.
"""
import numpy as np

HIT, MISS, LEFT, NODATA = 0, 1, 2, 3
BLOCK = 8          # cells per block side: the max-mipmap level inside a tile
PREFETCH = 4        # tiles looked ahead on a ray's way when one must be read


class _Rays:
    """Rays in pixel space for one batch: (u, v, z)(t) = o + t·d for t in [t0, t1]."""

    def __init__(self, o, d, t0, t1, at_edge):
        self.ou, self.ov, self.oz = o[:, 0].copy(), o[:, 1].copy(), o[:, 2].copy()
        self.du, self.dv, self.dz = d[:, 0].copy(), d[:, 1].copy(), d[:, 2].copy()
        self.t0, self.t1, self.at_edge = t0, t1, at_edge


def _walk(r: _Rays, idx, ta, tb, size: int, lo, hi, classify, max_steps: int, aux=None,
          bounded: bool = True):
    """Lockstep DDA (Amanatides & Woo) over the square grid of ``size`` cells, for the rays
    ``idx`` along [ta, tb], every crossed grid cell in order.

    ``lo``/``hi`` (v, u) bound the grid indices visited (inclusive; with ``bounded`` False the
    caller's classify copes with indices a step beyond). ``classify(ids, iv, iu,
    t_in, t_out, z_low, aux)`` gets the cells being visited (``ids``: positions in ``idx``;
    ``z_low``: the ray's lowest height over the cell) and returns an int8 code per cell: 0 go
    on, > 0 stop there. Returns (code, iv, iu, t_in, t_out) per ray: code 0 when the segment
    ended (t_in = t_out = tb) or ``max_steps`` were taken (t_in = t_out = where it stopped).
    """
    n = len(idx)
    code = np.zeros(n, np.int8)
    out_iv = np.zeros(n, np.int64)
    out_iu = np.zeros(n, np.int64)
    out_a, out_b = tb.copy(), tb.copy()
    ou, ov, oz = r.ou[idx], r.ov[idx], r.oz[idx]
    du, dv, dz = r.du[idx], r.dv[idx], r.dz[idx]
    s = float(size)
    with np.errstate(divide="ignore", invalid="ignore"):
        u, v = (ou + du * ta) / s, (ov + dv * ta) / s
        iu = np.where(du < 0, np.ceil(u) - 1, np.floor(u)).astype(np.int64)
        iv = np.where(dv < 0, np.ceil(v) - 1, np.floor(v)).astype(np.int64)
        np.clip(iu, lo[1], hi[1], out=iu)
        np.clip(iv, lo[0], hi[0], out=iv)
        su, sv = np.sign(du).astype(np.int64), np.sign(dv).astype(np.int64)
        inv_u = np.where(du != 0, 1.0 / du, np.inf)
        inv_v = np.where(dv != 0, 1.0 / dv, np.inf)
        nu_t = np.where(su != 0, ((iu + (su > 0)) * s - ou) * inv_u, np.inf)
        nv_t = np.where(sv != 0, ((iv + (sv > 0)) * s - ov) * inv_v, np.inf)
    tdu, tdv = np.abs(s * inv_u), np.abs(s * inv_v)
    lowz = np.where(dz < 0, 1, 0).astype(bool)
    t_in, t_end = ta.copy(), tb.copy()
    ids = np.arange(n)
    alive = np.ones(n, bool)
    n_alive = n
    for _ in range(max_steps):
        if n_alive == 0:
            break
        t_out = np.minimum(nu_t, nv_t)
        np.maximum(t_out, t_in, out=t_out)
        np.minimum(t_out, t_end, out=t_out)
        zl = oz + dz * np.where(lowz, t_out, t_in)
        c = classify(ids, iv, iu, t_in, t_out, zl, aux)
        stop = (c > 0) & alive
        if stop.any():
            k = ids[stop]
            code[k] = c[stop]
            out_iv[k], out_iu[k] = iv[stop], iu[stop]
            out_a[k], out_b[k] = t_in[stop], t_out[stop]
        go_u = nu_t <= nv_t
        go_v = ~go_u
        np.add(iu, su, out=iu, where=go_u)
        np.add(iv, sv, out=iv, where=go_v)
        np.add(nu_t, tdu, out=nu_t, where=go_u)
        np.add(nv_t, tdv, out=nv_t, where=go_v)
        gone = t_out >= t_end
        if bounded:
            gone |= (iu < lo[1]) | (iu > hi[1]) | (iv < lo[0]) | (iv > hi[0])
            np.clip(iu, lo[1], hi[1], out=iu)
            np.clip(iv, lo[0], hi[0], out=iv)
        t_in = t_out
        gone |= stop
        gone &= alive
        if gone.any():
            alive &= ~gone
            n_alive = int(np.count_nonzero(alive))
            if n_alive < 0.75 * len(alive):      # compact: drop the finished rays
                keep = alive
                (ou, ov, oz, du, dv, dz, iu, iv, su, sv, nu_t, nv_t, tdu, tdv, lowz, t_in, t_end,
                 ids) = [x[keep] for x in (ou, ov, oz, du, dv, dz, iu, iv, su, sv, nu_t, nv_t,
                                           tdu, tdv, lowz, t_in, t_end, ids)]
                if aux is not None:
                    aux = aux[keep]
                alive = np.ones(n_alive, bool)
    if n_alive:                                     # out of steps: report where each stopped
        k = ids[alive]
        out_a[k] = t_in[alive]
        out_b[k] = t_in[alive]
    return code, out_iv, out_iu, out_a, out_b


def _solve_cells(r: _Rays, idx, iv, iu, t_in, t_out, h):
    """Smallest t in [t_in, t_out] where the ray is at or below the bilinear cell (iv, iu)
    with corner heights h = (h00, h10, h01, h11); NaN where there is none.

    Along the ray the bilinear height is a quadratic in t, so ``z(t) − h(t) = C + B·s + A·s²``
    (s = t − t_in) is solved in closed form (the numerically stable quadratic formula)."""
    h00, h10, h01, h11 = h
    du, dv, dz = r.du[idx], r.dv[idx], r.dz[idx]
    a = r.ou[idx] + du * t_in - iu
    b = r.ov[idx] + dv * t_in - iv
    hx, hy = h10 - h00, h01 - h00
    hxy = h11 - h10 - h01 + h00
    C = r.oz[idx] + dz * t_in - (h00 + hx * a + hy * b + hxy * a * b)
    B = dz - (hx * du + hy * dv + hxy * (a * dv + b * du))
    A = -hxy * du * dv
    L = t_out - t_in
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        disc = B * B - 4 * A * C
        q = -0.5 * (B + np.copysign(np.sqrt(np.maximum(disc, 0.0)), B))
        r1 = np.where(A != 0, q / A, np.inf)
        r2 = np.where(q != 0, C / q, np.inf)
    r1 = np.where((r1 >= 0) & (r1 <= L), r1, np.inf)
    r2 = np.where((r2 >= 0) & (r2 <= L), r2, np.inf)
    s = np.where(disc >= 0, np.minimum(r1, r2), np.inf)
    s = np.where(C <= 0, 0.0, s)
    return np.where(np.isfinite(s), t_in + s, np.nan)


def _nodata_ceiling(surface) -> float:
    """Nodata may hide anything up to the highest height read (anything at all before a read)."""
    return surface.zmax if np.isfinite(surface.zmax) else np.inf


def _tile_walk(surface, r: _Rays, idx, ta, zc):
    """Walk the rays ``idx`` from ``ta`` over the tiles to the first one they come down into
    (code 1) or that is not read yet (code 2); ``_walk``'s (code, iv, iu, t_in, t_out)."""
    def tile_class(ids, iv, iu, t_in, t_out, zl, aux):
        # the slot first: another thread may be reading tiles, and sets a tile's slot only
        # after its maxima
        unread = surface.slot[iv, iu] < 0
        top = surface.tile_max[iv, iu]
        top = np.where(surface.tile_nod[iv, iu], np.maximum(top, zc), top)
        c = ((zl <= top) & (t_out > t_in)).astype(np.int8)
        c[unread] = 2
        return c

    return _walk(r, idx, ta, r.t1[idx], surface.T, np.array([0, 0]),
                 np.array([surface.ntv - 1, surface.ntu - 1]), tile_class,
                 surface.ntu + surface.ntv + 2)


def _read_wanted(surface, r: _Rays, idx, tv, tu, ta, prog) -> None:
    """Read the unread tiles (tv, tu) where the rays ``idx`` stopped at ``ta``, the unread
    tiles next on their way down, and (for a large job) the holes of the area read, so that
    file blocks shared by neighbouring tiles are decoded once."""
    need = set(zip(tv.tolist(), tu.tolist()))
    if np.isfinite(surface.zmax):
        need |= _tiles_ahead(surface, r, idx, ta, PREFETCH)
    if len(need) >= 4:
        a = np.array(sorted(need))
        (v0, u0), (v1, u1) = a.min(axis=0), a.max(axis=0)
        grown = set()
        for tv_, tu_ in need:
            for dv_ in (-1, 0, 1):
                for du_ in (-1, 0, 1):
                    if v0 <= tv_ + dv_ <= v1 and u0 <= tu_ + du_ <= u1:
                        grown.add((tv_ + dv_, tu_ + du_))
        need |= grown
    surface.load(need, prog)


def _down_to(r: _Rays, idx, top, ta, tb):
    """Where the rays ``idx`` on [ta, tb] come down to height ``top`` (ta where they are not
    above it there, or do not go down): before it they are above everything under ``top``."""
    dz = r.dz[idx]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_top = np.where(dz < 0, (top - r.oz[idx]) / dz, -np.inf)
    return np.clip(np.nan_to_num(t_top, nan=-np.inf), ta, tb)


def _traverse(surface, r: _Rays, prog):
    """First hits of a batch of rays in pixel space → (t (n,), status (n,)).

    Each round walks the rays over the tiles to the next one they come down into, then, inside
    it, over its blocks and the cells of each block they come down into, block after block,
    until they stop or leave the tile (the tile is not walked again for each block)."""
    n = len(r.t0)
    t = np.full(n, np.nan)
    status = np.full(n, MISS, np.uint8)
    T, nb = surface.T, surface.T // BLOCK
    T1 = T + 1
    t_cur = r.t0.copy()
    active = np.flatnonzero(r.t0 < r.t1)
    zero = np.array([0, 0])
    blocks_hi = np.array([surface.ntv * nb - 1, surface.ntu * nb - 1])
    cells_hi = np.array([surface.H, surface.W])
    while active.size:
        prog.check()
        zc = _nodata_ceiling(surface)
        code, tv, tu, ta, tb = _tile_walk(surface, r, active, t_cur[active], zc)
        ended = (code == 0) & (ta >= r.t1[active])     # MISS or LEFT: decided by _run
        t_cur[active] = ta                               # tile entry, or where the walk stopped
        want = np.flatnonzero(code == 2)
        if want.size:
            _read_wanted(surface, r, active[want], tv[want], tu[want], ta[want], prog)
        keep = ~ended
        cand = np.flatnonzero(code == 1)
        if cand.size:
            stopped = np.zeros(n, bool)
            ci, tv, tu, tb = active[cand], tv[cand], tu[cand], tb[cand]
            top = surface.tile_max[tv, tu]
            top = np.where(surface.tile_nod[tv, tu], np.maximum(top, zc), top)
            start = _down_to(r, ci, top, ta[cand], tb)
            while ci.size:
                has, ccode, cta, ctb, hit_t, bi = _blocks_of_tile(
                    surface, r, ci, tv, tu, start, tb, zc, zero, blocks_hi, cells_hi, T, T1, nb,
                    t_cur)
                if bi is None:
                    break
                h1, h2 = ccode == 1, ccode == 2
                t[bi[h1]], status[bi[h1]] = hit_t[h1], HIT
                t[bi[h2]], status[bi[h2]] = cta[h2], NODATA
                t_cur[bi] = ctb
                stopped[bi[~(ccode == 0)]] = True
                go = ccode == 0                  # no hit in that block: the next one in the tile
                ci, tv, tu, tb, start = ci[has[go]], tv[has[go]], tu[has[go]], tb[has[go]], ctb[go]
            keep &= ~stopped[active]
        active = active[keep]
    return t, status


def _blocks_of_tile(surface, r: _Rays, ci, tv, tu, start, tb, zc, zero, blocks_hi, cells_hi, T,
                    T1, nb, t_cur):
    """Walk the rays ``ci`` (in tiles (tv, tu)) over blocks from ``start`` to ``tb`` to the
    next block they come down into, and over its cells: (positions in ``ci`` that found a
    block, the cell walk's code, t_in, t_out, hit t, their ray ids), or ``bi`` None when no
    ray found one. ``t_cur`` is set to where each ray's block walk ended."""
    def block_class(ids, iv, iu, ta_, tb_, zl, aux):
        top = surface.block_max[iv, iu]
        top = np.where(surface.block_nod[iv, iu], np.maximum(top, zc), top)
        return ((zl <= top) & (tb_ > ta_)).astype(np.int8)

    bcode, biv, biu, bta, btb = _walk(r, ci, start, tb, BLOCK, zero, blocks_hi, block_class,
                                      2 * nb + 2)
    t_cur[ci] = btb                              # no candidate block: the tile's exit
    has = np.flatnonzero(bcode == 1)
    if not has.size:
        return has, None, None, None, None, None
    bi = ci[has]
    aux = np.column_stack([surface.slot[tv[has], tu[has]], tv[has] * T, tu[has] * T])
    hit_t = np.full(len(bi), np.nan)
    has_nod = bool(surface.tile_nod[tv[has], tu[has]].any())
    cmax = surface.cell_max_flat()
    samples = surface.samples_flat()

    def cell_class(ids, iv, iu, ta_, tb_, zl, ax):
        # segments lie in one block: a step beyond it inside the tile is the next cell; beyond
        # the tile, a zero-length sliver at its edge, where the edge cell's patch (clipped
        # index, also given to the solve) is exact
        lv = np.clip(iv - ax[:, 1], 0, T - 1)
        lu = np.clip(iu - ax[:, 2], 0, T - 1)
        f = ax[:, 0] * (T * T) + lv * T + lu
        top = cmax[f]
        c = np.zeros(len(ids), np.int8)
        if has_nod:
            nod = np.flatnonzero(np.isnan(top))
            if nod.size:
                c[nod[(zl[nod] <= zc) & (tb_[nod] > ta_[nod])]] = 2
        test = np.flatnonzero(zl <= top)
        if test.size:
            f = ax[test, 0] * (T1 * T1) + lv[test] * T1 + lu[test]
            h = (samples[f].astype(np.float64), samples[f + 1].astype(np.float64),
                 samples[f + T1].astype(np.float64), samples[f + T1 + 1].astype(np.float64))
            items = bi[ids[test]]
            # the solve uses the cell whose corners were read: the clipped one
            th = _solve_cells(r, items, lv[test] + ax[test, 1], lu[test] + ax[test, 2],
                              ta_[test], tb_[test], h)
            got = np.isfinite(th)
            c[test[got]] = 1
            k = ids[test[got]]
            first = np.isnan(hit_t[k])     # finished rays walk on until compacted
            hit_t[k[first]] = th[got][first]
        return c

    top = surface.block_max[biv[has], biu[has]]
    top = np.where(surface.block_nod[biv[has], biu[has]], np.maximum(top, zc), top)
    ccode, _, _, cta, ctb = _walk(r, bi, _down_to(r, bi, top, bta[has], btb[has]), btb[has], 1,
                                  zero, cells_hi, cell_class, 2 * BLOCK + 4, aux, bounded=False)
    return has, ccode, cta, ctb, hit_t, bi


def _tiles_ahead(surface, r: _Rays, idx, ta, k: int) -> set:
    """Unread tiles among the next ``k`` tiles on the rays' way from ``ta`` while they are
    not above the highest height read (so a wave reads more than one tile per ray)."""
    found = set()
    ceiling = surface.zmax + max(surface.zmax - surface.zmin, 1.0)
    seen = np.zeros(len(idx), np.int64)

    def classify(ids, iv, iu, t_in, t_out, zl, aux):
        unread = (surface.slot[iv, iu] < 0) & (zl <= ceiling)
        for a, b in zip(iv[unread].tolist(), iu[unread].tolist()):
            found.add((a, b))
        seen[ids] += 1
        return (seen[ids] >= k).astype(np.int8)

    _walk(r, idx, ta, r.t1[idx], surface.T, np.array([0, 0]),
          np.array([surface.ntv - 1, surface.ntu - 1]), classify, k)
    return found
