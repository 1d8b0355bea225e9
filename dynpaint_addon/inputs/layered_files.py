"""Layered files → a scene of layers (pipeline.md §15; issue 30): OpenRaster and folders.

OpenRaster (`.ora`, written by Krita, GIMP and MyPaint) is a zip of PNG layers and a
`stack.xml` listing them top first; Photoshop's *Export Layers to Files* writes a folder of
layer images named `_0000_Name.png`, `_0001_…` (0000 the top layer); any other folder of
images is read back to front by name (`01_sky.png` behind `02_hills.png`). No new
dependency: `zipfile`, `xml.etree` and the image reader.

A layer is either **one painted image** — then its bright image is that layer, its dark
image a shaded copy (`shade` × its linear colour) and its shape its silhouette inflated
(Make Shape's inflate; an opaque layer is a flat card) — or **a group** (an OpenRaster stack,
a subfolder) holding one layer's channels, matched by their names as *From Images* matches
files (`figure_normal`, `figure_dark`, …). Depths follow the stack: the back layer at 0,
each layer `spacing` image widths in front of the one behind. Hidden layers are left out,
blend modes other than normal read as normal, layer opacity as 1 — each said in a note.

    >>> order_in_folder(["_0001_sky.png", "_0000_figure.png"])
    ['_0001_sky.png', '_0000_figure.png']
    >>> order_in_folder(["02_hills.png", "01_sky.png"])
    ['01_sky.png', '02_hills.png']
"""
import os
import shutil
import tempfile
import xml.etree.ElementTree as ElementTree
import zipfile
from dataclasses import dataclass, field

import numpy as np

from .. import params
from ..core.colour import linear_to_srgb, scaled_srgb, srgb_to_linear
from ..core.frames import SheetGrid
from ..core.input_rules import ImageData
from ..core.layers import MAX_LAYERS, Layer, scene_notes
from ..core.lights import default_sun
from ..errors import UserError
from ..shapes.frames import fill_sheet
from ..shapes.maker import ShapeError, looks_like_height, read_as_made
from ..shapes.methods import make_shape
from .channel_names import IMAGE_EXTENSIONS, guess_channels
from .imageio import png_bound, png_header, read_image
from .memory import base_bytes, check, check_read
from .painting_folder import PHOTOSHOP, folder_kind
from .recipe import DEFAULT_SUN_NOTE, hidden_notes, load_layers, load_recipe

DEFAULT_SPACING = 0.05     # image widths between one layer and the next in front
DEFAULT_SHADE = 0.35       # a plain layer's dark image: this share of its linear colour
DEFAULT_RELIEF = 1.0       # a plain layer's inflated shape: Make Shape's inflate height


class LayeredFileError(UserError):
    """A layered file that cannot be read; the message names the file and what is wrong."""


@dataclass
class FileLayer:
    """A layer as a file holds it: its images by channel (or one painted image), where its
    top-left corner lies on the canvas (pixels, y down) and whether it is shown."""
    name: str
    images: dict                       # {channel: ImageData}, or {"painted": ImageData}
    x: int = 0
    y: int = 0
    hidden: bool = False
    notes: list = field(default_factory=list)
    sources: dict = field(default_factory=dict)   # {channel or "painted": file}, from a folder


def order_in_folder(names):
    """Image files of a folder back to front: Photoshop's numbers (0000 the top layer)
    reversed, else by name."""
    if names and all(PHOTOSHOP.match(n) for n in names):
        return sorted(names, key=lambda n: -int(PHOTOSHOP.match(n).group(1)))
    return sorted(names)


