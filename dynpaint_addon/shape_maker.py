"""Make a painting's shape image from what the artist has (docs/shape-from-painting.md).

The glue between image files (core.pipeline.ImageData) and the numpy methods: the command
line (`make-shape`) and the add-on's Make Shape operator both call these, so a method reads
its inputs the same way everywhere. No bpy here.

Methods: integrate (normal map → height), normals (height → normal map, §2), profiles
(lighting profiles → normal map), rg-photo (red/green photograph → normal map), inflate
(silhouette → height). Heights are in image widths; normal maps are unit vectors, y up.
"""
import os
import re

import numpy as np

from .core.colour import srgb_to_linear
from .core.inputs import mask_values
from .core.photometric import SIDES
from .core.shape import (decode_normal_map, height_field_px, normals_from_height_px,
                         preblurred_height)

GREENS = ("opengl", "directx")


class ShapeError(ValueError):
    """A make-shape input that cannot be used; the message says what to change."""


def linear_luminance(img):
    """Rec.709 luminance of an image's linear light (8/16-bit files are sRGB, floats linear)."""
    rgb = np.asarray(img.rgb(), np.float64)
    if img.bits != 32:
        rgb = srgb_to_linear(rgb)
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def figure_mask(img, channel="auto"):
    """Where the figure is (H, W) bool: the image's alpha when it has one that is not all
    opaque, else the mask read from `channel` (core.inputs.mask_values) above ½."""
    alpha = img.alpha()
    if channel == "auto" and alpha is not None and np.nanmin(alpha) < 0.5:
        return np.nan_to_num(alpha) >= 0.5
    values, _ = mask_values(img.pixels, channel)
    return np.nan_to_num(values) >= 0.5


def decode_normals(img, encoding="auto", flip_green=False, strength=1.0):
    """A normal-map image → unit normals (§2: its encoding, DirectX green, tilt strength)."""
    return decode_normal_map(np.asarray(img.rgb(), np.float64), flip_green, 0.001, encoding,
                             strength)


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


def sprite_lamp_side(path):
    """The lighting side a file's name says in Sprite Lamp's convention (portrait_left.png,
    'Top', 'front'…), or None."""
    stem = os.path.splitext(os.path.basename(path))[0].lower()
    match = re.search(r"(?:^|[_\-. ])(" + "|".join(SIDES) + r")$", stem)
    return match.group(1) if match else None


def same_size(images, what):
    """Refuse images of different sizes (they must show the same subject pixel for pixel)."""
    sizes = {name: img.size for name, img in images.items()}
    if len(set(sizes.values())) > 1:
        listed = ", ".join(f"{name} {w}×{h}" for name, (w, h) in sizes.items())
        raise ShapeError(f"{what} must all be the same size: {listed}")

