"""Shapes of a painting that moves, against 3D (issue 31, pipeline.md §16): do the made heights
flicker where the drawing does not change, and do they change as the truth does where it does?

A head that turns and blinks over --frames frames, with a box and a ball that stand still
beside it, rendered by Cycles (testkit/turning_head.py: true heights, normals and silhouette per
frame).
Each frame's shape is made as `make-shape` makes it — inflation from the silhouette (round and
flat profiles), integration of the true normals cut at the silhouette — two ways, in the same
run:
  - by parts (today's): each connected part solved and reshaped alone, the sequence's heights
    on one floor (core/laplace.solve_parts, shapes.frames);
  - whole image (the baseline: before §16): one solve per frame, the profile's tallest point
    and the integration's lowest point taken over the whole frame.
Measured on consecutive frames f, f + 1:
  - flicker: |h_{f+1} − h_f| of the made heights where the truth does not change (the parts
    of the figure whose true heights are equal in both frames, every pixel of them: the box)
    — goal ≤ 1e-3 image widths (the largest);
  - motion: the mean |h_{f+1} − h_f| over the figure, made against the truth's (a ratio: 1 =
    the made shape moves as much as the true one; reported).

Then the painting itself (issue 39): the true normal maps, with their alpha, as a moving
painting's shape, rendered with the defaults (the integrated relief, final shadows) under suns
at 15–60° and a point light, by the numpy core every frame and by Cycles (--cycles frames,
through the add-on). Flicker of the render: max |c_{f+1} − c_f| over the still parts' pixels
whose shadow rays pass over nothing that changes (out of the moving head's reach) — goal ≤ 1e-4.
The cos-θ term beside it, marched two ways in the same run: each ray's march ending where its
own path lets it (today's, core/path_bounds.py) and at the whole image's highest point (before).

    .venv/bin/python benchmarks/frames_stability.py --size 256 --out docs/frames-stability.md
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import command_line, publish  # noqa: E402

from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.core import pipeline  # noqa: E402
from dynpaint_addon.core.inflate import inflate  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.integrate import integrate  # noqa: E402
from dynpaint_addon.core.laplace import components  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from testkit.turning_head import render_turning_head  # noqa: E402


def sun(elevation, azimuth):
    e, a = np.radians(elevation), np.radians(azimuth)
    return Light("sun", (np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)))


LIGHTS = {"sun 15° from 250°": sun(15, 250), "sun 30° from 200°": sun(30, 200),
          "sun 45° from 120°": sun(45, 120), "sun 60° from 300°": sun(60, 300),
          "point light": Light("point", (-0.45, -0.4, 0.25))}

FLICKER_GOAL = 1e-3
RENDER_GOAL = 1e-4


def made_heights(truth, method, by_parts):
    """Every frame's made heights (frames, H, W), image widths."""
    masks = truth["alpha"] >= 0.5
    out = []
    for f, mask in enumerate(masks):
        if method.startswith("inflate"):
            profile = method.split()[-1]
            out.append(inflate(mask, profile, by_parts=by_parts).height)
        elif by_parts:                       # one floor for the whole sequence (shapes.frames)
            out.append(integrate(truth["normal"][f], mask, floor=0.0).height)
        else:
            out.append(integrate(truth["normal"][f], mask, by_parts=False).height)
    heights = np.asarray(out)
    if method == "integrate" and by_parts:
        heights = heights - heights.min()
    return heights


def whole_parts(same, alpha):
    """The pixels of the figure's parts (4-connected, in `alpha`) every pixel of which is
    `same`: the drawing does not change there (a pixel of the turning head that happens to
    stay the same is not)."""
    labels, count = components(alpha[:, 1:] & alpha[:, :-1], alpha[1:] & alpha[:-1])
    whole = np.bincount(labels.ravel(), ~same.ravel(), count) == 0
    return whole[labels] & alpha


def unchanged_parts(h0, h1, a0, a1):
    """The figure's parts whose heights are the same in both frames, every pixel of them."""
    return whole_parts((h0 == h1) & (a0 == a1), a0)


def measure(truth):
    """[(method, way, largest flicker, mean flicker, motion ratio, the ratio at the truth's
    scale, the frame's ratio furthest from 1)]."""
    true_h, alpha = truth["height"], truth["alpha"] >= 0.5
    still = np.array([unchanged_parts(true_h[f], true_h[f + 1], alpha[f], alpha[f + 1])
                      for f in range(len(true_h) - 1)])
    figure = alpha[1:] | alpha[:-1]
    true_motion = np.array([np.abs(true_h[f + 1] - true_h[f])[figure[f]].mean()
                            for f in range(len(true_h) - 1)])
    true_level = true_h[alpha].mean()
    rows = []
    for method in ("inflate round", "inflate flat", "integrate"):
        for way, by_parts in (("by parts", True), ("whole image", False)):
            h = made_heights(truth, method, by_parts)
            step = np.abs(h[1:] - h[:-1])
            motion = np.array([step[f][figure[f]].mean() for f in range(len(step))])
            ratio = motion / np.maximum(true_motion, 1e-12)
            scale = true_level / h[alpha].mean()      # its relief's size, the truth's
            rows.append((method, way, float(step[still].max()) if still.any() else 0.0,
                         float(step[still].mean()) if still.any() else 0.0,
                         float(motion.mean() / true_motion.mean()),
                         float(motion.mean() / true_motion.mean() * scale),
                         float(ratio[np.argmax(np.abs(np.log(np.maximum(ratio, 1e-12))))])))
    return rows, int(still.sum())


