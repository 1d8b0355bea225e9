"""A Grease Pencil drawing as a scene of lit layers (issue 42; pipeline.md §15, §16).

Grease Pencil cannot be lit (its material is not a BSDF: blender-notes.md). Here each of a
drawing's layers is drawn by **Blender's own Grease Pencil renderer** — its materials, fills,
textures, modifiers and effects; no rasterizer of ours — into an image with its alpha, unlit
(the layer's *Use Lights* off while it renders), in a scene of its own so nothing else of the
artist's scene is drawn or changed: Workbench, the Standard view transform (the colours as
drawn), transparent film, an orthographic camera framing the drawing's bounds over all its
frames (so every frame of an animation lands on the same pixels). Each layer is then made a
painting as a plain layer of a layered file is (layered_files.painting_of_frames: a shaded
dark copy, its silhouette inflated by parts; sprite sheets where it changes over the frames),
or a dark image drawn from the shadow colours the artist named (shadow_layers,
shadow_materials: a layer or material called "<name> shadow"),
and the layers are built as Add › Layered… builds them (layered_build.build_layered), where
the drawing is (light_drawing). The lit copy follows its drawing (refresh_lit_drawing).
"""
import contextlib
import hashlib
import json
import math
import os
import shutil
import tempfile
import threading

import numpy as np

import bpy
from mathutils import Matrix, Vector

from ...core.layers import MAX_LAYERS
from ...core.lights import default_sun
from ...errors import UserError
from ...inputs import memory
from ...inputs.imageio import quiet_native, read_image
from ...inputs.drawings import frame_range, load_drawing
from ...inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING, painting_of_frames
from ...shapes.methods import options as shape_options
from ..bake.layers import draft_group, final_bake_due, group_materials
from ..bake.live_bake import rendering
from ..material.sync import update
from ..state.animation import fcurves
from ..state.edits import note_edited
from ..state.frames import forget_frames, moves
from ..state.images import (forget_enlarged, packed_image, refill_enlarged,
                            refill_packed_image)
from ..state.status import report
from .layered_build import build_layered, remove_objects
from .painting_scene import NO_CAMERA, unchanged_images_on_failure

MARGIN = 0.02          # of the drawing's size, around its bounds (strokes' round caps)


class GreasePencilError(UserError):
    """A Grease Pencil object that cannot be made a painting; the message says why."""


def drawn_layers(obj, merge=False):
    """The layers of a Grease Pencil object that draw something, back to front, as the lit
    layers they become → (groups, notes about the layers left out: hidden, no frames,
    nothing drawn, shadow colours; and merged): each group one lit layer — one layer, or
    with `merge`, where more than a scene holds draw (§15: MAX_LAYERS), the back ones drawn
    together as one."""
    if obj is None or obj.type != "GREASEPENCIL":
        raise GreasePencilError(f"{getattr(obj, 'name', 'nothing')} is not a Grease Pencil "
                                f"object: select the drawing to light")
    kept, notes = [], []
    partners = {layer.name: owner for owner, layer in shadow_layers(obj).items()}
    for layer in obj.data.layers:          # the first layer is drawn first: the back one
        if layer.name in partners:
            notes.append(f"{layer.name}: the shadow colours of {partners[layer.name]} (its "
                         f"dark image), not a lit layer of its own")
        elif layer.hide:
            notes.append(f"{layer.name}: hidden, left out (show it to light it)")
        elif not len(layer.frames):
            notes.append(f"{layer.name}: no frames, left out")
        elif not _draws(layer):
            notes.append(f"{layer.name}: nothing drawn, left out")
        else:
            kept.append(layer)
    if not kept:
        raise GreasePencilError(f"{obj.name} has no layer that draws anything"
                                + (f" ({'; '.join(notes)})" if notes else ""))
    if len(kept) <= MAX_LAYERS:
        return [(layer,) for layer in kept], notes
    back = kept[:len(kept) - MAX_LAYERS + 1]
    if not merge:
        raise GreasePencilError(
            f"{obj.name} has {len(kept)} layers that draw; a scene of lit layers holds at most "
            f"{MAX_LAYERS} (§15): tick Merge Back Layers to draw the back {len(back)} "
            f"({', '.join(layer.name for layer in back)}) as one, merge some yourself, or hide "
            f"those that need no light of their own")
    notes.append(f"{', '.join(layer.name for layer in back)}: drawn together as one lit layer "
                 f"(a scene holds {MAX_LAYERS}; they shadow each other no more)")
    return [tuple(back)] + [(layer,) for layer in kept[len(back):]], notes


SHADOW = " shadow"      # "<name> shadow": the shadow colours of layer or material <name>


def shadow_of(name, names):
    """The name `name` gives shadow colours to ("Figure shadow" → "Figure", the suffix in
    any case) where that is one of `names`, else None."""
    base = name[:-len(SHADOW)]
    return base if name.lower().endswith(SHADOW) and base in names else None


def shadow_layers(obj):
    """{layer name: the layer drawn as its shadow colours} — a layer "<name> shadow" that
    draws, hidden or not (it is the dark image of <name>, not a lit layer of its own)."""
    names = {layer.name for layer in obj.data.layers}
    return {shadow_of(layer.name, names): layer for layer in obj.data.layers
            if shadow_of(layer.name, names) and _draws(layer)}


