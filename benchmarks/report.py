"""Shared by the benchmarks: print the Markdown page and write it where asked."""
import argparse
import os
import sys
import time


def command_line(script, argv=None):
    """How the benchmark `script` (its __file__) was run, for its report's first line:
    'python benchmarks/ground_truth.py --size 256'."""
    return " ".join([f"python benchmarks/{os.path.basename(script)}"]
                    + list(argv or sys.argv[1:]))


def publish(lines, path=None):
    text = "\n".join(lines) + "\n"
    print(text)
    if path:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)
    return text


def best(fn, runs):
    """The shortest of `runs` calls of fn(), in seconds."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def size_and_runs(doc, argv=None, size=1024, runs=3):
    """The arguments of a timing benchmark whose docstring is `doc`: --size (px), --runs
    (the best of them is kept) and --out (the Markdown report)."""
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--size", type=int, default=size)
    ap.add_argument("--runs", type=int, default=runs)
    ap.add_argument("--out", help="Markdown report")
    return ap.parse_args(argv)


def met(ok):
    """A goal's verdict, as every report writes it."""
    return "met" if ok else "not met"