def painting_frames(truth):
    """Each frame's images: the true normal map with its alpha as the shape, a flat dark and
    bright (what changes in the render is the shading alone)."""
    frames = []
    for n, alpha in zip(truth["normal"], truth["alpha"]):
        h, w = alpha.shape
        frames.append({"shape": ImageData(np.dstack([(n + 1) / 2, alpha]).astype(np.float32),
                                          32, "normal"),
                       "dark": ImageData(np.full((h, w, 3), 0.2, np.float32), 32, "dark"),
                       "bright": ImageData(np.ones((h, w, 3), np.float32), 32, "bright")})
    return frames


def defaults():
    p = params.defaults()
    p.shape.kind, p.shadows.enabled = "normal", True
    return p


def out_of_reach(moving, light):
    """(H, W) bool: pixels whose shadow ray (toward a sun, to the image's edge; toward a point
    light's foot, to it) passes over no pixel within 2 px of one that changes (`moving`)."""
    h, w = moving.shape
    near = moving.copy()
    for axis in (0, 1):
        grown = near.copy()
        for step in (1, 2):
            grown |= np.roll(near, step, axis) | np.roll(near, -step, axis)
        near = grown
    y, x = np.mgrid[0:h, 0:w] + 0.5
    if light.kind == "sun":
        dx, dy = light.vector[0], light.vector[1]
        length = np.full((h, w), float(h + w))
    else:
        fx, fy, _ = light.position_px(h, w)
        dx, dy = fx - x, fy - y
        length = np.hypot(dx, dy)
    norm = np.hypot(dx, dy)
    with np.errstate(divide="ignore", invalid="ignore"):      # at a point light's foot: none
        ux, uy = np.where(norm > 0, dx / norm, 0), np.where(norm > 0, dy / norm, 0)
    clear = np.ones((h, w), bool)
    for s in np.arange(0, h + w, 0.5):
        px, py = x + s * ux, y + s * uy
        on = (s <= length) & (px >= 0) & (px < w) & (py >= 0) & (py < h)
        i = np.clip(py.astype(int), 0, h - 1)
        j = np.clip(px.astype(int), 0, w - 1)
        clear &= ~(on & near[i, j])
    return clear


def still_pixels(truth):
    """The still parts (every pixel of them the same in every frame) and what changes."""
    alpha, normal = truth["alpha"] >= 0.5, truth["normal"]
    same = np.all(alpha == alpha[0], axis=0) & np.all(
        np.abs(normal - normal[0]).max(axis=-1) == 0, axis=0)
    return whole_parts(same, alpha[0]), ~same


def render_flicker(truth):
    """[(light, pixels measured, render flicker, cos-θ flicker with the path's end, with the
    image's)] over every frame, numpy core, the defaults."""
    frames, p = painting_frames(truth), defaults()
    still, moving = still_pixels(truth)
    decoded = [pipeline.shape_normals(f["shape"], p, relief=True) for f in frames]
    rows = []
    for name, light in LIGHTS.items():
        where = still & out_of_reach(moving, light)
        shaded = np.asarray([pipeline.render(f, [light], p).rgba[..., :3] for f in frames])
        terms = {bounds: np.asarray([cos_theta_shadow(n, light, p.shadows.offset,
                                                      p.shadows.steps, heights_px=z,
                                                      slopes=sl, reach=p.shadows.reach,
                                                      bounds=bounds)
                                     for n, z, sl in decoded])
                 for bounds in ("path", "image")}

        def worst(a):
            return float(np.abs(np.diff(a, axis=0))[:, where].max()) if where.any() else 0.0
        rows.append((name, int(where.sum()), worst(shaded),
                     worst(terms["path"]), worst(terms["image"])))
    return rows


