"""The cos-θ images of a painting's lights (docs/pipeline.md §6): baked with the numpy core,
each remembered with the key of what it was baked from, so a bake runs only when its light
moved or a parameter with the `bake` role (params.py) changed."""
import time
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from ... import params
from ...core.bake import own_size_t
from ...core.pipeline import (shadow_term, shadow_term_edited, shape_normals,
                              shape_normals_edited)
from ...core.strokes import changed_box, union
from ...inputs import memory
from ...inputs.imageio import file_channels
from ...inputs.painting_frames import BoundedCache
from ..state.edits import key_name
from ..state.frames import frame_data, painting_size, shown_frame, slot_frame
from ..state.images import grey_image
from ..state.lights import painting_frame_light, plane_matrix
from ..state.settings import settings_to_params

BAKE_PARAMS = tuple(prm for prm in params.PARAMS if prm.bake)


def light_key(light):
    """Where a light is, as far as its bake is concerned: to a millionth (of a unit vector or
    an image width) — coarser than the float32 noise of a light re-parented where it stands (a
    turntable made from it), finer than any move a shadow shows (0.004 px at 4096²)."""
    return repr((light.kind, np.round(light.vector, 6).tolist()))


def bake_key(light, p, s):
    """What a bake depends on: the light's place, the bake's parameters, the shape image."""
    return light_key(light) + "|" + settings_key(p, s)


def bake_values(p):
    """The parameters with the `bake` role (params.py)."""
    return [getattr(getattr(p, prm.section), prm.key) for prm in BAKE_PARAMS]


def settings_key(p, s):
    """What a bake depends on besides its light: the bake's parameters, the shape image and,
    of a moving shape, the frame shown (§16: not the scene frame — frames that show one
    drawing share their bakes)."""
    values = bake_values(p)
    if s.image_shape is None:
        return repr((values, None))
    frame = shown_frame(s.id_data, "shape")
    shape = key_name(s.image_shape)
    return repr((values, shape) if frame is None else (values, shape, frame))


# material name → BoundedCache: shape key → (normals, heights_px, slopes), the bakes' decoded
# shape: the newest one of a still painting; of a moving one (§16) its frames', up to
# SHAPE_FRAMES_MB (a frame that comes round again is not decoded, or integrated, again)
_SHAPES = {}
SHAPE_FRAMES_MB = 512


def bake_shape(mat, p, fresh=False, read=None):
    """The shape decoded for the bake (§2), cached per painting until its shape image or the
    shape settings change, so per-frame and live bakes do not read and decode it each time;
    `fresh` decodes again (the image's pixels may have been edited). read: channel → its
    ImageData, where the caller has read the images already (PaintingState.read)."""
    s = mat.dynamic_painting
    key = shape_key(s, p)
    moving = key[1] is not None
    cache = _SHAPES.get(mat.name)
    if cache is None or cache.mb != (SHAPE_FRAMES_MB if moving else 0):
        cache = _SHAPES[mat.name] = BoundedCache(SHAPE_FRAMES_MB if moving else 0)
    hit = None if fresh else cache.get(key)
    if hit is None:
        data = read("shape") if read is not None else frame_data(mat, "shape")
        hit = _decoded_after_edit(mat, data, p) if not moving else None
        if hit is None:
            hit = shape_normals(data, p, np.float32)
        if not moving:
            _remember(mat, data, p, hit)
        cache.put(key, hit, sum(a.nbytes for a in hit if a is not None))
    return hit


def shape_key(settings, p, edits=True):
    """What the decoded shape depends on: the image (of a moving one, the frame shown) and the
    §2 settings, and for a normal map the relief its shadows fall from (§6); `edits`: and how
    many times the image was edited (state/edits.py)."""
    img = settings.image_shape
    return (key_name(img) if edits else img.name, shown_frame(settings.id_data, "shape"),
            repr(vars(p.shape)), p.shadows.relief)


@dataclass
class _Still:
    """The newest decode of a still painting's shape: the next edit of its image decodes and
    bakes again only what the edit changed (core/strokes.py, issue 41)."""
    base: tuple                 # shape_key without the edits: what else it was decoded for
    pixels: np.ndarray          # the image's pixels it was decoded from
    decoded: tuple              # (normals, heights_px, slopes)
    bakes: dict = field(default_factory=dict)  # bake_slot → t, baked from this decode
    # bake_slot → (t, normals' box, heights' box): the newest bake of an earlier decode and
    # the boxes changed since (a live stroke bakes drafts; its final starts from the final
    # before the stroke, the boxes of all its dabs together)
    since: dict = field(default_factory=dict)


