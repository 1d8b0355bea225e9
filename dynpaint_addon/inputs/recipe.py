"""The painting recipe: a small human-editable TOML file naming the images, parameters and lights.

    name = "Dome"
    description = "One line for menus"   # optional
    credits = "Painted by …, 2026"        # optional: shown by the exported web page
    [images]                  # paths relative to this file
    shape = "height.png"
    dark = "dark.png"
    bright = "bright.png"
    [shape]
    kind = "height"
    height_scale = 0.1
    [[lights]]
    type = "sun"              # or "point" with position = [x, y, z]
    direction = [0.5, 0.4, 0.7]
    color = [1.0, 0.9, 0.8]
    strength = 1.0

Every section and key is listed by `dynpaint params` (generated from params.py).
Unknown keys, wrong types and out-of-range values raise RecipeError naming the key.
"""
import copy
import difflib
import math
import os
import shlex
import tomllib
from dataclasses import dataclass, field

from .. import params
from ..core.frames import is_pattern
from ..core.layers import MAX_LAYERS, Layer
from ..core.lights import DEFAULT_SUN_DIRECTION, LIGHT_KINDS, Light, default_sun
from ..errors import UserError
from .channel_names import IMAGE_EXTENSIONS
from .drawings import DrawingError, load_drawing
from .painting_folder import RECIPE_NAME, folder_kind, painting_recipe_data, recipe_in
from .painting_frames import (FrameError, PaintingFrames, check_frame_settings, painting_slots,
                              sequence_numbers)
from .samples import list_samples, recipe_path

LIGHT_KEYS = ("type", "direction", "position", "color", "strength", "name", "angle", "radius")
# a light's size (§15) by its kind: a sun's angle (degrees, Blender's Sun Angle), a point
# light's radius (image widths, Blender's Radius)
LIGHT_SIZE_KEYS = {"sun": "angle", "point": "radius"}
# what a [[layers]] table holds beside a one-painting recipe's keys (§15), with its check
LAYER_KEYS = ("name", "depth", "thickness", "offset", "scale", "visible")
DEFAULT_SUN_NOTE = (f"no lights named: lit by a default sun from the upper left (direction "
                    f"{list(DEFAULT_SUN_DIRECTION)}); add [[lights]] to the recipe to choose "
                    f"them (lights = [] for none: the dark image alone)")
# A section whose settings act only with an image: reflection needs an environment, refraction
# a background (§8, §9)
SECTION_IMAGES = {"reflection": "environment", "refraction": "background"}


class RecipeError(UserError):
    """A recipe problem; the message starts with the file and the key."""


@dataclass
class Recipe:
    params: object
    lights: list
    images: dict = field(default_factory=dict)   # channel → absolute path
    name: str = ""
    path: str = ""
    description: str = ""   # one line for menus and tooltips
    credits: str = ""       # who made it: shown under the title of an exported web page
    layers: list = field(default_factory=list)   # [RecipeLayer], back to front (§15)
    # §16: {"": [frames] as written, channel: [frames.<channel>] as written}
    frames: dict = field(default_factory=dict)
    # what reading it guessed or found likely not meant (a default sun, a setting with no
    # effect), one line each: every command prints them as `note: …`, Add reports them
    notes: list = field(default_factory=list)
    default_lights: bool = False    # no [[lights]]: lit by core.lights.default_sun()
    drawing: str = ""       # a Grease Pencil drawing (inputs/drawings.py) lit as its layers
    folder: str = ""        # where its image paths resolve from: the recipe's folder

    def images_outside(self):
        """{path: channel} of the images (its layers' too) that lie outside the recipe's
        folder: a recipe from someone else may name any file (issue 60)."""
        found = {}
        for part in [layer.recipe for layer in self.layers] or [self]:
            for channel, path in part.images.items():
                if self.folder and not inside(path, self.folder):
                    found[path] = channel
        return found

    @property
    def layered(self):
        return bool(self.layers)

    def slots(self):
        """{channel: painting_frames.SlotFrames}: how each image follows the frames (§16)."""
        return painting_slots(self.images, self.frames)


