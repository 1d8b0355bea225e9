"""The cos-θ term of a sun over a height map by exact crossings in a light-aligned frame (§6).

The march of shadow.py samples the relief K times along every ray. For a sun every ray has
the same direction, so the relief is resampled once onto a grid whose rows run along the
light's horizontal direction (u toward the light, v across). Along a row a ray rises by
m = L.z/|L.xy| per pixel of u, so with G(u) = H(u) − m·u the ray from (u0, z0) is inside the
relief exactly where G > c = z0 − m·u0. Per row, sparse tables of the maximum and minimum of
G over power-of-two windows find the next up- or down-crossing of c by a binary descent; the
inside length is the sum of the intervals between crossings, each placed by linear
interpolation of G between columns. A ray between two rows takes the two rows' lengths,
weighted by its distance to each. Where a ray is still inside when it leaves the box of pixel
centres, the tail of shadow.py (tangent plane of P_S) finishes it, as in the reference.

Everything is in pixels; the result is t = d / max(r, d) like shadow.cos_theta_shadow.
"""
import numpy as np

from .sampling import pixel_centres, sample_bilinear

MAX_CROSSINGS = 8     # enter/exit pairs followed per ray (more are very rare)


def _tables(g, op):
    """levels[k][r, i] = op(g[r, i : i + 2**k]) (windows that fit; others hold g's own)."""
    levels = [g]
    width = g.shape[1]
    k = 1
    while (1 << (k - 1)) < width:
        prev = levels[-1]
        half = 1 << (k - 1)
        nxt = prev.copy()
        op(prev[:, :width - half], prev[:, half:], out=nxt[:, :width - half])
        levels.append(nxt)
        k += 1
    return levels


def _descend(tables, base0, base1, wv, start, c, width, skip_if):
    """First column j ≥ start where the blended profile (1 − wv)·row0 + wv·row1 does not
    satisfy skip_if(·, c); `width` if none.

    A window is skipped when the same blend of the two rows' window extremes satisfies
    skip_if: a bound of the blended profile's own extreme (blend of maxima ≥ maximum of the
    blend), so a skip is always right; the last level (single columns) is exact. When a
    bound was too loose to skip, the column found may still satisfy skip_if: the caller
    checks it and descends again from the next column.
    """
    pos = start.copy()
    for k in range(len(tables) - 1, -1, -1):
        size = 1 << k
        cand = pos + size
        ok = cand <= width
        at = np.minimum(pos, width - 1)
        flat = tables[k].reshape(-1)
        win = np.take(flat, base0 + at) * (1 - wv) + np.take(flat, base1 + at) * wv
        pos = np.where(ok & skip_if(win, c), cand, pos)
    return pos


