"""A lit copy following its drawing while the artist draws (issue 42: draft while drawing,
final after): a stroke's draft (the changed layers drawn small, enlarged into their images,
the shadows drafted), then once the strokes stop the full redraw (the changed layers read,
a worker thread draws them at full size and makes them paintings, finish_redraws writes
them), the lit copy framed anew in place where only the drawing's bounds moved (_reframed),
or made anew where its layers or frames are no longer its own. With a UI (issue 61)
Blender's main thread only reads and writes: drafts, full redraws and their shadows are
made in worker threads, and the first stroke's draft is made ready after each full redraw
(warm_first_draft).
"""
import contextlib
import json
import threading

import numpy as np

import bpy

from ....inputs.imageio import image_data_from_blender
from ...bake.layers import (GroupDraft, draft_group_beside, final_bake_due, forget_group,
                            group_materials, hold_group, warm_drafts)
from ...bake.live_bake import rendering
from ...material.sync import update
from ...state.edits import note_edited
from ...state.frames import forget_frames, moves
from ...state.images import (derived_shown, enlarged, enlarged_kept, forget_enlarged,
                             image_rgba, keep_derived_enlarged, keep_enlarged,
                             refill_packed_image)
from ...state.painting_state import read_state
from ...state.settings import channel_images
from ...state.status import report
from ..layered_build import remove_objects
from .artist_changes import ArtistChanges
from .lit_copy import (LAYER, LIT_SETTINGS, SOURCE, SPACING_WIDTH, drawn_paintings,
                       light_drawing, lit_defaults, made_paintings, read_images)
from .reading import drawn_layers, framing, layer_digests, layer_stem
from .reframing import Reframe
from .strokes import unsupported

DRAFT_WIDTH = 128      # px: a stroke's draft drawing (Blender's draw costs its pixels here)
DRAFT_SAMPLES = 1      # and its anti-aliasing samples (each a draw of every pixel; SMAA stays)
_DRAFTED = {}          # lit copy's name → the layer digests its last draft drew


def _moving(mats):
    """{stem: whether its material moves} of _layer_materials' (read on the main thread)."""
    return {stem: moves(mat) for stem, mat in mats.items()}


def _layer_materials(obj, parent, source, settings, bounds=True):
    """The lit copy's layer materials {stem: material}, or None where the drawing's layers or
    (with `bounds`) its bounds are not those it was made from (it is made anew then)."""
    mats = {m.get(LAYER): m for m in group_materials(parent)}
    same = set(mats) == {layer_stem(i, group) for i, group
                         in enumerate(drawn_layers(obj, settings["merge"])[0])} \
        and (not bounds or np.allclose(framing(obj), source["bounds"], rtol=0, atol=1e-9))
    return mats if same else None


def _in_place(moving, made):
    """The made paintings (drawn_paintings' entries) that can be written into the lit copy's
    materials (`moving`: {stem: whether its material moves}) → [(stem, images)], or None
    where one of them moves and its material does not, or the other way round (other
    frames: the lit copy is made anew)."""
    if any((table is None) == moving[name]
           for name, _, imgs, _, table in made if imgs is not None):
        return None
    return [(name, imgs) for name, _, imgs, _, _ in made if imgs is not None]


def _source(parent):
    """(the drawing, the lit copy's settings, its recorded source) of a lit copy, or None
    where its drawing is gone."""
    source = json.loads(parent[SOURCE])
    obj = bpy.data.objects.get(source["object"])
    if obj is None or obj.type != "GREASEPENCIL":
        return None
    settings = {**lit_defaults(), **{k: source[k] for k in LIT_SETTINGS if k in source}}
    # (a lit copy recorded before its Spacing's width was: the width its layers were placed for)
    x0, x1 = source["bounds"][:2]
    settings[SPACING_WIDTH] = source.get(SPACING_WIDTH, x1 - x0)
    return obj, settings, source


