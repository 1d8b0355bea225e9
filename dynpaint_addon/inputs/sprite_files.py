"""Colour sprites beside their normal maps, named as 2D-lighting tools and engines name them
(issue 59; docs/your-painting.md has the table): `hero.png` + `hero_n.png` (SpriteIlluminator,
Laigter, Godot), `hero_normal.png` or `heroNormal.png` (Unity, Sprite Lamp), a height map as
`hero_depth.png`, and numbered frames `01.png` + `01_n.png` … `08_n.png`. A pair is found by
the names' *relation* — the map's name is the colour image's plus a map word — so the colour
image's own name is only a hint: `foreground_01.png` beside `foreground_01_n.png` is a sprite,
not a reflection image.

    >>> sprite_pairs(["hero.png", "hero_n.png", "notes.txt.png"]).pairs
    {'hero.png': 'hero_n.png'}
    >>> r = sprite_pairs(["01.png", "01_n.png", "02.png", "02_n.png", "03.png", "03_n.png"])
    >>> r.colour, r.shape, r.frames
    ('##.png', '##_n.png', 3)
    >>> sprite_pairs(["face_normal.png", "face_dark.png", "face_lit.png"]).pairs   # no pair
    {}
"""
import os
import re
from dataclasses import dataclass, field

# The words a map's name adds to its colour image's (after _, -, . or a space; or capitalised
# and joined, camelCase), most telling first: normal maps, then height maps.
NORMAL_SUFFIXES = ("n", "nm", "nrm", "nor", "norm", "normal", "normals", "normalmap",
                   "normal_map")
# A normal map whose alpha holds the depth, not the figure: Sprite Lamp's `_NormalDepth`, the
# Daemon engine's `_nh`
NORMAL_DEPTH_SUFFIXES = ("normaldepth", "normal_depth", "normalheight", "normal_height", "nh")
HEIGHT_SUFFIXES = ("depth", "height", "heightmap", "h", "disp", "bump")
# The words a colour image's name may end in when its maps share its stem instead (Sprite
# Lamp's `hero_Diffuse.png` + `hero_Normal.png`, an engine's `hero_d` + `hero_n`)
COLOUR_SUFFIXES = ("diffuse", "diff", "d", "albedo", "color", "colour", "col", "basecolor",
                   "base_color", "c")
_SEPARATED = re.compile(r"^[ _.\-](.+)$")
_COLOUR_WORD = re.compile(r"(?i)[ _.\-](" + "|".join(COLOUR_SUFFIXES) + r")$")
_DIGITS = re.compile(r"\d+(?=\D*$)")          # a name's last run of digits: its frame number


def map_suffix(colour, other):
    """'normal' or 'height' when `other` is named as `colour`'s map (both file names), else ''.

    >>> map_suffix("hero.png", "hero_n.png"), map_suffix("hero.png", "heroNormal.png")
    ('normal', 'normal')
    >>> map_suffix("hero.png", "heron.png"), map_suffix("hero.png", "hero_Depth.png")
    ('', 'height')
    >>> map_suffix("hero_Diffuse.png", "hero_Normal.png")      # siblings of one stem
    'normal'
    """
    stem, other_stem = os.path.splitext(colour)[0], os.path.splitext(other)[0]
    sibling = _COLOUR_WORD.search(stem)
    if sibling and (kind := _map_word(stem[:sibling.start()], other_stem)):
        return kind
    return _map_word(stem, other_stem)


def _map_word(stem, other_stem):
    """'normal' or 'height' when `other_stem` is `stem` plus a map word, else ''."""
    if len(other_stem) <= len(stem) or other_stem[:len(stem)].lower() != stem.lower():
        return ""
    rest = other_stem[len(stem):]
    separated = _SEPARATED.match(rest)
    if separated:
        word = separated.group(1).lower()
    elif rest[0].isupper() and len(rest) > 1:      # camelCase: heroNormal
        word = rest.lower()
    else:
        return ""
    if word in NORMAL_SUFFIXES or word in NORMAL_DEPTH_SUFFIXES:
        return "normal"
    return "height" if word in HEIGHT_SUFFIXES else ""


def depth_in_alpha(name):
    """Does a map's name say its alpha holds the depth (Sprite Lamp's NormalDepth)?

    >>> depth_in_alpha("StoneWall_NormalDepth.png"), depth_in_alpha("wall_nh.tga")
    (True, True)
    >>> depth_in_alpha("wall_normal.png"), depth_in_alpha("hero_n.png")
    (False, False)
    """
    stem = re.sub(r"(?<=[a-z])(?=[A-Z])", "_", os.path.splitext(os.path.basename(name))[0])
    return re.search(r"(?i)(?:^|[ _.\-])(?:normal[ _\-]?(?:depth|height)|nh)$", stem) is not None


@dataclass
class SpritePairs:
    """What a folder's names say of sprites and their maps: `pairs` {colour file: map file}
    (a normal map where both kinds are given), and when they are one sprite or one numbered
    sequence of them, `colour` and `shape` (file names, `##` for a frame number: §16) and
    `frames` (how many; 1 for one sprite). `rest`: the files in no pair."""
    pairs: dict = field(default_factory=dict)
    colour: str = ""
    shape: str = ""
    frames: int = 0
    rest: list = field(default_factory=list)

    @property
    def first_shape(self):
        """The first frame's map file (or the one map)."""
        return self.pairs[min(self.pairs)] if self.pairs else ""


def sprite_pairs(names):
    """A folder's image file names → SpritePairs (the module's rule)."""
    names = sorted(names)
    pairs, kinds = {}, {}
    for colour in names:
        for other in names:
            kind = map_suffix(colour, other) if other != colour else ""
            if kind and (colour not in pairs or (kind, kinds[colour]) == ("normal", "height")):
                pairs[colour], kinds[colour] = other, kind
    maps = set(pairs.values())
    pairs = {c: m for c, m in pairs.items() if c not in maps}     # a map is no sprite itself
    used = set(pairs) | set(pairs.values())
    found = SpritePairs(pairs, rest=[n for n in names if n not in used])
    if len(pairs) == 1:
        (found.colour, found.shape), found.frames = next(iter(pairs.items())), 1
    elif pairs:
        patterns = {(_numbered(c, pairs), _numbered(m, pairs.values())) for c, m in pairs.items()}
        if len(patterns) == 1 and "" not in next(iter(patterns)):
            (found.colour, found.shape), found.frames = patterns.pop(), len(pairs)
    return found


def _numbered(name, family):
    """`name` with its frame number as Blender's `#`s (as many as its digits when the family's
    numbers share a width, else one), or '' without digits."""
    match = _DIGITS.search(name)
    if not match:
        return ""
    widths = {len(m.group()) for m in map(_DIGITS.search, family) if m}
    hashes = "#" * (len(match.group()) if len(widths) == 1 else 1)
    return name[:match.start()] + hashes + name[match.end():]