def shadow_materials(obj):
    """{material slot index: the material "<its name> shadow"} of the drawing's materials
    that have one (drawn in their place for the dark images of the layers that use them)."""
    out = {}
    for k, slot in enumerate(obj.material_slots):
        partner = slot.material and bpy.data.materials.get(slot.material.name + SHADOW)
        if partner is not None and partner.grease_pencil is not None:
            out[k] = partner
    return out


def _draws(layer):
    """Whether a layer has a stroke on any of its frames."""
    return any(len(f.drawing.strokes) for f in layer.frames)


def layer_stem(i, group):
    """The name of the i-th lit layer's images and painting (drawn_layers' groups): NN_name,
    NN back to front; merged layers' names joined by '+'."""
    return f"{i + 1:02d}_{bpy.path.clean_name('+'.join(layer.name for layer in group))}"


def framing(obj, margin=MARGIN):
    """The bounds the drawing's layers are drawn in (drawing_bounds): of every layer that
    draws, hidden ones too — hiding one keeps the others in place."""
    return drawing_bounds([layer for layer in obj.data.layers if _draws(layer)], margin)


def layer_depths(layers, width, spacing):
    """Each layer's depth in front of the first (image widths of a drawing `width` wide):
    where the artist moved layers toward the camera (their translation's −Y, the front
    view's depth), those; where none was moved, `spacing` apart in drawing order."""
    ys = [float(layer.translation[1]) for layer in layers]
    if max(ys) - min(ys) > 1e-9:
        return [(ys[0] - y) / width for y in ys]
    return [i * spacing for i in range(len(layers))]


def animated(obj):
    """Whether a drawing changes over the frames: a layer with more than one keyframe, or
    animation data (_animation_data)."""
    return any(len(layer.frames) > 1 for layer in obj.data.layers) or _animation_data(obj)


def _animation_data(obj):
    """Whether anything the drawing is drawn from is animated: the object (its modifiers' and
    effects' settings too), its data (layer transforms, opacities) or its materials."""
    return obj.animation_data is not None or obj.data.animation_data is not None or \
        any(m is not None and m.animation_data is not None for m in obj.data.materials)


def shown_keyframes(obj, group, frames):
    """What a group of layers (drawn together) shows on each scene frame of `frames`: the
    frame numbers of the keyframes its layers hold there (the last at or before it; None
    before the first) — or, where anything of the drawing may change between keyframes
    (animation data, modifiers, effects), the scene frame itself. Frames with one key look
    the same: drawn once."""
    if _animation_data(obj) or len(obj.modifiers) or len(obj.shader_effects):
        return list(frames)
    keys = [sorted(frame.frame_number for frame in layer.frames) for layer in group]
    return [tuple(max((k for k in ks if k <= f), default=None) for ks in keys) for f in frames]


def _points(layer):
    """Every point of every frame of a layer in the object's space, and its radius."""
    out, radii = [], []
    m = np.array(layer.matrix_local)
    for frame in layer.frames:
        drawing = frame.drawing
        n = drawing.attributes.domain_size("POINT")
        if not n:
            continue
        pos = np.empty(n * 3, np.float32)
        drawing.attributes["position"].data.foreach_get("vector", pos)
        pos = pos.reshape(n, 3) @ m[:3, :3].T + m[:3, 3]
        radius = np.full(n, 0.0, np.float32)
        if "radius" in drawing.attributes:
            drawing.attributes["radius"].data.foreach_get("value", radius)
        out.append(pos)
        radii.append(radius)
    return np.concatenate(out), np.concatenate(radii)


def drawing_bounds(layers, margin=MARGIN):
    """(x0, x1, z0, z1): the drawing's extent in its object's X (right) and Z (up) over all
    frames of `layers`, strokes' radii included, with a margin (a share of its size; Grease
    Pencil draws on the XZ plane, seen from −Y)."""
    pts, radii = zip(*(_points(layer) for layer in layers))
    pts, radii = np.concatenate(pts), np.concatenate(radii)
    x0, x1 = float((pts[:, 0] - radii).min()), float((pts[:, 0] + radii).max())
    z0, z1 = float((pts[:, 2] - radii).min()), float((pts[:, 2] + radii).max())
    pad = margin * max(x1 - x0, z1 - z0, 1e-6)
    return x0 - pad, x1 + pad, z0 - pad, z1 + pad


