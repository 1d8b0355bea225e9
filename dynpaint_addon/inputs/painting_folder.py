"""What a folder given where a recipe is expected holds (issue 38): a recipe, one painting's
images, or the layers of a scene — one rule for the command line and the add-on.

- a folder with a `painting.toml` (or one `.toml` file) is that recipe;
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

from ..errors import UserError
from ..shapes.maker import looks_like_height
from .channel_names import CHANNEL_WORDS, IMAGE_EXTENSIONS, common_name, guess_channels, words
from .imageio import read_image

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
    channels, rest = guess_channels(names)
    basics = [c for c in channels if c in PAINTING_BASICS]
    if "shape" in channels or (basics and (len(channels) >= 2 or len(rest) <= 1)):
        return "painting"
    return "layers"


def folder_kind(path):
    """'recipe', 'painting' or 'layers' (see the module's rule); FolderError for a folder with
    nothing in it to paint."""
    if recipe_in(path):
        return "recipe"
    names = images_in(path)
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

    @property
    def has_shape(self):
        return "shape" in self.data["images"]


def read_painting_folder(path):
    """A folder of one painting's images → FolderReading: the channels by name, the shape
    image's kind by its colour (a float height map's values in image widths, as make-shape
    writes them), shadows on (a painting with a shape image casts them)."""
    names = images_in(path)
    channels, rest = guess_channels(names)
    reasons = {f"images.{c}": f"its name says '{_channel_word(c, f)}'"
               for c, f in channels.items()}
    # the painting itself, named for no channel, beside its shaded copy or its shape alone
    if "bright" not in channels and len(rest) == 1 and not {"shape", "dark"} <= set(channels):
        channels["bright"] = rest.pop()
        reasons["images.bright"] = "the one image named for no channel: the painting"
    notes = [f"{os.path.basename(os.path.normpath(path))}/: read as one painting: " +
             ", ".join(f"{c} = {f}" for c, f in channels.items())]
    if rest:
        notes.append(f"not used: {', '.join(rest)} (no channel word in the name: shape, "
                     f"normal, height, dark, bright, lit, …)")
    data = {"name": common_name(list(channels.values())) or os.path.basename(
        os.path.normpath(path)), "images": dict(channels),
        "shadows": {"enabled": True}}
    reasons["shadows.enabled"] = ("cast shadows and the subsurface look (§6); false draws "
                                  "faster")
    if "shape" in channels:
        shape = read_image(os.path.join(path, channels["shape"]))
        kind = "height" if looks_like_height(shape) else "normal"
        colour = "grey" if kind == "height" else "coloured"
        data["shape"] = {"kind": kind}
        reasons["shape.kind"] = f"{channels['shape']} is {colour}: a {kind} map"
        widths = kind == "height" and shape.bits == 32
        if widths:          # make-shape's EXRs (and its docs') hold heights in image widths
            data["shape"]["height_scale"] = 1.0
            reasons["shape.height_scale"] = (f"{channels['shape']} holds floats: heights in "
                                             f"image widths, as make-shape writes them")
        notes.append(f"{channels['shape']}: read as a {kind} map ({colour}"
                     + ("; floats: heights in image widths)" if widths else ")"))
    return FolderReading(data, notes, reasons)


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
    if not reading.has_shape:
        raise FolderError(
            f"{path}: no shape image (a file named …normal… or …height…): let `dynpaint new "
            f"{shlex.quote(path)}` make one from the painting's silhouette, or make it yourself: "
            f"`dynpaint make-shape inflate {shlex.quote(painted_image(path, reading))} --out "
            f"{shlex.quote(os.path.join(path, 'height.exr'))}`")
    return reading.data, reading.notes
