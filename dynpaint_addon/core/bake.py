"""The cos-θ bake at a quality level (docs/pipeline.md §6, §13): which method, at which resolution.

Two methods compute the same t = d / max(r, d): the reference march (shadow.py, K steps per
ray) and crossings (crossings.py: exact for suns, aimed for point lights). A quality level
names a resolution, K and a precision; this module picks the method that reaches the level
fastest, runs it at its resolution and resamples the result to the shape image's size. The
reference (K = 1024, float64) always marches.
"""
import functools
import weakref

import numpy as np

from . import crossing_blocks, crossings
from .sampling import enlarged_box, resample_separable
from .strokes import changed_box
from .shadow import BakeCancelled, cos_theta_shadow

# §13 quality levels of the bake: K, the resolution the march runs at (the result is upsampled
# bilinearly) and the precision. 'custom' takes K and the resolution from the parameters.
# Crossings (crossings.py) are more accurate per sample than a K-step march, so where they
# apply they run at a resolution of their own, for suns and point lights alike: draft and
# preview at crossings_scale (normal maps, whose rebuilt heights integrate slopes, need a
# little more: crossings_scale_normal), final at full resolution; point lights' polar grids
# have columns point_step px apart (crossings.POINT_STEP at final). Never below
# crossings_min_px on the short side: small paintings keep their detail (and are cheap).
# K does not apply there; custom K and the reference always march. Measured at 1024², tall
# relief: docs/shadow-quality.md.
QUALITY = {
    "draft": {"steps": 16, "scale": 0.25, "dtype": "float32",
              "crossings_scale": 0.125, "crossings_scale_normal": 0.25, "crossings_min_px": 96,
              "point_step": 1.0},
    "preview": {"steps": 32, "scale": 0.5, "dtype": "float32",
                "crossings_scale": 0.25, "crossings_scale_normal": 0.4, "crossings_min_px": 192,
                "point_step": 1.0},
    "final": {"steps": 64, "scale": 1.0, "dtype": "float32"},
    "reference": {"steps": 1024, "scale": 1.0, "dtype": "float64"},
}
QUALITIES = (*QUALITY, "custom")
FAST_FINAL_MIN_PX = 512


def quality_level(quality, steps=None, scale=None):
    """The level a bake chosen by `quality` and, optionally, its own K (`steps`) and
    resolution (`scale`) runs at (§13): the level while K and the resolution are the level's
    own (or not given), 'custom' once either is set otherwise — as editing K by hand in the
    add-on makes the level Custom.

    >>> quality_level("final"), quality_level("final", steps=64), quality_level("final", 32)
    ('final', 'final', 'custom')
    """
    q = QUALITY.get(quality)
    if q is None:
        return "custom"
    same = (steps is None or int(steps) == q["steps"]) and (
        scale is None or round(float(scale), 4) == q["scale"])
    return quality if same else "custom"


def quality_settings(quality, steps=64, scale=1.0):
    """(K, resolution scale, dtype) of a quality level; 'custom' uses steps and scale."""
    if quality == "custom":
        return int(steps), float(min(max(scale, 0.01), 1.0)), np.float32
    q = QUALITY[quality]
    return q["steps"], q["scale"], np.dtype(q["dtype"]).type


def _crossings_plan(light, quality, fast_level, h, w, normal_map, offset):
    """((H, W) to bake at, function) where crossings (crossings.py) bake this light at this
    level, else None: suns and point lights at the level's crossings scale (full size at
    final), when a block of their tables fits in memory."""
    if not fast_level or light.kind not in ("sun", "point"):
        return None
    q = QUALITY[quality]
    f = q.get("crossings_scale_normal" if normal_map else "crossings_scale", 1.0)
    f = min(1.0, max(f, q.get("crossings_min_px", 0) / max(1, min(h, w))))
    sh, sw = max(1, round(h * f)), max(1, round(w * f))
    # blocks are built in groups that fit in memory: one block must
    _, largest = crossings.table_bytes(light, sh, sw, offset, _point_step(quality))
    return ((sh, sw), _by_crossings(light, quality)) \
        if largest <= crossing_blocks.MAX_TABLE_BYTES else None


def _point_step(quality):
    """The column spacing of a point light's polar grid at this level (px)."""
    return QUALITY[quality].get("point_step", crossings.POINT_STEP)


