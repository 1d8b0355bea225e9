"""`dynpaint render RECIPE --out IMAGE`: a recipe rendered by the numpy core,
or by Cycles or EEVEE in background Blender (the add-on's material, framed pixel for pixel)."""
import os
import time

import numpy as np

from ..core.input_rules import resample_painting
from ..core.layers import render_scene
from ..core.pipeline import render
from ..errors import CommandError
from ..inputs import memory
from ..inputs.imageio import painting_headers, write_render
from ..inputs.layered_files import is_layered_file, load_layered
from ..inputs.painting_frames import PaintingFrames
from ..inputs.recipe import load_recipe, no_drawing
from ..inputs.samples import recipe_help
from .notes import on_words, print_notes


ENGINES = ("numpy", "cycles", "eevee")


def cmd_render(args):
    for flag, value in (("--width", args.width), ("--max-size", args.max_size)):
        if value is not None and value < 1:
            raise CommandError(f"{flag} must be at least 1 pixel, got {value}")
    chosen, args.engine = args.engine, args.engine or "numpy"
    if args.grease_pencil:
        return _render_grease_pencil(args)
    if is_layered_file(args.recipe):
        return _render_blender(args, args.recipe) if args.engine != "numpy" else \
            _render_layers(args)
    recipe = load_recipe(args.recipe)
    if recipe.drawing and chosen is None:       # (the numpy engine does not read drawings)
        args.engine = "cycles"
        print_notes([f"{recipe.name or args.recipe}: its painting is a Grease Pencil drawing: "
                     f"rendered with Cycles in background Blender (--engine eevee is "
                     f"faster with a GPU)"])
    if args.engine != "numpy":
        print_notes(recipe.notes)
        return _render_blender(args, recipe)
    no_drawing(recipe, "the numpy engine")
    if recipe.layered:
        return _render_layers(args)
    slots = recipe.slots()
    painting = PaintingFrames(slots)
    if args.frame is not None and not painting.animated:
        raise CommandError("--frame needs --engine eevee or cycles, or a painting that moves "
                           "(the numpy engine renders the recipe's lights as written)")
    width = _width(args, painting_headers({c: s.files()[0] for c, s in slots.items()}), recipe)
    frame = painting.start if args.frame is None else args.frame
    images = painting.images(frame)
    if width:
        images = resample_painting(images, width)
    dtype = np.float64 if args.float64 else np.float32
    h, w = images["shape"].pixels.shape[:2]
    if w * h >= 4096 * 4096:     # say what a long render is doing before it starts
        print(f"rendering {w}×{h} ({w * h / 1e6:.0f} Mpx) with the numpy core: a minute or "
              f"more", flush=True)
    t = time.perf_counter()
    result = render(images, recipe.lights, recipe.params, dtype, keep_passes=False)
    ms = (time.perf_counter() - t) * 1000
    print_notes(recipe.notes + painting.notes + result.warnings)
    write_render(args.out, result.rgba)
    h, w = result.rgba.shape[:2]
    shown = f" (scene frame {frame}: {painting.shown(frame)})" if painting.animated else ""
    print(f"rendered {w}×{h}{shown} in {ms:.0f} ms → {args.out}")


def _width(args, headers, recipe):
    """The render's width (--width, or the shape's capped by --max-size), its memory checked
    against the machine's before any image is read (memory.py)."""
    if headers is None:
        return args.width
    sw, sh = headers["shape"][:2]
    width = args.width or (min(sw, round(sw * args.max_size / max(sw, sh))) if args.max_size
                           else None)
    painting = memory.painting(headers, recipe.params, width)
    # float64: every per-pixel array twice as large
    needed = memory.render_bytes(painting, recipe.params, recipe.lights) * (1 + args.float64)
    memory.check(needed, f"rendering {painting.width}×{painting.height}",
                 lambda: _smaller(headers, recipe, args.float64, painting.width))
    return width


def _smaller(headers, recipe, float64, width):
    """What to do when a render does not fit: the largest width, halving from `width`, whose
    render fits the memory free now, else smaller images."""
    while width > 16:
        width //= 2
        painting = memory.painting(headers, recipe.params, width)
        if memory.fits(memory.render_bytes(painting, recipe.params, recipe.lights) *
                       (1 + float64)):
            return f"render it smaller (--width {width}, or --max-size)"
    return "give smaller images"


