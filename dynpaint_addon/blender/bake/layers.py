"""Layered paintings in Blender (pipeline.md §15, issue 30): one plane per layer under one
parent Empty, each with today's material; the shadows of the layers in front baked into each
layer's shadow images.

The scene the core lights (core.layers.Scene) is read off the planes themselves: the canvas
is the back layer's painting frame (its plane's object space, §0: image widths), and each
layer's depth, offset and scale are where its plane lies in that frame — so moving a plane,
or its Depth, moves its shadows, and the parallax scaling of Add › Layered… is in the
geometry the bake sees. The lights are read in the same frame. A bake of the group writes
every layer's cos-θ images at once; each image keeps the key of the whole group (every
plane's place, every layer's bake settings, the light), so a change anywhere rebakes all.

While a light is dragged the group bakes at draft quality at once and at its own quality
once the light has been still for DEBOUNCE_S, like the live bake of one painting: the final
bake runs in a worker thread on the scene read on the main thread (it takes seconds at
1024²), and a timer writes it when done — or drops it where the group changed meanwhile.
"""
import threading
import time

import numpy as np

import bpy

from ...core.input_rules import ImageData
from ...core.layers import Layer, Scene
from ...core.sampling import resample_separable
from ...inputs.painting_frames import BoundedCache
from ...nodegraph.derived_inputs import grey_rgba
from ..state.edits import versions
from ..state.frames import frame_data, moves, shown_frame
from ..state.lights import painting_frame_light, plane_matrix
from ..state.images import enlarged, shows_enlarged, write_enlarged
from ..state.settings import channel_images, settings_to_params
from .live_bake import DEBOUNCE_S
from .shadow_images import (KEPT_BAKES_MB, bake_shadows, light_key, settings_key,
                            shadow_image_name, write_shadow)

LAYERED = "dynamic_painting_layered"     # custom property that marks a layered scene's parent
LAYER_CHANNELS = ("shape", "dark", "bright", "transparency")   # what T and t_own read


def layer_parent(mat):
    """The parent Empty of a layered scene the painting belongs to, or None."""
    plane = mat.dynamic_painting.plane
    parent = plane.parent if plane is not None else None
    return parent if parent is not None and parent.get(LAYERED) else None


def group_materials(parent):
    """The paintings of a layered scene whose planes are shown in renders, back to front by
    their depth under the parent (equal depths: by name)."""
    mats = []
    for child in parent.children:
        mat = child.active_material
        if mat is not None and mat.dynamic_painting.is_painting and not child.hide_render:
            mats.append(mat)
    return sorted(mats, key=lambda m: (_relative(parent, m.dynamic_painting.plane)[2, 3],
                                       m.dynamic_painting.plane.name))


def _relative(frame, obj, depsgraph=None):
    """`obj`'s matrix in `frame`'s object space (evaluated when a depsgraph is given)."""
    ev = (lambda o: o.evaluated_get(depsgraph)) if depsgraph is not None else (lambda o: o)
    return np.linalg.inv(np.array(ev(frame).matrix_world)) @ np.array(ev(obj).matrix_world)


def _placement(back, plane, depsgraph=None):
    """(depth, offset, scale) of a plane in the back plane's painting frame (§15, image widths
    of the back layer), from the two planes' world matrices (planes face the same way)."""
    rel = _relative(back, plane, depsgraph)
    scale = float(np.linalg.norm(rel[:3, 0]))
    return float(rel[2, 3]), (float(rel[0, 3]), float(rel[1, 3])), scale


def group_key(mats, depsgraph=None):
    """What every layer's bake depends on besides its light: the planes' places, each layer's
    bake settings and shape image, its thickness, the edits of the images T reads and, of a
    layer that moves (§16), the frames they show."""
    back = mats[0].dynamic_painting.plane
    parts = []
    for mat in mats:
        s = mat.dynamic_painting
        depth, offset, scale = _placement(back, s.plane, depsgraph)
        parts.append((mat.name, round(depth, 7), tuple(np.round(offset, 7)), round(scale, 7),
                      round(s.layer_thickness, 7), settings_key(settings_to_params(s), s),
                      versions({c: img for c, img in channel_images(s).items()
                                if c in LAYER_CHANNELS}),
                      tuple(shown_frame(mat, c) for c in LAYER_CHANNELS)))
    return repr(parts)


_SCENES = {}     # parent name → (key without lights, core Scene, layer_keys): a drag keeps it


