"""What the render reads of a painting's images, and how (pipeline.md §1, §11, §12, §14).

`ImageData` holds one input image in core convention; the rules here decide what the render
and every backend make of a painting's images before shading: which channels are per pixel,
how a mask is read (transparency, gloss), whose alpha is the silhouette, whether the
transparency branch exists, what a normal map's shadows fall from, how non-finite pixels are
replaced, and the notes every command prints about the images. core/pipeline.py renders
with them; nodegraph/features.py and derived_inputs.py take the same rules for the graphs.
"""
from dataclasses import dataclass, field

import numpy as np

from .inputs import (finite_pixels, mask_channel, mask_note, non_finite_message,
                     normal_map_notes, normal_map_problem, size_message)
from .map_convention import green_reading
from .sampling import resample
from .shape import CURL_LIMIT, circulation, decode_normal_map, slopes_from_normals

PER_PIXEL_CHANNELS = ("dark", "bright", "specular_color", "gloss", "transparency")


@dataclass
class ImageData:
    """One input image in core convention: pixels (H, W, C) with row 0 at the bottom (§0).

    bits: 8, 16 or 32 (float). Integer images hold file values scaled to 0..1 (colour ones are
    sRGB-encoded); float images are linear already.
    """
    pixels: np.ndarray
    bits: int = 8
    name: str = ""
    notes: list = field(default_factory=list, compare=False)   # what reading the file found

    def __post_init__(self):
        px = np.asarray(self.pixels)
        if px.ndim == 2:
            px = px[..., None]
        self.pixels = px

    @property
    def size(self):
        return self.pixels.shape[1], self.pixels.shape[0]

    @property
    def has_alpha(self):
        return self.pixels.shape[2] in (2, 4)

    def rgb(self):
        """RGB view: grey is repeated, alpha dropped."""
        c = self.pixels.shape[2]
        if c >= 3:
            return self.pixels[..., :3]
        return np.repeat(self.pixels[..., :1], 3, axis=2)

    def grey(self):
        """One channel: grey as is; colour by Rec.709 luminance."""
        c = self.pixels.shape[2]
        if c < 3:
            return self.pixels[..., 0]
        return self.pixels[..., :3] @ np.array([0.2126, 0.7152, 0.0722], dtype=self.pixels.dtype)

    def alpha(self):
        c = self.pixels.shape[2]
        return self.pixels[..., c - 1] if c in (2, 4) else None


def relief_of(relief, shape_has_alpha):
    """shadows.relief as the relief a normal map's shadows fall from (§6 "Relief"): 'auto' is
    integrated where the shape image has an alpha (the figure is cut out; its hidden walls
    are at the cut), along the ray for a full-frame map (integrating it would spread each
    hidden wall over the whole image). Measured against 3D: docs/relief-choice.md.

    >>> relief_of("auto", shape_has_alpha=True), relief_of("auto", shape_has_alpha=False)
    ('integrated', 'along_ray')
    """
    if relief != "auto":
        return relief
    return "integrated" if shape_has_alpha else "along_ray"


# An alpha at least this everywhere cuts nothing out: many tools save every image as RGBA (the
# last 8-bit step, 254/255, is a rounding's, not a figure's edge)
OPAQUE = 254 / 255


def opaque_alpha(image):
    """Does an image's alpha cover every pixel (ImageData; False without an alpha)?"""
    alpha = image.alpha()
    return alpha is not None and float(np.min(alpha)) >= OPAQUE


def relief_guess(shape, name):
    """shadows.relief as `new` and Add start a normal map's painting (§6 "Relief"): where its
    alpha covers every pixel it cuts no figure out, so its shadows fall along the ray as a
    full-frame map's, said → (value, why); (None, '') for 'auto' to decide.

    >>> relief_guess(ImageData(np.ones((2, 2, 4))), "wall_n.png")[0]
    'along_ray'
    """
    if not opaque_alpha(shape):
        return None, ""
    return "along_ray", (f"{name}: its alpha covers every pixel and cuts no figure out, so "
                         f"its shadows fall along each ray, as a full-frame map's")


MASKS = {"transparency": ("transparency", "channel"), "gloss": ("specular", "gloss_channel")}


def mask_setting(p, channel):
    """The parameter that says how a mask channel (transparency, gloss) is read."""
    section, key = MASKS[channel]
    return getattr(getattr(p, section), key)


def mask_channels(images, p):
    """{mask channel: the channel it is read from}, decided on each whole image."""
    return {c: mask_channel(images[c].pixels, mask_setting(p, c)) for c in MASKS if c in images}


def mask_notes(masks, p):
    """What 'auto' made of the masks (`mask_channels`): a line for each read from one pure
    channel."""
    notes = [mask_note(f"{c} image", mask_setting(p, c), read) for c, read in masks.items()]
    return [note for note in notes if note]