@dataclass
class RecipeLayer:
    """One [[layers]] table of a layered recipe (§15): a painting and where it lies."""
    recipe: Recipe              # its images and parameters, as a one-painting recipe's
    name: str = ""
    depth: float = 0.0          # image widths of the canvas toward the viewer
    thickness: object = None    # image widths of the canvas; None: its tallest relief
    offset: tuple = (0.0, 0.0)  # its centre from the canvas's centre, image widths
    scale: float = 1.0          # its width over the canvas's width
    visible: bool = True


def _suggest(key, options):
    close = difflib.get_close_matches(key, list(options), n=1)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _check_value(param, value, where):
    try:
        return param.check(value)
    except ValueError as exc:      # "[1]: …" names a vec2's component
        sep = "" if str(exc).startswith("[") else ": "
        raise RecipeError(f"{where}{sep}{exc}") from None


def _vector(value, where, minimum=None):
    if (not isinstance(value, list) or len(value) != 3
            or any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in value)):
        raise RecipeError(f"{where}: expected three numbers [x, y, z], got {value!r}")
    if not all(math.isfinite(c) for c in value):
        raise RecipeError(f"{where}: must be finite, got {value!r}")
    if minimum is not None and any(c < minimum for c in value):
        raise RecipeError(f"{where}: components must be ≥ {minimum}, got {value!r}")
    return tuple(float(c) for c in value)


def _parse_light(i, table, where):
    where = f"{where}lights[{i}]"
    if not isinstance(table, dict):
        raise RecipeError(f"{where}: expected a table ([[lights]])")
    for key in table:
        if key not in LIGHT_KEYS:
            raise RecipeError(f"{where}.{key}: unknown key{_suggest(key, LIGHT_KEYS)}")
    kind = table.get("type", "sun")
    if kind not in LIGHT_KINDS:
        raise RecipeError(f"{where}.type: must be one of {', '.join(LIGHT_KINDS)}, got {kind!r}")
    vec_key = "direction" if kind == "sun" else "position"
    other = "position" if kind == "sun" else "direction"
    if other in table:
        raise RecipeError(f"{where}.{other}: a {kind} light takes '{vec_key}', not '{other}'")
    if vec_key not in table:
        raise RecipeError(f"{where}.{vec_key}: missing (a {kind} light needs one)")
    vec = _vector(table[vec_key], f"{where}.{vec_key}")
    if kind == "sun" and vec == (0.0, 0.0, 0.0):
        raise RecipeError(f"{where}.direction: must not be [0, 0, 0]")
    if kind == "point" and max(map(abs, vec)) > MAX_DISTANCE:   # its squares overflow: black
        raise RecipeError(f"{where}.position: {max(map(abs, vec)):g} image widths away; at most "
                          f"{MAX_DISTANCE:g} (a light that far is a sun: type = \"sun\")")
    colour = _vector(table.get("color", [1.0, 1.0, 1.0]), f"{where}.color", minimum=0)
    strength = table.get("strength", 1.0)
    if isinstance(strength, bool) or not isinstance(strength, (int, float)) \
            or not math.isfinite(strength) or strength < 0:
        raise RecipeError(f"{where}.strength: expected a number ≥ 0, got {strength!r}")
    name = table.get("name", "")
    if not isinstance(name, str):
        raise RecipeError(f"{where}.name: expected a string, got {name!r}")
    if len(name) > MAX_TEXT:
        raise RecipeError(f"{where}.name: {len(name)} characters; at most {MAX_TEXT}")
    size_key = LIGHT_SIZE_KEYS[kind]
    wrong = LIGHT_SIZE_KEYS["point" if kind == "sun" else "sun"]
    if wrong in table:
        raise RecipeError(f"{where}.{wrong}: a {kind} light's size is its '{size_key}'")
    size = _number(table.get(size_key, 0.0), f"{where}.{size_key}", 0.0,
                   180.0 if kind == "sun" else None)
    return Light(kind, vec, colour, float(strength), name,
                 size=math.radians(size) if kind == "sun" else size)