def render_layers(obj, folder, width_px, frames=None, progress=None, margin=MARGIN,
                  only=None, shade=DEFAULT_SHADE, merge=False, samples=None, bounds=None):
    """Draw each layer of the Grease Pencil object `obj` that draws something, alone (or
    with `merge`, the back ones together where more than a scene holds: drawn_layers), into
    `folder` (16-bit RGBA, sRGB as drawn) on each scene frame of `frames` (default: the
    current one) → (paths, bounds, notes, darks): paths[i][k] layer i's (back to front)
    drawing on frames[k], named NN_name.png for one frame, NN_name_FFFF.png for several;
    darks[i][k] its shadow colours on that frame where the artist named any (its layer
    "<name> shadow", else its materials' "<material> shadow" drawn in their place, the others
    `shade` × their colours), else darks[i] None; margin: around the drawing's bounds
    (drawing_bounds); only: the names of the layers to draw (paths[i] None for the others,
    a merged group drawn if any of its layers is named; the framing is the whole drawing's);
    samples: Grease Pencil's anti-aliasing samples per pixel (default: the artist's scene's
    render setting, as F12 draws the drawing; each costs a draw of every pixel); bounds:
    the framing (x0, x1, z0, z1) drawn in (default: the drawing's, framing: a stroke's
    draft keeps its lit copy's). A frame that shows what an earlier one showed
    (shown_keyframes) is drawn once. The artist's scene, the object, its layers and
    materials are left as they were."""
    layers, notes = drawn_layers(obj, merge)
    x0, x1, z0, z1 = bounds = framing(obj, margin) if bounds is None else tuple(bounds)
    w, h = drawn_size(bounds, width_px)
    artist = bpy.context.scene
    frames = [artist.frame_current] if frames is None else list(frames)
    memory.check(*drawing_memory(obj, layers, frames, w, h, only),
                 "draw it smaller (From Grease Pencil's Resolution, --width on the command "
                 "line) or over fewer frames (the scene's frame range)")
    os.makedirs(folder, exist_ok=True)
    partner_layers, partner_materials = shadow_layers(obj), shadow_materials(obj)
    scene = bpy.data.scenes.new(f"{obj.name} layers (Dynamic Painting)")
    cam = bpy.data.objects.new(f"{obj.name} layers camera", bpy.data.cameras.new("DP camera"))
    saved = [(layer, layer.hide, layer.use_lights) for layer in obj.data.layers]
    hidden = obj.hide_render
    drawn_count = [0]

    def draw(shown, stem):
        """The layers `shown` alone on each frame → their paths, one per frame."""
        names = {layer.name for layer in shown}
        for other in obj.data.layers:
            other.hide = other.name not in names
            other.use_lights = False              # drawn as painted: the lights come later
        drawn, keys = {}, shown_keyframes(obj, shown, frames)
        for frame, key in zip(frames, keys):
            if key not in drawn:
                scene.frame_set(frame)
                drawn[key] = draw_still(
                    scene, f"{stem}.png" if len(frames) == 1 else f"{stem}_{frame:04d}.png")
            drawn_count[0] += 1
            if progress is not None:
                progress(min(1.0, drawn_count[0] / (len(layers) * len(frames))))
        return [drawn[key] for key in keys]
    try:
        obj.hide_render = False           # (a drawing lit before is hidden from renders)
        scene.collection.objects.link(obj)
        scene.collection.objects.link(cam)
        cam.data.type = "ORTHO"
        cam.data.ortho_scale = x1 - x0
        cam.data.sensor_fit = "HORIZONTAL"
        # look along the object's +Y at the middle of its bounds (its front view)
        middle = obj.matrix_world @ Vector(((x0 + x1) / 2, 0.0, (z0 + z1) / 2))
        look = obj.matrix_world.to_3x3().normalized() @ Matrix.Rotation(math.pi / 2, 3, "X")
        r = scene.render
        drawing_settings(scene, samples or artist.grease_pencil_settings.aa_samples,
                         artist.grease_pencil_settings.antialias_threshold_render)
        # the camera moved by where Blender's anti-aliasing puts a drawing (drawn_offset)
        dx, dy = drawn_offset(scene, folder)
        pixel = (x1 - x0) / w
        cam.matrix_world = Matrix.Translation(
            middle + look.col[2] * 10.0 * (x1 - x0)
            + (look.col[0] * dx + look.col[1] * dy) * pixel) @ look.to_4x4()
        cam.data.clip_end = 100.0 * (x1 - x0)
        scene.camera = cam
        r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
        paths, darks = [], []
        for i, group in enumerate(layers):
            stem = os.path.join(folder, layer_stem(i, group))
            if only is not None and not only & {layer.name for layer in group}:
                paths.append(None)
                darks.append(None)
                continue
            paths.append(draw(group, stem))
            partners = tuple(partner_layers[layer.name] for layer in group
                             if layer.name in partner_layers)
            if partners:
                darks.append(draw(partners, stem + "_shadow"))
            elif partner_materials.keys() & set().union(*map(materials_used, group)):
                with materials_in_shadow(obj, partner_materials, shade):
                    darks.append(draw(group, stem + "_shadow"))
            else:
                darks.append(None)
    finally:
        obj.hide_render = hidden
        for layer, hide, lights in saved:
            layer.hide, layer.use_lights = hide, lights
        bpy.data.objects.remove(cam)
        bpy.data.scenes.remove(scene)
    return paths, (x0, x1, z0, z1), notes, darks


def drawing_settings(scene, samples, threshold):
    """A scene of our own set to draw Grease Pencil as it is painted: Workbench, `samples`
    anti-aliasing samples (and the artist's SMAA `threshold`), transparent film, the
    Standard view transform, 16-bit RGBA PNG files."""
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    scene.grease_pencil_settings.aa_samples = samples
    scene.grease_pencil_settings.antialias_threshold_render = threshold
    r.film_transparent = True
    r.image_settings.file_format = "PNG"
    r.image_settings.color_mode = "RGBA"
    r.image_settings.color_depth = "16"
    r.image_settings.compression = 0       # (temporary files: no time spent deflating)
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"


def draw_still(scene, path):
    """Render `scene` (drawing_settings) into the file `path`, Blender's log kept quiet
    → path."""
    scene.render.filepath = path
    with bpy.context.temp_override(scene=scene), quiet_native(1):
        bpy.ops.render.render(write_still=True, scene=scene.name)
    return path