def sun_cos_theta(normals, heights_px, light, offset):
    """t = d / max(r, d) (H, W) for a sun over a height map, r from exact crossings."""
    dtype = normals.dtype
    h, w = heights_px.shape
    lvec = np.asarray(light.vector, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    lx, ly, lz = lvec
    if lz <= 0:
        return np.zeros((h, w), dtype)
    lxy = float(np.hypot(lx, ly))
    d = max(0.0, float(offset)) * w
    nx, ny, nz = (normals[..., i].astype(np.float64) for i in range(3))
    ndl = nx * lx + ny * ly + nz * lz
    if lxy < 1e-6 or d == 0:
        from .shadow import cos_theta_shadow            # straight up, or the d → 0 limit
        return cos_theta_shadow(normals, light, offset, 64, heights_px=heights_px)
    ex, ey = lx / lxy, ly / lxy                          # along the light, in xy
    m = lz / lxy                                         # rise per pixel of u
    cx, cy = w / 2.0, h / 2.0
    # the light-aligned grid covering the box of pixel centres
    bx = np.array([0.5, w - 0.5, 0.5, w - 0.5]) - cx
    by = np.array([0.5, 0.5, h - 0.5, h - 0.5]) - cy
    us, vs = bx * ex + by * ey, -bx * ey + by * ex
    umin, vmin = np.floor(us.min()) - 1, np.floor(vs.min()) - 1
    width = int(np.ceil(us.max() - umin)) + 2
    rows = int(np.ceil(vs.max() - vmin)) + 2
    gu = umin + np.arange(width)
    gv = vmin + np.arange(rows)
    gx = cx + gu[None, :] * ex - gv[:, None] * ey
    gy = cy + gu[None, :] * ey + gv[:, None] * ex
    z = sample_bilinear(heights_px.astype(np.float32), gx.astype(np.float32),
                        gy.astype(np.float32), "extend").astype(np.float64)
    g = z - m * gu[None, :]            # beyond the box the relief extends; rays stop there
    gmax = _tables(g, np.maximum)
    gmin = _tables(g, np.minimum)

    # ray starts P0 = P_S − d·N, in grid coordinates
    x, y = pixel_centres(h, w, np.float64)
    zs = heights_px.astype(np.float64)
    x0, y0, z0 = x - d * nx, y - d * ny, zs - d * nz
    u0 = (x0 - cx) * ex + (y0 - cy) * ey
    v0 = -(x0 - cx) * ey + (y0 - cy) * ex
    fu, fv = (u0 - umin).ravel(), (v0 - vmin).ravel()
    c = (z0 - m * u0).ravel()
    r0 = np.clip(np.floor(fv).astype(np.int64), 0, rows - 2)
    wv = np.clip(fv - r0, 0.0, 1.0)
    rate = (ndl / nz).ravel()
    from .shadow import _exit_distance, _inside_box
    inbox0 = _inside_box(x0, y0, h, w).ravel()
    u_end = fu + _exit_distance(x0, y0, np.full_like(x0, ex), np.full_like(x0, ey), h, w).ravel()
    r_h = _inside_length(g, gmax, gmin, r0, wv, fu, c, width, u_end, rate, lxy)
    # P0 outside the box: no march, the tail from the tangent plane of P_S (δ0 = d/N.z)
    with np.errstate(divide="ignore", invalid="ignore"):
        out_tail = np.where(rate > 0, (d / nz.ravel()) / rate * lxy, 0)
    r_h = np.where(inbox0, r_h, out_tail)
    r = (r_h / lxy).reshape(h, w)                           # along the 3D ray
    t = d / np.maximum(r, d)
    return np.clip(np.where(np.isfinite(t), t, 0), 0, 1).astype(dtype, copy=False)


def _inside_length(g, gmax, gmin, r0, wv, fu, c, width, u_end, rate, lxy):
    """Length (px of u) of each ray inside the relief, along the profile blended from the two
    grid rows around it, until it leaves the box of pixel centres at u_end; plus the
    reference's tangent-plane tail if it is still inside there."""
    gflat = g.reshape(-1)
    base0, base1 = r0 * width, (r0 + 1) * width

    def g_col(k):
        k = np.clip(k, 0, width - 1)
        return np.take(gflat, base0 + k) * (1 - wv) + np.take(gflat, base1 + k) * wv

    def g_at(u):
        k = np.clip(np.floor(u).astype(np.int64), 0, width - 2)
        a, b = g_col(k), g_col(k + 1)
        return a + (b - a) * np.clip(u - k, 0.0, 1.0)
    exit_if = lambda v, cc: v > cc       # noqa: E731  (inside: skip while all of it is above c)
    entry_if = lambda v, cc: v <= cc     # noqa: E731  (outside: skip while all of it is below)
    g_here = g_at(fu)                    # G where the ray is now
    inside = g_here > c
    pos = fu.copy()                      # where the ray is now (u, grid units)
    col = np.clip(np.floor(fu).astype(np.int64), 0, width - 2) + 1
    total = np.zeros_like(fu)
    active = u_end > pos
    for _ in range(4 * MAX_CROSSINGS):
        if not active.any():
            break
        j = col.copy()
        todo = active.copy()
        for _ in range(8):               # descend again where a loose bound stopped early
            jj = np.where(inside, _descend(gmin, base0, base1, wv, j, c, width, exit_if),
                          _descend(gmax, base0, base1, wv, j, c, width, entry_if))
            j = np.where(todo, jj, j)
            gj = g_col(j)
            wrong = todo & (j < width) & np.where(inside, gj > c, gj <= c)
            if not wrong.any():
                break
            j = np.where(wrong, j + 1, j)
            todo = wrong
        jc = np.minimum(j, width - 1)
        g1 = g_col(jc)
        first = jc == col                # the crossing is in the segment the ray is in
        x0 = np.where(first, pos, jc - 1.0)
        g0 = np.where(first, g_here, g_col(jc - 1))
        denom = g0 - g1
        frac = np.where(denom != 0, (g0 - c) / np.where(denom != 0, denom, 1), 0)
        cross = np.where(j < width, np.clip(x0 + frac * (jc - x0), pos, jc), np.inf)
        ends = active & (cross >= u_end)         # the box ends before the next crossing
        total = np.where(active & inside, total + (np.minimum(cross, u_end) - pos), total)
        active &= ~ends
        pos = np.where(active, cross, pos)
        col = np.where(active, jc, col)
        inside = np.where(active, ~inside, inside)
        g_here = np.where(active, c, g_here)
    # still inside where the box ends: the tail along the tangent plane of P_S (§6)
    delta = g_at(np.minimum(u_end, width - 1.0)) - c
    with np.errstate(divide="ignore", invalid="ignore"):
        tail = np.where(inside & (delta > 0) & (rate > 0), delta / rate * lxy, 0)
    return total + tail
