"""A drawing's layers drawn by numpy (issue 61): each layer's strokes on a frame read into plain
arrays on Blender's main thread (a few milliseconds: attribute buffers), then drawn — fills
and round-capped lines, their colours mixed as Grease Pencil mixes them (core/raster.py) — in
any thread, into the image Blender's renderer would write (16-bit, sRGB-encoded, straight
alpha). What it does not draw (textures, gradients, blend modes, masks, modifiers, effects,
curves that are not polylines, soft or flat-capped lines, holdouts, tints, animated
layers and materials) is named by unsupported(), and Blender's renderer draws that drawing
(drawing.py).
"""
from dataclasses import dataclass

import numpy as np

from ....core.colour import linear_to_srgb16
from ....core.input_rules import ImageData
from ....core.raster import over, polygon_coverage, stroke_coverage
from ....core.strokes import box_of
from .reading import (attribute_values, material_drawn, materials_used, shadow_layers,
                      shadow_materials, shown_keyframes)

POLY = 1               # Grease Pencil's curve_type of a polyline (what its draw tool makes)
ROUND = 0              # a round cap (start_cap, end_cap)
# what a drawing's attribute holds where it is absent (Blender's defaults)
DEFAULTS = {"radius": 0.01, "opacity": 1.0, "vertex_color": 0.0, "material_index": 0,
            "cyclic": False, "fill_color": 0.0, "fill_opacity": 1.0, "start_cap": ROUND,
            "end_cap": ROUND, "softness": 0.0, "curve_type": 0, "hide_stroke": False,
            "fill_id": 0}


@dataclass
class Style:
    """How a material slot draws (linear RGBA colours; fill and line: whether it draws them,
    up to Blender 5.2 — 5.3 asks each stroke)."""
    line: tuple
    fill_colour: tuple
    fill: bool = True
    stroke: bool = True
    hidden: bool = False


@dataclass
class Strokes:
    """One layer's strokes on one keyframe, in the drawing's XZ plane (its object's space,
    the layer's transform applied): `offsets` (S + 1) into the points' `xz` (P, 2),
    `radius`, `opacity` (P), `vertex` (P, 4); per stroke `material`, `cyclic`,
    `fill_colour` (S, 4), `fill_opacity`, and (5.3) `filled`, `outlined`."""
    offsets: np.ndarray
    xz: np.ndarray
    radius: np.ndarray
    opacity: np.ndarray
    vertex: np.ndarray
    material: np.ndarray
    cyclic: np.ndarray
    fill_colour: np.ndarray
    fill_opacity: np.ndarray
    filled: np.ndarray = None
    outlined: np.ndarray = None


def unsupported(obj, groups):
    """Why numpy cannot draw the layers `groups` (drawn_layers') of the drawing `obj` as
    Blender does — the first thing it does not draw, in words — or None."""
    if len(obj.modifiers) or len(obj.shader_effects):
        return "its modifiers or effects"
    if obj.data.animation_data is not None or \
            any(m is not None and m.animation_data is not None for m in obj.data.materials):
        return "its animated layers or materials"      # (evaluated by Blender's frames)
    if obj.data.stroke_depth_order != "2D":
        return "its strokes ordered by depth"
    for slot in obj.material_slots:
        g = slot.material and slot.material.grease_pencil
        if g is None:
            continue
        if g.mode != "LINE" or g.stroke_style != "SOLID" or g.fill_style != "SOLID":
            return f"material {slot.material.name}'s textures, gradients or dots"
        if g.use_stroke_holdout or g.use_fill_holdout:
            return f"material {slot.material.name}'s holdout"
    for group in groups:
        for layer in group:
            if layer.blend_mode != "REGULAR" or layer.tint_factor > 0 or \
                    layer.radius_offset != 0 or (layer.use_masks and len(layer.mask_layers)) \
                    or layer.parent is not None:
                return f"layer {layer.name}'s blend mode, tint, radius offset, masks or parent"
            for frame in layer.frames:
                why = _unsupported_strokes(frame.drawing)
                if why:
                    return f"layer {layer.name}'s {why}"
    return None


def _unsupported_strokes(drawing):
    if not len(drawing.strokes):
        return None
    kinds = attribute_values(drawing, "curve_type")
    if kinds is None or np.any(kinds != POLY):
        return "curves (not polylines)"
    for name in ("start_cap", "end_cap"):
        caps = attribute_values(drawing, name)
        if caps is not None and np.any(caps != ROUND):
            return "flat caps"
    soft = attribute_values(drawing, "softness")
    if soft is not None and np.any(soft != 0):
        return "soft lines"
    fills = attribute_values(drawing, "fill_id")       # (5.3: strokes sharing an id fill as one)
    if fills is not None and len(np.unique(fills[fills != 0])) < np.count_nonzero(fills):
        return "strokes that fill together"
    return None


