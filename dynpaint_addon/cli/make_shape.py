"""`python -m dynpaint_addon make-shape METHOD …`: height and normal maps made from what the
artist has (docs/shape-from-painting.md). Registered by cli/__init__.py; the options are
shape_methods.OPTIONS; the work is shape_maker's and the core's."""
import argparse
import os
import time

import numpy as np

from .. import params
from ..core.inflate import inflate
from ..core.input_rules import input_notes
from ..core.integrate import integrate
from ..core.occlusion import ambient_occlusion
from ..core.photometric import SIDES, normals_from_profiles, normals_from_rg_photo
from ..core.pipeline import normal_map_relief_px, shape_normals
from ..imageio import read_image, write_exr, write_png
from ..recipe import load_recipe
from ..shape_maker import (ShapeError, decode_normals, encode_normals, figure_and_source,
                          figure_mask, height_widths, linear_luminance, normals_of_height, same_size,
                          sprite_lamp_side)
from ..shape_methods import METHODS, options
from .notes import check_and_print, figure_note, print_notes


def _write_height(path, z):
    """Heights in image widths: EXR as they are (bake-shadow --height-scale 1 reads them at
    their true scale), PNG as 16-bit 0..1 of the highest point (its height_scale printed)."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".exr":
        write_exr(path, z.astype(np.float32))
        print(f"wrote {path} (heights in image widths, 0 … {z.max():.4g}: height_scale 1)")
    elif ext == ".png":
        top = float(z.max())
        write_png(path, z / top if top > 0 else z, bits=16)
        print(f"wrote {path} (16-bit; white = {top:.4g} image widths: height_scale {top:.4g})")
    else:
        raise ShapeError(f"--out {path}: write a height map as .exr (float) or .png (16-bit)")


def _write_normals(path, n, green):
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".png", ".exr"):
        raise ShapeError(f"--out {path}: write a normal map as .png (16-bit) or .exr")
    rgb = encode_normals(n, green)
    (write_exr if ext == ".exr" else lambda p, px: write_png(p, px, bits=16))(path, rgb)
    print(f"wrote {path} ({green} green)")


def _timed(args, what, started):
    if args.verbose:
        print(f"{what}: {time.perf_counter() - started:.3f} s")


def cmd_integrate(args):
    img = read_image(args.normal)
    p = params.defaults()
    p.shape.encoding, p.shape.strength = args.encoding, args.strength
    try:
        notes = input_notes({"shape": img}, p)
    except ValueError as exc:
        raise ShapeError(str(exc)) from None
    n = decode_normals(img, args.encoding, args.flip_green, args.strength)
    mask = None
    if args.mask == "alpha":
        if img.alpha() is None:
            raise ShapeError(f"--mask alpha: {args.normal} has no alpha channel")
        mask = figure_mask(img, "alpha")
    elif args.mask != "none":
        mimg = read_image(args.mask)
        if mimg.size != img.size:
            raise ShapeError(f"--mask {args.mask} is {mimg.size[0]}×{mimg.size[1]}, the normal "
                             f"map {img.size[0]}×{img.size[1]}: they must match")
        mask, source = figure_and_source(mimg)
        notes.append(figure_note(args.mask, source))
    started = time.perf_counter()
    result = integrate(n, mask, args.depth)
    _timed(args, "integrate", started)
    if args.verbose:
        print(f"residual (the part no height map has): RMS {result.residual_rms:.4g} "
              f"(slope units), {100 * result.residual_share:.2f} % of the field; "
              f"{result.parts} part(s)")
    _write_height(args.out, result.height)
    if args.residual:
        write_exr(args.residual, result.residual.astype(np.float32))
        print(f"wrote {args.residual} (|g − ∇z| per pixel, slope units)")
    print_notes(notes)          # once the work is done: an error stays one line


def cmd_normals(args):
    img = read_image(args.height_map)
    started = time.perf_counter()
    n = normals_of_height(height_widths(img, args.height_scale, args.preblur))
    _timed(args, "normals", started)
    _write_normals(args.out, n, args.green)


def _profile_images(args):
    """{side: path} from the --left … options and Sprite Lamp file names."""
    chosen = {side: getattr(args, f"profile_{side}") for side in SIDES
              if getattr(args, f"profile_{side}")}
    for path in args.images:
        side = sprite_lamp_side(path)
        if side is None:
            raise ShapeError(f"{path}: its name does not say a side (Sprite Lamp names end in "
                             f"_{', _'.join(SIDES)}); give it with --left, --right, …")
        chosen.setdefault(side, path)
    if len(chosen) < 2:
        raise ShapeError("profiles: give at least two lighting profiles (--left, --right, "
                         "--top, --bottom, --front, or files named like portrait_left.png)")
    return chosen


def cmd_profiles(args):
    paths = _profile_images(args)
    named = {side: path for side, path in paths.items() if path in args.images}
    images = {side: read_image(path) for side, path in paths.items()}
    same_size(images, "lighting profiles")
    started = time.perf_counter()
    n = normals_from_profiles({side: linear_luminance(img) for side, img in images.items()},
                              args.elevation)
    _timed(args, f"profiles ({', '.join(paths)})", started)
    _write_normals(args.out, n, args.green)
    print_notes([f"{path}: the {side} profile (by its name; --{side} sets it)"
                 for side, path in named.items()])


def cmd_rg_photo(args):
    img = read_image(args.photo)
    _write_normals(args.out, normals_from_rg_photo(img.rgb(), args.red_from, args.green_from),
                   args.green)


def cmd_inflate(args):
    img = read_image(args.image)
    mask, source = figure_and_source(img, args.mask_channel)
    if not mask.any():
        raise ShapeError(f"{args.image}: no figure to inflate (its mask is empty: give an "
                         f"image with alpha, or a mask painted white on black)")
    started = time.perf_counter()
    result = inflate(mask, args.profile, args.height, args.detail,
                     linear_luminance(read_image(args.detail_image) if args.detail_image
                                      else img) if args.detail else None, args.detail_blur)
    _timed(args, "inflate", started)
    _write_height(args.out, result.height)
    print_notes([figure_note(args.image, source)])


def cmd_export_maps(args):
    recipe = load_recipe(args.recipe)
    images = {c: read_image(path) for c, path in recipe.images.items()   # only what it exports
              if c in ("shape", "gloss")}
    p = recipe.params
    check_and_print(images, p)
    n, z_px, _ = shape_normals(images["shape"], p, np.float64, relief=False)
    if z_px is None:
        # a normal map's heights: its figure cut at the alpha (the shadows' default relief),
        # whichever relief the recipe's shadows use
        z_px = normal_map_relief_px(n, images["shape"], precise=True)
    height = z_px / n.shape[1]
    os.makedirs(args.out, exist_ok=True)
    out = {name: os.path.join(args.out, name) for name in
           ("normal.png", "height.exr", "height.png", "ambient_occlusion.png", "specular.png")}
    _write_normals(out["normal.png"], n, args.green)
    _write_height(out["height.exr"], height)
    _write_height(out["height.png"], height)
    write_png(out["ambient_occlusion.png"], ambient_occlusion(height), bits=16)
    print(f"wrote {out['ambient_occlusion.png']}")
    if "gloss" in images or p.specular.enabled:
        gloss = images["gloss"].grey() if "gloss" in images else np.ones(n.shape[:2])
        write_png(out["specular.png"], np.clip(gloss * p.specular.amount, 0, 1), bits=16)
        print(f"wrote {out['specular.png']}")


# make-shape METHOD's runner on the command line (files in, files out), by METHODS key
COMMANDS = {"integrate": cmd_integrate, "normals": cmd_normals, "profiles": cmd_profiles,
            "rg_photo": cmd_rg_photo, "inflate": cmd_inflate, "export_maps": cmd_export_maps}
OUT_HELP = {"height": "height map: .exr (image widths) or .png (16-bit)",
            "normal": "normal map (.png 16-bit or .exr)",
            "maps": "folder for normal.png, height.exr/.png, ambient_occlusion.png, specular.png"}


def _value_type(option):
    """argparse type of a number option: parsed, then checked (Option.check)."""
    def parse(text):
        try:
            value = text if option.kind == "auto_float" and text == "auto" else \
                (int if option.kind is int else float)(text)
            return option.check(value)
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
    return parse


def add_option(parser, option):
    """One row of shape_methods.OPTIONS as a command-line argument."""
    if option.positional:
        parser.add_argument(option.name, metavar=option.positional, help=option.help,
                            nargs="*" if option.many else None)
        return
    shown = (option.default is not None and option.kind is not bool
             and "default" not in option.help)
    text = option.help + (f" (default {option.default})" if shown else "")
    kw = {"dest": option.name, "help": text}
    if option.kind is bool:
        parser.add_argument(option.cli_flag, action="store_true", **kw)
    elif isinstance(option.kind, tuple):
        parser.add_argument(option.cli_flag, choices=option.kind, default=option.default, **kw)
    else:
        numeric = option.kind in (float, int, "auto_float")
        parser.add_argument(option.cli_flag, type=_value_type(option) if numeric else str,
                            default=option.default, required=option.required, **kw)


def add_parser(sub):
    """Register `make-shape` and its methods (shape_methods.METHODS, their options from
    shape_methods.OPTIONS) on the command line's subparsers."""
    ms = sub.add_parser("make-shape", help="make a height or normal map from what you have",
                        description="Make the shape image: integrate a normal map into heights, "
                        "take a height map's normals, solve lighting profiles or a red/green "
                        "photograph for normals, inflate a silhouette, export maps for game "
                        "engines. Heights are in image widths.")
    methods = ms.add_subparsers(dest="method", required=True, metavar="METHOD")
    for name, method in METHODS.items():
        m = methods.add_parser(method.command, help=method.help, description=method.help)
        m.add_argument("-v", "--verbose", action="store_true", help="print the time (and, for "
                       "integrate, the non-integrable residual)")
        m.set_defaults(func=COMMANDS[name])
        for option in options(name, "cli"):
            add_option(m, option)
        m.add_argument("--out", required=True, help=OUT_HELP[method.makes])
