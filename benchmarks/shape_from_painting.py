"""Shape from the painting (issue 16) against true 3D: every method, its goal beside it.

Ground truth from Blender (benchmarks/ground_truth.py's scene tools, Cycles): a sphere, a
torus, Suzanne and two boxes, each alone on a ground plane seen from above, rendered as a
height map, a normal map, an object index, and lit by hard suns (white diffuse, direct light
only: a lit pixel reads N·L × visibility). The same renders lit from Sprite Lamp's sides are
the lighting profiles.

1. Integration (core/integrate.py): time at 1024² (best of 3), height error on smooth shapes;
   cast shadows baked from the integrated height of each object's *normal map* against those
   of its true height map (IoU of the cast-shadow regions, mean |t − 3D|), and the normal
   map's own along-the-ray shadows (the paper's way) beside them; the boxes with a mask.
2. Profiles → normals (core/photometric.py): mean angular error with 2, 3, 4, 5 profiles.
3. Inflation (core/inflate.py): a disc against its hemisphere, and the time at 1024².

    .venv/bin/python benchmarks/shape_from_painting.py --size 256 --out docs/shape-numbers.md
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import ground_truth as gt  # noqa: E402  (imports bpy)
import shadow_quality as sq  # noqa: E402
from report import command_line, publish  # noqa: E402

from dynpaint_addon.core.inflate import inflate  # noqa: E402
from dynpaint_addon.core.integrate import integrate  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.photometric import normals_from_profiles, profile_directions  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from dynpaint_addon.core.shape import decode_normal_map, normals_from_height_px  # noqa: E402

# Each scene alone on the ground (heights in image widths; the image spans [-0.5, 0.5]²),
# sunk to its outline: what a normal map describes (seen from above, nothing hides below
# the outline). A sphere *resting* on the ground hides a wall as tall as its radius under its
# outline, like a box: it is measured apart.
SMOOTH = {
    "sphere": [("sphere", "sphere", (0.0, 0.0, 0.0), 0.2)],
    "torus": [("torus", "torus", (0.0, 0.0, 0.0), (0.2, 0.07))],
    "Suzanne": [("Suzanne", "monkey", (0.0, 0.0, 0.0), 0.55)],
}
RESTING = {"sphere resting on the ground": [("sphere", "sphere", (0.0, 0.0, 0.16), 0.16)]}
BOXES = {"low box": [("low box", "box", (0.0, 0.0, 0.03), (0.14, 0.12, 0.06))],
         "tall box": [("tall box", "box", (0.0, 0.0, 0.08), (0.12, 0.12, 0.16))]}
PROFILE_SCENE = [("sphere", "sphere", (-0.22, 0.2, 0.12), 0.12),
                                        ("torus", "torus", (0.22, 0.22, 0.035), (0.1, 0.035)),
                                        ("Suzanne", "monkey", (0.0, -0.2, 0.08), 0.4)]
PROFILE_SETS = [("left", "right"), ("left", "right", "top"),
                ("left", "right", "top", "bottom"), ("left", "right", "top", "bottom", "front")]
WALL = 0.03     # image widths: a step this tall between neighbouring pixels is a hidden wall
GOALS = {"integrate_s": 0.2, "height_error": 0.005, "iou_ratio": 0.9, "t_gap": 0.01,
         "angle": {4: 4.0, 5: 3.0}, "hemisphere": 0.01, "inflate_s": 1.0}


def best_of(fn):
    """(the least time of shadow_quality's RUNS runs, the result)."""
    runs = [sq.timed(fn) for _ in range(sq.RUNS)]
    return min(t for _, t in runs), runs[-1][0]


def met(ok):
    return "met" if ok else "**not met**"


def smooth_height_errors(size=1024):
    """Integration of analytic smooth shapes' §2 normals: max |error| / relief, and the time."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    shapes = {"Gaussian hill": 0.1 * np.exp(-(x * x + y * y) / (2 * 0.12 ** 2)),
              "ball cap (r 0.6, cut at 0.35)":
                  np.where(x * x + y * y < 0.35 ** 2,
                           np.sqrt(np.clip(0.36 - x * x - y * y, 0, None))
                           - np.sqrt(0.36 - 0.35 ** 2),
                           0.0),
              "waves": 0.02 * np.sin(6 * np.pi * x) * np.cos(4 * np.pi * y)}
    rows, seconds = [], None
    for name, z in shapes.items():
        n = normals_from_height_px(z * size, 0.001)
        seconds_here, r = best_of(lambda: integrate(n))
        seconds = seconds_here if seconds is None else min(seconds, seconds_here)
        err = np.abs((r.height - r.height.mean()) - (z - z.mean())).max() / np.ptp(z)
        rows.append((name, float(err), r.residual_share))
    return rows, seconds


def scene_maps(objects, size, folder):
    scene = gt.build_scene(size, objects)
    z, nworld, index = gt.render_maps(scene, folder)
    n_map = decode_normal_map(ImageData((nworld + 1) / 2, 32).rgb()).astype(np.float64)
    return scene, z.astype(np.float64), nworld.astype(np.float64), n_map, index


def shadows_against_truth(objects, size, offset, steps, folder, heights):
    """{method: (mean |t − 3D|, cast-shadow IoU)} averaged over the suns, for the true height
    map and each method in `heights` (name → fn(n_map, z_true, index) → heights in widths, or
    None for the normal map's own along-the-ray shadows)."""
    scene, z, nworld, n_map, index = scene_maps(objects, size, folder)
    n_true = normals_from_height_px(z * size)
    made = {name: (fn(n_map, z, index) if fn else None) for name, fn in heights.items()}
    acc = {}
    for elevation, azimuth in gt.SUNS:
        truth = gt.render_truth(scene, folder, elevation, azimuth)
        light = Light("sun", gt.sun_direction(elevation, azimuth))
        ndl = np.clip(nworld @ np.array(gt.sun_direction(elevation, azimuth)), 0, 1)
        bakes = {"true height map": cos_theta_shadow(n_true, light, offset, steps,
                                                     heights_px=z * size)}
        for name, zz in made.items():
            bakes[name] = cos_theta_shadow(n_map, light, offset, steps, heights_px=zz * size) \
                if zz is not None else cos_theta_shadow(
                    n_map, light, offset, steps, slopes=-n_map[..., :2] / n_map[..., 2:3],
                    reach=0.05)
        for name, t in bakes.items():
            a, b = gt.cast_shadow(truth, ndl), gt.cast_shadow(t, ndl)
            iou = (a & b).sum() / max((a | b).sum(), 1)
            acc.setdefault(name, []).append((float(np.abs(t - truth).mean()), float(iou)))
    return {k: (float(np.mean([e for e, _ in v])), float(np.mean([i for _, i in v])))
            for k, v in acc.items()}


def border_depth(z, index):
    """The true height of the figures' rims above the ground beside them (what an artist
    would set as --depth): the median over figure pixels that touch the ground."""
    fig = index > 0
    inner = np.roll(fig, 1, 0) & np.roll(fig, -1, 0) & np.roll(fig, 1, 1) & np.roll(fig, -1, 1)
    rim = fig & ~inner
    return float(np.median(z[rim])) if rim.any() else 0.0


def true_walls(z):
    """The edges where the true height steps by more than WALL: the hidden walls, known only
    from the 3D truth (the bound in the table: what knowing them would give)."""
    return np.abs(np.diff(z, axis=1)) > WALL, np.abs(np.diff(z, axis=0)) > WALL


def default_relief(n_map, z, index):
    """The relief the add-on's shadows fall from (§6 "Relief"): the normal map integrated with
    its figure cut at the alpha (here the object index)."""
    return integrate(n_map, index > 0, precise=False).height


def relief_with_true_walls(n_map, z, index):
    """The bound: default_relief also cut at the true walls."""
    return integrate(n_map, index > 0, precise=False, breaks=true_walls(z)).height


def profile_errors(size, elevation, folder):
    """Mean angular error (degrees) of normals from Cycles-rendered profiles, per profile set,
    over the objects' pixels (cast shadows on the ground and on Suzanne included)."""
    scene, z, nworld, n_map, index = scene_maps(PROFILE_SCENE, size, folder)
    shots = {}
    for side, d in profile_directions(("left", "right", "top", "bottom", "front"),
                                      elevation).items():
        el = np.degrees(np.arcsin(d[2]))
        az = np.degrees(np.arctan2(d[1], d[0]))
        shots[side] = gt.render_truth(scene, folder, round(float(el), 6), round(float(az), 6))
    objects = index > 0
    rows = []
    for sides in PROFILE_SETS:
        got = normals_from_profiles({s: shots[s] for s in sides}, elevation)
        ang = np.degrees(np.arccos(np.clip(np.sum(got * n_map, -1), -1, 1)))
        rows.append((len(sides), ", ".join(sides), float(ang[objects].mean()),
                     float(np.median(ang[objects]))))
    return rows


def hemisphere(size=1024, radius=0.4):
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    r2 = x * x + y * y
    disc = r2 < radius ** 2
    seconds, result = best_of(lambda: inflate(disc))
    true = np.sqrt(np.clip(radius ** 2 - r2, 0, None))
    err = np.abs(result.height - true)
    inner = r2 < (0.9 * radius) ** 2
    return (seconds, abs(result.height.max() - radius) / radius, err[inner].max() / radius,
            float(np.sqrt(np.mean(err[disc] ** 2))) / radius)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=256, help="3D renders' size in pixels")
    ap.add_argument("--offset", type=float, default=0.01, help="d in image widths")
    ap.add_argument("--steps", type=int, default=256, help="K of the shadow bakes")
    ap.add_argument("--elevation", type=float, nargs="+", default=[45.0, 30.0],
                    help="the profiles' side lights above the painting (degrees; the goals "
                    "are judged at the first)")
    ap.add_argument("--out", help="Markdown report")
    args = ap.parse_args(argv)
    folder = tempfile.mkdtemp()
    command = command_line(__file__, argv)
    lines = ["# Shape from the painting, measured (issue 16)", "",
             f"`{command}` on this machine; 3D truth from Cycles ({args.size}², hard suns at "
             f"{', '.join(f'{e}°/{a}°' for e, a in gt.SUNS)} elevation/azimuth, white diffuse, "
             f"direct light only). Shadows: the numpy core's march, d = {args.offset} image "
             f"widths, K = {args.steps}. Cast shadow: a pixel facing the sun that gets less "
             "than half of N·L.", "", "## 1. Normal map → height (integration)", ""]

    rows, seconds = smooth_height_errors()
    lines += [f"Time at 1024² (best of 3): **{seconds:.3f} s** (goal ≤ {GOALS['integrate_s']} s: "
              f"{met(seconds <= GOALS['integrate_s'])}).", "",
              "| smooth shape (1024², §2 normals) | max height error / relief | goal | "
              "residual share |", "|---|---|---|---|"]
    for name, err, share in rows:
        lines.append(f"| {name} | {100 * err:.3f} % | ≤ {100 * GOALS['height_error']:.1f} %: "
                     f"{met(err <= GOALS['height_error'])} | {100 * share:.3f} % |")

    default = "integrated, cut at the figure's alpha (the default relief)"
    walls_known = f"bound: also cut at the true walls (steps > {WALL} widths, from 3D)"
    methods = {"integrated, no alpha": lambda n, z, index: integrate(n).height,
               default: default_relief,
               "along the ray (reach 0.05, the paper's way)": None,
               walls_known: relief_with_true_walls}
    lines += ["", "### Cast shadows of each object's normal map", "",
              "| object | method | mean \\|t − 3D\\| | cast-shadow IoU | goal |",
              "|---|---|---|---|---|"]
    ratios = {}
    for name, objects in {**SMOOTH, **RESTING}.items():
        res = shadows_against_truth(objects, args.size, args.offset, args.steps, folder, methods)
        true_err, true_iou = res["true height map"]
        for method, (err, iou) in res.items():
            goal = ""
            if name in RESTING:
                lines.append(f"| {name} | {method} | {err:.4f} | {iou:.3f} | (hidden wall) |")
                continue
            if method == default:
                ok = iou >= GOALS["iou_ratio"] * true_iou and err <= true_err + GOALS["t_gap"]
                goal = (f"IoU ≥ 0.9 × {true_iou:.3f}, error ≤ {true_err:.4f} + 0.01: {met(ok)}")
            ratios.setdefault(method, []).append((iou, err))
            lines.append(f"| {name} | {method} | {err:.4f} | {iou:.3f} | {goal} |")
    true_iou = np.mean([i for i, _ in ratios["true height map"]])
    true_err = np.mean([e for _, e in ratios["true height map"]])
    for method, vals in ratios.items():
        iou, err = np.mean([i for i, _ in vals]), np.mean([e for _, e in vals])
        ok = "" if method in ("true height map", walls_known) else (
            f"IoU ≥ 0.9 × {true_iou:.3f}, error ≤ {true_err:.4f} + 0.01: "
            f"{met(iou >= GOALS['iou_ratio'] * true_iou and err <= true_err + GOALS['t_gap'])}")
        lines.append(f"| **mean of the three** | {method} | {err:.4f} | {iou:.3f} "
                     f"({iou / true_iou:.2f} × true) | {ok} |")
    bound = np.mean([i for i, _ in ratios[walls_known]]) / true_iou
    lines += ["", f"The bound cuts the integration also where the true height steps by more than "
              f"{WALL} image widths between neighbouring pixels, which only the 3D scene knows: "
              f"{bound:.2f} × the true map's IoU. What the default relief misses is those "
              "hidden walls (Suzanne's muzzle and the rims of her ears stand above what lies "
              "beside them); the normals on either side of a wall are smooth, so no normal "
              "map records where it is or how tall it is. The resting sphere's wall is its "
              "whole rim, which the alpha cuts already: what it lacks is the rim's height, "
              "the depth an artist sets (as for the boxes below)."]

    box_methods = {k: v for k, v in methods.items() if k != walls_known}
    box_methods["integrated, box masked, depth = its rim's true height"] = \
        lambda n, z, index: integrate(n, index > 0, border_depth(z, index)).height
    lines += ["", "### Boxes: walls no normal map sees", "",
              "A box's normal map is flat everywhere: only a mask and the depth of its rim "
              "(`--depth`) can say that it stands out.", "",
              "| box | method | mean \\|t − 3D\\| | cast-shadow IoU |", "|---|---|---|---|"]
    for name, objects in BOXES.items():
        res = shadows_against_truth(objects, args.size, args.offset, args.steps, folder,
                                    box_methods)
        lines += [f"| {name} | {m} | {e:.4f} | {i:.3f} |" for m, (e, i) in res.items()]

    lines += ["", "## 2. Lighting profiles → normals (Cycles profiles with their cast shadows; "
              "sphere, torus, Suzanne resting on the ground; error over their pixels)", "",
              "| side lights | profiles | sides | mean angular error | median | goal |",
              "|---|---|---|---|---|---|"]
    for k, elevation in enumerate(args.elevation):
        for count, sides, mean, median in profile_errors(args.size, elevation, folder):
            goal = GOALS["angle"].get(count) if k == 0 else None
            lines.append(f"| {elevation:g}° | {count} | {sides} | {mean:.2f}° | {median:.2f}° | "
                         + (f"≤ {goal:g}°: {met(mean <= goal)}" if goal else "reported") + " |")

    seconds, peak, inner, rms = hemisphere()
    lines += ["", "## 3. Inflating a silhouette", "",
              "A disc of radius 0.4 image widths at 1024², round profile, against the hemisphere "
              "√(R² − r²):", "",
              "| measure | value | goal |", "|---|---|---|",
              f"| time (best of 3) | {seconds:.3f} s | ≤ {GOALS['inflate_s']:g} s: "
              f"{met(seconds <= GOALS['inflate_s'])} |",
              f"| peak height error | {100 * peak:.2f} % of R | ≤ 1 %: "
              f"{met(peak <= GOALS['hemisphere'])} |",
              f"| largest error inside 0.9 R | {100 * inner:.2f} % of R | ≤ 1 %: "
              f"{met(inner <= GOALS['hemisphere'])} |",
              f"| RMS error over the disc | {100 * rms:.2f} % of R | ≤ 1 %: "
              f"{met(rms <= GOALS['hemisphere'])} |", "",
              "Near the rim the disc's pixel staircase is the error: the hemisphere rises "
              "√(2RΔ) within the last pixel Δ, so no pixel grid holds it within 1 % there."]
    publish(lines, args.out)


if __name__ == "__main__":
    main()
