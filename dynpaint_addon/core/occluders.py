"""A layer in front as the rays of the layers behind it meet it (pipeline.md §15
"Occluders"): its solid's images and slab (`Occluder`), where its pixels lie on the canvas
(`Placement`), what is made of it once per light and kept on it (line maps, sun tables), and a
sun's table of it (`SunTable`): for any line along the sun at once, whether it meets the
solid. core/transmittance.py traces the rays through occluders; core/layer_edits.py says
what an edit of one changed.

    >>> import numpy as np
    >>> card = Occluder(alpha=np.ones((8, 8)), relief_px=np.zeros((8, 8)), z_px=4.0,
    ...                 thickness_px=1.0, opacity=np.ones((8, 8)))
    >>> card.top, card.bottom, card.box, card.uniform
    (4.0, 3.0, (0.0, 0.0, 8.0, 8.0), 1.0)
"""
import threading
from dataclasses import dataclass, field

import numpy as np

from .sampling import sample_bilinear_extend

MAPS_KEPT = 4            # line maps an occluder keeps (per light point; a drag makes new ones)
FACE_STEP = 0.25         # canvas px: the slab's top and default depth sit on this lattice, so that
                         # an edit that moves the tallest relief by hundredths of a pixel (a part
                         # inflated again) moves no face — and no ray through the rest of the
                         # layer need be traced again (core/layer_edits.py)


def on_faces_lattice(height):
    """A height (canvas px, ≥ 0) rounded up to FACE_STEP: the slab's faces (§15).

    >>> on_faces_lattice(9.833), on_faces_lattice(9.886), on_faces_lattice(0.0)
    (10.0, 10.0, 0.0)
    """
    return float(np.ceil(height / FACE_STEP) * FACE_STEP)


@dataclass(frozen=True)
class Placement:
    """Where a layer's pixels lie on the canvas (§15): canvas pixel = corner + px × layer
    pixel (x right, y up), its plane at depth z (canvas pixels toward the viewer)."""
    corner: tuple = (0.0, 0.0)
    px: float = 1.0
    z: float = 0.0

    def to_canvas(self, x, y, z):
        return (self.corner[0] + self.px * x, self.corner[1] + self.px * y, self.z + self.px * z)

    def to_layer(self, x, y):
        return (x - self.corner[0]) / self.px, (y - self.corner[1]) / self.px

    @property
    def identity(self):
        return self.corner == (0.0, 0.0) and self.px == 1.0


@dataclass
class Occluder:
    """A layer in front, as the rays of the layers behind it meet it (§15 "Occluders").
    alpha, relief_px and opacity are images of its own pixels; relief_px, z_px and
    thickness_px are canvas pixels; place maps canvas x, y to its pixels."""
    alpha: np.ndarray         # (H, W): its silhouette's alpha; the solid is where α ≥ ½
    relief_px: np.ndarray     # (H, W): its relief above its plane (0 for a flat card)
    z_px: float               # its plane's depth
    thickness_px: float       # τ: how far the solid reaches behind its plane
    opacity: np.ndarray       # (H, W): ρ = 1 − k (§11's transparency): 1 opaque, 0 clear
    place: Placement = field(default_factory=Placement)
    maps: dict = field(default_factory=dict, repr=False)   # line_map's cache
    edited: tuple = field(default=None, repr=False)        # (occluder, box): edited_from
    making: threading.Lock = field(default_factory=threading.Lock, repr=False, compare=False)

    def __post_init__(self):
        self.alpha, self.relief_px, self.opacity = (
            _at_least_2x2(np.asarray(a, np.float32)) for a in (self.alpha, self.relief_px,
                                                                self.opacity))
        self.top = self.z_px + on_faces_lattice(float(np.max(self.relief_px, initial=0.0)))
        self.bottom = self.z_px - self.thickness_px
        # the canvas box of its solid (where α ≥ ½): rays that miss it skip the layer
        solid = np.asarray(self.alpha) >= 0.5
        rows, cols = np.nonzero(solid)
        # one opacity over the whole solid (no transparency map): ρ needs no first hit
        inside = self.opacity[solid]
        self.uniform = float(inside[0]) if inside.size and np.all(inside == inside[0]) \
            else None
        if rows.size:
            x0, y0, _ = self.place.to_canvas(cols.min(), rows.min(), 0.0)
            x1, y1, _ = self.place.to_canvas(cols.max() + 1.0, rows.max() + 1.0, 0.0)
            self.box = (x0, y0, x1, y1)
        else:
            self.box = None


def _at_least_2x2(img):
    """The fast sampler reads 2×2 neighbours: a 1-pixel-wide image is repeated."""
    return np.pad(img, [(0, max(0, 2 - img.shape[0])), (0, max(0, 2 - img.shape[1]))], "edge")


def sample_layer(img, x, y):
    """An occluder's image (float32, at least 2×2) at layer pixels x, y (finite): bilinear,
    edges extended."""
    return sample_bilinear_extend(img, x.astype(np.float32), y.astype(np.float32))