# material name → _Still. Paintings up to STILL_PX pixels (a 4096² one keeps ~0.5 GB: the
# pixels and the decode, with a t per light and level)
_STILL = {}
STILL_PX = 4096 * 4096


def bake_slot(light, p):
    """What a bake of one decode depends on: the light's place and the bake's parameters."""
    return light_key(light) + repr(bake_values(p))


def _decoded_after_edit(mat, data, p):
    """The shape decoded again where its image's edit changed it, from the decode before
    (pipeline.shape_normals_edited), or None: decode it whole."""
    last = _STILL.get(mat.name)
    if last is None or last.base != shape_key(mat.dynamic_painting, p, edits=False):
        return None
    box = changed_box(last.pixels, data.pixels)
    if box is None and last.pixels.shape == data.pixels.shape:
        return last.decoded                        # (an update that changed nothing)
    edited = None if box is None else shape_normals_edited(
        data, p, last.decoded, box, in_place=not _READING[id(last.decoded[0])])
    if edited is None:
        return None
    decoded, nb, hb = edited
    since = {slot: (t, union(nb0, nb), union(hb0, hb))
             for slot, (t, nb0, hb0) in last.since.items()}
    since.update((slot, (t, nb, hb)) for slot, t in last.bakes.items())
    _STILL[mat.name] = _Still(last.base, data.pixels, decoded, since=since)
    return decoded


# id of a decode's normals → how many live bakes' workers read it (held, released): an edit
# decodes into copies of a decode being read, into its own arrays otherwise (the edit drops it)
_READING = Counter()


def held(shape):
    """A worker will read `shape` (a decode) until it calls released(shape): main thread."""
    _READING[id(shape[0])] += 1
    return shape


def released(shape):
    """The worker is done with `shape` (any thread: one dict entry, under the GIL)."""
    _READING[id(shape[0])] -= 1
    if _READING[id(shape[0])] <= 0:
        del _READING[id(shape[0])]


def _remember(mat, data, p, decoded):
    """Keep a still painting's decode (and its bakes, keep_bake) for its next edit."""
    last = _STILL.get(mat.name)
    if last is not None and last.decoded is decoded:
        return
    if data.pixels.shape[0] * data.pixels.shape[1] > STILL_PX:
        _STILL.pop(mat.name, None)
        return
    _STILL[mat.name] = _Still(shape_key(mat.dynamic_painting, p, edits=False), data.pixels,
                              decoded)


def edit_start(mat, shape, light, p):
    """(t, normals' box, heights' box): a bake of this light at p's level from before the
    edits that made `shape` (the painting's newest decode), and what they changed — what
    pipeline.shadow_term_edited starts from; None where there is none."""
    still = _STILL.get(mat.name)
    if still is None or still.decoded is not shape:
        return None
    slot = bake_slot(light, p)
    if slot in still.bakes:     # baked from this very decode: an edit changed nothing it reads
        return still.bakes[slot], None, None
    return still.since.get(slot)


def keep_bake(mat, shape, light, p, t):
    """A bake of `shape` (the painting's newest decode): the next edit starts from it."""
    still = _STILL.get(mat.name)
    if still is not None and still.decoded is shape:
        slot = bake_slot(light, p)
        still.bakes[slot] = t
        still.since.pop(slot, None)


def bake_light(shape, light, p, cancel=None, progress=None, start=None):
    """One light's cos-θ term of `shape` (§6): re-traced where the edits since `start`
    (edit_start) changed what its rays read, else baked whole. Blender data is not read:
    the live bake's worker calls it too."""
    t = None if start is None else shadow_term_edited(*shape, light, p, *start)
    return t if t is not None else shadow_term(*shape, light, p, cancel=cancel,
                                               progress=progress)


# material name → BoundedCache: bake key → t, the bakes of a moving shape (§16). A loop that
# comes round with its lights where they were shows each drawing's shadows again without
# baking them (playback of a looping animation under a still light); at most KEPT_BAKES_MB
# per painting (24 frames at 1024² hold 96 MB).
_BAKES = {}
KEPT_BAKES_MB = 256


def kept_bake(mat, key):
    """The cos-θ image baked before for this key, or None."""
    cache = _BAKES.get(mat.name)
    return None if cache is None else cache.get(key)


def keeps_bakes(mat):
    """Whether the painting's bakes are kept (its shape moves and it has baked)."""
    return mat.name in _BAKES


def forget_cached_shapes():
    """Another file is open: cached shapes may belong to same-named paintings of the last one."""
    _SHAPES.clear()
    _BAKES.clear()
    _STILL.clear()


