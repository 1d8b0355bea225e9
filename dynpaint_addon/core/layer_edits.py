"""What an edit of one layer changes in the shadows of a scene of layers (pipeline.md §15,
issue 61): a stroke changes a box of one layer's images, and T changes only for the rays of
the layers behind that pass through that box's part of its solid — the rest of T, baked
before the edit for the same light, stays as it was.

An occluder's change (SolidChange) is the box of its pixels where its silhouette, relief or
opacity moved by more than TOLERANCE, and the box where they moved by less or where its
slab's faces moved a little (a part inflated again: τ follows the tallest relief, §15) — the
whole solid where they moved far. A receiving pixel's rays toward any point of the light
meet a box only if the part of them inside the slab passes over it (rays_meeting); of the
rays that meet what moved a little, only those on the edge of the shadow before can change
(rays_changed: a ray that grazes the solid). Where the slab stayed, a bake that kept each
pixel's clearance (CLEARANCE) tells more: a relief that moved by at most δ where a pixel's
rays read it changes none of their answers if its clearance exceeds δ (rays_lifted) — of a
part inflated again, only the few rays that pass within hundredths of a pixel of its relief.
Those pixels, and their neighbours whose antialiasing reads them, are traced again
(core/layers.Scene.through).

Boxes of pixels are (r0, r1, c0, c1) as core/strokes.py's; a change is
(x0, y0, x1, y1, z_bottom, z_top) in canvas pixels.

>>> import numpy as np
>>> from dynpaint_addon.core.occluders import Occluder
>>> flat = np.zeros((16, 16)); dab = flat.copy(); dab[4:6, 8:10] = 1.0
>>> old = Occluder(np.ones((16, 16)), flat, 8.0, 2.0, np.ones((16, 16)))
>>> new = Occluder(np.ones((16, 16)), dab, 8.0, 2.0, np.ones((16, 16)))
>>> solid_change(old, new) is ALL        # the relief's top rose: its slab moved
False
>>> solid_change(old, old) is None
True
"""
from dataclasses import dataclass

import numpy as np

from .strokes import box_of, stepped, union, widened

ALL = "all"              # a change that cannot be bounded: trace every ray
TOLERANCE = 1e-3         # α, ρ (unitless) and relief (canvas px): a change under it moves an
                         # edge by under 1e-3 px, a pixel's shadow by under 1/255
READ_PX = 2              # occluder pixels a changed pixel reaches in what T reads of it: the
                         # bilinear samples (1) and the sun table's rows beside a line (1)
SLAB_SHIFT = 0.25        # canvas px: a relief or a slab's faces moved by more: every ray
                         # through it traced (by less: those that graze it)
MAX_GRAZE_PX = 4         # receiving pixels: a graze reaching further traces every ray it meets
LIFT_STEPS = tuple(4.0 ** -np.arange(6))   # canvas px (1 … 0.001): the tiers a relief's moves are
                         # bounded by, the rays that meet only the smaller moves told apart
CLEARANCE = TOLERANCE    # canvas px: a ray's clearance (transmittance's: the least |height −
                         # relief| where it crosses a solid's silhouette) must exceed the move
                         # by this much (float32 margins) for its answer to be kept


def changed_over(before, after, tolerance=TOLERANCE):
    """The smallest box holding every pixel where `after` differs from `before` by more than
    `tolerance` (NaN against a number counts), or None where none does."""
    return box_of(_moves(before, after) > tolerance)


def _moves(before, after):
    """|after − before| per pixel: inf where one is NaN and the other not, 0 where both are."""
    with np.errstate(invalid="ignore"):
        moves = np.abs(after - before)
    odd = np.isnan(moves)
    if odd.any():
        moves[odd] = np.where(np.isnan(before[odd]) & np.isnan(after[odd]), 0.0, np.inf)
    return moves


@dataclass
class SolidChange:
    """How an edit changed one occluder's solid. moved: a change holding every pixel whose
    α or ρ moved by more than TOLERANCE or its relief by more than SLAB_SHIFT (None: none
    did); grazed: one holding every pixel that moved by less, or the whole solid where its
    slab's faces moved (a part inflated again moves its heights by hundredths of a pixel
    far from the stroke, and τ follows the tallest), None where nothing did; shift: how far
    (canvas px) that moved a face at most. A ray whose answer so small a move changes
    grazes the solid: it lies on the edge of its shadow (rays_changed). Where the slab stayed
    (rays_lifted): cover_moved and cover_grazed, the same of α and ρ alone, and lifts, the
    relief's moves as nested changes, each (change, δ): every move over the next one's δ
    lies in its box, none over its own δ (None: the slab moved); grew: +1 where α only
    grew (a stroke that paints), −1 where it only shrank (one that erases), 0 else or where
    the solid is not of one opacity."""
    moved: tuple = None
    grazed: tuple = None
    shift: float = 0.0
    cover_moved: tuple = None
    cover_grazed: tuple = None
    lifts: list = None
    grew: int = 0


