"""A painting's material: build the node tree, the derived images and the shadow bake.

Three kinds of work, each done only when its inputs change (pipeline.md §12):
  - the node tree (pipeline_graph.describe → build_bpy.build) when the *structure* changes:
    a feature toggled, an image slot filled or emptied, a light linked or unlinked;
  - derived images (the pre-blurred height map, the blurred E/B lookup copies) when the
    image or its blur settings change;
  - the cos-θ shadow images (§6) when asked (creation, "Bake Shadows", each rendered frame).
Live values (t0, η, …) never come here: drivers carry them (shader_backend.py).
"""
from contextlib import contextmanager

import numpy as np

import bpy

from .. import params as P
from ..core.inputs import finite_pixels, non_finite_message
from ..core.lights import Light
from ..core.pipeline import PER_PIXEL_CHANNELS, lookup_copy, shadow_term, shape_normals, silhouette_channel
from ..core.shape import default_preblur_px, preblurred_height
from ..imageio import file_channels, image_data_from_blender
from ..nodegraph import build_bpy
from ..nodegraph.pipeline_graph import Features, describe
from ..nodegraph.shader_backend import POINT_POWER_UNIT, ShaderBackend
from .properties import DERIVED, SHADOW_INPUTS, STRUCTURAL, channel_images, settings_to_params

COLOUR_CHANNELS = {c for c, (_, kind) in P.CHANNELS.items() if kind == "colour"}
_suspended = [0]


@contextmanager
def batch():
    """Write many settings without refreshing after each one; refresh once after."""
    _suspended[0] += 1
    try:
        yield
    finally:
        _suspended[0] -= 1


def on_setting_changed(mat, path):
    """Property update callback (properties.py): do only the work this change needs."""
    if _suspended[0] or not mat.dynamic_painting.is_painting:
        return
    if path in ("shadows.quality", "shadows.steps", "shadows.resolution"):
        _sync_quality(mat.dynamic_painting.shadows, path)
    if path.startswith("images."):      # a slot filled from the panel or by Python
        channel = path.split(".", 1)[1]
        img = getattr(mat.dynamic_painting, f"image_{channel}")
        if img is not None:
            prepare_channel_image(img, channel)
    from .handlers import rendering, report   # late: handlers imports this module
    s = mat.dynamic_painting
    structure = path in STRUCTURAL or path.startswith("images.") or path == "light_collection"
    # A shadow setting dragged in the UI re-bakes live (preview, then final; never freezing
    # the UI) when the tree stays and every light has an image already.
    live = (path in SHADOW_INPUTS and not structure and path not in DERIVED and s.shadows.enabled
            and not rendering() and all(i.shadow is not None for i in s.lights))
    try:
        refresh(mat, structure=structure,
                derived=path in DERIVED or path.startswith("images."),
                shadows=not live and (path in SHADOW_INPUTS or path.startswith("images.shape")))
        if live:
            from .live_bake import LIVE
            LIVE.request(mat, bpy.context.scene)
    except Exception as exc:     # never let a callback raise into Blender's UI
        report(mat, exc)


def _sync_quality(sh, path):
    """A quality level writes its K and resolution into the settings (so the OSL shader's
    drivers see them too); editing K or the resolution by hand makes the level 'custom'."""
    from ..core.bake import QUALITY
    with batch():
        if path == "shadows.quality" and sh.quality in QUALITY:
            sh.steps = QUALITY[sh.quality]["steps"]
            sh.resolution = QUALITY[sh.quality]["scale"]
        elif path != "shadows.quality" and sh.quality in QUALITY:
            q = QUALITY[sh.quality]
            if (sh.steps, round(sh.resolution, 4)) != (q["steps"], q["scale"]):
                sh.quality = "custom"


# -- images ---------------------------------------------------------------------------------
def is_float_file(img):
    """Does the image come from a float file (EXR, HDR: linear values)? 16-bit PNG and TIFF
    also get float buffers in Blender but hold sRGB-encoded codes like 8-bit files."""
    return _bits(img) == 32


