"""`dynpaint make-shape METHOD …`: height and normal maps made from what the
artist has (docs/shape-from-painting.md). Registered by cli/__init__.py; the options are
shapes.methods.OPTIONS; the work is shapes.maker's and the core's."""
import argparse
import json
import os
import time
from dataclasses import dataclass, field

import numpy as np

from .. import params
from ..core.frames import SheetGrid, expand_pattern, is_pattern
from ..core.input_rules import input_notes
from ..core.integrate import integrate
from ..core.occlusion import ambient_occlusion
from ..core.photometric import SIDES, normals_from_profiles, normals_from_rg_photo
from ..core.pipeline import normal_map_relief_px, shape_normals
from ..inputs.channel_names import sprite_lamp_side
from ..inputs.imageio import read_image, write_exr, write_png
from ..inputs.whole_files import write_text_whole
from ..inputs.painting_frames import FrameInputs, PaintingFrames, grid_of, painting_slots
from ..inputs.recipe import DEFAULT_SUN_NOTE, load_recipe, no_drawing
from ..inputs.samples import recipe_help
from ..params import FRAME_BY_KEY
from ..shapes.frames import MadeFrames, fill_sheet, on_one_floor
from ..shapes.maker import (ShapeError, decode_normals, encode_normals, figure_and_source,
                            figure_mask, height_widths, linear_luminance, normals_of_height,
                            same_size)
from ..shapes.methods import METHODS, options
from ..shapes.painted import OPTIONS as RELIEF_OPTIONS
from ..shapes.painted import figure_relief
from ..shapes.relief import reads_painting
from .notes import check_and_print, figure_note, print_notes