def solid_change(before, after):
    """Where occluder `after` differs from `before` (the same layer before an edit) → None
    (nowhere), a SolidChange, or ALL where the two cannot be compared (another size or
    place)."""
    if before is after:
        return None
    if before is None or before.place != after.place or before.alpha.shape != after.alpha.shape:
        return ALL
    shift = max(abs(a - b) for a, b in ((before.z_px, after.z_px),
                                        (before.thickness_px, after.thickness_px),
                                        (before.top, after.top)))
    if before.uniform != after.uniform:       # (its rays decided another way: all of them)
        shift = np.inf
    # (α, relief, ρ), and how far each may move before every ray meeting it is traced: a
    # relief that moved by up to SLAB_SHIFT changes rays' answers only where they graze it
    moves = [(_moves(b, a), t) for b, a, t in ((before.alpha, after.alpha, TOLERANCE),
                                               (before.relief_px, after.relief_px, SLAB_SHIFT),
                                               (before.opacity, after.opacity, TOLERANCE))]
    lifted = moves[1][0]
    shift = max(shift, min(float(lifted[np.isfinite(lifted)].max(initial=0.0)), SLAB_SHIFT))
    if shift > SLAB_SHIFT:                    # the slab moved far: the whole solid, as moved
        moved, grazed = _solids_box(before, after), None
    else:
        moved = union(*(box_of(m > t) for m, t in moves))
        if shift > 0 and (before.top != after.top or before.bottom != after.bottom):
            grazed = _solids_box(before, after)
        else:
            grazed = union(*(box_of(m > 0) for m, _ in moves))
            grazed = None if grazed == moved else _canvas_box(after, grazed)
        moved = None if moved is None else _canvas_box(after, moved)
    if moved is None and grazed is None:
        return None
    grow = READ_PX * after.place.px

    def change(box):              # a box of after's pixels → its change (None: none)
        return None if box is None else (box[0] - grow, box[1] - grow, box[2] + grow,
                                         box[3] + grow, min(before.bottom, after.bottom),
                                         max(before.top, after.top))
    out = SolidChange(change(moved), change(grazed), max(shift, TOLERANCE))
    slab_kept = (before.z_px, before.thickness_px, before.top, before.uniform) == \
        (after.z_px, after.thickness_px, after.top, after.uniform)
    if slab_kept and np.isfinite(lifted).all():
        cover = np.maximum(moves[0][0], moves[2][0])

        def under(box):   # (a ray above the relief there meets no pixel whose α or ρ moved)
            if box is None:
                return None
            r0, r1, c0, c1 = (max(0, box[0] - READ_PX), box[1] + READ_PX,
                              max(0, box[2] - READ_PX), box[3] + READ_PX)
            tallest = max(float(k.relief_px[r0:r1, c0:c1].max()) for k in (before, after))
            return change(_canvas_box(after, box))[:5] + (
                min(after.top, after.z_px + tallest + TOLERANCE),)
        out.cover_moved = under(box_of(cover > TOLERANCE))
        if out.cover_moved is not None and after.uniform is not None:   # (ρ kept: one)
            grown = after.alpha - before.alpha
            out.grew = 1 if grown.min() >= 0 else -1 if grown.max() <= 0 else 0
        grazed = under(box_of(cover > 0))
        out.cover_grazed = None if grazed == out.cover_moved else grazed
        most = float(lifted.max(initial=0.0))
        bounds = [most] + [b for b in LIFT_STEPS if b < most]
        out.lifts = [(change(_canvas_box(after, box_of(lifted > low))), bound)
                     for bound, low in zip(bounds, bounds[1:] + [0.0]) if most > 0]
    return out


def _canvas_box(k, box):
    """A box of occluder k's pixels (r0, r1, c0, c1) → its canvas box (x0, y0, x1, y1)."""
    r0, r1, c0, c1 = box
    x0, y0, _ = k.place.to_canvas(c0, r0, 0.0)
    x1, y1, _ = k.place.to_canvas(c1, r1, 0.0)
    return x0, y0, x1, y1