def _number(value, where, minimum=None, maximum=None):
    """A finite number within [minimum, maximum] → float, or RecipeError naming the key."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value):
        raise RecipeError(f"{where}: expected a number, got {value!r}")
    if (minimum is not None and value < minimum) or (maximum is not None and value > maximum):
        bounds = f"≥ {minimum:g}" if maximum is None else f"in {minimum:g} … {maximum:g}"
        raise RecipeError(f"{where}: must be {bounds}, got {value!r}")
    return float(value)


def _parse_layer(i, table, base_dir, source, check_files, shared):
    """A [[layers]] table → RecipeLayer: its own keys, and a one-painting recipe's (its
    parameters starting from the scene's top-level sections, `shared`)."""
    where = f"{source}: layers[{i}]"
    if not isinstance(table, dict):
        raise RecipeError(f"{where}: expected a table ([[layers]])")
    if "lights" in table:
        raise RecipeError(f"{where}.lights: the lights belong to the scene: put [[lights]] "
                          f"at the top level")
    if "layers" in table:
        raise RecipeError(f"{where}.layers: a layer holds one painting, not layers of its own")
    painting = {k: v for k, v in table.items() if k not in LAYER_KEYS or k == "name"}
    recipe = parse_recipe(painting, base_dir, f"{source}: layers[{i}]", check_files, shared)
    offset = table.get("offset", [0.0, 0.0])
    if not isinstance(offset, list) or len(offset) != 2:
        raise RecipeError(f"{where}.offset: expected two numbers [x, y], got {offset!r}")
    thickness = table.get("thickness")
    visible = table.get("visible", True)
    if not isinstance(visible, bool):
        raise RecipeError(f"{where}.visible: expected true or false, got {visible!r}")
    return RecipeLayer(
        recipe, recipe.name or f"Layer {i}", _number(table.get("depth", 0.0), f"{where}.depth"),
        None if thickness is None else _number(thickness, f"{where}.thickness", 0.0),
        tuple(_number(c, f"{where}.offset[{j}]") for j, c in enumerate(offset)),
        _number(table.get("scale", 1.0), f"{where}.scale", 1e-6), visible)


MAX_LIGHTS = 64     # a recipe's lights (issue 60: 20000 of them ran for minutes)
MAX_TEXT = 10_000   # characters of a name, description or credits (a 50 MB name made a page)
MAX_DISTANCE = 1e6  # image widths to a point light (at 1e160 the picture went black)


def inside(path, folder):
    """Whether `path` lies in `folder` or below it (links followed)."""
    path, folder = os.path.realpath(path), os.path.realpath(folder)
    return os.path.commonpath([path, folder]) == folder