def layer_keys(mats):
    """Per layer, what its prepared inputs (§2) depend on: its parameters, the edits of the
    images the core reads and the frames they show (not its place)."""
    return [repr((m.name, repr(settings_to_params(m.dynamic_painting)),
                  versions({c: img for c, img in channel_images(m.dynamic_painting).items()
                            if c in LAYER_CHANNELS}),
                  tuple(shown_frame(m, c) for c in LAYER_CHANNELS))) for m in mats]


def core_scene(parent, mats, depsgraph=None, key=None, later=False, images=None):
    """The core Scene of a layered group, made once per group key (its layers' inputs read
    from Blender and prepared once: a moving light reuses them; a layer whose own inputs did
    not change keeps its prepared ones when another is edited, layer_keys); key: group_key's,
    when the caller has it; later: → a function that makes it (numpy alone: a worker
    thread prepares the changed layers, issue 61 — 0.1 s at 1024² on Blender's main
    thread), its inputs read now; images: {material name: {channel: ImageData}} just
    written into the group's images (draft_group_beside): read from these, not from
    Blender, for a scene made once and not kept."""
    if images is not None:     # (a layer they do not cover whole is read from Blender)
        kept = {}
        for mat in mats:
            given = images.get(mat.name, {})
            if {c for c in channel_images(mat.dynamic_painting) if c in LAYER_CHANNELS} \
                    <= set(given):
                kept[mat.name] = {c: img for c, img in given.items() if c in LAYER_CHANNELS}
        layers = _shadowed(group_layers(mats, depsgraph, LAYER_CHANNELS, kept=kept))
        return (lambda: Scene(layers)) if later else Scene(layers)
    key = key or group_key(mats, depsgraph)
    hit = _SCENES.get(parent.name)
    if hit is not None and hit[0] == key:
        return (lambda: hit[1]) if later else hit[1]
    keys = layer_keys(mats)
    before = {} if hit is None else {k: i for i, k in enumerate(hit[2])}
    kept = {i: before[k] for i, k in enumerate(keys) if k in before}
    layers = _shadowed(group_layers(
        mats, depsgraph, LAYER_CHANNELS,
        kept={mats[i].name: hit[1].layers[j].images for i, j in kept.items()}))
    prepared, name = {i: hit[1].ready[j] for i, j in kept.items()}, parent.name
    before = None if hit is None else hit[1]

    def made():          # (an edit's bakes patch the scene's before it: core/layer_edits.py)
        scene = Scene(layers, prepared=prepared, before=before)
        _SCENES[name] = (key, scene, keys)
        return scene
    return made if later else made()


def _shadowed(layers):
    """The group's layers as its bake reads them: each casting and receiving shadows."""
    for layer in layers:
        layer.p.shadows.enabled = True
    return layers


def group_layers(mats, depsgraph=None, channels=None, f=None, kept=None):
    """The paintings of a group (group_materials) as the core's layers (§15): their images
    (only `channels` when given) at scene frame `f` (default: now), parameters, and places
    in the back layer's frame; kept: {material name: images} already read (not read again;
    None: filled in later, warm_drafts)."""
    back = mats[0].dynamic_painting.plane
    layers = []
    for mat in mats:
        s = mat.dynamic_painting
        depth, offset, scale = _placement(back, s.plane, depsgraph)
        images = kept[mat.name] if kept is not None and mat.name in kept else \
            {c: frame_data(mat, c, f) for c in channel_images(s)     # (§16: the frame's)
             if channels is None or c in channels}
        layers.append(Layer(images, settings_to_params(s), mat.name, depth,
                            s.layer_thickness or None, offset, scale))
    return layers


def forget_group(name):
    """The group under parent `name` is gone (a lit copy made anew under the same name): its
    cached scene, kept bakes and drafts go with it."""
    _SCENES.pop(name, None)
    _SMALL.pop(name, None)
    _WARM.pop(name, None)
    _KEPT.pop(name, None)
    _BESIDE.pop(name, None)


def forget_scenes():
    """Another file is open, or undo: the cached scenes may show other planes."""
    _SCENES.clear()
    _SMALL.clear()
    _WARM.clear()
    _KEPT.clear()
    _BESIDE.clear()
    _FINAL_DUE.clear()
    _RUNNING.clear()              # (a running bake's results are dropped: its group is gone)