# Blender's Grease Pencil anti-aliasing does not spread its samples about each pixel's
# centre: at its default 8 a drawing lands 0.12 px left of and 0.19 px below its strokes
# (2: 0.49, 0.61; 32: 0.03, 0.08; blender-notes.md). The lit layers move together, so on
# screen this is where the lit copy sits against its strokes and the 3D scene; what it
# moves is the few-pixel shadows one layer casts on another against that scene (the
# middle layer's at 512², sharp sun at 45°: IoU 0.92 → 0.94 against 3D cards,
# benchmarks/grease_pencil_truth.py). Measured once per sample count, undone by the camera.
CALIBRATION_PX = 64
_DRAWN_OFFSET = {}


def drawn_offset(scene, folder):
    """(dx, dy): how many pixels right and up of its strokes Blender draws a drawing in
    `scene` (drawing_settings), at its anti-aliasing settings: a disc of radius 0.35 drawn
    CALIBRATION_PX across, the centroid of its alpha less its centre (a disc's edge meets
    the pixels at every phase, so no phase's rounding is counted)."""
    gp_settings = scene.grease_pencil_settings
    key = (gp_settings.aa_samples, round(gp_settings.antialias_threshold_render, 6))
    if key in _DRAWN_OFFSET:
        return _DRAWN_OFFSET[key]
    probe = bpy.data.scenes.new("Dynamic Painting anti-aliasing probe")
    gp = bpy.data.grease_pencils.new("DP probe")
    obj = bpy.data.objects.new("DP probe", gp)
    cam = bpy.data.objects.new("DP probe camera", bpy.data.cameras.new("DP probe camera"))
    white = fill_material(gp, "DP probe", (1.0, 1.0, 1.0))
    try:
        drawing_settings(probe, *key)
        probe.collection.objects.link(obj)
        probe.collection.objects.link(cam)
        angles = np.linspace(0.0, 2 * math.pi, 96, endpoint=False)
        add_fill(gp.layers.new("disc"), list(zip(0.35 * np.cos(angles), 0.35 * np.sin(angles))),
                 white, frame=probe.frame_current, radius=1e-4)
        cam.data.type, cam.data.ortho_scale = "ORTHO", 1.0
        cam.matrix_world = Matrix.Translation((0.0, -10.0, 0.0)) @ \
            Matrix.Rotation(math.pi / 2, 4, "X")
        probe.camera = cam
        r = probe.render
        r.resolution_x = r.resolution_y = CALIBRATION_PX
        r.resolution_percentage = 100
        path = draw_still(probe, os.path.join(folder, "anti-aliasing probe.png"))
        alpha = read_image(path).pixels[..., 3].astype(np.float64)   # rows: y up
        os.remove(path)
        centres = np.arange(CALIBRATION_PX) + 0.5 - CALIBRATION_PX / 2
        total = alpha.sum()
        offset = (float((alpha.sum(axis=0) * centres).sum() / total),
                  float((alpha.sum(axis=1) * centres).sum() / total)) if total > 0 else (0.0, 0.0)
    finally:
        bpy.data.objects.remove(obj)
        camera = cam.data
        bpy.data.objects.remove(cam)
        bpy.data.cameras.remove(camera)
        material = gp.materials[white]
        bpy.data.grease_pencils.remove(gp)
        bpy.data.materials.remove(material)
        bpy.data.scenes.remove(probe)
    _DRAWN_OFFSET[key] = offset
    return offset


def drawn_size(bounds, width_px):
    """(w, h) in pixels of each layer's drawing `width_px` across, the shape of its framing
    `bounds` (x0, x1, z0, z1: framing)."""
    x0, x1, z0, z1 = bounds
    w = max(1, int(width_px))
    return w, max(1, round(w * (z1 - z0) / (x1 - x0)))


def drawing_memory(obj, layers, frames, w, h, only=None):
    """(bytes, what) lighting the groups of `layers` (drawn_layers: those named in `only`)
    of the drawing `obj` on `frames` at w × h needs at its peak (memory.drawing_bytes: each
    distinct drawing, shown_keyframes, and each layer)."""
    drawn = [group for group in layers if only is None or only & {x.name for x in group}]
    drawings = sum(len(set(shown_keyframes(obj, group, frames))) for group in drawn)
    return memory.drawing_bytes(drawings, len(drawn), w, h), \
        f"lighting {obj.name} ({drawings} drawings of {len(drawn)} layers at {w}×{h})"


def materials_used(layer):
    """The material slot indices a layer's strokes use, on any of its frames."""
    used = set()
    for frame in layer.frames:
        attribute = frame.drawing.attributes.get("material_index")
        if attribute is None:
            used.add(0)
            continue
        values = np.empty(len(attribute.data), np.int32)
        attribute.data.foreach_get("value", values)
        used.update(int(v) for v in np.unique(values))
    return used


