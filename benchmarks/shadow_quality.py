"""The shadow bake's speed against its accuracy, per quality level (issue 4), in one run.

Tall relief (the built-in height map raised to half an image width), suns from 15° to 60°, a
point light, and the same relief as a normal map. Every quality level is timed (the bake
itself, no file I/O) and compared with the reference (K = 1024, float64); the baseline is the
straightforward march (one bilinear gather per pixel per step, K = 64, float32) measured in the
same run. Also: the live bake's latency from a light change to the updated image, and the
time and peak memory of a final bake at 4096². Writes a Markdown page and an SVG chart.

    .venv/bin/python benchmarks/shadow_quality.py --size 1024 --out docs/shadow-quality.md
    .venv/bin/python benchmarks/shadow_quality.py --cases sun     # the suns' timings only
"""
import argparse
import math
import os
import platform
import sys
import time
import tracemalloc

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import publish  # noqa: E402

from dynpaint_addon.core.bake import bake  # noqa: E402
from dynpaint_addon.core.crossing_blocks import MAX_TABLE_BYTES  # noqa: E402
from dynpaint_addon.core.integrate import integrate  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.shadow import ShadowStats, cos_theta_shadow  # noqa: E402
from dynpaint_addon.core.shape import (height_field_px, normals_from_height_px,  # noqa: E402
                                       slopes_from_normals)
from dynpaint_addon.inputs.testpainting import builtin_images  # noqa: E402

RELIEF = 0.5          # image widths: "tall relief, up to half the image width high"
OFFSET = 0.01
LEVELS = ("draft", "preview", "final")
RUNS = 3              # each time is the best of RUNS runs


def sun(elevation, azimuth):
    e, a = math.radians(elevation), math.radians(azimuth)
    return Light("sun", (math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)))


CASES = [("height map, sun 15°", "height", sun(15, 30)),
         ("height map, sun 35°", "height", sun(35, 150)),
         ("height map, sun 60°", "height", sun(60, 250)),
         ("height map, point light", "height", Light("point", (0.3, -0.2, 0.6))),
         ("height map, low point light", "height", Light("point", (-0.1, 0.15, 0.25))),
         ("height map, point light beside", "height", Light("point", (0.9, 0.6, 0.4))),
         ("normal map, sun 35°", "normal", sun(35, 150)),
         ("normal map, point light", "normal", Light("point", (0.3, -0.2, 0.6))),
         ("normal map (relief integrated), point light", "integrated",
          Light("point", (0.3, -0.2, 0.6)))]
# (final ≤ × baseline, final mean ≤) per kind of light (issue 4 for suns, issue 18 for points);
# preview ≤ 0.02×, mean ≤ 0.01 for both
FINAL_GOALS = {"sun": (0.1, 5e-4), "point": (0.2, 5e-4)}
PREVIEW_GOAL = (0.02, 0.01)


def shape(size, kind, dtype, relief=RELIEF):
    """(normals, heights px, slopes) of the built-in relief as a height map, a normal map
    along the ray, or a normal map whose shadows fall from its integrated relief (§6 Relief,
    the default)."""
    z = height_field_px(builtin_images(size)["shape"].grey().astype(dtype), relief)
    n = normals_from_height_px(z)
    if kind == "integrated":
        return n, (integrate(n, precise=False).height * size).astype(dtype), None
    return (n, z, None) if kind == "height" else (n, None, slopes_from_normals(n))


def goal(light, level, ratio, err):
    """The level's goal and whether this row meets it ('' where there is none)."""
    g = FINAL_GOALS[light.kind] if level == "final" else \
        PREVIEW_GOAL if level == "preview" else None
    if g is None:
        return ""
    met = ratio <= g[0] and err <= g[1]
    return f"≤ {g[0]:g}×, ≤ {g[1]:g}: {'met' if met else 'not met'}"


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t


def measure(size, cases=CASES, repeat=1):
    """(rows of the first run, {label: final × baseline in each of `repeat` runs}): each
    case's reference is computed once, then the baseline and the levels are timed in each
    run."""
    rows, spread = [], {}
    for label, kind, light in cases:
        n64, z64, s64 = shape(size, kind, np.float64)
        ref = cos_theta_shadow(n64, light, OFFSET, 1024, heights_px=z64, slopes=s64)
        n, z, s = shape(size, kind, np.float32)
        for run in range(repeat):
            case_rows = measure_case(label, light, n, z, s, ref, size)
            spread.setdefault(label, []).append(case_rows[-1][3])
            if run == 0:
                rows += case_rows
    return rows, spread