def _style(material, shade=1.0):
    """A material's Style, its colours `shade` × as drawn (alphas kept)."""
    g = material and material.grease_pencil
    if g is None:
        return Style((0, 0, 0, 0), (0, 0, 0, 0), False, False, True)
    drawn = material_drawn()

    def dim(c):
        return (c[0] * shade, c[1] * shade, c[2] * shade, c[3])
    return Style(dim(g.color), dim(g.fill_color), g.show_fill if "show_fill" in drawn else True,
                 g.show_stroke if "show_stroke" in drawn else True, g.hide)


def styles(obj, shadow=None):
    """[Style] of each material slot of the drawing (a slot without a Grease Pencil material
    draws nothing); shadow: the shade of the shadow colours — each slot with a partner
    material ("<name> shadow") drawn in its colours, the others `shadow` × theirs (as
    drawing.materials_in_shadow swaps them for Blender's renderer)."""
    partners = shadow_materials(obj) if shadow is not None else {}
    out = [_style(partners[k]) if k in partners else
           _style(slot.material, 1.0 if shadow is None else shadow)
           for k, slot in enumerate(obj.material_slots)]
    return out or [Style((0, 0, 0, 1), (0, 0, 0, 1), False, True)]


def read_strokes(layer, frame_number):
    """The strokes of `layer` shown on scene frame `frame_number` (its last keyframe at or
    before it) → Strokes, or None where it shows none."""
    frame = None
    for f in layer.frames:
        if f.frame_number <= frame_number and (frame is None
                                               or f.frame_number > frame.frame_number):
            frame = f
    if frame is None or not len(frame.drawing.strokes):
        return None
    drawing = frame.drawing
    s = len(drawing.strokes)
    p = drawing.attributes.domain_size("POINT")
    offsets = np.empty(s + 1, np.int32)
    drawing.curve_offsets.foreach_get("value", offsets)
    position = attribute_values(drawing, "position").astype(np.float64)
    m = np.array(layer.matrix_local)
    position = position @ m[:3, :3].T + m[:3, 3]

    def get(name, size, shape=()):
        got = attribute_values(drawing, name)
        return np.full((size, *shape), DEFAULTS[name]) if got is None else got
    # 5.3: each stroke says whether it is filled (fill_id 0: not) and outlined
    per_stroke = "show_fill" not in material_drawn()
    return Strokes(offsets, position[:, [0, 2]], get("radius", p), get("opacity", p),
                   get("vertex_color", p, (4,)), get("material_index", s), get("cyclic", s),
                   get("fill_color", s, (4,)), get("fill_opacity", s),
                   get("fill_id", s) != 0 if per_stroke else None,
                   ~get("hide_stroke", s).astype(bool) if per_stroke else None)


def _read_group(obj, group, frames):
    """[(Strokes of each layer of `group`, their opacities)] on each of `frames`; a frame
    showing what an earlier one showed (shown_keyframes) holds the same tuple."""
    seen, out = {}, []
    for frame, key in zip(frames, shown_keyframes(obj, group, frames)):
        if key not in seen:
            seen[key] = ([read_strokes(layer, frame) for layer in group],
                         [layer.opacity for layer in group])
        out.append(seen[key])
    return out


@dataclass
class ReadDrawing:
    """A drawing's lit layers read for numpy to draw (read_drawing: on the main thread;
    draw: in any). groups[i]: None where the group is not drawn, else (its frames'
    _read_group, the shadow colours' or None, their styles or None)."""
    groups: list
    styles: list
    bounds: tuple
    size: tuple

    def draw(self, progress=None):
        """→ (cells, darks): each group's ImageData per frame (None: not drawn) and its dark
        images per frame where the artist named shadow colours (else None) — what
        drawing.render_layers draws, read back."""
        w, h = self.size
        cells, darks, done = [], [], [0]
        total = sum(g is not None for g in self.groups) or 1

        def drawn(frames, styles_):
            made = {}
            for k in frames:
                if id(k) not in made:
                    made[id(k)] = draw_layers(*k, styles_, self.bounds, w, h)
            return [made[id(k)] for k in frames]
        for group in self.groups:
            if group is None:
                cells.append(None)
                darks.append(None)
                continue
            frames, dark_frames, dark_styles = group
            cells.append(drawn(frames, self.styles))
            darks.append(None if dark_frames is None else drawn(dark_frames, dark_styles))
            done[0] += 1
            if progress is not None:
                progress(done[0] / total)
        return cells, darks