def _by_crossings(light, quality, edited=False):
    """The crossings' bake of this light at this level: of the whole shape, or `edited`,
    of an edit (re-traced where it reads the edit)."""
    if light.kind == "sun":
        return crossings.sun_cos_theta_edited if edited else crossings.sun_cos_theta
    return functools.partial(
        crossings.point_cos_theta_edited if edited else crossings.point_cos_theta,
        step=_point_step(quality))


_REDUCED = {}   # id(normals) → (weak refs to the arrays, (hs, ws), reduced inputs)


def reduced_inputs(normals, heights_px, slopes, hs, ws):
    """The shape's inputs at hs × ws (normals renormalised, heights in reduced pixels). A
    dragged light bakes the same shape again and again (the add-on and a scene of layers keep
    the decoded shape; a moving painting's frames come round): reductions to at most a quarter
    of the pixels (preview and draft, normal maps' 0.4 included) are kept, for the same arrays
    and size, the newest REDUCED_KEPT, and only while those arrays live (an entry whose shape
    was let go is dropped at the next one kept: reductions hold at most a quarter of the
    memory of the shapes still held)."""
    key = id(normals)
    arrays = (normals, heights_px, slopes)
    hit = _REDUCED.get(key)
    if hit is not None and hit[1] == (hs, ws) and \
            all((ref() if ref is not None else None) is a for ref, a in zip(hit[0], arrays)):
        return hit[2]
    n_s = _reduced(normals, hs, ws, "normals")
    z_s = _reduced(heights_px, hs, ws, "heights", normals.dtype.type(ws / normals.shape[1]))
    sl_s = _reduced(slopes, hs, ws, "slopes")
    if 4 * hs * ws <= normals.shape[0] * normals.shape[1]:
        for gone in [k for k, (refs, _, _) in _REDUCED.items() if refs[0]() is None]:
            del _REDUCED[gone]
        if len(_REDUCED) >= REDUCED_KEPT:
            _REDUCED.pop(next(iter(_REDUCED)))
        _REDUCED[key] = (tuple(None if a is None else weakref.ref(a) for a in arrays),
                         (hs, ws), (n_s, z_s, sl_s))
    return n_s, z_s, sl_s


def forget_reductions(normals):
    """The shape whose normals are `normals` was edited in place (strokes.height_shape_edited):
    its kept reduction (reduced_inputs) no longer holds — a later bake of the same arrays
    would read the shape before the edit (a draft that never followed the brush, issue 61).
    (An edit's own bake at a reduced level reads the reduction kept with the bake before it,
    patched: bake_edited.)"""
    _REDUCED.pop(id(normals), None)


def _reduced(a, hs, ws, role, factor=None):
    """One of the shape's inputs (or a block of it) at hs × ws as a reduced bake reads it:
    'normals' renormalised, 'heights' times `factor` (reduced pixels per full pixel),
    'slopes' as they are; None stays None."""
    if a is None:
        return None
    out = resample_separable(a, hs, ws)
    if role == "normals":
        # averages of unit normals with N.z ≥ z_min: renormalising keeps N.z ≥ z_min (|n| ≤ 1,
        # and |n| ≥ N.z ≥ z_min > 0, so the division is safe)
        out /= np.sqrt(np.einsum("...i,...i->...", out, out))[..., None]
    elif role == "heights":
        out = out * factor
    return out


# shapes kept reduced: a scene holds at most 8 layers; a moving painting's drawings come
# round again (§16: a loop of 24 frames, each its own shape, plus margin)
REDUCED_KEPT = 32