def measure_case(label, light, n, z, s, ref, size):
    """The baseline's row and each level's for one case (times: best of RUNS)."""
    rows = []
    # the best of a few runs, for the baseline as for the levels (this machine's timings
    # vary by ±10–25 % from run to run)
    runs = [timed(lambda: cos_theta_shadow(n, light, OFFSET, 64, heights_px=z, slopes=s))
            for _ in range(RUNS)]
    base, base_s = runs[0][0], min(r[1] for r in runs)
    rows.append((label, "baseline", base_s, 1.0, float(np.abs(base - ref).mean()),
                 f"K = 64 march at {size}×{size}", 1.0, ""))
    for level in LEVELS:
        stats = ShadowStats()
        times = []
        for _ in range(RUNS):
            t, sec = timed(lambda: bake(n, light, OFFSET, level, heights_px=z, slopes=s,
                                        stats=stats))
            times.append(sec)
        err = float(np.abs(t - ref).mean())
        rows.append((label, level, min(times), min(times) / base_s, err, stats.settings(),
                     max(times) / base_s, goal(light, level, min(times) / base_s, err)))
    print(*[f"{r[0]} | {r[1]}: {r[2]:.3f} s ({r[3]:.3f}× baseline, worst {r[6]:.3f}×), "
            f"mean {r[4]:.1e} {r[7]}" for r in rows], sep="\n", flush=True)
    return rows


def large_final(size):
    """A sun's final bake of a large painting (its tables built a group of blocks at a time):
    (seconds, the K = 64 march's seconds, mean |Δt| between them, peak of traced allocations,
    the inputs' bytes); each time from one run (the march takes about a minute at 4096²)."""
    n, z, _ = shape(size, "height", np.float32)
    light = sun(35, 150)
    t, sec = timed(lambda: bake(n, light, OFFSET, "final", heights_px=z))
    march, march_sec = timed(lambda: cos_theta_shadow(n, light, OFFSET, 64, heights_px=z))
    tracemalloc.start()
    bake(n, light, OFFSET, "final", heights_px=z)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return sec, march_sec, float(np.abs(t - march).mean()), peak, n.nbytes + z.nbytes


LIVE_MOVES = 8


