"""The parity suite's paintings: smooth synthetic images and ≥ 20 recipes covering every
feature on and off and the extremes of pipeline.md §14 (issue 3).

Images are smooth on purpose: a texel-exact pipeline matches to float precision, and smooth
data keeps sub-texel lookup jitter (≈3e-5 of a texel in Cycles) from being amplified by
white noise. Sizes differ per channel (40×30 painting, 32×24 environment, 48×40 background)
so aspect and UV mapping errors show.
"""
import os

import numpy as np

from dynpaint_addon import params
from dynpaint_addon.core.lights import Light
from dynpaint_addon.inputs.imageio import write_exr, write_png
from dynpaint_addon.inputs.recipe import Recipe

W, H = 40, 30


def _grid(w, h):
    y, x = np.mgrid[0:h, 0:w]
    return (x + 0.5) / w, (y + 0.5) / h


def doubled_tilts(n):
    """Unit normals with each tilt from +z doubled (azimuth kept): what a map painted for the
    decoder normalize((0,0,1) + N) stores to mean `n`."""
    rxy = np.hypot(n[..., 0], n[..., 1])
    theta = 2 * np.arctan2(rxy, n[..., 2])
    along = np.where(rxy > 0, np.sin(theta) / np.where(rxy > 0, rxy, 1), 0)
    return np.stack([n[..., 0] * along, n[..., 1] * along, np.cos(theta)], -1)


