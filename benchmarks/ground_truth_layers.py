"""Layers that shadow each other against real 3D (issue 30, pipeline.md §15): Cycles renders
the ground truth; the scene helpers are ground_truth.py's.

The 3D scene, seen from above by the orthographic camera of ground_truth.py (one image
width = one scene unit): a ground (layer 0, z = 0); at z = 0.1, three flat cut-out cards one
pixel thick — a disc, a ring and a star (layer 1); at z = 0.22 a card with a dome on it (a
relief, layer 2). Every shape is defined once here (`SHAPES`, in image widths) and given
both to Blender (as meshes: the faces of a fine grid whose centres lie inside, made solid
downward by the card's thickness) and to the core (as each layer's alpha, supersampled,
and the dome's height map).

Ground truth per layer: Cycles' direct light on that layer's objects, every other layer
hidden from the camera but casting shadows (white diffuse, light strength π, so a lit
pixel reads N·L). The core: `core.layers.bake_scene` of the three layers (each its own
§6 term times T through the layers in front). Per layer and light: mean |t − 3D| over the
layer's pixels (one pixel in from its edges), and the IoU of the shadows cast by the
layers in front (pixels that get less than half of what they get with nothing in front).
Lights: hard suns at 15–60° elevation, a point light, and a sun 5° wide.

    .venv/bin/python benchmarks/ground_truth_layers.py --size 256 --out docs/layers-truth.md

(--offsets: d of each table; by default 0, where the cos-θ term is what the truth renders,
and the recipes' 0.01.)
"""
import argparse
import math
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from ground_truth import SUNS, build_scene, render_to, sun_direction  # noqa: E402
from report import command_line, publish  # noqa: E402

from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.layers import Layer, bake_scene  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402

GRID = 1024                  # mesh grid cells per image width: stair steps of ¼ px at 256²
THICKNESS = 1 / 256          # the cards' thickness, image widths
DEPTHS = (0.0, 0.1, 0.22)    # layers 0 (ground), 1 (cards), 2 (the relief)


def disc(cx, cy, r):
    return lambda x, y: np.hypot(x - cx, y - cy) <= r


def ring(cx, cy, r0, r1):
    return lambda x, y: (np.hypot(x - cx, y - cy) >= r0) & (np.hypot(x - cx, y - cy) <= r1)


def star(cx, cy, r, bumps=5, depth=0.35):
    def inside(x, y):
        a = np.arctan2(y - cy, x - cx)
        return np.hypot(x - cx, y - cy) <= r * (1 - depth + depth * np.cos(bumps * a))
    return inside


def square(cx, cy, half):
    return lambda x, y: (np.abs(x - cx) <= half) & (np.abs(y - cy) <= half)


DOME = (-0.04, -0.02, 0.08, 0.05)             # centre x, y, radius, height (image widths)


def dome_height(x, y):
    cx, cy, r, h = DOME
    return h * np.sqrt(np.clip(1 - ((x - cx) ** 2 + (y - cy) ** 2) / r ** 2, 0, 1))


# layer → [(name, inside(x, y) in image widths from the centre, bounding box)]
SHAPES = {
    1: [("disc", disc(-0.22, 0.2, 0.09), (-0.31, 0.11, -0.13, 0.29)),
        ("ring", ring(0.2, 0.18, 0.06, 0.12), (0.08, 0.06, 0.32, 0.3)),
        ("star", star(0.16, -0.22, 0.12), (0.04, -0.34, 0.28, -0.1))],
    2: [("dome card", square(-0.04, -0.02, 0.11), (-0.15, -0.13, 0.07, 0.09))],
}
LIGHTS = [(f"sun {e}°/{a}°", Light("sun", sun_direction(e, a))) for e, a in SUNS] + [
    ("point (0.3, 0.25, 0.7)", Light("point", (0.3, 0.25, 0.7))),
    ("sun 45°/220°, 5° wide", Light("sun", sun_direction(45, 220), size=math.radians(5)))]


def add_card(name, inside, box, z, relief=None):
    """A card of the scene: the faces of a GRID-per-width grid over `box` whose centres are
    inside, at height z (plus `relief` where given), made solid THICKNESS downward."""
    x0, y0, x1, y1 = box
    nx, ny = int(round((x1 - x0) * GRID)), int(round((y1 - y0) * GRID))
    xs, ys = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1)
    gx, gy = np.meshgrid(xs, ys)
    gz = z + (relief(gx, gy) if relief else np.zeros_like(gx))
    verts = np.dstack([gx, gy, gz]).reshape(-1, 3)
    cx, cy = np.meshgrid((xs[:-1] + xs[1:]) / 2, (ys[:-1] + ys[1:]) / 2)
    j, i = np.nonzero(inside(cx, cy))
    k = j * (nx + 1) + i
    faces = np.stack([k, k + 1, k + nx + 2, k + nx + 1], axis=1)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts.tolist(), [], faces.tolist())
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    solid = obj.modifiers.new("thickness", "SOLIDIFY")
    solid.thickness, solid.offset = THICKNESS, -1.0
    if relief:
        obj.data.shade_smooth()
    return obj


