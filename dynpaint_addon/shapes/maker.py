"""Make a painting's shape image from what the artist has (docs/shape-from-painting.md).

The glue between image files (core.input_rules.ImageData) and the numpy methods: the command
line (`make-shape`) and the add-on's Make Shape operator both call these, so a method reads
its inputs the same way everywhere. No bpy here.

Methods: integrate (normal map → height), normals (height → normal map, §2), profiles
(lighting profiles → normal map), rg-photo (red/green photograph → normal map), inflate
(silhouette → height). Heights are in image widths; normal maps are unit vectors, y up.
"""

import numpy as np

from ..core.colour import srgb_to_linear
from ..core.inputs import mask_values
from ..core.integrate import integrate
from ..core.photometric import normals_from_profiles, normals_from_rg_photo
from ..core.sampling import resample
from ..core.shape import (decode_normal_map, default_preblur_px, height_field_px,
                         normals_from_height_px, preblurred_height)
from ..errors import UserError
from .relief import reads_painting, snapped_relief

GREENS = ("opengl", "directx")


class ShapeError(UserError):
    """A make-shape input that cannot be used; the message says what to change."""


def looks_like_height(img):
    """Whether a shape image (ImageData) is a height map: grey (R = G = B), else a normal map
    (Add › From Images' Detect, layered files)."""
    px = img.pixels
    if px.shape[2] < 3:
        return True
    return bool(np.allclose(px[..., 0], px[..., 1], atol=2e-3)
                and np.allclose(px[..., 1], px[..., 2], atol=2e-3))


def linear_luminance(img):
    """Rec.709 luminance of an image's linear light (8/16-bit files are sRGB, floats linear)."""
    rgb = np.asarray(img.rgb(), np.float64)
    if img.bits != 32:
        rgb = srgb_to_linear(rgb)
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def figure_mask(img, channel="auto"):
    """Where the figure is (H, W) bool: the image's alpha when it has one that is not all
    opaque, else the mask read from `channel` (core.inputs.mask_values) above ½."""
    return figure_and_source(img, channel)[0]


def figure_and_source(img, channel="auto"):
    """(figure_mask, what it was read from: 'alpha', 'luminance', 'red', …): the guess a
    command says."""
    alpha = img.alpha()
    if channel == "auto" and alpha is not None and np.nanmin(alpha) < 0.5:
        return np.nan_to_num(alpha) >= 0.5, "alpha"
    values, read = mask_values(img.pixels, channel)
    return np.nan_to_num(values) >= 0.5, read


def decode_normals(img, encoding="auto", flip_green=False, strength=1.0):
    """A normal-map image → unit normals (§2: its encoding, DirectX green, tilt strength)."""
    return decode_normal_map(np.asarray(img.rgb(), np.float64), flip_green, 0.001, encoding,
                             strength, img.alpha())


def encode_normals(n, green="opengl"):
    """Unit normals → normal-map colours 0..1 (x, y, z → red, green, blue; DirectX stores −y)."""
    if green not in GREENS:
        raise ShapeError(f"green must be one of {', '.join(GREENS)}, got {green!r}")
    n = np.asarray(n, np.float64)
    if green == "directx":
        n = n * np.array([1, -1, 1])
    return np.clip((n + 1) / 2, 0, 1)


def height_widths(img, height_scale, preblur_px=0.0):
    """A height-map image → heights in image widths (§2: grey × height scale, pre-blurred σ
    pixels first)."""
    return preblurred_height(np.asarray(img.grey(), np.float64), preblur_px) * height_scale


def normals_of_height(height, z_min=0.001):
    """§2: the normals of a height field given in image widths."""
    h = np.asarray(height, np.float64)
    return normals_from_height_px(height_field_px(h, 1.0), z_min)


def same_size(images, what):
    """Refuse images of different sizes (they must show the same subject pixel for pixel)."""
    sizes = {name: img.size for name, img in images.items()}
    if len(set(sizes.values())) > 1:
        listed = ", ".join(f"{name} {w}×{h}" for name, (w, h) in sizes.items())
        raise ShapeError(f"{what} must all be the same size: {listed}")



# How the painting reads a shape image make_shape made (§2): heights in image widths, float
# (no pre-blur); normal maps in the standard RGB convention.
SHAPE_READS = {"height": {"kind": "height", "height_scale": 1.0, "preblur": "auto"},
               "normal": {"kind": "normal", "encoding": "rgb", "strength": 1.0,
                          "flip_green": False}}


def read_as_made(p, kind):
    """Set p's §2 shape settings to read a made shape image of `kind` (SHAPE_READS)."""
    for key, value in SHAPE_READS[kind].items():
        setattr(p.shape, key, value)
    return p


def _silhouette(images):
    """The figure of a painting: the alpha of its shape, dark or bright image (the first that
    has a transparent part) → (channel, alpha), or a ShapeError saying what to give."""
    for channel in ("shape", "dark", "bright"):
        img = images.get(channel)
        alpha = img.alpha() if img is not None else None
        if alpha is not None and np.nanmin(alpha) < 0.5 and np.nanmax(alpha) >= 0.5:
            return channel, np.nan_to_num(alpha)
    raise ShapeError("no silhouette to inflate: none of the shape, dark or bright images has a "
                     "transparent background (alpha); paint one, or use make-shape inflate "
                     "with a mask image")


