"""Painting on the shape: from a stroke's edit to updated shading and shadows (issue 41).

The built-in test painting (a 16-bit height map) at each --sizes, lit by its sun, built in
Blender as Add builds it. A dab of radius 32 px (a soft cone, 0.05 of the height) is painted
into the shape image's pixels, then `image.update_tag()` and `view_layer.update()` — the
headless contract (docs/addon.md): the time is that call's, from the edit to the painting's
derived images and cos-θ image written back, with the shadows baked at
  - draft: the live level while strokes come (the add-on's live bake runs this same decode
    and bake in its worker) — goals ≤ 33 ms at 1024², ≤ 100 ms at 4096²;
  - final: once the strokes stop — goal ≤ 1 s at 1024².
Then the same with the test painting's point light beside its sun: the final of a dab at most
3× the sun's alone (issue 61; a point light's rays re-traced in the wedge that sees the dab).
Then, at the first of --sizes, Paint Shape's figure mask, Snap to the Painting on (0.01): a
disc of 0.3 image widths, dabs of the same radius painted and erased on its edge (its part
inflated again, the stroke's box snapped again: reported, no goal).
Beside each, in the same run, the same edit with nothing kept from before it (the whole image
decoded and baked again, as before issue 41): the incremental saving. After the dabs, the
painting's cos-θ image is compared with a bake of the whole edited image: the incremental
path must equal it (≤ 1e-6). Times are medians of --dabs dabs at random places, each size
in a process of its own.

    .venv/bin/python benchmarks/paint_latency.py --sizes 1024 4096 --out docs/paint-latency.md
"""
import argparse
import os
import json
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import bpy  # noqa: E402

from report import command_line, publish  # noqa: E402

from dynpaint_addon.blender.bake import shadow_images  # noqa: E402
from dynpaint_addon.blender.state.painted import forget_painted  # noqa: E402
from dynpaint_addon.core.laplace import forget_solved_parts  # noqa: E402
from dynpaint_addon.blender.material.sync import update  # noqa: E402
from testkit.sun_painting import image_pixels, sun_painting  # noqa: E402

GOALS_MS = {("draft", 1024): 33.0, ("draft", 4096): 100.0, ("final", 1024): 1000.0}
POINT_FACTOR = 3.0      # a dab's final with the point light beside the sun (issue 61)
RADIUS, DEPTH = 32, 0.05
FIGURE, SNAP = 0.3, 0.01     # the figure mask's disc (image widths) and its Snap to the Painting


class Canvas:
    """The painting's shape image as numpy pixels, dabbed as a brush dabs it."""

    def __init__(self, img, seed=0):
        self.img = img
        self.px = image_pixels(img)
        self.rng = np.random.default_rng(seed)

    def dab(self, radius=RADIUS, depth=DEPTH):
        """A soft cone of `depth` at a random place (a stroke's dab), written to the image."""
        h, w = self.px.shape[:2]
        cy, cx = self.rng.integers(radius, h - radius), self.rng.integers(radius, w - radius)
        r0, r1, c0, c1 = cy - radius, cy + radius + 1, cx - radius, cx + radius + 1
        y, x = np.ogrid[r0:r1, c0:c1]
        cone = np.clip(1 - np.hypot(x - cx, y - cy) / radius, 0, 1)[..., None]
        part = self.px[r0:r1, c0:c1]
        part[..., :3] = np.clip(part[..., :3] + depth * self.rng.choice((-1, 1)) * cone, 0, 1)
        self.img.pixels.foreach_set(self.px.ravel())
        self.img.update_tag()


def shadow_pixels(mat):
    """Every light's cos-θ image's pixels, one after another."""
    out = []
    for item in mat.dynamic_painting.lights:
        px = np.empty(len(item.shadow.pixels), np.float32)
        item.shadow.pixels.foreach_get(px)
        out.append(px)
    return np.concatenate(out)