def read_ora(path):
    """An OpenRaster file → ((canvas W, H), [FileLayer] back to front)."""
    try:
        archive = zipfile.ZipFile(path)
    except (zipfile.BadZipFile, OSError) as exc:
        raise LayeredFileError(f"{path}: not an OpenRaster file (.ora is a zip archive: "
                               f"{exc})") from None
    with archive, tempfile.TemporaryDirectory() as folder:
        members = {m.filename: m for m in archive.infolist()}
        check_archive(path, members, folder)
        try:
            stack = ElementTree.fromstring(archive.read("stack.xml"))
        except ElementTree.ParseError as exc:
            raise LayeredFileError(f"{path}: its stack.xml is not valid XML ({exc})") from None
        top = stack.find("stack")
        if stack.tag != "image" or top is None:
            raise LayeredFileError(f"{path}: its stack.xml has no <image><stack> (not "
                                   f"OpenRaster)")
        canvas = (_int(stack, "w", path), _int(stack, "h", path))
        if min(canvas) < 1 or max(canvas) > MAX_CANVAS:
            raise LayeredFileError(f"{path}: stack.xml: its canvas {canvas[0]}×{canvas[1]} is "
                                   f"not a picture's size (1 … {MAX_CANVAS} pixels a side)")
        check(base_bytes() + 16 * canvas[0] * canvas[1], f"{path}'s canvas "
              f"({canvas[0]}×{canvas[1]})", "export it smaller from the painting program")

        def image(layer):
            src = layer.get("src", "")
            if not src.lower().endswith(".png"):
                raise LayeredFileError(f"{path}: layer '{layer.get('name', src)}' is "
                                       f"{src or 'missing its src'}: OpenRaster layers are PNG")
            member = members.get(src)
            if member is None:
                raise LayeredFileError(f"{path}: layer '{layer.get('name', src)}': {src} is "
                                       f"not in the file")
            with archive.open(member) as fh:      # its size, before a byte is unpacked
                header = png_header(fh.read(26))
            if header is None:
                raise LayeredFileError(f"{path}: {src} is not a PNG")
            check_read((*header, False), f"{os.path.basename(path)}: {src}")
            if member.file_size > png_bound(*header):
                raise LayeredFileError(
                    f"{path}: {src} unpacks to {member.file_size / 2**20:.0f} MiB, more than "
                    f"a {header[0]}×{header[1]} PNG can hold ({png_bound(*header) / 2**20:.1f} "
                    f"MiB): a damaged or hostile file, not read")
            return read_image(archive.extract(member, folder))
        layers = []
        for element in reversed(list(top)):          # stack.xml lists the top layer first
            layers.append(_ora_layer(element, image, path))
        return canvas, layers


MAX_STACK_XML = 4 << 20     # an OpenRaster stack.xml lists layers: a few kB
MAX_CANVAS = 1 << 16        # pixels a side: OpenRaster's and PNG's own practical limit


def check_archive(path, members, folder):
    """Refuse an .ora whose members say, before anything is unpacked, that it cannot be read:
    no stack.xml, a stack.xml larger than any list of layers, or members that would not fit
    in the temporary folder (sizes as the archive declares them; zipfile stops reading a
    member at its declared size)."""
    xml = members.get("stack.xml")
    if xml is None:
        raise LayeredFileError(f"{path}: not an OpenRaster file: it has no stack.xml (the list "
                               f"of its layers)")
    if xml.file_size > MAX_STACK_XML:
        raise LayeredFileError(f"{path}: its stack.xml unpacks to {xml.file_size / 2**20:.0f} "
                               f"MiB (a list of layers is a few kB): a damaged or hostile file, "
                               f"not read")
    total = sum(m.file_size for m in members.values())
    free = shutil.disk_usage(folder).free
    if total > free:
        raise LayeredFileError(f"{path}: its layers unpack to {total / 2**30:.1f} GiB; the "
                               f"temporary folder ({folder}) has {free / 2**30:.1f} GiB free")


def _int(element, key, path):
    try:
        return int(float(element.get(key)))
    except (TypeError, ValueError):
        raise LayeredFileError(f"{path}: stack.xml: <{element.tag}> needs a number {key}, got "
                               f"{element.get(key)!r}") from None


def _ora_layer(element, image, path):
    """One child of the top stack: a layer (one painted image) or a stack (a group of one
    layer's channels) → FileLayer."""
    name = element.get("name") or "layer"
    x, y = int(float(element.get("x", 0))), int(float(element.get("y", 0)))
    hidden = element.get("visibility", "visible") == "hidden"
    notes = _blend_notes(name, element)
    if element.tag == "layer":
        return FileLayer(name, {"painted": image(element)}, x, y, hidden, notes)
    parts = [child for child in element if child.tag == "layer"
             and child.get("visibility", "visible") != "hidden"]
    channels, rest = guess_channels([child.get("name", "") or child.get("src", "")
                                     for child in parts])
    by_name = {child.get("name", "") or child.get("src", ""): child for child in parts}
    images = {c: image(by_name[n]) for c, n in channels.items()}
    if rest:
        notes.append(f"{name}: not used: {', '.join(rest)} (no channel word in the name)")
    if not images:
        raise LayeredFileError(f"{path}: group '{name}' has no layer named for a channel "
                               f"(dark, bright, normal, height, …)")
    first = by_name[next(iter(channels.values()))]
    return FileLayer(name, images, x + int(float(first.get("x", 0))),
                     y + int(float(first.get("y", 0))), hidden, notes)