def input_notes(images, p):
    """The checks of core/inputs.py on a painting's images (§14): what every command and the
    add-on's Add say about them, one line each. Raises ValueError (one line) for a shape image
    that cannot be what `p` says (a grey image read as a normal map).

    images: {channel: ImageData} (a mapping: only the shape, the masks and the per-pixel
    images' sizes and alphas are read); p: the parameters.
    """
    shape = images["shape"]
    name = shape.name or "shape image"
    notes = [note for c in images for note in images[c].notes]     # a file cut short, …
    if p.shape.kind == "normal":
        problem = normal_map_problem(shape.pixels, name, p.shape.encoding)
        if problem:
            raise ValueError(problem)
        notes += normal_map_notes(shape.pixels, name, p.shape.encoding, p.shape.strength)
        notes += green_notes(shape, p, name)
    notes += mask_notes(mask_channels(images, p), p)
    notes += [size_message(c, images[c].size, shape.size) for c in PER_PIXEL_CHANNELS
              if c in images and images[c].size != shape.size]
    if p.shape.kind == "normal" and p.shadows.enabled and p.shadows.relief == "auto" and \
            not shape.has_alpha:
        notes.append(f"{name}: no alpha, so its live shadows fall from its slopes along each "
                     f"ray (shadows.relief auto; final ones from either relief where its "
                     f"normals fit a height field); give it the figure's alpha to cut the "
                     f"figure out, or set shadows.relief = \"integrated\" "
                     f"(docs/relief-choice.md)")
    if p.shape.kind == "normal" and p.shadows.enabled and p.shadows.relief == "auto" and \
            opaque_alpha(shape):
        notes.append(f"{name}: its alpha covers every pixel, yet shadows.relief auto integrates "
                     f"it as a cut-out figure: set shadows.relief = \"along_ray\" for a "
                     f"full-frame map (docs/relief-choice.md)")
    if p.shape.kind == "normal" and p.shadows.enabled and \
            relief_of(p.shadows.relief, shape.has_alpha) == "along_ray":
        notes.append(reach_note(shape, p, name))
    return notes + albedo_notes(images, p) + silhouette_notes(images, p) + \
        see_through_notes(images, p)


def albedo_notes(images, p):
    """What §1 made of a painting of one colour image: lit as an albedo (its dark image
    derived), or flat where the artist set the ambient to 1."""
    albedo = albedo_channel(images)
    if not albedo:
        return []
    a, name = p.diffuse.ambient, images[albedo].name or f"{albedo} image"
    if a >= 1:
        return [f"{name}: the one colour image, drawn flat (diffuse.ambient = 1: the light "
                f"changes nothing)"]
    return [f"{name}: the one colour image, lit as an albedo: colour × ({a:g} + {1 - a:g} × "
            f"light) (diffuse.ambient = {a:g}; a dark image beside it is mixed with it instead)"]


def green_of(shape, p):
    """Both readings of a normal-map shape image (map_convention), from the one `p` gives."""
    return green_reading(shape.rgb(), shape.alpha(), p.shape.encoding, p.shape.strength,
                         p.shape.flip_green)


def green_notes(shape, p, name):
    """A normal map read the way it does not fit (§2): say which way it fits, with numbers."""
    reading = green_of(shape, p)
    if reading.flip == p.shape.flip_green:
        return []
    return [f"{reading.describe(name)}: set shape.flip_green = "
            f"{str(reading.flip).lower()} (read as it is, it is lit from below)"]


def normal_map_normals(shape, p, dtype=np.float32):
    """§2: a normal-map shape image (ImageData) decoded as the parameters say."""
    return decode_normal_map(shape.rgb().astype(dtype), p.shape.flip_green, p.shape.z_min,
                             p.shape.encoding, p.shape.strength, shape.alpha())


def reach_note(shape, p, name):
    """What §6 Reach does to a normal map's relief along the ray (core.shape.reach_of): the
    whole ray where its slopes fit a height field, shadows.reach where they do not."""
    curl = circulation(slopes_from_normals(normal_map_normals(shape, p)))
    if curl < CURL_LIMIT:
        return (f"{name}: its normals fit a height field (circulation {curl:.2f} per image "
                f"width, under {CURL_LIMIT:g}): its relief along each ray is felt the whole way")
    return (f"{name}: its normals fit no height field (an impossible figure: circulation "
            f"{curl:.2f} per image width, {CURL_LIMIT:g} or more), so its relief along each "
            f"ray is felt only shadows.reach = {p.shadows.reach:g} image widths: longer "
            f"would streak")


# A background image darker than this everywhere (99th percentile of its values) shows black
BLACK = 0.03