def _changed(obj, recorded):
    """(the drawing's layer digests now, the names of the layers whose digest is not the one
    `recorded`)."""
    digests = layer_digests(obj)
    return digests, {n for n, d in digests.items() if recorded.get(n) != d}


def refresh_lit_drawing(context, parent, beside=None):
    """Redraw the lit copy `parent` from its drawing as it is now: the layers that changed
    (layer_digests) drawn again and their images written in place where the layers, the
    drawing's bounds, sizes and frames are as before (their edits noted, so the group bakes
    again), framed anew in place where only the bounds moved (_reframed), else the lit copy
    made anew → the parent (a new one then). beside (default: with a UI, rendering() not):
    the layers are read now (all of them where the lit copy is framed or made anew) and a
    worker thread draws them and makes them paintings (read_images: where numpy cannot draw
    the drawing, Blender's renderer draws them now); finish_redraws writes them once made,
    or frames or makes the lit copy anew from them, if the drawing is still as drawn."""
    found = _source(parent)
    if found is None:
        return parent
    obj, settings, source = found
    _DRAFTED.pop(parent.name, None)                # (drafts are drawn over from here)
    digests, changed = _changed(obj, source.get("layers", {}))
    mats = _layer_materials(obj, parent, source, settings)
    if not rendering() if beside is None else beside:
        draw, bounds, frames, notes = read_images(
            context.scene, obj, settings, only=None if mats is None else changed)
        _REDRAWS[parent.name] = _Redraw(digests, draw, settings,
                                        anew=None if mats is not None else (bounds, frames, notes))
        if not bpy.app.timers.is_registered(finish_redraws):
            bpy.app.timers.register(finish_redraws, first_interval=POLL_S)
        return parent
    if mats is None:            # other bounds (a stroke past them), layers or frames
        painted = drawn_paintings(context.scene, obj, settings)
        return _reframed(context, parent, obj, settings, source, digests, painted) or \
            _made_anew(context, parent, obj, settings, painted)
    made = _in_place(_moving(mats),
                     drawn_paintings(context.scene, obj, settings, only=changed)[0])
    return _write_redraw(context, parent, mats, made, obj, settings, source, digests)


def _reframed(context, parent, obj, settings, source, digests, painted, beside=False,
              rgba=None):
    """The lit copy framed anew in place where only the drawing's bounds moved (a stroke
    past them; its layers, their kinds and frames as before: reframing.Reframe) — beside
    the UI a layer a tick (finish_redraws: _framing), its group's bakes held meanwhile, then
    its shadows drafted in a worker from the images written (draft_group_beside), final
    after; else at once, baked now. painted: drawn_paintings' of every layer; rgba:
    _write_redraw's. → the parent, or None where it cannot be framed in place."""
    made, bounds, frames, _ = painted
    mats = _layer_materials(obj, parent, source, settings, bounds=False)
    job = None if mats is None or frames is not None or any(_moving(mats).values()) else \
        Reframe.of(parent, obj, mats, made, bounds, source["bounds"], rgba)
    if job is None:
        return None
    record = {**source, "bounds": list(bounds), "layers": digests,
              SPACING_WIDTH: settings[SPACING_WIDTH]}
    if not beside:
        _framed_whole(context, job, job.steps(context.scene), record)
        return parent
    hold_group(parent)
    _REFRAMES[parent.name] = (job, job.steps(context.scene), record, settings)
    _framing(parent.name)                 # (its first slice now)
    return parent


_REFRAMES = {}         # lit copy's name → (Reframe, its steps, its record, its settings)
_DONE = object()


def _framing(name):
    """The next slice of lit copy `name`'s Reframe (one per tick: finish_redraws); after its
    last, the lit copy's record, its shadows' draft in a worker (final after) and its first
    stroke's draft made ready. A slice that fails: the lit copy made anew, the error said."""
    job, steps, record, settings = _REFRAMES[name]
    try:
        with redrawing(name):
            if next(steps, _DONE) is _DONE:
                del _REFRAMES[name]
                _framed(bpy.context, job, record, beside=True)
    except Exception as exc:        # never into Blender's timer loop
        _REFRAMES.pop(name, None)
        forget_group(name)
        report(name, exc)
        try:
            _made_anew(bpy.context, job.parent, job.obj, settings, beside=True)
        except Exception as again:
            report(name, again)


