"""Make Shape's methods and options, once (issue 28; docs/shape-from-painting.md).

The command line's `make-shape METHOD` arguments (cli/make_shape.py) and the add-on's Make
Shape operator (its properties and its dialog, blender/operators/shape.py) are generated from
these two tables, as params.py generates a painting's properties and recipe keys: an option
is added in one place. `make_shape` runs a method on a painting's images. No bpy here.

    >>> [o.name for o in options("inflate", "addon")]
    ['profile', 'height', 'snap', 'detail', 'detail_blur', 'bevel_width', 'bevel_height', 'bevel_profile', 'smoothing']
    >>> OPTION["height"].check(20.0)
    Traceback (most recent call last):
    ValueError: 20.0 is out of range [0.01, 10.0]
"""
from dataclasses import dataclass, field
from typing import Callable

from ..core.effects import BEVEL_PROFILES
from ..core.inflate import PROFILES
from ..core.inputs import MASK_CHANNELS
from ..core.photometric import SIDES
from ..core.shape import ENCODINGS
from ..params import Param
from .maker import (GREENS, ShapeError, inflate_silhouette, integrate_normal_map,
                          normal_map_from_profiles, normal_map_from_rg_photo, normal_map_of_height)


@dataclass(frozen=True)
class Method:
    label: str                  # the operator's menu
    help: str                   # what it makes from what (tooltip, command help)
    makes: str                  # 'height', 'normal' or 'maps': what --out receives
    make: Callable = None       # (images, p, **its options) → (kind, RGBA, lines); None: the
    #                             command line only (it reads a recipe, writes several maps)

    @property
    def command(self):
        """Its name on the command line: 'rg_photo' → 'rg-photo'."""
        return next(k for k, m in METHODS.items() if m is self).replace("_", "-")


METHODS = {
    "inflate": Method("Inflate Silhouette", "silhouette → round height map (−Δh = 1 inside, "
                      "h = 0 on its edge): a round relief inside the painting's alpha", "height",
                      inflate_silhouette),
    "integrate": Method("Height from Normal Map", "normal map → height map by least squares "
                        "(free edges)", "height", integrate_normal_map),
    "normals": Method("Normal Map from Height", "height map → normal map (§2)", "normal",
                      normal_map_of_height),
    "profiles": Method("Normal Map from Lighting Profiles", "lighting profiles (2–5 images lit "
                       "from the sides) → normal map", "normal", normal_map_from_profiles),
    "rg_photo": Method("Normal Map from a Red/Green Photo", "photograph lit red from one side, "
                       "green from the top → normal map", "normal", normal_map_from_rg_photo),
    "export_maps": Method("Export Maps", "a recipe's maps for game engines: normal, height, AO, "
                          "specular", "maps"),
}

# the methods that make a shape image from a painting (the add-on's menu; make_shape)
SHAPE_MAKERS = [name for name, method in METHODS.items() if method.make is not None]


@dataclass(frozen=True)
class Option:
    """One option of one or more methods. `where`: 'both', 'cli' (what the command line reads
    from files or writes) or 'addon' (what the operator takes from the painting)."""
    name: str                   # make_shape's keyword, the operator's property, --name
    methods: tuple
    kind: object                # float, bool, 'auto_float' (a number or "auto"), 'file' (an
    #                             image read), 'output' (a file written), 'text', or a tuple
    #                             of choices
    default: object = None
    help: str = ""
    label: str = ""
    min: float | None = None
    max: float | None = None
    precision: int = 3          # the operator's slider digits
    where: str = "both"
    positional: str = ""        # command line: an argument with this metavar, not --name
    flag: str = ""              # command line: another name than --name
    many: bool = False          # a positional taking any number of files
    required: bool = False      # the command line needs it
    choice_help: dict = field(default_factory=dict)
    active_if: str = ""         # the operator greys it out while this bool option is off

    @property
    def cli_flag(self):
        return self.flag or "--" + self.name.replace("_", "-")

    @property
    def ui_label(self):
        return self.label or self.name.replace("_", " ").title()

    def check(self, value):
        """The value, or ValueError saying what is wrong (params.Param.check's rules)."""
        if self.kind not in (float, int, bool, "auto_float") and not isinstance(self.kind, tuple):
            return value
        kind = "enum" if isinstance(self.kind, tuple) else self.kind
        return Param("make_shape", self.name, kind, self.default, self.help, min=self.min,
                     max=self.max, choices=self.kind if kind == "enum" else ()).check(value)


