"""The crossing search along the rows of a profile (§6 by crossings): the generic part.

A grid (core/crossings.py: the suns' light-aligned grid, the point lights' polar grid) lays
the rays' paths out as rows of a profile G, such that a ray is inside the relief exactly
where G > c, its own level. Given each row's G, `search_tables` builds sparse tables of the
maximum and minimum of G over power-of-two windows and the suffix maxima; `inside_length`
then finds, per ray, the next up- or down-crossing of c by a binary descent through the
tables (`_descend`), placing each crossing by linear interpolation of the ray's depth
between columns, and sums the intervals inside. A ray between two rows follows the blend of
the two rows' profiles (the tables' blended extremes bound the blend's, single columns are
exact); most rays need no descent: their first exit is where the tangent plane puts it,
proved in O(1) (`_exit_guess`).

Nothing here knows which light made the grid: its caller passes the rows, columns and levels.
"""
import functools
from dataclasses import dataclass

import numpy as np

MAX_CROSSINGS = 8     # enter/exit pairs followed per ray (more are very rare)
TABLE_LEVELS = 9                  # windows of up to 256 columns (table_levels)
NEVER = 1e30                      # table padding: beyond any G, finite so blends stay finite
GUESS_STEPS, GUESS_LEAP = 3, 64   # _exit_guess: secant steps past the tangent plane's exit


def table_levels(width):
    """Table levels of a row `width` columns long: windows of 2**k ≤ width (a wider window
    would cross the row's end from every column: all sentinels, never read), at most
    TABLE_LEVELS: wider windows almost never skip (measured, sun 35° at 1024²: 0 % at 1024
    columns, 0.2 % at 512, 13 % at 256), and a descent that stops short of its answer is
    resumed by its caller."""
    return max(1, min(TABLE_LEVELS, int(width).bit_length()))


def _tables(g, op, sentinel):
    """t[k, r, i] = op(G[r, i : i + 2**k]) for windows inside the row, `sentinel` (never
    skipped by a descent) for windows that cross its end: one (levels, rows, width + 1) array
    (column `width` is padding), so descents need no bounds checks and a per-ray level k can
    be gathered from its flat view (_range_min)."""
    rows, width = g.shape
    levels = table_levels(width)
    out = np.empty((levels, rows, width + 1), g.dtype)
    out[0, :, :width] = g
    out[0, :, width] = sentinel
    wp = width + 1
    for k in range(1, levels):
        half = 1 << (k - 1)
        op(out[k - 1, :, :wp - half], out[k - 1, :, half:], out=out[k, :, :wp - half])
        out[k, :, wp - half:] = sentinel
    return out


@functools.lru_cache(maxsize=8)
def _windows(width, levels):
    """Per range of n + 1 columns (n = 0 … width − 1): the level k of the two overlapping
    windows that cover it (floor(log2(n + 1)), at most the top level), the second window's
    start from the first's (n + 1 − 2**k), and whether two top windows are too short."""
    n = np.arange(width)
    k = np.minimum(np.floor(np.log2(n + 1)).astype(np.int64), levels - 1)
    return k, n + 1 - (1 << k), n + 1 > (2 << (levels - 1))


def _suffix_max(g):
    """max of G from each column onward, per row (padded like the tables)."""
    out = np.empty((g.shape[0], g.shape[1] + 1), g.dtype)
    np.maximum.accumulate(g[:, ::-1], axis=1, out=out[:, -2::-1])
    out[:, -1] = -NEVER
    return out


def _range_min(tables, rows, lo, hi):
    """A lower bound of min over columns lo … hi (hi ≥ lo) of each ray's blended profile,
    from two overlapping windows of one level: O(1) per ray; −∞ (nothing proved) where the
    range is longer than two windows of the top level."""
    levels, nrows, stride = tables.shape
    k, back, too_long = _windows(stride, levels)
    span = hi - lo
    first = k.take(span)
    first *= nrows * stride           # the level's plane in the flat tables
    first += lo
    second = back.take(span)
    second += first
    flat = tables.reshape(-1)
    low = np.minimum(rows.at(flat, first), rows.at(flat, second))
    np.copyto(low, -np.inf, where=too_long.take(span))
    return rows.bend_bound(low, lo, hi, upper=False)


