"""The built-in test painting built in Blender as Add builds it, lit by its sun alone (or its
sun and its point light), and its shape image's pixels to paint into: what the stroke
benchmark (benchmarks/paint_latency.py) and the tests of edits, live bakes and Paint Shape
start from."""
import numpy as np

import bpy

from dynpaint_addon.blender import headless
from dynpaint_addon.inputs.recipe import load_recipe
from dynpaint_addon.inputs.testpainting import write_test_painting


def sun_painting(folder, size, kinds=("sun",), quality=None):
    """The test painting at size² in `folder`, built, its plane active → the material.
    kinds: which of its lights it keeps (its sun; ("sun", "point"): its point light too);
    quality: its shadows' level (default: the recipe's)."""
    recipe = load_recipe(write_test_painting(str(folder), size))
    recipe.lights = [light for light in recipe.lights if light.kind in kinds]
    if quality is not None:
        recipe.params.shadows.quality = quality
    _, mat = headless.build_recipe_scene(recipe)
    bpy.context.view_layer.objects.active = mat.dynamic_painting.plane
    return mat


def image_pixels(img):
    """An image's pixels (H, W, C), y up, to edit and write back with foreach_set."""
    w, h = img.size
    px = np.empty((h, w, img.channels), np.float32)
    img.pixels.foreach_get(px.ravel())
    return px