def bake_group(parent, depsgraph=None, quality=None, force=False):
    """Bake every layer's cos-θ images (t = t_own·T, §15) for its linked lights, at the
    layers' own quality or `quality` for all; skipped when every image already has this
    bake's key (unless `force`). → milliseconds taken (0: nothing to do)."""
    job = _group_job(parent, depsgraph, quality, force)
    if job is None:
        return 0.0
    start = time.perf_counter()
    job.run()
    job.write()
    return (time.perf_counter() - start) * 1000


class _GroupBake:
    """One bake of a group: what it bakes read from Blender (the group's key, its lights, the
    core Scene's inputs: main thread), the Scene made and baked by run() (numpy only: any
    thread), written by write() (main thread) where the group is still as it was read."""

    def __init__(self, parent, mats, group, quality, todo, scene, kept=None):
        self.parent_name, self.names = parent.name, [m.name for m in mats]
        self.group, self.quality, self.todo, self.scene = group, quality, todo, scene
        self.key = group + f"|{quality or 'own'}"
        self.kept = kept or {}      # light name → [t per layer] baked before for this key
        self.results, self.error, self.thread = None, None, None

    def run(self):
        if callable(self.scene):          # (core_scene's, made here: later)
            self.scene = self.scene()
        # (a reduced level's t at its own size: the images enlarge it as they are sampled)
        self.results = {name: self.kept[name] if name in self.kept else
                        self.scene.bake(light, self.quality, own_size=True)
                        for name, light in self.todo.items()}

    def _run_reporting(self):
        try:
            self.run()
        except Exception as exc:          # (said on the main thread, by write)
            self.error = exc

    def start(self):
        """run() in a worker thread (a UI stays free while a final bake takes seconds)."""
        self.thread = threading.Thread(target=self._run_reporting, daemon=True)
        self.thread.start()

    def done(self):
        return self.thread is None or not self.thread.is_alive()

    def write(self):
        """Write the results into each layer's cos-θ images — all or none. A bake that ran in
        a worker is dropped where the group changed meanwhile (its layers, places, images or
        settings, or a light it baked): a newer bake is due, or done. (One run in place is
        written as read: it may have read the evaluated scene of a render, which the
        original objects checked here need not show.) → whether it wrote."""
        if self.error is not None:
            raise self.error
        parent = bpy.data.objects.get(self.parent_name)
        mats = group_materials(parent) if parent is not None else []
        if [m.name for m in mats] != self.names or \
                self.thread is not None and not self._still_current(mats):
            return False
        _write_shadows(mats, self.results, lambda name: _key(self.key, self.todo[name]))
        if any(moves(m) for m in mats):        # a loop that comes round shows them again
            kept = _KEPT.setdefault(self.parent_name, BoundedCache(KEPT_BAKES_MB))
            for name, ts in self.results.items():
                kept.put(_key(self.key, self.todo[name]), ts, sum(t.nbytes for t in ts))
        return True

    def _still_current(self, mats):
        if group_key(mats) != self.group:
            return False
        lights = group_lights(mats)
        return all(name in lights and _key(self.key, lights[name]) == _key(self.key, light)
                   for name, light in self.todo.items())


def _write_shadows(mats, results, key_of):
    """Each layer's cos-θ images of the lights in `results` ({light name: [t per layer]}),
    keyed key_of(light name) (write_shadow); the layers' shadows then current."""
    for i, mat in enumerate(mats):
        for item in mat.dynamic_painting.lights:
            if item.object is not None and item.object.name in results:
                write_shadow(mat, item, results[item.object.name][i],
                             key_of(item.object.name))
        mat.dynamic_painting.shadows_stale = False


def _group_job(parent, depsgraph=None, quality=None, force=False, images=None):
    """A _GroupBake of what is out of date in the group (its images' keys against this bake's;
    all with `force`), or None where nothing is; images: core_scene's."""
    mats = group_materials(parent)
    if not mats:
        return None
    group = group_key(mats, depsgraph)
    key = group + f"|{quality or 'own'}"
    # (a draft is not made where the group's bake at its own quality shows: it is finer —
    # an update that changes no bake input drafted it again on the main thread, 87 ms at
    # 1024², and then baked its final again)
    shown = {key} | ({group + "|own"} if quality == "draft" else set())
    lights = group_lights(mats, depsgraph)
    todo = {item.object.name: lights[item.object.name] for _, item in _linked(mats)
            if force or item.shadow is None or
            item.bake_key not in {_key(k, lights[item.object.name]) for k in shown}}
    if not todo:
        return None
    cache = _KEPT.get(parent.name)
    kept = {} if cache is None or force else \
        {name: ts for name, ts in ((n, cache.get(_key(key, light))) for n, light in todo.items())
         if ts is not None}
    # (a group whose every light's bake is kept reads no scene: a frame come round again)
    scene = None if len(kept) == len(todo) else core_scene(parent, mats, depsgraph, group,
                                                            later=True, images=images)
    return _GroupBake(parent, mats, group, quality, todo, scene, kept)