def forget_cached_shape(mat):
    """The painting's shape image was replaced: decode it (and bake it) again."""
    _SHAPES.pop(mat.name, None)
    _BAKES.pop(mat.name, None)
    _STILL.pop(mat.name, None)


def light_bakes(mat, depsgraph=None, p=None):
    """[(light item, core Light in the painting frame, bake key)] of the painting's lights."""
    s = mat.dynamic_painting
    p = p or settings_to_params(s)
    m = plane_matrix(mat, depsgraph)
    return [(item, light, bake_key(light, p, s)) for item, light in
            ((i, painting_frame_light(i.object, m, depsgraph)) for i in s.lights
             if i.object is not None)]


def stale_lights(mat, depsgraph=None, p=None):
    """The light_bakes whose image is missing or was baked for another place or settings."""
    return [(item, light, key) for item, light, key in light_bakes(mat, depsgraph, p)
            if item.shadow is None or item.bake_key != key]


def shadow_image_name(mat, light_name):
    return f"DP {mat.name} shadow {light_name}"


def bake_shadows(mat, scene, depsgraph=None, force=True, progress=None, p=None, read=None):
    """Bake the cos-θ term (§6) of the linked lights into their images. → milliseconds taken.
    p: the painting's parameters when the caller has them (read from its settings if not);
    read: its images, where the caller read them (bake_shape).

    Without `force`, a light whose painting-frame position and shadow inputs are those of its
    last bake is skipped (static lights in an animation bake once). A failure leaves the
    previous images untouched: new pixels are written only after every light is baked.
    """
    s = mat.dynamic_painting
    p = p or settings_to_params(s)
    if s.image_shape is None:
        raise ValueError("no shape image to bake shadows from: assign one under Images "
                         "(the last baked shadows are kept)")
    todo = light_bakes(mat, depsgraph, p) if force else stale_lights(mat, depsgraph, p)
    if not todo:
        return 0.0
    if force:                  # the shape's pixels may have changed: nothing kept holds
        _BAKES.pop(mat.name, None)
    results = [kept_bake(mat, key) for _, _, key in todo]
    t_start = time.perf_counter()
    due = [i for i, t in enumerate(results) if t is None]
    if due:
        check_bake_memory(mat, p, [todo[i][1] for i in due])
        shape = bake_shape(mat, p, fresh=force, read=read)
    for j, i in enumerate(due):
        part = None if progress is None else \
            (lambda f, j=j: progress((j + f) / len(due)))     # noqa: E731
        light = todo[i][1]
        results[i] = bake_light(shape, light, p, progress=part,
                                start=edit_start(mat, shape, light, p))
        keep_bake(mat, shape, light, p, results[i])
    ms = (time.perf_counter() - t_start) * 1000
    if ms > 2000:      # long bakes (huge images, reference quality) say what they did
        w, h = painting_size(mat)
        print(f"Dynamic Painting: {mat.name}: baked {len(due)} light(s) at {w}×{h} "
              f"({p.shadows.quality}) in {ms / 1000:.1f} s")
    for (item, _, key), t in zip(todo, results):
        write_shadow(mat, item, t, key)
    s.shadows_stale = False
    return ms


def check_bake_memory(mat, p, lights):
    """Refuse a final bake that would not fit in memory (the last baked images are kept; the
    lower qualities bake a fraction of the pixels, so only a full-size bake is asked)."""
    if p.shadows.quality not in ("final", "reference"):
        return
    w, h = painting_size(mat)
    shape = memory.shape_work(p, file_channels(mat.dynamic_painting.image_shape) in (2, 4))
    memory.check(memory.final_bake_bytes(w, h, shape, lights, p.shadows.offset), f"baking the shadows of {w}×{h} pixels at {p.shadows.quality} "
                 f"quality", "bake at preview or draft quality (Shadows › Quality), or use a "
                 "smaller shape image (the last baked shadows are kept)")


def write_shadow(mat, item, t, key):
    """Write a finished bake into the light's image (a moving shape's also kept, _BAKES): a
    draft's or preview's at the size it was baked at (own_size_t: every backend's bilinear
    lookup shows it as the upsampled t; Blender's image API writes a 4096² image in ~65 ms,
    the 512² of a draft in under 1 ms), the image resized in place (float_image)."""
    small = own_size_t(t)
    item.shadow = grey_image(shadow_image_name(mat, item.object.name),
                             t if small is None else small)
    item.bake_key = key
    if slot_frame(mat, "shape") is not None:
        _BAKES.setdefault(mat.name, BoundedCache(KEPT_BAKES_MB)).put(key, t, t.nbytes)