def parse_recipe(data, base_dir=".", source="recipe", check_files=True, base=None):
    """Validate a recipe dict (as read from TOML) → Recipe. Image paths resolve from base_dir.
    base: the parameters to start from (a layer's: the scene's top-level sections), else
    the defaults. A recipe with [[layers]] is a scene (§15): its images are its layers'."""
    where = f"{source}: "
    values = copy.deepcopy(base) if base is not None else params.defaults()
    text = {"name": "", "description": "", "credits": ""}
    images, lights, frames, written, drawing = {}, [], {}, [], ""
    for key, value in data.items():
        if key in text:
            if not isinstance(value, str):
                raise RecipeError(f"{where}{key}: expected a string, got {value!r}")
            if len(value) > MAX_TEXT:           # it is shown in menus and on the page
                raise RecipeError(f"{where}{key}: {len(value)} characters; at most "
                                  f"{MAX_TEXT}")
            text[key] = value
        elif key == "images":
            if not isinstance(value, dict):
                raise RecipeError(f"{where}images: expected a table [images]")
            for ch, rel in value.items():
                if ch not in params.CHANNELS:
                    raise RecipeError(f"{where}images.{ch}: unknown image channel"
                                      f"{_suggest(ch, params.CHANNELS)}; channels: {', '.join(params.CHANNELS)}")
                if not isinstance(rel, str) or not rel:
                    raise RecipeError(f"{where}images.{ch}: expected a file path, got {rel!r}")
                full = os.path.normpath(os.path.join(base_dir, rel))
                if check_files and is_pattern(os.path.basename(full)):
                    try:
                        sequence_numbers(full)
                    except FrameError as exc:
                        raise RecipeError(f"{where}images.{ch}: {exc}") from None
                elif check_files and not os.path.isfile(full):
                    raise RecipeError(f"{where}images.{ch}: file not found: {full}")
                images[ch] = full
        elif key == "frames":
            frames = _parse_frames(value, f"{where}frames")
        elif key == "drawing":
            if not isinstance(value, str) or not value:
                raise RecipeError(f"{where}drawing: expected a file path, got {value!r}")
            drawing = os.path.normpath(os.path.join(base_dir, value))
            if check_files:
                try:
                    load_drawing(drawing)
                except DrawingError as exc:
                    raise RecipeError(f"{where}drawing: {exc}") from None
        elif key == "layers":
            if not isinstance(value, list) or not value:
                raise RecipeError(f"{where}layers: expected an array of tables [[layers]]")
            if len(value) > MAX_LAYERS:
                raise RecipeError(f"{where}layers: {len(value)} layers; a scene holds at most "
                                  f"{MAX_LAYERS} (the web page draws up to {MAX_LAYERS})")
        elif key == "lights":
            if not isinstance(value, list):
                raise RecipeError(f"{where}lights: expected an array of tables [[lights]]")
            if len(value) > MAX_LIGHTS:         # each one a branch of every shader, a bake
                raise RecipeError(f"{where}lights: {len(value)} lights; a painting takes at "
                                  f"most {MAX_LIGHTS}")
            lights = [_parse_light(i, t, where) for i, t in enumerate(value)]
        elif key in params.SECTIONS:
            if not isinstance(value, dict):
                raise RecipeError(f"{where}{key}: expected a table [{key}]")
            section = getattr(values, key)
            for k, v in value.items():
                param = params.BY_PATH.get(f"{key}.{k}")
                if param is None:
                    keys = [p.key for p in params.PARAMS if p.section == key]
                    raise RecipeError(f"{where}{key}.{k}: unknown key{_suggest(k, keys)}")
                setattr(section, k, _check_value(param, v, f"{where}{key}.{k}"))
                written.append(param)
        else:
            options = (*text, "images", "lights", "layers", "frames", "drawing") + \
                params.SECTIONS
            raise RecipeError(f"{where}{key}: unknown key{_suggest(key, options)}")
    notes = []
    default_lights = base is None and "lights" not in data    # a scene's lights, not a layer's
    if default_lights:
        lights, notes = [default_sun()], [DEFAULT_SUN_NOTE]
    if "layers" in data:
        if images:
            raise RecipeError(f"{where}images: a layered recipe's images belong to its layers "
                              f"([layers.images] under each [[layers]])")
        layers = [_parse_layer(i, t, base_dir, source, check_files, values)
                  for i, t in enumerate(data["layers"])]
        notes += [n for lay in layers for n in lay.recipe.notes]
        return Recipe(values, lights, {}, text["name"], description=text["description"],
                      credits=text["credits"], layers=layers, notes=notes,
                      default_lights=default_lights, folder=os.path.abspath(base_dir))
    if drawing:         # a Grease Pencil drawing: its layers are drawn, not given (issue 42)
        if images or "layers" in data or frames or written:
            raise RecipeError(f"{where}drawing: a drawing's recipe names the drawing, its "
                              f"lights and texts only (its layers, frames and their settings "
                              f"are From Grease Pencil's)")
        return Recipe(values, lights, {}, text["name"], description=text["description"],
                      credits=text["credits"], notes=notes, default_lights=default_lights,
                      drawing=drawing)
    for ch in params.REQUIRED_CHANNELS:
        if ch not in images:
            raise RecipeError(f"{where}images.{ch}: missing (a painting needs a shape image)")
    if "dark" not in images and "bright" not in images:
        raise RecipeError(f"{where}images.dark: missing (a painting needs a dark or a bright image)")
    notes += no_effect_notes(values, written, images, where)
    folder = os.path.abspath(base_dir)
    notes += [f"{where}images.{ch}: {path} lies outside the recipe's folder ({folder}): "
              f"export-web embeds it only with --allow-outside-images"
              for ch, path in images.items() if not inside(path, folder)]
    recipe = Recipe(values, lights, images, text["name"], description=text["description"],
                    credits=text["credits"], frames=frames, notes=notes,
                    default_lights=default_lights, folder=folder)
    if check_files:
        try:
            recipe.slots()           # a grid that cannot hold its count, a slot both ways
        except FrameError as exc:
            raise RecipeError(f"{where}{exc}") from None
    return recipe


