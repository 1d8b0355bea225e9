"""`dynpaint new FOLDER`: *From Images* on the command line (issue 38) — a folder of an
artist's files → a commented starter recipe (painting.toml) that says what it guessed and why,
ready for render, turntable and export-web.

A folder of one painting's images is read as every command reads it (painting_folder: the
channels by their names, the shape image's kind by its colour); without a shape image one is
inflated from the painting's silhouette and written beside the recipe. A folder of layers
gets a [[layers]] recipe (layered_files' reading: depths from the stack, each plain layer's
shaded dark image and inflated shape written to `made/`).
"""
import os
import re
import shlex
import tempfile
from collections import Counter

from .. import params
from ..core.input_rules import ImageData, input_notes, relief_guess
from ..core.lights import DEFAULT_SUN_DIRECTION
from ..core.map_convention import green_of_frames, green_reading
from ..errors import CommandError, UserError
from ..inputs.imageio import read_image, write_exr, write_png
from ..inputs.atlas import atlas_in, cut_frame
from ..inputs.layered_files import read_folder, scene_from_file_layers
from ..inputs.painting_folder import (RECIPE_NAME, FolderReading, folder_kind, images_in,
                                      painted_image, read_painting_folder, recipe_in)
from ..inputs.recipe import load_images, load_recipe, toml_value
from ..shapes.maker import SHAPE_READS
from ..shapes.methods import make_shape
from .notes import print_notes

MADE = "made"       # the folder, beside the recipe, of the images `new` makes for layers


def cmd_new(args):
    folder = os.path.abspath(args.folder)
    if not os.path.isdir(folder):
        raise CommandError(f"{args.folder}: not a folder (new reads a folder of a painting's "
                           f"images, or of its layers)")
    out = os.path.abspath(args.out or os.path.join(folder, RECIPE_NAME))
    if os.path.exists(out) and not args.force:
        raise CommandError(f"{out} exists: render it as it is, or pass --force to write it "
                           f"again (or --out another.toml)")
    kind = folder_kind(folder)
    if kind == "recipe" and os.path.abspath(recipe_in(folder)) != out:
        raise CommandError(f"{folder} holds a recipe already ({recipe_in(folder)}): render it "
                           f"as it is")
    if kind == "recipe":                 # --force: what the folder is, its recipe aside
        kind = folder_kind(folder, recipes=False)
    base = os.path.dirname(out)
    made = []
    # A failing `new` writes nothing (issue 59): the recipe is written beside its place,
    # checked as every command will read it, and only then put there; images it made go.
    fd, draft = tempfile.mkstemp(prefix=f".{os.path.basename(out)}.", suffix=".toml", dir=base)
    os.close(fd)
    try:
        if kind == "layers":
            lines, made, notes = _layers_recipe(folder, base)
        elif kind == "atlas":
            lines, made, notes = _atlas_recipe(folder, base)
        else:
            lines, made, notes = _painting_recipe(folder, base)
        with open(draft, "w", encoding="utf-8") as fh:
            fh.write("\n".join(lines) + "\n")
        recipe = load_recipe(draft)        # what every command will read: checked now
        if not recipe.layered:
            notes += input_notes(load_images(recipe), recipe.params)
        if notes:                          # … and kept with the recipe, for later
            with open(draft, "a", encoding="utf-8") as fh:
                fh.write("\n# What new noticed:\n" + "".join(f"#   {n}\n" for n in notes))
        os.replace(draft, out)
    except BaseException as exc:
        for path in [draft, *made]:
            if os.path.isfile(path):
                os.remove(path)
        if isinstance(exc, UserError):     # said of the recipe it would have written
            raise CommandError(str(exc).replace(draft, out)) from None
        raise
    print_notes(notes)
    for path in made:
        print(f"made {_shown(path)}")
    what = f"{len(recipe.layers)} layers" if recipe.layered else \
        ", ".join(recipe.images)
    print(f"wrote {_shown(out)} ({what}): try `dynpaint render {shlex.quote(_shown(out))} "
          f"--out render.png`")      # quoted: a path with a space pastes as one word


def _shown(path):
    """A path as the user would type it: from the working folder when it is below it."""
    rel = os.path.relpath(path)
    return path if rel.startswith("..") else rel


def _header(folder):
    return [f"# Dynamic Painting recipe, started by `dynpaint new "
            f"{shlex.quote(os.path.basename(folder))}`:",
            "# what it guessed is said beside each key. Change anything; every key is listed",
            "# by `dynpaint params` (docs/parameters.md shows each with pictures)."]


def _section(title, values, reasons, prefix=""):
    """A TOML table of {key: value}, each line with its reason as a comment."""
    lines = ["", f"[{title}]"]
    for key, value in values.items():
        line = f"{key} = {toml_value(value)}"
        why = reasons.get(f"{prefix}{key}")
        lines.append(f"{line:<33} # {why}" if why else line)
    return lines