def bake(normals, light, offset, quality="final", *, heights_px=None, slopes=None, steps=64,
         scale=1.0, occupancy="linear", reach=np.inf, stats=None, cancel=None, progress=None,
         own_size=False):
    """The cos-θ term at a quality level (§13): march at a reduced resolution if the level
    says so, then upsample to the shape's size. Heights are in pixels of the full image;
    reach: how far a normal map's rebuilt relief is felt (image widths, §6 Reach).
    progress: optional callable(fraction done) (the march reports once per band of rows,
    crossings once per chunk of rays). own_size: a reduced level's t at the size it was
    marched at, clipped, not upsampled (what own_size_t gives of the upsampled one: a caller
    that writes it as an image, which every backend's bilinear lookup enlarges alike)."""
    k, scale, dtype = quality_settings(quality, steps, scale)
    h, w = normals.shape[:2]
    normals = normals.astype(dtype, copy=False)
    heights_px = None if heights_px is None else heights_px.astype(dtype, copy=False)
    slopes = None if slopes is None else slopes.astype(dtype, copy=False)
    hs, ws = _scaled(h, w, scale)
    plan = _level_plan(light, quality, scale, occupancy, h, w, slopes is not None, offset)
    if plan is not None:
        (hs, ws), fast = plan
        if stats is not None:
            stats.method = "exact crossings" if light.kind == "sun" else "aimed crossings"

        def march(n, lt, off, _k, heights_px=None, slopes=None, reach=np.inf, cancel=None,
                  progress=None, **_):
            if cancel is not None and cancel():      # superseded before it starts
                raise BakeCancelled()
            t = fast(n, lt, off, heights_px=heights_px, slopes=slopes, reach=reach,
                     cancel=cancel, progress=progress)
            if progress is not None:                 # (closed forms report nothing)
                progress(1.0)
            return t
    else:
        # a level's march ends where each ray's own path lets it (§16: a still part of a moving
        # painting is marched the same); custom K and the reference end at the image's bounds,
        # as the in-shader marches do, so the page and the OSL shader are checked against
        # them step for step
        march = functools.partial(cos_theta_shadow, bounds="path" if quality in QUALITY and
                                  quality != "reference" else "image")
    if stats is not None:
        stats.size = (hs, ws)
    if (hs, ws) == (h, w):
        return march(normals, light, offset, k, heights_px=heights_px, slopes=slopes,
                     occupancy=occupancy, reach=reach, stats=stats, cancel=cancel,
                     progress=progress)
    n_s, z_s, sl_s = reduced_inputs(normals, heights_px, slopes, hs, ws)
    t = march(n_s, light, offset, k, heights_px=z_s, slopes=sl_s, occupancy=occupancy,
              reach=reach, stats=stats, cancel=cancel, progress=progress)
    if own_size:
        return np.clip(t, 0, 1).astype(dtype, copy=False)
    return _upsampled(t, h, w, dtype, (n_s, z_s, sl_s) if plan is not None else None)


def _scaled(h, w, scale):
    return max(1, round(h * scale)), max(1, round(w * scale))


def _level_plan(light, quality, scale, occupancy, h, w, normal_map, offset):
    """_crossings_plan of a bake at this level and resolution `scale`, or None (it marches).
    Crossings smear one-pixel walls a little (a resampled grid): below ~512 px the K = 64
    march is more accurate and cheap anyway, so 'final' marches there."""
    fast_level = quality in ("draft", "preview") or (
        quality == "final" and min(_scaled(h, w, scale)) >= FAST_FINAL_MIN_PX)
    return _crossings_plan(light, quality, fast_level and occupancy == "linear", h, w,
                           normal_map, offset)


# A reduced-size bake by crossings, kept for the edit that follows it (bake_edited): its
# full-size t (weakly: gone with it) → (the reduced inputs, the reduced t); the newest few
_REDUCED_BAKES = {}
REDUCED_BAKES_KEPT = 8


def _upsampled(t_s, h, w, dtype, reduced=None, before=None):
    """A reduced bake's t at the shape's size (bilinear, clipped to 0…1); `reduced`: its
    reduced inputs, kept with it when it was baked by crossings (for bake_edited); before:
    (the reduced t, its t at full size) of the bake an edit changed — only the pixels that
    read a changed reduced pixel are upsampled again (enlarged_box: the same values)."""
    if before is not None and before[0].shape == t_s.shape and \
            before[1].shape == (h, w) and before[1].dtype == dtype:
        t, box = before[1].copy(), changed_box(before[0], t_s)
        if box is not None:
            r0, r1, c0, c1 = out = enlarged_box(box, t_s.shape, (h, w))
            t[r0:r1, c0:c1] = np.clip(resample_separable(t_s, h, w, out), 0, 1)
    else:
        t = np.clip(resample_separable(t_s, h, w), 0, 1).astype(dtype, copy=False)
    if reduced is not None:
        for gone in [k for k, (ref, _, _) in _REDUCED_BAKES.items() if ref() is None]:
            del _REDUCED_BAKES[gone]
        if len(_REDUCED_BAKES) >= REDUCED_BAKES_KEPT:
            _REDUCED_BAKES.pop(next(iter(_REDUCED_BAKES)))
        _REDUCED_BAKES[id(t)] = (weakref.ref(t), reduced, t_s)
    return t


def _reduced_bake_of(t):
    """(reduced inputs, reduced t) of a reduced bake whose full-size t is `t`, or None."""
    hit = _REDUCED_BAKES.get(id(t))
    return None if hit is None or hit[0]() is not t else hit[1:]


