"""A small built-in test painting, made by code (no files to ship): the README's demo and tests.

A height map with a dome, a box and a ridge; a cool painterly dark image and a warm bright one.
"""
import os

import numpy as np

from . import params
from .core.colour import linear_to_srgb
from .core.lights import Light
from .core.input_rules import ImageData
from .imageio import write_png
from .recipe import Recipe, recipe_to_toml


def _strokes(x, y, seed):
    """Deterministic brush-stroke-like variation in [-1, 1]."""
    rng = np.random.default_rng(seed)
    v = np.zeros_like(x)
    for _ in range(6):
        a, fx, fy, ph = rng.uniform(0.2, 1), rng.uniform(5, 25), rng.uniform(2, 9), rng.uniform(0, 6.3)
        v += a * np.sin(fx * x + fy * y + ph + 2 * np.sin(3 * y + ph))
    return v / np.max(np.abs(v))


def builtin_images(size=256):
    """{channel: ImageData} with y-up arrays: 16-bit height, 8-bit sRGB dark and bright."""
    w = h = int(size)
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    x = (x + 0.5) / w
    y = (y + 0.5) / w
    r2 = ((x - 0.36) ** 2 + (y - 0.56) ** 2) / 0.22 ** 2
    dome = np.sqrt(np.clip(1 - r2, 0, 1))
    box = ((np.abs(x - 0.74) < 0.1) & (np.abs(y - 0.3) < 0.14)) * 0.55
    ridge = 0.35 * np.exp(-((y - 0.15 - 0.25 * x) / 0.03) ** 2) * (x < 0.55)
    height = np.clip(np.maximum(np.maximum(dome, box), ridge), 0, 1)
    height = np.round(height * 65535) / 65535
    s1, s2 = _strokes(x, y, 1), _strokes(x, y, 2)
    dark = np.stack([0.10 + 0.03 * s1, 0.09 + 0.02 * s2, 0.22 + 0.05 * s1], -1)
    bright = np.stack([0.95 + 0.04 * s2, 0.72 + 0.06 * s1, 0.42 + 0.05 * s2], -1)
    enc = lambda c: np.round(linear_to_srgb(np.clip(c, 0, 1)) * 255) / 255
    return {"shape": ImageData(height.astype(np.float32), 16, "height.png"),
            "dark": ImageData(enc(dark).astype(np.float32), 8, "dark.png"),
            "bright": ImageData(enc(bright).astype(np.float32), 8, "bright.png")}


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


def write_test_painting(folder, size=256):
    """Write the test painting's images and painting.toml into folder → the recipe's path."""
    os.makedirs(folder, exist_ok=True)
    recipe = builtin_recipe()
    for channel, img in builtin_images(size).items():
        path = os.path.join(folder, img.name)
        write_png(path, img.pixels, bits=img.bits)
        recipe.images[channel] = os.path.abspath(path)
    path = os.path.join(folder, "painting.toml")
    with open(path, "w") as fh:
        fh.write(recipe_to_toml(recipe, folder))
    return path