def _light_lines():
    return ["", "[[lights]]                        # a sun from the upper left, in front: move it "
            "(a point light: type = \"point\", position = [x, y, z])",
            'type = "sun"', f"direction = {toml_value(list(DEFAULT_SUN_DIRECTION))}",
            "strength = 1.0", 'name = "Key"']


def _atlas_recipe(folder, base):
    """A folder of a texture atlas → (recipe lines, files made): each frame it lists cut from
    its sheets at its source size and written to made/; the frames of one size are the
    painting (numbered frames that move, §16), a sprite of another size gets a folder of its
    own in made/ that `new` starts."""
    path, frames = atlas_in(folder, images_in(folder))
    stem = os.path.splitext(os.path.basename(path))[0].replace(" ", "_")
    sizes = Counter(f.source for f in frames)
    size = max(sizes, key=lambda wh: (sizes[wh], wh[0] * wh[1]))
    shown = [f for f in frames if f.source == size]
    if not shown[0].normal_map:
        raise CommandError(f"{path}: its sheet {shown[0].image} has no normal-map sheet beside "
                           f"it (named like {os.path.splitext(shown[0].image)[0]}_n.png)")
    sheets = {}
    readings, reliefs = [], []         # of the frames' maps, as they stand (§2, §6)

    def write(frame, out_stem):
        written = []
        for sheet, suffix in ((frame.image, ""), (frame.normal_map, "_n")):
            if sheet not in sheets:
                sheets[sheet] = read_image(os.path.join(folder, sheet))
            written.append(f"{out_stem}{suffix}.png")
            cut = cut_frame(sheets[sheet].pixels, frame)
            write_png(written[-1], cut, min(sheets[sheet].bits, 16))
            if suffix and frame.source == size:
                readings.append(green_reading(cut[..., :3], cut[..., 3], "auto", "auto"))
                reliefs.append(relief_guess(ImageData(cut), f"{frame.normal_map}'s frames"))
        return written

    made, notes = [], []
    numbered = len(shown) > 1
    for number, frame in enumerate(shown, 1):
        made += write(frame, os.path.join(base, MADE, f"{stem}_{number:04d}" if numbered
                                          else stem))
    for frame in (f for f in frames if f.source != size):
        own = re.sub(r"[^\w.-]+", "_", os.path.splitext(frame.name)[0])
        made += write(frame, os.path.join(base, MADE, own, own))
        notes.append(f"{frame.name} ({frame.source[0]}×{frame.source[1]}), another sprite of "
                     f"the atlas: written to {MADE}/{own}/; `dynpaint new "
                     f"{shlex.quote(os.path.join(_shown(base), MADE, own))}` starts it")
    pattern = f"{stem}_####" if numbered else stem
    names = {"bright": f"{MADE}/{pattern}.png", "shape": f"{MADE}/{pattern}_n.png"}
    first = shown[0]
    told = (f"{os.path.basename(path)}: a texture atlas; {len(shown)} frame(s) of "
            f"{size[0]}×{size[1]}, each at its source size, written to {MADE}/")
    reading = FolderReading(
        {"name": stem, "images": dict(names), "shadows": {"enabled": True},
         "shape": {"kind": "normal"}}, [told] + notes,
        {f"images.{c}": f"{told}: {first.name} … {shown[-1].name}" for c in names})
    reading.reasons["shape.kind"] = f"{first.normal_map}: the atlas's normal-map sheet"
    green = green_of_frames(readings)
    reading.guess("shape.flip_green", True if green.flip else None,
                  green.describe(f"{first.normal_map}'s frames"))
    if all(relief for relief, _ in reliefs):    # every shown frame's map opaque (§6)
        reading.guess("shadows.relief", *reliefs[0])
    lines, more, notes = _painting_recipe(folder, base, reading,
                                          {c: os.path.join(base, n) for c, n in names.items()})
    return lines, made + more, notes