def _solids_box(before, after):
    """The canvas box of the solid before and after (None: neither has one)."""
    boxes = [k.box for k in (before, after) if k.box is not None]
    if not boxes:
        return None
    return (min(b[0] for b in boxes), min(b[1] for b in boxes),
            max(b[2] for b in boxes), max(b[3] for b in boxes))


def rays_changed(origins, points, change, before, px=1.0):
    """The pixels whose T an occluder's `change` (SolidChange) can change → (H, W) bool:
    those whose rays can meet what moved (rays_meeting), and of those whose rays can meet
    what grazed, the ones within reach of an edge of `before` (their T before the edit) —
    a move of `shift` moves a ray's crossing of a face by shift·g sideways (g: the steepest
    slope of the rays, per unit of height), so a shadow's edge by as much; px: canvas px a
    pixel of the receiving layer spans. A reach over MAX_GRAZE_PX pixels: all of them."""
    meets = np.zeros(origins.shape[:2], bool)
    if change.moved is not None:
        meets |= rays_meeting(origins, points, change.moved)
    if change.grazed is not None:
        grazing = rays_meeting(origins, points, change.grazed)
        reach = 1 + int(np.ceil(change.shift * _steepest(origins, points, change.grazed[5])
                                / px))
        meets |= grazing if reach > MAX_GRAZE_PX else grazing & near_edges(before, reach)
    return meets


def rays_lifted(origins, points, change, before, clear, px=1.0):
    """Of an occluder whose slab stayed (`change.lifts` not None), the pixels whose T the
    change can change, told by their clearance (`clear`, the bake before's: transmittance's
    `clearance`) → (H, W) bool, and how far (canvas px) the relief moved at most where each
    pixel's rays read it ((H, W) float32; inf where α or ρ moved a little: a clearance kept
    there no longer holds). Traced: the pixels whose rays meet where α or ρ moved
    (rays_changed's rule), and those whose rays meet a relief moved by δ and whose clearance
    is not over δ + CLEARANCE. A relief moved by at most δ moves every height a ray compares
    by at most δ (bilinear samples, the sun table's running maxima), so a ray whose every
    comparison is further than that keeps its answer, and a pixel all of whose rays keep
    theirs keeps its T. Where α only grew, a pixel in the shadow of all its rays (T = 0)
    keeps it (more solid only adds to what each ray meets, and of one opacity: at the
    same ρ); where it only shrank, one none of whose rays meets a solid (T = 1)."""
    lifted = np.zeros(origins.shape[:2], np.float32)
    lifts = change.lifts[::-1]                     # the largest box, the smallest move, first
    for (_, bound), meets in zip(lifts, rays_meeting_each(origins, points,
                                                          [box for box, _ in lifts])):
        lifted[meets] = bound
    keeps = clear > lifted + CLEARANCE                          # (NaN: not known, traced)
    may = (lifted > 0) & ~keeps
    cover = SolidChange(change.cover_moved, change.cover_grazed, TOLERANCE)
    if cover.moved is not None or cover.grazed is not None:
        covered = rays_changed(origins, points, cover, before, px)
        if change.grew:
            covered &= ~(keeps & (before == (0.0 if change.grew > 0 else 1.0)))
        may |= covered
    if cover.grazed is not None:
        lifted[rays_meeting(origins, points, cover.grazed)] = np.inf
    return may, lifted


def near_edges(t, reach):
    """The pixels within `reach` pixels of a step of `t` (H, W) between neighbours."""
    return widened(stepped(t), reach)


def _steepest(origins, points, top):
    """The largest sideways move per unit of height of the rays from `origins` toward the
    light's points (a sun's one per point; a point light's from the farthest corner of the
    origins' box), inf where a point light is not above `top`."""
    vectors = np.array([v for _, v in points], np.float64)
    if points[0][0] == "sun":
        return float(np.max(np.hypot(vectors[:, 0], vectors[:, 1]) /
                            np.maximum(vectors[:, 2], 1e-12)))
    rise = vectors[:, 2] - max(float(origins[..., 2].max()), top)
    if rise.min() <= 0:
        return np.inf
    xs, ys = origins[..., 0], origins[..., 1]
    far = np.max([np.hypot(vectors[:, 0] - x, vectors[:, 1] - y)
                  for x in (xs.min(), xs.max()) for y in (ys.min(), ys.max())], axis=0)
    return float(np.max(far / rise))


