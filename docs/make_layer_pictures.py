"""Generate docs/layers.md: a scene of layers that shadow each other (pipeline.md §15, issue
30), with its pictures — the built-in layered test scene without and with the shadows between
its layers (numpy core), and a parallax strip (Cycles, a perspective camera trucking past the
layers as Add › Layered… builds them).

    .venv/bin/python docs/make_layer_pictures.py        # ≈ 15 s
"""
import math
import os
import sys
import tempfile

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(DOCS))
sys.path.insert(0, DOCS)

import bpy  # noqa: E402

from make_docs import side_by_side  # noqa: E402

from dynpaint_addon.blender import register_once  # noqa: E402
from dynpaint_addon.blender.scenes.grease_pencil.drawing import render_layers  # noqa: E402
from dynpaint_addon.blender.scenes.grease_pencil.lit_copy import GREASE_PENCIL_RELIEF  # noqa: E402
from dynpaint_addon.blender.scenes.layered_build import add_layered  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import output_settings  # noqa: E402
from dynpaint_addon.core.colour import linear_to_srgb  # noqa: E402
from dynpaint_addon.core.layers import MAX_LAYERS, Layer, render_scene  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.layered_files import (BACKDROP_FILL, BACKDROP_SPAN, DEFAULT_SPACING,  # noqa: E402
                                                 painting_of_frames)
from dynpaint_addon.inputs.recipe import load_layers, load_recipe  # noqa: E402
from dynpaint_addon.inputs.testpainting import write_test_scene  # noqa: E402
from testkit.grease_pencil import figure_on_a_hill  # noqa: E402

PX = 192
SUN = Light("sun", (0.55, 0.35, 0.76), name="Key")
WIDE = Light("sun", (0.55, 0.35, 0.76), name="Key", size=math.radians(6))


def _shown(rgba):
    """A core render (linear, premultiplied) → display values, as seen."""
    return np.dstack([linear_to_srgb(np.clip(rgba[..., :3], 0, 1)), rgba[..., 3:4]])


def without_between(layers, light):
    """The layers composited, each lit only by its own shadows (§6): what lighting each
    painting alone gives."""
    parts = [render_scene([layer], [light], canvas=layers[0].images["shape"].size[::-1]).rgba
             for layer in layers]
    out = np.zeros_like(parts[0])
    for top in parts:
        out = top + out * (1 - top[..., 3:4])
    return out


def before_after(layers):
    tiles = [without_between(layers, SUN), render_scene(layers, [SUN]).rgba,
             render_scene(layers, [WIDE]).rgba]
    return side_by_side([_shown(t) for t in tiles])


def grease_pencil(folder):
    """From Grease Pencil (issue 42): a drawing of three layers drawn by Blender's Grease Pencil
    renderer (scenes/grease_pencil/drawing.py), as it shows them (unlit), then its layers lit alone,
    then with the shadows between them (the operator's relief and spacing)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    drawing = figure_on_a_hill(bpy.context.scene)
    paths = render_layers(drawing, folder, PX)[0]
    cells = [read_image(p) for p, in paths]
    shown = np.zeros_like(cells[0].pixels)
    for top in (c.pixels for c in cells):               # as Grease Pencil shows it: over
        shown = top * top[..., 3:4] + shown * (1 - top[..., 3:4])
    shown[..., 3] = np.max([c.pixels[..., 3] for c in cells], axis=0)
    layers = []                                         # as From Grease Pencil makes them
    for i, cell in enumerate(cells):
        images, p, _, _ = painting_of_frames(str(i), [cell], relief=GREASE_PENCIL_RELIEF)
        layers.append(Layer(images, p, str(i), i * DEFAULT_SPACING))
    return side_by_side([shown] + [_shown(t) for t in (without_between(layers, SUN),
                                                        render_scene(layers, [SUN]).rgba)])


def parallax_strip(recipe, folder):
    """Cycles renders of the layered scene from a perspective camera trucked left, centre and
    right (the composition kept at the centre)."""
    bpy.ops.wm.read_homefile(use_empty=True)
    register_once()
    scene = bpy.context.scene
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.location = (0.0, 0.0, 1.5)
    cam.data.lens = 50.0
    cam.data.sensor_width = 36.0
    scene.camera = cam
    add_layered(bpy.context, recipe, lights="all")
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 16
    scene.cycles.seed = 0
    scene.cycles.use_denoising = False
    scene.cycles.device = "CPU"
    scene.render.resolution_x = scene.render.resolution_y = PX
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.world = None
    tiles = []
    for i, x in enumerate((-0.3, 0.0, 0.3)):
        cam.location.x = x
        path = os.path.join(folder, f"parallax_{i}.png")
        output_settings(scene, path)
        bpy.ops.render.render(write_still=True)
        tiles.append(read_image(path).pixels)
    return side_by_side([np.dstack([t[..., :3], np.ones(t.shape[:2])]) for t in tiles])


def main(out=DOCS):
    os.makedirs(os.path.join(out, "img", "layers"), exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:          # (first: it empties the scene)
        write_png(os.path.join(out, "img", "layers", "grease_pencil.png"), grease_pencil(folder))
    with tempfile.TemporaryDirectory() as folder:
        recipe = write_test_scene(folder, PX)
        layers = load_layers(load_recipe(recipe))
        write_png(os.path.join(out, "img", "layers", "before_after.png"), before_after(layers))
        write_png(os.path.join(out, "img", "layers", "parallax.png"),
                  parallax_strip(recipe, folder))
    page = f"""# Layers that shadow each other (a scene of paintings)

