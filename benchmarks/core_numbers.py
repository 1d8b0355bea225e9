"""Measured numbers of the numpy reference core, printed and written to docs/core-numbers.md.

    .venv/bin/python benchmarks/core_numbers.py [--size 1024] [--out docs/core-numbers.md]

1. Height-map bit depth (pipeline.md §2, §14): N·L error of a hemisphere lit at 45° from 8-bit,
   16-bit and float heights, with and without the default pre-blur.
2. The straightforward cos-θ march (§6, the baseline of §13): time and mean |Δt| against a
   K = 1024 float64 reference for several K, height map with tall relief, sun at 35°.
3. Art-directed Fresnel (§10): best minimax fit to the physical curve in sin θ and in cos θ.
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from dynpaint_addon.core.fresnel import fit_art_fresnel  # noqa: E402
from report import publish  # noqa: E402
from testkit.shapes import quantized_dome  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from dynpaint_addon.core.shape import (default_preblur_px, height_field_px,  # noqa: E402
                                       normals_from_height_px)


def bit_depth_table(size=256):
    exact, mask = quantized_dome(size, 32)
    light = np.array([1, 0, 1]) / np.sqrt(2)
    n_exact = normals_from_height_px(height_field_px(exact, 0.4))
    rows = []
    for bits in (8, 16, 32):
        h, _ = quantized_dome(size, bits)
        for sigma in sorted({0.0, default_preblur_px(bits), 1.5}):
            n = normals_from_height_px(height_field_px(h.astype(np.float32), 0.4, sigma))
            err = np.abs((n @ light) - (n_exact @ light))[mask]
            levels = len(np.unique(np.round((n @ light)[mask], 6)))
            rows.append((bits, sigma, sigma == default_preblur_px(bits), err.mean(), err.max(), levels))
    return rows


def relief(size):
    """Tall relief: domes and boxes up to half the image width high (long marches)."""
    rng = np.random.default_rng(7)
    y, x = np.mgrid[0:size, 0:size] / size
    h = np.zeros((size, size))
    for _ in range(5):
        cx, cy, r = rng.uniform(0.15, 0.85), rng.uniform(0.15, 0.85), rng.uniform(0.06, 0.18)
        h = np.maximum(h, np.sqrt(np.clip(1 - ((x - cx) ** 2 + (y - cy) ** 2) / r**2, 0, 1)))
    for _ in range(4):
        cx, cy, s, hh = rng.uniform(0.1, 0.9), rng.uniform(0.1, 0.9), rng.uniform(0.04, 0.1), rng.uniform(0.3, 1)
        h = np.maximum(h, hh * ((np.abs(x - cx) < s) & (np.abs(y - cy) < s)))
    return h


def march_table(size, steps=(16, 64, 256)):
    z64 = height_field_px(relief(size), 0.5)
    n64 = normals_from_height_px(z64)
    light = Light("sun", (np.cos(np.radians(35)) * np.cos(0.6), np.cos(np.radians(35)) * np.sin(0.6),
                          np.sin(np.radians(35))))
    t0 = time.perf_counter()
    ref = cos_theta_shadow(n64, light, 0.01, 1024, heights_px=z64)
    ref_s = time.perf_counter() - t0
    z, n = z64.astype(np.float32), n64.astype(np.float32)
    rows = [("K=1024 float64 (reference)", ref_s, 0.0)]
    for k in steps:
        t0 = time.perf_counter()
        t = cos_theta_shadow(n, light, 0.01, k, heights_px=z)
        rows.append((f"K={k} float32", time.perf_counter() - t0, float(np.mean(np.abs(t - ref)))))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, default=512, help="march benchmark size in pixels (default 512)")
    ap.add_argument("--out", default=os.path.join("docs", "core-numbers.md"), help="markdown report")
    args = ap.parse_args()

    lines = ["# Measured numbers of the numpy core", "",
             f"Made by `benchmarks/core_numbers.py --size {args.size}` on this project's 2-core "
             "CI machine; rerun it to check them.", "",
             "## Height-map bit depth (pipeline.md §2, §14)", "",
             "Hemisphere of radius 0.4 image widths, height scale 0.4, 256², lit at 45°; N·L against "
             "the exact sphere inside 80 % of its radius.", "",
             "| bits | pre-blur σ (px) | default for this depth | mean error | max error | distinct N·L |",
             "|---|---|---|---|---|---|"]
    for bits, sigma, is_default, mean, mx, levels in bit_depth_table():
        lines.append(f"| {bits if bits < 32 else 'float'} | {sigma} | {'yes' if is_default else ''} | "
                     f"{mean:.5f} | {mx:.5f} | {levels} |")
    lines += ["", f"## The straightforward cos-θ march (§6), {args.size}², one sun at 35° elevation", "",
              "Tall relief (up to half the image width), d = 0.01. This is the baseline the fast "
              "bake is measured against.", "",
              "| setting | time (s) | mean abs error vs reference |", "|---|---|---|"]
    for name, secs, err in march_table(args.size):
        lines.append(f"| {name} | {secs:.2f} | {err:.2e} |")
    lines += ["", "## Art-directed Fresnel fit (§10)", "",
              "Best x1, x2 (κ = 0) against the physical curve, minimax over θ.", "",
              "| η | domain | x1 | x2 | max error |", "|---|---|---|---|---|"]
    for eta in (1.33, 1.5, 2.0):
        for domain in ("sin", "cos"):
            x1, x2, err = fit_art_fresnel(eta, domain, samples=1001)
            lines.append(f"| {eta} | {domain} | {x1:.3f} | {x2:.3f} | {err:.3f} |")
    publish(lines, args.out)


if __name__ == "__main__":
    main()