def write_images(folder):
    """Write every test image (y-up arrays → files) → {name: path}."""
    os.makedirs(folder, exist_ok=True)
    x, y = _grid(W, H)
    paths = {}

    def save(name, px, bits=8):
        path = os.path.join(folder, name)
        write_exr(path, px) if name.endswith(".exr") else write_png(path, px, bits)
        paths[name.removesuffix(".png")] = path     # "dark", "bg.exr"

    # normal map: two smooth bumps; tilts reach past 45° (N.z down to ≈0.45)
    bx = 1.1 * np.sin(2 * np.pi * x) * np.cos(np.pi * (y - 0.5))
    by = 0.9 * np.cos(2 * np.pi * (x + 0.15)) * np.sin(np.pi * y)
    n = np.stack([bx, by, np.ones_like(x)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    save("normal.png", (n + 1) / 2, 16)
    # the same with an alpha silhouette (an ellipse, soft edge)
    r = np.hypot((x - 0.5) / 0.42, (y - 0.5) / 0.4)
    alpha = np.clip((1 - r) * 8, 0, 1)
    save("normal_alpha.png", np.concatenate([(n + 1) / 2, alpha[..., None]], -1), 16)
    save("normal_opaque_alpha.png", np.concatenate([(n + 1) / 2, np.ones_like(alpha)[..., None]],
                                                   -1), 16)
    # the same normals in other tools' conventions (§2): two-channel (x, y in red and green,
    # blue 0) and painted for a decoder that halves every tilt (each tilt stored doubled)
    save("normal_rg.png", np.concatenate([(n[..., :2] + 1) / 2, np.zeros_like(x)[..., None]], -1),
         16)
    save("normal_halving.png", (doubled_tilts(n) + 1) / 2, 16)
    # slopes that fit no height field (a smooth whirl, ∮ ≈ 0.16 px around each pixel's loop:
    # an impossible figure's kind, core.shape.circulation), so shadows.reach applies (§6)
    px, py = (x - 0.5) * W, (y - 0.5) * W
    whirl = np.stack([-0.08 * py, 0.08 * px, np.ones_like(x)], -1)   # slopes (−p, −q): N.xy
    whirl /= np.linalg.norm(whirl, axis=-1, keepdims=True)
    save("normal_whirl.png", (whirl + 1) / 2, 16)
    # height maps: a smooth dome plus a ridge, 16-bit and 8-bit
    hgt = 0.7 * np.exp(-((x - 0.4) ** 2 + (y - 0.55) ** 2) / 0.06) \
        + 0.3 * np.exp(-((x - 0.75) ** 2) / 0.01) 
    save("height16.png", hgt, 16)
    save("height8.png", hgt, 8)
    save("height.exr", hgt)
    # painted images (sRGB-encoded, 8-bit)
    dark = np.stack([0.15 + 0.2 * x, 0.1 + 0.15 * y, 0.3 + 0.2 * np.sin(3 * x + 2 * y)], -1)
    bright = np.stack([0.95 - 0.2 * y, 0.8 + 0.15 * np.cos(4 * x), 0.55 + 0.3 * x * y], -1)
    save("dark.png", dark)
    save("bright.png", bright)
    save("dark_alpha.png", np.concatenate([dark, alpha[..., None]], -1))
    save("bright_alpha.png", np.concatenate([bright, alpha[..., None]], -1))
    save("spec.png", np.stack([1 - 0.3 * x, 0.9 + 0.1 * y, 0.7 + 0.3 * x], -1))
    save("gloss.png", 0.4 + 0.6 * np.clip(np.sin(np.pi * x) * np.sin(np.pi * y) * 1.2, 0, 1))
    k = np.clip(1.4 * np.exp(-((x - 0.5) ** 2 + (y - 0.5) ** 2) / 0.08), 0, 1)
    save("transparency.png", k)
    # a mask painted in one colour channel (pure red marks the glass, issue 15), 8-bit RGB
    save("transparency_red.png", np.stack([k, np.zeros_like(k), np.zeros_like(k)], -1))
    save("white.png", np.ones((H, W, 3)))
    # environment and background: other sizes, smooth and colourful
    ex, ey = _grid(32, 24)
    save("env.png", np.stack([0.5 + 0.4 * np.sin(2 * np.pi * ex), 0.5 + 0.4 * np.cos(2 * np.pi * ey),
                              0.5 + 0.3 * np.sin(2 * np.pi * (ex + ey))], -1))
    gx, gy = _grid(48, 40)
    save("bg.png", np.stack([0.2 + 0.6 * gx, 0.3 + 0.5 * np.sin(np.pi * gy), 0.8 - 0.5 * gx * gy], -1))
    save("bg.exr", np.stack([0.1 + 1.5 * gx, 0.3 + 0.5 * gy, 0.6 * np.ones_like(gx)], -1))
    return paths


SUN = Light("sun", (-0.5, 0.45, 0.74), (1.0, 1.0, 1.0), 1.0, "Sun")


def _sun(direction, colour=(1.0, 1.0, 1.0), strength=1.0, name="Sun"):
    return Light("sun", direction, colour, strength, name)


def _point(position, colour=(1.0, 1.0, 1.0), strength=1.0, name="Point"):
    return Light("point", position, colour, strength, name)


# name: (images, parameter overrides, lights)
BASE = {"shape": "normal", "dark": "dark", "bright": "bright"}
GLASS = {**BASE, "environment": "env", "background": "bg", "transparency": "transparency"}
RECIPES = {
    "minimal": (BASE, {}, [SUN]),
    "gooch_coloured": (BASE, {"diffuse.t0": -1.0, "diffuse.t1": 1.0,
                              "diffuse.curve": "smoothstep"},
                       [_sun((0.3, -0.6, 0.6), (1.0, 0.7, 0.4))]),
    "cartoon_step": (BASE, {"diffuse.t0": 0.45, "diffuse.t1": 0.45}, [SUN]),
    "inverted_smootherstep": (BASE, {"diffuse.t0": 0.9, "diffuse.t1": 0.1,
                                     "diffuse.curve": "smootherstep"}, [SUN]),
    "two_lights_coloured": (BASE, {}, [_sun((-0.7, 0.2, 0.5), (1.0, 0.5, 0.3), 0.8, "Key"),
                                       _point((0.4, -0.3, 0.4), (0.3, 0.5, 1.0), 0.6, "Fill")]),
    "point_close": (BASE, {}, [_point((0.05, 0.02, 0.05))]),
    "grazing_sun": (BASE, {"diffuse.t0": -0.1, "diffuse.t1": 0.3}, [_sun((1.0, 0.2, 0.05))]),
    "below_horizon": (BASE, {"diffuse.t0": -0.5}, [_sun((0.3, 0.8, -0.2))]),
    "height16_sun": ({**BASE, "shape": "height16"}, {"shape.kind": "height",
                                                      "shape.height_scale": 0.08}, [SUN]),
    "height8_point_preblur": ({**BASE, "shape": "height8"},
                              {"shape.kind": "height", "shape.height_scale": 0.05},
                              [_point((-0.2, 0.3, 0.3), strength=1.5)]),
    "shadows_height": ({**BASE, "shape": "height.exr"},
                       {"shape.kind": "height", "shape.height_scale": 0.1,
                        "shadows.enabled": True, "shadows.quality": "custom",
                        "shadows.steps": 32},
                       [_sun((0.8, 0.3, 0.5))]),
    "shadows_normal_point": (BASE, {"shadows.enabled": True, "shadows.offset": 0.02,
                                    "diffuse.curve": "smoothstep"},
                             [_point((-0.3, -0.2, 0.25), (1.0, 0.9, 0.8))]),
    "specular_maps": ({**BASE, "specular_color": "spec", "gloss": "gloss"},
                      {"specular.enabled": True, "specular.s0": 0.6, "specular.amount": 0.8},
                      [_sun((0.2, 0.3, 0.9)), _point((0.3, 0.2, 0.5), (0.9, 0.9, 1.0), 0.5)]),
    "reflection_wrap": ({**BASE, "environment": "env", "transparency": "transparency"},
                        {"reflection.distance": 0.15, "reflection.extension": "wrap",
                         "specular.enabled": True}, [SUN]),
    "reflection_clamped_45deg_mirror": (
        {**BASE, "environment": "env"},
        {"reflection.mode": "clamped", "reflection.distance": 0.08, "reflection.max_offset": 0.3,
         "reflection.extension": "mirror", "transparency.amount": 0.9}, [SUN]),
    "refraction_eta_half_tir": ({**BASE, "background": "bg"},
                                {"refraction.ior": 0.5, "refraction.distance": 0.2,
                                 "transparency.amount": 1.0}, [SUN]),
    "refraction_eta_two": ({**BASE, "background": "bg.exr"},
                           {"refraction.ior": 2.0, "refraction.distance": 0.3,
                            "refraction.extension": "wrap", "transparency.amount": 0.8}, [SUN]),
    "refraction_mu_plus_one": ({**BASE, "background": "bg"},
                               {"refraction.mode": "linear", "refraction.mu": 1.0,
                                "refraction.distance": 0.2, "transparency.amount": 1.0}, [SUN]),
    "refraction_mu_minus_one": ({**BASE, "background": "bg"},
                                {"refraction.mode": "linear", "refraction.mu": -1.0,
                                 "refraction.distance": 0.2, "refraction.extension": "mirror",
                                 "transparency.amount": 1.0}, [SUN]),
    "glass_physical_fresnel": (GLASS, {"refraction.ior": 1.5, "refraction.distance": 0.1,
                                       "reflection.distance": 0.1, "specular.enabled": True},
                               [SUN]),
    "glass_art_fresnel_sin": (GLASS, {"fresnel.mode": "art", "fresnel.domain": "sin",
                                      "fresnel.x1": 0.2, "fresnel.x2": 0.6, "fresnel.kappa": 0.5,
                                      "refraction.mode": "linear", "refraction.mu": 0.4}, [SUN]),
    "glass_art_cos_blurred": (GLASS, {"fresnel.mode": "art", "fresnel.kappa": -0.5,
                                      "reflection.blur": 0.03, "refraction.blur": 0.05,
                                      "transparency.amount": 0.7}, [SUN]),
    "silhouette_over_background": ({**BASE, "shape": "normal_alpha", "background": "bg"},
                                   {"transparency.amount": 0.0}, [SUN]),
    "silhouette_dark_alpha_no_bg": ({**BASE, "dark": "dark_alpha"},
                                    {"silhouette.source": "dark"}, [SUN]),
    "flip_green_zmin": (BASE, {"shape.flip_green": True, "shape.z_min": 0.6}, [SUN]),
    "one_image_no_light": ({"shape": "normal", "dark": "dark"}, {}, []),
    # a sprite and its normal map (§1): the colour image an albedo, its alpha the figure
    "sprite_colour_alpha": ({"shape": "normal", "bright": "bright_alpha"},
                            {"diffuse.ambient": 0.3, "shadows.enabled": True}, [SUN]),
    "normal_two_channel": ({**BASE, "shape": "normal_rg"}, {}, [SUN]),       # encoding auto
    "view_weight": (BASE, {"view.show": "W"},
                    [_sun((-0.7, 0.2, 0.5), (1.0, 0.5, 0.3), 0.8, "Key"),
                     _point((0.4, -0.3, 0.4), (0.3, 0.5, 1.0), 0.6, "Fill")]),
    "view_t_shadows": ({**BASE, "shape": "height.exr"},
                       {"view.show": "t", "shape.kind": "height", "shape.height_scale": 0.1,
                        "shadows.enabled": True, "diffuse.curve": "smoothstep"},
                       [_sun((0.8, 0.3, 0.5))]),
    "view_highlight": ({**BASE, "gloss": "gloss"},
                       {"view.show": "s", "specular.enabled": True, "specular.s0": 0.6}, [SUN]),
    "view_fresnel": (GLASS, {"view.show": "F", "fresnel.mode": "art", "fresnel.kappa": 0.3},
                     [SUN]),
    "glass_red_mask": ({**GLASS, "transparency": "transparency_red", "gloss": "spec"},
                       {"refraction.distance": 0.1, "specular.enabled": True,
                        "specular.gloss_channel": "green"}, [SUN]),       # channel auto
    "placed_environment": (GLASS, {"reflection.offset": (0.3, -0.2), "reflection.scale": 0.6,
                                   "refraction.offset": (-0.15, 0.1), "refraction.scale": 1.7,
                                   "refraction.distance": 0.1}, [SUN]),       # mirror default
    "placed_background_silhouette": ({**BASE, "shape": "normal_alpha", "background": "bg"},
                                     {"refraction.offset": (0.2, 0.35), "refraction.scale": 0.45,
                                      "refraction.extension": "mirror",
                                      "transparency.amount": 0.5}, [SUN]),
    "mix_linear": (BASE, {"diffuse.mix_space": "linear", "diffuse.curve": "smoothstep"},
                   [_sun((-0.7, 0.2, 0.5), (1.0, 0.5, 0.3), 0.8, "Key")]),
    "normal_shadows_short_reach": ({**BASE, "shape": "normal_whirl"},
                                   {"shadows.enabled": True, "shadows.reach": 0.02,
                                    "shadows.relief": "along_ray"},
                                   [_sun((0.6, -0.4, 0.35))]),
    "normal_halving_strength": ({**BASE, "shape": "normal_halving"},
                                {"shape.strength": 0.5, "shadows.enabled": True}, [SUN]),
    "normal_shadows_integrated_figure": ({**BASE, "shape": "normal_alpha", "background": "bg"},
                                         {"shadows.enabled": True, "shadows.offset": 0.02},
                                         [_sun((0.5, -0.4, 0.4)), _point((0.2, 0.3, 0.3))]),
    "falloff_sun_and_point": (BASE, {"falloff.mode": "inverse_square", "falloff.radius": 0.3,
                                     "specular.enabled": True},
                              [SUN, _point((0.2, -0.1, 0.15), (1.0, 0.8, 0.6), 2.5, "Fill")]),
    "falloff_height_point": ({**BASE, "shape": "height16"},
                             {"shape.kind": "height", "shape.height_scale": 0.2,
                              "falloff.mode": "inverse_square", "falloff.radius": 0.05},
                             [_point((-0.1, 0.05, 0.2), strength=4.0)]),
}


# §12: a pruned tree against the full tree fed the documented neutral defaults (core/pipeline.py):
# bright := dark (one colour image at ambient 1, §1), white specular colour and gloss, a transparency map of 1 under the slider,
# an opaque silhouette, and the background standing in for the environment (C_M := C_T, exact
# here because the warp distances are 0, so both lookups read the same texel).
PRUNED = ({"shape": "normal", "dark": "dark", "background": "env"},
          {"specular.enabled": True, "transparency.amount": 0.6, "diffuse.ambient": 1.0, "refraction.distance": 0.0,
           "reflection.distance": 0.0, "reflection.extension": "extend"}, [SUN])
FULL_WITH_DEFAULTS = ({"shape": "normal_opaque_alpha", "dark": "dark", "bright": "dark",
                       "specular_color": "white", "gloss": "white", "transparency": "white",
                       "environment": "env", "background": "env"}, PRUNED[1], [SUN])


def make_recipe(name, paths):
    images, overrides, lights = {"pruned": PRUNED, "full_with_defaults": FULL_WITH_DEFAULTS}.get(
        name) or RECIPES[name]
    p = params.defaults()
    for path, value in overrides.items():
        section, key = path.split(".")
        setattr(getattr(p, section), key, value)
    return Recipe(p, list(lights), {ch: paths[img] for ch, img in images.items()}, name)


def random_params(rng, renderable=False):
    """A random parameter set with its extremes drawn often (each number is its min, its max or
    uniform between). renderable: keep to what a rendered sweep can afford (baked shadows, no
    OSL compile per set; K ≤ 8 steps)."""
    p = params.defaults()
    for prm in params.PARAMS:
        if prm.kind is bool:
            value = bool(rng.integers(2))
        elif prm.kind == "enum":
            value = prm.choices[rng.integers(len(prm.choices))]
        elif prm.kind is int:
            value = (0, 1, 2, 8)[rng.integers(4)]
        else:
            # (an index drawn as Generator.choice draws it: the same sets, a tenth the time)
            lo, hi = prm.min, prm.max
            value = tuple(float((lo, hi, rng.uniform(lo, hi))[rng.integers(3)])
                          for _ in range(2 if prm.kind == "vec2" else 1))
            value = value if prm.kind == "vec2" else value[0]
        setattr(getattr(p, prm.section), prm.key, value)
    if renderable:
        p.shadows.source = "baked"
        if p.shadows.quality == "reference":
            p.shadows.quality = "final"
    return p


def random_lights(rng):
    """A sun anywhere (below the horizon too) and sometimes a point light, near or far."""
    lights = [Light("sun", tuple(rng.normal(size=3) + [0, 0, 0.3]), tuple(rng.uniform(0, 2, 3)),
                    float(rng.uniform(0, 3)), "Sun")]
    if rng.integers(2):
        lights.append(Light("point", tuple(rng.uniform(-1, 1, 3) * [1, 1, 0.5] + [0, 0, 0.02]),
                            tuple(rng.uniform(0, 1, 3)), float(rng.uniform(0, 2)), "Point"))
    return lights


def random_recipe(rng, paths, name="random"):
    """A random painting: every channel present, shape a normal or a height map."""
    p = random_params(rng, renderable=True)
    shape = {"normal": rng.choice(["normal", "normal_alpha"]),
             "height": rng.choice(["height16", "height8", "height.exr"])}[p.shape.kind]
    images = {"shape": shape, "dark": "dark", "bright": "bright", "specular_color": "spec",
              "gloss": "gloss", "transparency": "transparency", "environment": "env",
              "background": rng.choice(["bg", "bg.exr"])}
    return Recipe(p, random_lights(rng), {ch: paths[img] for ch, img in images.items()}, name)
