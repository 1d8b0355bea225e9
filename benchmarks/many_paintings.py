"""Many paintings in one scene (issue 60): what each Add › Dynamic Painting costs as the scene
fills up, and the memory the scene holds.

Three runs in one Blender session each, the scene emptied between them:
- the built-in test painting (64², a Sun and a Point light) added `--count` times: each
  recipe's lights in a collection of their own that lights only its painting (the painting's
  Lights field), as Add makes them now;
- the baseline, in the same run: the same paintings each lit by every light in the scene (the
  Lights field emptied after each Add, as every painting was before issue 60), `--baseline`
  times: each Add re-lit every painting with every light, its cost growing with the square of
  the count;
- the portrait sample (a 1024×1024 height map with its dark and bright images) added
  `--portraits` times.

Each Add's time is the shortest of `--runs` runs (the baseline: one).

Goals (issue 60: 50 samples in one scene): each Add at most 2× the first; the memory linear in
the count (the megabytes a painting adds over the second half of the run at most 1.5× those
over the first half). The 64² painting shows Blender's own share, which grows with the scene.

    .venv/bin/python benchmarks/many_paintings.py --out docs/many-paintings.md     # ≈ 2 min
"""
import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, REPO)

import bpy  # noqa: E402

from report import command_line, met, publish  # noqa: E402

from dynpaint_addon import blender  # noqa: E402
from dynpaint_addon.inputs.testpainting import write_test_painting  # noqa: E402

PORTRAIT = os.path.join(REPO, "sample_scenes", "portrait", "painting.toml")
GOALS = "each Add ≤ 2× the first; memory linear (MB a painting adds, 2nd half ≤ 1.5× 1st half)"
SHOWN = (1, 2, 5, 10, 14, 20, 30, 40, 50)


def resident_mb():
    with open("/proc/self/status") as fh:
        return next(int(line.split()[1]) / 1024 for line in fh if line.startswith("VmRSS"))


def best_of(runs, recipe, count, every_light=False):
    """add_many `runs` times → per Add, its shortest time (this machine's other work only
    ever adds to one) and the first run's memory."""
    tries = [add_many(recipe, count, every_light) for _ in range(runs)]
    return [(min(t[i][0] for t in tries), tries[0][i][1]) for i in range(count)]


def add_many(recipe, count, every_light=False):
    """Add the recipe `count` times in an empty scene → [(ms, resident MB)] per Add."""
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    out = []
    for _ in range(count):
        start = time.perf_counter()
        assert bpy.ops.dynpaint.add(filepath=recipe) == {"FINISHED"}
        if every_light:         # as before issue 60: every light lights every painting
            bpy.context.object.active_material.dynamic_painting.light_collection = None
        out.append(((time.perf_counter() - start) * 1000, resident_mb()))
    return out


def verdict(run):
    """(worst Add ÷ first, MB a painting adds in the 2nd half ÷ 1st half, goals met)."""
    first = run[0][0]
    worst = max(ms for ms, _ in run[1:]) / first
    half = len(run) // 2
    early = (run[half][1] - run[0][1]) / max(half, 1)
    late = (run[-1][1] - run[half][1]) / max(len(run) - 1 - half, 1)
    growth = late / max(early, 1e-9)
    return worst, growth, worst <= 2 and growth <= 1.5


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--count", type=int, default=50)
    ap.add_argument("--baseline", type=int, default=14)
    ap.add_argument("--portraits", type=int, default=50)
    ap.add_argument("--runs", type=int, default=2, help="each Add's shortest of this many")
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as work:
        small = write_test_painting(os.path.join(work, "small"), 64)
        runs = [("test painting 64², its own lights (now)",
                 best_of(args.runs, small, args.count)),
                ("test painting 64², every light lights every painting (before)",
                 best_of(1, small, args.baseline, every_light=True)),
                ("portrait sample 1024², its own lights (now)",
                 best_of(args.runs, PORTRAIT, args.portraits))]
    counts = [n for n in SHOWN if n <= max(len(r) for _, r in runs)]
    lines = ["# Many paintings in one scene (issue 60)", "",
             f"`{command_line(__file__, argv)}`: each Add › Dynamic Painting's milliseconds "
             f"(and Blender's resident memory after it) as the scene fills up. Goals: {GOALS}.",
             "", "| run | " + " | ".join(f"Add {n}" for n in counts) +
             " | worst ÷ first | MB per painting, 2nd half ÷ 1st | goals |",
             "|---|" + "---|" * (len(counts) + 3)]
    results = []
    for name, run in runs:
        worst, growth, ok = verdict(run)
        results.append((name, ok))
        cells = [f"{run[n - 1][0]:.0f} ms, {run[n - 1][1]:.0f} MB" if n <= len(run) else "—"
                 for n in counts]
        lines.append(f"| {name} | " + " | ".join(cells) +
                     f" | {worst:.2f} | {growth:.2f} | {met(ok)} |")
    lines += ["", "Blender's own share grows with the scene: after 49 paintings, the view layer "
              "update that follows adding one object takes ≈57 ms (0.3 ms in an empty scene: "
              "the depsgraph's relations are rebuilt, every painting's light drivers with "
              "them), and an Add runs three.", "",
              "The baseline is the same painting with every light lighting every "
              "painting: each Add brought every painting up to date with every light, so the "
              "n-th Add cost about n² light bakes. Now a recipe's lights are a collection of "
              "their own, named in its painting's Lights field; an update touches only the "
              "paintings whose plane, lights or collection it changed, and an image another "
              "painting already shows is not loaded again (setting its colour space reloaded "
              "its pixels, and told every painting showing it that it was edited)."]
    publish(lines, args.out)
    return 0 if results[-1][1] else 1       # the goal: 50 samples in one scene


if __name__ == "__main__":
    sys.exit(main())