def _blend_notes(name, element):
    notes = []
    op = element.get("composite-op", "svg:src-over")
    if op != "svg:src-over":
        notes.append(f"{name}: blend mode {op.split(':')[-1]} read as normal")
    if float(element.get("opacity", 1.0)) < 1.0:
        notes.append(f"{name}: opacity {float(element.get('opacity')):.2g} read as 1 "
                     f"(its alpha cuts it out)")
    return notes


def read_folder(path):
    """A folder of layer images (subfolders: groups of one layer's channels) →
    ((canvas W, H), [FileLayer] back to front); the canvas is the largest layer's size."""
    entries = sorted(os.listdir(path))
    files = [e for e in entries if e.lower().endswith(IMAGE_EXTENSIONS)]
    groups = [e for e in entries if os.path.isdir(os.path.join(path, e))]
    if not files and not groups:
        raise LayeredFileError(f"{path}: no layer images in this folder "
                               f"({', '.join(IMAGE_EXTENSIONS)})")
    layers = []
    for entry in order_in_folder(files + groups):
        full = os.path.join(path, entry)
        name = PHOTOSHOP.sub("", os.path.splitext(entry)[0] if entry in files else entry)
        if entry in files:
            layers.append(FileLayer(name, {"painted": read_image(full)},
                                    sources={"painted": full}))
            continue
        parts = [p for p in sorted(os.listdir(full)) if p.lower().endswith(IMAGE_EXTENSIONS)]
        channels, rest = guess_channels(parts)
        if not channels:
            raise LayeredFileError(f"{full}: no image named for a channel (dark, bright, "
                                   f"normal, height, …)")
        notes = [f"{name}: not used: {', '.join(rest)}"] if rest else []
        sources = {c: os.path.join(full, f) for c, f in channels.items()}
        layers.append(FileLayer(name, {c: read_image(p) for c, p in sources.items()},
                                notes=notes, sources=sources))
    sizes = [img.size for layer in layers for img in layer.images.values()]
    return max(sizes, key=lambda s: s[0] * s[1]), layers


def scene_from_file_layers(canvas, file_layers, spacing=DEFAULT_SPACING, shade=DEFAULT_SHADE):
    """FileLayers (back to front) on a canvas (W, H) → ([core.layers.Layer], notes): each
    layer's missing channels made (a shaded dark, an inflated shape), its depth from the
    stack, its place from its corner and size."""
    notes, layers = [], []
    shown = [fl for fl in file_layers if not fl.hidden]
    notes += [f"{fl.name}: hidden: left out" for fl in file_layers if fl.hidden]
    if not shown:
        raise LayeredFileError("no visible layer: every layer is hidden")
    if len(shown) > MAX_LAYERS:
        raise LayeredFileError(f"{len(shown)} visible layers; a scene holds at most "
                               f"{MAX_LAYERS} (merge some, or hide them)")
    width, height = canvas
    for i, fl in enumerate(shown):
        images, p, made = painting_of(fl, shade)
        notes += fl.notes + made
        w, h = images["shape"].size
        offset = ((fl.x + w / 2 - width / 2) / width, (height / 2 - fl.y - h / 2) / width)
        layers.append(Layer(images, p, fl.name, i * spacing, None, offset, w / width))
    return layers, notes