Artists paint in layers, and the 2.5D scenes built from them — a figure in front of a window in
front of a landscape — are what "2.5D" most often means in Blender. Dynamic Painting lights
such a scene as a whole: each layer is a painting at its own depth, and **the layers in front
cast their shadows on the layers behind**, with the height of the gap between them: a shadow
falls further from its layer the further behind the receiving layer is, and a light with a
size (a Sun's *Angle*, a Point light's *Radius*) softens it more the further it falls.

![the test scene: layers lit alone, with the shadows between them, with a 6° sun](img/layers/before_after.png)

*The built-in layered test scene (`testpainting.write_test_scene`: the test painting at the
back, a flat ring card 0.12 image widths in front of it, a star with a dome's relief 0.25 in
front), one sun. Left: each layer lit by its own shadows only — what lighting each painting
alone gives. Middle: the shadows between the layers (the ring's on the dome, the star's on the
ring's layer and the back). Right: the same with a Sun 6° wide: penumbrae widen with the
distance between layers.*

## Using it

- **Blender:** *Add › Dynamic Painting › Layered…* and pick an OpenRaster file (`.ora`, from
  Krita, GIMP or MyPaint), a folder of layer images (Photoshop's *Export Layers to Files*) or a
  layered recipe. Each layer becomes a plane under one parent Empty, at its depth, with the
  material every painting has; drag a light and every layer's shadows follow (draft while
  dragging, final once it stops — baked beside Blender's UI, which stays free —, per frame
  when rendering), move a layer (its plane, or
  *Depth* in the **Layers** panel) and they move too; undo, save and reopen keep them. With a
  perspective camera, *Keep the Composition* scales each layer by (D − z)/D about the camera's
  axis, so the camera sees the painting as composed — and any camera move shows true parallax:

  ![a camera trucking past the layers: left, centre, right](img/layers/parallax.png)

  The sample **Window (layers)** (*Add › Dynamic Painting › Samples*; `window` on the command
  line) is a scene of three layers — a garden, a window frame, a vase — and comes with a
  perspective camera that trucks across them and a light turntable: press Play.

- **Command line:** `render`, `bake-shadow --layers` and `export-web` take a layered recipe,
  an `.ora` file or a folder:

  ```sh
  dynpaint render scene.ora --out scene.png
  dynpaint render scene.toml --engine eevee --out scene.png
  dynpaint bake-shadow --layers scene.toml --light 0.5 0.3 0.8 --light-angle 5 --out shadows/
  dynpaint export-web scene.ora --out scene.html
  ```

  `bake-shadow --layers` writes each layer's cos-θ term t as `shadows/layer_<i>.exr` (i = 0 at
  the back), the size of that layer's shape image; `--quality` and the other shadow options,
  when given, apply to every layer.

## A Grease Pencil drawing, lit

