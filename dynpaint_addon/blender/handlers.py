"""Application handlers: keep paintings current when lights change and bake per frame.

- depsgraph_update_post: a light linked or unlinked (added, deleted, moved between
  collections, Sun ↔ Point) rebuilds that painting's tree, so its drivers never point at a
  deleted light; an input image's pixels edited (an Image update: state/edits.py) remakes
  what is made from them; a Grease Pencil drawing changed redraws its lit copies.
- frame_change_post: with cos-θ shadows on, each frame bakes for the lights where that frame
  puts them (read from the evaluated depsgraph, blender-notes.md), in renders as in playback;
  a painting that moves (§16) first shows the frame's drawing (sync.update: its frame copies
  and derived images, then the bake, whose key holds the shape's frame).
- undo_post, redo_post: the same remaking after undo and redo, so the images match the
  settings and light positions undo brought back.
- render_pre: a painting that lost an optional image (deleted) is rebuilt without it; deleted
  planes or images and missing files are reported (one line each), never raised.
- save_pre: a painted shape's layers (Paint Shape) and a lit drawing's images a redraw wrote are
  packed again where they changed.
- load_post: a saved .blend keeps the node tree, drivers and settings but not the pixels of the
  images numpy made (derived copies, shadow bakes: generated images): they are remade when
  the file opens, so a reopened file renders the same pixels as before it was saved.

Each of them calls sync.update, which redoes only what changed; the first two do nothing
while an operator only reads the lights frame by frame (frame_sampling.py). A handler never
raises into Blender: failures are reported (status.py) and the painting keeps its last good
images (shadow_images.bake_shadows writes only after a complete bake).
"""
import functools
import time

import bpy
from bpy.app.handlers import persistent

from ..core.laplace import forget_solved_parts
from .bake.layers import bake_painting, forget_scenes
from .bake.live_bake import DEBOUNCE_S, rendering
from .bake.shadow_images import forget_cached_shapes
from .material.sync import invalidate_generated, update
from .material.tree import rebuild_tree, tree_is_stale
from .scenes.grease_pencil.lit_copy import drawing_of, stale_lit_copies
from .scenes.grease_pencil.live import (draft_lit_drawing, forget_drafts, frame_all_now,
                                         redrawing, redrawing_now, refresh_lit_drawing)
from .state.edits import artists_edits, forget_resized, note_edited
from .state.frame_sampling import only_reading_lights
from .state.frames import forget_frames, moves
from .state.images import PACK_ON_SAVE, forget_enlarged, forget_frames_made
from .state.lights import concerns, touched_by
from .state.painted import forget_painted, painted_layers, watched_images
from .state.settings import channel_images
from .state.status import problems, report


def paintings(scene):
    """Materials of Dynamic Paintings whose plane is in `scene` (cheap when there are none:
    handlers run on every update)."""
    found = [m for m in bpy.data.materials if m.dynamic_painting.is_painting]
    if not found:
        return []
    in_scene = set(scene.objects)
    return [m for m in found if m.dynamic_painting.plane in in_scene]


WATCHED = (bpy.types.Object, bpy.types.Light, bpy.types.Collection, bpy.types.Scene)


@persistent
def on_depsgraph_update(scene, depsgraph):
    """A light added, deleted, moved or relinked, the plane moved, an input image's pixels
    edited (state/edits.py): bring paintings up to date (a moving light or an edit bakes
    live: preview now, final once it stops; without a UI an edit bakes now, so a script sees
    at once what Rebuild Material would make)."""
    if only_reading_lights():
        return
    redraw_lit_drawings(scene, depsgraph)
    images = artists_edits({getattr(u.id, "original", u.id).name for u in depsgraph.updates
                            if isinstance(u.id, bpy.types.Image)})
    watched = any(isinstance(u.id, WATCHED) for u in depsgraph.updates)
    if not images and not watched:
        return
    # each painting's input images among them (the images numpy makes are the add-on's own)
    mine = {mat: images & {img.name for img in (*channel_images(mat.dynamic_painting).values(),
                                                 *watched_images(mat.dynamic_painting).values())}
            for mat in paintings(scene)}
    edited = set().union(*mine.values())
    if not edited and not watched:
        return
    note_edited(edited)
    touched = touched_by(depsgraph) if watched else set()
    for mat, its_edits in mine.items():
        if not its_edits and not concerns(mat, scene, touched):
            continue            # (another painting's lights or plane)
        when = ("now" if its_edits else "missing") if rendering() else "live"
        try:
            update(mat, scene, depsgraph, bake=when)
        except Exception as exc:     # never into Blender's update loop
            report(mat, exc)


