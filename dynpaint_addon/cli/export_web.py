"""`dynpaint export-web`: a recipe as one self-contained web page (issue 17).

The page (web/page.py) draws the painting with WebGL2 from a shader generated from the graph
description; the viewer drags the light. Problems end as one `error: …` line (cli.main).
"""
import os
import time

from .. import params
from ..errors import UserError
from ..inputs import memory
from ..inputs.imageio import painting_headers
from ..inputs.layered_files import is_layered_file, load_layered
from ..inputs.painting_frames import PaintingFrames
from ..inputs.recipe import image_bytes, load_recipe
from ..inputs.samples import recipe_help
from ..web.device_fit import DEFAULT_MAX_SIZE
from ..web.page import TURNTABLE_SECONDS, page_data, scene_data, write_page
from .notes import check_and_print, print_notes

STEPS = params.BY_PATH["shadows.steps"]
FPS = 24.0                   # Blender's default scene rate


class ExportError(UserError):
    """A user-facing problem with export-web's options."""


def cmd_export_web(args):
    if not args.out.lower().endswith((".html", ".htm")):
        raise ExportError(f"--out {args.out}: a web page is an .html file")
    if args.max_size != 0 and args.max_size < 16:
        raise ExportError(f"--max-size {args.max_size}: at least 16 pixels (0: the painting's "
                          f"own size)")
    if args.steps is not None:
        try:
            STEPS.check(args.steps)
        except ValueError as exc:
            raise ExportError(f"--steps: {exc}") from None
    if args.turntable_seconds <= 0:
        raise ExportError(f"--turntable-seconds {args.turntable_seconds}: must be positive")
    if not 0 < args.fps <= 240:
        raise ExportError(f"--fps {args.fps:g}: frames per second in 0 … 240")
    start = time.perf_counter()
    if args.grease_pencil:
        return _export_grease_pencil(args, start, args.recipe, args.grease_pencil)
    recipe = None if is_layered_file(args.recipe) else load_recipe(args.recipe)
    outside = recipe.images_outside() if recipe is not None else {}
    if outside and not args.allow_outside_images:     # a page publishes what it embeds
        raise ExportError(
            f"{recipe.path or args.recipe} names images outside its folder "
            f"({recipe.folder}): {', '.join(f'{c} = {p}' for p, c in outside.items())}; a "
            f"page embeds every image it shows: pass --allow-outside-images to publish them")
    if recipe is not None and recipe.drawing:
        return _export_grease_pencil(args, start, recipe)
    if args.width is not None:
        raise ExportError("--width is a drawing's width (--grease-pencil, or a drawing's "
                          "recipe such as walk); a painting's page takes --max-size")
    if recipe is None or recipe.layered:
        return _export_layers(args, start, recipe)
    print_notes(recipe.notes)
    headers = painting_headers({c: s.files()[0] for c, s in recipe.slots().items()})
    if headers is not None:            # before any image is read (a 12000² one took 6.9 GB)
        pt = memory.painting(headers, recipe.params)
        memory.check(memory.page_bytes(pt), f"a page of the {pt.width}×{pt.height} painting",
                     "give smaller images (the page reads them whole before --max-size)")
    painting = PaintingFrames(recipe.slots())
    images = painting.images(painting.start)
    check_and_print(images, recipe.params)
    frames = None
    if painting.animated:                  # §16: every drawing of one loop, played
        print_notes(painting.notes)
        frames = painting.web_frames(args.fps)
    data, warnings = page_data(
        images, recipe.lights, recipe.params,
        title=recipe.name if args.title is None else args.title,
        credits=recipe.credits if args.credits is None else args.credits,
        steps=args.steps, max_size=args.max_size, turntable_seconds=args.turntable_seconds,
        frames=frames)
    size = write_page(args.out, data)
    seconds = time.perf_counter() - start
    inputs = image_bytes(recipe)
    print_notes(warnings)
    moving = f", {len(frames['sequence'])} frames at {args.fps:g} fps" if frames else ""
    print(f"export-web: wrote {args.out} ({size / 1e6:.2f} MB, {size / inputs:.2f}× its input "
          f"images; {data['width']}×{data['height']}, {len(data['lights'])} light(s)"
          f"{', shadows K = %d' % data['steps'] if data['shadows'] else ''}{moving}) in "
          f"{seconds:.1f} s")


