"""Generate docs/real-paintings.md: before/after pictures of issue 15's points 1, 2, 4, 5 and 7
on example paintings made in other tools' conventions (testkit/example_paintings.py),
all rendered by the numpy core. "Before" is what the add-on did until 2026-11-23, reproduced
with today's settings (encoding rgb, strength 1, luminance masks, no placement and wrap, reach
over the whole image, linear mixing).

    .venv/bin/python docs/make_real_paintings.py        # ≈ 10 s
"""
import os
import sys

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(DOCS))

from testkit import example_paintings as ex            # noqa: E402
from dynpaint_addon import params                             # noqa: E402
from dynpaint_addon.core.colour import linear_to_srgb         # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.lights import Light                  # noqa: E402
from dynpaint_addon.core.pipeline import render  # noqa: E402
from dynpaint_addon.core.shading import barycentric_mix       # noqa: E402
from dynpaint_addon.inputs.imageio import write_png                  # noqa: E402

PX = 200
GAP = 4
SUN = Light("sun", (-0.55, 0.45, 0.7), (1.0, 0.97, 0.9), 1.0, "Key")


def _const(rgb, size=PX):
    return ImageData(np.broadcast_to(np.asarray(rgb, np.float32), (size, size, 3)).copy(), 8)


def _shade(images, lights=(SUN,), **settings):
    p = params.defaults()
    for path, value in settings.items():
        section, key = path.split("__")
        setattr(getattr(p, section), key, value)
    out = render(images, list(lights), p)
    return out.rgba, out.warnings


def _row(renders):
    tiles = [np.pad(linear_to_srgb(np.clip(r[..., :3] + (1 - r[..., 3:4]), 0, 1)),
                    ((0, 0), (0, GAP), (0, 0)), constant_values=1.0) for r in renders]
    return np.concatenate(tiles, 1)[:, :-GAP]


def _save(out, name, renders):
    """Write the renders side by side as img/real/<name> under `out` → its Markdown link."""
    write_png(os.path.join(out, "img", "real", name), _row(renders), bits=8)
    return f"![{name}](img/real/{name})"


PAINT = {"dark": _const((0.16, 0.12, 0.22)), "bright": _const((0.95, 0.82, 0.55))}


def normal_conventions():
    """Point 1: a two-channel (rg) map and a map painted for a tilt-halving decoder."""
    n, _ = ex.sphere(PX, 0.42)
    rg = ImageData(ex.normal_map_rg(n).astype(np.float32), 16)
    halving = ImageData(ex.normal_map_halving(n).astype(np.float32), 16)
    pics = [_shade({**PAINT, "shape": rg})[0],
            _shade({**PAINT, "shape": halving}, shape__strength=1.0)[0],
            _shade({**PAINT, "shape": halving})[0],
            _shade({**PAINT, "shape": ImageData(ex.normal_map_rgb(n).astype(np.float32), 16)})[0]]
    return pics


def glass_sphere(mask_rgb, env, **settings):
    n, inside = ex.sphere(PX, 0.36)
    images = {**PAINT, "shape": ImageData(ex.normal_map_rgb(n).astype(np.float32), 16),
              "transparency": ImageData(mask_rgb(inside).astype(np.float32), 8),
              "environment": ImageData(env.astype(np.float32), 8)}
    return _shade(images, **settings)


def red_mask():
    """Point 2: a mirror sphere whose transparency is painted pure red on black."""
    env = ex.photograph(PX, PX, seed=3)
    before, _ = glass_sphere(ex.red_mask, env, transparency__channel="luminance",
                             reflection__distance=0.2)
    after, warnings = glass_sphere(ex.red_mask, env, reflection__distance=0.2)
    return [before, after], warnings