def no_drawing(recipe, command):
    """A drawing's recipe (issue 42) where `command` reads a painting's own images: a
    RecipeError saying what does read one."""
    if recipe.drawing:
        raise RecipeError(f"{recipe.path or 'recipe'}: its painting is a Grease Pencil drawing "
                          f"({os.path.basename(recipe.drawing)}), which {command} does not "
                          f"read yet: render it with --engine cycles or eevee, or turn it with "
                          f"`turntable`")
    return recipe


def no_effect_notes(p, written, images, where=""):
    """A line for each setting the recipe writes that changes nothing as the rest of it stands,
    with what would make it count: a setting shown only in another mode (params' shown_if), a
    setting of a section switched off (its `enabled`), a reflection or refraction setting
    without the image it moves. Derived from params.PARAMS, not listed here.

    >>> p = params.defaults()
    >>> no_effect_notes(p, [params.BY_PATH["fresnel.kappa"]], {})[0]
    'fresnel.kappa has no effect while fresnel.mode = "physical": set fresnel.mode = "art" too'
    """
    notes = []
    for param in dict.fromkeys(written):
        section = getattr(p, param.section)
        switch = params.BY_PATH.get(f"{param.section}.enabled")
        if param.shown_if:
            path, wanted = param.shown_if
            now = getattr(getattr(p, path.split(".")[0]), path.split(".")[1])
            if now != wanted:
                notes.append(f"{where}{param.path} has no effect while {path} = "
                             f"{toml_value(now)}: set {path} = {toml_value(wanted)} too")
        elif switch is not None and param is not switch and not section.enabled:
            notes.append(f"{where}{param.path} has no effect while {switch.path} = false: set "
                         f"{switch.path} = true too")
        elif param.section in SECTION_IMAGES and SECTION_IMAGES[param.section] not in images:
            image = SECTION_IMAGES[param.section]
            article = "an" if image[0] in "aeiou" else "a"
            notes.append(f"{where}{param.path} has no effect without {article} {image} image "
                         f"([images] {image} = \"…\")")
    return notes


def _parse_frames(table, where):
    """[frames] and its [frames.<channel>] tables (§16) → {"": {...}, channel: {...}}, each
    holding the keys as written, checked by params.FRAME_PARAMS."""
    if not isinstance(table, dict):
        raise RecipeError(f"{where}: expected a table [frames]")
    own = {k: v for k, v in table.items() if not isinstance(v, dict)}
    frames = {}
    try:
        frames[""] = check_frame_settings(own, where)
        for ch, sub in table.items():
            if not isinstance(sub, dict):
                continue
            if ch not in params.CHANNELS:
                raise ValueError(f"{where}.{ch}: unknown image channel"
                                 f"{_suggest(ch, params.CHANNELS)}; a [frames.<channel>] "
                                 f"table sets one image's mapping")
            frames[ch] = check_frame_settings(sub, f"{where}.{ch}")
    except ValueError as exc:
        raise RecipeError(str(exc)) from None
    return {k: v for k, v in frames.items() if v}