O = Option
PROFILE_HELP = {"round": "A disc becomes a hemisphere; other outlines are rounded as a whole "
                "(a long part comes out taller than it is wide)",
                "soft": "Gentle at the rim, pointed in the middle",
                "flat": "Rounded rims and a plateau (a coin, a cushion, a face seen from the "
                "front)",
                "tube": "Every cross-section a semicircle as wide as the figure there (a ring "
                "becomes a torus, an arm a tube)"}
OPTIONS = (
    # inflate
    O("image", ("inflate",), "file", help="painting with alpha, or a mask (white = figure)",
      where="cli", positional="IMAGE"),
    O("profile", ("inflate",), PROFILES, "round", "The rim's profile: round (a disc gives a "
      "hemisphere), soft, flat (rounded rims, a plateau) or tube (round cross-sections as "
      "wide as the figure)", choice_help=PROFILE_HELP),
    O("height", ("inflate",), float, 1.0, "Scale of the relief: 1 makes a disc's hemisphere as "
      "tall as its radius", min=0.01, max=10.0),
    O("mask_channel", ("inflate",), MASK_CHANNELS, "auto", "what of IMAGE is the figure (auto: "
      "its alpha, else a painted mask)", where="cli"),
    O("snap", ("inflate",), float, 0.0, "Move the mask's edge onto the painting's strongest "
      "edge within this distance (image widths; 0 = off): for a mask painted by hand a little "
      "off the figure (0.01 is a few pixels)", label="Snap to the Painting", min=0.0, max=0.05,
      precision=4),
    O("detail", ("inflate",), float, 0.0, "Emboss the painting's luminance: image widths of "
      "relief per unit of luminance (0.005–0.02 is subtle; 0 = none; negative: the dark "
      "parts stand out instead)", min=-0.1, max=0.1),
    O("detail_image", ("inflate",), "file", help="the painting whose luminance is embossed "
      "and whose edges --snap finds (default IMAGE)", where="cli"),
    O("detail_blur", ("inflate",), float, 0.002, "Blur of the embossed luminance (image widths)",
      min=0.0, max=0.05, precision=4),
    O("bevel_width", ("inflate",), float, 0.0, "A bevel: a rim rising from the figure's edge "
      "over this width (image widths; 0 = none)", label="Bevel", min=0.0, max=0.25, precision=4),
    O("bevel_height", ("inflate",), float, 0.02, "How high the bevel rises (image widths)",
      min=-0.25, max=0.25, precision=4),
    O("bevel_profile", ("inflate",), BEVEL_PROFILES, "round", "The bevel's cross-section: round "
      "(a quarter circle) or linear (a ramp)",
      choice_help={"round": "A quarter circle: steep at the edge, flat on top",
                   "linear": "A straight ramp from the edge"}),
    O("smoothing", ("inflate",), float, 0.0, "Blur of the made relief inside the figure (image "
      "widths; 0 = none)", min=0.0, max=0.1, precision=4),
    O("structure", ("inflate",), "file", help="a tileable image whose luminance is added as "
      "height detail (a fabric, a canvas)", where="cli"),
    O("structure_scale", ("inflate",), float, 0.1, "The structure image's tile width (image "
      "widths)", min=0.001, max=1.0, where="cli"),
    O("structure_strength", ("inflate",), float, 0.0, "Image widths of relief per unit of the "
      "structure's luminance (0 = none)", min=-0.1, max=0.1, where="cli"),
    # integrate
    O("normal", ("integrate",), "file", help="normal map image", where="cli", positional="NORMAL"),
    O("mask", ("integrate",), "text", "none", "figure mask image (white or alpha = figure), "
      "'alpha' for the normal map's own alpha, or 'none' (default): equations across the "
      "mask's edge are dropped, each part integrated on its own", where="cli"),
    O("use_mask", ("integrate",), bool, True, "Integrate the figure (the normal map's alpha) "
      "apart from its background", label="Cut at the Alpha", where="addon"),
    O("depth", ("integrate",), float, 0.0, "How far the figure's rim stands above its "
      "background (image widths); a normal map cannot see this wall", min=-1.0, max=1.0,
      active_if="use_mask"),
    O("encoding", ("integrate",), ENCODINGS, "auto", "rgb, rg (two-channel) or auto (as "
      "shape.encoding)", where="cli"),
    O("flip_green", ("integrate",), bool, False, "DirectX normal map (green down)", where="cli"),
    O("strength", ("integrate",), "auto_float", "auto", "scale of each normal's tilt: a number "
      "(0.5 for tilt-halving maps) or auto (as shape.strength)", min=0.0, max=2.0, where="cli"),
    O("residual", ("integrate",), "output", help="also write the residual |g − ∇z| per pixel "
      "(.exr)", where="cli"),
    # normals
    O("height_map", ("normals",), "file", help="height map (grey; EXR in image widths)",
      where="cli", positional="HEIGHT"),
    O("height_scale", ("normals",), float, None, "relief of a white pixel (image widths; 1 for "
      "make-shape's EXRs)", where="cli", required=True),
    O("preblur", ("normals",), float, 0.0, "Gaussian blur before the slopes are taken (pixels; "
      "1.5 for 8-bit maps)", where="cli"),
    # profiles
    O("images", ("profiles",), "file", help="profiles named in Sprite Lamp's convention "
      "(name_left.png, _right, _top, _bottom, _front)", where="cli", positional="IMAGE",
      many=True),
    *(O(f"profile_{side}", ("profiles",), "file", help=f"The picture lit from the {side}"
        + (" (Sprite Lamp's name_left.png: the other sides beside it are found)"
           if side == "left" else ""), label=side.title(), flag=f"--{side}") for side in SIDES),
    O("elevation", ("profiles",), float, 45.0, "How high the side lights were above the "
      "painting (degrees)", label="Side Lights' Elevation", min=1.0, max=89.0),
    # rg_photo
    O("photo", ("rg_photo",), "file", help="A photograph lit by a red light from one side and "
      "a green light from the top", label="Photograph", positional="PHOTO"),
    O("red_from", ("rg_photo",), ("right", "left"), "right", "The side the red light came "
      "from"),
    O("green_from", ("rg_photo",), ("top", "bottom"), "top", "The side the green light came "
      "from"),
    # export_maps
    O("recipe", ("export_maps",), "file", help="painting.toml, or a sample's name", where="cli",
      positional="RECIPE"),
    # what the command line writes
    O("green", ("normals", "profiles", "rg_photo", "export_maps"), GREENS, "opengl",
      "normal map convention: opengl (green = up, Blender) or directx (green = down)",
      where="cli"),
)
OPTION = {o.name: o for o in OPTIONS}


