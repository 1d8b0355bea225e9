"""Every painting parameter, once: type, default, range, unit and tooltip.

The recipe reader (inputs/recipe.py), the command line's help, the docs and the add-on's Blender
properties are all generated from this table, so a parameter is added in one place.
No bpy import here. Lengths are in image widths (pipeline.md §0) unless a unit says otherwise.
"""
import math
from dataclasses import dataclass, replace
from types import SimpleNamespace

from .core.bake import QUALITIES
from .core.frames import MODES
from .core.fresnel import DOMAINS
from .core.inputs import MASK_CHANNELS
from .core.lights import FALLOFFS
from .core.sampling import EXTENSIONS
from .core.shading import CURVES, MIX_SPACES
from .core.shadow import OCCUPANCIES
from .core.shape import ENCODINGS
from .core.warps import REFLECTION_MODES, REFRACTION_MODES


@dataclass(frozen=True)
class Param:
    """One parameter and its role. Every other list of parameters (Blender properties and
    panels, the graph's structure, the keys of derived images and bakes, command-line options,
    the docs) is generated from these fields."""
    section: str
    key: str
    kind: type | str     # bool, int, float, 'enum', 'auto_float' (a number or "auto"),
    #                      'auto_int' (an integer or "auto"),
    #                      'vec2' (two numbers [x, y], each within min … max)
    default: object
    help: str
    unit: str = ""
    min: float | None = None
    max: float | None = None
    choices: tuple = ()
    spec: str = ""       # pipeline.md section
    label: str = ""      # short UI label (default: the key in title case)
    auto_value: float = 0.0   # auto_float: what the slider shows when 'auto' is switched off
    # Roles. structural: it decides which branches the graph has (a field of
    # nodegraph.features.Features, named `feature` or after the path); the graph reads any
    # parameter's value live (a driver or a group input carries it: changing it rebuilds
    # nothing), a structural one's too where a branch needs it. derives:
    # the images numpy derives from the inputs with it (nodegraph/derived_inputs.py). bake: the cos-θ
    # bake reads it.
    structural: bool = False
    feature: str = ""
    derives: tuple = ()
    bake: bool = False
    # Panels: `header` puts a toggle in its panel's header; `shown_if` (path, value) shows it
    # only while that parameter has that value.
    header: bool = False
    shown_if: tuple = ()

    @property
    def path(self):
        return f"{self.section}.{self.key}"

    @property
    def feature_name(self):
        """The Features field of a structural parameter: 'shape.kind' → 'shape_kind',
        'specular.enabled' → 'specular'."""
        if self.feature:
            return self.feature
        return self.section if self.key == "enabled" else f"{self.section}_{self.key}"

    @property
    def panel(self):
        return next(panel for panel, (_, sections) in PANELS.items() if self.section in sections)

    @property
    def components(self):
        """What a backend addresses one by one: (None,) for a number, (0, 1) for a vec2."""
        return (0, 1) if self.kind == "vec2" else (None,)

    def setting(self, index=None):
        """Its path in the painting's settings, of component `index` for a vec2:
        'diffuse.t0', 'reflection.offset[1]' (what a driver reads)."""
        return self.path if index is None else f"{self.path}[{index}]"

    @property
    def ui_label(self):
        return self.label or self.key.replace("_", " ").title()

    def check(self, value):
        """The value as the parameter holds it, or ValueError saying what is wrong (every
        reader of a value calls this: recipes, command-line options, export-web).

        >>> BY_PATH["refraction.ior"].check(1)
        1.0
        >>> BY_PATH["refraction.ior"].check(3.0)
        Traceback (most recent call last):
        ValueError: 3.0 is out of range [0.5, 2.0]
        """
        kind = self.kind
        if kind is bool:
            if not isinstance(value, bool):
                raise ValueError(f"expected true or false, got {value!r}")
            return value
        if kind == "enum":
            if value not in self.choices:
                raise ValueError(f"must be one of {', '.join(self.choices)}, got {value!r}")
            return value
        if kind in ("auto_float", "auto_int") and value == "auto":
            return value
        if kind == "vec2":
            if not isinstance(value, (list, tuple)) or len(value) != 2:
                raise ValueError(f"expected two numbers [x, y], got {value!r}")
            component = replace(self, kind=float)
            out = []
            for i, c in enumerate(value):
                try:
                    out.append(component.check(c))
                except ValueError as exc:
                    raise ValueError(f"[{i}]: {exc}") from None
            return tuple(out)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            expected = expected_integer(kind) if kind in (int, "auto_int") else (
                'a number or "auto"' if kind == "auto_float" else "a number")
            raise ValueError(f"expected {expected}, got {value!r}")
        if kind in (int, "auto_int") and not isinstance(value, int):
            raise ValueError(f"expected {expected_integer(kind)}, got {value!r}")
        if not math.isfinite(value):
            raise ValueError(f"must be a finite number, got {value!r}")
        if self.min is not None and value < self.min or self.max is not None and value > self.max:
            unit = f" {self.unit}" if self.unit else ""
            raise ValueError(f"{value!r} is out of range [{self.min}, {self.max}]{unit}")
        return int(value) if kind in (int, "auto_int") else float(value)