def redraw_lit_drawings(scene, depsgraph):
    """A Grease Pencil drawing changed (a stroke, a keyframe, a material): redraw the lit
    copies made from it (scenes/grease_pencil/live.refresh_lit_drawing: the layers that changed)
    — at once without a UI (the headless contract); with one, a draft at once
    (draft_lit_drawing: drawn small, in a worker thread) and the full redraw once no stroke
    has come for STROKES_QUIET_S."""
    if redrawing_now():             # (a lit copy's own renders of its drawing)
        return
    names = set()
    for u in depsgraph.updates:
        what = getattr(u.id, "original", u.id)
        if isinstance(what, bpy.types.GreasePencil):
            names |= {o.name for o in scene.objects if o.data == what}
        elif isinstance(what, bpy.types.Object) and what.type == "GREASEPENCIL":
            names.add(what.name)
    if not names:
        return
    stale = stale_lit_copies(scene, names)
    if not stale:
        return
    if not rendering():
        now = time.perf_counter()
        for parent in stale:       # a draft of each stroke now, the full drawing once they stop
            if _redraw(parent, functools.partial(draft_lit_drawing, beside=True)):
                _PENDING[parent.name] = now
            else:                  # (nothing new since the last draft, or no draft possible)
                _PENDING.setdefault(parent.name, now)
        if not bpy.app.timers.is_registered(_redraw_pending):
            bpy.app.timers.register(_redraw_pending, first_interval=STROKES_QUIET_S)
        return
    for parent in stale:
        _redraw(parent)


# The full redraw waits for a pause in the strokes longer than a dragged light's (DEBOUNCE_S):
# a drawing's strokes come with short lifts of the pen between them, and the full redraw
# holds Blender while it draws every changed layer at full size (seconds at 1024² without a
# GPU: docs/grease-pencil-cost.md; the paintings are then made in a worker thread,
# grease_pencil._Redraw); the draft shows each stroke meanwhile.
STROKES_QUIET_S = max(DEBOUNCE_S, 1.0)
_PENDING = {}       # lit copy's name → when its last stroke was drafted


def _redraw_pending():
    """Timer: the full redraw of the lit copies whose strokes have paused → seconds until the
    next is due (None: none left)."""
    scene, now = bpy.context.scene, time.perf_counter()
    for name, since in list(_PENDING.items()):
        if now - since < STROKES_QUIET_S:
            continue
        del _PENDING[name]
        parent = bpy.data.objects.get(name)
        if parent is not None and parent in stale_lit_copies(scene, {drawing_of(parent)}):
            _redraw(parent)
    if not _PENDING:
        return None
    return max(0.05, STROKES_QUIET_S - (time.perf_counter() - max(_PENDING.values())))


def _redraw(parent, how=refresh_lit_drawing):
    """how(context, parent) of a lit copy, its errors reported → what it returned (None when
    it failed)."""
    try:
        with redrawing(parent.name):
            return how(bpy.context, parent)
    except Exception as exc:        # never into Blender's update loop
        report(parent.name, exc)


@persistent
def on_frame_change(scene, depsgraph):
    """Each frame's lights where that frame puts them: baked here in renders (the render waits
    for its own light positions), live during playback."""
    if only_reading_lights():
        return
    for mat in paintings(scene):
        sh = mat.dynamic_painting.shadows
        try:
            if moves(mat):       # §16: the frame's drawing (its copies, its bake) first
                update(mat, scene, depsgraph, bake="now" if rendering() else "live")
                continue
            if not sh.enabled or (sh.source == "osl" and scene.render.engine == "CYCLES"
                                  and rendering()):
                continue         # Cycles marches in its OSL shader: nothing to bake per frame
            if rendering():
                bake_painting(mat, scene, depsgraph, force=False)
            else:
                update(mat, scene, depsgraph, bake="live")
        except Exception as exc:     # never into the render loop; the last bake stays
            report(mat, exc)