Grease Pencil cannot be lit in Blender (its material is not a BSDF: no normal maps, no
shadows). *Add › Dynamic Painting › From Grease Pencil* lights the active drawing: each of its
layers that draws something is drawn unlit into an image with its alpha, framed by the
drawing's extent over all its frames — by numpy (`scenes/grease_pencil/strokes.py`,
`core/raster.py`: fills by each pixel's exact covered area, round-capped lines that thicken
and fade with the pen, vertex colours, layer opacity, as Grease Pencil mixes them; 23× faster
than Blender's renderer here and free of its main thread), or, where the drawing uses what
numpy does not draw (textures and gradients, modifiers and effects, blend modes, masks, tints,
curves that are not polylines, soft or flat-capped lines, holdouts, animated layers and
materials), by **Blender's own Grease Pencil renderer**, a note saying why. Inside every
figure the two agree within 1/255; at the edges numpy's coverage is the exact area where
Blender's anti-aliasing spreads an edge over ~2 px. The layers are then built as a folder of
layers is (below): a plane per layer where the drawing is — at the depth the artist moved it
toward the camera (its layer's translation), else *Spacing* apart ({DEFAULT_SPACING:g} of its width when
the lit copy was made: a stroke past its bounds does not move the layers apart) — each
inflated by parts from its alpha with a low *Relief* (0.1 of a hemisphere: a drawing's layers
lie close), but a backdrop (a fill to the drawing's bounds: a sky, a wall) stays a flat card;
the layers in front shadow those behind. With a UI the lit copy shows its shadows as a draft
at once and the final ones from a worker thread (1.2 s at 1024² here until it shows; a script
waits for the final bake, 4.0 s). The drawing is hidden, not changed: unhide it and draw on, and the
lit copy follows — each change of the drawing (a stroke, a keyframe, a material's colour)
shows at once as a draft (the changed layer drawn 128 px across, made a painting there and
enlarged where it changed, its shadows from the layers made as small: under 0.1 s at 1024²
here) and is drawn in full in place once no stroke has come for 1 s — with a UI its drawing,
painting and final shadows are made in worker threads and Blender is held only to write
them (at most ~70 ms at 1024² here; the images so written are packed when the file is
saved); at once in scripts and renders, after a depsgraph evaluation. The final shadows
after a stroke trace again only the rays that can meet what it changed (0.34–0.59 s for a dab
of its own at 1024² here, 0.7–0.9 s for one that re-inflates a figure: of the rays that pass
that part, those its hundredths-of-a-pixel moves can flip, told by the clearance each pixel's
rays kept from its relief; docs/pipeline.md §15 "Clearance"), the layers behind side by side
in threads. A stroke
past the drawing's bounds (its draft shows it as far as the lit copy reaches) frames the lit
copy anew in place — the same objects and materials, each layer's images resized, its plane
placed and shaped for the new bounds, a layer at a time with a UI (Blender held at most
65–80 ms at 1024² here), each layer's shadows kept where they were until the group's draft
comes from a worker, then the final. A layer added or removed makes the lit copy anew,
keeping what you changed on it: each layer's settings but its shape, its keyframes, its
plane's visibility, and any object you parented to it.
Where Blender's renderer draws the drawing, it draws each layer at the scene's Grease Pencil
anti-aliasing samples (*Render Properties › Grease Pencil*, 8 unless set), as F12 would. Scene frames that show the same drawing share one bake: a frame where the
drawing holds costs milliseconds.
An animated
drawing (a layer with more than one keyframe, or animated data) is drawn on every frame of
the scene's range: a layer whose drawing changes becomes a painting of sprite sheets that
follow the scene's frames (§16; each frame's shape inflated by parts, so what does not
change keeps its heights), a layer that does not a still one; playback and renders show
each frame lit, its shadows baked for that frame. On the command line, a .blend file's
drawing is lit the same way and rendered (the numpy core, Cycles or EEVEE, framed on its back
layer, the file's lights) or turned under its light (an animated drawing plays meanwhile):

```sh
dynpaint render drawing.blend --grease-pencil "Figure" --frame 12 --width 1024 --out lit.png
dynpaint turntable drawing.blend --grease-pencil "Figure" --out turntable.mp4
```

Measured against Cycles renders of the same cards in 3D (`benchmarks/grease_pencil_truth.py`,
[grease-pencil-truth.md](grease-pencil-truth.md), scenes not chosen on): with *Relief* 0 (flat
cards, as the 3D ones are) every layer's mean |t − 3D| is at most 0.005 and the shadows cast on
the ground have an IoU of 0.98–1.00; the small shadows cast on a middle layer by the one in
front reach 0.82–0.92 at 45° at 256², where the same cards given as exact masks reach
0.87–0.96 — those shadows are a few pixels wide; at 512² 0.95–0.99 (exact masks 0.96–0.99), and
at 1024², the operator's resolution, 0.98–0.99 under a sharp sun and 0.96–0.99 under a sun 5°
wide, within 0.01 of exact masks, on both scenes (docs/limits.md). Blender's anti-aliasing
spreads a drawing's edges over about 2 px, so below 1024 px each layer is drawn twice as large
at a quarter of the samples and averaged: its edges come out as exact coverage's (it takes
1.4–1.6× as long to draw here). With the default *Relief* 0.1 the cards are low domes, which the 3D cards are
not: their own shading differs by 0.02–0.07. What it costs: [grease-pencil-cost.md](grease-pencil-cost.md).
An animation plays without flicker: a still post in front of a walking figure keeps its
shading from frame to frame, exactly, in numpy and in Cycles
([grease-pencil-frames.md](grease-pencil-frames.md)). The sample **Walk (Grease Pencil)**
(*Add › Dynamic Painting › Samples*; `walk` on the command line) is such a drawing, shipped
as its data (`drawing.json`: filled shapes per layer and frame; a recipe may name a drawing
instead of images), built and lit in one click, its light turning.

**Shadow colours.** Each layer's dark image is a shaded copy of its colours unless the artist
names its shadow colours: a layer called **"<name> shadow"** (for example *Figure shadow*;
hide it if you like — it is read hidden or not) is drawn as the dark image of the layer
*<name>* where it covers it, the shaded copy elsewhere, and is not a lit layer of its own; a
material called **"<material> shadow"** (on no slot needed) is drawn in place of *<material>*
for the dark images of the layers that use it. An edit of either redraws the layer it
colours.

**More than 8 layers.** A scene holds 8 lit layers: a drawing with more says which and asks
first; tick *Merge Back Layers* and the back ones are drawn together as one lit layer (named
after them, e.g. *01_Back_Extra_0*), the 7 in front keep their own — the merged ones no
longer shadow each other.

**Relief effects.** The dialog (and its *Adjust Last Operation* panel) takes Paint Shape's
relief effects for every layer's inflated silhouette — *Profile*, *Bevel* (width, height,
profile), *Detail* embossed from the layer's own colours, *Smoothing* — kept with the lit
copy, so a redraw after a stroke shapes the layer the same way.

