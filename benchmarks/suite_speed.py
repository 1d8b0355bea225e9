"""How long the numpy tier of the tests takes (issue 62: ≤ 45 s on the project's 2-core
machine), against a baseline checkout in the same run.

The tier — README's command, `pytest -q -n auto --dist loadfile -m "not blender" tests` — is
run --runs times in this checkout and as many in a git worktree of --baseline, alternately:
this machine's speed drifts by a fifth from hour to hour (the same code measured 42 s and
52 s on one day), and runs taken in turn see the same drift. Each run keeps its wall time
(from the start of its Python to its exit), its CPU time (user + system of every process it
started) and its count of tests; the report gives each checkout's median and range and the
ratio of medians.

    .venv/bin/python benchmarks/suite_speed.py --baseline 1cdb38e --runs 4 --out docs/suite-speed.md
"""
import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from report import command_line, met, publish  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIER = ["-m", "pytest", "-q", "-p", "no:cacheprovider", "-n", "auto", "--dist", "loadfile",
        "-m", "not blender"]
GOAL_S = 45.0


def pytest_summary(text):
    """(tests passed, seconds) from pytest's last line: '694 passed, 2 skipped in 45.13s'."""
    found = re.search(r"(\d+) passed.* in ([\d.]+)s", text)
    if not found:
        raise RuntimeError(f"no pytest summary in: {text[-400:]}")
    return int(found.group(1)), float(found.group(2))


def run_tier(checkout, tests):
    """(tests passed, wall s, CPU s) of one run of the tier in `checkout`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, *TIER, tests], cwd=checkout, text=True,
                          capture_output=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"the tier failed in {checkout}:\n{done.stdout[-2000:]}")
    passed = pytest_summary(done.stdout)[0]
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return passed, wall, cpu


def spread(values):
    """'median (min–max)' of seconds."""
    return f"{statistics.median(values):.1f} ({min(values):.1f}–{max(values):.1f})"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", required=True, help="a commit to compare with")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--tests", default="tests", help="what pytest runs (default: tests)")
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    base = tempfile.mkdtemp(prefix="suite-baseline-")
    subprocess.run(["git", "worktree", "add", "--detach", "-f", base, args.baseline],
                   cwd=REPO, check=True, capture_output=True)
    for venv in (".venv", ".venv-newest"):          # tests that start the venv's tools
        if os.path.isdir(os.path.join(REPO, venv)):
            os.symlink(os.path.join(REPO, venv), os.path.join(base, venv))
    try:
        runs = {"this checkout": [], f"baseline {args.baseline}": []}
        for i in range(args.runs):
            for (name, kept), checkout in zip(runs.items(), (REPO, base)):
                kept.append(run_tier(checkout, args.tests))
                print(f"run {i + 1}/{args.runs}, {name}: {kept[-1][1]:.1f} s, "
                      f"{kept[-1][2]:.1f} s of CPU, {kept[-1][0]} passed", flush=True)
    finally:
        subprocess.run(["git", "worktree", "remove", "--force", base], cwd=REPO,
                       capture_output=True)
        shutil.rmtree(base, ignore_errors=True)
    (now, baseline) = runs.values()
    wall_now = statistics.median(r[1] for r in now)
    ratio = wall_now / statistics.median(r[1] for r in baseline)
    lines = [f"# The numpy tier's time (`{command_line(__file__, argv)}`)", "",
             f"{os.cpu_count()} cores; runs taken in turn; median (range) of {args.runs} "
             f"runs each.", "",
             "| checkout | tests | wall s | CPU s |", "|---|---|---|---|"]
    lines += [f"| {name} | {kept[0][0]} | {spread([r[1] for r in kept])} | "
              f"{spread([r[2] for r in kept])} |" for name, kept in runs.items()]
    lines += ["", f"This checkout against the baseline: {ratio:.2f}× its wall time. "
              f"Goal ≤ {GOAL_S:g} s (median): {wall_now:.1f} s, {met(wall_now <= GOAL_S)}."]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
