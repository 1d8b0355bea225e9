"""Command line: `python -m dynpaint_addon <command>` (see --help of each command).

User mistakes (missing files, unreadable images, bad recipes or options: errors.UserError) end
with one line `error: …` on stderr and exit status 1 (2 for malformed command lines); never a
traceback.
"""
import argparse
import difflib
import os
import sys
import time

import numpy as np

from . import params
from .core.colour import linear_to_srgb
from .core.lights import Light
from .core.input_rules import PER_PIXEL_CHANNELS, ImageData
from .core.pipeline import render, shape_normals
from .core.sampling import resample
from .core.bake import QUALITY, bake, quality_level, quality_settings
from .core.shadow import ShadowStats
from .errors import UserError
from .export_web_cli import add_parser as add_export_web_parser
from .imageio import read_image, write_exr, write_png
from .make_shape_cli import add_parser as add_make_shape_parser
from .notes import check_and_print, print_notes
from .recipe import load_images, load_recipe
from .samples import recipe_help
from .testpainting import builtin_images, builtin_recipe, write_test_painting


class CommandError(UserError):
    """A user-facing problem with a command's options."""


def write_render(path, rgba):
    """Write premultiplied linear RGBA: .exr as is (float), .png as 8-bit sRGB straight alpha."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".exr":
        write_exr(path, rgba)
    elif ext == ".png":
        out = np.empty(rgba.shape[:2] + (4,), np.float32)
        rows = max(1, (1 << 20) // max(1, rgba.shape[1]))     # bands: bounded temporaries
        for r in range(0, rgba.shape[0], rows):
            band = rgba[r:r + rows]
            a = band[..., 3:4]
            straight = np.where(a > 0, band[..., :3] / np.where(a > 0, a, 1), 0)
            out[r:r + rows, :, :3] = linear_to_srgb(straight)
            out[r:r + rows, :, 3:] = a
        write_png(path, out, bits=8)
    else:
        raise CommandError(f"{path}: unsupported output format '{ext}' (use .png or .exr)")


def _resample_images(images, width):
    """--width: resample the shape and every per-pixel image so the shape is `width` px wide.

    Environment and background are looked up by UV (§8, §9), so their size does not matter.
    """
    h0, w0 = images["shape"].pixels.shape[:2]
    height = max(1, round(h0 * width / w0))
    return {ch: ImageData(resample(img.pixels, height, width), img.bits, img.name)
            if ch == "shape" or ch in PER_PIXEL_CHANNELS else img
            for ch, img in images.items()}


ENGINES = ("numpy", "cycles", "eevee")


def cmd_render(args):
    if args.width is not None and args.width < 1:
        raise CommandError(f"--width must be at least 1 pixel, got {args.width}")
    recipe = load_recipe(args.recipe)
    if args.engine != "numpy":
        return _render_blender(args, recipe)
    if args.frame is not None:
        raise CommandError("--frame needs --engine eevee or cycles (the numpy engine renders "
                           "the recipe's lights as written)")
    images = load_images(recipe)
    if args.width:
        images = _resample_images(images, args.width)
    dtype = np.float64 if args.float64 else np.float32
    h, w = images["shape"].pixels.shape[:2]
    if w * h >= 4096 * 4096:     # say what a long render is doing before it starts
        print(f"rendering {w}×{h} ({w * h / 1e6:.0f} Mpx) with the numpy core: about "
              f"{w * h * 80 / 2**30:.0f} GiB of memory and a minute or more", flush=True)
    t = time.perf_counter()
    result = render(images, recipe.lights, recipe.params, dtype, keep_passes=False)
    ms = (time.perf_counter() - t) * 1000
    print_notes(result.warnings)
    write_render(args.out, result.rgba)
    h, w = result.rgba.shape[:2]
    print(f"rendered {w}×{h} in {ms:.0f} ms → {args.out}")


def _render_blender(args, recipe):
    """EEVEE or Cycles in background Blender, the scene built as the add-on builds it."""
    if args.width or args.float64:
        raise CommandError("--width and --float64 apply to the numpy engine only")
    if os.path.splitext(args.out)[1].lower() not in (".png", ".exr"):
        raise CommandError(f"{args.out}: unsupported output format (use .png or .exr)")
    from .blender.headless import render_recipe     # Blender only when asked for
    seconds = render_recipe(recipe, args.engine, args.out, args.frame, notes=print_notes)
    print(f"rendered with {args.engine} in {seconds * 1000:.0f} ms → {args.out}")


# bake-shadow's options that are recipe parameters: flag → params.py path (default, unit,
# range and help come from the table)
BAKE_OPTIONS = {"--height-scale": "shape.height_scale", "--preblur": "shape.preblur",
                "--flip-green": "shape.flip_green", "--z-min": "shape.z_min",
                "--offset": "shadows.offset", "--steps": "shadows.steps",
                "--scale": "shadows.resolution", "--quality": "shadows.quality",
                "--occupancy": "shadows.occupancy", "--relief": "shadows.relief",
                "--reach": "shadows.reach", "--encoding": "shape.encoding",
                "--strength": "shape.strength"}


def _dest(flag):
    return flag.lstrip("-").replace("-", "_")


def add_param_option(parser, flag, path):
    """An option for the parameter at `path`, with the table's default, unit and help.
    Options whose default depends on others (K and the resolution follow --quality, the
    pre-blur the image's bit depth) default to None: 'from …'."""
    prm = params.BY_PATH[path]
    unit = f" {prm.unit}" if prm.unit else ""
    follows = path in ("shadows.steps", "shadows.resolution") or prm.kind == "auto_float"
    default = None if follows else prm.default
    if path in ("shadows.steps", "shadows.resolution"):
        shown = "from --quality"
    else:
        shown = str(prm.default)
    text = f"{prm.help}{unit and f' (in{unit})'}; default: {shown}"
    if prm.kind is bool:
        parser.add_argument(flag, action="store_true", help=text)
    elif prm.kind == "enum":
        parser.add_argument(flag, choices=prm.choices, default=default, help=text)
    else:
        parser.add_argument(flag, type=int if prm.kind is int else float, default=default,
                            help=text)


def _check_ranges(args, options):
    """Every parameter option as its params.py entry allows (Param.check), or one clear line."""
    for flag, path in options.items():
        value = getattr(args, _dest(flag))
        if value is not None and value is not False:
            try:
                params.BY_PATH[path].check(value)
            except ValueError as exc:
                raise CommandError(f"{flag}: {exc}") from None


def _bake_params(args):
    """The recipe parameters bake-shadow's options set (the rest at their defaults)."""
    p = params.defaults()
    for flag, path in BAKE_OPTIONS.items():
        value = getattr(args, _dest(flag))
        if value is not None:
            section, key = path.split(".")
            setattr(getattr(p, section), key, value)
    p.shape.kind = args.kind
    return p


def cmd_bake_shadow(args):
    if not os.path.splitext(args.out)[1].lower() == ".exr":
        raise CommandError(f"--out {args.out}: the shadow term is written as a float EXR (.exr)")
    _check_ranges(args, BAKE_OPTIONS)
    try:
        light = Light("sun", args.light) if args.light else Light("point", args.point_light)
    except ValueError as exc:
        raise CommandError(str(exc)) from None
    p = _bake_params(args)
    quality = quality_level(args.quality, args.steps, args.scale)
    level = QUALITY.get(args.quality, {"steps": params.BY_PATH["shadows.steps"].default,
                                       "scale": params.BY_PATH["shadows.resolution"].default})
    steps, scale, dtype = quality_settings(
        quality, level["steps"] if args.steps is None else args.steps,
        level["scale"] if args.scale is None else args.scale)
    shape = read_image(args.shape)
    check_and_print({"shape": shape}, p)
    n, z, slopes = shape_normals(shape, p, dtype)
    stats = ShadowStats()
    t0 = time.perf_counter()
    t = bake(n, light, p.shadows.offset, quality, heights_px=z, slopes=slopes, steps=steps,
             scale=scale, occupancy=p.shadows.occupancy, reach=p.shadows.reach, stats=stats)
    ms = (time.perf_counter() - t0) * 1000
    write_exr(args.out, t)
    if args.verbose:
        h, w = t.shape
        print(f"bake: {ms:.1f} ms for {w}×{h} ({args.kind} map, {light.kind} light)")
        how = f"steps={steps} (marched {stats.steps}) longest march=" \
            f"{stats.max_march_px:.1f} px" if stats.method == "march" else \
            f"method={stats.method} ({light.kind}; K does not apply)"
        bh, bw = stats.size
        print(f"settings: quality={quality} {how} resolution={bw}×{bh} "
              f"dtype={np.dtype(dtype).name} offset={p.shadows.offset} image widths")
    print(f"wrote {args.out}")


def cmd_turntable(args):
    out_ext = os.path.splitext(args.out)[1].lower()
    if out_ext not in (".mp4", ".mkv", ".mov"):
        raise CommandError(f"--out {args.out}: a turntable is a video (use .mp4)")
    if args.frames < 2:
        raise CommandError(f"--frames must be at least 2, got {args.frames}")
    if args.size is not None and min(args.size) < 16:
        raise CommandError(f"--size must be at least 16 × 16 pixels, got {args.size}")
    if args.size is not None and any(s % 2 for s in args.size):
        raise CommandError(f"--size must be even in both directions (H.264), got {args.size}")
    if args.samples is not None and args.samples < 1:
        raise CommandError(f"--samples must be at least 1, got {args.samples}")
    if args.elevation is not None and not -90 <= args.elevation <= 90:
        raise CommandError(f"--elevation must be in [-90, 90] degrees, got {args.elevation}")
    recipe = load_recipe(args.recipe)
    from .blender.headless import render_turntable  # Blender only when asked for
    try:
        seconds, samples = render_turntable(
            recipe, args.out, args.frames, args.engine, args.size, args.elevation, args.light,
            args.clockwise, args.samples, args.fps,
            progress=lambda line: print(line, flush=True), notes=print_notes)
    except ValueError as exc:
        raise CommandError(str(exc)) from None
    print(f"turntable: {args.frames} frames with {args.engine}, {samples} sample"
          f"{'s' if samples > 1 else ''} a pixel, in {seconds:.1f} s "
          f"({seconds / args.frames:.2f} s/frame) → {args.out}")


def cmd_demo(args):
    recipe = builtin_recipe()
    t = time.perf_counter()
    result = render(builtin_images(args.size), recipe.lights, recipe.params)
    ms = (time.perf_counter() - t) * 1000
    write_render(args.out, result.rgba)
    print(f"rendered the built-in test painting ({args.size}×{args.size}, numpy core, "
          f"cos-θ shadows, 2 lights) in {ms:.0f} ms → {args.out}")


def cmd_make_test_painting(args):
    path = write_test_painting(args.folder, args.size)
    print(f"wrote {path}")


def cmd_params(args):
    section = None
    for p in params.PARAMS:
        if p.section != section:
            section = p.section
            print(f"\n[{section}]")
        rng = f" range [{p.min}, {p.max}]" if p.min is not None else ""
        choices = f" one of: {', '.join(p.choices)}" if p.choices else ""
        unit = f" ({p.unit})" if p.unit else ""
        print(f"  {p.key} = {p.default!r}{unit}{rng}{choices}  {p.spec}\n      {p.help}")
    print("\n[images]  (paths relative to the recipe)")
    for ch, (what, space) in params.CHANNELS.items():
        print(f"  {ch}: {what} [{space}]")
    print("\n[[lights]]  type = \"sun\" with direction = [x, y, z] (toward the light), or "
          "\"point\" with position = [x, y, z] (image widths from the painting's centre);\n"
          "            color = [r, g, b] (linear), strength = k ≥ 0 (pipeline.md §5)")


def build_parser():
    ap = argparse.ArgumentParser(
        prog="python -m dynpaint_addon",
        description="Dynamic Painting: relight a painting from its images (pipeline.md). "
                    "Lengths are in image widths; the painting frame has x right, y up, z toward "
                    "the viewer, origin at the painting's centre.")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")

    r = sub.add_parser("render", help="render a recipe to an image",
                       description="Render a painting recipe (painting.toml) to PNG (8-bit sRGB) "
                                   "or EXR (linear float, premultiplied RGBA).")
    r.add_argument("recipe", help=recipe_help())
    r.add_argument("--out", required=True, help="output image (.png or .exr)")
    r.add_argument("--engine", default="numpy", choices=ENGINES,
                   help="numpy (the reference core, default), or cycles / eevee (the add-on's "
                        "material in background Blender, framed pixel for pixel)")
    r.add_argument("--frame", type=int, help="scene frame to render (eevee/cycles; keyframed "
                                             "lights and parameters move with it)")
    r.add_argument("--width", type=int, help="output width in pixels (default: the shape image's); "
                                             "every per-pixel image is resampled to it")
    r.add_argument("--float64", action="store_true", help="compute in float64 (reference)")
    r.set_defaults(func=cmd_render)

    b = sub.add_parser("bake-shadow", help="bake the raw cos-θ shadow term t = d/max(r, d) to EXR",
                       description="Bake the raw cos-θ term (pipeline.md §6) of one light as a "
                                   "one-channel float EXR of the shape image's size.")
    b.add_argument("shape", metavar="SHAPE", help="normal map or height map image")
    b.add_argument("--kind", required=True, choices=("height", "normal"), help="what SHAPE holds")
    lg = b.add_mutually_exclusive_group(required=True)
    lg.add_argument("--light", nargs=3, type=float, metavar=("X", "Y", "Z"),
                    help="sun: direction toward the light in the painting frame (any length)")
    lg.add_argument("--point-light", nargs=3, type=float, metavar=("X", "Y", "Z"),
                    help="point light position, image widths from the painting's centre")
    for flag, path in BAKE_OPTIONS.items():
        add_param_option(b, flag, path)
    b.add_argument("--out", required=True, help="output .exr (one channel, Y)")
    b.add_argument("-v", "--verbose", action="store_true",
                   help="print the bake's own time (ms, no process start or file I/O) and settings")
    b.set_defaults(func=cmd_bake_shadow)

    tt = sub.add_parser("turntable", help="render a light turntable of a recipe to a video",
                        description="The recipe's first Sun (or --light) orbits the painting once, "
                        "starting where the recipe puts it; each frame re-bakes its shadows.")
    tt.add_argument("recipe", help=recipe_help())
    tt.add_argument("--frames", type=int, default=48, help="frames in one orbit (default 48)")
    tt.add_argument("--engine", choices=("eevee", "cycles"), default="cycles",
                    help="cycles (default: CPU, any machine) or eevee (fast with a GPU; this "
                    "needs an OpenGL/EGL driver even in the background)")
    tt.add_argument("--size", type=int, nargs=2, metavar=("W", "H"),
                    help="video size in pixels (default: the shape image's size)")
    tt.add_argument("--out", required=True, help="video file (.mp4, H.264)")
    tt.add_argument("--elevation", type=float, help="light elevation above the painting in "
                    "degrees (default: where the recipe puts the light)")
    tt.add_argument("--light", help="name of the recipe light to orbit (default: its first Sun)")
    tt.add_argument("--clockwise", action="store_true", help="orbit clockwise (seen from the front)")
    tt.add_argument("--samples", type=int, help="render samples per pixel; default: one at the "
                    "shape image's size (the video frames the painting pixel for pixel, and one "
                    "sample at each pixel centre is the exact image), antialiased at other sizes "
                    "(the count is printed)")
    tt.add_argument("--fps", type=int, default=24, help="frames per second of the video "
                    "(default 24)")
    tt.set_defaults(func=cmd_turntable)
    d = sub.add_parser("demo", help="render the built-in test painting with the numpy core (no "
                       "Blender needed; the README's main job is `turntable portrait`)")
    d.add_argument("--out", default="out/demo.png", help="output image (default out/demo.png)")
    d.add_argument("--size", type=int, default=256, help="size in pixels (default 256)")
    d.set_defaults(func=cmd_demo)

    m = sub.add_parser("make-test-painting", help="write the built-in test painting as files")
    m.add_argument("folder", help="folder for painting.toml and its images")
    m.add_argument("--size", type=int, default=256, help="size in pixels (default 256)")
    m.set_defaults(func=cmd_make_test_painting)

    pa = sub.add_parser("params", help="list every recipe parameter with its unit, range, default")
    pa.set_defaults(func=cmd_params)
    add_make_shape_parser(sub)
    add_export_web_parser(sub)
    return ap


def main(argv=None):
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    unknown = _unknown_command(parser, argv)
    if unknown:
        parser.print_usage(sys.stderr)
        print(f"error: {unknown}", file=sys.stderr)
        return 2
    args = parser.parse_args(argv)
    try:
        args.func(args)
    except UserError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except BrokenPipeError:
        # `params | head`: the reader has gone; say nothing more (Python's own advice)
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except (ValueError, OSError, MemoryError) as exc:
        print(f"error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1
    return 0


def _unknown_command(parser, argv):
    """'rendr: no such command (did you mean 'render'?)' for a first word that names none."""
    if not argv or argv[0].startswith("-"):
        return ""
    commands = next(a for a in parser._actions
                    if isinstance(a, argparse._SubParsersAction)).choices
    if argv[0] in commands:
        return ""
    close = difflib.get_close_matches(argv[0], list(commands), n=1)
    hint = f" (did you mean '{close[0]}'?)" if close else ""
    return f"'{argv[0]}' is no command{hint}; the commands: {', '.join(commands)}"
