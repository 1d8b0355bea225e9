"""Make the sample paintings (images, recipes, thumbnails) from scratch: every pixel is ours.

    .venv/bin/python sample_scenes/make_samples.py [--only NAME] [--size N]

- portrait:   Suzanne (Blender's own monkey head) rendered as a height map by Cycles, emerging
              from a canvas; painterly dark and bright images made from its relief; a warm key
              sun and a cool point fill. Cast shadows from the height map (§6).
- glass:      a bottle whose normal map is exact (a surface of revolution, in closed form), an
              environment and a background cut from Blender's bundled CC0 studio-light HDRIs;
              refraction (§9), reflection (§8), the art-directed Fresnel (§10), highlights (§7).
- impossible: Penrose stairs, a ring of steps that climbs forever: a normal map no height field
              produces (its slopes circulate around the ring), with cos-θ shadows from the normal
              map (§6 integrates the slopes along each light row).
- window:     a scene of three layers at depths whose shadows fall on the layers behind (§15).
- blink:      a painting that moves (§16): Suzanne turns and blinks over 24 frames, rendered
              by Cycles as normal maps per frame (a sequence of files), painted dark and
              bright frames in sprite sheets.
- walk:       a Grease Pencil animation (issue 42): a figure walks across a drawn sky behind a
              still post, shipped as the drawing's data and lit as From Grease Pencil lights it.

Deterministic (fixed seeds, fixed Cycles samples). The thumbnails are rendered by the numpy core.
"""
import argparse
import math
import os
import shutil
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))

from dynpaint_addon import params                                   # noqa: E402
from dynpaint_addon.core.colour import linear_to_srgb    # noqa: E402
from dynpaint_addon.core.lights import Light                             # noqa: E402
from dynpaint_addon.core.sampling import gaussian_blur, resample        # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_exr, write_png     # noqa: E402
from dynpaint_addon.inputs.recipe import Recipe, RecipeLayer, recipe_to_toml   # noqa: E402
from testkit.animated import sheet_of                                   # noqa: E402
from testkit.render3d import cycles_to_exr, ortho_camera                # noqa: E402

THUMB_PX = 192