@persistent
def on_render_pre(scene, *_):
    """Before a render: a lit drawing being framed anew is framed whole (its shadows baked);
    a painting whose optional image was deleted is rebuilt without it; anything that cannot
    be mended is reported, once per render, and never raised."""
    try:
        frame_all_now(bpy.context)
    except Exception as exc:
        report(scene.name, exc)
    for mat in paintings(scene):
        try:
            if tree_is_stale(mat) and mat.dynamic_painting.image_shape is not None:
                update(mat, scene)
                rebuild_tree(mat, scene, force=True)
            for problem in problems(mat):
                report(mat, problem)
        except Exception as exc:
            report(mat, exc)


def scene_of(mat):
    """The scene a painting is in: the window's scene if its plane is there, else the first."""
    plane = mat.dynamic_painting.plane
    context_scene = getattr(bpy.context, "scene", None)
    if context_scene is not None and plane in set(context_scene.objects):
        return context_scene
    return next((sc for sc in bpy.data.scenes if plane in set(sc.objects)), None)


@persistent
def remake_generated_images(*_):
    """After a file opens, or undo/redo: a .blend keeps no pixels of the images numpy made, and
    undo restores settings, lights and bake keys but not necessarily those pixels. Remake them
    so the painting matches what is loaded."""
    forget_cached_shapes()
    forget_frames()
    forget_frames_made()
    forget_enlarged()
    forget_drafts()
    forget_resized()
    forget_solved_parts()
    forget_painted()
    forget_scenes()
    paintings_ = [m for m in bpy.data.materials if m.dynamic_painting.is_painting]
    if paintings_ and getattr(bpy.context, "view_layer", None) is not None:
        bpy.context.view_layer.update()     # after undo, world matrices are not evaluated yet
    for mat in paintings_:
        try:
            scene = scene_of(mat)
            if scene is None:
                continue        # a painting whose plane is in no scene: nothing to show
            invalidate_generated(mat)
            update(mat, scene)
        except Exception as exc:     # a broken painting must not stop the file from opening
            report(mat, exc)


@persistent
def pack_edited_images(*_):
    """Before a save: the packed images written since they were packed are packed again —
    the layers of painted shapes that strokes changed, and a lit drawing's images that a
    redraw wrote without packing (a 1024² image takes 75–260 ms to pack: not while the
    artist draws) — a packed image saves the pixels it was packed with: the strokes would
    be lost; and the images a lit drawing made anew beside the UI left unpacked."""
    for mat in bpy.data.materials:
        s = mat.dynamic_painting
        for img in {*painted_layers(s), *channel_images(s).values()}:
            try:
                if img.packed_file is None and img.get(PACK_ON_SAVE):
                    img.pack()                       # (made unpacked: packed_image)
                    del img[PACK_ON_SAVE]
                elif img.packed_file is not None and img.is_dirty:
                    img.pack()
            except RuntimeError as exc:          # never stop a save
                report(mat, f"could not pack {img.name}: {exc}")


HANDLERS = ((bpy.app.handlers.depsgraph_update_post, on_depsgraph_update),
            (bpy.app.handlers.save_pre, pack_edited_images),
            (bpy.app.handlers.frame_change_post, on_frame_change),
            (bpy.app.handlers.load_post, remake_generated_images),
            (bpy.app.handlers.render_pre, on_render_pre),
            (bpy.app.handlers.undo_post, remake_generated_images),
            (bpy.app.handlers.redo_post, remake_generated_images))


def _same(a, b):
    """Same handler, even from a reloaded copy of this module (add-on disabled and enabled)."""
    return getattr(a, "__name__", None) == b.__name__ and \
        getattr(a, "__module__", None) == b.__module__


def register():
    unregister()
    for handlers, fn in HANDLERS:
        handlers.append(fn)


def unregister():
    for handlers, fn in HANDLERS:
        for h in [h for h in handlers if _same(h, fn)]:
            handlers.remove(h)
