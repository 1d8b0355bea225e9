"""Keep a painting current: compare what its images, bakes and tree were made from with what
they would be made from now, and redo only what differs.

Nothing here lists which parameter affects what: the derived images carry keys built from the
parameters whose `derives` role names them, the cos-θ images keys from the `bake` parameters
and the light's place, and the tree the Features it was built for (params.py roles,
nodegraph/features.py). A setting change, a light move, an image swap, undo: each calls
`update`, which compares all three (cheap when nothing changed).
"""
from contextlib import contextmanager

import bpy

from ...core.bake import QUALITY, quality_level
from ..bake.layers import bake_group, bake_group_live, layer_parent
from ..bake.live_bake import LIVE, rendering
from ..bake.shadow_images import bake_shadows, forget_cached_shape, stale_lights
from ..state.frames import forget_frames
from ..state.images import prepare_channel_image, update_derived_images
from ..state.painted import LIVE_RELIEFS, update_painted_shape
from ..state.painting_state import read_state
from ..state.status import clear_errors, report
from .tree import rebuild_tree, sync_light_items

_suspended = [0]


@contextmanager
def batch():
    """Write many settings without updating after each one; update once after."""
    _suspended[0] += 1
    try:
        yield
    finally:
        _suspended[0] -= 1


def on_setting_changed(mat, path):
    """Property update callback (properties.py): a setting, an image slot or the light
    collection changed. Never raises into Blender's UI: problems are reported."""
    s = mat.dynamic_painting
    if path.startswith(("images.", "frames")):
        forget_frames(mat)          # what moves and how: read again when next asked (§16)
    if _suspended[0] or not s.is_painting:
        return
    try:
        if path in QUALITY_LINKED:
            sync_quality(s.shadows, path)
        rebake = False
        if path.startswith("images."):      # a slot filled from the panel or by Python
            channel = path.split(".", 1)[1]
            img = getattr(s, f"image_{channel}")
            if img is not None:
                prepare_channel_image(img, channel)
            if channel == "shape":      # its pixels may be new under an old name
                forget_cached_shape(mat)
                rebake = True
        update(mat, bpy.context.scene, bake="live", rebake=rebake)
    except Exception as exc:     # never let a callback raise into Blender's UI
        report(mat, exc)


# A quality level writes its K and resolution into the settings (so the OSL shader's drivers
# see them too); editing K or the resolution by hand makes the level 'custom'.
QUALITY_LINKED = ("shadows.quality", "shadows.steps", "shadows.resolution")


def sync_quality(sh, path):
    with batch():
        if path == "shadows.quality" and sh.quality in QUALITY:
            sh.steps = QUALITY[sh.quality]["steps"]
            sh.resolution = QUALITY[sh.quality]["scale"]
        elif quality_level(sh.quality, sh.steps, sh.resolution) != sh.quality:
            sh.quality = "custom"        # K or the resolution edited by hand


def update(mat, scene=None, depsgraph=None, progress=None, bake="now", rebake=False,
           force=False, small=None):
    """Bring the painting up to date: derived images, cos-θ images, then the tree. → warnings

    bake: when a cos-θ image that is out of date is baked — 'now'; 'live' (someone is
    interacting: in the live-bake worker, preview then final, when no render runs and every
    light has an image to show meanwhile, else now); 'missing' (only lights without an image
    now: a light moved in a script or a render waits for the per-frame bake); 'none' (left
    as they are: a draft wrote them, bake/layers.draft_group).
    A painted shape's relief to make again is made in a worker where bake is 'live' (the
    painting brought up to date by a timer when it is ready: state/painted.LiveReliefs).
    rebake: bake every light again (the shape's pixels may have changed); force: remake
    every derived image and rebuild the tree as well; small: a draft's images drawn small
    (update_derived_images').
    """
    scene = scene or bpy.context.scene
    live = bake == "live" and not rendering()
    update_painted_shape(mat, live)         # a painted shape first: it is the shape image
    if live and LIVE_RELIEFS.busy() and not bpy.app.timers.is_registered(_reliefs_made):
        bpy.app.timers.register(_reliefs_made, first_interval=RELIEF_POLL_S)
    state = read_state(mat, scene)          # the settings, read once for the whole update
    warnings = update_derived_images(mat, state, force=force, small=small)
    sync_light_items(mat.dynamic_painting, state.lights)
    if state.params.shadows.enabled and bake != "none":
        _bake(mat, scene, depsgraph, progress, bake, rebake or force, state.params, state.read)
    rebuild_tree(mat, scene, force=force, state=state)
    clear_errors(mat)
    return warnings


RELIEF_POLL_S = 0.02


def _reliefs_made():
    """Timer: the paintings whose figure relief the worker made (state/painted.LiveReliefs)
    brought up to date → seconds to the next look (None: no relief is being made)."""
    for name, exc in LIVE_RELIEFS.finished():
        mat = bpy.data.materials.get(name)
        if mat is None:
            continue
        try:
            if exc is not None:
                raise exc
            update(mat, bpy.context.scene, bake="live")
        except Exception as error:         # never into Blender's timers
            report(mat, error)
    return RELIEF_POLL_S if LIVE_RELIEFS.busy() else None


def _bake(mat, scene, depsgraph, progress, when, everything, p, read):
    parent = layer_parent(mat)
    if parent is not None:            # a layer: the whole group bakes at once (§15)
        if when == "live" and not rendering() and not everything:
            bake_group_live(parent, depsgraph)
        else:
            bake_group(parent, depsgraph, force=everything)
        return
    s = mat.dynamic_painting
    stale = everything or stale_lights(mat, depsgraph, p)
    if not stale:
        return
    all_have_images = all(i.shadow is not None for i in s.lights)
    if when == "missing" and all_have_images and not everything:
        return
    if when == "live" and all_have_images and not everything and not rendering():
        LIVE.ensure(mat, scene, depsgraph, p)
        return
    s.shadows_stale = True         # until the bake succeeds (the panel says so)
    bake_shadows(mat, scene, depsgraph, force=everything, progress=progress, p=p, read=read)


def invalidate_generated(mat):
    """Mark every image numpy made for the painting as out of date (a reopened .blend keeps the
    images but not their pixels), so the next update remakes them all."""
    s = mat.dynamic_painting
    for item in s.derived:
        item.key = ""
    s.painted.key = ""           # a painted shape too: undo restores its layers' pixels
    for item in s.lights:
        item.bake_key = ""