def read_drawing(obj, groups, frames, bounds, size, shade, only=None):
    """What numpy needs to draw the groups of layers `groups` (drawn_layers') of the drawing
    `obj` on scene `frames` in the framing `bounds` at `size` (w, h) → ReadDrawing; only:
    the names of the layers to draw (drawing.render_layers' rules: a group is drawn if any
    of its layers is named; its dark images from its "<name> shadow" layers, else from its
    materials' "<material> shadow" partners, the others at `shade`)."""
    partner_layers, partner_materials = shadow_layers(obj), shadow_materials(obj)
    shadow_styles = styles(obj, shadow=shade)
    out = []
    for group in groups:
        if only is not None and not only & {layer.name for layer in group}:
            out.append(None)
            continue
        partners = tuple(partner_layers[layer.name] for layer in group
                         if layer.name in partner_layers)
        if partners:
            dark = (_read_group(obj, partners, frames), None)
        elif partner_materials.keys() & set().union(*map(materials_used, group)):
            dark = (_read_group(obj, group, frames), shadow_styles)
        else:
            dark = (None, None)
        out.append((_read_group(obj, group, frames), *dark))
    plain = styles(obj)
    return ReadDrawing([None if g is None else (g[0], g[1], g[2] or plain) for g in out],
                       plain, tuple(bounds), tuple(size))


def draw_layers(strokes, opacities, styles_, bounds, width, height):
    """Layers' strokes (read_strokes', back to front; None: nothing) drawn into the framing
    `bounds` (x0, x1, z0, z1) at width × height, each layer over those behind at its
    opacity → ImageData as Blender's renderer writes a layer (16-bit, sRGB-encoded, straight
    alpha, row 0 at the bottom)."""
    rgba = np.zeros((height, width, 4), np.float32)       # linear, premultiplied
    for st, layer_opacity in zip(strokes, opacities):
        if st is None or layer_opacity <= 0:
            continue
        if layer_opacity >= 1:
            _draw_strokes(rgba, st, styles_, bounds)
            continue
        alone = _draw_strokes(np.zeros_like(rgba), st, styles_, bounds)
        rgba *= 1 - layer_opacity * alone[..., 3:]         # a layer blended as a whole
        rgba += layer_opacity * alone
    return straight_srgb(rgba)


def _draw_strokes(rgba, st, styles_, bounds):
    """One layer's Strokes drawn in order over premultiplied `rgba` (updated) → rgba: each
    stroke's fill, then its line — colours mixed with the strokes' vertex colours by their
    alphas, alphas × the points' or the fill's opacity, as Grease Pencil mixes them."""
    height, width = rgba.shape[:2]
    x0, x1, z0, z1 = bounds
    scale = width / (x1 - x0)
    px = np.column_stack([(st.xz[:, 0] - x0) * scale,
                          (st.xz[:, 1] - (z0 + z1) / 2) * scale + height / 2])
    for k in range(len(st.offsets) - 1):
        a, b = st.offsets[k], st.offsets[k + 1]
        style = styles_[min(int(st.material[k]), len(styles_) - 1)]
        if style.hidden:
            continue
        if (style.fill if st.filled is None else st.filled[k]) and b - a >= 3:
            v = st.fill_colour[k]
            colour = np.asarray(style.fill_colour[:3]) * (1 - v[3]) + v[:3] * v[3]
            over(rgba, colour, polygon_coverage(px[a:b], height, width),
                 style.fill_colour[3] * st.fill_opacity[k])
        if style.stroke if st.outlined is None else st.outlined[k]:
            per_point = np.column_stack([st.vertex[a:b], st.opacity[a:b]])
            cover, values, at = stroke_coverage(px[a:b], st.radius[a:b] * scale, height,
                                                width, bool(st.cyclic[k]), per_point)
            v = values[..., 3:4]
            over(rgba, np.asarray(style.line[:3], np.float32) * (1 - v) + values[..., :3] * v,
                 (cover, at), style.line[3] * values[..., 4])
    return rgba


def straight_srgb(rgba):
    """Linear premultiplied RGBA → ImageData as Blender writes a 16-bit PNG of it with the
    Standard view transform: colour divided by alpha, sRGB-encoded, both quantised."""
    out = np.zeros_like(rgba)                   # (where nothing is drawn: clear black)
    box = box_of(rgba[..., 3] > 0)
    if box is not None:                         # (a layer's strokes cover a part of it)
        r0, r1, c0, c1 = box
        part = rgba[r0:r1, c0:c1]
        a = np.minimum(part[..., 3], 1.0)
        alpha = out[r0:r1, c0:c1, 3]
        alpha[:] = np.round(a * 65535) / 65535
        inverse = np.divide(1.0, a, out=np.zeros_like(a), where=alpha > 0)   # none: black
        out[r0:r1, c0:c1, :3] = linear_to_srgb16(part[..., :3] * inverse[..., None])
    return ImageData(out, bits=16)