def prepare_channel_image(img, channel):
    """Colour images are sRGB-decoded by Blender (8/16-bit) or linear (float); data images
    are never colour-managed (§0). Alpha is kept apart from colour (channel packed)."""
    if channel in COLOUR_CHANNELS and not is_float_file(img):
        img.colorspace_settings.name = "sRGB"     # 8- and 16-bit files hold sRGB codes (§0)
    else:
        img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "CHANNEL_PACKED"
    img.use_half_precision = False   # 16-bit GPU textures cost EEVEE ~1e-2 on steep slopes


def float_image(name, rgba):
    """A float RGBA image holding `rgba` (y-up (H, W, 4)), reused when the name exists."""
    h, w = rgba.shape[:2]
    img = bpy.data.images.get(name)
    if img is None or tuple(img.size) != (w, h) or not img.is_float:
        if img is not None:
            bpy.data.images.remove(img)
        img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True, is_data=True)
    img.colorspace_settings.name = "Non-Color"   # before the pixels: it regenerates them
    img.alpha_mode = "CHANNEL_PACKED"
    img.use_half_precision = False
    img.pixels.foreach_set(np.ascontiguousarray(rgba, dtype=np.float32).ravel())
    return img


def grey_rgba(grey, alpha=None):
    a = np.ones_like(grey) if alpha is None else alpha
    return np.stack([grey, grey, grey, a], axis=-1)


def _set_derived(settings, channel, image, key):
    item = next((d for d in settings.derived if d.channel == channel), None)
    if item is None:
        item = settings.derived.add()
        item.channel = channel
    item.image, item.key = image, key


def _derived(settings, channel):
    return next((d.image for d in settings.derived if d.channel == channel), None)


def _remove_derived(settings, channel):
    for i, d in enumerate(settings.derived):
        if d.channel == channel:
            settings.derived.remove(i)
            return


def update_derived_images(mat):
    """Make the images numpy derives from the inputs (only those whose inputs changed),
    reading only the images they come from. → warnings (non-finite pixels replaced)."""
    s = mat.dynamic_painting
    p = settings_to_params(s)
    imgs = channel_images(s)
    base = f"DP {mat.name}"
    read = {}       # source channel → (its pixels made finite, how many were not)
    warnings = []

    def source_read(source):
        if source not in read:
            data = image_data_from_blender(imgs[source])
            role = "colour" if source != "shape" else p.shape.kind
            clean, bad = finite_pixels(data.pixels, role)
            if bad:
                warnings.append(non_finite_message(imgs[source].name, bad))
            read[source] = (type(data)(clean, data.bits, data.name), bad)
        return read[source]

    def source_data(source):
        return source_read(source)[0]

    def need(channel, key, source, make):
        item = next((d for d in s.derived if d.channel == channel), None)
        if item is None or item.image is None or item.key != key:
            _set_derived(s, channel, float_image(f"{base} {channel}", make(source_data(source))),
                         key)

    # Float files may hold NaN/Inf (core/inputs.py): the tree then samples a finite copy
    # (a derived image under the channel's own name replaces it in the tree). Integer files
    # cannot: they are sampled as they are.
    for channel in ("shape", *PER_PIXEL_CHANNELS):
        img = imgs.get(channel)
        if img is None or not img.is_float or (channel == "shape" and p.shape.kind == "height"):
            _remove_derived(s, channel)
            continue
        key = f"{img.name}|finite|{p.shape.kind if channel == 'shape' else ''}"
        item = next((d for d in s.derived if d.channel == channel), None)
        if item is not None and item.key == key and item.image is not None:
            continue
        data, bad = source_read(channel)
        if not bad:
            _set_derived(s, channel, img, key)          # checked: the image itself
        else:
            clean = data.pixels
            rgba = clean if clean.shape[2] == 4 else np.concatenate(
                [np.repeat(clean[..., :1], 3, 2) if clean.shape[2] < 3 else clean[..., :3],
                 np.ones(clean.shape[:2] + (1,), clean.dtype)], -1)
            _set_derived(s, channel, float_image(f"{base} {channel} finite", rgba), key)

    if p.shape.kind == "height" and "shape" in imgs:
        sigma = p.shape.preblur
        sigma = default_preblur_px(_bits(imgs["shape"])) if sigma == "auto" else sigma
        need("height", f"{imgs['shape'].name}|{sigma}", "shape",
             lambda d: grey_rgba(preblurred_height(d.grey(), float(sigma))))
    source = _silhouette_source(mat)
    if source:
        # A float copy of the alpha: EEVEE reads 8-bit alpha up to 1/255 off (254 → 255).
        need("silhouette", f"{imgs[source].name}|{source}", source,
             lambda d: grey_rgba(*[np.clip(np.nan_to_num(d.alpha()), 0, 1)] * 2))
    for channel, sec in (("environment", p.reflection), ("background", p.refraction)):
        if channel in imgs:
            need(channel, f"{imgs[channel].name}|{sec.blur}|{sec.extension}", channel,
                 lambda d, sec=sec: lookup_copy(d, sec.blur, sec.extension))
    if "background" in imgs:
        if p.refraction.blur == 0:
            _set_derived(s, "background_sharp", _derived(s, "background"), "same")
        else:
            need("background_sharp", f"{imgs['background'].name}|0", "background",
                 lambda d: lookup_copy(d, 0.0, "extend"))
    return warnings


