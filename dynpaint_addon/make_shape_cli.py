"""`python -m dynpaint_addon make-shape METHOD …`: height and normal maps made from what the
artist has (docs/shape-from-painting.md). Registered by cli.py; the work is in shape_maker and
the core."""
import argparse
import os
import time

import numpy as np

from . import params
from .core.inflate import PROFILES, inflate
from .core.integrate import integrate
from .core.occlusion import ambient_occlusion
from .core.photometric import SIDES, normals_from_profiles, normals_from_rg_photo
from .core.pipeline import input_notes, normal_map_relief_px, shape_normals
from .core.shape import ENCODINGS
from .imageio import read_image, write_exr, write_png
from .notes import check_and_print, figure_note, print_notes
from .recipe import load_recipe
from .samples import recipe_help
from .shape_maker import (GREENS, ShapeError, decode_normals, encode_normals, figure_and_source,
                          figure_mask, height_widths, linear_luminance, normals_of_height, same_size,
                          sprite_lamp_side)


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


def _strength(text):
    """--strength: 'auto' or a number in shape.strength's range."""
    if text == "auto":
        return text
    prm = params.BY_PATH["shape.strength"]
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number or auto, got {text!r}") from None
    if not prm.min <= value <= prm.max:
        raise argparse.ArgumentTypeError(f"must be in [{prm.min:g}, {prm.max:g}], got {value:g}")
    return value


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
    img = read_image(args.height)
    started = time.perf_counter()
    n = normals_of_height(height_widths(img, args.height_scale, args.preblur))
    _timed(args, "normals", started)
    _write_normals(args.out, n, args.green)


def _profile_images(args):
    """{side: path} from the --left … options and Sprite Lamp file names."""
    chosen = {side: getattr(args, side) for side in SIDES if getattr(args, side)}
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


def add_parser(sub):
    """Register `make-shape` and its methods on the command line's subparsers."""
    ms = sub.add_parser("make-shape", help="make a height or normal map from what you have",
                        description="Make the shape image: integrate a normal map into heights, "
                        "take a height map's normals, solve lighting profiles or a red/green "
                        "photograph for normals, inflate a silhouette, export maps for game "
                        "engines. Heights are in image widths.")
    methods = ms.add_subparsers(dest="method", required=True, metavar="METHOD")

    def method(name, help_, func):
        m = methods.add_parser(name, help=help_, description=help_)
        m.add_argument("-v", "--verbose", action="store_true", help="print the time (and, for "
                       "integrate, the non-integrable residual)")
        m.set_defaults(func=func)
        return m

    def green_option(m):
        m.add_argument("--green", choices=GREENS, default="opengl",
                       help="normal map convention: opengl (green = up, Blender) or directx "
                       "(green = down)")

    def normal_map_out(m):
        green_option(m)
        m.add_argument("--out", required=True, help="normal map (.png 16-bit or .exr)")

    m = method("integrate", "normal map → height map by least squares (free edges)",
               cmd_integrate)
    m.add_argument("normal", metavar="NORMAL", help="normal map image")
    m.add_argument("--mask", default="none", help="figure mask image (white or alpha = figure), "
                   "'alpha' for the normal map's own alpha, or 'none' (default): equations "
                   "across the mask's edge are dropped, each part integrated on its own")
    m.add_argument("--depth", type=float, default=0.0, help="with a mask: how far the figure's "
                   "rim stands above its background (image widths, default 0)")
    m.add_argument("--encoding", choices=ENCODINGS, default="auto",
                   help="rgb, rg (two-channel) or auto (as shape.encoding)")
    m.add_argument("--flip-green", action="store_true", help="DirectX normal map (green down)")
    m.add_argument("--strength", type=_strength, default="auto",
                   help="scale of each normal's tilt: a number (0.5 for tilt-halving maps) or "
                   "auto (default; as shape.strength)")
    m.add_argument("--residual", help="also write the residual |g − ∇z| per pixel (.exr)")
    m.add_argument("--out", required=True, help="height map: .exr (image widths) or .png (16-bit)")

    m = method("normals", "height map → normal map (§2)", cmd_normals)
    m.add_argument("height", metavar="HEIGHT", help="height map (grey; EXR in image widths)")
    m.add_argument("--height-scale", type=float, required=True,
                   help="relief of a white pixel (image widths; 1 for make-shape's EXRs)")
    m.add_argument("--preblur", type=float, default=0.0,
                   help="Gaussian blur before the slopes are taken (pixels; 1.5 for 8-bit maps)")
    normal_map_out(m)

    m = method("profiles", "lighting profiles (2–5 images lit from the sides) → normal map",
               cmd_profiles)
    m.add_argument("images", nargs="*", metavar="IMAGE",
                   help="profiles named in Sprite Lamp's convention (name_left.png, _right, _top, "
                   "_bottom, _front)")
    for side in SIDES:
        m.add_argument(f"--{side}", help=f"the image lit from the {side}")
    m.add_argument("--elevation", type=float, default=45.0,
                   help="the side lights' height above the painting (degrees, default 45)")
    normal_map_out(m)

    m = method("rg-photo", "photograph lit red from one side, green from the top → normal map",
               cmd_rg_photo)
    m.add_argument("photo", metavar="PHOTO", help="the photograph")
    m.add_argument("--red-from", choices=("right", "left"), default="right",
                   help="side the red light came from (default right)")
    m.add_argument("--green-from", choices=("top", "bottom"), default="top",
                   help="side the green light came from (default top)")
    normal_map_out(m)

    m = method("inflate", "silhouette → round height map (−Δh = 1 inside, h = 0 on its edge)",
               cmd_inflate)
    m.add_argument("image", metavar="IMAGE", help="painting with alpha, or a mask (white = figure)")
    m.add_argument("--profile", choices=PROFILES, default="round",
                   help="round (a disc gives a hemisphere), soft or flat (rounded rims, a plateau)")
    m.add_argument("--height", type=float, default=1.0,
                   help="scale of the relief (1: a disc's hemisphere as tall as its radius)")
    m.add_argument("--mask-channel", default="auto",
                   choices=("auto", "alpha", "luminance", "red", "green", "blue"),
                   help="what of IMAGE is the figure (auto: its alpha, else a painted mask)")
    m.add_argument("--detail", type=float, default=0.0,
                   help="emboss the painting's luminance: image widths of relief per unit "
                   "of luminance (e.g. 0.01; default 0 = none)")
    m.add_argument("--detail-image", help="the painting whose luminance is embossed "
                   "(default IMAGE)")
    m.add_argument("--detail-blur", type=float, default=0.002,
                   help="blur of the embossed luminance (image widths, default 0.002)")
    m.add_argument("--out", required=True, help="height map: .exr (image widths) or .png (16-bit)")

    m = method("export-maps", "a recipe's maps for game engines: normal, height, AO, specular",
               cmd_export_maps)
    m.add_argument("recipe", metavar="RECIPE", help=recipe_help())
    green_option(m)
    m.add_argument("--out", required=True, help="folder for normal.png, height.exr/.png, "
                   "ambient_occlusion.png, specular.png")
