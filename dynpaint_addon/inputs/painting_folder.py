"""What a folder given where a recipe is expected holds (issue 38): a recipe, one painting's
images, or the layers of a scene — one rule for the command line and the add-on.

- a folder with a `painting.toml` (or one `.toml` file) is that recipe;
- a folder of a texture atlas (TexturePacker's JSON beside its sheets: atlas) is the frames it
  lists, a painting that moves;
- a folder of a colour sprite beside its map, named as 2D-lighting tools name them
  (`hero.png` + `hero_n.png`, numbered frames `01.png` + `01_n.png` …: sprite_files), is one
  painting whatever the words in its names;
- a folder of one painting's channels, matched by their names as *From Images* matches the
  files an artist picks (`channel_names.guess_channels`: `…normal…`, `…dark…`, `…lit…`, …),
  is one painting: it names a shape image, or two channels or more, or a dark or bright image
  beside at most one file named for none (the painting itself: its bright image);
- any other folder of images (Photoshop's `_0000_` numbering, subfolders of one layer's
  channels, names without channel words: `01_sky.png`, `02_figure.png`) is a scene of
  layers (§15, layered_files).

    >>> kind_of_names(["face_normal.png", "face_dark.png", "face_lit.png", "thumbnail.png"])
    'painting'
    >>> kind_of_names(["01_sky.png", "02_hills.png", "03_figure.png"])
    'layers'
    >>> kind_of_names(["_0001_background.png", "_0000_figure_lit.png"])
    'layers'
    >>> kind_of_names(["background.png", "tree.png", "figure.png"])
    'layers'
    >>> kind_of_names(["pear.png", "pear_dark.png"])       # the painting and its shaded copy
    'painting'
"""
import os
import re
import shlex
from dataclasses import dataclass, field

from ..core.input_rules import ImageData, relief_guess
from ..core.map_convention import green_reading
from ..errors import UserError
from ..shapes.maker import looks_like_height
from .channel_names import (CHANNEL_WORDS, IMAGE_EXTENSIONS, OTHER_MAP_WORDS, common_name,
                            guess_channels, words)
from .atlas import atlas_in
from .imageio import read_image
from .sprite_files import depth_in_alpha, sprite_pairs

RECIPE_NAME = "painting.toml"
PHOTOSHOP = re.compile(r"^_(\d{4})_")     # Export Layers to Files: _0000_ the top layer
PAINTING_BASICS = ("shape", "dark", "bright")


class FolderError(UserError):
    """A folder that holds nothing to paint; the message names it and what was looked for."""


def images_in(path):
    """The image files directly in a folder, by name."""
    return sorted(e for e in os.listdir(path) if e.lower().endswith(IMAGE_EXTENSIONS)
                  and os.path.isfile(os.path.join(path, e)))


def recipe_in(path):
    """The recipe a folder holds (its painting.toml, or its only .toml file) or ''."""
    if os.path.isfile(os.path.join(path, RECIPE_NAME)):
        return os.path.join(path, RECIPE_NAME)
    tomls = [e for e in os.listdir(path) if e.lower().endswith(".toml")]
    return os.path.join(path, tomls[0]) if len(tomls) == 1 else ""


def kind_of_names(names, groups=()):
    """'painting' or 'layers' for a folder's image names (and its subfolders of images)."""
    # Photoshop's Export Layers numbers every file: that is a stack, whatever the names say
    if groups or (names and all(PHOTOSHOP.match(n) for n in names)):
        return "layers"
    if sprite_pairs(names).frames:          # a sprite and its map, or numbered frames of them
        return "painting"
    channels, rest = guess_channels(names)
    basics = [c for c in channels if c in PAINTING_BASICS]
    if "shape" in channels or (basics and (len(channels) >= 2 or len(rest) <= 1)):
        return "painting"
    return "layers"