def placement():
    """Point 4: a photograph reflected far (lookups beyond its edges), then placed."""
    env = ex.photograph(PX // 2, PX, seed=5)
    grey = lambda m: np.repeat(m[..., None].astype(float), 3, -1)     # noqa: E731
    kw = dict(reflection__distance=0.6, reflection__max_offset=1.2)
    before, _ = glass_sphere(grey, env, reflection__extension="wrap", **kw)
    mirrored, _ = glass_sphere(grey, env, **kw)
    placed, _ = glass_sphere(grey, env, reflection__offset=(0.0, 0.15),
                             reflection__scale=1.6, **kw)
    return [before, mirrored, placed]


def penrose():
    """Point 5: cos-θ shadows of a Penrose tribar drawn as flat facets."""
    n, _ = ex.penrose_triangle(PX)
    shape = ImageData(ex.normal_map_rgb(n).astype(np.float32), 16)
    sun = Light("sun", (np.cos(np.radians(35)) * np.cos(np.radians(200)),
                        np.cos(np.radians(35)) * np.sin(np.radians(200)), np.sin(np.radians(35))))
    pics = [_shade({**PAINT, "shape": shape}, [sun], shadows__enabled=True,
                   shadows__relief="along_ray", shadows__reach=reach)[0]
            for reach in (10.0, 0.05)]
    return pics


def mix_space():
    """Point 7: black and white painted, lit by a sun: the mid-tones of the two mixes."""
    n, _ = ex.sphere(PX, 0.45)
    images = {"dark": _const((0.0, 0.0, 0.0)), "bright": _const((1.0, 1.0, 1.0)),
              "shape": ImageData(ex.normal_map_rgb(n).astype(np.float32), 16)}
    linear, _ = _shade(images, diffuse__mix_space="linear")
    painted, _ = _shade(images)
    # half-way (W = ½): the value on screen of each mix, in levels of 255
    half = {space: 255 * float(linear_to_srgb(barycentric_mix(
        np.zeros(3, np.float32), np.ones(3, np.float32), np.full(3, 0.5, np.float32), space))[0])
        for space in ("linear", "painted")}
    return [linear, painted], half


def main(out=DOCS):
    os.makedirs(os.path.join(out, "img", "real"), exist_ok=True)
    conventions = _save(out, "normal_conventions.png", normal_conventions())
    renders, mask_warnings = red_mask()
    mask = _save(out, "red_mask.png", renders)
    placed = _save(out, "placement.png", placement())
    stairs = _save(out, "penrose_shadows.png", penrose())
    renders, half = mix_space()
    mix = _save(out, "mix_space.png", renders)
    page = f"""# Real paintings as their artists made them

Pictures made by `docs/make_real_paintings.py` from the example paintings of
`testkit/example_paintings.py` (numpy only, in the conventions other tools use), rendered
by the numpy core. *Before* is what Dynamic Painting did until 2026-11-23. Parameters:
[parameters.md](parameters.md); the changes: [CHANGELOG](../CHANGELOG.md).

## Normal maps in other conventions (`shape.encoding`, `shape.strength`)

{conventions}

A sphere lit from the upper left. 1: a two-channel map (x, y in red and green, blue 0), read
with `encoding = "auto"` (blue about 0 → rg, whatever 8-bit export or JPEG left in it). Before,
it was refused with a misleading "is it a colour or height image?"; read as RGB (`encoding =
"rgb"`, an explicit setting) it is read as asked, with a note that names the fix: *set 'auto'
or 'rg' to read x, y*. 2: a map painted for a decoder that halves every tilt, at strength 1
(before): twice as steep as drawn, the shading crowded to the rim. 3: the same with `strength =
"auto"` (the default since 2026-11-25): its unit vectors face away where the drawing is steep,
which only such a map's do, so it is read at 0.5, and said. A map whose vectors are not unit
length cannot tell: its note names `strength = 0.5`. 4: the sphere's own RGB map, for
comparison (1, 3 and 4 agree to float precision). How each guess survives noisy and JPEG
files: [detection-numbers.md](detection-numbers.md).

## Masks painted in one colour channel (`transparency.channel`)

{mask}

A mirror sphere whose transparency mask is pure red on black. Before (left), masks were read as
luminance: the sphere is at most 21 % mirror. After (`channel = "auto"`), the red channel is the
mask, and the render says so: *{mask_warnings[0] if mask_warnings else ''}*

## Placed environments (`reflection.offset`, `reflection.scale`, `reflection.extension`)

{placed}

A photograph reflected far enough that lookups leave it. Left: the old default `wrap` — hard
seams where its top meets its bottom and its left its right. Middle: the new default `mirror`,
seamless. Right: placed — moved up 0.15 image widths and 1.6 × larger, so the horizon lands where
the artist wants it.

## Shadows of impossible figures (`shadows.reach`)

{stairs}

A Penrose tribar drawn as flat facets (a normal map no height field produces), cos-θ shadows
from a sun at 35°, marched along each ray (`shadows.relief = "along_ray"`: the default
integrated relief looks for the height field that best fits the normals, and an impossible
figure has none). Left: the relief rebuilt along each ray over the whole image (before): the
slopes of the facets rebuild heights that never come back down, and long dark smears cover the
lower bar and the canvas. Right: the default reach of 0.05 image widths: every facet is lit as
the plane it is, with short contact shadows at its edges. Measured (tests/core/test_shadow.py,
256², sun at 35°, azimuths 200°, 60°, 135°): share of pixels farther than 0.05 image widths
from any other facet whose t is off its facet's N·L by more than 0.1 — before 1.2 %, 3.7 %,
7.4 %; now 0 at reach 0.05 and at 0.1. The reach is kept for such maps only: the tribar's
slopes circulate around its loops (4.3 per image width, `core.shape.circulation`; 2.5 is the
limit), while a map whose normals fit a height field — any map of a 3D object — is marched
along the whole ray, so a figure's shadow on the ground falls as far as it should
(docs/relief-choice.md).

## Colours mixed as painted (`diffuse.mix_space`)

{mix}

Black and white painted, a sun from the upper left. Left: mixed in linear light (before): the
sphere is mostly light, its terminator pushed to the edge — half-way between black and white
shows {half['linear']:.0f} of 255 on screen. Right: mixed as painted (the new default): half-way
is {half['painted']:.0f} of 255, the grey the painter mixed.
"""
    with open(os.path.join(out, "real-paintings.md"), "w", encoding="utf-8") as fh:
        fh.write(page)
    print(f"wrote {out}/real-paintings.md and {out}/img/real/*.png")


if __name__ == "__main__":
    main()