def _silhouette_source(mat):
    """The channel whose alpha cuts the painting out (§11), as Features resolves it."""
    imgs = channel_images(mat.dynamic_painting)
    return silhouette_channel(mat.dynamic_painting.silhouette.source,
                              lambda c: c in imgs and has_alpha(imgs[c]))


# -- lights -----------------------------------------------------------------------------------
def linked_lights(mat, scene):
    """The Sun and Point lights that shade this painting, in a stable order (by name)."""
    coll = mat.dynamic_painting.light_collection
    objects = coll.all_objects if coll is not None else scene.objects
    return sorted((o for o in objects if o.type == "LIGHT" and o.data.type in ("SUN", "POINT")),
                  key=lambda o: o.name)


def painting_frame_light(obj, plane_matrix, depsgraph=None):
    """A Blender light → core Light in the painting frame (the plane's object space, §0).

    Uses the evaluated object when a depsgraph is given (animation renders, blender-notes.md).
    """
    ev = obj.evaluated_get(depsgraph) if depsgraph is not None else obj
    inv = np.linalg.inv(np.array(plane_matrix, dtype=np.float64))
    m = np.array(ev.matrix_world, dtype=np.float64)
    colour = tuple(ev.data.color)
    if ev.data.type == "SUN":
        direction = inv[:3, :3] @ (m[:3, :3] @ np.array([0.0, 0.0, 1.0]))
        return Light("sun", tuple(direction / np.linalg.norm(direction)), colour,
                     ev.data.energy, obj.name)
    pos = inv @ np.append(m[:3, 3], 1.0)
    return Light("point", tuple(pos[:3]), colour, ev.data.energy / POINT_POWER_UNIT, obj.name)


# -- the node tree ----------------------------------------------------------------------------
def features_for(mat, scene):
    s = mat.dynamic_painting
    imgs = channel_images(s)
    if "shape" not in imgs:
        raise ValueError("the painting has no shape image (normal or height map)")
    if "dark" not in imgs and "bright" not in imgs:
        raise ValueError("the painting needs a dark or a bright image")
    data_alpha = {c for c, img in imgs.items() if has_alpha(img)}
    lights = linked_lights(mat, scene)
    f = Features.from_params(settings_to_params(s), imgs.keys(),
                             [o.data.type.lower() for o in lights], imgs["shape"].size,
                             data_alpha, {c: tuple(img.size) for c, img in imgs.items()})
    return f, lights


