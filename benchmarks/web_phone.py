"""The page on a phone (issue 62): what a page of a 1K–8K painting weighs, and which of its
copies each kind of device draws.

For each size the built-in test painting (make-test-painting) is exported with `export-web`
at its own size (--max-size 0) and at the default --max-size. Each page: its file size, the
seconds it takes to arrive over a phone's connection (PHONE_MBIT), its copies (web/device_fit.py:
each power of two below the painting down to 2048, each with the GPU memory the viewer
estimates for it), the copy each device of DEVICES draws (device_fit.chosen_copy, the
viewer's rule), and the export's time. The test painting is smooth: a painted or photographed
one deflates less (the samples' pages are 0.8–2.3× their input files: web-numbers.md).

    .venv/bin/python benchmarks/web_phone.py --sizes 1024 2048 4096 8192
"""
import argparse
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import command_line, publish  # noqa: E402

from dynpaint_addon.cli import main as cli_main  # noqa: E402
from dynpaint_addon.web.device_fit import DEFAULT_MAX_SIZE, GPU_SHARE, chosen_copy  # noqa: E402
from dynpaint_addon.web.page import data_of_page  # noqa: E402

PHONE_MBIT = 10          # a phone's connection, megabits per second (a slow 4G; 3G is ~2)
SIZE_GOAL_S = 10         # the default page of every size arrives within this
# (name, MAX_TEXTURE_SIZE, memory in GB as navigator.deviceMemory reports it)
DEVICES = [("desktop", 16384, 8), ("phone, 4 GB", 4096, 4), ("phone, 2 GB", 4096, 2),
           ("old phone, 2 GB", 2048, 2)]


def export(folder, out, max_size):
    start = time.perf_counter()
    assert cli_main(["export-web", folder, "--out", out, "--max-size", str(max_size)]) in (0, None)
    return time.perf_counter() - start


def rows(sizes, work):
    out = []
    for size in sizes:
        folder = os.path.join(work, f"p{size}")
        cli_main(["make-test-painting", "--size", str(size), folder])
        for max_size in [0] + ([DEFAULT_MAX_SIZE] if DEFAULT_MAX_SIZE < size else []):
            path = os.path.join(work, f"p{size}_{max_size}.html")
            seconds = export(folder, path, max_size)
            data = data_of_page(open(path, encoding="utf-8").read())
            mb = os.path.getsize(path) / 1e6
            arrive = mb * 8 / PHONE_MBIT
            copies = ", ".join(f"{d['width']}: {d['fit']['bytes'] / 2 ** 20:.0f} MB"
                               for d in [data] + data["smaller"])
            drawn = " | ".join(str(chosen_copy(data, side, gb)["width"])
                               for _, side, gb in DEVICES)
            default = max_size == DEFAULT_MAX_SIZE or size <= DEFAULT_MAX_SIZE
            goal = ("met" if arrive <= SIZE_GOAL_S else "not met") if default else "reported"
            label = (str(max_size) if max_size else "own size") + (" (default)" if default else "")
            out.append(f"| {size}² | {label} | {mb:.2f} | {arrive:.1f} s: {goal} | {copies} | "
                       f"{drawn} | {seconds:.1f} |")
            os.remove(path)
    return out


def phone_lines(sizes):
    """The report's section (also web_page.py's, in web-numbers.md)."""
    with tempfile.TemporaryDirectory() as work:
        body = rows(sizes, work)
    devices = " | ".join(f"{name} ({side} px, {gb} GB → {gb * GPU_SHARE * 1024:.0f} MB)"
                         for name, side, gb in DEVICES)
    return ["## On a phone: file size and the copy each device draws (issue 62)", "",
            f"`{command_line(__file__, ['--sizes'] + [str(s) for s in sizes])}`: the built-in "
            f"test painting at each size, exported at its own size and at the default "
            f"`--max-size {DEFAULT_MAX_SIZE}`. A page larger than 2048 px carries a copy at each "
            f"power of two below it down to 2048; the viewer draws the largest copy whose "
            f"textures the device takes (MAX_TEXTURE_SIZE) and whose estimated GPU memory is "
            f"within {GPU_SHARE:.0%} of the device's (navigator.deviceMemory). Goal: the "
            f"default page arrives within {SIZE_GOAL_S} s over {PHONE_MBIT} Mbit/s. *drawn*: "
            f"the side of the copy each device draws.", "",
            f"| painting | --max-size | page MB | over {PHONE_MBIT} Mbit/s | copies (GPU memory) | "
            f"{devices} | export s |",
            "|---|---|---|---|---|" + "---|" * len(DEVICES) + "---|", *body]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[1024, 2048, 4096, 8192])
    ap.add_argument("--out", help="also write the Markdown page here")
    args = ap.parse_args(argv)
    publish(["# The page on a phone", ""] + phone_lines(args.sizes), args.out)


if __name__ == "__main__":
    main()