def expected_integer(kind):
    return 'an integer or "auto"' if kind == "auto_int" else "an integer"


P = Param
PARAMS = (
    # §2 shape
    P("shape", "kind", "enum", "normal", "What the shape image holds: a normal map (RGB) or a "
      "height map (grey, lighter = nearer the viewer)", choices=("normal", "height"), spec="§2",
      structural=True, derives=("shape", "height"), bake=True),
    P("shape", "flip_green", bool, False, "Normal maps whose green channel means 'lit from below' "
      "(DirectX style)", spec="§2", label="Flip Green (DirectX)", derives=("relief",), bake=True,
      shown_if=("shape.kind", "normal")),
    P("shape", "encoding", "enum", "auto", "How a normal map stores its normals: rgb (x, y, z in "
      "red, green, blue) or rg (x and y only, z = √(1 − x² − y²), blue ignored: the two-channel "
      "maps of many engines and tools); auto reads a map whose blue is 0 everywhere as rg",
      choices=ENCODINGS, spec="§2", derives=("shape", "relief"), bake=True,
      shown_if=("shape.kind", "normal")),
    P("shape", "strength", "auto_float", "auto", "Scales each normal's tilt angle: 0.5 halves "
      "every tilt, exactly what maps made for a decoder that halves them (normalize((0,0,1) + "
      "N), some web relighting tools) need; 1 = as painted; 'auto' = 0.5 for a map of unit "
      "vectors of which some face away (only such maps do), else 1", min=0.0, max=2.0,
      spec="§2", auto_value=1.0, derives=("shape", "relief"), bake=True,
      shown_if=("shape.kind", "normal")),
    P("shape", "z_min", float, 0.05, "Smallest allowed N.z: steeper normals are tilted back up so "
      "slopes stay finite", min=0.001, max=1.0, spec="§2", label="Minimum N.z",
      derives=("relief",), bake=True),
    P("shape", "height_scale", float, 0.05, "Relief height of a white height-map pixel",
      unit="image widths", min=0.0, max=10.0, spec="§2", label="Height", bake=True,
      shown_if=("shape.kind", "height")),
    P("shape", "preblur", "auto_float", "auto", "Gaussian blur of the height map before slopes "
      "are taken, against 8-bit terracing; 'auto' = 1.5 px for 8-bit images, 0 for 16-bit and float",
      unit="pixels", min=0.0, max=64.0, spec="§2", label="Pre-blur", auto_value=1.5,
      derives=("height",), bake=True, shown_if=("shape.kind", "height")),
    # §3–§5 diffuse style
    P("diffuse", "t0", float, 0.0, "Clamp&Step start: light terms below this give the dark image",
      min=-1.0, max=1.0, spec="§3", label="Start (t0)"),
    P("diffuse", "t1", float, 1.0, "Clamp&Step end: light terms above this give the bright image "
      "(t0 = t1 is a cartoon step; t0 > t1 inverts)", min=-1.0, max=1.0, spec="§3",
      label="End (t1)"),
    P("diffuse", "curve", "enum", "linear", "Shape of the ramp between t0 and t1", choices=CURVES,
      spec="§3", structural=True),
    P("diffuse", "mix_space", "enum", "painted", "How the dark and bright images mix: painted "
      "mixes the colours as painted (display sRGB values, as the paper and the painter's screen "
      "do), linear mixes linear light (mid-tones come out lighter than painted)",
      choices=MIX_SPACES, spec="§5", label="Mix Colours", structural=True),
    P("diffuse", "ambient", float, 0.2, "A painting of one colour image (a sprite beside its "
      "normal map) is lit as an albedo, colour × (ambient + (1 − ambient) × light): how much "
      "of its colour shows where no light falls; 1 = flat, the light changes nothing. A "
      "painting with a dark and a bright image mixes them instead", min=0.0, max=1.0,
      spec="§1, §5"),
    P("falloff", "mode", "enum", "none", "How point lights fade with distance: none (the "
      "paper's lights: as strong everywhere) or inverse square with a radius, "
      "k / (1 + (distance/radius)²); suns never fade", choices=FALLOFFS, spec="§5",
      label="Point-Light Falloff", structural=True),
    P("falloff", "radius", float, 0.5, "Distance from a point light at which its strength is "
      "halved; far beyond it the light fades as the inverse square", unit="image widths",
      min=0.001, max=100.0, spec="§5", shown_if=("falloff.mode", "inverse_square")),
    # §6 shadows
    P("shadows", "enabled", bool, False, "cos-θ shadows: cast shadows, shading and a subsurface "
      "look in one number (replaces N·L in the diffuse term)", spec="§6", structural=True,
      header=True),
    P("shadows", "source", "enum", "baked", "Where the cos-θ term comes from: baked into images "
      "by numpy (EEVEE and Cycles), or 'osl': marched per pixel and frame inside an OSL shader "
      "that Cycles (CPU) renders the whole painting with; EEVEE keeps the baked material",
      choices=("baked", "osl"), spec="§6, §13", structural=True, feature="shadow_source"),
    P("shadows", "quality", "enum", "final", "Speed against accuracy of the bake (§13): draft "
      "and preview bake at a reduced resolution (⅛ and ¼), final at full, all by crossings "
      "(final from 512 px up; below, the K = 64 march), reference in float64 with K = 1024; "
      "custom uses your K and resolution", choices=QUALITIES,
      spec="§13", bake=True),
    P("shadows", "offset", float, 0.01, "d: how deep below the surface each shadow ray starts; "
      "relief finer than d is smoothed: larger = softer, more translucent look, smaller = "
      "crisper fine relief", unit="image widths", min=0.0, max=1.0, spec="§6",
      label="Offset (d)", bake=True),
    P("shadows", "steps", int, 64, "K: march steps per pixel (more = more accurate, slower; "
      "custom quality)", min=0, max=100000, spec="§6", label="Steps (K)", bake=True),
    P("shadows", "resolution", float, 1.0, "Resolution the bake marches at, then upsampled "
      "(custom quality)", unit="× the shape image", min=0.05, max=1.0, spec="§13", bake=True),
    P("shadows", "relief", "enum", "auto", "What a normal map's shadows fall from: "
      "integrated, the height field that best fits its normals (least squares, the figure cut "
      "at the shape image's alpha); along_ray, its slopes rebuilt along each shadow ray (the "
      "paper's way: impossible figures, whose normals fit no height field, and full-frame maps "
      "whose hidden walls the integration would spread); auto = at final quality the shadow "
      "of either relief (the darker of the two: a map cannot tell a figure sunk in its ground "
      "from one resting on it) where the normals fit a height field; at live levels, and "
      "for impossible figures, integrated where the shape image has an alpha, else along_ray "
      "(measured against 3D: docs/relief-choice.md)",
      choices=("integrated", "along_ray", "auto"),   # this order: a .blend stores the index
      spec="§6", label="Normal-Map Relief", structural=True, derives=("relief",), bake=True,
      shown_if=("shape.kind", "normal")),
    P("shadows", "reach", float, 0.05, "How far along each shadow ray an impossible figure's "
      "relief is felt (relief along_ray); beyond it the surface continues flat (its tangent "
      "plane). A normal map holds slopes, not heights: rebuilt along a ray across an "
      "impossible figure they never come back down and streak. A map whose normals fit a "
      "height field (measured: their circulation, docs/relief-choice.md) is felt along the "
      "whole ray, whatever this says; 10 = the whole image", unit="image widths",
      min=0.0, max=10.0, spec="§6", bake=True, shown_if=("shape.kind", "normal")),
    P("shadows", "occupancy", "enum", "linear", "How a march step counts as inside the relief: "
      "linear crossing (accurate) or the paper's midpoint test", choices=OCCUPANCIES, spec="§6",
      bake=True),
    # §7 specular
    P("specular", "enabled", bool, False, "Opaque highlights of the specular colour", spec="§7",
      structural=True, header=True),
    P("specular", "s0", float, 0.9, "Highlight Clamp&Step start (on R_L·I)", min=-1.0, max=1.0,
      spec="§7", label="Start (s0)"),
    P("specular", "s1", float, 1.0, "Highlight Clamp&Step end", min=-1.0, max=1.0, spec="§7",
      label="End (s1)"),
    P("specular", "curve", "enum", "smoothstep", "Shape of the highlight ramp", choices=CURVES,
      spec="§7", structural=True),
    P("specular", "amount", float, 1.0, "g: gloss strength (multiplies the gloss map)",
      min=0.0, max=1.0, spec="§7"),
    P("specular", "gloss_channel", "enum", "auto", "What of the gloss map is g: its luminance, "
      "one channel, or auto (a map painted in one pure channel is read from that channel, "
      "else its luminance)", choices=MASK_CHANNELS, spec="§7", label="Gloss Channel",
      derives=("gloss",)),
    # §8 reflection
    P("reflection", "distance", float, 0.05, "d_E: how far the environment appears behind the "
      "surface (reflection offset scale)", unit="image widths", min=0.0, max=10.0, spec="§8"),
    P("reflection", "mode", "enum", "stereographic", "Bounded offset: stereographic 2·d_E·N.xy/N.z,"
      " or the paper's R.xy/R.z clamped at the maximum offset", choices=REFLECTION_MODES, spec="§8",
      structural=True),
    P("reflection", "max_offset", float, 0.5, "Largest reflection offset", unit="image widths",
      min=0.0, max=10.0, spec="§8", label="Max Offset"),
    P("reflection", "extension", "enum", "mirror", "Environment lookups beyond its edges: "
      "mirror (seamless on photographs), wrap (for tiling images), extend (edge pixels)",
      choices=EXTENSIONS, spec="§8", structural=True, derives=("environment",)),
    P("reflection", "offset", "vec2", (0.0, 0.0), "Where the environment sits: its centre "
      "moved from the painting's centre by (x, y), e.g. to put a reflection in a pupil",
      unit="image widths", min=-2.0, max=2.0, spec="§8"),
    P("reflection", "scale", float, 1.0, "How large the environment is: 1 spans the painting, "
      "2 twice its size, 0.5 half (repeated by the extension beyond its edges)", unit="×",
      min=0.1, max=10.0, spec="§8"),
    P("reflection", "blur", float, 0.0, "Glossy reflection: Gaussian blur σ of the environment",
      unit="image widths", min=0.0, max=1.0, spec="§11", derives=("environment",)),
    # §9 refraction
    P("refraction", "distance", float, 0.05, "d_B: how far the background lies behind the surface",
      unit="image widths", min=0.0, max=10.0, spec="§9"),
    P("refraction", "mode", "enum", "physical", "physical (index of refraction η) or art-directed "
      "(linear in μ)", choices=REFRACTION_MODES, spec="§9", structural=True),
    P("refraction", "ior", float, 1.5, "η = η₂/η₁, the relative index of refraction (also drives "
      "the physical Fresnel)", min=0.5, max=2.0, spec="§9", label="IOR (η)"),
    P("refraction", "mu", float, 0.585, "μ = log₂ η for art-directed refraction: 0 = none, "
      "+1 magnifies most, −1 shrinks most", min=-1.0, max=1.0, spec="§9", label="Art IOR (μ)",
      shown_if=("refraction.mode", "linear")),
    P("refraction", "extension", "enum", "extend", "Background lookups beyond its edges",
      choices=EXTENSIONS, spec="§9", structural=True, derives=("background",)),
    P("refraction", "offset", "vec2", (0.0, 0.0), "Where the background sits: its centre moved "
      "from the painting's centre by (x, y), refracted and shown around the silhouette alike",
      unit="image widths", min=-2.0, max=2.0, spec="§9"),
    P("refraction", "scale", float, 1.0, "How large the background is: 1 spans the painting",
      unit="×", min=0.1, max=10.0, spec="§9"),
    P("refraction", "blur", float, 0.0, "Translucent refraction: Gaussian blur σ of the background",
      unit="image widths", min=0.0, max=1.0, spec="§11",
      derives=("background", "background_sharp")),     # blur 0: the sharp copy is the same
    # §10 Fresnel
    P("fresnel", "mode", "enum", "physical", "Reflection/refraction ratio: physical Fresnel of η, "
      "or the art-directed piecewise-linear curve", choices=("physical", "art"), spec="§10",
      structural=True),
    P("fresnel", "domain", "enum", "cos", "Art-directed curve placed along 1 − cos θ (fits the "
      "physical curve better) or sin θ", choices=DOMAINS, spec="§10", structural=True,
      shown_if=("fresnel.mode", "art")),
    P("fresnel", "x1", float, 0.45, "Art-directed 'total refraction' point: F = 0 up to here",
      min=0.0, max=1.0, spec="§10", label="Refraction Until",
      shown_if=("fresnel.mode", "art")),
    P("fresnel", "x2", float, 0.9, "Art-directed 'equal mix' point: F = ½ here", min=0.0, max=1.0,
      spec="§10", label="Equal Mix At",
      shown_if=("fresnel.mode", "art")),
    P("fresnel", "kappa", float, 0.0, "κ: −1 total refraction … 0 as the curve says … +1 total "
      "reflection", min=-1.0, max=1.0, spec="§10", label="Reflect ↔ Refract (κ)",
      shown_if=("fresnel.mode", "art")),
    # §11 composite
    P("transparency", "amount", "auto_float", "auto", "k: where the surface shows the reflection/"
      "refraction mix (multiplies the transparency map); 'auto' = 1 with a map, 0 without",
      min=0.0, max=1.0, spec="§11", auto_value=1.0, structural=True, feature="transparency"),
    P("transparency", "channel", "enum", "auto", "What of the transparency map is k: its "
      "luminance, one channel, or auto (a mask painted in one pure channel, say red on black, "
      "is read from that channel, else its luminance)", choices=MASK_CHANNELS, spec="§11",
      label="Map Channel", derives=("transparency",)),
    P("view", "show", "enum", "painting", "What the material shows, to tune by eye: the painting, "
      "or one pass alone — W, the light weight that mixes dark and bright (§5); t, the largest "
      "light term after Clamp&Step (§4); s, the highlight weight (§7); F, the Fresnel ratio "
      "(§10, 0 without both environment and background)", choices=("painting", "W", "t", "s", "F"),
      spec="§5, §11", label="Show", structural=True),
    P("silhouette", "source", "enum", "auto", "Whose alpha cuts the painting out over the "
      "background: auto (shape, else dark), shape, dark, none",
      choices=("auto", "shape", "dark", "none"), spec="§11", structural=True,
      feature="silhouette", derives=("silhouette",)),
)

