"""Why point lights march at final quality (issue 4; docs/limits.md): aimed crossings at full
resolution against the K = 64 march, on tall and on ordinary relief, in one run.

The reference ray of a point light (pipeline.md §6) starts at P0 = P_S − d·N_S and runs along
L(P_S), so it passes the light d·|N.xy| to the side: rays share no grid. Aimed crossings
(core/crossings.py, _PointGrid) aim every ray at the light instead. This prints, per relief,
the time and mean |Δt| (against K = 1024, float64) of both, and the aimed error on flat
pixels (|N.xy| < 0.01, where the aimed ray is the reference's ray) and on slopes.

    .venv/bin/python benchmarks/point_light_study.py --size 1024
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import shadow_quality as sq  # noqa: E402

from dynpaint_addon.core import crossings  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402

LIGHT = sq.CASES[3][2]      # the benchmark's point light


def study(size, relief):
    n64, z64, _ = sq.shape(size, "height", np.float64, relief)
    ref = cos_theta_shadow(n64, LIGHT, sq.OFFSET, 1024, heights_px=z64)
    n, z, _ = sq.shape(size, "height", np.float32, relief)
    march = [sq.timed(lambda: cos_theta_shadow(n, LIGHT, sq.OFFSET, 64, heights_px=z))
             for _ in range(sq.RUNS)]
    aimed = [sq.timed(lambda: crossings.point_cos_theta(n, LIGHT, sq.OFFSET, heights_px=z))
             for _ in range(sq.RUNS)]
    base_s = min(s for _, s in march)
    err = np.abs(aimed[0][0] - ref)
    flat = np.hypot(n[..., 0], n[..., 1]) < 0.01
    print(f"relief {relief} image widths, {size}²:")
    print(f"  K = 64 march      {base_s:.3f} s  1.000×  "
          f"mean {np.abs(march[0][0] - ref).mean():.1e}")
    aimed_s = min(s for _, s in aimed)
    print(f"  aimed crossings   {aimed_s:.3f} s  {aimed_s / base_s:.3f}×  mean {err.mean():.1e}"
          f"  (flat pixels, {flat.mean():.0%}: {err[flat].mean():.1e}; slopes: "
          f"{err[~flat].mean():.1e})", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=1024)
    args = ap.parse_args()
    for relief in (0.5, 0.1):
        study(args.size, relief)


if __name__ == "__main__":
    main()