def load_recipe(path):
    """Read and validate a recipe file, a sample's name ('portrait') or a folder → Recipe. A
    folder is the recipe it holds, or one painting read from its images' names
    (painting_folder); a folder of layers is layered_files' (load_layered). A path that is
    none of these says which samples there are, and an image says that a recipe was expected."""
    path = recipe_path(os.fspath(path))
    if os.path.isdir(path):
        return _folder_recipe(path)
    if not os.path.isfile(path):
        raise RecipeError(_not_found(path))
    if path.lower().endswith(IMAGE_EXTENSIONS):
        raise RecipeError(f"{path} is an image: a recipe (painting.toml) was expected, which "
                          f"names the images ([images] shape = \"{os.path.basename(path)}\", "
                          f"…; docs/your-painting.md)")
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise RecipeError(f"{path}: not valid TOML ({exc})") from None
    except RecursionError:
        raise RecipeError(f"{path}: its tables or arrays nest deeper than Python reads (a "
                          f"recipe nests two or three levels)") from None
    except UnicodeDecodeError:
        raise RecipeError(f"{path}: not a text file: a recipe (painting.toml) was "
                          f"expected") from None
    recipe = parse_recipe(data, os.path.dirname(os.path.abspath(path)), path)
    recipe.path = os.path.abspath(path)
    return recipe


def _folder_recipe(path):
    kind = folder_kind(path)
    if kind == "recipe":
        return load_recipe(recipe_in(path))
    if kind == "atlas":
        raise RecipeError(f"{path}: a texture atlas (its JSON lists the frames): let "
                          f"`dynpaint new {shlex.quote(path)}` read its frames into a recipe")
    if kind == "layers":
        raise RecipeError(f"{path}: a folder of layers (no file named for a painting's "
                          f"channels: shape, normal, height, dark, bright, …): a scene (§15) "
                          f"for render, export-web and Add › Layered…")
    data, notes = painting_recipe_data(path)
    recipe = parse_recipe(data, path, path)
    recipe.notes[:0] = notes
    recipe.path = os.path.join(os.path.abspath(path), RECIPE_NAME)   # where `new` writes it
    return recipe


def _not_found(path):
    names = [s.id for s in list_samples()]
    if os.sep in path or path.endswith(".toml"):
        return f"{path}: recipe file not found"
    return (f"{path}: no recipe file and no sample of that name"
            f"{_suggest(path, names)} (samples: {', '.join(names)})")


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(c) for c in v) + "]"
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'