def edit_ms(canvas, whole):
    """One dab and the update it causes → ms; whole: nothing kept from before the edit."""
    canvas.dab()
    if whole:
        shadow_images._STILL.clear()
    start = time.perf_counter()
    bpy.context.view_layer.update()
    return (time.perf_counter() - start) * 1000


def all_pixels():
    """{image name: its pixels} of every image with pixels."""
    out = {}
    for img in bpy.data.images:
        if img.has_data and img.size[0]:
            out[img.name] = np.empty(len(img.pixels), np.float32)
            img.pixels.foreach_get(out[img.name])
    return out


def transfer_ms(canvas):
    """What an edit costs in Blender's image API alone: the shape image's pixels read once and
    every image the edit wrote (found as the images whose pixels a dab changed, the shape
    image itself aside) written once, ms (best of 3) — a floor no update that reads and writes
    Blender images from Python can go under."""
    before = all_pixels()
    canvas.dab()
    bpy.context.view_layer.update()
    after = all_pixels()
    written = [bpy.data.images[name] for name, px in after.items()
               if name != canvas.img.name and name in before
               and not np.array_equal(px, before[name])]
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        canvas.img.pixels.foreach_get(after[canvas.img.name])
        for img in written:
            img.pixels.foreach_set(after[img.name])
        best = min(best, time.perf_counter() - start)
    return best * 1000, len(written)