def folder_kind(path, recipes=True):
    """'recipe', 'atlas', 'painting' or 'layers' (see the module's rule; `recipes` False: what
    the folder is without its recipe); FolderError for a folder with nothing in it to paint."""
    if recipes and recipe_in(path):
        return "recipe"
    names = images_in(path)
    if atlas_in(path, names):        # a texture atlas and its JSON: a painting that moves
        return "atlas"
    groups = [e for e in sorted(os.listdir(path)) if os.path.isdir(os.path.join(path, e))
              and images_in(os.path.join(path, e))]
    if not names and not groups:
        raise FolderError(f"{path}: no recipe ({RECIPE_NAME}) and no images in this folder "
                          f"({', '.join(IMAGE_EXTENSIONS)})")
    return kind_of_names(names, groups)


@dataclass
class FolderReading:
    """What a folder of one painting's images was read as: the recipe's data (as a
    painting.toml holds it), the notes every command prints, and why each key was chosen
    (`dynpaint new` writes them as comments)."""
    data: dict
    notes: list
    reasons: dict = field(default_factory=dict)     # "images.shape", "shape.kind", … → why
    depth_in_alpha: str = ""    # the shape file whose alpha is its depth (its RGB is the map)
    depth_map_colour: ImageData = None      # … that RGB, as read (`new` writes it out)

    @property
    def has_shape(self):
        return "shape" in self.data["images"]

    def guess(self, path, value, why):
        """A key the images chose: `section.key` = value in the recipe's data (None: left at
        its default), why kept for `new`'s comment and said in the notes."""
        if value is not None:
            section, key = path.split(".")
            self.data.setdefault(section, {})[key] = value
        self.reasons[path] = why
        self.notes.append(why)


def painting_channels(names):
    """One painting's image files → ({channel: file}, [not used], {"images.<channel>": why}):
    a sprite and its map by their names' relation (sprite_files: `##` for numbered frames),
    the other channels by the words in their names, and one image named for no channel
    beside no bright image is the painting itself (its bright image). One rule for
    `dynpaint new`, `render FOLDER` and Add › From Images.

    >>> painting_channels(["foreground_01.png", "foreground_01_n.png"])[0]
    {'shape': 'foreground_01_n.png', 'bright': 'foreground_01.png'}
    >>> painting_channels(["pear.png", "pear_normal.png", "pear_dark.png"])[0]
    {'shape': 'pear_normal.png', 'bright': 'pear.png', 'dark': 'pear_dark.png'}
    """
    sprites = sprite_pairs(names)
    channels, rest = guess_channels(sprites.rest if sprites.frames else names)
    reasons = {f"images.{c}": f"its name says '{_channel_word(c, f)}'"
               for c, f in channels.items()}
    if sprites.frames:      # the names' relation is the verdict; their words only hints
        rest += [f for c, f in channels.items() if c in ("shape", "bright")]   # (a 2nd map)
        channels = {"shape": sprites.shape, "bright": sprites.colour,
                    **{c: f for c, f in channels.items() if c not in ("shape", "bright")}}
        told = (f"{sprites.frames} numbered frames: " if sprites.frames > 1 else "") + \
            f"{os.path.basename(sprites.shape)} is named as " \
            f"{os.path.basename(sprites.colour)}'s map"
        reasons["images.shape"] = told
        reasons["images.bright"] = f"the colour image (a sprite): {told}"
    elif "bright" not in channels and len(rest) == 1:   # the painting, named for no channel
        channels["bright"] = rest.pop()
        reasons["images.bright"] = "the one image named for no channel: the painting"
    return channels, rest, reasons