def recipe_to_toml(recipe, base_dir, only_changed=True):
    """Serialize a Recipe to TOML text with image paths relative to base_dir.

    only_changed writes parameters that differ from their defaults (the file stays short and
    keeps following new defaults); False writes every parameter.
    """
    lines = ["# Dynamic Painting recipe (see `dynpaint params`)"]
    if recipe.name:
        lines.append(f"name = {toml_value(recipe.name)}")
    if recipe.description:
        lines.append(f"description = {toml_value(recipe.description)}")
    if recipe.credits:
        lines.append(f"credits = {toml_value(recipe.credits)}")
    if recipe.drawing:
        lines.append(f"drawing = {toml_value(_relative(recipe.drawing, base_dir))}")
    lines += _painting_toml(recipe, base_dir, "", params.defaults(), only_changed)
    for layer in recipe.layers:
        lines += ["", "[[layers]]", f"name = {toml_value(layer.name)}",
                  f"depth = {toml_value(layer.depth)}"]
        if layer.thickness is not None:
            lines.append(f"thickness = {toml_value(layer.thickness)}")
        lines += [f"offset = {toml_value(list(layer.offset))}",
                  f"scale = {toml_value(layer.scale)}"]
        if not layer.visible:
            lines.append("visible = false")
        lines += _painting_toml(layer.recipe, base_dir, "layers.", recipe.params, only_changed)
    for light in [] if recipe.default_lights else recipe.lights:    # read back: the same sun
        lines += ["", "[[lights]]", f"type = {toml_value(light.kind)}"]
        lines.append(f"{'direction' if light.kind == 'sun' else 'position'} = "
                     f"{toml_value(list(light.vector))}")
        lines.append(f"color = {toml_value(list(light.colour))}")
        lines.append(f"strength = {toml_value(light.strength)}")
        if light.name:
            lines.append(f"name = {toml_value(light.name)}")
        if light.size:
            key = LIGHT_SIZE_KEYS[light.kind]
            size = math.degrees(light.size) if light.kind == "sun" else light.size
            lines.append(f"{key} = {toml_value(size)}")
    return "\n".join(lines) + "\n"


def _relative(full, base_dir):
    """A file's path in a recipe: from the recipe's folder, with / between its parts."""
    return os.path.relpath(full, base_dir).replace(os.sep, "/")


def _painting_toml(recipe, base_dir, prefix, base, only_changed):
    """The [images] and parameter sections of a painting (prefix 'layers.' for a layer's),
    parameters that differ from `base` only with only_changed."""
    lines = []
    if recipe.images:
        lines += ["", f"[{prefix}images]"]
        for ch, full in recipe.images.items():
            lines.append(f"{ch} = {toml_value(_relative(full, base_dir))}")
    for ch, table in sorted(recipe.frames.items()):
        if table:
            lines += ["", f"[{prefix}frames{'.' + ch if ch else ''}]"]
            lines += [f"{k} = {toml_value(v)}" for k, v in table.items()]
    start = params.as_dict(base)
    for section, values in params.as_dict(recipe.params).items():
        changed = {k: v for k, v in values.items() if not only_changed or v != start[section][k]}
        if changed:
            lines += ["", f"[{prefix}{section}]"] + [f"{k} = {toml_value(v)}"
                                                     for k, v in changed.items()]
    return lines


def image_files(recipe):
    """Every image file the recipe reads, its layers' and every frame of a sequence too, each
    once (a set of paths)."""
    paintings = [recipe] + [lay.recipe for lay in recipe.layers]
    return {f for r in paintings for slot in r.slots().values() for f in slot.files()}


def image_bytes(recipe):
    """The size in bytes of the recipe's image files (image_files)."""
    return sum(os.path.getsize(p) for p in image_files(recipe))


def load_images(recipe, frame=None):
    """Read every image the recipe names → {channel: ImageData}; of a painting that moves
    (§16), the images scene frame `frame` shows (None: its start frame)."""
    if recipe.layered:
        raise RecipeError(f"{recipe.path or recipe.name}: a layered recipe (§15): its images "
                          f"are its layers' (load_layers)")
    painting = PaintingFrames(recipe.slots(), cache_mb=0)
    return painting.images(painting.start if frame is None else frame)


def load_layers(recipe):
    """The visible layers of a recipe, back to front as listed → [core.layers.Layer] (a
    one-painting recipe is one layer)."""
    if not recipe.layered:
        return [Layer(load_images(recipe), recipe.params, recipe.name)]
    return [Layer(load_images(lay.recipe), lay.recipe.params, lay.name, lay.depth,
                  lay.thickness, lay.offset, lay.scale)
            for lay in recipe.layers if lay.visible]


def hidden_notes(recipe):
    """A line for each layer a layered recipe hides (visible = false): left out."""
    return [f"{lay.name}: hidden (visible = false): left out" for lay in recipe.layers
            if not lay.visible]