# parent name → BoundedCache: bake key → [t per layer], the bakes of a group that moves (§16):
# a looping animation played under still lights shows each frame's shadows again without
# baking them, as a moving painting's (shadow_images._BAKES), within KEPT_BAKES_MB a group
_KEPT = {}


def _linked(mats):
    """(material, light item) of each light linked to a layer of the group."""
    return [(mat, item) for mat in mats for item in mat.dynamic_painting.lights
            if item.object is not None]


def group_lights(mats, depsgraph=None):
    """{light object name: core Light in the back layer's frame} of the group's lights."""
    back = plane_matrix(mats[0], depsgraph)
    lights = {}
    for _, item in _linked(mats):
        if item.object.name not in lights:
            lights[item.object.name] = painting_frame_light(item.object, back, depsgraph)
    return lights


DRAFTED = "draft"      # the bake key of cos-θ images a draft wrote: the next bake redoes them
_SMALL = {}            # parent name → {layer_keys' key: (its images made small, prepared,
                       # {light name: its Scene.own entry})} (draft_group)


def draft_group(parent, drawn, depsgraph=None):
    """A draft of a group's shadows (§15) from layers drawn small (issue 42: a stroke on a
    drawing while strokes come): `drawn` {material name: the layer's images, f times
    smaller than its images}; the other layers' images made as small (bilinear, kept by
    layer_keys: a stroke reads them once), the small scene baked at draft quality as the
    full-size one would be (Scene.bake's `reduced`) and each t enlarged into its cos-θ
    images (where it changed), keyed DRAFTED so that the next bake_group bakes them at full
    size. A layer the strokes leave alone keeps its prepared inputs and own terms from the
    last draft. GroupDraft, here in one go. → milliseconds taken."""
    start = time.perf_counter()
    job = GroupDraft(parent, set(drawn), depsgraph)
    if not job.lights or not drawn:
        return 0.0
    job.run(drawn)
    job.write()
    return (time.perf_counter() - start) * 1000