def kept_on(k, key, make):
    """What `make()` makes for occluder k, kept on it under `key` (line maps, sun tables):
    the newest MAPS_KEPT (a dragged light makes new ones at every step). Made once: a thread
    that needs what another is making waits for it (a scene's layers bake side by side, and
    two scenes in two threads may share an occluder)."""
    with k.making:
        made = k.maps.get(key)
        if made is None:
            made = make()
            if len(k.maps) >= MAPS_KEPT:
                k.maps.clear()
            k.maps[key] = made
    return made


class SunTable:
    """Which lines along a sun meet occluder k's solid, for any line at once (§15): the
    solid's relief H resampled on a grid whose rows run along the light's horizontal
    direction e (u along it, v across, one occluder pixel apart; H = −∞ outside the
    silhouette), G = H − m·u (m: the line's rise per pixel of u) and its suffix maximum
    S(u) = max_{u' ≥ u} G(u'). The line crossing the occluder's plane at (u_q, v_q) rises
    from z_k − τ at u_q − τ/m toward the light: it meets the solid where some
    H(u') ≥ m·(u' − u_q) with u' ≥ u_q − τ/m, i.e. S(u_q − τ/m) ≥ −m·u_q — one lookup per
    ray. Columns are STEP_U pixels apart and each stands for its whole width (the line's
    lowest point over it), so a card thinner than a column is never stepped over; edges
    move by at most half a column along e. Across, a line between two rows is theirs when
    they agree, and marched when they do not (a draft takes the nearer row's)."""
    STEP_U = 0.25

    def __init__(self, k, direction, before=None, box=None):
        """before, box: the table of the same light on this layer before an edit that changed
        its pixels in `box` (r0, r1, c0, c1; None: none), where it spans the same grid: only
        its rows that read the box are made again (the others are the same, bit for bit)."""
        self.k, self.direction = k, direction
        flat = float(np.hypot(direction[0], direction[1]))
        self.vertical = flat < 1e-9
        if self.vertical:
            return
        self.e = np.array(direction[:2]) / flat
        self.n = np.array([-self.e[1], self.e[0]])
        self.m = direction[2] / flat * k.place.px   # canvas px of rise per occluder px of u
        (x0, y0), (x1, y1) = (k.place.to_layer(*k.box[:2]), k.place.to_layer(*k.box[2:]))
        corners = np.array([[x0, y0], [x0, y1], [x1, y0], [x1, y1]])
        u, v = corners @ self.e, corners @ self.n
        self.u0, self.v0 = np.floor(u.min()) - 1, np.floor(v.min()) - 1
        coarse = int(np.ceil(u.max() - self.u0)) + 2
        rows = int(np.ceil(v.max() - self.v0)) + 2
        if before is not None and not before.vertical and before.m == self.m and \
                (before.u0, before.v0) == (self.u0, self.v0) and \
                before.suffix.shape[0] == rows and before.coarse == coarse:
            self.suffix = before.suffix.copy()
            lo, hi = self._rows_reading(box, rows)
            if hi > lo:
                self.suffix[lo:hi] = self._suffix_rows(lo, hi, coarse)
        else:
            self.suffix = self._suffix_rows(0, rows, coarse)
        self.coarse = coarse
        # where a line may cross the plane and still meet the solid: its box, grown by how far
        # a line travels sideways over the slab's heights (occluder px)
        travel = (k.top - k.bottom) / self.m + 1.0
        self.reach = (min(x0, x1) - travel, min(y0, y1) - travel, max(x0, x1) + travel,
                      max(y0, y1) + travel)

    def _rows_reading(self, box, rows):
        """The rows [lo, hi) whose samples read a pixel of `box` (bilinear: a pixel round it)."""
        if box is None:
            return 0, 0
        r0, r1, c0, c1 = box
        corners = np.array([[c0 - 1, r0 - 1], [c0 - 1, r1 + 1], [c1 + 1, r0 - 1],
                            [c1 + 1, r1 + 1]], np.float64)
        v = corners @ self.n - self.v0
        return max(0, int(np.floor(v.min())) - 1), min(rows, int(np.ceil(v.max())) + 2)

    def _suffix_rows(self, lo, hi, coarse):
        """Rows lo … hi − 1 of the table's suffix maxima (each row made on its own)."""
        k = self.k
        # the silhouette and relief sampled a pixel apart along u, then interpolated to the
        # finer columns (sampling every column costs 1/STEP_U times more for the same picture)
        per = int(round(1 / self.STEP_U))
        gu, gv = np.meshgrid(self.u0 + np.arange(coarse, dtype=np.float64),
                             self.v0 + np.arange(lo, hi, dtype=np.float64))
        x, y = gu * self.e[0] + gv * self.n[0], gu * self.e[1] + gv * self.n[1]
        lh, lw = k.alpha.shape
        on = (x >= 0) & (x <= lw) & (y >= 0) & (y <= lh)
        cover, relief = np.zeros(x.shape, np.float32), np.zeros(x.shape, np.float32)
        cover[on] = sample_layer(k.alpha, x[on], y[on])
        relief[on] = sample_layer(k.relief_px, x[on], y[on])
        f = (np.arange((coarse - 1) * per + 1) / per).astype(np.float32)
        j = np.minimum(f.astype(np.int64), coarse - 2)
        w = f - j
        cover = cover[:, j] * (1 - w) + cover[:, j + 1] * w
        relief = relief[:, j] * (1 - w) + relief[:, j + 1] * w
        gu = self.u0 + f.astype(np.float64)[None, :]
        h = np.where(cover >= 0.5, relief, -np.inf).astype(np.float32)
        g = h - (self.m * (gu - self.STEP_U / 2)).astype(np.float32)   # lowest over its width
        return np.maximum.accumulate(g[:, ::-1], axis=1)[:, ::-1]

    def meets(self, x, y, rise, exact=True):
        """Whether the rays whose lines cross the occluder's plane at its pixels (x, y) meet
        it, each starting `rise` canvas px below the plane (negative: inside the slab, above
        the plane: only the part of its line beyond its start counts) → (hit, doubt,
        clearance): with `exact`, doubt where the table's two rows beside a line disagree —
        the solid's edge runs between them, closer than a pixel, and the ray is to be
        marched; without, the nearer row's answer (a draft's: edges move by up to half a
        pixel across the light, in dots along them). Clearance: how far the relief may move
        before a row's answer can change — the least |S − threshold| of the rows read (a
        relief moved by δ everywhere moves every S by at most δ; inf: no row reads the
        solid)."""
        k = self.k
        out, doubt = np.zeros(len(x), bool), np.zeros(len(x), bool)
        clear = np.full(len(x), np.inf, np.float32)
        if self.vertical:
            lh, lw = k.alpha.shape
            on = (x >= 0) & (x <= lw) & (y >= 0) & (y <= lh)
            on[on] = sample_layer(k.alpha, x[on], y[on]) >= 0.5
            # straight up: the solid over it, above the start
            relief = sample_layer(k.relief_px, x[on], y[on])
            out[on], clear[on] = rise[on] >= -relief, np.abs(rise[on] + relief)
            return out, doubt, clear
        # only lines that cross the plane within the slab's sideways reach of the solid
        x0, y0, x1, y1 = self.reach
        near = np.flatnonzero((x >= x0) & (x <= x1) & (y >= y0) & (y <= y1))
        if near.size:
            out[near], doubt[near], clear[near] = self._meets(x[near], y[near], rise[near],
                                                              exact)
        return out, doubt, clear

    def _meets(self, x, y, rise, exact):
        k = self.k
        uq = x * self.e[0] + y * self.e[1]
        vq = x * self.n[0] + y * self.n[1]
        rows, cols = self.suffix.shape
        behind = np.minimum(np.float32(k.thickness_px), rise)       # the slab's or the start's
        start = uq - behind / np.float32(self.m) - self.STEP_U / 2   # columns reaching it
        c = np.ceil((start - self.u0) / self.STEP_U - 1e-6).astype(np.int64)
        c = np.maximum(c, 0)

        def row_meets(r):
            ok = (r >= 0) & (r < rows) & (c < cols)
            out, clear = np.zeros(len(x), bool), np.full(len(x), np.inf, np.float32)
            suffix, threshold = self.suffix[r[ok], c[ok]], -self.m * uq[ok]
            out[ok] = suffix >= threshold
            clear[ok] = np.abs(suffix - threshold)     # (−inf: no silhouette, inf)
            return out, clear
        if not exact:
            out, clear = row_meets(np.rint(vq - self.v0).astype(np.int64))
            return out, np.zeros(len(x), bool), clear
        below = np.floor(vq - self.v0).astype(np.int64)
        (lower, c_lower), (upper, c_upper) = row_meets(below), row_meets(below + 1)
        return lower & upper, lower != upper, np.minimum(c_lower, c_upper)


def sun_table(k, direction):
    """The SunTable of occluder k for a sun along `direction`, cached on the occluder — made
    from the same light's table of the occluder it was edited from, where there is one
    (edited_from)."""
    key = ("table", tuple(np.round(direction, 9)))

    def make():
        was, box = k.edited or (None, None)
        # (taken from the earlier occluder: a 4096² layer's table is hundreds of MB, and the
        # earlier scene is done with — a bake of it still running holds its own reference)
        table = None if was is None else was.maps.pop(key, None)
        return SunTable(k, np.asarray(direction, np.float64), table, box)
    return kept_on(k, key, make)


def edited_from(before, after, box):
    """Occluder `after` is `before` (the same layer) edited in `box` of its pixels (None:
    nowhere): its sun tables are made from before's, again only in the rows that read the
    box (SunTable's `before`) — a stroke's bake builds no table whole. (before's own
    source is dropped: one edit back is kept, not a chain of them.)"""
    before.edited = None
    after.edited = (before, box)