def cycles_flicker(truth, frames, folder):
    """{light: render flicker} of the first `frames` frames rendered by Cycles through the
    add-on (a moving painting: its shape a sequence of EXR files; each frame's shadows baked
    as a render bakes them), on the same pixels as render_flicker."""
    import bpy
    from dynpaint_addon.blender.headless import build_recipe_scene
    from dynpaint_addon.blender.scenes.painting_scene import (exact_render_settings,
                                                              output_settings)
    from dynpaint_addon.inputs.imageio import read_image, write_png
    from dynpaint_addon.inputs.recipe import load_recipe
    from testkit.animated import write_sequence
    still, moving = still_pixels(truth)
    shapes = [np.dstack([(n + 1) / 2, a]) for n, a in zip(truth["normal"][:frames],
                                                           truth["alpha"][:frames])]
    write_sequence(os.path.join(folder, "normal_####.exr"), shapes)
    h, w = truth["alpha"].shape[1:]
    write_png(os.path.join(folder, "dark.png"), np.full((h, w, 3), 0.2), bits=16)
    write_png(os.path.join(folder, "bright.png"), np.ones((h, w, 3)), bits=16)
    out = {}
    for name, light in LIGHTS.items():
        key = "direction" if light.kind == "sun" else "position"
        path = os.path.join(folder, "painting.toml")
        with open(path, "w") as fh:
            fh.write('[images]\nshape = "normal_####.exr"\ndark = "dark.png"\nbright = '
                     '"bright.png"\n[shape]\nkind = "normal"\n[shadows]\nenabled = true\n'
                     f'[[lights]]\ntype = "{light.kind}"\n{key} = {list(light.vector)}\n')
        build_recipe_scene(load_recipe(path))
        scene = bpy.context.scene
        exact_render_settings(scene, "cycles")
        shown = []
        for f in range(1, frames + 1):
            scene.frame_set(f)
            output_settings(scene, os.path.join(folder, f"frame_{f}.exr"))
            bpy.ops.render.render(write_still=True)
            shown.append(read_image(os.path.join(folder, f"frame_{f}.exr")).pixels[..., :3])
        where = still & out_of_reach(moving, light)
        out[name] = float(np.abs(np.diff(np.asarray(shown), axis=0))[:, where].max())
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256, help="frame size in pixels")
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--cycles", type=int, default=6, metavar="FRAMES",
                    help="frames rendered by Cycles through the add-on (0: none)")
    ap.add_argument("--out", help="also write the Markdown report here")
    args = ap.parse_args(argv)
    truth = render_turning_head(args.size, args.frames, sphere=True)
    rows, still = measure(truth)
    lines = ["# Shapes of a painting that moves, against 3D", "",
             f"`{command_line(__file__, argv)}` — a head that turns ±25° and blinks, a box "
             f"and a ball that stand still, {args.frames} frames at {args.size}² rendered by Cycles "
             f"(testkit/turning_head.py); {still} pixel-steps where the truth does not change "
             f"(the box and the ball). Flicker: |h(f+1) − h(f)| there, image widths (goal ≤ "
             f"{FLICKER_GOAL:g}, the largest). Motion: mean |h(f+1) − h(f)| over the figure, "
             f"made ÷ true (1 = moves as the truth moves; the frame furthest from 1 beside "
             f"it); *at the truth's scale*: the made relief first scaled to the truth's mean "
             f"height (an integrated cut-out is taller than the truth: its rim's steep normals "
             f"raise it). *By parts* is make-shape's way since pipeline.md §16; *whole image* "
             f"the baseline, one solve per frame as before.", "",
             "| method | way | flicker, largest | flicker, mean | goal | motion, made ÷ true "
             "| at the truth's scale | furthest frame |", "|---|---|---|---|---|---|---|---|"]
    for method, way, worst, mean, motion, scaled, furthest in rows:
        met = "met" if worst <= FLICKER_GOAL else "not met"
        lines.append(f"| {method} | {way} | {worst:.2e} | {mean:.2e} | ≤ {FLICKER_GOAL:g}: "
                     f"{met} | {motion:.2f} | {scaled:.2f} | {furthest:.2f} |")
    flicker = render_flicker(truth)
    with tempfile.TemporaryDirectory() as folder:
        cycles = cycles_flicker(truth, args.cycles, folder) if args.cycles > 1 else {}
    lines += ["", "## The painting rendered", "",
              f"The true normal maps with their alpha as a moving painting's shape, rendered "
              f"with the defaults (the integrated relief, final shadows: at this size the K = "
              f"{defaults().shadows.steps} march) by the numpy core, every frame. Flicker: max "
              f"|c(f+1) − c(f)| of the rendered colour over the still parts' pixels out of the "
              f"moving head's reach (their shadow rays pass over nothing that changes); goal ≤ "
              f"{RENDER_GOAL:g}. The cos-θ term beside it, each ray's march ending where its own "
              f"path lets it (today's, core/path_bounds.py) and where the whole image's highest "
              f"point does (before: a part that did not change was marched with other steps "
              f"whenever the head rose).", "",
              "| light | pixels | numpy render flicker | Cycles render flicker (first "
              f"{args.cycles} frames) | goal | cos-θ, the path's end | cos-θ, the image's end "
              "(before) |", "|---|---|---|---|---|---|---|"]
    for name, count, shade, path, image in flicker:
        worst = max(shade, cycles.get(name, 0.0))
        met = "met" if worst <= RENDER_GOAL else "not met"
        seen = f"{cycles[name]:.1e}" if name in cycles else "—"
        lines.append(f"| {name} | {count} | {shade:.1e} | {seen} | ≤ {RENDER_GOAL:g}: {met} | "
                     f"{path:.1e} | {image:.1e} |")
    publish(lines, args.out)
    return rows, flicker, cycles


if __name__ == "__main__":
    main()