def frame_all_now(context):
    """A render is about to start: the lit copies being framed anew a layer a tick are
    framed whole now, their shadows baked now (a render shows no half-framed lit copy)."""
    for name in list(_REFRAMES):
        job, steps, record, _ = _REFRAMES.pop(name)
        try:
            with redrawing(name):
                _framed_whole(context, job, steps, record)
        finally:
            forget_group(name)          # (its bakes held no longer, whatever happened)


def _framed_whole(context, job, steps, record):
    """A Reframe's slices left (`steps`, its generator) all run now, its shadows baked now."""
    for _ in steps:
        pass
    _framed(context, job, record, beside=False)


def _framed(context, job, record, beside):
    """A Reframe's every slice done: the lit copy's record, its group's scenes and drafts of
    the old framing dropped; its shadows baked now, or `beside` the UI drafted in a worker
    from the images written (final after) and its first stroke's draft made ready."""
    parent = job.parent
    forget_frames()
    forget_group(parent.name)
    parent[SOURCE] = json.dumps(record)
    if not beside:
        for _, mat, _, _ in job.layers:      # (the first bakes the group)
            update(mat, context.scene, bake="now")
        return
    draft_group_beside(parent, {mat.name: imgs for _, mat, _, imgs in job.layers})
    warm_first_draft(context, parent, job.rgba)


def _made_anew(context, parent, obj, settings, painted=None, beside=False):
    """The lit copy `parent` removed (its images too) and made again from its drawing (its
    bounds, layers, sizes or frames are no longer those it was made from), what the artist
    changed on it kept (artist_changes.py) → the new parent.
    painted: light_drawing's; beside the UI, its shadows baked as a dragged light's: a
    draft now, the final in a worker thread (bake_group_live)."""
    hidden = obj.hide_get()
    changes = ArtistChanges.of(parent)             # (nothing of the artist's lost)
    remove_objects(changes.own(parent) + [parent], images=True)
    obj.hide_set(False)
    parent, _ = light_drawing(context, obj, settings, painted=painted,
                              bake="live" if beside else "now")
    changes.given_to(context, parent, bake="live" if beside else "now")
    obj.hide_set(hidden or obj.hide_get())
    if beside:
        warm_first_draft(context, parent)
    return parent


def _write_redraw(context, parent, mats, made, obj, settings, source, digests, beside=False,
                  rgba=None):
    """The made paintings written into the lit copy's images in place (packed when the file
    is saved: handlers.pack_edited_images) and its record updated, or the lit copy made anew
    where they cannot be (made None, or an image of another size or kind) → the parent. The
    group is baked now, or `beside` the UI: at its own quality in a worker thread
    (final_bake_due); rgba: {(layer, channel): the RGBA buffer written} made there
    already."""
    written = []
    for name, imgs in made or ():
        for channel, data in imgs.items():
            img = getattr(mats[name].dynamic_painting, f"image_{channel}")
            # (beside the UI its RGBA made by the worker, _Redraw: Blender is held to copy)
            if img is None or not refill_packed_image(img, data,
                                                      rgba=(rgba or {}).get((name, channel))):
                made = None
                break
            written.append(img.name)
        if made is None:
            break
    if made is None:                               # other layers, sizes or frames: anew
        return _made_anew(context, parent, obj, settings)
    forget_enlarged(written)
    note_edited(written)
    forget_frames()
    parent[SOURCE] = json.dumps({**source, "layers": digests})
    for mat in mats.values():       # (the first bakes the group, unless beside the UI)
        update(mat, context.scene, bake="none" if beside else "now")
    if beside:                      # the stroke's draft shows till then: no full-size draft
        final_bake_due(parent)
        warm_first_draft(context, parent, {(name, c): rgba[(name, c)] for name, imgs in made
                                           for c in imgs if (name, c) in (rgba or {})})
    return parent


