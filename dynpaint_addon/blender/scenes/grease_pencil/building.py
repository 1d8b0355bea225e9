"""A Grease Pencil drawing made from data (inputs/drawings.py: a sample's drawing.json, the
tests' and benchmarks' drawings): filled strokes of plain colours on layers."""
import bpy

from .reading import material_drawn


def fill_material(gp, name, rgb):
    """A fill-only Grease Pencil material of linear colour `rgb` on `gp` → its index."""
    m = bpy.data.materials.new(name)
    bpy.data.materials.create_gpencil_data(m)
    if "show_fill" in material_drawn():      # Blender 5.0–5.2 (5.3: add_fill's attributes)
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
    if hasattr(stroke, "fill_id"):
        # Blender 5.3 fills a stroke and outlines it as the stroke says, not its material
        # (blender-notes.md): a fill of its own, no outline — what 5.3 makes of a 5.0 file's
        # stroke in a fill-only material
        stroke.fill_id = len(drawing.strokes)
        stroke.hide_stroke = True


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
