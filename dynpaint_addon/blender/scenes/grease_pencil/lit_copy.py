"""The lit copy of a drawing (Add › From Grease Pencil; the command line): its layers drawn
(drawing.py), made paintings as a layered file's plain layers are, and built as a scene of
lit layers where the drawing is (light_drawing), its settings and the layers' digests kept
on the copy's parent so that it can follow its drawing (live.py).
"""
import json
import math
import shutil
import tempfile

import bpy
from mathutils import Matrix

from ....core.inputs import about
from ....core.lights import default_sun
from ....inputs.drawings import frame_range, load_drawing
from ....inputs.imageio import read_image
from ....inputs.layered_files import DEFAULT_SHADE, DEFAULT_SPACING, painting_of_frames
from ....shapes.methods import options as shape_options
from ...bake.layers import group_materials
from ...state.images import packed_image
from ..layered_build import build_layered
from ..painting_scene import NO_CAMERA, unchanged_images_on_failure
from .building import build_drawing
from .drawing import check_drawing_memory, drawn_size, render_layers
from .reading import (animated, drawn_layers, framing, layer_depths, layer_digests,
                      layer_stem)
from .strokes import read_drawing, unsupported

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
SPACING_WIDTH = "spacing_width"     # a lit copy's record: the drawing's width its Spacing is of


def drawing_frames(scene, obj, settings):
    """The scene frames a drawing is drawn on (the scene's range where it is animated and
    settings' `animation` asks for it), or None (the current frame alone)."""
    return list(range(scene.frame_start, scene.frame_end + 1)) \
        if settings["animation"] and animated(obj) else None


def read_images(scene, obj, settings, only=None, samples=None, bounds=None):
    """Each layer of the drawing that draws something, read on Blender's main thread to be
    drawn → (draw, bounds, frames or None, notes): draw(progress=None) → [(name, depth,
    [ImageData per frame] or None, [its dark ones] or None)], safe in a worker thread.
    numpy draws the layers (strokes.read_drawing) where it draws all the drawing uses;
    else Blender's renderer draws them here (render_layers, read back: a note says why).
    only: the layers to draw (the others' images None); samples, bounds: render_layers'."""
    frames = drawing_frames(scene, obj, settings)
    layers, notes = drawn_layers(obj, settings["merge"])
    bounds = framing(obj) if bounds is None else tuple(bounds)
    width = bounds[1] - bounds[0]          # (a merged group lies where its back one is)
    depths = layer_depths([group[0] for group in layers], width,
                          settings["spacing"] * spacing_width(settings, width) / width)
    names = [layer_stem(i, group) for i, group in enumerate(layers)]
    why = unsupported(obj, layers)
    if why is None:
        size, shown = drawn_size(bounds, settings["resolution"]), frames or [scene.frame_current]
        check_drawing_memory(obj, layers, shown, *size, only)
        read = read_drawing(obj, layers, shown, bounds, size, settings["shade"], only)

        def draw(progress=None):
            return list(zip(names, depths, *read.draw(progress)))
        return draw, bounds, frames, notes
    notes.append(f"{obj.name}: drawn by Blender's Grease Pencil renderer (slower: numpy does "
                 f"not draw {why})")
    folder = tempfile.mkdtemp(prefix="dynpaint-grease-pencil-")
    try:
        paths, bounds, _, darks = render_layers(
            obj, folder, settings["resolution"], frames, only=only, shade=settings["shade"],
            merge=settings["merge"], samples=samples, bounds=bounds)
        read = {}          # a frame showing what another showed: its file, read once

        def cells(files):
            for path in files or ():
                if path not in read:
                    read[path] = read_image(path)
            return files and [read[path] for path in files]
        drawn = [(name, depth, cells(layer_paths), cells(dark_paths))
                 for name, depth, layer_paths, dark_paths in zip(names, depths, paths, darks)]
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return (lambda progress=None: drawn), bounds, frames, notes


def drawn_images(scene, obj, settings, progress=None, only=None, samples=None, bounds=None):
    """read_images' layers drawn now → (drawn, bounds, frames or None, notes)."""
    draw, bounds, frames, notes = read_images(scene, obj, settings, only, samples, bounds)
    return draw(progress), bounds, frames, notes


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
        notes += about(name, lines)
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
        # (beside the UI, packed when the file is saved: a lit copy made anew while the
        # artist draws holds Blender only to make it)
        images[name] = {c: packed_image(f"{obj.name} {name} {c}", img, c,
                                        pack=bake != "live")
                        for c, img in imgs.items()}
        if table is not None:
            tables[name] = {"": {**table, "start": frames[0]}}
        layers.append((name, depth, (0.0, 0.0), 1.0, None, images[name], p))
    place = drawing_place(obj, (x0, x1, z0, z1))
    with unchanged_images_on_failure():           # (its images are packed copies)
        parent, messages = build_layered(context, obj.name, layers, lights or [default_sun()],
                                         notes, x1 - x0, parallax=False, add_lights=True,
                                         frames=tables, place=place, bake=bake,
                                         name=f"{obj.name} (lit)")
    for mat in group_materials(parent):           # which layer each painting shows
        bright = mat.dynamic_painting.image_bright
        mat[LAYER] = next(n for n, imgs in images.items() if imgs["bright"] == bright)
    parent[SOURCE] = json.dumps({"object": obj.name, **settings, "layers": layer_digests(obj),
                                 "bounds": [x0, x1, z0, z1],
                                 SPACING_WIDTH: spacing_width(settings, x1 - x0)})
    obj.hide_render = True
    obj.hide_set(True)
    return parent, [m for m in messages if NO_CAMERA not in m]


def spacing_width(settings, width):
    """The drawing's width its lit copy's Spacing was given in: the width it had when the lit
    copy was made (kept in its record, SPACING_WIDTH), so that a stroke past its bounds
    frames it anew with its layers as far apart as they were — their shadows where they
    were — rather than moved apart with the drawing's width; `width` for a new one."""
    return settings.get(SPACING_WIDTH) or width


def drawing_place(obj, bounds):
    """A lit copy's parent's world matrix: at the middle of the drawing's `bounds` (x0, x1,
    z0, z1), facing as its XZ plane does."""
    x0, x1, z0, z1 = bounds
    return obj.matrix_world @ Matrix.Translation(((x0 + x1) / 2, 0.0, (z0 + z1) / 2)) @ \
        Matrix.Rotation(math.pi / 2, 4, "X")


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