def at_size(pixels, size):
    """Pixels (H, W[, C]) resampled to a painting's (W, H) when they differ."""
    w, h = size
    return pixels if pixels.shape[:2] == (h, w) else resample(pixels, h, w)


def _with_alpha(values, alpha):
    """Heights (H, W) or normal-map colours (H, W, 3) as RGBA, with `alpha` where it fits
    the result, else opaque."""
    h, w = values.shape[:2]
    if alpha is None or alpha.shape != (h, w):
        alpha = np.ones((h, w))
    rgb = np.repeat(values[..., None], 3, axis=2) if values.ndim == 2 else values
    return np.concatenate([rgb, np.asarray(alpha)[..., None]], axis=2)


def _shape_alpha(images):
    shape = images.get("shape")
    return shape.alpha() if shape is not None else None


# Each method: (images, p, its options) → (kind, RGBA pixels, report lines). Its options
# and their defaults are in shapes.methods.OPTIONS; shapes.methods.make_shape calls them.
def inflate_silhouette(images, p, **values):
    """inflate: the painting's silhouette (the alpha of its shape, dark or bright image) made
    a relief with the inflate options `values` (shapes/relief.py: snapped onto the painting's
    edges, inflated, its luminance embossed, a bevel and a smoothing)."""
    channel, alpha = _silhouette(images)
    painting = images.get("bright") or images.get("dark")
    lum = linear_luminance(painting) if reads_painting(values) and painting is not None else None
    if lum is not None and lum.shape != alpha.shape:
        raise ShapeError("the painting and its silhouette differ in size: resample one")
    heights = snapped_relief(alpha >= 0.5, lum, None, values)
    return "height", _with_alpha(heights, alpha), [
        f"inflated the {channel} image's silhouette ({values['profile']}), highest point "
        f"{heights.max():.3g} image widths"]


def integrate_normal_map(images, p, use_mask, depth, floor=None):
    """integrate: the normal map (read as p's §2 settings say) integrated into heights by least
    squares (core.integrate), cut at its alpha when `use_mask`, the rim `depth` up; floor: the
    height made 0 (None: the lowest; the frames of a painting that moves take one, §16)."""
    shape = images.get("shape")
    if shape is None or p.shape.kind != "normal":
        raise ShapeError("Height from Normal Map needs a normal map as the shape image")
    n = decode_normals(shape, p.shape.encoding, p.shape.flip_green, p.shape.strength)
    mask = figure_mask(shape, "alpha") if use_mask else None    # no alpha: all figure
    result = integrate(n, mask, depth, floor=floor)
    values = result.height
    return "height", _with_alpha(values, shape.alpha()), [
        f"integrated the normal map: relief {values.max():.3g} image widths; "
        f"{100 * result.residual_share:.1f} % of it no height map can hold "
        f"(painted or impossible parts)"]


def normal_map_of_height(images, p):
    """normals: the height map's normals (§2, with p's height scale and pre-blur)."""
    shape = images.get("shape")
    if shape is None or p.shape.kind != "height":
        raise ShapeError("Normal Map from Height needs a height map as the shape image")
    blur = p.shape.preblur if p.shape.preblur != "auto" else default_preblur_px(shape.bits)
    values = encode_normals(normals_of_height(height_widths(shape, p.shape.height_scale,
                                                            float(blur))))
    return "normal", _with_alpha(values, shape.alpha()), ["made the height map's normal map"]


def _painting_size(images):
    return (images.get("shape") or images.get("bright") or images.get("dark")).size


def normal_map_from_profiles(images, p, profiles, elevation):
    """profiles: normals solved from two to five pictures lit from the sides ({side:
    ImageData}, resampled to the painting's size; core.photometric)."""
    size = _painting_size(images)
    given = {side: img for side, img in (profiles or {}).items() if img is not None}
    if len(given) < 2:
        raise ShapeError("Lighting Profiles: give at least two pictures (left, right, "
                         "top, bottom, front)")
    n = normals_from_profiles({side: at_size(linear_luminance(img), size)
                               for side, img in given.items()}, elevation)
    return "normal", _with_alpha(encode_normals(n), _shape_alpha(images)), [
        f"solved {len(given)} lighting profiles ({', '.join(given)})"]


def normal_map_from_rg_photo(images, p, photo, red_from, green_from):
    """rg_photo: normals decoded from a photograph lit red from one side and green from the
    top or bottom (core.photometric)."""
    if photo is None:
        raise ShapeError("Red/Green Photo: give the photograph")
    n = normals_from_rg_photo(at_size(np.asarray(photo.rgb(), np.float64), _painting_size(images)),
                              red_from, green_from)
    return "normal", _with_alpha(encode_normals(n), _shape_alpha(images)), [
        "decoded the red/green photograph"]