@contextlib.contextmanager
def materials_in_shadow(obj, partners, shade):
    """The drawing's materials swapped for their shadow colours while it is drawn: each slot
    with a partner material ("<name> shadow") shows it, the others a copy of theirs at
    `shade` × its colours (as the shaded rule darkens a drawn layer; a texture is kept as
    it is). The slots and materials are put back afterwards."""
    saved = [slot.material for slot in obj.material_slots]
    copies = []
    try:
        for k, slot in enumerate(obj.material_slots):
            if k in partners:
                slot.material = partners[k]
            elif slot.material is not None and slot.material.grease_pencil is not None:
                dim = slot.material.copy()
                copies.append(dim)
                g = dim.grease_pencil
                for field in ("color", "fill_color"):
                    c = getattr(g, field)
                    setattr(g, field, (c[0] * shade, c[1] * shade, c[2] * shade, c[3]))
                slot.material = dim
        yield
    finally:
        for slot, material in zip(obj.material_slots, saved):
            slot.material = material
        for dim in copies:
            bpy.data.materials.remove(dim)


# -- a drawing made from data (inputs/drawings.py: a sample's drawing.json) ------------------
def fill_material(gp, name, rgb):
    """A fill-only Grease Pencil material of linear colour `rgb` on `gp` → its index."""
    m = bpy.data.materials.new(name)
    bpy.data.materials.create_gpencil_data(m)
    m.grease_pencil.show_fill, m.grease_pencil.show_stroke = True, False
    m.grease_pencil.fill_color = (*rgb, 1.0)
    gp.materials.append(m)
    return len(gp.materials) - 1


def add_fill(layer, points, material, frame=1, radius=0.005):
    """A closed filled stroke through `points` [(x, z)] (the drawing's XZ plane) on `frame`
    of a Grease Pencil layer."""
    found = [f for f in layer.frames if f.frame_number == frame]
    drawing = (found[0] if found else layer.frames.new(frame)).drawing
    drawing.add_strokes([len(points)])
    stroke = drawing.strokes[len(drawing.strokes) - 1]
    for p, (x, z) in zip(stroke.points, points):
        p.position = (x, 0.0, z)
        p.radius = radius
    stroke.cyclic = True
    stroke.material_index = material


def build_drawing(scene, drawing, location=(0.0, 0.0, 0.0)):
    """A Grease Pencil object drawn as `drawing` (inputs/drawings.Drawing) says, linked to
    `scene` at `location` → the object."""
    gp = bpy.data.grease_pencils.new(drawing.name)
    obj = bpy.data.objects.new(drawing.name, gp)
    scene.collection.objects.link(obj)
    obj.location = location
    index = {name: fill_material(gp, name, rgb) for name, rgb in drawing.materials.items()}
    for spec in drawing.layers:
        layer = gp.layers.new(spec.name)
        layer.translation = spec.translation
        for fill in spec.fills:
            add_fill(layer, fill.points, index[fill.material], fill.frame)
    return obj


# -- the lit copy (Add › From Grease Pencil; the command line) -------------------------------
# A drawing's layers lie a Spacing apart (0.05 image widths): inflated as a file's layers are
# (a disc a hemisphere), a large card would reach through the layers in front of it
GREASE_PENCIL_RELIEF = 0.1
GREASE_PENCIL_RESOLUTION = 1024     # px across the drawing: each layer's images
# Paint Shape's relief effects (issue 41: make-shape inflate's options but its height, which
# is Relief here, and its snap: Blender draws a layer's alpha exactly where its strokes are),
# applied to every layer's inflated silhouette
LAYER_EFFECTS = tuple(o for o in shape_options("inflate", "addon")
                      if o.name not in ("height", "snap"))
LIT_SETTINGS = ("resolution", "spacing", "shade", "relief", "animation", "merge",
                *(o.name for o in LAYER_EFFECTS))
SOURCE = "dynamic_painting_grease_pencil"    # a lit copy's parent: its drawing and settings
LAYER = "dynamic_painting_grease_pencil_layer"   # a lit layer's material: its layer's name


def drawing_frames(scene, obj, settings):
    """The scene frames a drawing is drawn on (the scene's range where it is animated and
    settings' `animation` asks for it), or None (the current frame alone)."""
    return list(range(scene.frame_start, scene.frame_end + 1)) \
        if settings["animation"] and animated(obj) else None


def drawn_images(scene, obj, settings, progress=None, only=None, samples=None, bounds=None):
    """Each layer of the drawing that draws something, drawn by Blender (render_layers, read
    back) → ([(name, depth, [ImageData per frame] or None, [its dark ones] or None)], bounds,
    frames or None, notes); only: the layers to draw (the others' images None); samples,
    bounds: render_layers'."""
    progress = progress or (lambda f: None)
    frames = drawing_frames(scene, obj, settings)
    folder = tempfile.mkdtemp(prefix="dynpaint-grease-pencil-")
    try:
        paths, bounds, notes, darks = render_layers(
            obj, folder, settings["resolution"], frames, progress, only=only,
            shade=settings["shade"], merge=settings["merge"], samples=samples, bounds=bounds)
        layers = drawn_layers(obj, settings["merge"])[0]
        # a group of merged layers (drawn_layers) lies where its back one does
        depths = layer_depths([group[0] for group in layers], bounds[1] - bounds[0],
                              settings["spacing"])
        drawn = [(layer_stem(i, layer), depth,
                  layer_paths and [read_image(path) for path in layer_paths],
                  dark_paths and [read_image(path) for path in dark_paths])
                 for i, (layer, layer_paths, dark_paths, depth)
                 in enumerate(zip(layers, paths, darks, depths))]
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return drawn, bounds, frames, notes


