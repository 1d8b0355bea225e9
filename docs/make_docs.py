"""Generate docs/parameters.md (every parameter, from params.py) and the pictures the docs and
README show, all rendered by the numpy core from the sample paintings.

    .venv/bin/python docs/make_docs.py          # ≈ 1 min on 2 cores

Pictures: docs/img/turntable.png (a light orbiting the portrait, six frames), and one
before/after pair per parameter where a picture says more than words (docs/img/params/).
"""
import copy
import math
import os
import sys

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(DOCS)
sys.path.insert(0, REPO)

from dynpaint_addon import params                       # noqa: E402
from dynpaint_addon.core.input_rules import resample_painting  # noqa: E402
from dynpaint_addon.core.lights import Light                 # noqa: E402
from dynpaint_addon.core.pipeline import render              # noqa: E402
from dynpaint_addon.inputs.imageio import write_png      # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe   # noqa: E402
from dynpaint_addon.inputs.samples import recipe_path               # noqa: E402

PX = 176          # width of a parameter picture
GAP = 4

# parameter → (sample, [(value, caption)…], optional overrides applied to both sides)
PICTURES = {
    "shape.height_scale": ("portrait", [(0.08, "0.08"), (0.33, "0.33 (the sample)")], {}),
    "diffuse.t0": ("portrait", [(0.0, "t0 = 0, t1 = 1 (classic)"), (0.45, "t0 = t1 = 0.45 (cartoon)")],
                   {"__pair__": "diffuse.t1"}),
    "diffuse.curve": ("portrait", [("linear", "linear"), ("smootherstep", "smootherstep")],
                      {"diffuse.t0": -0.4, "diffuse.t1": 0.9}),
    "shadows.enabled": ("portrait", [(False, "off (N·L only)"), (True, "on (cos-θ)")], {}),
    "shadows.offset": ("portrait", [(0.001, "d = 0.001"), (0.04, "d = 0.04 (translucent)")], {}),
    "shadows.quality": ("impossible", [("draft", "draft"), ("final", "final")], {}),
    "specular.s0": ("portrait", [(0.8, "s0 = 0.8"), (0.97, "s0 = 0.97")],
                    {"specular.amount": 1.0}),
    "reflection.distance": ("glass", [(0.05, "d_E = 0.05"), (0.6, "d_E = 0.6")],
                            {"fresnel.kappa": 0.8}),
    "reflection.blur": ("glass", [(0.0, "σ = 0"), (0.03, "σ = 0.03 (glossy)")],
                        {"fresnel.kappa": 0.8}),
    "refraction.ior": ("glass", [(1.1, "η = 1.1"), (1.9, "η = 1.9")], {"fresnel.kappa": -1.0}),
    "refraction.blur": ("glass", [(0.0, "σ = 0"), (0.02, "σ = 0.02 (frosted)")],
                        {"fresnel.kappa": -1.0}),
    "fresnel.mode": ("glass", [("physical", "physical (η = 1.5)"), ("art", "art-directed")], {}),
    "fresnel.kappa": ("glass", [(-1.0, "κ = −1 (all refraction)"), (1.0, "κ = +1 (all reflection)")],
                      {}),
    "transparency.amount": ("glass", [(0.0, "k = 0 (opaque paint)"), (0.9, "k = 0.9")], {}),
}


def _set(p, path, value):
    section, key = path.split(".")
    setattr(getattr(p, section), key, value)


_CACHE = {}


def sample_images(sample, width):
    key = (sample, width)
    if key not in _CACHE:
        recipe = load_recipe(recipe_path(sample))
        _CACHE[key] = (recipe, resample_painting(load_images(recipe), width))
    return _CACHE[key]


def side_by_side(images, gap=GAP):
    """Straight-alpha-composited RGB renders over white, in a row with a gap."""
    rows = []
    for rgba in images:
        rgb = rgba[..., :3] + (1 - rgba[..., 3:4])           # premultiplied over white
        rows.append(np.pad(rgb, ((0, 0), (0, gap), (0, 0)), constant_values=1.0))
    return np.concatenate(rows, 1)[:, :-gap]


def parameter_picture(path, sample, values, overrides):
    recipe, images = sample_images(sample, PX)
    renders = []
    for value, _ in values:
        p = copy.deepcopy(recipe.params)
        for k, v in overrides.items():
            if k != "__pair__":
                _set(p, k, v)
        _set(p, path, value)
        if "__pair__" in overrides:
            _set(p, overrides["__pair__"], 1.0 if value == 0.0 else value)
        renders.append(render(images, recipe.lights, p).rgba)
    return side_by_side(renders)


