"""A painting with no shape image against true 3D (issue 41, "full-frame paintings against 3D").

The painting: a front-lit Cycles render of each object on its ground (benchmarks/
shape_from_painting.py's scenes, seen from above, no alpha: the whole frame is painted). The
artist paints a figure mask by hand: here the object's true silhouette moved 2 px right and
1 px down and softened (blurred 1.5 px), read at ½. Shapes compared, each baked into cast
shadows under hard suns at 15–60° (the core's final bake at d = 1 px, the normals its own
heights give) against Cycles' truth (N·L × visibility):

- the true height map (what a 3D artist would have);
- the hand mask inflated alone (`make-shape inflate mask.png`);
- the mask inflated with the painting's luminance embossed (`--detail D --detail-image
  painting.png`), D = 0.005, 0.01, 0.02 image widths per unit of luminance;
- the same at D = 0.01 with its rim lifted to the true rim's height by a one-pixel bevel (what
  an artist who knows the figure stands on the ground can set; the true height read from 3D,
  so a bound, not a method);
- the hand mask snapped onto the painting's edges within SNAP image widths (`--snap`,
  core/snap.py: the painting shows where the outline is), inflated;
- the same two with the tube profile (`--profile tube`: round cross-sections as wide as the
  figure, where the default round profile makes a long part √2 too tall); and the true
  silhouette with it (a bound: what the hand's slip costs);
- the hand mask with the flat profile (`--profile flat`: steep rims, a plateau);
- the best the hand mask gives with any profile, height and bevel at its rim (BOUND_GRID; a
  bound, chosen on the truth itself): what no choice of these options can pass;
- the flat-profile mask with height painted on it as Paint Shape's height layer holds it:
  the truth's difference from it, blurred as soft brushes paint (σ = PAINTED image widths) —
  a bound (the painter knows the truth), what painted height must hold to meet the goal;
- the figure painted as n = NESTED nested parts, each a mask painted over the last (Monster
  Mash's layered parts): the truth's region above each of n evenly spaced heights, slipped
  and softened as the hand's mask is, each inflated flat and raised one step (top / n) — a
  bound (the parts follow the truth's contour lines), what masks alone can give at best.

Per object: mean |t − 3D| and the IoU of the cast shadows (each shape's own N·L decides what
faces the sun). Goals (issue 41): mask + detail better than the mask alone on every object;
≥ 0.85 × the true height map's IoU on the round objects (sphere, torus, Suzanne's head).

    .venv/bin/python benchmarks/no_shape_image.py --size 256 --out docs/no-shape-numbers.md
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import ground_truth as gt  # noqa: E402  (imports bpy)
from report import command_line, publish  # noqa: E402
from shape_from_painting import RESTING, SMOOTH, border_depth, scene_maps  # noqa: E402

from dynpaint_addon.core.inflate import inflate  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.sampling import gaussian_blur  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from dynpaint_addon.core.shape import normals_from_height_px  # noqa: E402
from dynpaint_addon.core.snap import snap_to_edges  # noqa: E402
from dynpaint_addon.shapes.relief import with_effects  # noqa: E402

DETAILS = (0.005, 0.01, 0.02)
SHIFT = (2, -1)          # the hand mask's offset from the true silhouette: x, y pixels
SOFT = 1.5               # its edge's blur, pixels
GOAL_RATIO = 0.85
ALONE = "hand mask, inflated"
TUBE = "hand mask, tube"
SNAP = 0.01              # image widths the hand mask is snapped within (--snap)
SNAPPED = f"hand mask snapped to the painting ({SNAP:g})"
TRUE_TUBE = "true silhouette, tube (a bound)"
FLAT = "hand mask, flat"
BEST = "hand mask, best profile, height and bevel (a bound, chosen on the truth)"
PAINTED = (0.005, 0.01, 0.02)   # image widths: the soft brushes' blur of the painted height
PAINTED_ROW = "hand mask, flat, + painted height (a bound: the truth's difference blurred by σ)"
NESTED = (2, 4, 6)      # nested parts painted (a part over the last, at the truth's contours)
NESTED_ROW = "hand masks in nested parts at the truth's contours (a bound), flat steps"
# the options searched for BEST: profile × height × bevel height (image widths, 3 px wide)
BOUND_GRID = {"profile": ("round", "soft", "flat", "tube"), "height": (0.7, 1.0, 1.4),
              "bevel": (0.0, 0.03, 0.07)}


def hand_mask(figure):
    """A region (H, W) bool as a hand paints it: moved by SHIFT and softened → bool."""
    moved = np.roll(np.roll(figure.astype(np.float64), SHIFT[0], axis=1), SHIFT[1], axis=0)
    return gaussian_blur(moved, SOFT) >= 0.5


def nested_parts(z, index, n):
    """The figure painted as n nested parts (NESTED_ROW; a bound): part k the truth's region
    above k/n of its top, as a hand paints it, inflated flat to a plateau one step high."""
    figure, top = index > 0, float(z.max())
    heights = np.zeros_like(z)
    for k in range(n):
        part = inflate(hand_mask(figure & (z > top * k / n)), "flat").height
        heights += part / max(float(part.max()), 1e-12) * (top / n)
    return heights


def shapes(z, index, painting, mask):
    """{name: heights (image widths)} of the shapes compared; mask: hand_mask(index > 0)."""
    size = z.shape[1]
    out = {"true height map": z, ALONE: inflate(mask).height}
    for d in DETAILS:
        out[f"hand mask + detail {d:g}"] = inflate(mask, detail=d, luminance=painting).height
    # what an artist can add who knows the figure stands on the ground: its rim lifted to
    # the true rim's height by a one-pixel bevel (a wall; as integrate's --depth)
    lift = border_depth(z, index)
    out[f"hand mask + detail 0.01, rim lifted {lift:.3f}"] = with_effects(
        out["hand mask + detail 0.01"], mask, 1.0 / size, lift, "linear")
    snapped = snap_to_edges(mask, painting, SNAP * size)
    out[SNAPPED] = inflate(snapped).height
    out[TUBE] = inflate(mask, "tube").height
    out[SNAPPED + ", tube"] = inflate(snapped, "tube").height
    out[TRUE_TUBE] = inflate(index > 0, "tube").height
    return out


def mask_options(mask):
    """{(profile, height, bevel): heights} of BOUND_GRID: every shape a mask alone makes."""
    size = mask.shape[1]
    out = {}
    for profile in BOUND_GRID["profile"]:
        for height in BOUND_GRID["height"]:
            z = inflate(mask, profile, height).height
            for lift in BOUND_GRID["bevel"]:
                out[profile, height, lift] = with_effects(z, mask, 3.0 / size, lift, "round")
    return out


def painted(z, base, mask, sigma):
    """`base` with height painted on it inside `mask` (Paint Shape's height layer): the
    truth `z`'s difference from it, blurred by σ image widths — a bound, the painter knowing
    the truth, its strokes as soft as σ."""
    return base + np.where(mask, gaussian_blur(z - base, sigma * z.shape[1]), 0.0)


def best(ratios):
    """The ratio of the best of the mask's options (its name carries the options)."""
    return next(r for shape, r in ratios.items() if shape.startswith(BEST))


def painted_ratio(ratios, sigma):
    """The ratio of the painted-height shape at σ."""
    return ratios[f"{PAINTED_ROW}, σ {sigma:g}"]


def nested_ratio(ratios, n):
    """The ratio of the figure painted as n nested parts."""
    return ratios[f"{NESTED_ROW}, n = {n}"]


def lifted(ratios):
    """The ratio of the shape whose rim was lifted (its name carries the lift)."""
    return next(r for shape, r in ratios.items() if "lifted" in shape)


def measure(objects, size, offset_px, steps, folder):
    """{shape: (mean |t − 3D|, cast-shadow IoU)} over the suns."""
    scene, z, nworld, _, index = scene_maps(objects, size, folder)
    painting = gt.render_truth(scene, folder, 90, 0)        # front-lit: the painted picture
    mask = hand_mask(index > 0)
    made = shapes(z, index, painting, mask)
    options = mask_options(mask)
    made[FLAT] = options["flat", 1.0, 0.0]       # (the grid's flat profile, no bevel)
    for sigma in PAINTED:
        made[f"{PAINTED_ROW}, σ {sigma:g}"] = painted(z, made[FLAT], mask, sigma)
    for n in NESTED:
        made[f"{NESTED_ROW}, n = {n}"] = nested_parts(z, index, n)
    made.update(options)
    acc = {}
    for elevation, azimuth in gt.SUNS:
        direction = np.array(gt.sun_direction(elevation, azimuth))
        truth = gt.render_truth(scene, folder, elevation, azimuth)
        ndl_true = np.clip(nworld @ direction, 0, 1)
        light = Light("sun", tuple(direction))
        for name, heights in made.items():
            n = normals_from_height_px(heights * size)
            t = cos_theta_shadow(n, light, offset_px / size, steps, heights_px=heights * size)
            a = gt.cast_shadow(truth, ndl_true)
            b = gt.cast_shadow(t, np.clip(n @ direction, 0, 1))
            iou = (a & b).sum() / max((a | b).sum(), 1)
            acc.setdefault(name, []).append((float(np.abs(t - truth).mean()), float(iou)))
    res = {k: (float(np.mean([e for e, _ in v])), float(np.mean([i for _, i in v])))
           for k, v in acc.items()}
    top = max(options, key=lambda k: res[k][1])
    res[f"{BEST}: {top[0]}, height {top[1]:g}, bevel {top[2]:g}"] = res[top]
    return {k: v for k, v in res.items() if k not in options}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--steps", type=int, default=64)
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    folder = tempfile.mkdtemp()
    lines = ["# A painting with no shape image, against 3D (issue 41)", "",
             f"`{command_line(__file__, argv)}` — {args.size}², each object on its ground "
             f"rendered front-lit by Cycles as the painting (no alpha); the figure mask painted "
             f"by hand: the true silhouette moved {SHIFT[0]} px right and {-SHIFT[1]} px down, "
             f"softened by {SOFT:g} px; cast shadows under hard suns at "
             f"{', '.join(f'{e}°/{a}°' for e, a in gt.SUNS)} (elevation/azimuth), d = 1 px, "
             f"K = {args.steps}, against Cycles' N·L × visibility. Goals: the mask with detail "
             f"better than the mask alone on every object; ≥ {GOAL_RATIO} × the true height "
             f"map's IoU on the round objects.", "",
             "| object | shape | mean \\|t − 3D\\| | cast-shadow IoU | × true | goal |",
             "|---|---|---|---|---|---|"]
    ratio, worse = {}, []
    for name, objects in {**SMOOTH, **RESTING}.items():
        res = measure(objects, args.size, 1.0, args.steps, folder)
        true_iou = res["true height map"][1]
        ratio[name] = {shape: iou / max(true_iou, 1e-9) for shape, (_, iou) in res.items()}
        for shape, (err, iou) in res.items():
            goal = ""
            if ("detail" in shape and "lifted" not in shape) or SNAPPED in shape:
                alone = res[TUBE if "tube" in shape else ALONE]
                better = err <= alone[0] and iou >= alone[1]
                if SNAPPED in shape and not better:
                    worse.append(f"the {name} with the {'tube' if 'tube' in shape else 'round'} "
                                 "profile")
                goal = (f"better than the mask alone: {'met' if better else 'not met'}; "
                        f"≥ {GOAL_RATIO} × true: "
                        f"{'met' if iou >= GOAL_RATIO * true_iou else 'not met'}")
            lines.append(f"| {name} | {shape} | {err:.4f} | {iou:.3f} | "
                         f"{ratio[name][shape]:.2f} | {goal} |")
    resting = ratio["sphere resting on the ground"]
    torus, head, sphere = ratio["torus"], ratio["Suzanne"], ratio["sphere"]
    lines += ["", "Reading it: the mask is what matters. A hand's mask inflated gives a sphere "
              f"nearly its true shadows ({sphere[ALONE]:.2f} of the true map's IoU), a torus "
              f"{torus[ALONE]:.2f} and a head {head[ALONE]:.2f}. Two things cost the torus. "
              "The round profile makes a ring's tube √2 too tall (core/inflate.py): the tube "
              f"profile takes it to {torus[TUBE]:.2f}, and to {torus[TRUE_TUBE]:.2f} from the "
              "true silhouette. The rest is the hand's slip of two pixels, which moves a thin "
              "part's shadows off the truth's: snapped onto the painting's edges (the "
              "outline is where its luminance changes most), the hand's mask gives the "
              f"sphere {sphere[SNAPPED + ', tube']:.2f} and the torus "
              f"{torus[SNAPPED + ', tube']:.2f} with the tube profile — the goal ≥ "
              f"{GOAL_RATIO} met on both. A head seen from the front is no round cross-sections "
              "of its outline but a plateau with steep walls (Suzanne's face stands about 0.2 "
              "image widths high within 0.04 of its rim): the flat profile gives it "
              f"{head[FLAT]:.2f}, and the best of every profile, height and bevel at its rim "
              f"(chosen on the truth itself) {best(head):.2f}. The rest of "
              "its depth is in features inside the outline (brow, eyes, nose) that a mask "
              "does not hold, so its goal is not "
              "met by any shape made from a mask — not even by masks painted as nested "
              "parts along the truth's own contour lines, each a plateau one step above the "
              "last (" + ", ".join(f"{nested_ratio(head, n):.2f} with {n}" for n in NESTED)
              + " parts: a bound). Painted on the flat shape (Paint Shape's "
              "height layer; here the truth's difference from it, blurred as soft brushes "
              "paint: a bound) the head gets " + ", ".join(
                  f"{painted_ratio(head, sigma):.2f} at σ {sigma:g}" for sigma in PAINTED)
              + " image widths: its shadows are cast by sharp features (and soft strokes "
              f"across the rim cost a sphere: {painted_ratio(sphere, PAINTED[-1]):.2f} at "
              f"σ {PAINTED[-1]:g}). The painting's luminance embossed as detail "
              "changes the shadows by little either way — a front-lit painting's light and "
              "dark follow the shape too smoothly to add a feature the inflation lacks; its "
              "edges are what it adds (snapped: better than the mask alone on every object "
              f"with either profile{' but ' + ', '.join(worse) if worse else ''}). What an "
              "object standing on the ground lacks is its "
              "wall: the rim lifted to its true height (a bevel one pixel wide) brings the "
              f"resting sphere from {resting[ALONE]:.2f} to {lifted(resting):.2f} of the true "
              f"map's IoU, and costs a sunk one ({lifted(sphere):.2f}: its rim is at the "
              "ground)."]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