def made_paintings(drawn, settings, progress=None):
    """drawn_images' layers made paintings (layered_files.painting_of_frames; numpy alone, so
    a worker thread may run it: _Redraw) → ([(name, depth, {channel: ImageData}, params,
    [frames] table or None)], notes); a layer not drawn holds None for the last three."""
    made, notes = [], []
    for i, (name, depth, cells, dark) in enumerate(drawn):
        if cells is None:
            made.append((name, depth, None, None, None))
            continue
        images, p, lines, table = painting_of_frames(name, cells, settings["shade"],
                                                     settings["relief"], dark, effects(settings))
        notes += [f"{name}: {n}" for n in lines]
        made.append((name, depth, images, p, table))
        if progress is not None:
            progress((i + 1) / len(drawn))
    return made, notes


def drawn_paintings(scene, obj, settings, progress=None, only=None, samples=None,
                    bounds=None):
    """Each layer of the drawing that draws something, drawn by Blender and made a painting
    (drawn_images, made_paintings) → ([(name, depth, {channel: ImageData}, params, [frames]
    table or None)], bounds, frames or None, notes); only: the layers to draw (the
    others' entries hold None for their images, params and table); samples, bounds:
    render_layers'."""
    progress = progress or (lambda f: None)
    drawn, bounds, frames, notes = drawn_images(scene, obj, settings, lambda f: progress(0.4 * f),
                                                only, samples, bounds)
    made, lines = made_paintings(drawn, settings, lambda f: progress(0.4 + 0.3 * f))
    return made, bounds, frames, notes + lines


def light_drawing(context, obj, settings, progress=None, lights=None, painted=None,
                  bake="now"):
    """The drawing `obj` as a scene of lit layers (§15) where it is, the drawing hidden →
    (parent, notes). settings: LIT_SETTINGS' values (the operator's); lights: core Lights in
    the lit copy's frame, added where the scene has none (default: the default sun);
    painted: drawn_paintings' result where it is made already (a redraw's, beside the UI);
    bake: build_layered's."""
    made, (x0, x1, z0, z1), frames, notes = painted or drawn_paintings(context.scene, obj,
                                                                       settings, progress)
    layers, tables, images = [], {}, {}
    for name, depth, imgs, p, table in made:
        images[name] = {c: packed_image(f"{obj.name} {name} {c}", img, c)
                        for c, img in imgs.items()}
        if table is not None:
            tables[name] = {"": {**table, "start": frames[0]}}
        layers.append((name, depth, (0.0, 0.0), 1.0, None, images[name], p))
    place = obj.matrix_world @ Matrix.Translation(((x0 + x1) / 2, 0.0, (z0 + z1) / 2)) @ \
        Matrix.Rotation(math.pi / 2, 4, "X")      # where the drawing is: its XZ plane
    with unchanged_images_on_failure():           # (its images are packed copies)
        parent, messages = build_layered(context, obj.name, layers, lights or [default_sun()],
                                         notes, x1 - x0, parallax=False, add_lights=True,
                                         frames=tables, place=place, bake=bake,
                                         name=f"{obj.name} (lit)")
    for mat in group_materials(parent):           # which layer each painting shows
        bright = mat.dynamic_painting.image_bright
        mat[LAYER] = next(n for n, imgs in images.items() if imgs["bright"] == bright)
    parent[SOURCE] = json.dumps({"object": obj.name, **settings, "layers": layer_digests(obj),
                                 "bounds": [x0, x1, z0, z1]})
    obj.hide_render = True
    obj.hide_set(True)
    return parent, [m for m in messages if NO_CAMERA not in m]


# how each kind of attribute is read: (field, dtype, values per element)
ATTRIBUTE_READS = {"FLOAT_VECTOR": ("vector", np.float32, 3), "FLOAT": ("value", np.float32, 1),
                   "INT": ("value", np.int32, 1), "BOOLEAN": ("value", np.bool_, 1),
                   "FLOAT_COLOR": ("color", np.float32, 4)}


MATERIAL_DRAWN = ("color", "fill_color", "show_fill", "show_stroke")   # what layer_digests reads


def _plain(value):
    return tuple(value) if hasattr(value, "__len__") else value


def layer_digests(obj):
    """{layer name: digest} of what each layer of the drawing is drawn from: its settings,
    place and frames' strokes (points, radii, opacities, materials), its shadow colours'
    layer's, and the materials' colours (their shadow colours' too) — what an edit of it
    changes (showing or hiding the drawing does not)."""
    materials = hashlib.sha1()
    for m in [*obj.data.materials, *shadow_materials(obj).values()]:
        g = getattr(m, "grease_pencil", None)
        if g is not None:          # an animated colour by its keys: not the frame's value
            curves = fcurves(m)
            moving = {fc.data_path for fc in curves}
            materials.update(repr((
                [_plain(getattr(g, f)) for f in MATERIAL_DRAWN
                 if f"grease_pencil.{f}" not in moving],
                [(fc.data_path, fc.array_index, [tuple(k.co) for k in fc.keyframe_points])
                 for fc in curves])).encode())
    out = {}
    for layer in obj.data.layers:
        digest = hashlib.sha1(materials.digest())
        digest.update(repr((layer.hide, layer.opacity, layer.blend_mode,
                            [list(r) for r in layer.matrix_local])).encode())
        for frame in layer.frames:
            digest.update(str(frame.frame_number).encode())
            attributes = frame.drawing.attributes
            for name in ("position", "radius", "opacity", "material_index", "cyclic"):
                if name in attributes:
                    attribute = attributes[name]
                    field, dtype, size = ATTRIBUTE_READS[attribute.data_type]
                    values = np.empty(len(attribute.data) * size, dtype)
                    attribute.data.foreach_get(field, values)
                    digest.update(values.tobytes())
        out[layer.name] = digest.hexdigest()
    for owner, partner in shadow_layers(obj).items():     # its shadow colours are its own
        out[owner] = hashlib.sha1((out[owner] + out[partner.name]).encode()).hexdigest()
    return out