def _bits(img):
    """Bits per channel of a loaded image (8, 16 or 32), without reading its pixels."""
    if not img.is_float:
        return 8
    return 16 if img.file_format in ("PNG", "TIFF") else 32


def has_alpha(img):
    return file_channels(img) in (2, 4)


def rebuild_tree(mat, scene, force=False):
    """Rebuild the node tree if its structure changed (or `force`). → True if rebuilt."""
    s = mat.dynamic_painting
    f, lights = features_for(mat, scene)
    signature = repr((f.key(), [o.name for o in lights]))
    if not force and signature == s.signature and len(mat.node_tree.nodes):
        return False
    images = {c: img for c, img in channel_images(s).items()}
    for item in s.derived:
        images[item.channel] = item.image
    _sync_light_items(s, lights)
    for i, item in enumerate(s.lights):
        if item.shadow is not None:
            images[f"shadow_{i}"] = item.shadow
    missing = f.image_channels() - images.keys()
    if missing:
        raise ValueError(f"images not ready: {', '.join(sorted(missing))}")
    tree = mat.node_tree
    tree.animation_data_clear()
    tree.nodes.clear()
    build_bpy.build(tree, describe(f), ShaderBackend(mat, images, lights))
    if f.shadow_source == "osl":
        # Cycles renders the OSL shader (in-shader march); EEVEE keeps the node material.
        from . import osl
        eevee_out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
        eevee_out.target = "EEVEE"
        osl.build_osl_tree(mat, f, images, lights, march=f.shadows)
        cycles_out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                          and n != eevee_out)
        cycles_out.target = "CYCLES"
        scene.cycles.shading_system = True
    may_be_transparent = f.has_lookups or bool(f.silhouette)
    mat.surface_render_method = "BLENDED" if may_be_transparent else "DITHERED"
    s.signature = signature
    return True


def _sync_light_items(s, lights):
    """Keep s.lights in the order of `lights`, each with its shadow image."""
    old = {item.object.name: (item.shadow, item.bake_key) for item in s.lights
           if item.object is not None}
    s.lights.clear()
    for obj in lights:
        item = s.lights.add()
        item.object = obj
        item.kind = obj.data.type
        item.shadow, item.bake_key = old.get(obj.name, (None, ""))


# -- the cos-θ bake ---------------------------------------------------------------------------
def light_key(light):
    """Where a light is, as far as its bake is concerned."""
    return repr((light.kind, np.round(light.vector, 9).tolist()))


def bake_key(light, p, s):
    """What a bake depends on: the light's place, the shape and shadow settings, the image."""
    return light_key(light) + "|" + repr((vars(p.shape), vars(p.shadows),
                                          s.image_shape.name if s.image_shape else None))


_SHAPES = {}   # material name → (key, (normals, heights_px, slopes)): the bakes' decoded shape


def bake_shape(mat, p, fresh=False):
    """The shape decoded for the bake (§2), cached per painting until its shape image or the
    shape settings change, so per-frame and live bakes do not read and decode it each time;
    `fresh` decodes again (the image's pixels may have been edited)."""
    s = mat.dynamic_painting
    key = (s.image_shape.name, repr(vars(p.shape)))
    hit = _SHAPES.get(mat.name)
    if fresh or hit is None or hit[0] != key:
        hit = (key, shape_normals(image_data_from_blender(s.image_shape), p, np.float32))
        _SHAPES[mat.name] = hit
    return hit[1]


def forget_cached_shapes():
    """Another file is open: cached shapes may belong to same-named paintings of the last one."""
    _SHAPES.clear()


def invalidate_generated(mat):
    """Mark every image numpy made for the painting as out of date (a reopened .blend keeps the
    images but not their pixels), so the next refresh remakes them all."""
    s = mat.dynamic_painting
    for item in s.derived:
        item.key = ""
    for item in s.lights:
        item.bake_key = ""


