"""The block grid both crossing grids of crossings.py are built on (§6): rows of rays' paths
stored in blocks of rows, each block's profile and tables built on their own and in groups
that fit MAX_TABLE_BYTES, the rays traced in chunks of TRACE_PIXELS and bands of pixel rows on
threads; and the rays' starts (P0 and its depth δ0, the reference's) that both grids share.
"""
import os
from dataclasses import dataclass

import numpy as np

from .crossing_search import table_levels
from .sampling import pixel_centres, sample_extend
from .shadow import BakeCancelled
from .strokes import inside

MAX_TABLE_BYTES = 1.5 * 2**30   # tables built at once (larger grids: in groups of blocks)
THREADS = max(1, min(4, os.cpu_count() or 1))
RAY_BAND_PIXELS = 1 << 17       # rays searched together (see crossings._bake)
EDIT_RAYS_IN_THREADS = 1 << 14  # an edit's rays from here on searched in the threads
TRACE_PIXELS = 1 << 21          # rays whose starts are held at once (BlockGrid.trace)


def by_bands(pool, h, w, fn):
    """[fn(r0, r1)] for bands of pixel rows, side by side: the per-ray arrays stay small
    (whole-image temporaries are slower, and page-fault on every allocation)."""
    rows = max(1, min(RAY_BAND_PIXELS // w, -(-h // THREADS)))
    return list(pool.map(lambda r0: fn(r0, min(h, r0 + rows)), range(0, h, rows)))


def ray_pixels(normals, heights_px, where):
    """N, the pixel centres x, y and the relief z (0 for normal maps) of pixel rows
    where = (r0, r1) (2D), or of the flat pixel indices `where` (1D: an edit's rays), float32:
    the same numbers either way."""
    f32 = np.float32
    h, w = normals.shape[:2]
    if isinstance(where, tuple):
        r0, r1 = where
        x, y = pixel_centres(h, w, f32)
        zs = heights_px[r0:r1] if heights_px is not None else None
        n, x, y = normals[r0:r1], x[r0:r1], y[r0:r1]
    else:
        rows, cols = np.divmod(where, w)
        x, y = cols.astype(f32) + f32(0.5), rows.astype(f32) + f32(0.5)
        n = normals.reshape(-1, 3)[where]
        zs = heights_px.reshape(-1)[where] if heights_px is not None else None
    zs = zs.astype(f32, copy=False) if zs is not None else f32(0)
    return n.astype(f32, copy=False), x, y, zs


def start_points(normals, d, heights_px, where):
    """Both grids' ray starts for pixel rows where = (r0, r1), or pixels `where` (ray_pixels)
    (float32): N, P0 = P_S − d·N (§6) and its depth δ0 under the relief, the reference's: the
    exact bilinear relief above P0 for height maps; on the tangent plane of P_S for normal
    maps, which also need H(P0) there, h0 = d|N.xy|²/N.z (δ0 = d/N.z); h0 is None for height
    maps."""
    f32 = np.float32
    n, x, y, zs = ray_pixels(normals, heights_px, where)
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]
    x0, y0, z0 = x - f32(d) * nx, y - f32(d) * ny, zs - f32(d) * nz
    if heights_px is not None:
        delta0, h0 = sample_extend(heights_px.astype(f32, copy=False), x0, y0) - z0, None
    else:
        delta0, h0 = f32(d) / nz, f32(d) * (nx * nx + ny * ny) / nz
    return nx, ny, nz, x0, y0, z0, delta0, h0


@dataclass
class Rays:
    """The rays of some pixel rows in a grid's coordinates: flat arrays, one entry per ray
    (§6's ray from P0; a grid's `starts` makes them, its `_search_block` and `finish` read
    them). Fields a grid does not use are None."""
    row0: np.ndarray            # the grid row below the ray's path …
    wv: np.ndarray              # … blended with the next by this weight (0: row0 alone)
    fu: np.ndarray              # the start's column u (fractional)
    u_end: np.ndarray           # where the search stops: the box's edge, the light, the reach
    c: np.ndarray               # the ray's level: inside the relief where G > c
    delta0: np.ndarray          # δ0, the start's depth under the relief (px)
    h0: np.ndarray | None       # normal maps: H(P0) on the tangent plane of P_S
    searched: np.ndarray        # P0 inside the box (the others: `alone`)
    alone: np.ndarray           # the inside length from δ0 alone (the tangent-plane tail)
    by_reach: np.ndarray        # stopped by the reach before the box's edge
    fall: np.ndarray = None     # suns: δ's fall per px of u on the tangent plane of P_S
    fall_d: np.ndarray = None   # point lights: δ's fall per px of ρ on that plane
    g_start: np.ndarray = None  # point lights: G at the start
    reach_h: np.ndarray = None  # point lights: the reach in px of ρ
    to_light: np.ndarray = None     # point lights: the box's edge is at or past the light
    rho0: np.ndarray = None     # point lights: ρ of the start (px from the light's foot)
    ndl: np.ndarray = None      # point lights: N·L at the start
    slant: np.ndarray = None    # point lights: 3D length per px of ρ


class BlockGrid:
    """What both grids share: rows of rays' paths stored in blocks of rows (one row shared
    between neighbours, so a ray's two rows are in one block), each only as wide as the
    columns its rows' rays can read; a block's profile and tables are built on their own,
    and each ray is searched in its block.

    A subclass sets rows and width, calls _split with each row's column range, and writes
    _profile (G of a block), starts (the rays of some pixel rows), _search_block (their
    inside lengths) and finish (t from them); for an edit (retrace), cells_reading (the rows
    and columns whose profile reads a box of pixels) and pixels_near (the pixels whose rays
    may read those rows).
    """

    def _split(self, lo, hi, blocks):
        """`blocks` blocks (a, n, c0, c1) of rows a … a + n − 1 and columns c0 … c1 − 1,
        covering each row's columns lo … hi (empty rows: lo > hi)."""
        blocks = max(1, min(blocks, self.rows // 2))
        self.block_rows = max(1, -(-(self.rows - 1) // blocks))
        self.blocks = []
        for a in range(0, self.rows - 1, self.block_rows):
            n = min(self.block_rows + 1, self.rows - a)
            lo_a, hi_a = lo[a:a + n], hi[a:a + n]
            full = lo_a <= hi_a
            first = lo_a[full].min() if full.any() else self.width - 2
            last = hi_a[full].max() if full.any() else 0
            c0 = int(np.clip(np.floor(first), 0, self.width - 2))
            c1 = int(np.clip(np.ceil(last) + 1, c0 + 2, self.width))
            self.blocks.append((a, n, c0, c1))

    def block_bytes(self):
        """The memory each block's profile and tables take."""
        return [(2 * table_levels(c1 - c0) + 2) * n * (c1 - c0 + 1) * 4
                for _, n, c0, c1 in self.blocks]

    def groups(self):
        """The blocks in runs whose tables fit MAX_TABLE_BYTES together (one run up to about
        3000² px), each built, searched and freed in turn (table_groups)."""
        return table_groups(self.block_bytes())

    def trace(self, pool, normals, offset, heights_px, slopes, cancel=None, progress=None):
        """t: per group of blocks (groups), their profiles and tables side by side, then the
        rays in chunks of up to TRACE_PIXELS (bounded memory on huge images): the rays'
        starts in bands of pixel rows, then the search in each block of the group for the
        rays whose rows are in it, side by side. The starts are recomputed per group (cheaper
        than holding a huge image's); the last group's pass finishes t. cancel is asked
        before each chunk (BakeCancelled), progress told after it."""
        h, w = normals.shape[:2]
        inputs = self._inputs(heights_px, slopes)
        groups = self.groups()
        r_h = np.empty(h * w, np.float32)
        t = np.empty((h, w), normals.dtype)
        rows = max(1, TRACE_PIXELS // w)
        chunks = range(0, h, rows)
        for g, group in enumerate(groups):
            searches = None                    # (the last group's tables freed first)
            searches = dict(zip(group, pool.map(
                lambda b: self._profile(self.blocks[b], *inputs), group)))
            for i, r0 in enumerate(chunks):
                if cancel is not None and cancel():
                    raise BakeCancelled()
                r1 = min(h, r0 + rows)
                self._trace_rows(pool, searches, normals, offset, heights_px, r0, r1,
                                 r_h[r0 * w:r1 * w], t[r0:r1] if g == len(groups) - 1 else None,
                                 first=g == 0)
                if progress is not None:
                    progress((g * len(chunks) + i + 1) / (len(groups) * len(chunks)))
        return t

    def _trace_rows(self, pool, searches, normals, offset, heights_px, r0, r1, r_h, t, first):
        """The rays of pixel rows r0 … r1 − 1 in the blocks of `searches`: their inside
        lengths into r_h (set first to the tail from δ0 alone, for the rays no block
        searches), and t from them where t is given."""
        w = normals.shape[1]
        arrays = {}

        def start(a, b):
            # each band writes its part of the chunk's arrays (no serial concatenation after;
            # setdefault is atomic, the first band to finish allocates)
            part_rays = self.starts(normals, offset, heights_px, (r0 + a, r0 + b))
            for key, part in vars(part_rays).items():
                chunk = arrays.setdefault(key, None if part is None else
                                          np.empty((r1 - r0) * w, part.dtype))
                if part is not None:
                    chunk[a * w:b * w] = part
        by_bands(pool, r1 - r0, w, start)
        ray = Rays(**arrays)
        if first:
            r_h[:] = ray.alone
        block = np.minimum(ray.row0 // self.block_rows, len(self.blocks) - 1)
        block = block.astype(np.int16)
        block[~ray.searched] = -1

        def search_block(b):
            sel = np.flatnonzero(block == b)
            if sel.size:
                r_h[sel] = self._search_block(self.blocks[b], searches[b], ray, sel)
        list(pool.map(search_block, searches))
        if t is not None:
            done = self.finish(ray, r_h, float(offset) * w)
            t[:] = np.clip(np.where(np.isfinite(done), done, 0), 0, 1).reshape(r1 - r0, w)

    # -- an edit (issues 41, 61): only the rays that read changed pixels are traced again --
    def retrace(self, pool, normals, offset, heights_px, slopes, t, path_box, own_box):
        """t after an edit, from t before it: the rays whose grid rows read `path_box` (the
        relief, or a normal map's slopes, changed there: the grid's cells_reading) and those
        starting in `own_box` (their normal or the relief at P0 changed) are traced again,
        in the blocks they are in; None where every row reads the edit or those rows'
        tables do not fit in memory. A ray reads its rows from the column it starts in
        onward: one starting past the last changed column sees nothing new on a height map
        (a normal map's rebuilt heights run on along the whole row)."""
        h, w = normals.shape[:2]
        d = float(offset) * w
        idx = np.zeros(0, np.int64)
        reading = None
        if path_box is not None:
            # past the image's edge a lookup reads the edge's pixels: a height map's rays read
            # the relief from within d of the image onward; a normal map's rebuilt heights
            # integrate each row from its block's first column (the rounding of the whole
            # row's heights changes with any slope on it)
            reading = self.cells_reading(path_box, d + 4 if heights_px is not None else None)
            if reading is None:
                return None
            rows, last = reading
            idx = self.pixels_near(rows, last if heights_px is not None else None, d + 1)
        if own_box is not None:
            r0, r1, c0, c1 = own_box
            idx = np.union1d(idx, (np.arange(r0, r1)[:, None] * w + np.arange(c0, c1)).ravel())
        if idx.size == 0:
            return t.copy()
        ray = self.starts(normals, offset, heights_px, idx)
        keep = inside(own_box, *np.divmod(idx, w))
        if reading is not None:
            rows, last = reading
            reads = rows[ray.row0] | rows[ray.row0 + 1]
            if heights_px is not None:
                reads &= np.floor(ray.fu) <= last
            keep |= reads
        idx = idx[keep]
        ray = Rays(**{k: None if v is None else v[keep] for k, v in vars(ray).items()})
        block = np.minimum(ray.row0 // self.block_rows, len(self.blocks) - 1).astype(np.int16)
        block[~ray.searched] = -1
        # each block's rows that these rays read, alone: a row's profile and tables are the
        # row's own (the block's columns kept), so they equal the whole block's there
        parts = {}
        for b in np.unique(block[block >= 0]):
            sel = np.flatnonzero(block == b)
            first, last = int(ray.row0[sel].min()), int(ray.row0[sel].max())
            _, _, c0, c1 = self.blocks[b]
            parts[int(b)] = (sel, (first, last - first + 2, c0, c1))
        if sum((2 * table_levels(c1 - c0) + 2) * n * (c1 - c0 + 1) * 4
               for _, (_, n, c0, c1) in parts.values()) > MAX_TABLE_BYTES:
            return None
        inputs = self._inputs(heights_px, slopes)
        r_h = ray.alone.copy()

        def search_part(part):
            sel, spec = part
            r_h[sel] = self._search_block(spec, self._profile(spec, *inputs), ray, sel)
        # (side by side where it pays: a stroke's few rays cost less than the handoffs)
        run = pool.map if len(parts) > 1 and idx.size > EDIT_RAYS_IN_THREADS else map
        list(run(search_part, parts.values()))
        done = self.finish(ray, r_h, d)
        out = t.copy()
        out.reshape(-1)[idx] = np.clip(np.where(np.isfinite(done), done, 0), 0, 1)
        return out

    def read_area(self, box, beyond):
        """(x_lo, x_hi, y_lo, y_hi): where a lookup reads pixels of `box` (strokes.py):
        within 1 px of their centres, and past the image's edge (the edge's own pixels) up to
        `beyond` px out."""
        r0, r1, c0, c1 = box
        return (c0 - 0.5 if c0 > 0 else 0.5 - beyond,
                c1 + 0.5 if c1 < self.w else self.w - 0.5 + beyond,
                r0 - 0.5 if r0 > 0 else 0.5 - beyond,
                r1 + 0.5 if r1 < self.h else self.h - 0.5 + beyond)

    def _block_rays(self, spec, ray, sel):
        """Rays `sel` in the coordinates of block `spec` (a, n, c0, c1): (rows from its
        first, u from its first column, u_end there)."""
        a, _, c0, _ = spec
        return (ray.row0[sel] - a, np.clip(ray.fu[sel] - c0, 0, None),
                ray.u_end[sel] - c0)


def table_groups(sizes):
    """Block indices in runs whose table bytes `sizes` fit MAX_TABLE_BYTES together; a block
    too big alone is a run of its own (the bake's plan marches rather than build it)."""
    groups, total = [[]], 0
    for b, size in enumerate(sizes):
        if groups[-1] and total + size > MAX_TABLE_BYTES:
            groups, total = groups + [[]], 0
        groups[-1].append(b)
        total += size
    return groups
