"""A small built-in test painting, made by code (no files to ship): the README's demo and tests.

A height map with a dome, a box and a ridge; a cool painterly dark image and a warm bright one.
"""
import os

import numpy as np

from .. import params
from ..core.colour import linear_to_srgb
from ..core.input_rules import ImageData
from ..core.lights import Light
from .imageio import write_png
from .recipe import Recipe, RecipeLayer, recipe_to_toml
from .whole_files import write_text_whole


def _strokes(x, y, seed):
    """Deterministic brush-stroke-like variation in [-1, 1] (float32) at pixel centres x (1, W)
    and y (H, 1), in image widths: six waves sin(fx·x + θ(y)), θ(y) = fy·y + φ + 2 sin(3y + φ).
    Each is sin(fx·x)·cos θ + cos(fx·x)·sin θ, so the image is one (H, 12) × (12, W) product:
    no sine per pixel (an 8192² painting's cost is writing its files)."""
    rng = np.random.default_rng(seed)
    across, down = [], []
    for _ in range(6):
        a, fx, fy, ph = rng.uniform(0.2, 1), rng.uniform(5, 25), rng.uniform(2, 9), rng.uniform(0, 6.3)
        theta = fy * y[:, 0] + ph + 2 * np.sin(3 * y[:, 0] + ph)
        down += [a * np.cos(theta), a * np.sin(theta)]
        across += [np.sin(fx * x[0]), np.cos(fx * x[0])]
    v = np.stack(down, 1).astype(np.float32) @ np.stack(across).astype(np.float32)
    v /= np.max(np.abs(v))
    return v


def _centres(h, w):
    """Pixel centres x (1, W) and y (H, 1) in image widths (y up)."""
    return (np.arange(w)[None, :] + 0.5) / w, (np.arange(h)[:, None] + 0.5) / w


def _encoded(channels):
    """8-bit sRGB of linear colour channels (each H × W): what a painter's PNG holds."""
    out = np.empty(channels[0].shape + (len(channels),), np.float32)
    for i, c in enumerate(channels):
        out[..., i] = np.round(linear_to_srgb(np.clip(c, 0, 1).astype(np.float32)) * 255) / 255
    return out


def builtin_images(size=256):
    """{channel: ImageData} with y-up arrays: 16-bit height, 8-bit sRGB dark and bright."""
    w = h = int(size)
    x, y = _centres(h, w)
    height = (x - 0.36) ** 2 + (y - 0.56) ** 2             # the dome's r² · 0.22²
    np.sqrt(np.clip(1 - height / 0.22 ** 2, 0, 1), out=height)
    box = (np.abs(x - 0.74) < 0.1) & (np.abs(y - 0.3) < 0.14)
    np.maximum(height, box * 0.55, out=height)
    left = int(np.searchsorted(x[0], 0.55))                # the ridge: x < 0.55
    ridge = 0.35 * np.exp(-((y - 0.15 - 0.25 * x[:, :left]) / 0.03) ** 2)
    np.maximum(height[:, :left], ridge, out=height[:, :left])
    height = np.round(np.clip(height, 0, 1) * 65535) / 65535
    s1, s2 = _strokes(x, y, 1), _strokes(x, y, 2)
    dark = _encoded([0.10 + 0.03 * s1, 0.09 + 0.02 * s2, 0.22 + 0.05 * s1])
    bright = _encoded([0.95 + 0.04 * s2, 0.72 + 0.06 * s1, 0.42 + 0.05 * s2])
    return {"shape": ImageData(height.astype(np.float32), 16, "height.png"),
            "dark": ImageData(dark, 8, "dark.png"),
            "bright": ImageData(bright, 8, "bright.png")}


def builtin_recipe():
    """Parameters and lights of the test painting (images not attached)."""
    p = params.defaults()
    p.shape.kind = "height"
    p.shape.height_scale = 0.25
    p.shadows.enabled = True
    p.shadows.offset = 0.01
    p.specular.enabled = True
    p.specular.s0 = 0.92
    lights = [Light("sun", (-0.6, 0.5, 0.45), (1.0, 0.92, 0.8), 1.0, "Key"),
              Light("point", (0.45, -0.1, 0.35), (0.45, 0.55, 1.0), 0.25, "Fill")]
    return Recipe(p, lights, {}, "Built-in test painting")