**On the web.** `export-web` exports the lit drawing as one page — its layers at their
places, the shadows between them marched in the page when the light moves, and an animated
drawing's frames played at the scene's rate (the *Frames* slider and *Play*), each frame the
numpy core's within 2e-3 (`tests/blender/test_grease_pencil.py`); *File › Export › Dynamic
Painting (.html)* on the lit copy does the same:

```sh
dynpaint export-web drawing.blend --grease-pencil "Figure" --width 1024 --out drawing.html
dynpaint export-web walk --out walk.html
```

![a Grease Pencil drawing: as drawn, its layers lit alone, with the shadows between them](img/layers/grease_pencil.png)

*A drawing of three layers (`testkit/grease_pencil.py`: a sky card, a hill, a figure), drawn
by Blender's Grease Pencil renderer as it shows them (left), its layers each lit by its own
shading only (middle), and with the shadows the figure and the hill cast on the layers behind
(right), one sun.*

## Layered files

- **A plain painted layer is enough.** Its bright image is the layer, its dark image a shaded
  copy (*Dark Shade*, 0.35 of its linear colour by default), its shape its silhouette inflated
  (*Make Shape › Inflate*); an opaque layer (a background) is a flat card, and so is a
  backdrop: a layer whose figure spans at least {BACKDROP_SPAN:.0%} of the canvas both ways and
  fills {BACKDROP_FILL:.0%} of that box (a sky drawn to a Grease Pencil drawing's bounds, only its margin
  clear; or with a moon drawn beyond it) — inflated, its border would fall off like a
  pillow's and shadows cast on it would bend.
- **A group holds one layer's channels** (an OpenRaster stack, a subfolder), matched by their
  names as *From Images* matches files: `figure_dark`, `figure_bright`, `figure_normal`, …