def painting_of(fl, shade=DEFAULT_SHADE, relief=DEFAULT_RELIEF, effects=None):
    """A file layer's painting → ({channel: ImageData}, params, notes): a painted image
    becomes bright, a shaded dark and an inflated shape (`relief` high, with make-shape
    inflate's `effects`); a group's missing channels are made the same way."""
    p = params.defaults()
    p.shadows.enabled = True
    images = dict(fl.images)
    notes = [note for img in images.values() for note in img.notes]     # a file cut short
    if "painted" in images:
        images = {"bright": images.pop("painted")}
    if "bright" not in images and "dark" in images:
        images["bright"] = images["dark"]
    if "dark" not in images:
        images["dark"] = shaded(images["bright"], shade)
    if "shape" in images:
        p.shape.kind = "height" if looks_like_height(images["shape"]) else "normal"
        return images, p, notes
    backdrop, flat = backdrop_share(images["bright"]), None
    if backdrop is not None:
        flat = f"fills {backdrop:.0%} of the canvas, a backdrop"
    else:
        try:
            kind, rgba, lines = make_shape("inflate", images, p, height=relief,
                                           **(effects or {}))
            notes.append(f"{fl.name}: {lines[0]}")
        except ShapeError:
            flat = "no transparent part to inflate"          # opaque
    if flat is not None:
        w, h = images["bright"].size
        kind, rgba = "height", np.zeros((h, w, 1), np.float32)
        if backdrop is not None:    # its figure, as an inflated shape's alpha holds it
            rgba = np.dstack([rgba] * 3 + [images["bright"].alpha()])
        notes.append(f"{fl.name}: {flat}: a flat card (give it a shape image for relief)")
    read_as_made(p, kind)
    images["shape"] = ImageData(np.asarray(rgba, np.float32), 32, f"{fl.name} shape")
    return images, p, notes


# A layer whose figure spans BACKDROP_SPAN of the canvas both ways and fills BACKDROP_FILL of
# that box is a backdrop (a sky, a wall; a Grease Pencil fill drawn to the drawing's bounds
# leaves only the drawing's margin clear): a flat card — inflated, its border would fall
# off as a pillow's, and a shadow cast on it would bend where the scene has no edge. The
# span is lenient: a stroke drawn past a drawing's sky card (a moon, a figure walking out)
# widens the canvas, and the sky is no less a backdrop for it (at 0.9, a moon 0.2 of the
# card's width beyond its edge turned the sky into a pillow and moved every shadow on it)
BACKDROP_SPAN, BACKDROP_FILL = 0.6, 0.9


def backdrop_share(img):
    """The share of the canvas a backdrop layer's figure (alpha ≥ ½) fills, or None where
    the layer is no backdrop (or opaque: no figure to speak of).

    >>> a = np.zeros((100, 100, 4), np.float32); a[2:98, 2:98, 3] = 1
    >>> round(backdrop_share(ImageData(a, 8)), 2)               # a sky within a margin
    0.92
    >>> a[:, 70:, 3] = 0; round(backdrop_share(ImageData(a, 8)), 2)   # drawn past its edge
    0.65
    >>> a[:, 50:, 3] = 0; backdrop_share(ImageData(a, 8)) is None     # a card on the left
    True
    """
    alpha = img.alpha()
    if alpha is None:
        return None
    inside = np.nan_to_num(alpha) >= 0.5
    rows, cols = np.flatnonzero(inside.any(1)), np.flatnonzero(inside.any(0))
    if rows.size == 0 or inside.all():
        return None
    h, w = inside.shape
    box_h, box_w = rows[-1] - rows[0] + 1, cols[-1] - cols[0] + 1
    share = float(inside.mean())
    if box_h < BACKDROP_SPAN * h or box_w < BACKDROP_SPAN * w or \
            share * h * w < BACKDROP_FILL * box_h * box_w:
        return None
    return share


