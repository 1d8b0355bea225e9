"""What pruning buys and what each engine costs (issue 3), measured in one run.

For the minimal tree (normal map, dark, bright, one sun) and the full tree (height map with
cos-θ shadows, specular colour and gloss, environment and background with Fresnel, a
transparency map, a silhouette, a sun and a point light) at each size:
  - node count (groups counted once each, frames excluded),
  - EEVEE: first render (shader compile + render) and second render (render only); the
    difference is the compile time,
  - Cycles (1 sample, CPU) and the numpy core (float32) per frame, and the shadow bake,
  - the largest difference of each engine from the numpy core (pixels away from the border).

    .venv/bin/python benchmarks/material_numbers.py --sizes 512 1024 --out docs/material-numbers.md
"""
import argparse
import os
import platform
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from report import publish  # noqa: E402

from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.bake.shadow_images import bake_shadows  # noqa: E402
from dynpaint_addon.blender.nodes.build import count_nodes  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.core.shape import normals_from_height_px  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import Recipe, load_images  # noqa: E402
from dynpaint_addon.inputs.testpainting import builtin_images  # noqa: E402


def write_paintings(folder, size):
    """The minimal and the full recipe at `size`² → (minimal, full)."""
    imgs = builtin_images(size)
    height = imgs["shape"].pixels[..., 0]
    n = normals_from_height_px(height * (0.25 * size))
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    r = np.hypot(x - 0.5, y - 0.5)
    files = {
        "height.png": (height, 16), "normal.png": ((n + 1) / 2, 16),
        "dark.png": (imgs["dark"].pixels, 8), "bright.png": (imgs["bright"].pixels, 8),
        "spec.png": (np.stack([np.ones_like(x), 0.9 + 0.1 * y, 0.8 + 0.2 * x], -1), 8),
        "gloss.png": (0.5 + 0.5 * np.sin(6 * x) ** 2, 8),
        "env.png": (np.stack([0.5 + 0.4 * np.sin(9 * x), 0.5 + 0.4 * np.cos(7 * y),
                              0.5 + 0.3 * np.sin(5 * (x + y))], -1), 8),
        "bg.png": (np.stack([0.2 + 0.6 * x, 0.3 + 0.5 * np.sin(3 * y), 0.8 - 0.5 * x * y], -1), 8),
        "transparency.png": (np.clip(1.6 - 4 * r, 0, 1), 8),
        "height_alpha.png": (np.stack([height, np.clip(8 * (0.48 - r), 0, 1)], -1), 16),
    }
    paths = {}
    for name, (px, bits) in files.items():
        paths[name] = os.path.join(folder, name)
        write_png(paths[name], px, bits)
    sun = Light("sun", (-0.6, 0.5, 0.45), (1.0, 0.92, 0.8), 1.0, "Key")
    point = Light("point", (0.45, -0.1, 0.35), (0.45, 0.55, 1.0), 0.25, "Fill")
    minimal = Recipe(params.defaults(), [sun],
                     {"shape": paths["normal.png"], "dark": paths["dark.png"],
                      "bright": paths["bright.png"]}, "minimal")
    p = params.defaults()
    p.shape.kind, p.shape.height_scale = "height", 0.25
    p.shadows.enabled, p.specular.enabled, p.specular.s0 = True, True, 0.92
    p.fresnel.mode = "art"
    full = Recipe(p, [sun, point], {
        "shape": paths["height_alpha.png"], "dark": paths["dark.png"], "bright": paths["bright.png"],
        "specular_color": paths["spec.png"], "gloss": paths["gloss.png"],
        "environment": paths["env.png"], "background": paths["bg.png"],
        "transparency": paths["transparency.png"]}, "full")
    return minimal, full


def timed_render():
    t = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    return time.perf_counter() - t


