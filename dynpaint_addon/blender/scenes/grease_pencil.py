"""A Grease Pencil drawing as a scene of lit layers (issue 42, first step; pipeline.md §15).

Grease Pencil cannot be lit (its material is not a BSDF: blender-notes.md). Here each of a
drawing's layers is drawn by **Blender's own Grease Pencil renderer** — its materials, fills,
textures, modifiers and effects; no rasterizer of ours — into an image with its alpha, unlit
(the layer's *Use Lights* off while it renders), in a scene of its own so nothing else of the
artist's scene is drawn or changed: Workbench, the Standard view transform (the colours as
drawn), transparent film, an orthographic camera framing the drawing's bounds over all its
frames (so every frame of an animation lands on the same pixels). The images are a folder of
layers, back to front, which Add › Layered… builds as a scene of layers (§15): each a bright
image with its alpha, a shaded dark copy and its silhouette inflated by parts.
"""
import math
import os

import numpy as np

import bpy
from mathutils import Matrix, Vector

from ...core.layers import MAX_LAYERS
from ...errors import UserError

MARGIN = 0.02          # of the drawing's size, around its bounds (strokes' round caps)


class GreasePencilError(UserError):
    """A Grease Pencil object that cannot be made a painting; the message says why."""


def drawn_layers(obj):
    """The layers of a Grease Pencil object that draw something, back to front → (layers,
    notes about the layers left out: hidden, no frames, nothing drawn)."""
    if obj is None or obj.type != "GREASEPENCIL":
        raise GreasePencilError(f"{getattr(obj, 'name', 'nothing')} is not a Grease Pencil "
                                f"object: select the drawing to light")
    kept, notes = [], []
    for layer in obj.data.layers:          # the first layer is drawn first: the back one
        if layer.hide:
            notes.append(f"{layer.name}: hidden, left out (show it to light it)")
        elif not len(layer.frames):
            notes.append(f"{layer.name}: no frames, left out")
        elif not any(len(f.drawing.strokes) for f in layer.frames):
            notes.append(f"{layer.name}: nothing drawn, left out")
        else:
            kept.append(layer)
    if not kept:
        raise GreasePencilError(f"{obj.name} has no layer that draws anything"
                                + (f" ({'; '.join(notes)})" if notes else ""))
    if len(kept) > MAX_LAYERS:
        raise GreasePencilError(
            f"{obj.name} has {len(kept)} layers that draw; a scene of lit layers holds at most "
            f"{MAX_LAYERS} (§15): merge some ({', '.join(layer.name for layer in kept)}) or "
            f"hide those that need no light of their own")
    return kept, notes


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
    animated data (layer transforms, modifiers' settings)."""
    return any(len(layer.frames) > 1 for layer in obj.data.layers) or \
        obj.data.animation_data is not None or obj.animation_data is not None


def _points(layer):
    """Every point of every frame of a layer in the object's space, and its radius."""
    out, radii = [], []
    m = np.array(layer.matrix_local)
    for frame in layer.frames:
        drawing = frame.drawing
        n = drawing.attributes.domain_size("POINT") if hasattr(drawing, "attributes") else 0
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


def drawing_bounds(layers):
    """(x0, x1, z0, z1): the drawing's extent in its object's X (right) and Z (up) over all
    frames of `layers`, strokes' radii included, with a MARGIN (Grease Pencil draws on the
    XZ plane, seen from −Y)."""
    pts, radii = zip(*(_points(layer) for layer in layers))
    pts, radii = np.concatenate(pts), np.concatenate(radii)
    x0, x1 = float((pts[:, 0] - radii).min()), float((pts[:, 0] + radii).max())
    z0, z1 = float((pts[:, 2] - radii).min()), float((pts[:, 2] + radii).max())
    pad = MARGIN * max(x1 - x0, z1 - z0, 1e-6)
    return x0 - pad, x1 + pad, z0 - pad, z1 + pad


def render_layers(obj, folder, width_px, frames=None, progress=None):
    """Draw each layer of the Grease Pencil object `obj` that draws something, alone, into
    `folder` (16-bit RGBA, sRGB as drawn) on each scene frame of `frames` (default: the
    current one) → (paths, bounds, notes): paths[i][k] layer i's (back to front) drawing on
    frames[k], named NN_name.png for one frame, NN_name_FFFF.png for several. The artist's
    scene, the object and its layers are left as they were."""
    layers, notes = drawn_layers(obj)
    # framed by every layer that draws, hidden ones too: hiding one keeps the others in place
    x0, x1, z0, z1 = drawing_bounds([layer for layer in obj.data.layers
                                     if any(len(f.drawing.strokes) for f in layer.frames)])
    w = max(1, int(width_px))
    h = max(1, round(w * (z1 - z0) / (x1 - x0)))
    os.makedirs(folder, exist_ok=True)
    frames = [bpy.context.scene.frame_current] if frames is None else list(frames)
    scene = bpy.data.scenes.new(f"{obj.name} layers (Dynamic Painting)")
    cam = bpy.data.objects.new(f"{obj.name} layers camera", bpy.data.cameras.new("DP camera"))
    saved = [(layer, layer.hide, layer.use_lights) for layer in obj.data.layers]
    hidden = obj.hide_render
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
        cam.matrix_world = Matrix.Translation(middle + look.col[2] * 10.0 * (x1 - x0)) @ \
            look.to_4x4()
        cam.data.clip_end = 100.0 * (x1 - x0)
        scene.camera = cam
        r = scene.render
        r.engine = "BLENDER_WORKBENCH"
        r.resolution_x, r.resolution_y, r.resolution_percentage = w, h, 100
        r.film_transparent = True
        r.image_settings.file_format = "PNG"
        r.image_settings.color_mode = "RGBA"
        r.image_settings.color_depth = "16"
        scene.view_settings.view_transform = "Standard"
        scene.view_settings.look = "None"
        paths = []
        for i, layer in enumerate(layers):
            for other in obj.data.layers:
                other.hide = other.name != layer.name
                other.use_lights = False          # drawn as painted: the lights come later
            stem = os.path.join(folder, f"{i + 1:02d}_{bpy.path.clean_name(layer.name)}")
            paths.append([])
            for k, frame in enumerate(frames):
                scene.frame_set(frame)
                r.filepath = f"{stem}.png" if len(frames) == 1 else f"{stem}_{frame:04d}.png"
                with bpy.context.temp_override(scene=scene):
                    bpy.ops.render.render(write_still=True, scene=scene.name)
                paths[-1].append(r.filepath)
                if progress is not None:
                    progress((i * len(frames) + k + 1) / (len(layers) * len(frames)))
    finally:
        obj.hide_render = hidden
        for layer, hide, lights in saved:
            layer.hide, layer.use_lights = hide, lights
        bpy.data.objects.remove(cam)
        bpy.data.scenes.remove(scene)
    return paths, (x0, x1, z0, z1), notes