def _painting_recipe(folder, base, reading=None, images=None):
    """A folder of one painting → (recipe lines, files made); `reading` and `images` (paths)
    when the caller read the folder already (an atlas)."""
    reading = reading or read_painting_folder(folder)
    data, reasons, made = reading.data, dict(reading.reasons), []
    images = images or {c: os.path.join(folder, f) for c, f in data["images"].items()}
    if reading.depth_in_alpha:          # Sprite Lamp's NormalDepth: the map is its RGB
        source = reading.depth_map_colour          # (as the folder's reading read it)
        stem = os.path.splitext(reading.depth_in_alpha)[0]
        images["shape"] = os.path.join(base, MADE, f"{stem}_rgb.png")
        write_png(images["shape"], source.rgb(), min(source.bits, 16))
        made.append(images["shape"])
        reasons["images.shape"] = (f"{reading.depth_in_alpha}'s colour, written by new: its "
                                   f"alpha is the depth, not the figure")
    if not reading.has_shape:
        painted = painted_image(folder, reading)
        p = params.defaults()
        kind, rgba, lines = make_shape("inflate", {"bright": read_image(painted)}, p)
        path = os.path.join(base, f"{data['name'] or 'painting'}_height.exr".replace(" ", "_"))
        write_exr(path, rgba[..., :1])
        images["shape"], made = path, [path]
        data["shape"] = {k: v for k, v in SHAPE_READS[kind].items()     # defaults unwritten
                         if k == "kind" or v != params.BY_PATH[f"shape.{k}"].default}
        reasons["images.shape"] = f"made by new: {lines[0]} (dynpaint make-shape changes it)"
        reasons["shape.kind"] = f"new made a {kind} map"
        reasons["shape.height_scale"] = "its heights are in image widths already"
    lines = _header(folder)
    lines += [f"name = {toml_value(data['name'])}"]
    lines += _section("images", {c: _rel(p, base) for c, p in images.items()}, reasons,
                      "images.")
    for section in ("shape", "shadows"):
        lines += _section(section, data[section], reasons, f"{section}.")
    if "background" in images:
        lines += ["", "[refraction]",
                  f"distance = {params.BY_PATH['refraction.distance'].default:<23}# how far the "
                  f"background lies behind, in image widths: raise it to bend it more (glass "
                  f"painted for the original research system: about 1)"]
    return lines + _light_lines(), made, reading.notes


def _layers_recipe(folder, base):
    """A folder of layers → (recipe lines, files made): each layer's images as files (the
    made ones written to made/)."""
    canvas, file_layers = read_folder(folder)
    layers, notes = scene_from_file_layers(canvas, file_layers)
    notes.insert(0, f"{os.path.basename(folder)}/: read as a scene of {len(layers)} layers, back "
                    f"to front (no file in it named for a painting's channels)")
    shown = [fl for fl in file_layers if not fl.hidden]
    lines, made = _header(folder), []
    lines += [f"name = {toml_value(os.path.basename(folder))}"]
    for fl, layer in zip(shown, layers):
        sources = {("bright" if c == "painted" else c): p for c, p in fl.sources.items()}
        files, why = {}, {}
        for channel, img in layer.images.items():
            if channel in sources:
                files[channel] = _rel(sources[channel], base)
                continue
            stem = os.path.join(base, MADE, f"{fl.name}_{channel}".replace(" ", "_"))
            if channel == "shape":
                path = stem + ".exr"
                write_exr(path, img.pixels[..., :1])
                why[f"images.{channel}"] = "made by new: inflated from its alpha"
            else:                        # float images hold linear values: EXR
                path = stem + (".exr" if img.bits == 32 else ".png")
                (write_exr if img.bits == 32 else write_png)(path, img.pixels)
                why[f"images.{channel}"] = "made by new: a shaded copy of its colours"
            files[channel], made = _rel(path, base), made + [path]
        lines += ["", "[[layers]]", f"name = {toml_value(layer.name)}",
                  f"depth = {toml_value(round(layer.depth, 6))}"
                  f"{'':<18}# image widths in front of the back layer",
                  f"offset = {toml_value([round(c, 6) for c in layer.offset])}",
                  f"scale = {toml_value(round(layer.scale, 6))}"]
        lines += _section("layers.images", files, why, "images.")
        shape = layer.p.shape
        lines += _section("layers.shape", {"kind": shape.kind, **(
            {"height_scale": shape.height_scale} if shape.kind == "height" else {})}, {})
        lines += _section("layers.shadows", {"enabled": True}, {})
    return lines + _light_lines(), made, notes


def _rel(path, base):
    return os.path.relpath(path, base).replace(os.sep, "/")


def add_parser(sub):
    """Register `new` on the command line's subparsers."""
    n = sub.add_parser("new", help="start a recipe from a folder of a painting's images",
                       description="Read a folder of an artist's files as every command reads "
                       "it — one painting's images matched to their channels by name "
                       "(…normal…, …height…, …dark…, …bright…/…lit…, …env…, …background…, "
                       "…mask…), or a folder of layers — and write a commented starter recipe "
                       "that says what it guessed and why. Without a shape image one is "
                       "inflated from the painting's silhouette (its alpha).")
    n.add_argument("folder", help="the folder of images")
    n.add_argument("--out", help=f"the recipe to write (default FOLDER/{RECIPE_NAME}); its "
                   f"image paths are relative to it")
    n.add_argument("--force", action="store_true", help="write over an existing recipe")
    n.set_defaults(func=cmd_new)
