"""The cos-θ term by crossings (§6): the fast bake, for suns and for point lights.

The march of shadow.py samples the relief K times along every ray. Here the relief is
resampled once onto a grid whose rows are the rays' paths, and each ray's crossings in and
out of the relief are searched along its row:

- Suns (_SunGrid): every ray has the same direction; rows run along the light's horizontal
  direction (u toward the light, v across). A ray rises by m = L.z/|L.xy| per pixel of u, so
  with G(u) = H(u) − m·u it is inside the relief exactly where G > c = z0 − m·u0.
- Point lights over height maps (_PointGrid): a polar grid around the light's foot; the ray
  is aimed at the light (§6 "Which ray"), G = (H − z_L)/ρ, c = (z0 − z_L)/ρ0.

The search along a row (crossing_search.py) is the same for both: sparse tables of G find
each ray's next crossing of c by a binary descent, and the inside length is the sum of the
intervals between crossings. Here: the two grids and the rays' tails; the blocks they are
stored in and the rays' starts (Rays) are crossing_blocks.py's. The
start is the reference's: δ0 from the exact bilinear relief at P0 (height maps) or the tangent
plane of P_S (normal maps, whose rebuilt height along a row is the running integral of the
row's slope). Where a ray is still inside when it leaves the box of pixel centres, the tail
of shadow.py (tangent plane of P_S) finishes it, as in the reference; a flat plane gives
cos θ exactly, up to the border.

Both grids are stored in blocks of rows, each as wide as its rows' rays can read, and
built in groups of blocks that fit MAX_TABLE_BYTES (crossing_blocks.BlockGrid). Measured
(benchmarks/shadow_quality.py, 1024², relief 0.5 image widths, d = 0.01): mean |Δt|
1.4e-4–5e-4 against the K = 1024 float64 reference for suns and point lights (the K = 64
march: 1e-3–2e-2).
Everything is in pixels; the result is t = d / max(r, d) like shadow.cos_theta_shadow.
"""
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import crossing_blocks
from .crossing_blocks import BlockGrid, Rays, start_points, table_groups
from .crossing_search import inside_length, row_value, search_tables
from .sampling import sample_extend
from .shadow import cos_theta_shadow, exit_distance, inside_box, vertical_cos_theta
from .strokes import grow, union

SUN_BLOCKS, SUN_BLOCK_ROWS = 8, 160   # _SunGrid's blocks of rows: at most 8, ≥ 160 rows
POINT_RHO_MIN = 1e-3   # ρ (px) below which G = (H − z_L)/ρ divides by this: only a column at F
POINT_ARC = 2.0   # row spacing (px) at ρ_max of full-circle grids (most rays are nearer F)
POINT_STEP = 0.7  # column spacing (px of ρ) of polar grids at final: finer than pixels
# _PointGrid's blocks of rows, each trimmed to the box seen from F: at most 16, one per 2**18
# cells of the untrimmed grid, at least one per thread (small grids: per-call costs dominate)
POINT_BLOCKS, POINT_BLOCK_CELLS = 16, 1 << 18