def drawing_of(parent):
    """The name of the drawing a lit copy was made from."""
    return json.loads(parent[SOURCE])["object"]


def stale_lit_copies(scene, names):
    """The parents of lit copies in `scene` whose drawing, one of the objects `names`, has
    changed since they were drawn."""
    out = []
    for parent in (o for o in scene.objects if o.get(SOURCE)):
        source = json.loads(parent[SOURCE])
        obj = bpy.data.objects.get(source["object"])
        if source["object"] in names and obj is not None and obj.type == "GREASEPENCIL" \
                and source.get("layers") != layer_digests(obj):
            out.append(parent)
    return out


DRAFT_WIDTH = 128      # px: a stroke's draft drawing (Blender's draw costs its pixels here)
DRAFT_SAMPLES = 1      # and its anti-aliasing samples (each a draw of every pixel; SMAA stays)
_DRAFTED = {}          # lit copy's name → the layer digests its last draft drew


def _layer_materials(obj, parent, source, settings, bounds=True):
    """The lit copy's layer materials {stem: material}, or None where the drawing's layers or
    (with `bounds`) its bounds are not those it was made from (it is made anew then)."""
    mats = {m.get(LAYER): m for m in group_materials(parent)}
    same = set(mats) == {layer_stem(i, group) for i, group
                         in enumerate(drawn_layers(obj, settings["merge"])[0])} \
        and (not bounds or np.allclose(framing(obj), source["bounds"], rtol=0, atol=1e-9))
    return mats if same else None