def _write_height(path, z, top=None):
    """Heights in image widths: EXR as they are (bake-shadow --height-scale 1 reads them at
    their true scale), PNG as 16-bit 0..1 of `top` (default the highest point; a sequence's
    frames share one), its height_scale printed."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".exr":
        write_exr(path, z.astype(np.float32))
        return f"heights in image widths, 0 … {z.max():.4g}: height_scale 1"
    if ext == ".png":
        top = float(z.max()) if top is None else top
        write_png(path, z / top if top > 0 else z, bits=16)
        return f"16-bit; white = {top:.4g} image widths: height_scale {top:.4g}"
    raise ShapeError(f"--out {path}: write a height map as .exr (float) or .png (16-bit)")


def _write_normals(path, n, green):
    ext = os.path.splitext(path)[1].lower()
    if ext not in (".png", ".exr"):
        raise ShapeError(f"--out {path}: write a normal map as .png (16-bit) or .exr")
    rgb = encode_normals(n, green)
    (write_exr if ext == ".exr" else lambda p, px: write_png(p, px, bits=16))(path, rgb)
    return f"{green} green"


@dataclass
class Made:
    """What a method made of one frame: heights (image widths; `lowest_zero`: shifted so
    that the lowest point is 0, over every frame of a sequence) or unit normals."""
    kind: str
    values: np.ndarray
    notes: list = field(default_factory=list)
    lowest_zero: bool = False
    residual: np.ndarray = None


def _timed(args, what, started):
    if args.verbose:
        print(f"{what}: {time.perf_counter() - started:.3f} s")


def make_integrate(args, read):
    img = read(args.normal)
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
        mimg = read(args.mask)
        if mimg.size != img.size:
            raise ShapeError(f"--mask {args.mask} is {mimg.size[0]}×{mimg.size[1]}, the normal "
                             f"map {img.size[0]}×{img.size[1]}: they must match")
        mask, source = figure_and_source(mimg)
        notes.append(figure_note(args.mask, source))
    started = time.perf_counter()
    result = integrate(n, mask, args.depth, floor=0.0)     # the floor: _run's, once
    _timed(args, "integrate", started)
    if args.verbose:
        print(f"residual (the part no height map has): RMS {result.residual_rms:.4g} "
              f"(slope units), {100 * result.residual_share:.2f} % of the field; "
              f"{result.parts} part(s)")
    return Made("height", result.height, notes, lowest_zero=True,
                residual=result.residual if args.residual else None)


def make_normals(args, read):
    img = read(args.height_map)
    started = time.perf_counter()
    n = normals_of_height(height_widths(img, args.height_scale, args.preblur))
    _timed(args, "normals", started)
    return Made("normal", n)


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


def make_profiles(args, read):
    paths = _profile_images(args)
    named = {side: path for side, path in paths.items() if path in args.images}
    images = {side: read(path) for side, path in paths.items()}
    same_size(images, "lighting profiles")
    started = time.perf_counter()
    n = normals_from_profiles({side: linear_luminance(img) for side, img in images.items()},
                              args.elevation)
    _timed(args, f"profiles ({', '.join(paths)})", started)
    return Made("normal", n, [f"{path}: the {side} profile (by its name; --{side} sets it)"
                              for side, path in named.items()])


def make_rg_photo(args, read):
    img = read(args.photo)
    return Made("normal", normals_from_rg_photo(img.rgb(), args.red_from, args.green_from))


def make_inflate(args, read):
    img = read(args.image)
    mask, source = figure_and_source(img, args.mask_channel)
    if not mask.any():
        raise ShapeError(f"{img.name or args.image}: no figure to inflate (its mask is empty: "
                         f"give an image with alpha, or a mask painted white on black)")
    started = time.perf_counter()
    values = {o.name: getattr(args, o.name) for o in RELIEF_OPTIONS}
    lum = linear_luminance(read(args.detail_image) if args.detail_image else img) \
        if reads_painting(values) else None
    if lum is not None and lum.shape != mask.shape:
        raise ShapeError(f"{args.detail_image}: not the size of {args.image}: resample one")
    tile = linear_luminance(read(args.structure)) if args.structure else None
    heights = figure_relief(mask, lum, tile, **values)      # as Paint Shape's figure mask
    _timed(args, "inflate", started)
    return Made("height", heights, [figure_note(args.image, source)])


def _write(args, path, made, values, top=None):
    """One frame's (or sheet's) shape → `path`; → the line that says what it holds."""
    if made.kind == "height":
        return _write_height(path, values, top)
    return _write_normals(path, values, args.green)


def _input_paths(args):
    """The method's input images (shapes.methods.OPTIONS of kind 'file')."""
    paths = []
    for option in options(args.method_key, "cli"):
        if option.kind == "file":
            value = getattr(args, option.name)
            paths += value if option.many else [value]
    if getattr(args, "mask", "none") not in ("alpha", "none"):      # integrate's mask file
        paths.append(args.mask)
    return [p for p in paths if p]


def run_method(args):
    """make-shape METHOD: its maker on the input image, or on every frame of a sequence or
    sprite sheet (§16, shapes.frames), the shapes written in the input's layout."""
    make = MAKERS[args.method_key]
    inputs = FrameInputs(_input_paths(args), grid_of(vars(args)))
    if not inputs.animated:
        made = make(args, read_image)
        values = made.values - made.values.min() if made.lowest_zero else made.values
        print(f"wrote {args.out} ({_write(args, args.out, made, values)})")
        if made.residual is not None:
            write_exr(args.residual, made.residual.astype(np.float32))
            print(f"wrote {args.residual} (|g − ∇z| per pixel, slope units)")
        print_notes(made.notes)          # once the work is done: an error stays one line
        return
    _run_frames(args, make, inputs)