def options(method, where):
    """The options `method` takes on the command line ('cli') or in the add-on ('addon')."""
    return [o for o in OPTIONS if method in o.methods and o.where in ("both", where)]


def make_shape(method, images, p, floor=None, **values):
    """A painting's new shape image (the add-on's Make Shape; docs/shape-from-painting.md).

    Parameters
    ----------
    method : str
        A key of METHODS that has a `make` (not 'export_maps').
    images : dict
        {channel: ImageData} of the painting (pipeline.md §1).
    p : namespace
        The painting's parameters (params.defaults() layout): how its shape image is read.
    floor : float or None
        integrate: the height made 0 (None: the lowest point); the frames of a painting
        that moves take one (§16), so a part that does not change keeps its heights.
    **values
        The method's add-on options (OPTIONS), each at its default when not given; file
        options as ImageData (profiles: `profile_<side>`; rg_photo: `photo`).

    Returns
    -------
    kind : str
        'height' or 'normal'.
    pixels : ndarray (H, W, 4)
        Heights in image widths (grey) or a normal map's colours, with the old shape image's
        alpha (inflated: the silhouette's), else opaque.
    lines : list of str
        What was done, for the report.
    """
    if method not in SHAPE_MAKERS:
        raise ShapeError(f"unknown method {method!r} (expected one of {', '.join(SHAPE_MAKERS)})")
    taken = options(method, "addon")
    unknown = set(values) - {o.name for o in taken}
    if unknown:
        raise ShapeError(f"{method} takes no option {', '.join(sorted(unknown))}")
    kwargs = {o.name: values.get(o.name, o.default) for o in taken}
    if method == "profiles":       # the sides, gathered
        kwargs = {"profiles": {o.name.removeprefix("profile_"): kwargs.pop(o.name)
                               for o in taken if o.name.startswith("profile_")}, **kwargs}
    if method == "integrate":
        kwargs["floor"] = floor
    return METHODS[method].make(images, p, **kwargs)