_REDRAWING = []        # a lit copy being redrawn: its own renders update the drawing too


@contextlib.contextmanager
def redrawing(name):
    """While lit copy `name` is redrawn (its drawing's updates are its own: redrawing_now)."""
    _REDRAWING.append(name)
    try:
        yield
    finally:
        _REDRAWING.pop()


def redrawing_now():
    return bool(_REDRAWING)


_REDRAWS = {}          # lit copy's name → its _Redraw (the newest: an older one is dropped)
POLL_S = 0.05          # how often finish_redraws looks for made paintings


class _Redraw:
    """A full redraw's layers drawn (numpy's drawing; Blender's renderer drew them already
    where numpy does not draw the drawing: lit_copy.read_images) and made paintings in a
    worker thread (the inflation of a changed part at full size takes a second at 1024²)
    while the UI goes on.
    anew: (bounds, frames, notes) of read_images where the lit copy is framed or made anew
    (a stroke beyond the drawing's bounds: every layer drawn again), else None."""

    def __init__(self, digests, draw, settings, anew=None):
        self.digests, self.anew, self.made, self.error = digests, anew, None, None
        self.rgba = None
        self.thread = threading.Thread(target=self._run, args=(draw, settings), daemon=True)
        self.thread.start()

    def _run(self, draw, settings):
        try:
            self.made = made_paintings(draw(), settings)[0]
            self.rgba = {(name, channel): image_rgba(data)
                         for name, _, imgs, _, _ in self.made if imgs is not None
                         for channel, data in imgs.items()}
        except Exception as exc:        # (said on the main thread: finish_redraws)
            self.error = exc


def finish_redraws():
    """Timer: the full redraws whose paintings are made written into their lit copies
    (_write_redraw), framed them anew (_reframed: its shadows drafted in a worker, final
    after) or made them anew (_made_anew, its shadows baked as a dragged light's: a draft
    now, final in a worker), where the drawing is still as Blender
    drew it — else dropped: the strokes since are drafted, and their own full redraw
    follows. → seconds to the next call (None: none left)."""
    for name in list(_REFRAMES):
        _framing(name)
    for name, job in list(_REDRAWS.items()):
        if job.thread.is_alive() or name in _REFRAMES:     # (a lit copy being framed: after)
            continue
        del _REDRAWS[name]
        parent = bpy.data.objects.get(name)
        found = None if parent is None else _source(parent)
        if found is None:
            continue
        if job.error is not None:
            report(name, job.error)
            continue
        obj, settings, source = found
        mats = None if job.anew else _layer_materials(obj, parent, source, settings)
        if (mats is None and job.anew is None) or layer_digests(obj) != job.digests:
            continue
        try:
            with redrawing(name):
                if job.anew is not None:
                    painted = (job.made, *job.anew)
                    _reframed(bpy.context, parent, obj, settings, source, job.digests,
                              painted, beside=True, rgba=job.rgba) or \
                        _made_anew(bpy.context, parent, obj, settings, painted, beside=True)
                else:
                    _write_redraw(bpy.context, parent, mats,
                                  _in_place(_moving(mats), job.made), obj, settings, source,
                                  job.digests, beside=True, rgba=job.rgba)
        except Exception as exc:        # never into Blender's timer loop
            report(name, exc)
    return POLL_S if _REDRAWS or _REFRAMES else None


