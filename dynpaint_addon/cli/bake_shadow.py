"""`python -m dynpaint_addon bake-shadow SHAPE --kind K --light X Y Z --out T.exr`: the raw
cos-θ term of one light (pipeline.md §6) at a quality level (§13), as a float EXR."""
import os
import time

import numpy as np

from .. import params
from ..core.bake import QUALITY, bake, quality_level, quality_settings
from ..core.lights import Light
from ..core.pipeline import shape_normals
from ..core.shadow import ShadowStats
from ..errors import CommandError
from ..imageio import read_image, write_exr
from .notes import check_and_print


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


def add_parser(sub):
    """Register `bake-shadow` on the command line's subparsers."""
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
