"""Shapes of a painting that moves, against 3D (issue 31, pipeline.md §16): do the made heights
flicker where the drawing does not change, and do they change as the truth does where it does?

A head that turns and blinks over --frames frames, with a box that stands still beside it,
rendered by Cycles (testkit/turning_head.py: true heights, normals and silhouette per frame).
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

    .venv/bin/python benchmarks/frames_stability.py --size 256 --out docs/frames-stability.md
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import command_line, publish  # noqa: E402

from dynpaint_addon.core.inflate import inflate  # noqa: E402
from dynpaint_addon.core.integrate import integrate  # noqa: E402
from dynpaint_addon.core.laplace import components  # noqa: E402
from testkit.turning_head import render_turning_head  # noqa: E402

FLICKER_GOAL = 1e-3


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


def unchanged_parts(h0, h1, a0, a1):
    """The pixels of the figure's parts (4-connected) that are the same in both frames, every
    pixel of them: the drawing does not change there (a pixel of the turning head that
    happens to keep its height is not)."""
    same = (h0 == h1) & (a0 == a1)
    labels, count = components(a0[:, 1:] & a0[:, :-1], a0[1:] & a0[:-1])
    whole = np.bincount(labels.ravel(), ~same.ravel(), count) == 0
    return whole[labels] & a0


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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256, help="frame size in pixels")
    ap.add_argument("--frames", type=int, default=24)
    ap.add_argument("--out", help="also write the Markdown report here")
    args = ap.parse_args(argv)
    truth = render_turning_head(args.size, args.frames)
    rows, still = measure(truth)
    lines = ["# Shapes of a painting that moves, against 3D", "",
             f"`{command_line(__file__, argv)}` — a head that turns ±25° and blinks, a box "
             f"that stands still, {args.frames} frames at {args.size}² rendered by Cycles "
             f"(testkit/turning_head.py); {still} pixel-steps where the truth does not change "
             f"(the box). Flicker: |h(f+1) − h(f)| there, image widths (goal ≤ "
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
    publish(lines, args.out)
    return rows


if __name__ == "__main__":
    main()
