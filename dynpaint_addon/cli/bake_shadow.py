"""`dynpaint bake-shadow SHAPE --kind K --light X Y Z --out T.exr`: the raw
cos-θ term of one light (pipeline.md §6) at a quality level (§13), as a float EXR; with
`--layers SCENE.toml --out DIR` the term of every layer of a scene, the layers in front
casting their shadows (§15), as DIR/layer_<i>.exr."""
import argparse
import os
import time

import numpy as np

from .. import params
from ..core.bake import QUALITY, quality_level, quality_settings
from ..core.layers import bake_scene
from ..core.lights import Light
from ..core.input_rules import finite_image, pixel_role
from ..core.pipeline import shadow_term, shape_normals
from ..core.shadow import ShadowStats
from ..errors import CommandError
from ..inputs import memory
from ..inputs.imageio import painting_headers, read_image, write_exr
from ..inputs.layered_files import load_layered
from .notes import check_and_print, print_notes


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
    """An option for the parameter at `path`, with the table's default, unit and help. Its
    value is None unless given (the parameters' own defaults then apply, and --layers
    leaves each layer's recipe as it is); options whose default depends on others say so
    (K and the resolution follow --quality, the pre-blur the image's bit depth)."""
    prm = params.BY_PATH[path]
    unit = f" {prm.unit}" if prm.unit else ""
    shown = "from --quality" if path in ("shadows.steps", "shadows.resolution") else \
        str(prm.default)
    text = f"{prm.help}{unit and f' (in{unit})'}; default: {shown}"
    if prm.kind is bool:
        parser.add_argument(flag, action="store_true", default=None, help=text)
    elif prm.kind == "enum":
        parser.add_argument(flag, choices=prm.choices, help=text)
    elif prm.kind == "auto_float":        # a number, or 'auto' as the help describes it
        parser.add_argument(flag, type=_auto_or_number, metavar="{auto,NUMBER}", help=text)
    else:
        parser.add_argument(flag, type=int if prm.kind is int else float, help=text)


def _auto_or_number(text):
    """An option that takes 'auto' or a number (argparse's type)."""
    if text == "auto":
        return text
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected 'auto' or a number, got {text!r}") from None


def _given(args, options):
    """{params.py path: value} of the parameter options given on the command line."""
    return {path: getattr(args, _dest(flag)) for flag, path in options.items()
            if getattr(args, _dest(flag)) is not None}


def _check_ranges(args, options):
    """Every parameter option as its params.py entry allows (Param.check), or one clear line."""
    for flag, path in options.items():
        value = getattr(args, _dest(flag))
        if value is not None:
            try:
                params.BY_PATH[path].check(value)
            except ValueError as exc:
                raise CommandError(f"{flag}: {exc}") from None


def _set(p, given):
    """p with the parameters `given` ({path: value}) set."""
    for path, value in given.items():
        section, key = path.split(".")
        setattr(getattr(p, section), key, value)
    return p


def _bake_params(args):
    """The recipe parameters bake-shadow's options set (the rest at their defaults)."""
    p = _set(params.defaults(), _given(args, BAKE_OPTIONS))
    p.shape.kind = args.kind
    return p


def _light(args):
    """The light the options name, its size from --light-angle or --light-radius (§15)."""
    if args.light_angle is not None and not args.light:
        raise CommandError("--light-angle is a sun's size: give it with --light")
    if args.light_radius is not None and not args.point_light:
        raise CommandError("--light-radius is a point light's size: give it with --point-light")
    if args.light_angle is not None and not 0 <= args.light_angle <= 180:
        raise CommandError(f"--light-angle: degrees in 0 … 180, got {args.light_angle:g}")
    try:
        if args.light:
            return Light("sun", args.light, size=np.radians(args.light_angle or 0.0))
        return Light("point", args.point_light, size=args.light_radius or 0.0)
    except ValueError as exc:
        raise CommandError(f"{'--light' if args.light else '--point-light'}: {exc}") from None


def cmd_bake_layers(args):
    """bake-shadow --layers: each layer's t = t_own·T (§15) as DIR/layer_<i>.exr, i = 0 at
    the back (the recipe's order); --quality, when given, sets every layer's level."""
    if args.shape or args.kind:
        raise CommandError("--layers bakes the layers of a scene: give no SHAPE or --kind "
                           "(each layer's recipe says its own)")
    if os.path.splitext(args.out)[1]:
        raise CommandError(f"--out {args.out}: with --layers, a folder (it gets layer_0.exr, "
                           f"layer_1.exr, …)")
    _check_ranges(args, BAKE_OPTIONS)
    light = _light(args)
    layers, _, notes = load_layered(args.layers)
    for layer in layers:                   # what the command line gives, every layer takes
        _set(layer.p, _given(args, BAKE_OPTIONS))
    print_notes(notes)
    t0 = time.perf_counter()
    terms = bake_scene(layers, light)
    ms = (time.perf_counter() - t0) * 1000
    os.makedirs(args.out, exist_ok=True)
    for i, t in enumerate(terms):
        write_exr(os.path.join(args.out, f"layer_{i}.exr"), t)
    if args.verbose:
        sizes = ", ".join(f"{t.shape[1]}×{t.shape[0]}" for t in terms)
        print(f"bake: {ms:.1f} ms for {len(terms)} layers ({sizes}), {light.kind} light")
    print(f"wrote {len(terms)} layers to {args.out} (layer_0.exr at the back)")