def sun_cos_theta(normals, light, offset, *, heights_px=None, slopes=None, reach=np.inf,
                  cancel=None, progress=None):
    """t = d / max(r, d) (H, W) for a sun, r from exact crossings.

    heights_px: the relief in pixels (height maps); or slopes (H, W, 2), −N.xy/N.z (normal
    maps): along a grid row the rebuilt height is then the running integral of the row's
    slope, so the same crossing search applies (§6: height rebuilt along the ray only), felt
    up to `reach` image widths along the ray (shadow.cos_theta_shadow). cancel, progress: as
    cos_theta_shadow's, asked and told once per chunk of rays (large paintings).
    """
    dtype = normals.dtype
    h, w = normals.shape[:2]
    lvec = np.asarray(light.vector, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    if lvec[2] <= 0:
        return np.zeros((h, w), dtype)
    if offset <= 0:             # the d → 0 limit: hard visibility, marched
        return cos_theta_shadow(normals, light, offset, 64, heights_px=heights_px, slopes=slopes,
                                reach=reach, cancel=cancel, progress=progress)
    if np.hypot(lvec[0], lvec[1]) < 1e-6:
        # straight up: no horizontal direction to lay rows along, and no need (closed form;
        # on a normal map t = N.z whatever the reach)
        return vertical_cos_theta(normals, offset, heights_px=heights_px)
    reach_px = max(0.0, float(reach)) * w if slopes is not None else np.inf
    return _bake(_SunGrid(lvec, h, w, reach_px), normals, offset, heights_px, slopes, cancel,
                 progress)


def sun_cos_theta_edited(normals, light, offset, t, normals_box, heights_box, *,
                         heights_px=None, slopes=None, reach=np.inf):
    """sun_cos_theta of an edited shape from `t`, the term before the edit (issue 41): the
    edit changed the normals in `normals_box` and the relief in `heights_box` (pixel boxes,
    core/strokes.py; None: unchanged). Only the rays that read a changed pixel are traced
    again (_SunGrid.retrace), so the result is the whole bake's of the edited shape. None
    where this does not apply (d = 0 marches; tables beyond memory): bake the whole then."""
    h, w = normals.shape[:2]
    lvec = np.asarray(light.vector, dtype=np.float64)
    lvec = lvec / np.linalg.norm(lvec)
    if lvec[2] <= 0 or offset <= 0 or np.hypot(lvec[0], lvec[1]) < 1e-6:
        return None          # (nothing to trace: the whole bake is as cheap)
    reach_px = max(0.0, float(reach)) * w if slopes is not None else np.inf
    return _retrace(_SunGrid(lvec, h, w, reach_px), normals, offset, t, normals_box,
                    heights_box, heights_px, slopes)


def point_cos_theta_edited(normals, light, offset, t, normals_box, heights_box, *,
                           heights_px=None, slopes=None, reach=np.inf, step=POINT_STEP):
    """point_cos_theta of an edited shape from `t`, the term before the edit, as
    sun_cos_theta_edited (issue 61: a dab under a point light at a sun's speed): only the
    rays whose rows (the angles about the light's foot that see the edit) read a changed
    pixel nearer the light than their start are traced again. None where every row reads
    the edit (the light's foot over it) or d = 0: bake the whole then."""
    if offset <= 0:
        return None
    h, w = normals.shape[:2]
    reach_px = max(0.0, float(reach)) * w if slopes is not None else np.inf
    return _retrace(_PointGrid(light, h, w, offset, reach_px, step), normals, offset, t,
                    normals_box, heights_box, heights_px, slopes)


def _retrace(grid, normals, offset, t, normals_box, heights_box, heights_px, slopes):
    h, w = normals.shape[:2]
    d = float(offset) * w
    # a start reads its own normal, and the relief within d of its pixel
    own = union(normals_box, grow(heights_box, d + 2, h, w))
    path = heights_box if heights_px is not None else normals_box
    return grid.retrace(_pool(), normals, offset, heights_px, slopes, t, path, own)


def _relative(phi, centre):
    """Angles `phi` relative to `centre`, in (−π, π]."""
    return np.angle(np.exp(1j * (phi - centre)))


def _bake(grid, normals, offset, heights_px, slopes, cancel=None, progress=None):
    """t (H, W) by the grid's crossing search. numpy releases the GIL on large arrays: the
    blocks' profiles and tables, the rays' starts and their searches each run side by side,
    on threads kept for every bake (a moving painting bakes a frame at a time: starting them
    for each bake cost a few ms of its budget; no task waits on another, so bakes from two
    threads — a render's and the live worker's — share them safely)."""
    return grid.trace(_pool(), normals, offset, heights_px, slopes, cancel, progress)


_POOL = []


def _pool():
    if not _POOL:
        _POOL.append(ThreadPoolExecutor(crossing_blocks.THREADS, thread_name_prefix="dynpaint-crossings"))
    return _POOL[0]


class _SunGrid(BlockGrid):
    """The light-aligned grid covering the box of pixel centres: column u runs toward the
    light (horizontally), row v across; one grid step is one pixel.

    Up to SUN_BLOCKS blocks: a rotated image's bounding grid is up to twice its area, 8
    blocks ≈ 1.3×.
    """

    def __init__(self, lvec, h, w, reach_px=np.inf):
        lx, ly, lz = lvec
        self.h, self.w = h, w
        self.lxy = float(np.hypot(lx, ly))
        self.ex, self.ey = lx / self.lxy, ly / self.lxy
        self.m = lz / self.lxy                          # rise per pixel of u
        self.reach_u = reach_px * self.lxy              # the reach, in pixels of u
        self.cx, self.cy = w / 2.0, h / 2.0
        bx = np.array([0.5, w - 0.5, 0.5, w - 0.5]) - self.cx
        by = np.array([0.5, 0.5, h - 0.5, h - 0.5]) - self.cy
        us, vs = bx * self.ex + by * self.ey, -bx * self.ey + by * self.ex
        self.umin, self.vmin = np.floor(us.min()) - 1, np.floor(vs.min()) - 1
        self.width = int(np.ceil(us.max() - self.umin)) + 2
        self.rows = int(np.ceil(vs.max() - self.vmin)) + 2
        # small grids: fewer blocks, fewer calls
        self._split(*self._footprint(np.arange(self.rows)),
                    min(SUN_BLOCKS, self.rows // SUN_BLOCK_ROWS))

    def _footprint(self, rows):
        """Column range (lo, hi) of each grid row inside the box of pixel centres grown by
        3 px (empty rows: lo > hi)."""
        v = self.vmin + rows
        lo = np.full(rows.shape, -np.inf)
        hi = np.full(rows.shape, np.inf)
        grow = 3.0
        for e, across, centre, size in ((self.ex, -self.ey, self.cx, self.w),
                                        (self.ey, self.ex, self.cy, self.h)):
            # coordinate = centre + u·e + v·across must lie in [0.5 − grow, size − 0.5 + grow]
            a, b = 0.5 - grow - centre - v * across, size - 0.5 + grow - centre - v * across
            if abs(e) > 1e-12:
                ua, ub = a / e, b / e
                lo, hi = np.maximum(lo, np.minimum(ua, ub)), np.minimum(hi, np.maximum(ua, ub))
            else:
                out = (a > 0) | (b < 0)
                lo, hi = np.where(out, np.inf, lo), np.where(out, -np.inf, hi)
        lo = np.where(np.isfinite(lo), lo - self.umin, 0)
        hi = np.where(np.isfinite(hi), hi - self.umin, self.width - 1)
        return lo, hi

    def _inputs(self, heights_px, slopes):
        f32 = np.float32
        hz = None if heights_px is None else heights_px.astype(f32, copy=False)
        # slope along u at each grid point (lookups are linear: one image of it)
        sz = None if slopes is None else \
            (slopes[..., 0] * self.ex + slopes[..., 1] * self.ey).astype(f32)
        return hz, sz

    def _profile(self, spec, hz, sz):
        """A block's profile G = H − m·u (float32) and tables, and the rebuilt heights z
        (normal maps)."""
        f32 = np.float32
        a, n, c0, c1 = spec
        gu = self.umin + np.arange(c0, c1)
        v = (self.vmin + np.arange(a, a + n))[:, None]
        gx = (self.cx + gu * self.ex).astype(f32)[None, :] - (v * self.ey).astype(f32)
        gy = (self.cy + gu * self.ey).astype(f32)[None, :] + (v * self.ex).astype(f32)
        if hz is not None:
            return search_tables(sample_extend(hz, gx, gy) - (self.m * gu).astype(f32)), None
        # the running integral (trapezoids) of the slope is the height along the row
        su = sample_extend(sz, gx, gy).astype(np.float64)
        z = np.zeros(su.shape)
        np.cumsum((su[:, 1:] + su[:, :-1]) / 2, axis=1, out=z[:, 1:])
        return search_tables((z - self.m * gu[None, :]).astype(f32)), z

    def starts(self, normals, offset, heights_px, where):
        """The rays of pixel rows where = (r0, r1), or of pixels `where`, in grid coordinates
        (flat arrays)."""
        h, w, ex, ey, m, lxy = self.h, self.w, self.ex, self.ey, self.m, self.lxy
        d = float(offset) * w
        # float32 (positions < 2·10³ px keep 1e-4 px); the level c of each ray in float64
        f32 = np.float32
        nx, ny, nz, x0, y0, z0, delta0, h0 = start_points(normals, d, heights_px, where)
        ndl = (nx * f32(ex) + ny * f32(ey)) * f32(lxy) + nz * f32(m * lxy)
        # ray starts in grid coordinates
        xc, yc = x0 - f32(self.cx), y0 - f32(self.cy)
        u0 = xc * f32(ex) + yc * f32(ey)
        fu = (u0 - f32(self.umin)).ravel()
        fv = (yc * f32(ex) - xc * f32(ey) - f32(self.vmin)).ravel()
        inbox0 = inside_box(x0, y0, h, w)
        # to the box's edge along (ex, ey) (shadow.exit_distance for one direction)
        to_x = ((f32(w - 0.5) - x0) if ex > 0 else (f32(0.5) - x0)) / f32(ex) if ex else np.inf
        to_y = ((f32(h - 0.5) - y0) if ey > 0 else (f32(0.5) - y0)) / f32(ey) if ey else np.inf
        row0 = np.clip(np.floor(fv).astype(np.int32), 0, self.rows - 2)
        to_edge = np.where(inbox0, np.maximum(np.minimum(to_x, to_y), 0), 0).ravel()
        fall = (ndl / nz).ravel() / f32(lxy)       # δ's fall per px of u (tangent plane)
        with np.errstate(divide="ignore", invalid="ignore"):
            # P0 outside the box: no search, the tail from the tangent plane of P_S (δ0 = d/N.z)
            alone = np.where(fall > 0, (f32(d) / nz.ravel()) / fall, np.inf).astype(f32)
        return Rays(fu=fu, row0=row0, wv=np.clip(fv - row0, f32(0), f32(1)),
                    c=(z0.astype(np.float64) - m * u0.astype(np.float64)).ravel(),
                    u_end=fu + np.minimum(to_edge, f32(min(self.reach_u, 1e30))),
                    by_reach=to_edge > self.reach_u, searched=inbox0.ravel(),
                    delta0=delta0.ravel(), h0=None if h0 is None else h0.ravel(), fall=fall,
                    alone=alone)

    def _search_block(self, spec, block_search, ray, sel):
        """The inside length (px of u) of rays `sel`, all in block `spec`, with the tail."""
        f32 = np.float32
        search, z = block_search
        rb, fub, ueb = self._block_rays(spec, ray, sel)
        wv, fall, cb = ray.wv[sel], ray.fall[sel], ray.c[sel]
        if z is not None:
            # the row's running integral, shifted so that it reads H(P0) at the start
            cb = cb - ray.h0[sel] + row_value(z, rb, wv, fub)
        total, inside_end, gap = inside_length(
            search, rb, wv, fub.astype(f32), cb.astype(f32),
            (cb + ray.delta0[sel]).astype(f32), ueb.astype(f32), fall)
        # still inside where the box ends: the tail along the tangent plane of P_S (§6);
        # stopped by the reach: the rest of the ray against that plane itself
        with np.errstate(divide="ignore", invalid="ignore"):
            tail = np.where(inside_end & (gap > 0), np.where(fall > 0, gap / fall, np.inf), 0)
            plane = np.where(fall > 0, np.maximum(ray.delta0[sel] / fall - self.reach_u, 0),
                             np.inf)
        return total + np.where(ray.by_reach[sel], plane, tail)

    def finish(self, ray, r_h, d):
        r = r_h / self.lxy                                      # along the 3D ray
        return d / np.maximum(r, d)

    # -- an edit (issue 41): only the rays that read changed pixels are traced again ------
    def cells_reading(self, box, beyond):
        """(mask of the grid rows whose profile reads pixels of `box` (strokes.py), the last
        column that does): a lookup reads the pixels within 1 px of its point, and past the
        image's edge the edge's own, up to `beyond` px from it (None: as far as the grid
        runs)."""
        x_lo, x_hi, y_lo, y_hi = self.read_area(
            box, beyond if beyond is not None else self.width + self.rows)
        xs = np.array([x_lo, x_hi, x_lo, x_hi]) - self.cx
        ys = np.array([y_lo, y_lo, y_hi, y_hi]) - self.cy
        v = ys * self.ex - xs * self.ey - self.vmin
        u = xs * self.ex + ys * self.ey - self.umin
        mask = np.zeros(self.rows, bool)
        mask[max(0, int(np.floor(v.min())) - 1):int(np.ceil(v.max())) + 2] = True
        return mask, int(np.ceil(u.max())) + 1

    def pixels_near(self, mask, last_column, margin):
        """Flat indices of the pixels whose rays may read the rows of `mask`: those whose
        centre lies within `margin` of them (a ray starts within d of its pixel)."""
        rows = np.flatnonzero(mask)
        return self._pixels_near_rows(rows[0] - 1, rows[-1] + 1, margin)

    def _pixels_near_rows(self, first, last, margin):
        """Flat indices of the pixels whose centre lies within grid rows first − margin …
        last + margin (a ray starts within d of its pixel): per pixel row, an interval."""
        h, w, ex, ey = self.h, self.w, self.ex, self.ey
        v_lo, v_hi = self.vmin + first - margin, self.vmin + last + margin
        rows = np.arange(h)
        yv = (rows + 0.5 - self.cy) * ex              # v = yv − (x − cx)·ey
        if abs(ey) < 1e-12:
            full = (yv >= v_lo) & (yv <= v_hi)
            lo, hi = np.where(full, 0, w), np.where(full, w - 1, -1)
        else:
            xa, xb = self.cx + (yv - v_lo) / ey, self.cx + (yv - v_hi) / ey
            lo = np.ceil(np.minimum(xa, xb) - 0.5).clip(0, w).astype(np.int64)
            hi = np.floor(np.maximum(xa, xb) - 0.5).clip(-1, w - 1).astype(np.int64)
        counts = np.maximum(hi - lo + 1, 0)
        firsts = rows * w + lo
        ends = np.cumsum(counts)
        return np.arange(ends[-1] if h else 0) - np.repeat(ends - counts, counts) + \
            np.repeat(firsts, counts)


def point_cos_theta(normals, light, offset, *, heights_px=None, slopes=None, reach=np.inf,
                    step=POINT_STEP, cancel=None, progress=None):
    """t = d / max(r, d) (H, W) for a point light, by crossings along the rows of a polar
    grid around the light's foot (_PointGrid): each ray is aimed from P0 at the light, §6's
    ray. heights_px, or slopes and reach, cancel and progress as sun_cos_theta; step: the
    grid's column spacing (px; coarser is faster, and less exact near walls)."""
    if offset <= 0:             # the d → 0 limit: hard visibility, marched (as suns)
        return cos_theta_shadow(normals, light, offset, 64, heights_px=heights_px, slopes=slopes,
                                reach=reach, cancel=cancel, progress=progress)
    h, w = normals.shape[:2]
    reach_px = max(0.0, float(reach)) * w if slopes is not None else np.inf
    return _bake(_PointGrid(light, h, w, offset, reach_px, step), normals, offset, heights_px,
                 slopes, cancel, progress)


def table_bytes(light, h, w, offset, step=POINT_STEP):
    """(all blocks, the largest block): the memory the profiles and tables of a crossing bake
    of this light take at (h, w); its blocks are built in groups within MAX_TABLE_BYTES
    (BlockGrid.groups), so a bake needs the largest block to fit."""
    sizes = _grid(light, h, w, offset, step)
    return (0, 0) if sizes is None else (sum(sizes), max(sizes))


def _grid(light, h, w, offset, step):
    """The table bytes of each block of this light's grid at (h, w); None: no grid (a sun
    below the horizon, or straight up)."""
    if light.kind == "sun":
        lvec = np.asarray(light.vector, np.float64) / np.linalg.norm(light.vector)
        if lvec[2] <= 0 or np.hypot(lvec[0], lvec[1]) < 1e-6:
            return None
        grid = _SunGrid(lvec, h, w)
    else:
        grid = _PointGrid(light, h, w, offset, step=step)
    return grid.block_bytes()


def table_peak(light, h, w, offset, step=POINT_STEP):
    """The most memory the tables of a crossing bake of this light hold at once at (h, w):
    its largest group of blocks; 0 where it has no grid (memory.py's estimate)."""
    sizes = _grid(light, h, w, offset, step) or []
    return max((sum(sizes[b] for b in g) for g in table_groups(sizes)), default=0)


class _PointGrid(BlockGrid):
    """A polar grid around the foot F of a point light: row v = angle φ about F, column u =
    (ρ_max − ρ) / col_step (toward the light); rows POINT_ARC px apart at ρ_max.

    A ray aimed from P0 at the light P_L runs along a row, and with G(ρ) = (H − z_L)/ρ it is
    inside the relief exactly where G > c = (z0 − z_L)/ρ0 (the line from P0 to P_L has
    height z_L + (z0 − z_L)·ρ/ρ0), so the search of the suns applies unchanged. It is §6's
    ray ("Which ray", amended 2026-11-23: the paper's segment from P'_S to P_L), the one the
    reference march follows too.

    Normal maps: the height rebuilt along a row is the running integral of its slope (as
    for suns), but a ray's relief is that shifted by its own b (so that it reads H(P0) at
    P0), and a shift is no constant in G = (H − z_L)/ρ: each ray searches G − b/ρ, which
    _Rows bounds over a window from the window's ends. Felt up to the reach, then P_S's
    tangent plane, as the reference.

    Columns are closer than the suns' (POINT_STEP at final) because rays near the light are
    steep: the profile's chords between columns cut a wall's top corner, and the 3D length
    missed is the horizontal one times dist/ρ0. Each block keeps only the columns its
    angles' rays can start from (the box seen from F): half a full-circle grid.
    """

    def __init__(self, light, h, w, offset, reach_px=np.inf, step=POINT_STEP):
        self.h, self.w, self.reach_px, self.col_step = h, w, reach_px, step
        self.fx, self.fy, self.zl = (float(v) for v in light.position_px(h, w))
        margin = float(offset) * w + 2                 # ray starts lie within d of the box
        xs, ys = (0.5 - margin, w - 0.5 + margin), (0.5 - margin, h - 0.5 + margin)
        corners = np.array([(x - self.fx, y - self.fy) for x in xs for y in ys])
        self.rho_max = float(np.hypot(corners[:, 0], corners[:, 1]).max()) + 2
        base, lo, hi, near = self._seen_from_f(xs, ys)
        if xs[0] < self.fx < xs[1] and ys[0] < self.fy < ys[1]:
            self.rows = int(np.ceil(2 * np.pi * self.rho_max / POINT_ARC)) + 2
            self.phi0 = -np.pi
            self.dphi = 2 * np.pi / (self.rows - 2)    # one row past 2π: the seam blends
        else:
            self.dphi = 1 / self.rho_max                 # one pixel apart at ρ_max, as suns
            self.phi0 = base + lo - 2 * self.dphi
            self.rows = int(np.ceil((hi - lo) / self.dphi)) + 5
        # rays end where they leave the box, so the grid stops at its nearest point to F
        self.width = int(np.ceil((self.rho_max - max(near - 2, 0)) / step)) + 2
        far = self._farthest(self.phi0 + self.dphi * np.arange(self.rows), xs, ys)
        self._split((self.rho_max - far - 3) / step, np.full(self.rows, self.width - 1.0),
                    max(crossing_blocks.THREADS, min(POINT_BLOCKS, self.rows * self.width // POINT_BLOCK_CELLS)))

    def _seen_from_f(self, xs, ys):
        """(the angle about F of the box xs × ys's centre, the least and the greatest angle of
        its corners from that one, its distance from F): F outside the box, the corners'
        angles span under π."""
        centre = np.arctan2((ys[0] + ys[1]) / 2 - self.fy, (xs[0] + xs[1]) / 2 - self.fx)
        rel = _relative(np.arctan2(np.repeat(ys, 2) - self.fy, np.tile(xs, 2) - self.fx),
                        centre)
        near = np.hypot(max(xs[0] - self.fx, 0, self.fx - xs[1]),
                        max(ys[0] - self.fy, 0, self.fy - ys[1]))
        return centre, rel.min(), rel.max(), near

    def _farthest(self, phi, xs, ys):
        """ρ where a line from F at angle φ leaves the box xs × ys (−∞ where it misses it):
        the slab test, ρ ≥ 0 inside both slabs."""
        lo, hi = np.zeros(phi.shape), np.full(phi.shape, np.inf)
        for e, f, (a, b) in ((np.cos(phi), self.fx, xs), (np.sin(phi), self.fy, ys)):
            with np.errstate(divide="ignore", invalid="ignore"):
                ta, tb = (a - f) / e, (b - f) / e
            along = np.abs(e) > 1e-12          # else parallel to the slab: in it or never
            lo = np.where(along, np.maximum(lo, np.minimum(ta, tb)), lo if a <= f <= b else np.inf)
            hi = np.where(along, np.minimum(hi, np.maximum(ta, tb)), hi)
        return np.where(hi >= lo, hi, -np.inf)

    def _inputs(self, heights_px, slopes):
        if heights_px is not None:
            return heights_px.astype(np.float32, copy=False), None
        return None, [np.ascontiguousarray(slopes[..., i], np.float32) for i in (0, 1)]

    def _profile(self, spec, hz, sxy):
        """A block's profile G = (H − z_L)/ρ and its tables, and the rebuilt heights z
        (normal maps); the search reads ρ (in columns) as its rho_max − u, u counted from
        the block's first column."""
        f32 = np.float32
        a, n, c0, c1 = spec
        rho = self.rho_max - self.col_step * np.arange(c0, c1)
        phi = self.phi0 + self.dphi * np.arange(a, a + n)
        cos, sin = np.cos(phi)[:, None], np.sin(phi)[:, None]
        gx = (self.fx + cos * rho[None, :]).astype(f32)
        gy = (self.fy + sin * rho[None, :]).astype(f32)
        inv = (1 / np.maximum(rho, POINT_RHO_MIN)).astype(f32)
        rho_cols = self.rho_max / self.col_step - c0
        if hz is not None:
            return search_tables((sample_extend(hz, gx, gy) - f32(self.zl)) * inv[None, :],
                                 rho_cols), None
        # toward F the slope along the row is −(s·(cos φ, sin φ)); its running integral
        # (trapezoids, col_step px a column) is the height along the row
        su = -(sample_extend(sxy[0], gx, gy) * cos + sample_extend(sxy[1], gx, gy) * sin)
        z = np.zeros(su.shape)
        np.cumsum((su[:, 1:] + su[:, :-1]) * (self.col_step / 2), axis=1, out=z[:, 1:])
        return search_tables(((z - self.zl) * inv[None, :]).astype(f32), rho_cols,
                       np.append(inv, inv[-1])), z

    def starts(self, normals, offset, heights_px, where):
        """The rays of pixel rows where = (r0, r1), or of pixels `where`, in grid coordinates
        (flat arrays)."""
        h, w = self.h, self.w
        d = float(offset) * w
        f32 = np.float32
        nx, ny, nz, x0, y0, z0, delta0, h0 = start_points(normals, d, heights_px, where)
        dx, dy, dz = f32(self.fx) - x0, f32(self.fy) - y0, f32(self.zl) - z0
        rho0 = np.hypot(dx, dy)
        dist = np.sqrt(rho0 * rho0 + dz * dz)                    # P0 → P_L
        safe = np.maximum(rho0, f32(1e-6))
        ndl = (nx * dx + ny * dy + nz * dz) / np.maximum(dist, f32(1e-6))     # N·L0
        fall_d = (ndl / nz) * dist / safe        # δ's fall per px of ρ on the tangent plane
        step = f32(self.col_step)
        fu = (f32(self.rho_max) - rho0) / step
        # the angle from φ0, in [0, 2π): φ0 may lie below −π (a foot right of the image)
        fv = np.mod(np.arctan2(-dy, -dx) - f32(self.phi0), f32(2 * np.pi)) / f32(self.dphi)
        row0 = np.clip(np.floor(fv).astype(np.int64), 0, self.rows - 2)
        c = -dz / safe
        box = exit_distance(x0, y0, dx / safe, dy / safe, h, w)
        reach_h = f32(min(self.reach_px, 1e30)) * safe / np.maximum(dist, f32(1e-6))
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # P0 outside the box or under the light: the tangent-plane tail from δ0 = d/N.z
            alone = np.minimum(np.where(fall_d > 0, (f32(d) / nz) / fall_d, np.inf), rho0)
        flat = {"fu": fu, "row0": row0, "wv": np.clip(fv - row0, f32(0), f32(1)), "c": c,
                "delta0": delta0, "h0": h0, "g_start": c + delta0 / safe,
                "u_end": fu + np.minimum(np.minimum(box, rho0), reach_h) / step,
                "reach_h": reach_h, "by_reach": np.minimum(box, rho0) > reach_h,
                "fall_d": fall_d, "to_light": box >= rho0, "rho0": rho0, "alone": alone,
                "searched": inside_box(x0, y0, h, w) & (rho0 >= 1), "ndl": ndl,
                "slant": dist / safe}
        return Rays(**{k: None if v is None else v.ravel() for k, v in flat.items()})

    def _search_block(self, spec, block_search, ray, sel):
        """The inside length (px of ρ) of rays `sel`, all in block `spec`, with the tail."""
        search, z = block_search
        rb, fub, ueb = self._block_rays(spec, ray, sel)
        wv, fall_d, step = ray.wv[sel], ray.fall_d[sel], np.float32(self.col_step)
        # normal maps: each ray's relief is its rows' rebuilt heights shifted by
        # b = z(P0) − H(P0), so that it reads H(P0) at the start (the class)
        bend = None if z is None else \
            (row_value(z, rb, wv, fub) - ray.h0[sel]).astype(np.float32)
        rho0 = ray.rho0[sel]
        total, inside_end, gap = inside_length(
            search, rb, wv, fub, ray.c[sel], ray.g_start[sel], ueb,
            fall_d / np.maximum(rho0, np.float32(1e-6)) * step, bend)
        total, gap = total * step, gap * step        # columns → px (δ/ρ in columns, too)
        rho_end = np.maximum(rho0 - (ueb - fub) * step, 0)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            # still inside where it leaves the box: the tangent-plane tail, never past the light
            tail = np.where(fall_d > 0, gap / fall_d, np.inf)
            tail = np.where(inside_end & (gap > 0) & ~ray.to_light[sel],
                            np.minimum(tail, rho_end), 0)
            # stopped by the reach: the rest of the ray against that plane, not past the light
            reach_h = ray.reach_h[sel]
            plane = np.where(fall_d > 0, np.maximum(ray.delta0[sel] / fall_d - reach_h, 0),
                             np.inf)
            plane = np.minimum(plane, np.maximum(rho0 - reach_h, 0))
        return total + np.where(ray.by_reach[sel], plane, tail)

    # -- an edit (issue 61): the rows at the angles that see the box --------------------
    EDIT_TILE = 16      # pixels_near's tiles (px): a tile's angles are bounded by its corners

    def cells_reading(self, box, beyond):
        """(mask of the grid rows whose profile reads pixels of `box`, the last column that
        does), or None where F lies within the pixels the box's lookups reach (every row
        reads them). A row is a ray from F: it reads the box where its angle lies between
        the angles of the box's corners (grown by the 1 px a lookup reads, and past the
        image's edge by `beyond`; None: as far as the grid runs), from the nearest on."""
        x_lo, x_hi, y_lo, y_hi = self.read_area(box, beyond if beyond is not None else
                                                self.rho_max + np.hypot(self.fx, self.fy)
                                                + self.w + self.h)
        if x_lo - 1 <= self.fx <= x_hi + 1 and y_lo - 1 <= self.fy <= y_hi + 1:
            return None
        centre, lo, hi, near = self._seen_from_f((x_lo, x_hi), (y_lo, y_hi))
        rows = _relative(self.phi0 + self.dphi * np.arange(self.rows), centre)
        mask = (rows >= lo - self.dphi) & (rows <= hi + self.dphi)
        return mask, int(np.ceil((self.rho_max - near) / self.col_step)) + 1

    def pixels_near(self, mask, last_column, margin):
        """Flat indices of a superset of the pixels whose rays may read the rows of `mask`
        from their start on: those of the EDIT_TILE² tiles that lie, grown by `margin` (a ray
        starts within d of its pixel), at those rows' angles and, where `last_column` is
        given (height maps), farther from F than that column."""
        phi = self.phi0 + self.dphi * np.flatnonzero(mask)
        centre = np.angle(np.exp(1j * phi).sum())
        rel = _relative(phi, centre)
        lo, hi = rel.min() - self.dphi, rel.max() + self.dphi
        n = self.EDIT_TILE
        ty, tx = np.arange(0, self.h, n), np.arange(0, self.w, n)
        x_lo = (tx + 0.5 - margin)[None, :].repeat(len(ty), 0)
        x_hi = (np.minimum(tx + n, self.w) - 0.5 + margin)[None, :].repeat(len(ty), 0)
        y_lo = (ty + 0.5 - margin)[:, None].repeat(len(tx), 1)
        y_hi = (np.minimum(ty + n, self.h) - 0.5 + margin)[:, None].repeat(len(tx), 1)
        xs, ys = np.stack([x_lo, x_hi, x_lo, x_hi]), np.stack([y_lo, y_lo, y_hi, y_hi])
        a = _relative(np.arctan2(ys - self.fy, xs - self.fx), centre)
        has_f = (x_lo <= self.fx) & (self.fx <= x_hi) & (y_lo <= self.fy) & (self.fy <= y_hi)
        # a tile across the ray opposite `centre` spans about (−π, π]: kept, as it may
        take = has_f | ((a.max(0) >= lo) & (a.min(0) <= hi))
        if last_column is not None:
            far = np.hypot(xs - self.fx, ys - self.fy).max(0)
            take &= far >= self.rho_max - (last_column + 1) * self.col_step
        return np.flatnonzero(np.repeat(np.repeat(take, n, 0), n, 1)[:self.h, :self.w])

    def finish(self, ray, r_h, d):
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            t = d / np.maximum(r_h * ray.slant, d)               # along the 3D ray
        # under the light itself: N·L (the limit d → 0 of a flat neighbourhood)
        return np.where(np.isfinite(t), t,
                        np.where(ray.rho0 < 1e-6, np.maximum(ray.ndl, 0), 0))