- **Depths** follow the stack: the back layer at 0, each next one *Spacing* image widths
  (0.05) in front. Layers smaller than the canvas are placed by their corner.
- Hidden layers are left out, blend modes other than normal are read as normal and layer
  opacity as 1 — each said in a note; a broken file (no or invalid `stack.xml`, a layer that is
  not a PNG, more than {MAX_LAYERS} visible layers) is one clear error.

## A layered recipe

```toml
name = "Window"
[shadows]                  # top-level sections: every layer starts from them
offset = 0.01

[[layers]]                 # the back layer first
name = "landscape"
depth = 0.0                # image widths of the canvas (the back layer's width) toward the viewer
[layers.images]
shape = "landscape_height.png"
bright = "landscape.png"

[[layers]]
name = "figure"
depth = 0.2
thickness = 0.01           # how far it reaches behind its plane (default: its tallest relief)
offset = [0.1, -0.05]      # its centre from the canvas's centre, image widths
scale = 0.5                # its width over the canvas's width
[layers.images]
shape = "figure_normal.png"
dark = "figure_dark.png"
bright = "figure_bright.png"

[[lights]]                 # the lights belong to the scene
direction = [0.5, 0.3, 0.8]
angle = 5.0                # a Sun's angular diameter in degrees (Blender's Angle)
```

## The model (pipeline.md §15)

Each layer keeps its own cos-θ term (§6: its relief's shading, cast shadows and subsurface
look) and multiplies it by T, what the layers in front let through along the ray from each of
its pixels' surface points toward the light. A layer in front is the solid between its plane
minus its thickness and its relief, where its alpha covers (α ≥ ½), of opacity 1 − k (§11's
transparency: glass casts a lighter shadow). One layer is today's painting, bit for bit. The
composite is back to front by each layer's alpha.

How it is computed: for a sun over layers of one opacity, each layer in front is resampled once
along the light's direction and a running maximum of its relief answers, for any ray, whether
it meets the layer — one lookup per pixel; point lights and glass layers march each layer's
own pixels once per light and are read where each ray crosses them; rays that start inside a
layer's slab (a relief poking through the layer in front), and rays whose answer the
resampled layer cannot give (its edge passes between two of its samples), are marched. A
shadow's edge is antialiased: where T steps between neighbouring pixels, a preview or final
bake takes the mean of a grid of rays across the pixel (4 × 4 at final), the share of the
pixel in shadow, as a render's pixel shows it (a draft, while a light is dragged, takes each
pixel's centre). Measured against Cycles on the scene the layers were built on and on two
held out from the choosing — thin cards 0.15 image widths apart, a dome under a star card
(docs/layers-truth.md): cast-shadow IoU 0.95–0.99, mean |t − 3D| ≤ 0.006 on the cards and the
ground and ≤ 0.011 on the reliefs, for suns from 15° to 60°, a point light and a 5° sun;
speed and memory (docs/layers-speed.md): three 1024² layers bake in about 1.3× the time of
the same images baked alone (antialiased edges made a final bake about a fifth slower), a
dragged light's update takes 54–57 ms on this 2-core machine, written at the size its draft
was baked at (goal 50 ms; the three layers' own draft bakes alone take 52–66 ms in the same
runs), at most {MAX_LAYERS} layers.

## Limits

- **A card has no sides.** A layer is a plane with a relief and a thickness behind it: its
  sides are never lit or seen, and light that would pass *between* two layers sideways (under
  an overhang of the layer in front) is blocked as if the layer reached down to its thickness
  everywhere its alpha covers.
- **Layers shadow those behind them only**: rays rise toward the light, so a layer never
  shadows the layers in front of it, and a light between two layers lights the back one
  without the front one's shadow only where its rays do not cross it.
- **Parallax is a camera's**: moving the camera shows the layers at their depths, but each
  stays a flat painting facing the parent; a camera that turns far to the side sees their edges.
- **The web page** draws a scene of up to {MAX_LAYERS} layers with the shadows between them
  (docs/web.md); its parallax is a shift of each layer by its depth, not a perspective camera.
"""
    with open(os.path.join(out, "layers.md"), "w", encoding="utf-8") as fh:
        fh.write(page)


if __name__ == "__main__":
    main()