# Paintings that move (§16): how a painting's image sequences and sprite sheets follow the
# scene's frames. One mapping per painting ([frames]); any key can be set again for one image
# slot ([frames.dark], …); a still image stays still. Not pipeline parameters: they choose
# which images the pipeline gets, so the graph never reads them.
FRAME_PARAMS = (
    P("frames", "start", int, 1, "Scene frame that shows the painting's first frame "
      "(Blender's Start Frame)", min=-1048574, max=1048574, spec="§16", label="Start Frame"),
    P("frames", "offset", "auto_int", "auto", "Added to the painting's frame to give the "
      "file number (Blender's Offset); 'auto' = the first file's number − 1 for a sequence "
      "(what Blender's Open does: the first file shows at the start frame), 0 for a sheet",
      min=-1048574, max=1048574, spec="§16", auto_value=0),
    P("frames", "count", int, 0, "How many frames the painting has (Blender's Frames); 0 = "
      "all of them (a sequence's first to last file, a sheet's cells)", min=0, max=1048574,
      spec="§16", label="Frames"),
    P("frames", "mode", "enum", "cyclic", "What the scene frames beyond the painting's show: "
      "cyclic (it loops, Blender's Cyclic), ping-pong (forth and back), hold (its first "
      "frame before, its last after: Blender without Cyclic)", choices=MODES, spec="§16",
      label="Repeat"),
    P("frames", "rate", float, 1.0, "Painting frames per scene frame: 0.5 holds each drawing "
      "for two frames (animation 'on twos'), 2 skips every other one", min=0.01, max=100.0,
      spec="§16", label="Rate"),
    P("frames", "columns", int, 1, "A sprite sheet's columns (1 column and 1 row: not a "
      "sheet); its frames run row by row from the top left", min=1, max=4096, spec="§16"),
    P("frames", "rows", int, 1, "A sprite sheet's rows", min=1, max=4096, spec="§16"),
    P("frames", "margin", int, 0, "Pixels around a sprite sheet's grid", unit="pixels",
      min=0, max=65536, spec="§16"),
    P("frames", "spacing", int, 0, "Pixels between a sprite sheet's cells", unit="pixels",
      min=0, max=65536, spec="§16"),
)
FRAME_BY_KEY = {p.key: p for p in FRAME_PARAMS}