def cmd_bake_shadow(args):
    if args.layers:
        return cmd_bake_layers(args)
    if not args.shape or not args.kind:
        raise CommandError("bake-shadow needs SHAPE and --kind (or --layers SCENE.toml)")
    if not os.path.splitext(args.out)[1].lower() == ".exr":
        raise CommandError(f"--out {args.out}: the shadow term is written as a float EXR (.exr)")
    _check_ranges(args, BAKE_OPTIONS)
    light = _light(args)
    p = _bake_params(args)
    quality = quality_level(p.shadows.quality, args.steps, args.scale)
    level = QUALITY.get(p.shadows.quality, {"steps": params.BY_PATH["shadows.steps"].default,
                                            "scale": params.BY_PATH["shadows.resolution"].default})
    steps, scale, dtype = quality_settings(
        quality, level["steps"] if args.steps is None else args.steps,
        level["scale"] if args.scale is None else args.scale)
    headers = painting_headers({"shape": args.shape}) if os.path.isfile(args.shape) else None
    if headers is not None:             # memory asked for before it is spent
        painting = memory.painting(headers, p)
        memory.check(memory.bake_shadow_bytes(painting, p, light),
                     f"baking {painting.width}×{painting.height}",
                     "give a smaller shape image (scale it down in a painting program)")
    shape = read_image(args.shape)
    if not np.any(np.isfinite(shape.pixels)):     # as render refuses it (core.pipeline.prepare)
        raise CommandError(f"{args.shape}: the shape image has no finite pixel (all NaN or Inf)")
    check_and_print({"shape": shape}, p)
    shape, warning = finite_image(shape, pixel_role("shape", p), "shape image")
    print_notes([warning] if warning else [])
    n, z, slopes = shape_normals(shape, p, dtype)
    stats = ShadowStats()
    t0 = time.perf_counter()
    p.shadows.quality, p.shadows.steps, p.shadows.resolution = quality, steps, scale
    t = shadow_term(n, z, slopes, light, p, stats=stats)
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


def add_parser(sub):
    """Register `bake-shadow` on the command line's subparsers."""
    b = sub.add_parser("bake-shadow", help="bake the raw cos-θ shadow term t = d/max(r, d) to EXR",
                       usage="dynpaint bake-shadow (SHAPE --kind {height,normal} | --layers "
                             "SCENE) (--light X Y Z | --point-light X Y Z) [options] --out OUT",
                       description="Bake the raw cos-θ term (pipeline.md §6) of one light as a "
                                   "one-channel float EXR of the shape image's size.")
    b.add_argument("shape", metavar="SHAPE", nargs="?", help="normal map or height map image")
    b.add_argument("--kind", choices=("height", "normal"),
                   help="what SHAPE holds (needed with SHAPE)")
    b.add_argument("--layers", metavar="SCENE",
                   help="bake every layer of a layered recipe, an .ora file or a folder of "
                        "layer images instead (§15): the layers in front cast their shadows; "
                        "--out is then a folder")
    lg = b.add_mutually_exclusive_group(required=True)
    lg.add_argument("--light", nargs=3, type=float, metavar=("X", "Y", "Z"),
                    help="sun: direction toward the light in the painting frame (any length)")
    lg.add_argument("--point-light", nargs=3, type=float, metavar=("X", "Y", "Z"),
                    help="point light position, image widths from the painting's centre")
    size = b.add_mutually_exclusive_group()
    size.add_argument("--light-angle", type=float, metavar="DEG",
                      help="the sun's angular diameter in degrees (Blender's Sun Angle): "
                           "softens the shadows layers cast (default 0, hard)")
    size.add_argument("--light-radius", type=float, metavar="R",
                      help="the point light's radius in image widths (Blender's Radius)")
    for flag, path in BAKE_OPTIONS.items():
        add_param_option(b, flag, path)
    b.add_argument("--out", required=True,
                   help="output .exr (one channel, Y); with --layers a folder")
    b.add_argument("-v", "--verbose", action="store_true",
                   help="print the bake's own time (ms, no process start or file I/O) and settings")
    b.set_defaults(func=cmd_bake_shadow)