# -- painterly helpers -----------------------------------------------------------------------
def strokes(h, w, seed, length=14.0, angle=0.6, scale=1.0):
    """Brush-stroke texture in [-1, 1]: noise smeared along a direction (a cheap line-integral
    convolution), so it reads as strokes rather than grain."""
    rng = np.random.default_rng(seed)
    lo = rng.standard_normal((max(2, h // 3), max(2, w // 3))).astype(np.float32)
    n = resample(lo[..., None], h, w)[..., 0]
    dx, dy = np.cos(angle), np.sin(angle)
    acc = np.zeros_like(n)
    taps = int(length)
    for k in range(-taps, taps + 1):
        acc += np.roll(n, (int(round(k * dy)), int(round(k * dx))), axis=(0, 1))
    acc -= acc.mean()
    return scale * acc / (np.abs(acc).max() + 1e-6)


def srgb8(linear_rgb):
    """Linear colour → 8-bit sRGB code values as floats in [0, 1] (what the PNG will hold)."""
    return np.round(linear_to_srgb(np.clip(linear_rgb, 0, 1)) * 255) / 255


def mix(a, b, t):
    t = np.asarray(t)[..., None]
    return np.asarray(a) * (1 - t) + np.asarray(b) * t


def save(folder, name, pixels, bits):
    path = os.path.join(folder, name)
    (write_exr if name.endswith(".exr") else lambda p, x: write_png(p, x, bits=bits))(path, pixels)
    return path


# -- portrait: Suzanne as a height map --------------------------------------------------------
def render_suzanne_height(size):
    """Cycles renders Suzanne (subdivided, facing the viewer) over a canvas plane with an
    emission = height material → (height in [0, 1] y-up, relief in image widths)."""
    import bpy
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_monkey_add(size=2.0, rotation=(-np.pi / 2, 0, 0))
    head = bpy.context.object
    mod = head.modifiers.new("smooth", "SUBSURF")
    mod.levels = mod.render_levels = 3
    bpy.ops.object.shade_smooth()
    bpy.context.view_layer.update()
    ev = head.evaluated_get(bpy.context.evaluated_depsgraph_get())
    zs = np.array([(ev.matrix_world @ v.co).z for v in ev.data.vertices])
    z_top = float(zs.max())
    z_canvas = float(zs.min() + 0.3 * (zs.max() - zs.min()))   # the head emerges from here
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0, 0, z_canvas))
    canvas = bpy.context.object
    mat = bpy.data.materials.new("height")
    nt = mat.node_tree
    nt.nodes.clear()
    geo = nt.nodes.new("ShaderNodeNewGeometry")
    xyz = nt.nodes.new("ShaderNodeSeparateXYZ")
    rng = nt.nodes.new("ShaderNodeMapRange")
    rng.inputs["From Min"].default_value = z_canvas
    rng.inputs["From Max"].default_value = z_top
    emit = nt.nodes.new("ShaderNodeEmission")
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(geo.outputs["Position"], xyz.inputs[0])
    nt.links.new(xyz.outputs["Z"], rng.inputs["Value"])
    nt.links.new(rng.outputs["Result"], emit.inputs["Color"])
    nt.links.new(emit.outputs[0], out.inputs["Surface"])
    for obj in (head, canvas):
        obj.data.materials.append(mat)
    width = 3.4
    ortho_camera(scene, width, (0, -0.15, 10))
    r = scene.render
    cycles_to_exr(scene, size, 16)
    tmp = os.path.join(bpy.app.tempdir or HERE, "_suzanne_height.exr")
    r.filepath = tmp
    bpy.ops.render.render(write_still=True)
    height = read_image(tmp).pixels[..., 0]
    os.remove(tmp)
    return np.clip(height, 0, 1), (z_top - z_canvas) / width


def make_portrait(folder, size):
    height, relief = render_suzanne_height(size)
    h, w = height.shape
    head = np.clip(gaussian_blur((height > 1e-3).astype(np.float32)[..., None], 1.5)[..., 0], 0, 1)
    cavity = np.clip((gaussian_blur(height[..., None], 6.0)[..., 0] - height) * 12, 0, 1)
    y, x = np.mgrid[0:h, 0:w].astype(np.float32) / w
    s1 = strokes(h, w, 11, angle=0.9)
    s2 = strokes(h, w, 12, angle=-0.5)
    s3 = strokes(h, w, 13, length=24, angle=0.15)
    # Bright: warm ochre skin, redder in the cavities; a pale teal canvas with a sky gradient.
    skin = mix([0.78, 0.46, 0.22], [0.62, 0.16, 0.10], cavity) * (1 + 0.10 * s1[..., None])
    sky = mix([0.30, 0.52, 0.50], [0.62, 0.70, 0.58], y) * (1 + 0.12 * s3[..., None])
    bright = mix(sky, skin, head)
    # Dark: violet shadows in the skin, deep blue canvas (the shadow side is painted, not grey).
    skin_d = mix([0.16, 0.06, 0.14], [0.08, 0.02, 0.06], cavity) * (1 + 0.15 * s2[..., None])
    sky_d = mix([0.03, 0.05, 0.12], [0.06, 0.09, 0.16], y) * (1 + 0.15 * s3[..., None])
    dark = mix(sky_d, skin_d, head)
    save(folder, "height.png", np.round(height * 65535) / 65535, 16)
    save(folder, "dark.png", srgb8(dark), 8)
    save(folder, "bright.png", srgb8(bright), 8)
    p = params.defaults()
    p.shape.kind = "height"
    p.shape.height_scale = round(float(relief), 4)
    p.shadows.enabled = True
    p.shadows.offset = 0.006
    p.specular.enabled = True
    p.specular.s0, p.specular.s1 = 0.93, 1.0
    p.specular.amount = 0.35
    lights = [Light("sun", (-0.55, 0.45, 0.70), (1.0, 0.9, 0.75), 1.0, "Key"),
              Light("point", (0.6, -0.2, 0.4), (0.35, 0.45, 0.9), 0.25, "Fill")]
    return Recipe(p, lights, {"shape": "height.png", "dark": "dark.png", "bright": "bright.png"},
                  "Portrait (Suzanne)",
                  description="A head lit by a moving light: height map rendered from Blender's "
                              "Suzanne, painterly dark and bright images, cast shadows")


# -- glass: a bottle as an exact normal map ---------------------------------------------------
def bottle_radius(v):
    """Radius (image widths) of the bottle at height v ∈ [0, 1] up the bottle, and dr/dv."""
    body, neck = 0.30, 0.085
    t = np.clip((v - 0.52) / 0.2, 0, 1)
    shoulder = t * t * (3 - 2 * t)                     # smoothstep from body to neck
    r = body + (neck - body) * shoulder
    base = np.clip(v / 0.05, 0, 1)                      # rounded foot
    r = r * np.sqrt(np.clip(1 - (1 - base) ** 2, 0, 1)) ** 0.3
    lip = np.exp(-((v - 0.93) / 0.015) ** 2) * 0.018    # the lip ring
    return np.where((v >= 0) & (v <= 0.97), r + lip, 0.0)


def make_glass(folder, size):
    w, h = size * 3 // 4, size
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    x = (x + 0.5) / w - 0.5                            # image widths, centred
    y = (y + 0.5) / w
    bottom, tall = 0.08, 1.10
    v = (y - bottom) / tall
    r = bottle_radius(v)
    dv = 1e-4
    drdy = (bottle_radius(v + dv) - bottle_radius(v - dv)) / (2 * dv * tall)
    inside = np.abs(x) < r
    z = np.sqrt(np.clip(r * r - x * x, 1e-12, None))  # front surface of revolution
    n = np.stack([x / z, -r * drdy / z, np.ones_like(z)], -1)   # (−∂z/∂x, −∂z/∂y, 1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where(inside[..., None], n, [0.0, 0.0, 1.0])
    alpha = np.clip(gaussian_blur(inside.astype(np.float32)[..., None], 0.7)[..., 0], 0, 1)
    alpha = np.where(inside, np.maximum(alpha, 0.5), alpha * 0)   # hard outside, soft inside
    rgba = np.concatenate([n * 0.5 + 0.5, alpha[..., None]], -1)
    save(folder, "normal.png", np.round(rgba * 65535) / 65535, 16)
    s = strokes(h, w, 21, angle=1.5)
    dark = mix([0.01, 0.05, 0.04], [0.02, 0.09, 0.06], v.clip(0, 1)) * (1 + 0.2 * s[..., None])
    bright = mix([0.18, 0.55, 0.40], [0.45, 0.80, 0.60], v.clip(0, 1)) * (1 + 0.1 * s[..., None])
    save(folder, "dark.png", srgb8(dark), 8)
    save(folder, "bright.png", srgb8(bright), 8)
    studio = _studio_light("studio.exr", 256)
    env = studio * (1.4 / max(1e-6, float(np.percentile(studio, 99))))
    save(folder, "environment.exr", np.clip(env, 0, 4).astype(np.float32), 32)
    bg = _studio_light("forest.exr", 512)
    bh, bw = bg.shape[:2]
    crop = bg[bh // 4: bh // 4 + bw * 2 // 5, bw * 3 // 10: bw * 3 // 10 + bw * 3 // 10]
    crop = resample(crop, h // 2, w // 2)
    crop = crop * (0.5 / max(1e-6, float(np.mean(crop))))
    save(folder, "background.exr", np.clip(crop, 0, 4).astype(np.float32), 32)
    p = params.defaults()
    p.shape.kind = "normal"
    p.refraction.mode, p.refraction.ior, p.refraction.distance = "physical", 1.5, 0.12
    p.reflection.distance, p.reflection.extension = 0.3, "wrap"
    p.fresnel.mode, p.fresnel.x1, p.fresnel.x2, p.fresnel.kappa = "art", 0.3, 0.85, 0.15
    p.transparency.amount = 0.9
    p.specular.enabled = True
    p.specular.s0, p.specular.s1 = 0.96, 1.0
    p.diffuse.t0, p.diffuse.t1 = -0.2, 1.0
    lights = [Light("sun", (-0.5, 0.55, 0.67), (1.0, 0.97, 0.92), 1.0, "Key")]
    return Recipe(p, lights, {"shape": "normal.png", "dark": "dark.png", "bright": "bright.png",
                              "environment": "environment.exr", "background": "background.exr"},
                  "Glass bottle",
                  description="A green glass bottle: exact normal map, refraction of a forest, "
                              "reflection of a studio, art-directed Fresnel")


def _studio_light(name, width):
    """One of Blender's bundled CC0 studio-light HDRIs (datafiles/studiolights/world), downsized."""
    import bpy
    path = os.path.join(bpy.utils.system_resource("DATAFILES"), "studiolights", "world", name)
    img = read_image(path).pixels[..., :3]
    h, w = img.shape[:2]
    return resample(img, max(1, round(h * width / w)), width)


# -- impossible: Penrose stairs as a non-conservative normal map ------------------------------
def penrose_normals(size, steps=16, r_in=0.22, r_out=0.40, riser=0.28, tilt=1.15):
    """A ring of `steps` stairs: each step a flat tread and a riser facing back down the stairs
    (normal tilted `tilt` rad along −tangent). Walking around, every riser climbs: the slopes
    circulate, so no height field has these normals. Inner and outer walls are bevelled."""
    y, x = np.mgrid[0:size, 0:size].astype(np.float64)
    x = (x + 0.5) / size - 0.5
    y = (y + 0.5) / size - 0.5
    r = np.hypot(x, y)
    theta = np.arctan2(y, x)
    a = np.mod(theta * steps / (2 * np.pi), 1.0)        # position within a step, 0…1
    tangent = np.stack([-np.sin(theta), np.cos(theta)], -1)
    radial = np.stack([np.cos(theta), np.sin(theta)], -1)
    on_riser = a > 1 - riser
    slope_t = np.where(on_riser, -np.tan(tilt) * 0.35, 0.0)       # ∂h/∂s along the tangent
    bevel = 0.018
    outer = np.clip((r - (r_out - bevel)) / bevel, 0, 1)
    inner = np.clip(((r_in + bevel) - r) / bevel, 0, 1)
    slope_r = -2.2 * outer + 2.2 * inner                           # walls slope down outward
    ring = (r > r_in) & (r < r_out)
    g = tangent * slope_t[..., None] + radial * slope_r[..., None]   # ∇h where it exists
    g = np.where(ring[..., None], g, 0.0)
    n = np.concatenate([-g, np.ones_like(r)[..., None]], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n, ring, a, r


def slope_circulation(normals, radius):
    """∮ ∇h · dl around a circle of `radius` (image widths) centred in the image: 0 for every
    height field; the stairs climb by this much per turn."""
    h, w = normals.shape[:2]
    t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    px = np.clip(((0.5 + radius * np.cos(t)) * w).astype(int), 0, w - 1)
    py = np.clip(((0.5 + radius * np.sin(t)) * h).astype(int), 0, h - 1)
    n = normals[py, px]
    gx, gy = -n[:, 0] / n[:, 2], -n[:, 1] / n[:, 2]
    dl = 2 * np.pi * radius / t.size
    return float(np.sum((gx * -np.sin(t) + gy * np.cos(t)) * dl))


def make_impossible(folder, size):
    n, ring, a, r = penrose_normals(size)
    save(folder, "normal.png", np.round((n * 0.5 + 0.5) * 65535) / 65535, 16)
    h, w = ring.shape
    s1, s2 = strokes(h, w, 31, angle=0.3), strokes(h, w, 32, angle=2.0, length=20)
    edge = np.exp(-((a - 0.02) / 0.03) ** 2)           # a painted nosing on each tread
    stone = mix([0.80, 0.62, 0.38], [0.52, 0.30, 0.18], edge) * (1 + 0.12 * s1[..., None])
    floor = mix([0.20, 0.30, 0.42], [0.42, 0.50, 0.55], np.clip(r * 1.6, 0, 1)) \
        * (1 + 0.12 * s2[..., None])
    bright = np.where(ring[..., None], stone, floor)
    dark = np.where(ring[..., None], [0.12, 0.06, 0.12], [0.03, 0.04, 0.09]) \
        * (1 + 0.2 * s2[..., None])
    save(folder, "dark.png", srgb8(dark), 8)
    save(folder, "bright.png", srgb8(bright), 8)
    p = params.defaults()
    p.shape.kind = "normal"
    p.shadows.enabled = True
    p.shadows.offset = 0.004
    p.shadows.relief = "along_ray"          # no height field fits these normals (§6 Relief)
    p.diffuse.t0, p.diffuse.t1 = 0.05, 0.9
    lights = [Light("sun", (0.62, 0.35, 0.70), (1.0, 0.93, 0.82), 1.0, "Key")]
    return Recipe(p, lights, {"shape": "normal.png", "dark": "dark.png", "bright": "bright.png"},
                  "Penrose stairs",
                  description="Stairs that climb forever: a normal map no height field can "
                              "produce, with cos-θ shadows baked from the normal map")


# -- window: a scene of layers (§15) ----------------------------------------------------------
def make_window(folder, size):
    """Three layers at depths: a garden of hills under a sky (a height map), a window frame
    (a flat card cut out by its alpha) and a vase on the sill in front (an exact normal map,
    a surface of revolution): the frame's and the vase's shadows fall on the layers behind."""
    w = h = size
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    u, v = (x + 0.5) / w, (y + 0.5) / w
    # the garden: rolling hills (heights) under a sky
    hills = 0.22 + 0.07 * np.sin(u * 7.0 + 1.0) + 0.04 * np.sin(u * 17.0 + 2.0)
    ground = v < hills
    height = np.where(ground, 0.5 + 0.5 * np.clip((hills - v) / 0.25, 0, 1), 0.0)
    height = gaussian_blur(height.astype(np.float32)[..., None], 2.0)[..., 0]
    save(folder, "garden_height.png", np.round(np.clip(height, 0, 1) * 65535) / 65535, 16)
    s = strokes(h, w, 31, angle=0.2)[..., None]
    sky_d, sky_b = mix([0.05, 0.07, 0.16], [0.10, 0.14, 0.30], v), mix([0.45, 0.62, 0.90], [0.75, 0.85, 1.0], v)
    grass_d, grass_b = [0.03, 0.08, 0.04], [0.30, 0.62, 0.22]
    g = ground[..., None]
    save(folder, "garden_dark.png", srgb8(np.where(g, grass_d, sky_d) * (1 + 0.2 * s)), 8)
    save(folder, "garden_bright.png", srgb8(np.where(g, grass_b, sky_b) * (1 + 0.12 * s)), 8)
    # the window frame: a wooden frame with two mullions, open panes
    frame = ~((np.abs(u - 0.5) < 0.40) & (np.abs(v - 0.52) < 0.40))
    frame |= (np.abs(u - 0.5) < 0.018) | (np.abs(v - 0.55) < 0.018)
    frame &= (np.abs(u - 0.5) < 0.48) & (np.abs(v - 0.5) < 0.48)
    alpha = frame.astype(np.float64)[..., None]
    s = strokes(h, w, 32, angle=0.0)[..., None]
    wood_d, wood_b = [0.06, 0.03, 0.02], [0.55, 0.32, 0.16]
    save(folder, "frame_dark.png", np.concatenate([srgb8(np.broadcast_to(wood_d, (h, w, 3)) * (1 + 0.3 * s)), alpha], -1), 8)
    save(folder, "frame_bright.png", np.concatenate([srgb8(np.broadcast_to(wood_b, (h, w, 3)) * (1 + 0.2 * s)), alpha], -1), 8)
    save(folder, "frame_height.png", np.zeros((h, w)), 16)
    # the vase: a surface of revolution standing on the sill (bottle_radius, smaller)
    xs, ys = u - 0.68, (v - 0.13) / 0.42
    r = 0.42 * bottle_radius(ys)
    drdy = 0.42 * (bottle_radius(ys + 1e-4) - bottle_radius(ys - 1e-4)) / (2e-4 * 0.42)
    inside = np.abs(xs) < r
    z = np.sqrt(np.clip(r * r - xs * xs, 1e-12, None))
    n = np.stack([xs / z, -r * drdy / z, np.ones_like(z)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where(inside[..., None], n, [0.0, 0.0, 1.0])
    a = inside.astype(np.float64)[..., None]
    save(folder, "vase_normal.png", np.round(np.concatenate([n * 0.5 + 0.5, a], -1) * 65535) / 65535, 16)
    s = strokes(h, w, 33, angle=1.4)[..., None]
    save(folder, "vase_dark.png", np.concatenate([srgb8(np.broadcast_to([0.12, 0.03, 0.05], (h, w, 3)) * (1 + 0.2 * s)), a], -1), 8)
    save(folder, "vase_bright.png", np.concatenate([srgb8(np.broadcast_to([0.95, 0.45, 0.30], (h, w, 3)) * (1 + 0.1 * s)), a], -1), 8)
    garden, window, vase = params.defaults(), params.defaults(), params.defaults()
    garden.shape.kind, garden.shape.height_scale = "height", 0.06
    window.shape.kind = "height"
    vase.shape.kind = "normal"
    vase.specular.enabled, vase.specular.s0 = True, 0.93
    for q in (garden, window, vase):
        q.shadows.enabled = True
    layers = [RecipeLayer(Recipe(garden, [], {"shape": "garden_height.png", "dark": "garden_dark.png",
                                              "bright": "garden_bright.png"}, "garden"), "garden", 0.0),
              RecipeLayer(Recipe(window, [], {"shape": "frame_height.png", "dark": "frame_dark.png",
                                              "bright": "frame_bright.png"}, "window"), "window", 0.1),
              RecipeLayer(Recipe(vase, [], {"shape": "vase_normal.png", "dark": "vase_dark.png",
                                            "bright": "vase_bright.png"}, "vase"), "vase", 0.18)]
    lights = [Light("sun", (-0.5, 0.45, 0.74), (1.0, 0.93, 0.82), 1.0, "Key", size=math.radians(2))]
    return Recipe(params.defaults(), lights, {}, "Window (layers)",
                  description="A scene of three layers at depths — a garden, a window frame, a "
                              "vase — whose shadows fall on the layers behind; a camera move "
                              "shows their parallax", layers=layers)


# -- blink: a painting that moves (§16) -------------------------------------------------------
def make_blink(folder, size, frames=24, columns=6):
    """Suzanne turns and blinks over 24 frames (testkit/turning_head.py: one Cycles render of
    her normals per frame, cut out by her silhouette): the normal maps as a sequence of files
    (normal_0001.png …), the painted dark and bright frames as sprite sheets (6 × 4 cells, row
    by row from the top left). Shadows from each frame's integrated relief."""
    from testkit.turning_head import render_turning_head
    truth = render_turning_head(size, frames, box=False)
    s1, s2 = strokes(size, size, 41, angle=0.9), strokes(size, size, 42, angle=-0.5)
    darks, brights = [], []
    for f in range(frames):
        n, a, h = truth["normal"][f], truth["alpha"][f][..., None], truth["height"][f]
        save(folder, f"normal_{f + 1:04d}.png",
             np.round(np.concatenate([n * 0.5 + 0.5, a], -1) * 65535) / 65535, 16)
        cavity = np.clip((gaussian_blur(h[..., None], 4.0)[..., 0] - h) * 25, 0, 1)
        rim = np.clip(1 - n[..., 2], 0, 1)          # warmer where the head turns away
        skin = mix(mix([0.80, 0.50, 0.26], [0.66, 0.22, 0.12], rim), [0.45, 0.10, 0.08], cavity)
        shade = mix(mix([0.20, 0.08, 0.18], [0.12, 0.03, 0.10], rim), [0.05, 0.01, 0.04], cavity)
        brights.append(np.concatenate([srgb8(skin * (1 + 0.10 * s1[..., None])), a], -1))
        darks.append(np.concatenate([srgb8(shade * (1 + 0.15 * s2[..., None])), a], -1))
    rows = -(-frames // columns)
    save(folder, "dark_sheet.png", sheet_of(darks, columns, rows), 8)
    save(folder, "bright_sheet.png", sheet_of(brights, columns, rows), 8)
    p = params.defaults()
    p.shape.kind = "normal"
    p.shadows.enabled = True
    p.shadows.offset = 0.006
    p.specular.enabled = True
    p.specular.s0, p.specular.s1, p.specular.amount = 0.93, 1.0, 0.3
    lights = [Light("sun", (-0.75, 0.45, 0.48), (1.0, 0.9, 0.75), 1.0, "Key")]
    return Recipe(p, lights, {"shape": "normal_####.png", "dark": "dark_sheet.png",
                              "bright": "bright_sheet.png"}, "Blink (animated)",
                  description="A painting that moves: Suzanne turns and blinks over 24 frames "
                              "(normal maps as a sequence of files, the painted frames as "
                              "sprite sheets), her shadows baked per frame",
                  frames={"": {"columns": columns, "rows": rows}})


def make_walk(folder, size, frames=24):
    """A Grease Pencil animation (issue 42; testkit/grease_pencil.py): a figure walks across a
    sky card, behind a still post, over 24 frames — shipped as the drawing's data
    (drawing.json, built into a Grease Pencil object by the add-on) and lit as From Grease
    Pencil lights it. `size` is its thumbnail's business only: the drawing is vectors."""
    from dynpaint_addon.inputs.drawings import drawing_json
    from testkit.grease_pencil import walking_drawing
    path = os.path.join(folder, "drawing.json")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(drawing_json(walking_drawing(frames)) + "\n")
    lights = [Light("sun", (-0.75, 0.45, 0.48), (1.0, 0.92, 0.8), 1.0, "Key")]
    return Recipe(params.defaults(), lights, {}, "Walk (Grease Pencil)",
                  description="A Grease Pencil animation, lit: a figure walks across a drawn "
                              "sky behind a still post over 24 frames, each layer a lit "
                              "painting that casts its shadows on the layers behind",
                  drawing=path)


SAMPLES = {"portrait": (make_portrait, 512), "glass": (make_glass, 512),
           "impossible": (make_impossible, 512), "window": (make_window, 384),
           "blink": (make_blink, 160), "walk": (make_walk, 192)}


def drawing_layers(recipe, px):
    """A drawing's recipe as the core's layers at its middle frame, drawn `px` wide (as From
    Grease Pencil makes them)."""
    import bpy
    from dynpaint_addon.blender.scenes.grease_pencil.building import build_drawing
    from dynpaint_addon.blender.scenes.grease_pencil.lit_copy import drawn_paintings, lit_defaults
    from dynpaint_addon.core.layers import Layer
    from dynpaint_addon.inputs.drawings import frame_range, load_drawing
    bpy.ops.wm.read_homefile(use_empty=True)
    drawing = load_drawing(recipe.drawing)
    scene = bpy.context.scene
    first, last = frame_range(drawing)
    scene.frame_set((first + last) // 2)
    obj = build_drawing(scene, drawing)
    made, _, _, _ = drawn_paintings(scene, obj, {**lit_defaults(), "resolution": px,
                                                 "animation": False})
    return [Layer(images, p, name, depth) for name, depth, images, p, _ in made]


def thumbnail(recipe_path, out, px=THUMB_PX):
    """Render the sample with the numpy core at `px` wide → out (PNG)."""
    from dynpaint_addon.core.input_rules import resample_painting
    from dynpaint_addon.core.layers import render_scene
    from dynpaint_addon.core.pipeline import render
    from dynpaint_addon.inputs.imageio import write_render
    from dynpaint_addon.inputs.recipe import load_images, load_layers, load_recipe
    recipe = load_recipe(recipe_path)
    if recipe.drawing:               # drawn by Blender at its middle frame, lit by the core
        write_render(out, render_scene(drawing_layers(recipe, px), recipe.lights).rgba)
        return
    if recipe.layered:
        layers = load_layers(recipe)
        for layer in layers:
            layer.images = resample_painting(layer.images, px)
        write_render(out, render_scene(layers, recipe.lights).rgba)
        return
    images = resample_painting(load_images(recipe), px)
    write_render(out, render(images, recipe.lights, recipe.params).rgba)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", choices=sorted(SAMPLES))
    ap.add_argument("--size", type=int, help="override each sample's size (pixels)")
    ap.add_argument("--out", default=HERE, help="where the sample folders go (default: here)")
    args = ap.parse_args(argv)
    for name, (make, size) in SAMPLES.items():
        if args.only and name != args.only:
            continue
        folder = os.path.join(args.out, name)
        shutil.rmtree(folder, ignore_errors=True)
        os.makedirs(folder)
        recipe = make(folder, args.size or size)
        for part in [recipe] + [layer.recipe for layer in recipe.layers]:
            part.images = {ch: os.path.join(folder, f) for ch, f in part.images.items()}
        path = os.path.join(folder, "painting.toml")
        with open(path, "w") as fh:
            fh.write(recipe_to_toml(recipe, folder))
        thumbnail(path, os.path.join(folder, "thumbnail.png"))
        print(f"{name}: {path}", flush=True)


if __name__ == "__main__":
    main()
