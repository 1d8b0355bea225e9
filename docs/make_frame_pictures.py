"""Generate the pictures of docs/frames.md: a painting that moves (pipeline.md §16, issue 31).
The animated sample (sample_scenes/blink) drawn by the numpy core at six frames of its
turntable — the head turns and blinks while the key light goes round once over 48 frames, as
*Add › Dynamic Painting › Blink* sets the scene up.

    .venv/bin/python docs/make_frame_pictures.py        # ≈ 3 s
"""
import math
import os
import sys

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(DOCS))
sys.path.insert(0, DOCS)

from make_docs import side_by_side  # noqa: E402

from dynpaint_addon.core.colour import linear_to_srgb  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.pipeline import render  # noqa: E402
from dynpaint_addon.inputs.imageio import write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe  # noqa: E402

FRAMES = (1, 9, 17, 25, 33, 41)
LOOP = 48           # the sample's scene: its 24 frames twice, the light once round


def turning(light, f):
    """The key sun turned about the painting's normal as the light turntable turns it."""
    x, y, z = light.vector
    a = 2 * math.pi * (f - 1) / LOOP
    return Light("sun", (x * math.cos(a) - y * math.sin(a), x * math.sin(a) + y * math.cos(a),
                         z), light.colour, light.strength, light.name)


def frames_strip():
    recipe = load_recipe("blink")
    shown = []
    for f in FRAMES:
        rgba = render(load_images(recipe, f), [turning(lt, f) for lt in recipe.lights],
                      recipe.params).rgba
        a = rgba[..., 3:4]
        straight = np.where(a > 0, rgba[..., :3] / np.where(a > 0, a, 1), 0)
        shown.append(np.dstack([linear_to_srgb(np.clip(straight, 0, 1)) * a, a]))
    return side_by_side(shown)


def main(out=DOCS):
    folder = os.path.join(out, "img", "frames")
    os.makedirs(folder, exist_ok=True)
    write_png(os.path.join(folder, "blink_frames.png"), frames_strip(), bits=8)
    print(f"wrote {folder}/blink_frames.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else DOCS)