def _export_layers(args, start, recipe):
    """export-web of a layered recipe (`recipe`), .ora file or folder (§15; recipe None): each
    layer drawn at its place, the shadows between layers marched in the page."""
    layers, lights, notes = load_layered(args.recipe)
    print_notes(notes)
    name = recipe.name if recipe is not None and recipe.name else \
        os.path.splitext(os.path.basename(os.fspath(args.recipe).rstrip(os.sep)))[0]
    credits = recipe.credits if recipe is not None else ""
    data, warnings = scene_data(layers, lights, title=name if args.title is None else args.title,
                                credits=credits if args.credits is None else args.credits,
                                steps=args.steps,
                                max_size=args.max_size,
                                turntable_seconds=args.turntable_seconds)
    size = write_page(args.out, data)
    print_notes(warnings)
    print(f"export-web: wrote {args.out} ({size / 1e6:.2f} MB; {len(layers)} layers on "
          f"{data['width']}×{data['height']}, {len(data['lights'])} light(s)) in "
          f"{time.perf_counter() - start:.1f} s")


def _export_grease_pencil(args, start, source, name=None):
    """export-web of a Grease Pencil drawing (issue 42) — a .blend file's (`source` its path,
    `name` the drawing) or a drawing's recipe (`source`, its Recipe): lit in background
    Blender as *From Grease Pencil* lights it, its layers' frames played, its lights dragged."""
    if args.width is not None and args.width < 16:
        raise ExportError(f"--width {args.width}: at least 16 pixels")
    if name is None:
        print_notes(source.notes)
    from ..blender.headless import grease_pencil_page      # Blender only when asked for
    try:
        data, warnings = grease_pencil_page(
            source, name, args.width, title=args.title or name or source.name,
            credits=source.credits if args.credits is None and name is None else
            args.credits or "", steps=args.steps, max_size=args.max_size)
    except ValueError as exc:
        raise ExportError(str(exc)) from exc
    data["turntable_seconds"] = float(args.turntable_seconds)
    size = write_page(args.out, data)
    print_notes(warnings)
    moving = f", {len(data['frames']['sequence'])} frames at {data['frames']['fps']:g} fps" \
        if data["frames"] else ""
    print(f"export-web: wrote {args.out} ({size / 1e6:.2f} MB; {data['title']}, "
          f"{len(data['layers'])} layers on {data['width']}×{data['height']}, "
          f"{len(data['lights'])} light(s){moving}) in {time.perf_counter() - start:.1f} s")


def add_parser(sub):
    """Register `export-web` on the command line's subparsers."""
    w = sub.add_parser("export-web", help="export a recipe as a self-contained web page (.html)",
                       description="Write one offline .html file (images inside, no network) "
                       "where viewers drag the light over the painting (WebGL2). Open "
                       "PAINTING.html?embed for the painting alone at its own size.")
    w.add_argument("recipe", help=recipe_help())
    w.add_argument("--out", required=True, help="the web page (.html)")
    w.add_argument("--max-size", type=int, metavar="PX", default=DEFAULT_MAX_SIZE,
                   help=f"longest side of the painting in the page, in pixels (default "
                   f"{DEFAULT_MAX_SIZE}, the most many phones draw; 0: the shape image's own "
                   f"size). A page over 2048 px also carries smaller copies, and each device "
                   f"draws the largest it can")
    w.add_argument("--steps", type=int, metavar="K",
                   help="march steps per pixel of the in-page shadows (default: the recipe's "
                   "shadows.steps, 64; fewer draw faster)")
    w.add_argument("--title", help="title shown above the painting (default: the recipe's name)")
    w.add_argument("--credits", help="credits shown under the title (default: the recipe's)")
    w.add_argument("--turntable-seconds", type=float, default=TURNTABLE_SECONDS,
                   help=f"seconds per turn of the light when the page plays "
                   f"(default {TURNTABLE_SECONDS:g})")
    w.add_argument("--fps", type=float, default=FPS, help=f"a painting that moves (§16): scene "
                   f"frames per second the page plays its frames at (default {FPS:g})")
    w.add_argument("--allow-outside-images", action="store_true",
                   help="embed images the recipe names outside its own folder (refused by "
                   "default: a recipe from someone else could put any file of yours into "
                   "the page you publish)")
    w.add_argument("--grease-pencil", metavar="OBJECT",
                   help="RECIPE is a .blend file: light its Grease Pencil drawing OBJECT as "
                   "Add › From Grease Pencil does and export it, its frames played")
    w.add_argument("--width", type=int, metavar="PX",
                   help="a Grease Pencil drawing (--grease-pencil, or a drawing's recipe such "
                   "as walk): each layer drawn this many pixels across (default 1024)")
    w.set_defaults(func=cmd_export_web)