def _run_frames(args, make, inputs):
    sequence = inputs.pattern is not None
    for option, path in (("--out", args.out), ("--residual", getattr(args, "residual", None))):
        if path and sequence and not is_pattern(os.path.basename(path)):
            raise ShapeError(f"{option} {path}: a sequence's shapes need a frame number in the "
                             f"name, as the input has (e.g. height_####.exr)")
        if path and not sequence and option == "--residual":
            raise ShapeError("--residual: a sprite sheet's residuals are not written (give a "
                             "sequence of files, or one image)")
    frames, seen, notes, last = MadeFrames(), {}, [], None    # last: the kind made, its floor
    names = inputs.names()
    try:
        for i, name in enumerate(names):
            started = time.perf_counter()
            key = inputs.fingerprint(i)
            if key in seen:
                frames.put(i, frames.get(seen[key]))
                print(f"frame {i + 1}/{len(names)} ({name}): the same pixels as frame "
                      f"{seen[key] + 1}: its shape", flush=True)
                continue
            made = make(args, lambda path: inputs.read(path, i))
            last = made
            seen[key] = i
            frames.put(i, made.values)
            notes += [n for n in made.notes if n not in notes]
            if made.residual is not None:
                write_exr(expand_pattern(args.residual, inputs.numbers[i]),
                          made.residual.astype(np.float32))
            print(f"frame {i + 1}/{len(names)} ({name}): "
                  f"{time.perf_counter() - started:.2f} s", flush=True)
        floor = frames.low if last.lowest_zero else None
        top = frames.high - (floor or 0.0)

        def shaped(i):
            values = frames.get(i)
            return values - floor if floor is not None else values
        if sequence:
            for i, n in enumerate(inputs.numbers):
                line = _write(args, expand_pattern(args.out, n), last, shaped(i), top)
            print(f"wrote {len(names)} frames {args.out} ({line})")
        else:
            fill = 0.0 if last.kind == "height" else np.array([0.0, 0.0, 1.0])
            sheet = fill_sheet([shaped(i) for i in range(len(names))], inputs.grid,
                               inputs.sheet_size(), fill)
            line = _write(args, args.out, last, sheet, top)
            print(f"wrote a sheet of {len(names)} frames, {inputs.grid.columns} × "
                  f"{inputs.grid.rows} cells, {args.out} ({line})")
    finally:
        frames.close()
    print_notes(notes)


MAP_FILES = ("normal.png", "height.exr", "height.png", "ambient_occlusion.png", "specular.png")


def _maps(images, p, integrated_floor):
    """One painting frame's maps for game engines → {"normal": unit normals, "height": image
    widths, "specular": 0 … 1 or None}; a normal map's heights integrated (its figure cut at
    the alpha, whichever relief the recipe's shadows use), `integrated_floor` the height made
    0 (None: its lowest point)."""
    n, z_px, _ = shape_normals(images["shape"], p, np.float64, relief=False)
    if z_px is None:
        z_px = normal_map_relief_px(n, images["shape"], precise=True, floor=integrated_floor)
    gloss = None
    if "gloss" in images or p.specular.enabled:
        g = images["gloss"].grey() if "gloss" in images else np.ones(n.shape[:2])
        gloss = np.clip(g * p.specular.amount, 0, 1)
    return {"normal": n, "height": z_px / n.shape[1], "specular": gloss}


def _write_maps(args, n, height, specular, top=None):
    out = {name: os.path.join(args.out, name) for name in MAP_FILES}
    for name, line in (("normal.png", _write_normals(out["normal.png"], n, args.green)),
                       ("height.exr", _write_height(out["height.exr"], height)),
                       ("height.png", _write_height(out["height.png"], height, top))):
        print(f"wrote {out[name]} ({line})")
    write_png(out["ambient_occlusion.png"], ambient_occlusion(height), bits=16)
    print(f"wrote {out['ambient_occlusion.png']}")
    if specular is not None:
        write_png(out["specular.png"], specular, bits=16)
        print(f"wrote {out['specular.png']}")


def cmd_export_maps(args):
    recipe = no_drawing(load_recipe(args.recipe), "export-maps")
    print_notes(n for n in recipe.notes if n != DEFAULT_SUN_NOTE)   # maps have no lights
    used = {c: path for c, path in recipe.images.items() if c in ("shape", "gloss")}
    painting = PaintingFrames(painting_slots(used, recipe.frames))
    p = recipe.params
    check_and_print(painting.images(painting.start), p)
    os.makedirs(args.out, exist_ok=True)
    if not painting.animated:
        maps = _maps(painting.images(painting.start), p, None)
        _write_maps(args, maps["normal"], maps["height"], maps["specular"])
        return
    _export_sheets(args, recipe, painting, p)