def warm_first_draft(context, parent, bigs=None):
    """Once the lit copy `parent` shows its drawing in full (From Grease Pencil, a full
    redraw written), make its first stroke's draft ready in a worker thread — every layer
    drawn DRAFT_WIDTH across and made a painting there (as draft_lit_drawing draws it),
    refill_enlarged told what each image shows (`bigs`: {(layer stem, channel): its RGBA};
    the others kept from the last, or read from Blender now) and what each derived image
    shows (read now), the group's small scene prepared with its own draft terms
    (bake/layers.warm_drafts) — so the first draft costs what the next ones do (issue 61).
    Where numpy does not draw the drawing, or a layer moves, nothing is made
    ready (the draft does it all). → the worker thread, or None."""
    found = _source(parent)
    if found is None:
        return None
    obj, settings, source = found
    mats = _layer_materials(obj, parent, source, settings, bounds=False)
    if mats is None or any(moves(m) for m in mats.values()) or \
            unsupported(obj, drawn_layers(obj, settings["merge"])[0]):
        return None
    small = _draft_settings(settings)
    draw = read_images(context.scene, obj, small, bounds=source["bounds"])[0]
    images = {(stem, c): img for stem, m in mats.items()
              for c, img in channel_images(m.dynamic_painting).items() if img is not None}
    shown = {}
    for key, img in images.items():      # what each shows: written, kept, else read now
        big = (bigs or {}).get(key)
        big = enlarged_kept(img) if big is None else big
        big = image_rgba(image_data_from_blender(img)) if big is None else big
        shown[key] = (img.name, img.as_pointer(), big)
    names = {stem: m.name for stem, m in mats.items()}
    derived = {}                 # what the draft's derived images will be made from
    for stem, m in mats.items():
        state = read_state(m, context.scene)
        derived[stem] = (*derived_shown(m, state, channel_images(m.dynamic_painting)),
                         state.params)

    def made_small():            # (the worker: numpy alone)
        out = {}
        for stem, _, imgs, _, _ in made_paintings(draw(), small)[0]:
            out[names[stem]] = imgs
            for c, data in imgs.items():
                if (stem, c) in shown:
                    name, pointer, big = shown[(stem, c)]
                    keep_enlarged(name, pointer, image_rgba(data), big)
            keep_derived_enlarged(*derived[stem][:2], imgs, derived[stem][2])
        return out
    return warm_drafts(parent, made_small)


def _draft_settings(settings):
    """A lit copy's settings as a stroke's draft draws its layers: DRAFT_WIDTH across, the
    current frame."""
    return {**settings, "resolution": min(DRAFT_WIDTH, settings["resolution"]),
            "animation": False}


def forget_drafts():
    """Another file is open, or undo: the drafts' digests and the redraws under way may be
    of other drawings."""
    _DRAFTED.clear()
    _REDRAWS.clear()
    _DRAFTS.clear()
    _REFRAMES.clear()


def draft_lit_drawing(context, parent, beside=False):
    """A stroke while the artist draws (issue 42: draft while drawing, final after): the
    layers that changed since the last draft drawn at DRAFT_WIDTH px across (DRAFT_SAMPLES
    a pixel) and made paintings there (their relief inflated at that size), enlarged into
    their images (state/images.enlarged) and the group's shadows drafted from its layers
    made as small (bake/layers.GroupDraft), in the lit copy's framing (a stroke past the
    drawing's bounds shows as far as they reach: the full redraw frames the lit copy anew).
    Nothing is packed and the lit copy's record is left as it was: refresh_lit_drawing
    draws them at full size once the strokes stop. beside (a UI: issue 61): what Blender
    holds is read now, the draft made in a worker thread and written by finish_drafts (a
    stroke meanwhile is drafted after it). → whether it drew, or started to (False: nothing
    new, or other layers or frames, or a layer that moves: those wait for the full
    redraw)."""
    if parent.name in _REFRAMES:                # (being framed anew: its redraw follows)
        return False
    running = _DRAFTS.get(parent.name)
    if beside and running is not None:          # one at a time: this stroke's comes next
        running.again = True
        return True
    found = _source(parent)
    if found is None:
        return False
    obj, settings, source = found
    digests, changed = _changed(obj, _DRAFTED.get(parent.name, source.get("layers", {})))
    mats = _layer_materials(obj, parent, source, settings, bounds=False)
    if not changed or mats is None:
        return False
    job = _Draft(context, parent, obj, settings, source, mats, digests, changed)
    if not beside:
        job.run()
        return job.write(context)
    _DRAFTS[parent.name] = job
    job.thread = threading.Thread(target=job.run_reporting, daemon=True)
    job.thread.start()
    if not bpy.app.timers.is_registered(finish_drafts):
        bpy.app.timers.register(finish_drafts, first_interval=POLL_S)
    return True