def turntable_strip(sample="portrait", frames=6, width=224):
    """A key light orbiting the sample, `frames` frames of one turn (numpy core)."""
    recipe, images = sample_images(sample, width)
    key = next(lt for lt in recipe.lights if lt.kind == "sun")
    x, y, z = key.vector
    elev, az = math.asin(z / math.sqrt(x * x + y * y + z * z)), math.atan2(y, x)
    out = []
    for i in range(frames):
        a = az + 2 * math.pi * i / frames
        sun = Light("sun", (math.cos(elev) * math.cos(a), math.cos(elev) * math.sin(a),
                            math.sin(elev)), key.colour, key.strength, key.name)
        lights = [sun if lt is key else lt for lt in recipe.lights]
        out.append(render(images, lights, recipe.params).rgba)
    return side_by_side(out)


def _srgb(rgb):
    from dynpaint_addon.core.colour import linear_to_srgb
    return linear_to_srgb(np.clip(rgb, 0, 1))


def _entry(prm):
    """One parameter's heading, help and facts."""
    rng = f" · range {prm.min:g} … {prm.max:g}" if prm.min is not None else ""
    choices = f" · one of {', '.join(f'`{c}`' for c in prm.choices)}" if prm.choices else ""
    unit = f" · unit: {prm.unit}" if prm.unit else ""
    return [f"### `{prm.path}`", "", f"{prm.help}.", "",
            f"default `{prm.default!r}`{unit}{rng}{choices} · {prm.spec}", ""]


def parameters_page(pictures):
    lines = ["# Every parameter",
             "",
             "Generated by `docs/make_docs.py` from `dynpaint_addon/params.py` (the one table the "
             "recipe reader, the command line and the Blender properties are made from). Lengths "
             "are in **image widths**: 0.05 on a 2000-pixel painting is 100 pixels, and stays the "
             "same fraction when the painting is resized. § numbers point to `pipeline.md`. "
             "Pictures are rendered by the numpy core from the samples (`sample_scenes/`); left "
             "and right differ only in the parameter named.",
             "",
             "In Blender each parameter is a property of the material's *Dynamic Painting* panel "
             "with this text as its tooltip; in a recipe it is `section.key` (`[shadows]` "
             "`offset = 0.02`).", ""]
    section = None
    for prm in params.PARAMS:
        if prm.section != section:
            section = prm.section
            lines += [f"## {section}", ""]
        lines += _entry(prm)
        if prm.path in pictures:
            file, captions = pictures[prm.path]
            lines += [f"![{prm.path}: {' vs '.join(captions)}](img/params/{file})", "",
                      f"*Left: {captions[0]}. Right: {captions[1]}.*", ""]
    lines += ["## Images", "", "| recipe key | what it is | colour or data |", "|---|---|---|"]
    lines += [f"| `{ch}` | {what} | {space} |" for ch, (what, space) in params.CHANNELS.items()]
    lines += ["", "A frame-numbered file name (`walk_####.png`, Blender's convention, or "
              "`walk_%04d.png`) is a sequence: the painting moves ([frames.md](frames.md)).",
              "", "## frames", "",
              "A painting that moves (§16): how its image sequences and sprite sheets follow "
              "the scene's frames. `[frames]` is the painting's mapping; `[frames.<channel>]` "
              "(`[frames.dark]`, …) gives one image a mapping of its own. In Blender: *Dynamic "
              "Painting › Frames*.", ""]
    for prm in params.FRAME_PARAMS:
        lines += _entry(prm)
    lines += ["", "## Lights", "",
              "Every Sun and Point light in the scene, or in the painting's Lights collection "
              "(a painting added from a recipe is lit by the recipe's lights, put in a "
              "collection of their own; empty the field to light it with every light). "
              "A Sun's *Strength* is k (§5) and only its direction counts; a Point light's "
              "*Power* / 1000 W is k (Blender's default point light gives k = 1) and its "
              "position counts, in image widths from the painting's centre. Light colour tints "
              "(linear). In a recipe: `[[lights]]` with `type`, `direction` or `position`, "
              "`color`, `strength`, `name`.", ""]
    return "\n".join(lines) + "\n"


def picture_index():
    """parameter → (picture file in img/params/, captions): what parameters.md links."""
    return {path: (path.replace(".", "_") + ".png", [c for _, c in values])
            for path, (_, values, _) in PICTURES.items()}


def main():
    os.makedirs(os.path.join(DOCS, "img", "params"), exist_ok=True)
    pictures = picture_index()
    for path, (sample, values, overrides) in PICTURES.items():
        rgb = parameter_picture(path, sample, values, overrides)
        write_png(os.path.join(DOCS, "img", "params", pictures[path][0]), _srgb(rgb), bits=8)
        print(f"{path}: img/params/{pictures[path][0]}", flush=True)
    write_png(os.path.join(DOCS, "img", "turntable.png"), _srgb(turntable_strip()), bits=8)
    with open(os.path.join(DOCS, "parameters.md"), "w", encoding="utf-8") as fh:
        fh.write(parameters_page(pictures))
    print("wrote docs/parameters.md, docs/img/turntable.png")


if __name__ == "__main__":
    main()
