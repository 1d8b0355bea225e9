"""Grease Pencil drawings made from Python (Blender 5.0's Grease Pencil v3, blender-notes.md):
filled shapes on layers, for the tests and benchmarks of From Grease Pencil (issue 42)."""
import math

import numpy as np

import bpy

from dynpaint_addon.blender.scenes.grease_pencil.building import (  # noqa: F401
    add_fill, build_drawing, fill_material)
from dynpaint_addon.blender.scenes.grease_pencil.reading import material_drawn
from dynpaint_addon.inputs.drawings import Drawing, DrawingLayer, Fill


def disc(cx, cz, r, n=48):
    return [(cx + r * math.cos(a), cz + r * math.sin(a))
            for a in np.linspace(0, 2 * math.pi, n, endpoint=False)]


def rectangle(x0, x1, z0, z1):
    return [(x0, z0), (x1, z0), (x1, z1), (x0, z1)]


def card_and_disc(scene, name="Drawing"):
    """A drawing of two layers: a blue card 2 × 1.5 (the back) and an orange disc of radius
    0.3 up and left of its middle (the front) → the Grease Pencil object, linked to scene."""
    gp = bpy.data.grease_pencils.new(name)
    obj = bpy.data.objects.new(name, gp)
    scene.collection.objects.link(obj)
    blue, orange = fill_material(gp, "blue", (0.2, 0.4, 0.8)), \
        fill_material(gp, "orange", (0.9, 0.5, 0.2))
    add_fill(gp.layers.new("Back"), rectangle(-1.0, 1.0, -0.75, 0.75), blue)
    add_fill(gp.layers.new("Figure"), disc(-0.3, 0.2, 0.3), orange)
    return obj


def figure_on_a_hill(scene, name="Figure on a hill"):
    """A drawing of three layers, back to front: a sky card, a hill, a figure (a head and a
    body) standing on it → the Grease Pencil object, linked to scene."""
    gp = bpy.data.grease_pencils.new(name)
    obj = bpy.data.objects.new(name, gp)
    scene.collection.objects.link(obj)
    sky = fill_material(gp, "sky", (0.35, 0.55, 0.85))
    hill = fill_material(gp, "hill", (0.25, 0.5, 0.15))
    coat = fill_material(gp, "coat", (0.75, 0.2, 0.1))
    skin = fill_material(gp, "skin", (0.9, 0.65, 0.45))
    add_fill(gp.layers.new("Sky"), rectangle(-1.0, 1.0, -0.75, 0.75), sky)
    add_fill(gp.layers.new("Hill"),
             [(x, -0.75 + 0.45 * math.cos(x * 1.2)) for x in np.linspace(-1.0, 1.0, 40)]
             + [(1.0, -0.75), (-1.0, -0.75)], hill)
    figure = gp.layers.new("Figure")
    add_fill(figure, rectangle(0.05, 0.35, -0.4, 0.15), coat)
    add_fill(figure, disc(0.2, 0.32, 0.14), skin)
    return obj


def figure_on_a_hill_in_the_sun(scene, name="Figure on a hill"):
    """figure_on_a_hill under a sun 40° high from the front left, the drawing active (what
    the cost benchmark and the stroke tests light) → the Grease Pencil object."""
    obj = figure_on_a_hill(scene, name)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.rotation_euler = (np.radians(50), 0, np.radians(-60))
    bpy.context.view_layer.objects.active = obj
    return obj


def rolling_disc(scene, name="Rolling disc", frames=(1, 2, 3)):
    """card_and_disc whose disc is drawn anew on each of `frames`, 0.25 further right each
    time (a keyframe per frame), the card still → the Grease Pencil object."""
    obj = card_and_disc(scene, name)
    figure = obj.data.layers["Figure"]
    for k, frame in enumerate(frames[1:], 1):
        add_fill(figure, disc(-0.3 + 0.25 * k, 0.2, 0.3), 1, frame=frame)
    return obj


def walking_drawing(frames=24, name="Walk"):
    """A drawing of three layers, back to front: a sky card and a still prop (a post, in
    front) that never change, and between them a figure (a body and a head) drawn anew on
    each of frames 1 … `frames` as it walks left to right → inputs.drawings.Drawing (the
    sample `walk` ships it as drawing.json)."""
    figure = []
    for f in range(1, frames + 1):
        x = -0.7 + 1.4 * (f - 1) / max(1, frames - 1)
        figure += [Fill("coat", rectangle(x - 0.1, x + 0.1, -0.5, 0.1), f),
                   Fill("coat", disc(x, 0.22, 0.1), f)]
    return Drawing(name, {"sky": (0.35, 0.55, 0.85), "coat": (0.75, 0.2, 0.1),
                          "wood": (0.45, 0.3, 0.15)},
                   [DrawingLayer("Sky", [Fill("sky", rectangle(-1.0, 1.0, -0.75, 0.75))]),
                    DrawingLayer("Figure", figure),
                    DrawingLayer("Prop", [Fill("wood", rectangle(0.55, 0.7, -0.75, 0.0))])])


def walking_figure(scene, frames=24, name="Walk"):
    """walking_drawing built as a Grease Pencil object in `scene` → the object."""
    return build_drawing(scene, walking_drawing(frames, name))


def line_material(gp, name, rgba):
    """A line-only Grease Pencil material of linear colour `rgba` on `gp` → its index."""
    m = bpy.data.materials.new(name)
    bpy.data.materials.create_gpencil_data(m)
    if "show_fill" in material_drawn():      # Blender 5.0–5.2 (5.3: add_line's attributes)
        m.grease_pencil.show_stroke, m.grease_pencil.show_fill = True, False
    m.grease_pencil.color = rgba
    gp.materials.append(m)
    return len(gp.materials) - 1


def add_line(layer, points, radii, material, opacities=None, colours=None, frame=1):
    """An open round-capped line through `points` [(x, z)] of `radii` on `frame` of a layer;
    opacities: each point's (the pen's pressure), colours: its vertex colour (r, g, b, mix)."""
    found = [f for f in layer.frames if f.frame_number == frame]
    drawing = (found[0] if found else layer.frames.new(frame)).drawing
    drawing.add_strokes([len(points)])
    stroke = drawing.strokes[len(drawing.strokes) - 1]
    for k, (p, (x, z)) in enumerate(zip(stroke.points, points)):
        p.position = (x, 0.0, z)
        p.radius = radii[k]
        p.opacity = 1.0 if opacities is None else opacities[k]
        if colours is not None:
            p.vertex_color = colours[k]
    stroke.material_index = material
    if hasattr(stroke, "fill_id"):          # Blender 5.3: outlined as the stroke says
        stroke.hide_stroke = False


def inked(obj, opacity=0.6):
    """An "Ink" layer on top of a drawing at `opacity`: a wavy line thickening left to right
    as its pen presses harder, and a second turning red along it (a vertex colour) → the
    layer."""
    ink = line_material(obj.data, "ink", (0.05, 0.05, 0.1, 1.0))
    layer = obj.data.layers.new("Ink")
    t = np.linspace(0, 1, 30)
    for k in range(2):
        add_line(layer, list(zip(-0.8 + 1.6 * t, 0.25 * np.sin(6 * t) + 0.3 * k)),
                 0.01 + 0.02 * t, ink, opacities=0.3 + 0.7 * t,
                 colours=[(1.0, 0.2, 0.1, v * k) for v in t])
    layer.opacity = opacity
    return layer