def bake_shadows(mat, scene, depsgraph=None, force=True, progress=None):
    """Bake the cos-θ term (§6) of the linked lights into their images. → milliseconds taken.

    Without `force`, a light whose painting-frame position and shadow inputs are those of its
    last bake is skipped (static lights in an animation bake once). A failure leaves the
    previous images untouched: new pixels are written only after every light is baked.
    """
    import time
    s = mat.dynamic_painting
    p = settings_to_params(s)
    plane = s.plane
    if plane is None:
        raise ValueError("the painting has no plane")
    if s.image_shape is None:
        raise ValueError("no shape image to bake shadows from: assign one under Images "
                         "(the last baked shadows are kept)")
    plane_m = (plane.evaluated_get(depsgraph) if depsgraph is not None else plane).matrix_world
    todo = []
    for item in s.lights:
        if item.object is None:
            continue
        light = painting_frame_light(item.object, plane_m, depsgraph)
        key = bake_key(light, p, s)
        if force or item.shadow is None or item.bake_key != key:
            todo.append((item, light, key))
    if not todo:
        return 0.0
    n, z_px, slopes = bake_shape(mat, p, fresh=force)
    t_start = time.perf_counter()
    results = []
    for i, (_, light, _) in enumerate(todo):
        part = None if progress is None else \
            (lambda f, i=i: progress((i + f) / len(todo)))     # noqa: E731
        results.append(shadow_term(n, z_px, slopes, light, p, progress=part))
    ms = (time.perf_counter() - t_start) * 1000
    if ms > 2000:      # long bakes (huge images, reference quality) say what they did
        w, h = s.image_shape.size
        print(f"Dynamic Painting: {mat.name}: baked {len(todo)} light(s) at {w}×{h} "
              f"({p.shadows.quality}) in {ms / 1000:.1f} s")
    for (item, _, key), t in zip(todo, results):
        item.shadow = float_image(f"DP {mat.name} shadow {item.object.name}", grey_rgba(t))
        item.bake_key = key
    s.shadows_stale = False
    return ms


# -- health -----------------------------------------------------------------------------------
def problems(mat):
    """What keeps the painting from rendering as set up, one line each (the panel shows them,
    renders report them): deleted plane or images, image files gone from disk."""
    import os
    s = mat.dynamic_painting
    found = []
    if s.plane is None:
        found.append("its plane was deleted: add the painting again (Add › Dynamic Painting)")
    if s.image_shape is None:
        found.append("it has no shape image (deleted?): open one under Images")
    if s.image_dark is None and s.image_bright is None:
        found.append("it has no dark or bright image (deleted?): open one under Images")
    for channel, img in channel_images(s).items():
        if img.source == "FILE" and img.packed_file is None:
            path = bpy.path.abspath(img.filepath, library=img.library)
            if not os.path.isfile(path):
                found.append(f"the {channel.replace('_', ' ')} image's file is missing: {path} "
                             "(File › External Data › Find Missing Files, or open it again)")
    return found


def tree_is_stale(mat):
    """An image the node tree samples was deleted (its node lost the image)."""
    return any(n.bl_idname == "ShaderNodeTexImage" and n.image is None
               for n in mat.node_tree.nodes)


# -- everything -------------------------------------------------------------------------------
def refresh(mat, structure=True, derived=True, shadows=False, scene=None, depsgraph=None,
            progress=None):
    """Bring the painting up to date: derived images, shadow bake, then the tree."""
    scene = scene or bpy.context.scene
    s = mat.dynamic_painting
    warnings = []
    if derived:
        warnings += update_derived_images(mat)
    if structure:
        _, lights = features_for(mat, scene)
        _sync_light_items(s, lights)
    if s.shadows.enabled and (shadows or any(i.shadow is None for i in s.lights)):
        bake_shadows(mat, scene, depsgraph, progress=progress)
    elif shadows:
        s.shadows_stale = True
    if structure or shadows:
        rebuild_tree(mat, scene, force=False)
    from .handlers import LAST_ERRORS   # up to date again: the panel stops showing old errors
    LAST_ERRORS[:] = [e for e in LAST_ERRORS if e[0] != mat.name]
    return warnings