def figure_mask_ms(mat, dabs, seed=0):
    """Paint Shape's figure mask, snapped (see the module's docstring) → (incremental ms, whole
    ms), medians of `dabs` dabs each; whole: the mask's relief, snap, parts and decode
    forgotten before the edit."""
    bpy.ops.dynpaint.paint_shape()
    pt = mat.dynamic_painting.painted
    pt.snap = SNAP
    px = image_pixels(pt.mask)
    h, w = px.shape[:2]
    y, x = np.ogrid[0:h, 0:w]
    rng = np.random.default_rng(seed)

    def stroke(cx, cy, r, value):
        px[np.hypot(x - cx, y - cy) < r, :3] = value
        pt.mask.pixels.foreach_set(px.ravel())
        pt.mask.update_tag()

    stroke(w / 2, h / 2, FIGURE * w, 1.0)
    bpy.context.view_layer.update()
    times = ([], [])
    for i in range(2 * dabs):
        whole = i % 2
        angle = rng.uniform(0, 2 * np.pi)
        stroke(w / 2 + FIGURE * w * np.cos(angle), h / 2 + FIGURE * w * np.sin(angle), RADIUS,
               float(i // 2 % 2))
        if whole:
            forget_painted(mat)
            forget_solved_parts()
            shadow_images._STILL.clear()
        start = time.perf_counter()
        bpy.context.view_layer.update()
        times[whole].append((time.perf_counter() - start) * 1000)
    return tuple(float(np.median(t)) for t in times)


def measure(size, dabs, mask=True, kinds=("sun",)):
    """{level: (incremental ms, whole ms)}, and the largest |Δt| against a whole bake; mask:
    the figure mask's too (figure_mask_ms); kinds: the test painting's lights kept."""
    with tempfile.TemporaryDirectory() as folder:
        mat = sun_painting(folder, size, kinds)
        canvas = Canvas(mat.dynamic_painting.image_shape)
        out = {}
        for level in ("draft", "final"):
            mat.dynamic_painting.shadows.quality = level
            bpy.context.view_layer.update()
            edit_ms(canvas, whole=False)           # the first edit keeps the decode
            out[level] = tuple(float(np.median([edit_ms(canvas, whole) for _ in range(dabs)]))
                               for whole in (False, True))
            out[f"{level} transfers"] = transfer_ms(canvas)
        for _ in range(dabs):                      # then a run of edits, all incremental
            edit_ms(canvas, whole=False)
        incremental = shadow_pixels(mat)
        shadow_images._STILL.clear()
        update(mat, bpy.context.scene, rebake=True, force=True)
        out["error"] = float(np.abs(incremental - shadow_pixels(mat)).max())
        if mask:
            out["mask"] = figure_mask_ms(mat, dabs)
    return out


def measured_alone(size, dabs, mask, kinds=("sun",)):
    """measure() in a fresh process: one size's memory does not slow the next (this machine
    is slow to touch memory a process has not used yet: the 4096² draft took 460 ms alone,
    719 ms after the 1024² run in the same process)."""
    run = subprocess.run([sys.executable, __file__, "--one", str(size), str(dabs),
                          str(int(mask)), ",".join(kinds)],
                         capture_output=True, text=True, check=True)
    return json.loads(run.stdout.strip().splitlines()[-1])


def goal(level, size, ms, sun_ms=None):
    """The goal's words: a level's own (GOALS_MS), or with a point light beside the sun
    (sun_ms: the sun's alone at that level) at most POINT_FACTOR × the sun's alone."""
    if sun_ms is not None:
        if level != "final":
            return "reported"
        return (f"≤ {POINT_FACTOR:g}× the sun's alone ({ms / sun_ms:.1f}×): "
                f"{'met' if ms <= POINT_FACTOR * sun_ms else 'not met'}")
    g = GOALS_MS.get((level, size))
    if g is None:
        return "reported"
    return f"≤ {g:g} ms: {'met' if ms <= g else 'not met'}"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--one"]:                    # (measured_alone's process)
        print(json.dumps(measure(int(argv[1]), int(argv[2]), argv[3] == "1",
                                 tuple(argv[4].split(",")))))
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1024])
    ap.add_argument("--dabs", type=int, default=5)
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    lines = ["# Painting on the shape: stroke latency (issue 41)", "",
             f"`{command_line(__file__, argv)}` — the built-in test painting (16-bit height "
             f"map) lit by its sun; a dab of radius {RADIUS} px at a random place, then "
             "`image.update_tag()` and `view_layer.update()`: the time from the edit to the "
             "painting's derived and cos-θ images written back, median of "
             f"{args.dabs} dabs. Whole: the same edit with nothing kept from before it (the "
             "whole image decoded and baked again), same run. Machine: "
             f"{os.cpu_count()} cores.", "",
             "| size | level | incremental | whole | saving | goal | image API alone |",
             "|---|---|---|---|---|---|---|"]
    errors = []
    for size in args.sizes:
        m = measured_alone(size, args.dabs, mask=size == args.sizes[0])
        both = measured_alone(size, args.dabs, mask=False, kinds=("sun", "point"))
        rows = [(level, m, None) for level in ("draft", "final", "mask") if level in m] + \
            [(level, both, m[level][0]) for level in ("draft", "final")]
        for level, got, sun_ms in rows:
            inc, whole = got[level]
            name = f"final, figure mask (Snap {SNAP:g})" if level == "mask" else level
            name += ", sun + point light" if sun_ms is not None else ""
            floor = got.get(f"{level} transfers")
            floor = (f"{floor[0]:.0f} ms ({floor[1]} image{'s' * (floor[1] != 1)} written)"
                     if floor else "")
            lines.append(f"| {size}² | {name} | {inc:.0f} ms | {whole:.0f} ms | "
                         f"{whole / inc:.1f}× | {goal(level, size, inc, sun_ms)} | {floor} |")
        errors.append(f"{size}²: {m['error']:.1e} (sun), {both['error']:.1e} (sun + point)")
    lines += ["", "Incremental = whole: the largest |Δt| between the cos-θ image after the "
              f"dabs and a bake of the whole edited image: {', '.join(errors)} (goal ≤ 1e-6).",
              "", "Image API alone: the shape image's pixels read once (`foreach_get`) and each "
              "image the edit wrote (its derived images and cos-θ image, at their sizes: a "
              "draft's cos-θ image is the size it baked at) written "
              "once (`foreach_set`), best of 3 — what any update that goes through Blender's "
              "Python image API pays, the bake and the decode apart."]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