def _descend(tables, rows, start, c, upper):
    """First column j ≥ start where the blended profile (1 − w)·row0 + w·row1 is not beyond c:
    above it (upper, tables of maxima: the next entry) or below or at it (tables of minima:
    the next exit); `width` if none.

    A window is skipped when the same blend of the two rows' window extremes is still on the
    skipped side: a bound of the blended profile's own extreme (blend of maxima ≥ maximum of
    the blend), so a skip is always right; the last level (single columns) is exact. When a
    bound was too loose to skip, the column found may still be on the skipped side: the
    caller checks it and descends again from the next column. Windows past the row's end hold
    a sentinel that is never skipped, so j ≤ width always.
    """
    levels, _, stride = tables.shape
    skip_if = np.less_equal if upper else np.greater
    i = rows.b0 + start                      # flat index of row0 at the window's start
    a, b = np.empty(i.size, tables.dtype), np.empty(i.size, tables.dtype)
    skip, step = np.empty(i.size, bool), np.empty(i.size, np.int64)
    for k in range(levels - 1, -1, -1):
        flat = tables[k].reshape(-1)
        # (buffers and no bounds checks: this loop is the bake's hottest)
        flat.take(i, out=a, mode="clip")
        flat[stride:].take(i, out=b, mode="clip")     # row1, one row further
        b -= a
        b *= rows.w
        b += a
        bound = b
        if rows.bend is not None:
            pos = i - rows.b0
            bound = rows.bend_bound(b, pos, pos + ((1 << k) - 1), upper)
        skip_if(bound, c, out=skip)
        # (a product, not `where=`: numpy's masked loops are slow on scattered masks)
        np.multiply(skip, 1 << k, out=step)
        i += step
    return i - rows.b0


def search_tables(g, rho_max=None, q=None):
    """The profile G's tables (Search): G (rows, width) float32; rho_max and q as Search's."""
    gmin = _tables(g, np.minimum, -NEVER)
    return Search(gmin[0], _tables(g, np.maximum, NEVER), gmin, _suffix_max(g), g.shape[1],
                   rho_max, q)


def row_value(z, rb, wv, fu):
    """The rebuilt heights z (rows, width) at each ray's start: linear along its two rows
    rb, rb + 1 at column fu, blended by wv."""
    width = z.shape[1]
    k = np.clip(np.floor(fu).astype(np.int64), 0, width - 2)
    f = np.clip(fu - k, 0, 1)
    zf = z.reshape(-1)

    def along(row):
        i = row * width + k
        return zf[i] + (zf[i + 1] - zf[i]) * f
    return along(rb) * (1 - wv) + along(rb + 1) * wv


@dataclass
class Search:
    """A grid's profile G and its tables, all (…, rows, width + 1) with a padding column:
    what every ray's crossing search reads."""
    g: np.ndarray
    gmax: np.ndarray
    gmin: np.ndarray
    suffix: np.ndarray
    width: int
    rho_max: float = None     # polar grids: G − c is δ/ρ, ρ = rho_max − u (see _crossing)
    q: np.ndarray = None      # polar grids of normal maps: 1/ρ (px) per column (see _Rows)


class _Rows:
    """Gathers at column k from the blend (1 − w)·row0 + w·row1 of each ray's two grid rows
    (in a (rows, width + 1) layout, or one level of the tables).

    A bend b per ray (polar grids of normal maps, _PointGrid) makes each ray's profile
    G(k) − b·q(k), q = 1/ρ: its relief is the row's rebuilt height shifted by b, and a shift
    divided by ρ is no shift of G (g; bend_bound bounds it over a window)."""

    def __init__(self, row0, w, stride, bend=None, q=None):
        self.b0 = row0.astype(np.int64) * stride
        self.w, self.stride, self.bend, self.q = w, stride, bend, q

    def sub(self, sel):
        out = _Rows.__new__(_Rows)
        out.b0, out.w, out.stride, out.q = self.b0[sel], self.w[sel], self.stride, self.q
        out.bend = None if self.bend is None else self.bend[sel]
        return out

    def g(self, search, k):
        """The ray's profile at column k."""
        v = self.at(search.g.reshape(-1), k)
        if self.bend is not None:
            v -= self.bend * self.q[np.clip(k, 0, self.q.size - 1)]
        return v

    def bend_bound(self, v, lo, hi, upper):
        """v, a bound of G over columns lo … hi, made a bound of G − b·q (q grows with k)."""
        if self.bend is None:
            return v
        last = self.q.size - 1
        q_lo, q_hi = self.q[np.clip(lo, 0, last)], self.q[np.clip(hi, 0, last)]
        # −b·q is largest at q_lo where b ≥ 0, at q_hi where b < 0 (and the other way round)
        pick = (self.bend >= 0) == upper
        return v - self.bend * np.where(pick, q_lo, q_hi)

    def at(self, flat, k):
        i = self.b0 + k
        a = flat.take(i)
        b = flat[self.stride:].take(i)      # row1; a + (b − a)·w, in place
        b -= a
        b *= self.w
        b += a
        return b