def _in_place(mats, made):
    """The made paintings (drawn_paintings' entries) that can be written into the lit copy's
    materials `mats` → [(stem, images)], or None where one of them moves and its material
    does not, or the other way round (other frames: the lit copy is made anew)."""
    if any((table is None) != (not moves(mats[name]))
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
    return obj, {**lit_defaults(), **{k: source[k] for k in LIT_SETTINGS if k in source}}, \
        source


def _changed(obj, recorded):
    """(the drawing's layer digests now, the names of the layers whose digest is not the one
    `recorded`)."""
    digests = layer_digests(obj)
    return digests, {n for n, d in digests.items() if recorded.get(n) != d}


def refresh_lit_drawing(context, parent, beside=None):
    """Redraw the lit copy `parent` from its drawing as it is now: the layers that changed
    (layer_digests) drawn again and their images written in place where the layers, the
    drawing's bounds, sizes and frames are as before (their edits noted, so the group bakes
    again), else the lit copy made anew → the parent (a new one then). beside (default:
    with a UI, rendering() not): Blender draws the layers now (all of them where the lit
    copy is made anew) and a worker thread makes them paintings; finish_redraws writes them
    once made, or makes the lit copy anew from them, if the drawing is still as drawn."""
    found = _source(parent)
    if found is None:
        return parent
    obj, settings, source = found
    _DRAFTED.pop(parent.name, None)                # (drafts are drawn over from here)
    digests, changed = _changed(obj, source.get("layers", {}))
    mats = _layer_materials(obj, parent, source, settings)
    if not rendering() if beside is None else beside:
        drawn, bounds, frames, notes = drawn_images(
            context.scene, obj, settings, only=None if mats is None else changed)
        _REDRAWS[parent.name] = _Redraw(digests, drawn, settings,
                                        anew=None if mats is not None else (bounds, frames, notes))
        if not bpy.app.timers.is_registered(finish_redraws):
            bpy.app.timers.register(finish_redraws, first_interval=POLL_S)
        return parent
    made = None if mats is None else \
        _in_place(mats, drawn_paintings(context.scene, obj, settings, only=changed)[0])
    return _write_redraw(context, parent, mats, made, obj, settings, source, digests)


def _made_anew(context, parent, obj, settings, painted=None, beside=False):
    """The lit copy `parent` removed (its images too) and made again from its drawing (its
    bounds, layers, sizes or frames are no longer those it was made from) → the new parent.
    painted: light_drawing's; beside the UI, its shadows baked as a dragged light's: a
    draft now, the final in a worker thread (bake_group_live)."""
    hidden = obj.hide_get()
    remove_objects(list(parent.children) + [parent], images=True)
    obj.hide_set(False)
    parent, _ = light_drawing(context, obj, settings, painted=painted,
                              bake="live" if beside else "now")
    obj.hide_set(hidden or obj.hide_get())
    return parent


def _write_redraw(context, parent, mats, made, obj, settings, source, digests, beside=False):
    """The made paintings written into the lit copy's images in place (packed) and its
    record updated, or the lit copy made anew where they cannot be (made None, or an image
    of another size or kind) → the parent. The group is baked now, or `beside` the UI: at
    its own quality in a worker thread (final_bake_due)."""
    written = []
    for name, imgs in made or ():
        for channel, data in imgs.items():
            img = getattr(mats[name].dynamic_painting, f"image_{channel}")
            if img is None or not refill_packed_image(img, data):
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
    """A full redraw's layers, drawn by Blender, made paintings in a worker thread (the
    inflation of a changed part at full size takes a second at 1024²) while the UI goes on.
    anew: (bounds, frames, notes) of drawn_images where the lit copy is made anew from them
    (a stroke beyond the drawing's bounds: every layer drawn again), else None."""

    def __init__(self, digests, drawn, settings, anew=None):
        self.digests, self.anew, self.made, self.error = digests, anew, None, None
        self.thread = threading.Thread(target=self._run, args=(drawn, settings), daemon=True)
        self.thread.start()

    def _run(self, drawn, settings):
        try:
            self.made = made_paintings(drawn, settings)[0]
        except Exception as exc:        # (said on the main thread: finish_redraws)
            self.error = exc


def finish_redraws():
    """Timer: the full redraws whose paintings are made written into their lit copies
    (_write_redraw) or made their lit copies anew (_made_anew, its shadows baked as a
    dragged light's: a draft now, final in a worker), where the drawing is still as Blender
    drew it — else dropped: the strokes since are drafted, and their own full redraw
    follows. → seconds to the next call (None: none left)."""
    for name, job in list(_REDRAWS.items()):
        if job.thread.is_alive():
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
                    bounds, frames, notes = job.anew
                    _made_anew(bpy.context, parent, obj, settings,
                               (job.made, bounds, frames, notes), beside=True)
                else:
                    _write_redraw(bpy.context, parent, mats, _in_place(mats, job.made), obj,
                                  settings, source, job.digests, beside=True)
        except Exception as exc:        # never into Blender's timer loop
            report(name, exc)
    return POLL_S if _REDRAWS else None


def forget_drafts():
    """Another file is open, or undo: the drafts' digests and the redraws under way may be
    of other drawings."""
    _DRAFTED.clear()
    _REDRAWS.clear()


def draft_lit_drawing(context, parent):
    """A stroke while the artist draws (issue 42: draft while drawing, final after): the
    layers that changed since the last draft drawn at DRAFT_WIDTH px across (DRAFT_SAMPLES
    a pixel) and made paintings there (their relief inflated at that size), enlarged into
    their images (refill_enlarged) and the group's shadows drafted from its layers made as
    small (draft_group), in the lit copy's framing (a stroke past the drawing's bounds shows
    as far as they reach: the full redraw makes the lit copy anew). Nothing is packed and
    the lit copy's record is left as it was: refresh_lit_drawing draws them at full size
    once the strokes stop. → whether it drew (False: nothing new, or other layers or
    frames, or a layer that moves: those wait for the full redraw)."""
    found = _source(parent)
    if found is None:
        return False
    obj, settings, source = found
    digests, changed = _changed(obj, _DRAFTED.get(parent.name, source.get("layers", {})))
    mats = _layer_materials(obj, parent, source, settings, bounds=False)
    if not changed or mats is None:
        return False
    small = {**settings, "resolution": min(DRAFT_WIDTH, settings["resolution"]),
             "animation": False}
    made = _in_place(mats, drawn_paintings(context.scene, obj, small, only=changed,
                                           samples=DRAFT_SAMPLES, bounds=source["bounds"])[0])
    if made is None:
        return False
    written = []
    for name, imgs in made:
        for channel, data in imgs.items():
            img = getattr(mats[name].dynamic_painting, f"image_{channel}")
            if img is not None and refill_enlarged(img, data):
                written.append(img.name)
    _DRAFTED[parent.name] = digests
    note_edited(written)
    draft_group(parent, {mats[name].name: imgs for name, imgs in made})
    for name, imgs in made:         # their derived images from the small ones; the shadows
        update(mats[name], context.scene, bake="none", small=imgs)     # the draft's
    return True


def light_recipe_drawing(context, recipe, location=(0.0, 0.0, 0.0), width=None):
    """A recipe's drawing (its `drawing`, inputs/drawings.py) built in the scene, the scene's
    frames set to the drawing's, and lit as From Grease Pencil lights it by default (each
    layer drawn `width` pixels across, when given), with the recipe's lights → (parent,
    notes)."""
    drawing = load_drawing(recipe.drawing)
    scene = context.scene
    scene.frame_start, scene.frame_end = frame_range(drawing)
    scene.frame_set(scene.frame_start)
    obj = build_drawing(scene, drawing, location)
    settings = lit_defaults()
    if width:
        settings["resolution"] = int(width)
    return light_drawing(context, obj, settings, lights=recipe.lights)


def lit_defaults():
    """From Grease Pencil's settings as its dialog starts them (LIT_SETTINGS)."""
    return {"resolution": GREASE_PENCIL_RESOLUTION, "spacing": DEFAULT_SPACING,
            "shade": DEFAULT_SHADE, "relief": GREASE_PENCIL_RELIEF, "animation": True,
            "merge": False,
            **{o.name: o.default for o in LAYER_EFFECTS}}


def effects(settings):
    """The relief effects of From Grease Pencil's settings (LAYER_EFFECTS) → make_shape's
    keywords."""
    return {o.name: settings[o.name] for o in LAYER_EFFECTS}