def builtin_painting_files():
    """The names write_test_painting writes into its folder: its recipe and its images."""
    return ("painting.toml", *(img.name for img in builtin_images(2).values()))


def write_test_painting(folder, size=256):
    """Write the test painting's images and painting.toml into folder → the recipe's path."""
    os.makedirs(folder, exist_ok=True)
    recipe = builtin_recipe()
    for channel, img in builtin_images(size).items():
        path = os.path.join(folder, img.name)
        write_png(path, img.pixels, bits=img.bits)
        recipe.images[channel] = os.path.abspath(path)
    path = os.path.join(folder, "painting.toml")
    write_text_whole(path, recipe_to_toml(recipe, folder))
    return path


def _cutout(inside, colour, seed, x, y):
    """An 8-bit sRGB RGBA image of one painted colour with stroke variation, alpha = inside."""
    s = 1 + 0.08 * _strokes(x, y, seed)
    return np.dstack([_encoded([c * s for c in colour]), inside.astype(np.float32)])


def builtin_scene_layers(size=128):
    """The layers of a small scene made by code (§15), back to front → [(name, depth,
    {channel: ImageData}, p)]: the test painting behind, a flat ring card in the middle and
    a star with a dome's relief in front, both cut out by their dark image's alpha."""
    w = h = int(size)
    x, y = _centres(h, w)
    r = np.hypot(x - 0.62, y - 0.6)
    ring = (r > 0.12) & (r < 0.2)
    ang = np.arctan2(y - 0.35, x - 0.35)
    star_r = 0.13 + 0.06 * np.cos(5 * ang)
    rs = np.hypot(x - 0.35, y - 0.35)
    star = rs < star_r
    dome = np.sqrt(np.clip(1 - (rs / 0.16) ** 2, 0, 1)) * star
    back_p = builtin_recipe().params
    card_p = params.defaults()
    card_p.shape.kind = "height"
    card_p.shadows.enabled = True
    star_p = params.defaults()
    star_p.shape.kind = "height"
    star_p.shape.height_scale = 0.06
    star_p.shadows.enabled = True
    flat = ImageData(np.zeros((h, w), np.float32), 16, "flat.png")
    grey = lambda c, name: ImageData(_cutout(np.ones((h, w), bool), c, 3, x, y)[..., :3], 8,
                                     name)
    return [("back", 0.0, builtin_images(size), back_p),
            ("ring", 0.12, {"shape": flat,
                            "dark": ImageData(_cutout(ring, (0.08, 0.2, 0.12), 4, x, y), 8,
                                              "ring_dark.png"),
                            "bright": grey((0.3, 0.85, 0.45), "ring_bright.png")}, card_p),
            ("star", 0.25, {"shape": ImageData(np.round(dome * 65535).astype(np.float32)
                                               / 65535, 16, "star_height.png"),
                            "dark": ImageData(_cutout(star, (0.25, 0.05, 0.05), 5, x, y), 8,
                                              "star_dark.png"),
                            "bright": grey((1.0, 0.35, 0.25), "star_bright.png")}, star_p)]


def write_test_scene(folder, size=128):
    """Write the test scene's images and a layered painting.toml into folder → its path."""
    os.makedirs(folder, exist_ok=True)
    layers = []
    for name, depth, images, p in builtin_scene_layers(size):
        paths = {}
        for channel, img in images.items():
            path = os.path.join(folder, img.name)
            write_png(path, img.pixels, bits=img.bits)
            paths[channel] = os.path.abspath(path)
        layers.append(RecipeLayer(Recipe(p, [], paths, name), name, depth))
    recipe = Recipe(params.defaults(), [Light("sun", (0.55, 0.35, 0.76), name="Key")], {},
                    "Built-in layered test scene", layers=layers)
    path = os.path.join(folder, "scene.toml")
    write_text_whole(path, recipe_to_toml(recipe, folder))
    return path