def _crossing(search, rows, pos, col, j, g_here, g_j, cc):
    """Where G crosses c between the ray's position (or column j − 1) and column j, by linear
    interpolation of the ray's depth δ (clipped to [pos, j]): δ = G − c for suns, ρ·(G − c)
    on a polar grid (G = (H − z)/ρ is curved in ρ; δ is linear wherever H is)."""
    first = j == col
    x0 = np.where(first, pos, j - 1.0)
    d0 = np.where(first, g_here, rows.g(search, np.maximum(j - 1, 0))) - cc
    d1 = g_j - cc
    if search.rho_max is not None:
        d0, d1 = d0 * (search.rho_max - x0), d1 * (search.rho_max - j)
    denom = d0 - d1
    frac = np.where(denom != 0, d0 / np.where(denom != 0, denom, 1), 0)
    return np.clip(x0 + frac * (j - x0), pos, j)


def _exit_guess(search, rows, pos, col, g_here, cc, fall):
    """(ok, j, G(j)): where ok, j is the first column ≥ col with G ≤ c, found at the tangent
    plane's exit (δ falls by `fall` per px of u), or a secant step or two past it where the
    ray is still inside there, and proved: G(j) ≤ c, and a lower bound of G over
    col … j − 1 above c (the descent's own answer, without the descent)."""
    width = search.width
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        est = pos + (g_here - cc) / fall
    sel = (g_here > cc) & (fall > 0) & (est < width - 1)
    jg = np.clip(np.ceil(np.where(sel, est, pos)).astype(np.int64), col, width - 1)
    g_j = np.zeros(pos.size, search.g.dtype)
    ok = np.zeros(pos.size, bool)
    p = np.flatnonzero(sel)                   # rays whose candidate is still to check
    for step in range(GUESS_STEPS):
        gp = rows.sub(p).g(search, jg[p])
        g_j[p] = gp
        below = gp <= cc[p]
        hit = p[below]
        far = hit[jg[hit] > col[hit]]
        ok[hit] = True
        if far.size:
            low = _range_min(search.gmin, rows.sub(far), col[far], jg[far] - 1)
            ok[far[low <= cc[far]]] = False
        # still inside at the candidate: a secant step along G to the next one
        p = p[~below]
        if p.size == 0 or step == GUESS_STEPS - 1:
            break
        g0 = rows.sub(p).g(search, jg[p] - 1)
        drop = g0 - g_j[p]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            ahead = np.where(drop > 0, (g_j[p] - cc[p]) / drop, 1)
        nxt = jg[p] + np.clip(np.ceil(ahead), 1, GUESS_LEAP).astype(np.int64)
        p = p[nxt < width]
        jg[p] = nxt[nxt < width]
    return ok, jg, g_j


