"""Which channel (docs/pipeline.md §1) an image file is for, from its name (no bpy).

Add › Dynamic Painting › From Images assigns the files an artist picks by the words in their
names — the channel names and the synonyms other tools and artists use — checked in this
order ("specular" before "light", …); a word counts whole (`bg`, not the b and g of
`bright_glow`), and a name's words are split at any other character, at camelCase humps and
before digits (`height16` is a height map).

    >>> guess_channels(["face_normal.png", "face_dark.png", "face_lit.png", "notes.png"])
    ({'shape': 'face_normal.png', 'dark': 'face_dark.png', 'bright': 'face_lit.png'}, ['notes.png'])
    >>> guess_channels(["diffuse.png", "alpha.png", "reflect.jpg", "bg.png", "nrm.png"])[0]
    {'bright': 'diffuse.png', 'transparency': 'alpha.png', 'environment': 'reflect.jpg', 'background': 'bg.png', 'shape': 'nrm.png'}
    >>> common_name(["Eye_normal.png", "Eye_dark.png", "Eye_bright.png"])
    'Eye'
"""
import os
import re

from ..core.photometric import SIDES

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".bmp", ".tga", ".webp",
                    ".hdr")
# File-name words → channel, checked in this order ("specular" before "light", …).
CHANNEL_WORDS = (
    ("specular_color", ("specular", "spec", "highlight", "highlights")),
    ("gloss", ("gloss", "glossiness", "rough", "roughness", "shine", "shininess")),
    ("environment", ("environment", "env", "envmap", "reflect", "reflection", "reflected",
                     "mirror", "foreground", "fg")),
    ("background", ("background", "backdrop", "bg", "back", "refract", "refraction",
                    "refracted", "behind")),
    ("transparency", ("transparency", "transparent", "transp", "opacity", "mask", "alpha",
                      "matte", "glass")),
    ("shape", ("normal", "normals", "nrm", "nor", "norm", "n", "height", "heightmap", "depth",
               "disp", "displacement", "bump", "shape", "relief")),
    ("dark", ("dark", "shadow", "shade", "shaded", "unlit", "c0", "ambient", "night")),
    ("bright", ("bright", "lit", "light", "c1", "albedo", "color", "colour", "diffuse",
                "base", "basecolor", "day")),
)


def words(path):
    """The lower-case words of a file's name, also without their digits: 'tree_blurryBG-2.png'
    → {'tree', 'blurry', 'bg', '2'}, 'height16.png' → {'height16', 'height'}."""
    stem = os.path.splitext(os.path.basename(path))[0]
    stem = re.sub(r"(?<=[a-z])(?=[A-Z])", " ", stem).lower()
    return {w for w in re.split(r"[^a-z0-9]+", stem) if w} | set(re.findall(r"[a-z]+", stem))


# Maps 2D-lighting tools make that no channel reads (Sprite Lamp's `_AmbientOcclusion` and
# `_Emissive`, Laigter's `_o`): their names' other words ("ambient") must not place them
OTHER_MAP_WORDS = ("occlusion", "ao", "emissive", "emission", "anisotropy", "preview")


def guess_channels(paths):
    """Assign image files to channels by their names → ({channel: path}, [unassigned]).

    >>> guess_channels(["hero_AmbientOcclusion.png", "hero_dark.png"])
    ({'dark': 'hero_dark.png'}, ['hero_AmbientOcclusion.png'])
    """
    found, rest = {}, []
    for path in paths:
        ws = words(path)
        channel = None if ws & set(OTHER_MAP_WORDS) else next(
            (c for c, names in CHANNEL_WORDS if c not in found and ws & set(names)), None)
        if channel is None:
            rest.append(path)
        else:
            found[channel] = path
    return found, rest


def common_name(paths):
    """What the images' names share, without the channel words: the painting's name ('' if
    nothing)."""
    stems = [os.path.splitext(os.path.basename(p))[0] for p in paths]
    if not stems:
        return ""
    prefix = os.path.commonprefix(stems)
    if len(stems) == 1:
        channel_words = {w for _, names in CHANNEL_WORDS for w in names}
        prefix = " ".join(w for w in re.split(r"[^A-Za-z0-9]+", stems[0])
                          if w and w.lower() not in channel_words)
    return prefix.strip(" _-.")


def sprite_lamp_side(path):
    """The lighting side a file's name says in Sprite Lamp's convention (portrait_left.png,
    'Top', 'front'…), or None."""
    stem = os.path.splitext(os.path.basename(path))[0].lower()
    match = re.search(r"(?:^|[_\-. ])(" + "|".join(SIDES) + r")$", stem)
    return match.group(1) if match else None


def sprite_lamp_siblings(path):
    """{side: path} of the profiles beside `path` named like it in Sprite Lamp's convention
    (portrait_left.png → portrait_right.png, portrait_top.jpg, …), `path` included."""
    side = sprite_lamp_side(path)
    if side is None:
        return {}
    folder, name = os.path.split(path)
    stem = os.path.splitext(name)[0][:-len(side)]
    found = {}
    for other in sorted(os.listdir(folder or ".")):
        base, ext = os.path.splitext(other)
        if base.lower().startswith(stem.lower()) and base[len(stem):].lower() in SIDES \
                and ext.lower() in IMAGE_EXTENSIONS:
            found.setdefault(base[len(stem):].lower(), os.path.join(folder, other))
    return found