def read_painting_folder(path):
    """A folder of one painting's images → FolderReading: the channels by name, the shape
    image's kind by its colour (a float height map's values in image widths, as make-shape
    writes them), shadows on (a painting with a shape image casts them)."""
    names = images_in(path)
    channels, rest, reasons = painting_channels(names)
    sprites = sprite_pairs(names)
    notes = [f"{os.path.basename(os.path.normpath(path))}/: read as one painting: " +
             ", ".join(f"{c} = {f}" for c, f in channels.items())]
    if rest:
        notes.append(not_used_note(rest))
    data = {"name": common_name(list(channels.values())) or os.path.basename(
        os.path.normpath(path)), "images": dict(channels),
        "shadows": {"enabled": True}}
    reasons["shadows.enabled"] = ("cast shadows and the subsurface look (§6); false draws "
                                  "faster")
    reading = FolderReading(data, notes, reasons)
    depth_map = ""
    if "shape" in channels:
        first = sprites.first_shape if sprites.frames > 1 else channels["shape"]
        shape = read_image(os.path.join(path, first))
        if shape.has_alpha and depth_in_alpha(first):   # the map is its RGB alone
            shape = ImageData(shape.rgb(), shape.bits, shape.name)
            depth_map = first
            notes.append(f"{first}: its alpha is the depth (Sprite Lamp's NormalDepth), not "
                         f"the figure: the normal map is its colour alone; the figure is the "
                         f"colour image's alpha")
        kind = "height" if looks_like_height(shape) else "normal"
        colour = "grey" if kind == "height" else "coloured"
        data["shape"] = {"kind": kind}
        reasons["shape.kind"] = f"{first} is {colour}: a {kind} map"
        widths = kind == "height" and shape.bits == 32
        if widths:          # make-shape's EXRs (and its docs') hold heights in image widths
            data["shape"]["height_scale"] = 1.0
            reasons["shape.height_scale"] = (f"{first} holds floats: heights in "
                                             f"image widths, as make-shape writes them")
        notes.append(f"{first}: read as a {kind} map ({colour}"
                     + ("; floats: heights in image widths)" if widths else ")"))
        if kind == "normal":        # which way its green points, read from the map (§2)
            green = green_reading(shape.rgb(), shape.alpha(), "auto", "auto")
            reading.guess("shape.flip_green", True if green.flip else None,
                          green.describe(first))
            relief, why = relief_guess(shape, first)
            if relief:
                reading.guess("shadows.relief", relief, why)
    if sprites.frames <= 1 and depth_map:       # (numbered NormalDepth frames: not yet)
        reading.depth_in_alpha, reading.depth_map_colour = depth_map, shape
    return reading


def not_used_note(rest):
    """The note naming a folder's images no channel takes, each with why.

    >>> not_used_note(["hero_AO.png", "hero_Depth.png"])
    'not used: hero_AO.png (a map no channel reads: occlusion, emissive, …); hero_Depth.png (a second shape image)'
    """
    def why(name):
        if words(name) & set(OTHER_MAP_WORDS):
            return "a map no channel reads: occlusion, emissive, …"
        channel = next(iter(guess_channels([name])[0]), "")
        return f"a second {channel} image" if channel else \
            "no channel word in the name: shape, normal, height, dark, bright, lit, …"
    return "not used: " + "; ".join(f"{name} ({why(name)})" for name in rest)


def _channel_word(channel, name):
    """The word of a file's name that made it `channel`'s."""
    synonyms = dict(CHANNEL_WORDS)[channel]
    return next(w for w in synonyms if w in words(name))


def painted_image(path, reading):
    """The image a folder's shape is made from when it has none: its bright (else dark)."""
    channels = reading.data["images"]
    return os.path.join(path, channels.get("bright") or channels.get("dark")
                        or images_in(path)[0])


def painting_recipe_data(path):
    """A folder of one painting's images → (recipe data, notes), as read_painting_folder reads
    it; FolderError when it has no shape image (`dynpaint new` makes one)."""
    reading = read_painting_folder(path)
    if reading.depth_in_alpha:
        raise FolderError(
            f"{path}: {reading.depth_in_alpha} holds the depth in its alpha (Sprite Lamp's "
            f"NormalDepth): let `dynpaint new {shlex.quote(path)}` write its normal map "
            f"without it (made/), then render the recipe it writes")
    if not reading.has_shape:
        raise FolderError(
            f"{path}: no shape image (a file named …normal… or …height…): let `dynpaint new "
            f"{shlex.quote(path)}` make one from the painting's silhouette, or make it yourself: "
            f"`dynpaint make-shape inflate {shlex.quote(painted_image(path, reading))} --out "
            f"{shlex.quote(os.path.join(path, 'height.exr'))}`")
    return reading.data, reading.notes