def _render_layers(args):
    """A layered recipe, .ora or folder (§15) by the numpy core: each layer lit through the
    layers in front of it, composited back to front on the canvas."""
    if args.frame is not None or args.width or args.max_size:
        raise CommandError("the numpy engine renders a layered painting at its canvas's size "
                           "with the lights as written (no --frame, --width or --max-size; "
                           "--engine eevee or cycles take --frame)")
    layers, lights, notes = load_layered(args.recipe)
    print_notes(notes)
    t = time.perf_counter()
    result = render_scene(layers, lights, dtype=np.float64 if args.float64 else np.float32)
    ms = (time.perf_counter() - t) * 1000
    write_render(args.out, result.rgba)
    h, w = result.rgba.shape[:2]
    print(f"rendered {len(layers)} layer{'s' if len(layers) > 1 else ''} on {w}×{h} in "
          f"{ms:.0f} ms → {args.out}")


def _render_blender(args, recipe):
    """EEVEE or Cycles in background Blender, the scene built as the add-on builds it."""
    if (args.width and not getattr(recipe, "drawing", None)) or args.max_size or args.float64:
        raise CommandError("--width, --max-size and --float64 apply to the numpy engine only "
                           "(and --width to a drawing's recipe: its layers' width in pixels)")
    if os.path.splitext(args.out)[1].lower() not in (".png", ".exr"):
        raise CommandError(f"{args.out}: unsupported output format (use .png or .exr)")
    from ..blender.headless import drawn_on, render_recipe     # Blender only when asked for
    seconds = render_recipe(recipe, args.engine, args.out, args.frame, notes=print_notes,
                            drawing_width=args.width)
    print(f"rendered with {args.engine}{on_words(drawn_on(args.engine))} in "
          f"{seconds * 1000:.0f} ms → {args.out}")


def _render_grease_pencil(args):
    """A .blend file's Grease Pencil drawing, lit (issue 42): in background Blender, as Add ›
    Dynamic Painting › From Grease Pencil lights it, then rendered by the chosen engine."""
    if args.max_size or args.float64:
        raise CommandError("--grease-pencil takes --width (each layer's drawing), --frame and "
                           "--engine; not --max-size or --float64")
    if os.path.splitext(args.out)[1].lower() not in (".png", ".exr"):
        raise CommandError(f"{args.out}: unsupported output format (use .png or .exr)")
    from ..blender.headless import drawn_on, render_grease_pencil  # Blender only when asked for
    try:
        seconds = render_grease_pencil(args.recipe, args.grease_pencil, args.engine, args.out,
                                       args.frame, args.width)
    except ValueError as exc:
        raise CommandError(str(exc)) from exc
    shown = f" (frame {args.frame})" if args.frame is not None else ""
    print(f"rendered {args.grease_pencil}{shown}, lit, with {args.engine}"
          f"{on_words(drawn_on(args.engine))} in {seconds * 1000:.0f} ms → {args.out}")


def add_parser(sub):
    """Register `render` on the command line's subparsers."""
    r = sub.add_parser("render", help="render a recipe to an image",
                       description="Render a painting recipe (painting.toml) to PNG (8-bit sRGB) "
                                   "or EXR (linear float, premultiplied RGBA).")
    r.add_argument("recipe", help=recipe_help() + "; or a layered painting: an .ora file or a "
                                                  "folder of layer images (§15)")
    r.add_argument("--out", required=True, help="output image (.png or .exr)")
    r.add_argument("--engine", choices=ENGINES,
                   help="numpy (the reference core, default; cycles for a Grease Pencil "
                        "drawing's recipe, which it does not read), or cycles / eevee (the "
                        "add-on's material in background Blender, framed pixel for pixel)")
    r.add_argument("--frame", type=int, help="scene frame to render (they count from 1, as "
                   "Blender's do): a painting that moves "
                   "shows that frame's drawing (§16); with eevee/cycles keyframed lights and "
                   "parameters move with it too")
    r.add_argument("--width", type=int, help="output width in pixels (default: the shape image's); "
                                             "every per-pixel image is resampled to it (a "
                                             "drawing's recipe: each layer drawn that wide)")
    r.add_argument("--max-size", type=int, metavar="PX",
                   help="longest side of the render at most PX pixels: larger inputs are "
                        "downsampled on reading (less memory and time)")
    r.add_argument("--float64", action="store_true", help="compute in float64 (reference)")
    r.add_argument("--grease-pencil", metavar="OBJECT",
                   help="RECIPE is a .blend file: light its Grease Pencil drawing OBJECT as "
                        "Add › From Grease Pencil does (--width: each layer's drawing in "
                        "pixels) and render it")
    r.set_defaults(func=cmd_render)