def rays_meeting(origins, points, change, margin=1.0):
    """Which pixels' rays toward any of a light's `points` (transmittance.light_points') can
    pass through a change's box within its slab → (H, W) bool. origins: (H, W, 3) canvas px;
    margin: canvas px around each origin its antialiasing rays may start from.

    Inside the slab z ∈ [z_bottom, z_top] a ray from o climbs s = z − o_z ≥ 0 and moves
    s·g sideways, g = d_xy / d_z (a sun: one g per point; a point light at P: (P_xy − o_xy) /
    (P_z − o_z), each end of P's box): its sideways reach is bounded by the corners of
    [s_lo, s_hi] × [g_min, g_max]. A light at or below the slab's top: every pixel."""
    return rays_meeting_each(origins, points, [change], margin)[0]


def rays_meeting_each(origins, points, changes, margin=1.0):
    """rays_meeting of each of `changes` → [(H, W) bool], the rays' reach found once (a
    relief's nested boxes, rays_lifted)."""
    shape, vectors = origins.shape[:2], np.array([v for _, v in points], np.float64)
    if not changes:
        return []
    if points[0][0] == "sun":
        if vectors[:, 2].min() <= 1e-9:
            return [np.ones(shape, bool) for _ in changes]
        g = vectors[:, :2] / vectors[:, 2:3]
        ranges = [(g[:, a].min(), g[:, a].max()) for a in (0, 1)]
        # a sun's g is the same for every pixel: only pixels within the reach of the lowest
        # and highest origins can meet a change (a grid's rows and columns: a block to test)
        union = tuple(f(c[a] for c in changes) for a, f in enumerate((min, min, max, max,
                                                                       min, max)))
        rows, cols = _within(origins, union, ranges, margin)
        block = [origins[rows, cols, a].astype(np.float64) for a in range(3)]
        out = []
        for change in changes:
            out.append(np.zeros(shape, bool))
            out[-1][rows, cols] = _meeting(block, change, ranges, margin)
        return out
    if all(vectors[:, 2].min() <= change[5] for change in changes):
        return [np.ones(shape, bool) for _ in changes]     # (no reach to bound)
    o = [origins[..., a].astype(np.float64) for a in range(3)]
    rise = [vectors[:, 2].min() - o[2], vectors[:, 2].max() - o[2]]
    ranges = []
    for a in (0, 1):
        ends = [(p - o[a]) / r for p in (vectors[:, a].min(), vectors[:, a].max())
                for r in rise]
        ranges.append((np.minimum.reduce(ends), np.maximum.reduce(ends)))
    return [np.ones(shape, bool) if vectors[:, 2].min() <= change[5] else
            _meeting(o, change, ranges, margin) for change in changes]


def _meeting(origins, change, ranges, margin):
    """rays_meeting's test of each pixel, its sideways reach per axis bounded by `ranges`
    ((g_min, g_max) per axis: numbers, or arrays per pixel); origins: its x, y, z
    (float64 arrays)."""
    x0, y0, x1, y1, zb, zt = change
    ox, oy, oz = origins
    s_lo, s_hi = np.maximum(zb - oz, 0.0), zt - oz
    meets = s_hi >= 0
    for o, (g_min, g_max), lo_edge, hi_edge in ((ox, ranges[0], x0, x1), (oy, ranges[1], y0, y1)):
        lo = o + np.minimum(s_lo * g_min, s_hi * g_min)
        hi = o + np.maximum(s_lo * g_max, s_hi * g_max)
        meets &= (hi >= lo_edge - margin) & (lo <= hi_edge + margin)
    return meets


def _within(origins, change, ranges, margin):
    """The rows and columns (slices) of a grid of origins whose rays toward a sun (g within
    `ranges`) can reach the change at all, from the lowest or highest origin."""
    x0, y0, x1, y1, zb, zt = change
    z = origins[..., 2]
    s_lo, s_hi = max(zb - float(z.max()), 0.0), zt - float(z.min())
    if s_hi < 0:
        return slice(0, 0), slice(0, 0)
    out = []
    for axis, centres, (g_min, g_max), lo_edge, hi_edge in (
            (0, origins[0, :, 0], ranges[0], x0, x1), (1, origins[:, 0, 1], ranges[1], y0, y1)):
        # an origin at c reaches [c + min(s·g), c + max(s·g)] over s, g in their ranges
        reach_lo = min(s_lo * g_min, s_hi * g_min)
        reach_hi = max(s_lo * g_max, s_hi * g_max)
        keep = (centres + reach_hi >= lo_edge - margin) & (centres + reach_lo <= hi_edge + margin)
        index = np.flatnonzero(keep)
        out.append(slice(int(index[0]), int(index[-1]) + 1) if index.size else slice(0, 0))
    return out[1], out[0]