_DRAFTS = {}           # lit copy's name → its _Draft under way beside the UI


class _Draft:
    """A stroke's draft (draft_lit_drawing): read on the main thread here, made by run()
    (numpy: any thread), written by write() on the main thread."""

    def __init__(self, context, parent, obj, settings, source, mats, digests, changed):
        self.parent_name, self.digests, self.recorded = parent.name, digests, \
            source.get("layers", {})
        self.small = _draft_settings(settings)
        self.draw = read_images(context.scene, obj, self.small, only=changed,
                                samples=DRAFT_SAMPLES, bounds=source["bounds"])[0]
        self.moving = _moving(mats)
        self.names = {stem: m.name for stem, m in mats.items()}
        self.shown = {(stem, c): (img.name, img.as_pointer(), tuple(img.size), img.is_float)
                      for stem, m in mats.items() for c, img in
                      channel_images(m.dynamic_painting).items() if img is not None}
        drawn = {layer_stem(i, group) for i, group in
                 enumerate(drawn_layers(obj, settings["merge"])[0])
                 if changed & {layer.name for layer in group}}
        self.group = GroupDraft(parent, {mats[stem].name for stem in drawn if stem in mats})
        self.made = self.bigs = self.error = self.thread = None
        self.again = False

    def run(self):
        # drawn as it was made (not a layer that moves, nor one that stopped: the full
        # redraw makes those anew)
        self.made = _in_place(self.moving, made_paintings(self.draw(), self.small)[0])
        if self.made is None:
            return
        self.bigs = {}
        for stem, imgs in self.made:
            for c, data in imgs.items():
                name, pointer, size, is_float = self.shown.get((stem, c), (None,) * 4)
                if name is not None and is_float == (data.bits == 32):
                    self.bigs[(stem, c)] = enlarged(name, pointer, size, image_rgba(data))
        self.group.run({self.names[stem]: imgs for stem, imgs in self.made})

    def run_reporting(self):
        try:
            self.run()
        except Exception as exc:        # (said on the main thread: finish_drafts)
            self.error = exc

    def write(self, context):
        """The draft written where the lit copy still shows what it showed when read (a full
        redraw written since is newer) → whether it wrote."""
        parent = bpy.data.objects.get(self.parent_name)
        if self.made is None or parent is None or self.parent_name in _REFRAMES or \
                json.loads(parent[SOURCE]).get("layers", {}) != self.recorded:
            return False
        written = []
        for (stem, c), big in self.bigs.items():
            name, pointer = self.shown[(stem, c)][:2]
            img = bpy.data.images.get(name)
            if big is not None and img is not None and img.as_pointer() == pointer:
                img.pixels.foreach_set(big.ravel())
                written.append(name)
        _DRAFTED[self.parent_name] = self.digests
        note_edited(written)
        self.group.write()
        for stem, imgs in self.made:    # their derived images from the small ones; the
            mat = bpy.data.materials.get(self.names[stem])       # shadows the draft's
            if mat is not None:
                update(mat, context.scene, bake="none", small=imgs)
        return True


def finish_drafts():
    """Timer: the drafts made beside the UI written (_Draft.write); where a stroke came
    meanwhile, its draft started. → seconds to the next call (None: none left)."""
    for name, job in list(_DRAFTS.items()):
        if job.thread.is_alive():
            continue
        del _DRAFTS[name]
        parent = bpy.data.objects.get(name)
        try:
            if job.error is not None:
                raise job.error
            job.write(bpy.context)
            if job.again and parent is not None:
                with redrawing(name):
                    draft_lit_drawing(bpy.context, parent, beside=True)
        except Exception as exc:        # never into Blender's timer loop
            report(name, exc)
    return POLL_S if _DRAFTS else None