def painting_of_frames(name, cells, shade=DEFAULT_SHADE, relief=DEFAULT_RELIEF, darks=None,
                       effects=None):
    """A layer drawn on each of some frames (a Grease Pencil layer's, issue 42) →
    ({channel: ImageData}, params, notes, its [frames] table but the start, or None): each
    distinct cell (ImageData of one size, one per frame) made a painting as a plain painted
    layer is (painting_of: a shaded dark, its silhouette inflated by parts `relief` high, so
    a figure that does not change keeps its heights bit for bit) — or, with `darks` (the
    shadow colours the artist drew on each frame), its dark image those colours over the
    shaded one (shadow_colours); effects: make-shape inflate's relief effects (bevel, detail,
    smoothing, profile). Cells that all agree are one still painting, else the cells are laid
    out as sprite sheets (§16), a cell given again (the same object: a drawing held over
    frames) made a painting once."""
    darks = darks or [None] * len(cells)

    def painting(cell, dark):
        images = {"bright": cell} if dark is None else \
            {"bright": cell, "dark": shadow_colours(cell, dark, shade)}
        return painting_of(FileLayer(name, images), shade, relief, effects)
    if all(np.array_equal(c.pixels, cells[0].pixels) for c in cells[1:]) and \
            all(d is darks[0] or np.array_equal(d.pixels, darks[0].pixels) for d in darks[1:]):
        return (*painting(cells[0], darks[0]), None)
    made, first = [], {}
    for cell, dark in zip(cells, darks):     # a drawing held over frames: made once
        key = (id(cell), id(dark))
        if key not in first:
            first[key] = painting(cell, dark)
        made.append(first[key])
    notes = sorted({n for _, _, lines in made for n in lines if "inflated" not in n})
    grid = SheetGrid.squarest(len(cells))
    h, w = cells[0].pixels.shape[:2]
    size = grid.sheet_size(w, h)
    images = {c: ImageData(fill_sheet([m[0][c].pixels for m in made], grid, size, 0.0),
                           made[0][0][c].bits, f"{name} {c}") for c in made[0][0]}
    table = {"offset": 0, "count": len(cells), "mode": "hold", "rate": 1.0,
             "columns": grid.columns, "rows": grid.rows, "margin": 0, "spacing": 0}
    return images, made[0][1], notes, table


def shadow_colours(bright, drawn, shade):
    """A layer's dark image from the shadow colours an artist drew for it (issue 42): `drawn`
    over the shaded `bright` (where they drew none, the shaded rule), composited in linear
    light, with the bright image's alpha (its coverage is the layer's)."""
    a = drawn.alpha()
    a = (np.ones(drawn.pixels.shape[:2]) if a is None else np.asarray(a, np.float64))[..., None]
    dark = _linear(drawn) * a + _linear(bright) * float(shade) * (1 - a)
    return _like(bright, dark, "shadow colours")


def shaded(img, shade):
    """A dark image for a painted one: `shade` × its linear colour, its alpha kept."""
    if img.bits in (8, 16):                 # (by its codes: the same, 10× sooner)
        return _with_alpha(img, scaled_srgb(img.rgb(), shade, img.bits), "shaded")
    return _like(img, _linear(img) * float(shade), "shaded")


def _linear(img):
    """An image's colour, linear (float64 (H, W, 3))."""
    rgb = np.asarray(img.rgb(), np.float64)
    return rgb if img.bits == 32 else srgb_to_linear(rgb)


def _like(img, linear, what):
    """Linear colour stored as `img` stores its colour, with its alpha: ImageData."""
    return _with_alpha(img, linear if img.bits == 32 else linear_to_srgb(linear), what)


def _with_alpha(img, rgb, what):
    """Colour `rgb` stored as `img` stores its colour, with its alpha: ImageData."""
    alpha = img.alpha()
    px = rgb if alpha is None else np.dstack([rgb, alpha])
    return ImageData(px.astype(np.float32), img.bits, f"{img.name} ({what})")


def is_layered_file(path):
    """Whether `path` is read here (an .ora file or a folder of layers) rather than as a
    recipe (a folder holding one, or one painting's images: painting_folder)."""
    if os.path.isdir(path):
        return folder_kind(path) == "layers"
    return os.fspath(path).lower().endswith(".ora")


def load_scene(path, spacing=DEFAULT_SPACING, shade=DEFAULT_SHADE):
    """An .ora file or a folder of layer images → ([Layer], [Light], notes)."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise LayeredFileError(f"{path}: file not found")
    if os.path.isdir(path):
        canvas, file_layers = read_folder(path)
    elif path.lower().endswith(".ora"):
        canvas, file_layers = read_ora(path)
    else:
        raise LayeredFileError(f"{path}: not a layered file (an .ora, or a folder of layer "
                               f"images)")
    layers, notes = scene_from_file_layers(canvas, file_layers, spacing, shade)
    return layers, [default_sun()], notes + [DEFAULT_SUN_NOTE]


def load_layered(path):
    """Any scene source — an .ora, a folder of layer images, a layered recipe — →
    ([Layer], [Light], notes); a one-painting recipe is one layer."""
    if is_layered_file(path):
        return load_scene(path)
    recipe = load_recipe(path)
    layers = load_layers(recipe)
    return layers, recipe.lights, recipe.notes + scene_notes(layers) + hidden_notes(recipe)