def _export_sheets(args, recipe, painting, p):
    """A painting that moves (§16): each map a sprite sheet of its frames on the grid of the
    painting's own sheets (none: the squarest grid that holds them), row by row from the top
    left, for Godot's and Unity's sprite sheets (docs/frames.md); the heights of all frames on
    one floor and one white."""
    shown, _ = painting.drawings()       # the drawings one loop shows, in order
    frames = []
    for i, f in enumerate(shown):
        frames.append(_maps(painting.images(f), p, 0.0))
        print(f"frame {i + 1}/{len(shown)} (scene frame {f}: {painting.shown(f)})", flush=True)
    heights = [m["height"] for m in frames]
    if p.shape.kind == "normal":                 # integrated: the lowest point of them all
        heights = on_one_floor(heights)
    # the painting's own sheets' grid (the sprite the maps go with), else the squarest
    sheet = next((s for s in recipe.slots().values() if s.kind == "sheet"
                  and s.grid.frames() >= len(frames)), None)
    grid = sheet.grid if sheet is not None else SheetGrid.squarest(len(frames))
    h, w = heights[0].shape
    size = grid.sheet_size(w, h)
    n = fill_sheet([m["normal"] for m in frames], grid, size, np.array([0.0, 0.0, 1.0]))
    z = fill_sheet(heights, grid, size, 0.0)
    spec = None if frames[0]["specular"] is None else \
        fill_sheet([m["specular"] for m in frames], grid, size, 0.0)
    _write_maps(args, n, z, spec, top=float(max(hh.max() for hh in heights)))
    write_text_whole(os.path.join(args.out, "sheet.json"), json.dumps(
        {"columns": grid.columns, "rows": grid.rows, "frames": len(frames), "cell": [w, h],
         "margin": grid.margin, "spacing": grid.spacing,
         "order": "row by row from the top left"}, indent=1))
    print(f"wrote {len(frames)} frames as sheets of {grid.columns} × {grid.rows} cells of "
          f"{w}×{h} (sheet.json says so)")


# make-shape METHOD's maker on the command line (an input frame in, a Made out), by METHODS key
MAKERS = {"integrate": make_integrate, "normals": make_normals, "profiles": make_profiles,
          "rg_photo": make_rg_photo, "inflate": make_inflate}
OUT_HELP = {"height": "height map: .exr (image widths) or .png (16-bit)",
            "normal": "normal map (.png 16-bit or .exr)",
            "maps": "folder for normal.png, height.exr/.png, ambient_occlusion.png, specular.png "
                    "(of a painting that moves: sprite sheets, and sheet.json for the grid)"}


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
    """One row of shapes.methods.OPTIONS as a command-line argument."""
    if option.positional:
        # a recipe argument names the samples there are, as every command's does
        text = recipe_help() if option.positional == "RECIPE" else option.help
        parser.add_argument(option.name, metavar=option.positional, help=text,
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


def add_grid_options(parser):
    """--columns, --rows, --count, --margin, --spacing: a sprite sheet's grid (§16), every
    input read cell by cell (params.FRAME_PARAMS: the recipe's [frames] keys)."""
    group = parser.add_argument_group("sprite sheets (§16): every input a sheet of frames, "
                                      "the shapes written as a sheet of the same grid")
    for key in ("columns", "rows", "count", "margin", "spacing"):
        prm = FRAME_BY_KEY[key]
        group.add_argument(f"--{key}", type=_param_type(prm), default=prm.default,
                           help=f"{prm.help} (default {prm.default})")


def _param_type(prm):
    def parse(text):
        try:
            return prm.check(int(text))
        except ValueError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
    return parse


def add_parser(sub):
    """Register `make-shape` and its methods (shapes.methods.METHODS, their options from
    shapes.methods.OPTIONS) on the command line's subparsers."""
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
        m.set_defaults(func=cmd_export_maps if name == "export_maps" else run_method,
                       method_key=name)
        for option in options(name, "cli"):
            add_option(m, option)
        if name in MAKERS:
            add_grid_options(m)
        m.add_argument("--out", required=True, help=OUT_HELP[method.makes])
