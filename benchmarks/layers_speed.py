"""Layers that shadow each other: what the layers cost (issue 30, pipeline.md §15).

The built-in layered test scene (testpainting.write_test_scene: the test painting behind, a
ring card, a star with a dome's relief in front) at --size, a sun:
  - final: every layer's t = t_own·T (core.layers.bake_scene) against the baseline in the
    same run, the same images baked each as a painting alone (their own §6 terms, nothing in
    front) — goal ≤ 1.5×;
  - live: one update while a light is dragged (Scene.bake at draft quality, the scene's inputs
    prepared once as the add-on keeps them, each layer's t at its own size as the add-on
    writes it: the images enlarge it as they are sampled) — goal ≤ 50 ms; beside it the same
    enlarged to the layers' size in numpy (as it was before issue 62), reported; and what the
    artist waits for in Blender, the drag's draft baked and written into the layers' images
    on the main thread (layers.bake_group_live, the scene added with Add › Layered), reported;
  - peak memory (tracemalloc) of the final against a single layer's own final — goal ≤ 2×;
  - 8 layers (the documented maximum): the scene's cards repeated at more depths, reported.
Times are the best of --runs.

    .venv/bin/python benchmarks/layers_speed.py --size 1024 --out docs/layers-speed.md
"""
import copy
import os
import sys
import tempfile
import tracemalloc

import bpy
import numpy as np
from mathutils import Matrix

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import best, command_line, met, publish, size_and_runs  # noqa: E402

from dynpaint_addon import blender  # noqa: E402
from dynpaint_addon.blender.bake.layers import bake_group_live  # noqa: E402

from dynpaint_addon.core.layers import Scene, bake_scene  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.pipeline import prepare, shadow_term  # noqa: E402
from dynpaint_addon.inputs.recipe import load_layers, load_recipe  # noqa: E402
from dynpaint_addon.inputs.testpainting import write_test_scene  # noqa: E402

SUN = Light("sun", (0.55, 0.35, 0.76))
GOALS = {"final": 1.5, "live_ms": 50.0, "memory": 2.0}


def peak_bytes(fn):
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak


def alone(layers, light):
    """Each layer baked as a painting by itself: its own §6 term, nothing in front."""
    for layer in layers:
        ready = prepare(layer.images, layer.p)
        shadow_term(ready.n, ready.z_px, ready.slopes, light, layer.p)


def eight(layers):
    """The scene's layers and its two fronts repeated at more depths: 8 layers."""
    out = list(layers)
    for j in range(5):
        extra = copy.copy(layers[1 + j % 2])
        extra.name, extra.depth = f"{extra.name} {j + 2}", layers[2].depth + 0.06 * (j + 1)
        out.append(extra)
    return out


def blender_drag(recipe, runs):
    """Seconds of one drag's update in Blender (the best of `runs` after two): the scene
    added as Add › Layered adds it, its key light turned a little before each."""
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    bpy.ops.dynpaint.add_layered(filepath=recipe)
    parent, key = bpy.context.object, bpy.data.objects["Key"]

    def dragged():
        key.matrix_world = Matrix.Rotation(0.03, 4, "X") @ key.matrix_world
        bake_group_live(parent)
    best(dragged, 2)
    return best(dragged, runs)


def measure(size, runs):
    folder = tempfile.mkdtemp()
    recipe = write_test_scene(folder, size)
    layers = load_layers(load_recipe(recipe))
    base = best(lambda: alone(layers, SUN), runs)
    final = best(lambda: bake_scene(layers, SUN), runs)
    scene = Scene(layers)
    angle = [0.0]

    def dragged(own_size=True):       # the light moved a little before each update
        angle[0] += 0.05
        c, s = np.cos(angle[0]), np.sin(angle[0])
        x, y, z = SUN.vector
        scene.bake(Light("sun", (c * x - s * y, s * x + c * y, z)), quality="draft",
                   own_size=own_size)
    dragged()                 # (the first update also builds the occluders)
    live = best(dragged, max(runs, 5))
    live_enlarged = best(lambda: dragged(False), max(runs, 5))
    # the baseline of a drag: each layer's own draft bake alone (what the layers cost before
    # any of them shadows another), the inputs prepared once as well
    ready = [prepare(layer.images, layer.p) for layer in layers]
    draft = [copy.deepcopy(layer.p) for layer in layers]
    for p in draft:
        p.shadows.quality = "draft"
    live_alone = best(lambda: [shadow_term(r.n, r.z_px, r.slopes, SUN, p)
                               for r, p in zip(ready, draft)], max(runs, 5))
    mem_one = max(peak_bytes(lambda: alone([layer], SUN)) for layer in layers)
    mem_scene = peak_bytes(lambda: bake_scene(layers, SUN))
    many = eight(layers)
    base8 = best(lambda: alone(many, SUN), 1)
    final8 = best(lambda: bake_scene(many, SUN), 1)
    in_blender = blender_drag(recipe, max(runs, 5))
    return dict(base=base, final=final, live=live, live_enlarged=live_enlarged,
                in_blender=in_blender,
                live_alone=live_alone, mem_one=mem_one,
                mem_scene=mem_scene,
                base8=base8, final8=final8)


def main(argv=None):
    args = size_and_runs(__doc__, argv)
    m = measure(args.size, args.runs)
    ratio, mem = m["final"] / m["base"], m["mem_scene"] / m["mem_one"]
    live_ms = m["live"] * 1000
    lines = ["# Layers: what they cost (issue 30)", "",
             f"`{command_line(__file__, argv)}` — the built-in layered test scene at "
             f"{args.size}² (3 layers: the test painting, a ring card, a star with a dome), a "
             f"sun; best of {args.runs}. Baseline: the same images baked each as a painting "
             f"alone (its own §6 term, nothing in front), the same run.", "",
             "| what | measured | baseline | ratio | goal |", "|---|---|---|---|---|",
             f"| final, 3 layers | {m['final']:.2f} s | {m['base']:.2f} s | {ratio:.2f}× | "
             f"≤ {GOALS['final']}×: {met(ratio <= GOALS['final'])} |",
             f"| live update while a light is dragged (draft, at its own size) | "
             f"{live_ms:.0f} ms | "
             f"{m['live_alone'] * 1000:.0f} ms (each layer's own draft bake) | "
             f"{m['live'] / m['live_alone']:.2f}× | "
             f"≤ {GOALS['live_ms']:g} ms: {met(live_ms <= GOALS['live_ms'])} |",
             f"| the same, each t enlarged to its layer's size in numpy (before issue 62) | "
             f"{m['live_enlarged'] * 1000:.0f} ms | {m['live_alone'] * 1000:.0f} ms | "
             f"{m['live_enlarged'] / m['live_alone']:.2f}× | reported |",
             f"| the drag in Blender: the draft baked and written into the layers' images "
             f"(main thread) | {m['in_blender'] * 1000:.0f} ms | – | – | reported |",
             f"| peak memory of the final | {m['mem_scene'] / 2**20:.0f} MiB | "
             f"{m['mem_one'] / 2**20:.0f} MiB (one layer) | {mem:.2f}× | "
             f"≤ {GOALS['memory']}×: {met(mem <= GOALS['memory'])} |",
             f"| final, 8 layers | {m['final8']:.2f} s | {m['base8']:.2f} s | "
             f"{m['final8'] / m['base8']:.2f}× | reported |"]
    publish(lines, args.out)
    return m


if __name__ == "__main__":
    main()