def own_size_t(t):
    """The t a reduced bake by crossings (draft, preview: §13) made before it was upsampled
    into `t`, or None: what an image sampled bilinearly with its edges extended shows as `t`
    (resample_separable's taps at (i + ½)·f − ½ are the texture's pixel centres), so a draft's
    or preview's cos-θ image is written at this size — 64× fewer pixels at 4096² draft.

    >>> own_size_t(np.zeros((4, 4))) is None
    True
    """
    kept = _reduced_bake_of(t)
    return None if kept is None else np.clip(kept[1], 0, 1)


def reduced_box(box, f, h_s, w_s):
    """The reduced pixels (a box) that read a full-size box when the size is divided by the
    whole factor `f`: output pixel i reads input pixels f·i … f·i + f − 1 only
    (resample_separable's taps at (i + ½)·f − ½)."""
    if box is None:
        return None
    r0, r1, c0, c1 = box
    return r0 // f, min(h_s, -(-r1 // f)), c0 // f, min(w_s, -(-c1 // f))


def _reduced_edited(full, before, box, f, role, factor=None):
    """A reduced input (_reduced's `role`) of an edited shape from the one `before` it: only
    the reduced box that reads the edit is reduced again, from its own block of full-size
    pixels (the same taps: equal to reducing the whole)."""
    if box is None or full is None:
        return before
    r0, r1, c0, c1 = box
    out = before.copy()
    out[r0:r1, c0:c1] = _reduced(full[r0 * f:r1 * f, c0 * f:c1 * f], r1 - r0, c1 - c0, role,
                                 factor)
    return out


def bake_edited(normals, light, offset, quality, t_before, normals_box, heights_box, *,
                heights_px=None, slopes=None, steps=64, scale=1.0, occupancy="linear",
                reach=np.inf):
    """bake() of a shape an edit changed in normals_box and heights_box (core/strokes.py),
    from t_before, its bake before the edit at the same level, light and settings (issue 41):
    where the level bakes by crossings, only the rays that read a changed pixel are traced
    again (crossings.sun_cos_theta_edited, point_cos_theta_edited; equal to the whole bake)
    — also at a reduced size (draft, preview: a whole factor smaller) from the reduced
    inputs and t kept with t_before, their boxes that read the edit reduced again, then
    upsampled. None where the level bakes otherwise (a march, a point light over the edit, a
    size that is no whole multiple, nothing kept): bake the whole then (those are the cheap
    ones, or the reference)."""
    _, scale, dtype = quality_settings(quality, steps, scale)
    h, w = normals.shape[:2]
    if normals_box is None and heights_box is None and t_before.shape == (h, w):
        # an edit that changed nothing the bake reads (a dab clipped to what was there, an
        # image reloaded unchanged): at any level its bake is the one before
        return t_before.astype(dtype, copy=False)
    plan = _level_plan(light, quality, scale, occupancy, h, w, slopes is not None, offset)
    if plan is None or t_before.shape != (h, w):
        return None
    normals = normals.astype(dtype, copy=False)
    heights_px = None if heights_px is None else heights_px.astype(dtype, copy=False)
    slopes = None if slopes is None else slopes.astype(dtype, copy=False)
    (hs, ws), _ = plan
    if (hs, ws) == (h, w):
        t = _by_crossings(light, quality, edited=True)(
            normals, light, offset, t_before.astype(dtype, copy=False), normals_box,
            heights_box, heights_px=heights_px, slopes=slopes, reach=reach)
        return None if t is None else t.astype(dtype, copy=False)
    # a reduced level (draft, preview): the reduced inputs patched where the edit reaches
    # them, the reduced rays that read a changed reduced pixel traced again, then upsampled
    f, kept = h // hs, _reduced_bake_of(t_before)
    if kept is None or hs * f != h or ws * f != w:
        return None
    (n_s, z_s, sl_s), t_s = kept
    nb, hb = reduced_box(normals_box, f, hs, ws), reduced_box(heights_box, f, hs, ws)
    reduced = (_reduced_edited(normals, n_s, nb, f, "normals"),
               _reduced_edited(heights_px, z_s, hb, f, "heights", normals.dtype.type(ws / w)),
               _reduced_edited(slopes, sl_s, nb, f, "slopes"))
    edited = _by_crossings(light, quality, edited=True)(
        reduced[0], light, offset, t_s, nb, hb, heights_px=reduced[1], slopes=reduced[2],
        reach=reach)
    return None if edited is None else _upsampled(edited, h, w, dtype, reduced,
                                                  (t_s, t_before))