def live_latency(size):
    """Light change → updated image, through the add-on's live bake (background Blender), for
    one sun and one point light: the light moved LIVE_MOVES times, each change baked at the
    live level the add-on picks (it adapts to LIVE_BUDGET_MS), then once still at final →
    {kind: (median ms of the last half of the moves, their levels, final ms, budget ms)}.
    Blender is imported here only: the other measurements run without it."""
    import bpy
    from dynpaint_addon.blender import headless
    from dynpaint_addon.blender.bake import live_bake
    from dynpaint_addon.inputs.recipe import load_recipe
    from dynpaint_addon.inputs.testpainting import write_test_painting
    import tempfile
    folder = tempfile.mkdtemp()
    out = {}
    for kind in ("sun", "point"):
        recipe = load_recipe(write_test_painting(folder, size))
        recipe.lights = [lt for lt in recipe.lights if lt.kind == kind][:1]
        plane, mat = headless.build_recipe_scene(recipe)
        live = live_bake.LiveBake()
        obj = mat.dynamic_painting.lights[0].object
        obj.rotation_mode = "XYZ"
        for move in range(LIVE_MOVES):
            obj.rotation_euler = (0.7, 0.3, 1.0 + 0.05 * move)     # a sun turns,
            obj.location.x += 0.01                                   # a point light moves
            bpy.context.view_layer.update()
            live.request(mat, bpy.context.scene)
            live.wait()
        moving = live.latencies[LIVE_MOVES // 2:]
        live.request(mat, bpy.context.scene, quality="final")
        live.wait()
        out[kind] = (float(np.median([ms for _, ms in moving])),
                     sorted({q for q, _ in moving}), live.latencies[-1][1],
                     live_bake.LIVE_BUDGET_MS[kind])
    return out


def svg_chart(rows, path):
    """Time against error on log axes, one colour per quality level, the targets as boxes."""
    w, h, pad = 640, 400, 60
    xs = [r[3] for r in rows]
    ys = [r[4] for r in rows]
    x0, x1 = math.log10(min(xs + [0.01]) / 2), math.log10(max(xs) * 2)
    y0, y1 = math.log10(min(ys + [1e-4]) / 2), math.log10(max(ys) * 2)

    def px(v):
        return pad + (math.log10(v) - x0) / (x1 - x0) * (w - 2 * pad)

    def py(v):
        return h - pad - (math.log10(v) - y0) / (y1 - y0) * (h - 2 * pad)
    colours = {"baseline": "#555", "draft": "#d95f02", "preview": "#7570b3", "final": "#1b9e77"}
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
             'font-family="sans-serif" font-size="12">',
             f'<rect width="{w}" height="{h}" fill="white"/>',
             f'<line x1="{pad}" y1="{h - pad}" x2="{w - pad}" y2="{h - pad}" stroke="black"/>',
             f'<line x1="{pad}" y1="{pad}" x2="{pad}" y2="{h - pad}" stroke="black"/>',
             f'<text x="{w / 2}" y="{h - 15}" text-anchor="middle">bake time ÷ baseline '
             '(log)</text>',
             f'<text x="15" y="{h / 2}" transform="rotate(-90 15 {h / 2})" '
             'text-anchor="middle">mean |t − reference| (log)</text>']
    for label, xmax, ymax in (("final target", 0.1, 5e-4), ("preview target", 0.02, 0.01)):
        if 10 ** x0 < xmax and 10 ** y0 < ymax:
            parts.append(f'<rect x="{pad}" y="{py(ymax)}" width="{px(xmax) - pad}" '
                         f'height="{h - pad - py(ymax)}" fill="none" stroke="#999" '
                         'stroke-dasharray="4"/>')
            parts.append(f'<text x="{pad + 4}" y="{py(ymax) - 4}" fill="#777">{label}</text>')
    for _, level, _, ratio, err, *_ in rows:
        parts.append(f'<circle cx="{px(ratio):.1f}" cy="{py(err):.1f}" r="5" '
                     f'fill="{colours[level]}"/>')
    for i, (level, colour) in enumerate(colours.items()):
        parts.append(f'<circle cx="{w - 130}" cy="{pad + 18 * i}" r="5" fill="{colour}"/>'
                     f'<text x="{w - 120}" y="{pad + 18 * i + 4}">{level}</text>')
    for decade in range(math.ceil(x0), math.floor(x1) + 1):
        parts.append(f'<text x="{px(10 ** decade)}" y="{h - pad + 16}" text-anchor="middle">'
                     f'{10 ** decade:g}</text>')
    for decade in range(math.ceil(y0), math.floor(y1) + 1):
        parts.append(f'<text x="{pad - 6}" y="{py(10 ** decade) + 4}" text-anchor="end">'
                     f'1e{decade}</text>')
    parts.append("</svg>")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(parts))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--memory-size", type=int, default=4096)
    ap.add_argument("--truth-size", type=int, default=256,
                    help="size of the 3D ground-truth scene (benchmarks/ground_truth.py)")
    ap.add_argument("--out", help="Markdown page (the SVG chart goes next to it, in img/)")
    ap.add_argument("--repeat", type=int, default=3,
                    help=f"runs of the timings (each the best of {RUNS}) for the finals' spread")
    ap.add_argument("--cases", default="",
                    help="only the cases whose name holds this text (e.g. 'sun'): their "
                         "timings and spread are printed, nothing else is measured or written")
    args = ap.parse_args(argv)
    cases = [c for c in CASES if args.cases in c[0]]
    rows, spread = measure(args.size, cases, args.repeat)
    runs = [f"| {label} | {' · '.join(f'{r:.3f}' for r in ratios)} | {min(ratios):.3f}–"
            f"{max(ratios):.3f} | ≤ {FINAL_GOALS[light.kind][0]:g}×: "
            f"{'met in every run' if max(ratios) <= FINAL_GOALS[light.kind][0] else 'not met'} |"
            for (label, _, light), ratios in zip(cases, spread.values())]
    print("final × baseline in each run:", *runs, sep="\n")
    if args.cases:
        return
    large_sec, march_sec, large_gap, peak, inputs = large_final(args.memory_size)
    latency = live_latency(args.size)
    from ground_truth import level_errors
    truth = level_errors(args.truth_size)
    lines = ["# Shadow bake: speed against accuracy (pipeline.md §13)", "",
             f"`.venv/bin/python benchmarks/shadow_quality.py --size {args.size}` on "
             f"{platform.machine()}, {os.cpu_count()} cores. {args.size}² built-in height map "
             f"raised to {RELIEF} image widths (tall relief: long marches), d = {OFFSET}. "
             "Time: the bake itself. Error: mean |t − reference| (K = 1024, float64). "
             "Baseline: the straightforward march (one bilinear gather per pixel per step, "
             "K = 64, float32), measured in the same run.", "",
             f"| case | level | settings | seconds | × baseline (worst of {RUNS}) | mean error "
             "| goal |",
             "|---|---|---|---|---|---|---|"]
    for label, level, sec, ratio, err, settings, worst, target in rows:
        lines.append(f"| {label} | {level} | {settings} | {sec:.3f} | {ratio:.3f} "
                     f"({worst:.3f}) | {err:.1e} | {target} |")
    lines += ["", "Suns bake by exact crossings (core/crossings.py: a light-aligned grid, sparse "
              "tables, binary descents) at draft, preview and final (final from 512 px up), "
              "at the level's own resolution (draft ⅛, preview ¼; ¼ and 0.4 for normal maps; "
              "never below 96/192 px): K does not apply there. Point lights bake by crossings "
              "on a polar grid around the light's foot at the same levels and resolutions "
              "(columns 1 px apart, 0.7 px at final): each ray runs from P0 to the light, §6's "
              "ray. Normal maps: relief rebuilt along each ray (the K = 1024 reference "
              "likewise; no reach), or integrated once (`shadows.relief = integrated`, the "
              "default: then the reference marches that relief). "
              f"Every time (baseline and levels) is the best of {RUNS} runs, the worst in "
              "brackets: timings on this shared 2-core machine vary by ±10–25 % between runs.",
              "", "Goals: final ≤ 0.1× baseline for suns (issue 4), ≤ 0.2× for point lights "
              "(issue 18), both with mean ≤ 5e-4; preview ≤ 0.02× with mean ≤ 0.01.", "",
              f"Final × baseline in each of {args.repeat} runs of the timings (baseline and "
              f"final each the best of {RUNS} in every run; the table above is the first):",
              "", "| case | final × baseline, run by run | spread | goal |", "|---|---|---|---|",
              *runs, ""]
    if args.out:
        img = os.path.join(os.path.dirname(os.path.abspath(args.out)), "img", "shadow-quality.svg")
        os.makedirs(os.path.dirname(img), exist_ok=True)
        svg_chart(rows, img)
        lines += ["![time against error per quality level](img/shadow-quality.svg)", ""]
    lines += ["## Against 3D ground truth", "",
              f"The scene of `benchmarks/ground_truth.py` (sphere, torus, boxes, a floating "
              f"plate on a ground plane) rendered by Cycles at {args.truth_size}² with a hard "
              "sun, white diffuse, direct light only: each level's bake of its height map and "
              "normal map against the render, averaged over suns at 15°, 30°, 45° and 60° "
              "(per object and per sun: [ground-truth.md](ground-truth.md)). The 2.5D "
              "approximation itself (overhangs, walls in normal maps) dominates: the levels "
              "differ far less from each other than from the truth.", "",
              "| level | shape | mean \\|t − truth\\| | cast-shadow IoU |", "|---|---|---|---|"]
    lines += [f"| {level} | {label} | {err:.4f} | {iou:.3f} |" for level, label, err, iou in truth]
    lines += ["", f"A large painting: a sun's final bake at {args.memory_size}² takes "
              f"{large_sec:.1f} s against {march_sec:.1f} s for the K = 64 march (one run "
              f"each; mean |Δt| between them {large_gap:.1e}). Its tables would not fit "
              f"{MAX_TABLE_BYTES / 2**30:g} GiB at once: they are built a group of blocks at "
              f"a time. Peak of its numpy allocations (tracemalloc): {peak / 2**20:.0f} MiB, "
              f"{peak / inputs:.1f}× its inputs (normals and heights, {inputs / 2**20:.0f} "
              "MiB).",
              "", f"Live bake latency at {args.size}² in the add-on: light change → updated "
              f"image, the light moved {LIVE_MOVES} times, each change baked at the live level "
              "the add-on picks (preview while it keeps within the budget, draft where it does "
              "not); the median of the last half of the moves. Goal (issue 18): ≤ 33 ms for "
              "one sun (a 30 fps viewport), ≤ 50 ms for a point light. The UI stays free "
              "meanwhile (worker thread); a newer change supersedes a bake in flight; the "
              "painting's own quality follows once the light is still.", "",
              "| light | while moving, ms | live level | goal | final once still, ms |",
              "|---|---|---|---|---|"]
    for kind, (ms, levels, final, goal) in latency.items():
        lines.append(f"| one {kind} | {ms:.0f} | {', '.join(levels)} | ≤ {goal:g} ms: "
                     f"{'met' if ms <= goal else 'not met'} | {final:.0f} |")
    publish(lines, args.out)


if __name__ == "__main__":
    main()