def warm_up_eevee():
    """Start EEVEE once (GPU context, its own shaders) so no recipe pays for that."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add()
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    cam.location = (0, 0, 5)
    exact_render_settings(scene, "eevee")
    scene.render.resolution_x = scene.render.resolution_y = 8
    scene.render.filepath = os.path.join(tempfile.gettempdir(), "dp_warm_up.png")
    timed_render()


def measure(recipe, folder):
    """One recipe: build, bake, render with both engines, compare with the core."""
    row = {}
    t = time.perf_counter()
    plane, mat = headless.build_recipe_scene(recipe)
    row["build_s"] = time.perf_counter() - t
    row["nodes"] = count_nodes(mat.node_tree)
    scene = bpy.context.scene
    if recipe.params.shadows.enabled:
        row["bake_ms"] = bake_shadows(mat, scene)
    images = load_images(recipe)
    t = time.perf_counter()
    want = core_render(images, recipe.lights, recipe.params).rgba
    row["numpy_s"] = time.perf_counter() - t
    w, h = scene.render.resolution_x, scene.render.resolution_y
    for engine in ("eevee", "cycles"):
        out = os.path.join(folder, f"{recipe.name}_{engine}.exr")
        exact_render_settings(scene, engine)
        output_settings(scene, out)
        if engine == "eevee":
            # Compile time: EEVEE compiles a new material on its first render. Render it at
            # 8×8 (no pixel work) first, then four more times; the difference is the compile.
            scene.render.resolution_x = scene.render.resolution_y = 8
            row["eevee_first8_s"] = timed_render()
            row["eevee_next8_s"] = float(np.median([timed_render() for _ in range(4)]))
            scene.render.resolution_x, scene.render.resolution_y = w, h
        row[f"{engine}_s"] = min(timed_render() for _ in range(2))
        err = np.abs(read_image(out).pixels - want)[1:-1, 1:-1].max(-1)
        row[f"{engine}_err"] = float(err.max())
        row[f"{engine}_over"] = float(np.mean(err > {"eevee": 3e-3, "cycles": 1e-3}[engine]))
    return row


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    ap.add_argument("--out", help="also write the table as Markdown here")
    args = ap.parse_args(argv)
    lines = ["# Material numbers (issue 3)", "",
             f"Machine: {platform.machine()}, {os.cpu_count()} cores, no GPU (EEVEE on llvmpipe); "
             f"bpy {bpy.app.version_string}. Command: `.venv/bin/python "
             f"benchmarks/material_numbers.py --sizes {' '.join(map(str, args.sizes))}`.", "",
             "| size | tree | nodes | EEVEE 8×8 first / next s | EEVEE render s | Cycles render s | numpy s "
             "| shadow bake ms | max |Δ| EEVEE (share > 3e-3) | max |Δ| Cycles (share > 1e-3) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    rows = {}
    warm_up_eevee()
    with tempfile.TemporaryDirectory() as folder:
        for size in args.sizes:
            minimal, full = write_paintings(folder, size)
            for recipe in (minimal, full):
                r = measure(recipe, folder)
                rows[size, recipe.name] = r
                line = (f"| {size}² | {recipe.name} | {r['nodes']} "
                        f"| {r['eevee_first8_s']:.2f} / {r['eevee_next8_s']:.2f} "
                        f"| {r['eevee_s']:.2f} | {r['cycles_s']:.2f} | {r['numpy_s']:.2f} "
                        f"| {r.get('bake_ms', 0):.0f} | {r['eevee_err']:.1e} ({r['eevee_over']:.4%}) "
                        f"| {r['cycles_err']:.1e} ({r['cycles_over']:.4%}) |")
                lines.append(line)
                print(line, flush=True)
    lines.append("")
    a, b = rows[args.sizes[0], "minimal"], rows[args.sizes[0], "full"]
    lines.append(f"- Pruning to the minimal tree keeps {a['nodes'] / b['nodes']:.0%} of the nodes. "
                 f"EEVEE's shader compile does not show on this machine: a new material's first "
                 f"render (8×8) takes {a['eevee_first8_s']:.2f} s (minimal) and "
                 f"{b['eevee_first8_s']:.2f} s (full), the next ones {a['eevee_next8_s']:.2f} s "
                 f"and {b['eevee_next8_s']:.2f} s: compiling is below the ±0.3 s noise of an "
                 f"EEVEE render on llvmpipe (≈2–3 s each, whatever the size), and the later "
                 f"sizes reuse the compiled shaders.")
    for size in args.sizes:
        a, b = rows[size, "minimal"], rows[size, "full"]
        lines.append(f"- {size}²: the minimal tree renders in {a['eevee_s'] / b['eevee_s']:.0%} "
                     f"of the full tree's time in EEVEE, {a['cycles_s'] / b['cycles_s']:.0%} in "
                     f"Cycles, {a['numpy_s'] / b['numpy_s']:.0%} in numpy.")
    lines += ["", "Render times exclude the shadow bake (its own column: numpy, K = 64, both "
              "lights), which runs when a light moves, not per render. EEVEE's times here are "
              "mostly a fixed ≈2 s per render under llvmpipe (software OpenGL), so its ratios "
              "are noise; Cycles and numpy show what pruning saves per pixel.",
              "", "The full tree's height map is the built-in test painting: a box with vertical walls "
              "(141 px tall at 1024², a slope of 70 per pixel) under a highlight ramp 0.08 wide. "
              "There the material's float32 UV (±1.5e-5 texel in Cycles) moves the gradient taps "
              "across the wall, and the highlight magnifies that: the few pixels over 1e-3 sit "
              "next to the walls. Smooth relief (the parity suite) stays within 5e-6."]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