class GroupDraft:
    """draft_group in three steps (issue 61: a stroke's draft beside the UI): made on the main
    thread (what it reads of Blender: the group, its lights, places and parameters, the
    images of the layers neither drawn nor kept), run(drawn) in any thread (numpy: the small
    scene baked, each t enlarged to its image's size), write() on the main thread, after
    the drawn layers' images are (their keys are the layers' then).
    drawn_names: the materials whose layers run() is given drawn small."""

    def __init__(self, parent, drawn_names, depsgraph=None):
        mats = group_materials(parent)
        self.parent_name, self.names = parent.name, [m.name for m in mats]
        self.lights = group_lights(mats, depsgraph) if mats else {}
        self.keys = layer_keys(mats)
        before = {**_SMALL.get(parent.name, {}), **_WARM.pop(parent.name, {})}
        self.kept = {i: before[key] for i, (mat, key) in enumerate(zip(mats, self.keys))
                     if key in before and mat.name not in drawn_names}
        self.read = {mat.name: {c: frame_data(mat, c) for c in channel_images(
            mat.dynamic_painting) if c in LAYER_CHANNELS} for i, mat in enumerate(mats)
            if mat.name not in drawn_names and i not in self.kept}
        self.layers = group_layers(mats, depsgraph, LAYER_CHANNELS,
                                   kept=dict.fromkeys(self.names))
        self.full = {m.name: tuple(m.dynamic_painting.image_shape.size) for m in mats}
        self.shown = {(i, name): shows_enlarged(shadow_image_name(mat, name),
                                                self.full[mat.name])
                      for i, mat in enumerate(mats) for name in self.lights}
        self.enlarged = self.small = None

    def run(self, drawn):
        """Bake the small scene (`drawn`: {material name: its images drawn small}); each
        light's t per layer enlarged where it changed (state/images.enlarged)."""
        name, small = next(iter(drawn.items()))
        f = _smaller(self.full[name], small)
        images = {}
        for i, mat_name in enumerate(self.names):
            images[mat_name] = drawn[mat_name] if mat_name in drawn else \
                self.kept[i][0] if i in self.kept else \
                {c: _made_small(img, f) for c, img in self.read[mat_name].items()}
        for layer, mat_name in zip(self.layers, self.names):
            layer.images = images[mat_name]
            layer.p.shadows.enabled = True
        scene = Scene(self.layers, prepared={i: entry[1] for i, entry in self.kept.items()})
        own, self.enlarged = {i: {} for i in range(len(self.names))}, {}
        for light, at in self.lights.items():
            ts = scene.bake(at, "draft", reduced=f[0],
                            own={i: entry[2][light] for i, entry in self.kept.items()
                                 if light in entry[2]})
            for i, entry in scene.own.items():
                own[i][light] = entry
            for i, t in enumerate(ts):
                self.enlarged[(i, light)] = enlarged(*self.shown[(i, light)],
                                                     grey_rgba(np.clip(t, 0, 1)))
        self.small = [(images[n], scene.ready[i], own[i]) for i, n in enumerate(self.names)]

    def write(self):
        """The drafted shadows written into the layers' cos-θ images (keyed DRAFTED) where
        the group is still the one read → whether it wrote."""
        parent = bpy.data.objects.get(self.parent_name)
        mats = group_materials(parent) if parent is not None else []
        if [m.name for m in mats] != self.names or self.enlarged is None:
            return False
        # kept by the layers' keys now: the drawn layers' images were written (their edits
        # noted) since this draft was read
        _SMALL[self.parent_name] = dict(zip(layer_keys(mats), self.small))
        for i, mat in enumerate(mats):
            for item in mat.dynamic_painting.lights:
                light = item.object.name if item.object is not None else None
                if (i, light) not in self.enlarged:
                    continue
                big = self.enlarged[(i, light)]
                if big is not None:               # (None: t did not change here)
                    image, _, size = self.shown[(i, light)]
                    item.shadow = write_enlarged(image, size, big)
                item.bake_key = DRAFTED
            mat.dynamic_painting.shadows_stale = False
        return True


def _smaller(full, small):
    """(fx, fy): how many times smaller than a layer's images (`full`: its shape image's
    size) are its `small` ones."""
    return full[0] / small["shape"].size[0], full[1] / small["shape"].size[1]


_WARM = {}             # parent name → {layer_keys' key: a _SMALL entry} warm_drafts made


def warm_drafts(parent, small, depsgraph=None):
    """Make ready, in a worker thread, what the group's first draft needs (issue 61: cold, a
    first stroke's draft held Blender 180 ms at 512²): a GroupDraft of every layer run on
    small(): {material name: its images}, called in the worker (a drawing drawn small) — its
    layers prepared and their own draft terms per light kept as draft_group keeps its own
    (_SMALL), which takes them where the layers are still as they were here, and the
    draft's t kept for refill_enlarged (state/images.enlarged) as if a draft had enlarged it
    into the cos-θ images (the first draft enlarges only where it differs). Places,
    parameters and lights are read now. → the thread, or None (no light)."""
    job = GroupDraft(parent, {m.name for m in group_materials(parent)}, depsgraph)
    if not job.lights:
        return None

    def run():
        try:
            job.run(small())
            _WARM[job.parent_name] = dict(zip(job.keys, job.small))
        except Exception as exc:         # (the first draft is made cold, as before)
            print(f"Dynamic Painting: drafts of {job.parent_name} not made ready: {exc}")
    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    WARMING[job.parent_name] = thread
    return thread


WARMING = {}           # parent name → its warm_drafts thread (the newest)


def _made_small(img, f):
    """ImageData f = (fx, fy) times smaller (bilinear at the new pixel centres): a layer of
    the drawn one's size becomes exactly its size."""
    w, h = img.size
    return ImageData(resample_separable(img.pixels, max(1, round(h / f[1])),
                                        max(1, round(w / f[0]))), img.bits, img.name)


def bake_painting(mat, scene, depsgraph=None, force=True, progress=None, p=None):
    """Bake a painting's cos-θ images: a layer's whole group (bake_group), any other painting
    its own lights (shadow_images.bake_shadows). → milliseconds taken."""
    parent = layer_parent(mat)
    if parent is not None:
        return bake_group(parent, depsgraph, force=force)
    return bake_shadows(mat, scene, depsgraph, force=force, progress=progress, p=p)