def inside_length(search, r0, wv, fu, c, g_start, u_end, fall, bend=None):
    """How far each ray runs inside the relief along its row of the grid (§6 by crossings).

    Parameters
    ----------
    search : Search
        The grid's profile G and its tables (search_tables), a block of rows of it.
    r0 : ndarray of int (n,)
        Each ray's grid row, counted from the block's first: its path blends r0 and r0 + 1 …
    wv : ndarray (n,)
        … by this weight (0: row r0 alone, 1: row r0 + 1).
    fu : ndarray (n,)
        The ray's start, in columns from the block's first (fractional).
    c : ndarray (n,)
        The ray's level: it is inside the relief where G > c.
    g_start : ndarray (n,)
        G at the start, from the reference's exact δ0, so that the start is inside exactly
        when it is there.
    u_end : ndarray (n,)
        Where the search stops (columns): the ray leaves the box of pixel centres, reaches
        a point light or its reach.
    fall : ndarray (n,)
        How fast G − c falls per column on the tangent plane of P_S: the first exit's guess
        (_exit_guess).
    bend : ndarray (n,), optional
        Polar grids of normal maps: each ray's relief shift b, its profile G − b·q (_Rows).

    Returns
    -------
    length : ndarray float32 (n,)
        Columns inside the relief between the start and u_end.
    inside_end : ndarray bool (n,)
        Still inside at u_end (the caller adds its tail).
    depth : ndarray (n,)
        δ at u_end where still inside (0 elsewhere): how deep the tail starts.

    Fast lane first: every ray starts inside (d/N.z under the surface) and most leave where
    the tangent plane of P_S says (a guess proved exactly, _exit_guess); with nothing higher
    ahead (the suffix maximum) they are lit and done in one pass. The others (rays in cast
    shadow, ≈ 40 % on tall relief) go round by round, one crossing each, by binary descents;
    rays are compacted as they finish.

    A flat profile the ray starts under and leaves after 2.5 columns:

    >>> g = np.zeros((2, 16), np.float32) - 0.25 * np.arange(16, dtype=np.float32)
    >>> one = np.ones(1, np.float32)
    >>> length, inside, _ = inside_length(search_tables(g), np.zeros(1, int), 0 * one, 0 * one,
    ...                                   -0.625 * one, 0.0 * one, 15 * one, 0.25 * one)
    >>> float(length[0]), bool(inside[0])
    (2.5, False)
    """
    width, stride = search.width, search.g.shape[1]
    sflat = search.suffix.reshape(-1)
    n = fu.size
    total = np.zeros(n, np.float32)
    inside_end = g_start > c
    idx = np.flatnonzero(u_end > fu)           # the rays still marching
    pos = fu[idx]
    col = np.clip(np.floor(pos).astype(np.int64), 0, width - 2) + 1
    g_here = g_start[idx]
    inside = g_here > c[idx]
    # the fast lane
    def rays(i):
        return _Rows(r0[i], wv[i], stride, None if bend is None else bend[i], search.q)
    rows, cc, ue = rays(idx), c[idx], u_end[idx]
    ok, jg, g_j = _exit_guess(search, rows, pos, col, g_here, cc, fall[idx])
    f = np.flatnonzero(ok)
    rf = rows.sub(f)
    cross = _crossing(search, rf, pos[f], col[f], jg[f], g_here[f], g_j[f], cc[f])
    ends = cross >= ue[f]
    total[idx[f]] = np.minimum(cross, ue[f]) - pos[f]
    lit = ~ends & (rf.bend_bound(rf.at(sflat, jg[f]), jg[f], width - 1, True) <= cc[f])
    inside_end[idx[f[ends | lit]]] = True
    inside_end[idx[f[lit]]] = False
    pos[f], col[f], g_here[f], inside[f] = cross, jg[f], cc[f], False
    keep = np.ones(idx.size, bool)
    keep[f[ends | lit]] = False
    idx, pos, col, inside, g_here = idx[keep], pos[keep], col[keep], inside[keep], g_here[keep]

    for _ in range(2 * MAX_CROSSINGS):
        if idx.size == 0:
            break
        rows, cc, ue = rays(idx), c[idx], u_end[idx]
        # outside rays with nothing higher ahead are done (a blended suffix maximum bounds it)
        done = ~inside & (rows.bend_bound(rows.at(sflat, col), col, width - 1, True) <= cc)
        j = col.copy()
        g_j = np.zeros(idx.size, search.g.dtype)    # G at min(j, width − 1), once checked
        todo = ~done
        # descend again where a loose bound, or the top level's reach, stopped one early
        for _ in range(8 + (width >> (search.gmin.shape[0] - 1))):
            sel = np.flatnonzero(todo)
            if sel.size == 0:
                break
            jj = np.empty(sel.size, np.int64)
            ins = inside[sel]
            # inside: the next exit (minima); outside: the next entry (maxima)
            for flag, table in ((True, search.gmin), (False, search.gmax)):
                m = np.flatnonzero(ins == flag)
                if m.size:
                    s_ = sel[m]
                    jj[m] = _descend(table, rows.sub(s_), j[s_], cc[s_], not flag)
            j[sel] = jj
            gj = g_j[sel] = rows.sub(sel).g(search, np.minimum(jj, width - 1))
            wrong = (jj < width) & np.where(ins, gj > cc[sel], gj <= cc[sel])
            todo = np.zeros_like(todo)
            todo[sel[wrong]] = True
            j[sel[wrong]] += 1
        jc = np.minimum(j, width - 1)
        cross = _crossing(search, rows, pos, col, jc, g_here, g_j, cc)
        cross = np.where((j < width) & ~done, cross, np.inf)
        ends = cross >= ue
        seg = np.where(inside, np.minimum(cross, ue) - pos, 0.0)
        total[idx] += seg
        fin = ends | done
        inside_end[idx[fin]] = inside[fin]
        keep = ~fin
        idx, pos, col, inside, g_here = (idx[keep], cross[keep], jc[keep], ~inside[keep],
                                         cc[keep])
    # δ where the rays still inside end (the others' depth is never read)
    end = np.flatnonzero(inside_end)
    ue = np.minimum(u_end[end], width - 1.0)
    k = np.clip(np.floor(ue).astype(np.int64), 0, width - 2)
    there = rays(end)
    ce = c[end]
    d0, d1 = there.g(search, k) - ce, there.g(search, k + 1) - ce
    if search.rho_max is not None:                 # δ = ρ·(G − c) on a polar grid
        d0, d1 = d0 * (search.rho_max - k), d1 * (search.rho_max - k - 1)
    depth = np.zeros(n, d0.dtype)
    depth[end] = d0 + (d1 - d0) * np.clip(ue - k, 0, 1)
    return total, inside_end, depth