def build(size):
    """The 3D scene → {layer: [objects]} (the ground is layer 0)."""
    scene = build_scene(size, [])
    objects = {0: [bpy.data.objects["ground"]], 1: [], 2: []}
    for layer, shapes in SHAPES.items():
        for name, inside, box in shapes:
            relief = dome_height if layer == 2 else None
            objects[layer].append(add_card(name, inside, box, DEPTHS[layer], relief))
    return scene, objects


def set_light(scene, light):
    """The core's light in Blender: strength π, a sun's angle or a point light of radius 0."""
    from mathutils import Vector
    for obj in [o for o in scene.objects if o.type == "LIGHT"]:
        bpy.data.objects.remove(obj)
    kind = "SUN" if light.kind == "sun" else "POINT"
    lamp = bpy.data.objects.new("light", bpy.data.lights.new("light", kind))
    scene.collection.objects.link(lamp)
    if light.kind == "sun":
        lamp.data.energy, lamp.data.angle = math.pi, light.size
        lamp.rotation_mode = "QUATERNION"
        lamp.rotation_quaternion = Vector(light.vector).to_track_quat("Z", "Y")
    else:
        # radiance π·(what reaches a unit area facing it at distance r)/r²: a point light of
        # power P W gives P/(4π r²) W/m² → P = 4π² makes N·L/r²; the core's point light has no
        # falloff, so the truth is divided by 1/r² per pixel afterwards
        lamp.data.energy, lamp.data.shadow_soft_size = 4 * math.pi ** 2, 0.0
        lamp.location = light.vector


def render_truth(scene, objects, layer, light, folder, name):
    """Cycles: direct light on `layer`'s objects, the others hidden from the camera."""
    mat = bpy.data.materials.get("white") or bpy.data.materials.new("white")
    nt = mat.node_tree
    nt.nodes.clear()
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
    nt.links.new(bsdf.outputs[0], nt.nodes.new("ShaderNodeOutputMaterial").inputs[0])
    for i, objs in objects.items():
        for obj in objs:
            obj.data.materials.clear()
            obj.data.materials.append(mat)
            obj.visible_camera = i == layer
    set_light(scene, light)
    scene.world = None
    scene.cycles.max_bounces = 0
    scene.cycles.samples = 64 if light.size == 0 else 256
    return render_to(scene, os.path.join(folder, f"{name}.exr"))[..., 0]


def core_layers(size):
    """The scene as the core's layers: alpha supersampled 4×4 per pixel, the dome's heights."""
    sub = 4
    c = (np.arange(size * sub) + 0.5) / (size * sub) - 0.5
    gx, gy = np.meshgrid(c, c)

    def coverage(inside):
        return inside(gx, gy).reshape(size, sub, size, sub).mean(axis=(1, 3)).astype(np.float32)
    layers = []
    for i, z in enumerate(DEPTHS):
        p = params.defaults()
        p.shape.kind, p.shadows.enabled, p.shape.preblur = "height", True, 0.0
        grey = np.full((size, size, 3), 0.8, np.float32)
        if i == 0:
            heights, alpha = np.zeros((size, size), np.float32), None
        else:
            alpha = np.clip(sum(coverage(inside) for _, inside, _ in SHAPES[i]), 0, 1)
            c1 = (np.arange(size) + 0.5) / size - 0.5
            hx, hy = np.meshgrid(c1, c1)
            heights = (dome_height(hx, hy) if i == 2 else np.zeros_like(hx)).astype(np.float32)
        p.shape.height_scale = 1.0
        dark = grey if alpha is None else np.dstack([grey, alpha])
        images = {"shape": ImageData(heights, 32), "dark": ImageData(dark, 32),
                  "bright": ImageData(grey, 32)}
        layers.append(Layer(images, p, ("ground", "cards", "relief")[i], z,
                            None if i == 0 else THICKNESS))
    return layers