def _key(group, light):
    return f"{group}|{light_key(light)}|{light.size!r}"


_FINAL_DUE = {}    # parent name → when its lights were last moved (a final bake is due)


def bake_group_live(parent, depsgraph=None):
    """A light moved interactively: the group at draft quality now, its own quality once the
    light has been still for DEBOUNCE_S (in a worker thread: _final_bakes) — where images
    were just written from numpy arrays (draft_group_beside), the draft made from those in a
    worker, and not again here while it is made."""
    if _BESIDE.get(parent.name) is _HOLD:
        return 0.0
    images, running = _BESIDE.pop(parent.name, None), _RUNNING.get(parent.name)
    if images is not None and running is None:
        running = _group_job(parent, depsgraph, "draft", images=images)
        if running is not None:
            running.start()
            _RUNNING[parent.name] = running
        final_bake_due(parent)
    if running is not None and running.quality == "draft" and \
            running.group == group_key(group_materials(parent), depsgraph):
        return 0.0
    ms = bake_group(parent, depsgraph, quality="draft")
    if ms:
        final_bake_due(parent, DEBOUNCE_S)
    return ms


# parent name → {material name: {channel: ImageData}} just written into the group's images
# (draft_group_beside): its next live bake drafts from them in a worker; or _HOLD
_BESIDE = {}
_HOLD = "hold"


def hold_group(parent):
    """The group's live and final bakes wait (bake_group_live, _final_bakes) until
    draft_group_beside or forget_group: its layers are being framed anew a slice at a time
    (scenes/grease_pencil/reframing.py), and a bake of them half framed is thrown away."""
    _BESIDE[parent.name] = _HOLD


def draft_group_beside(parent, images):
    """The group's images were just written from `images` ({material name: {channel:
    ImageData}}) and its planes moved (a lit copy framed anew, issue 61: a draft read back
    and baked on Blender's main thread held it 0.4 s at 1024²): its next live bake — the
    depsgraph update that follows, once it has noted those edits — drafts it in a worker
    thread from them (nothing read back from Blender), written by _final_bakes, its final
    bake after it; the final is due meanwhile (where no update follows: a script)."""
    _BESIDE[parent.name] = images
    final_bake_due(parent)


def final_bake_due(parent, after=0.0):
    """The group's final bake started in a worker thread `after` seconds from now (0: with no
    draft first — its shadows show a stroke's draft already, draft_group)."""
    _FINAL_DUE[parent.name] = time.perf_counter() - DEBOUNCE_S + after
    if not bpy.app.timers.is_registered(_final_bakes):
        bpy.app.timers.register(_final_bakes, first_interval=max(after, POLL_S))


_RUNNING = {}          # parent name → its final _GroupBake in a worker thread
POLL_S = 0.05          # how often the timer looks for a finished final bake


def _final_bakes():
    """Timer: the groups whose lights have been still DEBOUNCE_S start their bake at the
    layers' own quality in a worker thread (one at a time per group: a group still baking
    waits); finished ones are written here, on the main thread. → seconds to the next call."""
    now = time.perf_counter()
    for name, job in list(_RUNNING.items()):
        if job.done():
            del _RUNNING[name]
            _written(name, job)
    for name, since in list(_FINAL_DUE.items()):
        if now - since < DEBOUNCE_S or name in _RUNNING or _BESIDE.get(name) is _HOLD:
            continue
        del _FINAL_DUE[name]
        _BESIDE.pop(name, None)           # (its final starts: no draft before it now)
        parent = bpy.data.objects.get(name)
        try:
            job = _group_job(parent) if parent is not None else None
            if job is not None:
                job.start()
                _RUNNING[name] = job
        except Exception as exc:          # a timer never raises into Blender
            print(f"Dynamic Painting: layered bake of {name}: {exc}")
    return POLL_S if _RUNNING else DEBOUNCE_S if _FINAL_DUE else None


def _written(name, job):
    try:
        job.write()
    except Exception as exc:              # a timer never raises into Blender
        print(f"Dynamic Painting: layered bake of {name}: {exc}")


def settle():
    """Finish the final bakes that are running or due now, here (tests and background mode,
    where no timer runs)."""
    for name, job in list(_RUNNING.items()):
        job.thread.join()
        del _RUNNING[name]
        _written(name, job)
    for name in list(_FINAL_DUE):
        del _FINAL_DUE[name]
        parent = bpy.data.objects.get(name)
        if parent is not None:
            bake_group(parent)
