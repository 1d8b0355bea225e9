"""What a Grease Pencil object holds, read for lighting it (issue 42): the layers that draw
(back to front, grouped where more than a scene holds), the shadow colours an artist named
("<name> shadow" layers and materials), each layer's depth and what it shows on each frame,
the drawing's bounds, and a digest of what each layer is drawn from (what an edit changes).
"""
import hashlib

import numpy as np

import bpy

from ....core.layers import MAX_LAYERS
from ....errors import UserError
from ...state.animation import fcurves

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


def stem_layers(stem):
    """A layer_stem without its place in the stack (NN_): what it draws, whatever its place
    (a layer added behind it moves that)."""
    return stem.split("_", 1)[-1]


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
        pos = attribute_values(frame.drawing, "position")
        if pos is None or not len(pos):
            continue
        radius = attribute_values(frame.drawing, "radius")
        out.append(pos @ m[:3, :3].T + m[:3, 3])
        radii.append(np.zeros(len(pos), np.float32) if radius is None else radius)
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


def materials_used(layer):
    """The material slot indices a layer's strokes use, on any of its frames."""
    used = set()
    for frame in layer.frames:
        values = attribute_values(frame.drawing, "material_index")
        if values is None:
            used.add(0)
            continue
        used.update(int(v) for v in np.unique(values))
    return used


# how each kind of attribute is read: (field, dtype, values per element)
ATTRIBUTE_READS = {"FLOAT_VECTOR": ("vector", np.float32, 3), "FLOAT": ("value", np.float32, 1),
                   "INT": ("value", np.int32, 1), "BOOLEAN": ("value", np.bool_, 1),
                   "FLOAT_COLOR": ("color", np.float32, 4), "INT8": ("value", np.int8, 1)}


def attribute_values(drawing, name):
    """A drawing's attribute `name` as an array ((n,), or (n, k) for vectors and colours),
    or None where it is absent or of a kind not read (ATTRIBUTE_READS)."""
    attribute = drawing.attributes.get(name)
    if attribute is None or attribute.data_type not in ATTRIBUTE_READS:
        return None
    field, dtype, size = ATTRIBUTE_READS[attribute.data_type]
    values = np.empty(len(attribute.data) * size, dtype)
    attribute.data.foreach_get(field, values)
    return values.reshape(-1, size) if size > 1 else values


def material_drawn():
    """The fields of a Grease Pencil material that decide how its strokes are drawn (what
    layer_digests reads): colours, and up to Blender 5.2 whether it fills and outlines them —
    5.3 keeps that on each stroke (fill_id, hide_stroke: STROKE_DRAWN) and deprecates the
    material's show_fill and show_stroke (blender-notes.md)."""
    props = bpy.types.MaterialGPencilStyle.bl_rna.properties
    return tuple(f for f in ("color", "fill_color", "show_fill", "show_stroke")
                 if not getattr(props[f], "is_deprecated", False))


# A drawing's attributes that decide what its strokes draw (those a Blender has: fill_id and
# hide_stroke since 5.3)
STROKE_DRAWN = ("position", "radius", "opacity", "material_index", "cyclic", "fill_id",
                "hide_stroke", "fill_opacity", "fill_color", "vertex_color", "softness")


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
                [_plain(getattr(g, f)) for f in material_drawn()
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
            for name in STROKE_DRAWN:
                values = attribute_values(frame.drawing, name)
                if values is not None:
                    digest.update(values.tobytes())
        out[layer.name] = digest.hexdigest()
    for owner, partner in shadow_layers(obj).items():     # its shadow colours are its own
        out[owner] = hashlib.sha1((out[owner] + out[partner.name]).encode()).hexdigest()
    return out
