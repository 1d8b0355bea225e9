"""Each layer of a drawing drawn by Blender's own Grease Pencil renderer into an image with
its alpha (issue 42): in a scene of its own (drawing_settings), framed by an orthographic
camera over the drawing's bounds on every frame, moved by where Blender's anti-aliasing puts
a drawing (drawn_offset); the shadow colours drawn as the layer's dark image.
"""
import contextlib
import math
import os

import numpy as np

import bpy
from mathutils import Matrix, Vector

from ....core.sampling import box_reduced
from ....inputs import memory
from ....inputs.imageio import quiet_native, read_image, write_png
from ....inputs.layered_files import DEFAULT_SHADE
from .building import add_fill, fill_material
from .reading import (MARGIN, drawn_layers, framing, layer_stem, materials_used,
                      shadow_layers, shadow_materials, shown_keyframes)


def render_layers(obj, folder, width_px, frames=None, progress=None, margin=MARGIN,
                  only=None, shade=DEFAULT_SHADE, merge=False, samples=None, bounds=None,
                  supersample=None):
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
    draft keeps its lit copy's); supersample: drawn that many times as large and averaged
    (default: supersampling's choice). A frame that shows what an earlier one showed
    (shown_keyframes) is drawn once. The artist's scene, the object, its layers and
    materials are left as they were."""
    layers, notes = drawn_layers(obj, merge)
    x0, x1, z0, z1 = bounds = framing(obj, margin) if bounds is None else tuple(bounds)
    w, h = drawn_size(bounds, width_px)
    artist = bpy.context.scene
    frames = [artist.frame_current] if frames is None else list(frames)
    check_drawing_memory(obj, layers, frames, w, h, only)
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
                drawn[key] = draw_reduced(
                    scene, f"{stem}.png" if len(frames) == 1 else f"{stem}_{frame:04d}.png", k)
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
        k, drawn_samples = supersampling(w, samples or artist.grease_pencil_settings.aa_samples,
                                         supersample)
        drawing_settings(scene, drawn_samples,
                         artist.grease_pencil_settings.antialias_threshold_render)
        # the camera moved by where Blender's anti-aliasing puts a drawing (drawn_offset)
        dx, dy = drawn_offset(scene, folder)
        pixel = (x1 - x0) / (w * k)
        cam.matrix_world = Matrix.Translation(
            middle + look.col[2] * 10.0 * (x1 - x0)
            + (look.col[0] * dx + look.col[1] * dy) * pixel) @ look.to_4x4()
        cam.data.clip_end = 100.0 * (x1 - x0)
        scene.camera = cam
        r.resolution_x, r.resolution_y, r.resolution_percentage = w * k, h * k, 100
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


# Blender's Grease Pencil anti-aliasing spreads an edge over ~2 px either side whatever its
# samples (the small shadows one layer casts on another lose their width: the middle layer's
# at 512², sharp sun at 45°, IoU 0.940 against exact coverage's 0.988). Drawn twice as large
# at a quarter of the samples (as many samples in all) and averaged 2 × 2 the edges are exact
# coverage's (0.988), for 1.4–1.6× the drawing's time on this 2-core machine (three layers:
# 0.69 → 0.96 s at 256 px, 2.2 → 3.5 s at 512; the larger file is read and written again);
# from 1024 px on it changes nothing (0.989 either way), so larger drawings are drawn as
# they are.
SUPERSAMPLE = 2
SUPERSAMPLED_BELOW = 1024


def supersampling(width_px, samples, supersample=None):
    """(k, samples per drawn pixel): a drawing `width_px` across at `samples` anti-aliasing
    samples per pixel is drawn k times as large at that many samples, then averaged
    (draw_reduced) — SUPERSAMPLE below SUPERSAMPLED_BELOW px where the samples can be
    shared out (≥ 4: a stroke's 1-sample draft is drawn as it is); `supersample`: k asked
    for (the samples shared out as far as they go)."""
    k = supersample or (SUPERSAMPLE if width_px < SUPERSAMPLED_BELOW
                        and samples >= SUPERSAMPLE ** 2 else 1)
    return k, max(1, samples // (k * k))


def draw_reduced(scene, path, k):
    """draw_still, the drawing then averaged k × k (sampling.box_reduced) into the same file
    (16-bit) → path."""
    draw_still(scene, path)
    if k > 1:
        write_png(path, box_reduced(read_image(path).pixels, k), bits=16, level=0)
    return path


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


def check_drawing_memory(obj, layers, frames, w, h, only=None):
    """memory.check of drawing_memory: refused, with what to do, where it does not fit."""
    memory.check(*drawing_memory(obj, layers, frames, w, h, only),
                 "draw it smaller (From Grease Pencil's Resolution, --width on the command "
                 "line) or over fewer frames (the scene's frame range)")


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