SECTIONS = tuple(dict.fromkeys(p.section for p in PARAMS))
BY_PATH = {p.path: p for p in PARAMS}

# The sub-panels of the Dynamic Painting panel, in order: id → (label, sections shown).
PANELS = {
    "shape": ("Shape", ("shape",)),
    "style": ("Light & Style", ("diffuse", "falloff")),
    "shadows": ("Shadows", ("shadows",)),
    "highlights": ("Highlights", ("specular",)),
    "warps": ("Reflection & Refraction", ("reflection", "refraction")),
    "fresnel": ("Fresnel", ("fresnel",)),
    "transparency": ("Transparency", ("transparency", "silhouette")),
    "view": ("View", ("view",)),
}

# §1 channels: recipe key → (what it is, colour or data)
CHANNELS = {
    "shape": ("normal map (RGB) or height map (grey)", "data"),
    "dark": ("dark control image C0", "colour"),
    "bright": ("bright control image C1", "colour"),
    "specular_color": ("colour of highlights (default white)", "colour"),
    "gloss": ("gloss map g (grey, default 1)", "data"),
    "environment": ("environment E, reflected", "colour"),
    "background": ("background B, refracted and shown outside the silhouette", "colour"),
    "transparency": ("transparency map k (grey)", "data"),
}
REQUIRED_CHANNELS = ("shape",)


def defaults():
    """A namespace per section holding every default: p.shadows.offset, …"""
    return SimpleNamespace(**{s: SimpleNamespace(**{p.key: p.default for p in PARAMS
                                                    if p.section == s}) for s in SECTIONS})


def as_dict(params):
    """Section → {key: value} (for writing and comparing recipes; recipe.parse_recipe reads
    them back)."""
    return {s: dict(vars(getattr(params, s))) for s in SECTIONS}


def frame_defaults():
    """[frames]' keys → their defaults (a painting that does not move has exactly these)."""
    return {p.key: p.default for p in FRAME_PARAMS}
