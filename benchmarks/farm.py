"""A turntable on a Flamenco render farm (issue 64): 1 worker against 2 on this machine, and
what the Manager costs per task.

The built-in test painting at --size, a --frames orbit in chunks of --chunk-size, all on this
machine: a Manager and Workers built from ../shared/flamenco (testkit/flamenco.py). Timed
end to end, submit to the job's video, against the same work without a farm in the same run:
the whole turntable in one process (`turntable --out frames/####.png`), and each chunk in a
process of its own one after the other (what one worker runs). The Manager's cost per task:
(1 worker − the chunks one after the other) / tasks. Every farm's frames are checked against
the whole turntable's, bit for bit. --picture writes a contact sheet of a finished job's
frames (docs/img/farm/frames.png).

    .venv/bin/python benchmarks/farm.py --painting-size 256 --frames 24 --out docs/farm-numbers.md \\
        --picture docs/img/farm/frames.png
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import command_line, publish  # noqa: E402

from dynpaint_addon.cli.farm import job_settings  # noqa: E402
from dynpaint_addon.cli.turntable import add_orbit_options  # noqa: E402
from dynpaint_addon.farm.flamenco import submit  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import load_recipe  # noqa: E402
from testkit import flamenco  # noqa: E402
from testkit.animated import sheet_of  # noqa: E402


def dynpaint(*args):
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "dynpaint_addon", *map(str, args)], check=True,
                   capture_output=True, text=True)
    return time.perf_counter() - start


def frames_of(folder):
    names = sorted(n for n in os.listdir(folder) if n.endswith(".png"))
    return [read_image(os.path.join(folder, n)).pixels for n in names]


def on_farm(work, recipe, workers, settings, name):
    """Seconds from submit to the job's end on a farm of `workers` → (seconds, its frames)."""
    with flamenco.Farm(os.path.join(work, f"farm{workers}"), workers=workers) as farm:
        start = time.perf_counter()
        job, output = submit(farm.url, recipe, settings, name)
        done = farm.wait_job(job["id"], timeout=3600)
        seconds = time.perf_counter() - start
        if done["status"] != "completed":
            failed = [t for t in farm.tasks(job["id"]) if t["status"] == "failed"]
            raise RuntimeError(f"the farm's job {done['status']}: " + "\n".join(
                farm.task_log(t["id"]) for t in failed[:1]))
        return seconds, frames_of(output)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--painting-size", type=int, default=256,
                    help="the test painting's size in pixels")
    ap.add_argument("--chunk-size", type=int, default=4)
    ap.add_argument("--out", help="also write the Markdown page here")
    ap.add_argument("--picture", help="a contact sheet of the 2-worker job's frames (PNG)")
    add_orbit_options(ap)
    args = ap.parse_args(argv)
    why = flamenco.unavailable()
    if why:
        sys.exit(f"farm benchmark: {why}")
    flamenco.build()
    with tempfile.TemporaryDirectory() as work:
        painting = os.path.join(work, "painting")
        dynpaint("make-test-painting", "--size", args.painting_size, painting)
        recipe = load_recipe(painting)
        whole = dynpaint("turntable", painting, "--frames", args.frames, "--out",
                         os.path.join(work, "whole", "####.png"))
        chunks = [(a, min(a + args.chunk_size - 1, args.frames))
                  for a in range(1, args.frames + 1, args.chunk_size)]
        apart = sum(dynpaint("turntable", painting, "--frames", args.frames, "--only",
                             f"{a}-{b}", "--out", os.path.join(work, "apart", "####.png"))
                    for a, b in chunks)
        want = frames_of(os.path.join(work, "whole"))
        settings = job_settings(args)
        runs = {n: on_farm(work, recipe, n, settings, f"bench {n}") for n in (1, 2)}
        same = all(len(f) == len(want) and all(np.array_equal(a, b) for a, b in zip(want, f))
                   for _, f in runs.values())
        if args.picture:
            os.makedirs(os.path.dirname(os.path.abspath(args.picture)), exist_ok=True)
            columns = min(6, len(want))
            rows = -(-len(want) // columns)
            write_png(args.picture, np.clip(sheet_of(runs[2][1], columns, rows, 4, 4, 0.1),
                                            0, 1))
    one, two = runs[1][0], runs[2][0]
    per_task = (one - apart) / len(chunks)
    lines = ["# A turntable on a Flamenco farm (issue 64)", "",
             f"`{command_line(__file__, argv)}` on this machine ({os.cpu_count()} cores, no "
             f"GPU): the built-in test painting at {args.painting_size}², a {args.frames}-frame orbit "
             f"({args.engine}), {len(chunks)} tasks of {args.chunk_size} frames and the video; "
             f"a Manager and its Workers on loopback, built from Flamenco's source "
             f"(testkit/flamenco.py). Farm times run from submit to the job's video.", "",
             "| what | seconds | per frame | against one worker |", "|---|---|---|---|",
             f"| the whole turntable in one process (no farm) | {whole:.1f} | "
             f"{whole / args.frames:.2f} | – |",
             f"| each chunk in a process of its own, one after the other (no farm) | "
             f"{apart:.1f} | {apart / args.frames:.2f} | – |",
             f"| farm, 1 worker | {one:.1f} | {one / args.frames:.2f} | 1.00× |",
             f"| farm, 2 workers | {two:.1f} | {two / args.frames:.2f} | "
             f"{one / two:.2f}× faster |", "",
             f"The Manager's cost per task (1 worker against the chunks one after the other): "
             f"{per_task:.1f} s; each task also starts Blender once (the chunks apart against "
             f"the whole: {(apart - whole) / len(chunks):.1f} s a task). Every farm's frames are "
             f"the whole turntable's bit for bit: {'yes' if same else '**no**'}."]
    publish(lines, args.out)
    return {"whole": whole, "apart": apart, "one": one, "two": two, "same": same}


if __name__ == "__main__":
    main()