def point_falloff(light, layers):
    """r² from each layer's surface points to a point light: the core's point light has no
    falloff, Cycles' has 1/r², so the truth is multiplied by it."""
    out = []
    for layer in layers:
        heights = layer.images["shape"].pixels[..., 0]
        size = heights.shape[1]
        c = (np.arange(size) + 0.5) / size - 0.5
        gx, gy = np.meshgrid(c, c)
        out.append((light.vector[0] - gx) ** 2 + (light.vector[1] - gy) ** 2
                   + (light.vector[2] - layer.depth - heights) ** 2)
    return out


def evaluate(size, offset):
    folder = tempfile.mkdtemp()
    scene, objects = build(size)
    layers = core_layers(size)
    for layer in layers:
        layer.p.shadows.offset = offset
    rows, seconds = [], {}
    for label, light in LIGHTS:
        start = time.perf_counter()
        t = bake_scene(layers, light)
        seconds[label] = time.perf_counter() - start
        alone = [bake_scene([layer], light)[0] for layer in layers]   # nothing in front
        r2 = point_falloff(light, layers) if light.kind == "point" else [1.0] * len(layers)
        for i, layer in enumerate(layers):
            truth = render_truth(scene, objects, i, light, folder, f"{label}_{i}") * r2[i]
            mask = np.ones((size, size), bool) if i == 0 else _inner(layer)
            err = float(np.abs(t[i] - truth)[mask].mean())
            if i < len(layers) - 1:
                a = mask & (truth < 0.5 * alone[i])
                b = mask & (t[i] < 0.5 * alone[i])
                iou = float((a & b).sum() / max((a | b).sum(), 1)) if (a | b).any() else None
            else:
                iou = None
            rows.append((label, layer.name, err, iou))
    return rows, seconds


def _inner(layer):
    """A layer's pixels one pixel in from its edges (alpha ≥ ½ there and at the 8 beside)."""
    a = layer.images["dark"].pixels[..., 3] >= 0.5
    inner = a.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(a, dy, 0), dx, 1)
    return inner


GOALS = {"cards": (0.95, 0.02), "ground": (0.95, 0.02), "relief": (0.90, 0.03)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--offsets", type=float, nargs="+", default=[0.0, 0.01],
                    help="d in image widths, a table each (0: the cos-θ term is N·L × hard "
                         "visibility, what the truth renders; the recipes' 0.01 adds §6's "
                         "translucent look to each layer's own relief)")
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    lines = ["# Layers that shadow each other against 3D ground truth (issue 30)", "",
             f"`{command_line(__file__, argv)}` — {args.size}², the scene of "
             f"`benchmarks/ground_truth_layers.py`: a ground, three cards one pixel thick at "
             f"z = {DEPTHS[1]} (disc, ring, star) and a card with a dome at z = {DEPTHS[2]}; "
             f"truth = Cycles' direct light on each layer, the others hidden from the camera "
             f"but casting shadows; core = `bake_scene` at final quality. Error over each "
             f"layer's pixels (one in from its edges); IoU of the shadows cast by the layers in "
             f"front (less than half of the light the layer gets alone). The relief layer's "
             f"own dome is §6's term: at d > 0 it carries the term's translucent look, which "
             f"3D has not (docs/ground-truth.md).", ""]
    for offset in args.offsets:
        lines += [f"## d = {offset:g} image widths", ""] + _table(*evaluate(args.size, offset))
        lines.append("")
    lines += ["Reading it: what the layers add — the shadows cast between them — is the same at "
              "both d (the ground and cards rows), because T's rays start at each pixel's "
              "surface point (§15, amended: from §6's P0 the shadows moved by d·cot(elevation) "
              "and the IoU fell to 0.46–0.92 at d = 0.01). The relief rows at d > 0 measure "
              "the dome's own §6 term, whose translucent look 3D has not: a one-layer painting "
              "shows the same (docs/ground-truth.md)."]
    publish(lines, args.out)


def _table(rows, seconds):
    lines = ["| light | layer | mean \\|t − 3D\\| | goal | cast-shadow IoU | goal | bake s |",
             "|---|---|---|---|---|---|---|"]
    for label, layer, err, iou in rows:
        goal_iou, goal_err = GOALS[layer]
        if "wide" in label:
            goal_err = 0.03
        lines.append(f"| {label} | {layer} | {err:.4f} | ≤ {goal_err} "
                     f"({'met' if err <= goal_err else 'not met'}) | "
                     + (f"{iou:.3f} | ≥ {goal_iou} ({'met' if iou >= goal_iou else 'not met'})"
                        if iou is not None else "– | –")
                     + f" | {seconds[label]:.2f} |")
    return lines


if __name__ == "__main__":
    main()