def see_through_notes(images, p):
    """What a see-through painting (§11: k > 0) likely did not mean: its glass shows a black
    (or no) background — a mirror drawn under the physical Fresnel, which reflects a few per
    cent facing the viewer (§10), or glass painted for a lighter k."""
    if transparency_branch(p.transparency.amount, "transparency" in images) == "none":
        return []
    background = images.get("background")
    if background is not None and np.percentile(background.rgb(), 99) > BLACK:
        return []
    behind = "no background image" if background is None else "a black background"
    if "environment" in images and p.fresnel.mode == "physical":
        return [f"the see-through parts show {behind} under the physical Fresnel (it reflects "
                f"the environment a few per cent facing the viewer): for a mirror set "
                f"fresnel.mode = \"art\" and fresnel.kappa = 1 (total reflection)"]
    return [f"the see-through parts (transparency {p.transparency.amount}) show {behind}: "
            f"give a background image, or set transparency.amount lower (0.3 lets the "
            f"painting show through)"]


def silhouette_notes(images, p):
    """A painting that shows glass or a background needs a silhouette (§11): without an alpha
    in the colour, shape or dark image (a JPEG has none) the whole canvas is the figure."""
    if p.silhouette.source == "none" or \
            silhouette_channel(p.silhouette.source, *image_channels(images)):
        return []
    glass = transparency_branch(p.transparency.amount, "transparency" in images) != "none"
    if not glass and "background" not in images:
        return []
    shows = "is glass" if glass else "hides the background"
    return [f"no alpha in the colour, shape or dark image (a JPEG has none): the whole canvas "
            f"{shows}; give the colour image the figure's alpha (PNG), or set silhouette.source = "
            f"\"none\" to keep the canvas whole"]


def pixel_role(channel, p):
    """How core/inputs.py replaces a channel's NaN/Inf pixels: the shape image by its kind
    ('normal' or 'height'), every other image as colour."""
    return p.shape.kind if channel == "shape" else "colour"


def finite_image(img, role, name):
    """`img` with NaN/Inf replaced by the rule of core/inputs.py → (ImageData, warning or '')."""
    clean, bad = finite_pixels(img.pixels, role)
    if not bad:
        return img, ""
    return ImageData(clean, img.bits, img.name), non_finite_message(name, bad)


def transparency_branch(amount, has_map):
    """§11, §12: whether the k branch exists and what drives it — 'none' (k ≡ 0, pruned),
    'param' (the slider, live) or 'map' (auto with a transparency map). An explicit 0 with
    no map prunes it; any other value keeps it (a slider may be dragged up). One rule for the
    core's passes and the graphs' features."""
    if amount == "auto":
        return "map" if has_map else "none"
    return "param" if amount > 0 or has_map else "none"


def albedo_channel(channels):
    """§1 (amended 2026-11-29): the painting's one colour image A, lit as an albedo
    (C_d = A·(a + (1 − a)·W)) — 'bright' or 'dark', whichever is the only one of the two given
    — or '' for a painting with both (the paper's barycentric mix of C0 and C1).

    >>> albedo_channel({"shape", "bright"}), albedo_channel({"shape", "dark", "bright"})
    ('bright', '')
    """
    given = [c for c in ("dark", "bright") if c in channels]
    return given[0] if len(given) == 1 else ""


# §1 silhouette.source → the channels whose alpha may cut the painting out, in order; "colour"
# is the one colour image A (albedo_channel): a sprite's alpha is its figure
SILHOUETTE_ORDER = {"auto": ("colour", "shape", "dark"), "shape": ("shape",), "dark": ("dark",),
                    "none": ()}


def silhouette_channel(source, channels, alpha_channels):
    """The channel whose alpha is the silhouette ('' for none), of the channels that have an
    image and those of them with an alpha. One rule for the core, the graphs and the add-on.

    >>> silhouette_channel("auto", {"shape", "bright"}, {"shape", "bright"})
    'bright'
    >>> silhouette_channel("auto", {"shape", "dark", "bright"}, {"shape", "bright"})
    'shape'
    """
    albedo = albedo_channel(channels)
    order = [albedo if c == "colour" else c for c in SILHOUETTE_ORDER[source]]
    return next((c for c in order if c and c in alpha_channels), "")


def image_channels(images):
    """(channels with an image, channels whose image has an alpha) of {channel: ImageData}:
    what silhouette_channel reads."""
    return set(images), {c for c, img in images.items() if img.has_alpha}


def resample_painting(images, width):
    """The painting at `width` pixels (render --width): the shape and every per-pixel image
    resampled so that the shape is `width` px wide.

    Environment and background are looked up by UV (§8, §9), so their size does not matter.
    """
    h0, w0 = images["shape"].pixels.shape[:2]
    height = max(1, round(h0 * width / w0))
    return {ch: ImageData(resample(img.pixels, height, width), img.bits, img.name, img.notes)
            if ch == "shape" or ch in PER_PIXEL_CHANNELS else img
            for ch, img in images.items()}
