"""Artists' files as they come, tried as a newcomer tries them (issue 59): each set of
benchmarks/artists_files.toml (public files from SpriteIlluminator's, Laigter's, Godot's,
Unity's, TexturePacker's and Blender users' repositories, fetched at a named commit), a few
variants of them (a map saved as JPEG, a map's green turned down), and the generated sets of
testkit/sprite_sets.py, each through `dynpaint new FOLDER` and `dynpaint render FOLDER` with no
hand edit.

Measured per set (testkit.sprite_sets.judge): the render over the colour image against the
true N·L (Pearson r; goal ≥ 0.5), the colour's alpha kept (IoU; goal ≥ 0.98), the share of the
pixels facing the light (true N·L ≥ 0.6) left in shadow (goal ≤ 15 %), numbered frames and
atlases on two of their frames; and the seconds `new` + `render` took, as the user waits. The
baseline, in the same run: the same render with the map read the other way (what reading the
green wrong costs), and the unlit picture every set gave before (r = 0: the colour image).

    .venv/bin/python benchmarks/artists_files.py --out docs/artists-files.md     # ≈ 3 min
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
import urllib.request

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, REPO)

from report import command_line, met, publish  # noqa: E402

from dynpaint_addon.core.frames import expand_pattern  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.lights import DEFAULT_SUN_DIRECTION, Light  # noqa: E402
from dynpaint_addon.core.pipeline import render  # noqa: E402
from dynpaint_addon.core.shape import decode_normal_map  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.painting_frames import PaintingFrames  # noqa: E402
from dynpaint_addon.inputs.recipe import load_recipe  # noqa: E402
from testkit import sprite_sets  # noqa: E402
from testkit.artist_folders import write_jpeg  # noqa: E402

FETCH_LIST = os.path.join(HERE, "artists_files.toml")
CACHE = os.path.join(HERE, "artists_files")
MIRRORS = os.environ.get("DYNPAINT_MIRRORS", "/work/.mirror")
LIGHT = np.asarray(DEFAULT_SUN_DIRECTION) / np.linalg.norm(DEFAULT_SUN_DIRECTION)
GOALS = "r ≥ 0.5, IoU ≥ 0.98, shadowed ≤ 0.15"


def fetch(entry):
    """The set's files in CACHE/<name>/ (fetched once): from a git mirror of the repository
    when there is one, else from raw.githubusercontent.com at the commit."""
    folder = os.path.join(CACHE, entry["name"])
    if all(os.path.isfile(os.path.join(folder, n)) for n in entry["files"]):
        return folder
    os.makedirs(folder, exist_ok=True)
    mirror = os.path.join(MIRRORS, entry["repo"].replace("/", "+"), "repo")
    for name, path in entry["files"].items():
        if os.path.isdir(mirror):
            data = subprocess.run(["git", f"--git-dir={mirror}", "show",
                                   f"{entry['commit']}:{path}"], capture_output=True,
                                  check=True).stdout
        else:
            url = (f"https://raw.githubusercontent.com/{entry['repo']}/{entry['commit']}/"
                   + urllib.request.quote(path))
            try:
                with urllib.request.urlopen(url, timeout=60) as response:
                    data = response.read()
            except OSError as exc:       # (URLError is one): offline, no mirror — say so
                raise SystemExit(f"artists_files: {entry['name']}: {path} could not be "
                                 f"fetched ({exc}); it needs the network or a git mirror "
                                 f"of {entry['repo']} under {MIRRORS} (DYNPAINT_MIRRORS)")
        with open(os.path.join(folder, name), "wb") as fh:
            fh.write(data)
    return folder


def dynpaint(*args):
    """`dynpaint ARGS` as the user runs it → (seconds, what it printed)."""
    start = time.perf_counter()
    res = subprocess.run([sys.executable, "-m", "dynpaint_addon", *map(str, args)],
                         capture_output=True, text=True, cwd=REPO)
    if res.returncode:
        raise RuntimeError(f"dynpaint {' '.join(map(str, args))}: {res.stderr.strip()}")
    return time.perf_counter() - start, res.stderr + res.stdout


def true_normals(recipe, frame, green):
    """The map of `frame` read in its true convention: the truth the render is judged by."""
    shape = read_image(expand_pattern(recipe.images["shape"], frame))
    return decode_normal_map(shape.rgb().astype(np.float64), green == "down", 0.05, "auto",
                             "auto", shape.alpha())


def try_set(name, tool, folder, green, frames, work):
    """`new` + `render` of a copy of `folder` → a report row's values."""
    copy = os.path.join(work, name)
    shutil.copytree(folder, copy)
    seconds, said = dynpaint("new", copy)
    recipe = load_recipe(os.path.join(copy, "painting.toml"))
    read_down = bool(recipe.params.shape.flip_green)
    shown = [1, frames // 2 + 1] if frames > 1 else [1]
    ambient = recipe.params.diffuse.ambient     # (what the render lit the colour with, §1)
    verdicts, wrong, unshadowed, finer, picture = [], [], [], [], None
    for frame in shown:
        out = os.path.join(work, f"{name}_{frame}.exr")
        took, _ = dynpaint("render", copy, "--out", out, *(["--frame", frame] if frames > 1
                                                           else []))
        seconds += took
        colour = read_image(expand_pattern(recipe.images["bright"], frame)).pixels
        alpha = colour[..., 3] if colour.shape[2] in (2, 4) else None
        rgba = np.dstack([ImageData(colour).rgb(), np.ones(colour.shape[:2]) if alpha is None
                          else alpha])
        full = alpha is None or alpha.min() > 0.99
        n = true_normals(recipe, frame, green)
        got = read_image(out).pixels

        def judged(render_rgba):
            return sprite_sets.judge(render_rgba, rgba, n, None if full else alpha, LIGHT,
                                     ambient)
        half = half_offset(recipe, frame)
        verdicts.append(judged(got))
        wrong.append(judged(other_way(recipe, frame)).pearson)
        unshadowed.append(judged(shadows_off(recipe, frame)).pearson)
        finer.append(judged(half).pearson)
        if picture is None:
            picture = [n @ LIGHT] + [sprite_sets.light_received(px, rgba, ambient)
                                     for px in (got, half)]
    worst = min(verdicts, key=lambda v: (v.passes(), -1 if v.pearson is None else v.pearson))
    return {"name": name, "tool": tool, "size": f"{got.shape[1]}×{got.shape[0]}",
            "frames": frames, "read": "down" if read_down else "up", "true": green,
            "verdict": worst, "wrong_r": None if None in wrong else min(wrong),
            "unshadowed_r": None if None in unshadowed else min(unshadowed),
            "finer_r": None if None in finer else min(finer),
            "offset": recipe.params.shadows.offset, "width": got.shape[1],
            "picture": picture, "seconds": seconds}


def where_it_varies(ndl, rows=40, cols=200):
    """The window (rows × cols at most) of a true N·L image where it varies most → slices."""
    def band(spread, n):
        n = min(n, spread.size)
        sums = np.convolve(spread, np.ones(n), "valid")
        start = int(np.argmax(sums))
        return slice(start, start + n)
    ys = band(np.nanvar(ndl, axis=1), rows)
    xs = band(np.nanvar(ndl[ys], axis=0), cols)
    return ys, xs


def write_picture(path, tiles, zoom=3):
    """Tiles (y-up greys: the true N·L, the light received at d and at ½d), cut where N·L
    varies most, enlarged `zoom` times, stacked top to bottom with a white gap."""
    ys, xs = where_it_varies(tiles[0])
    gap = np.ones((2, (xs.stop - xs.start) * zoom, 3))
    parts = []
    for tile in tiles:             # (y-up: the first tile last, so that it shows on top)
        cut = tile[ys, xs]
        rgb = np.where(np.isnan(cut)[..., None], UNMEASURED,
                       np.clip(np.nan_to_num(cut), 0, 1)[..., None])
        parts = [rgb.repeat(zoom, 0).repeat(zoom, 1), gap] + parts
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_png(path, np.concatenate(parts[:-1], 0))


UNMEASURED = (0.85, 0.35, 0.3)     # a picture's pixels whose colour is too dark to tell


def _px(row):
    """The row's offset d in the image's pixels."""
    return f"{row['offset'] * row['width']:.1f}"


def _r(value):
    return "— (flat)" if value is None else f"{value:.2f}"


def variant(recipe, frame, section, key, value):
    """The recipe's render of `frame` with one setting changed → premultiplied RGBA."""
    p = getattr(recipe.params, section)
    kept = getattr(p, key)
    setattr(p, key, value)
    images = PaintingFrames(recipe.slots()).images(frame)
    result = render(images, [Light("sun", tuple(LIGHT))], recipe.params, keep_passes=False)
    setattr(p, key, kept)
    return result.rgba


def other_way(recipe, frame):
    """Baseline: the recipe's render with the map read the other way."""
    return variant(recipe, frame, "shape", "flip_green", not recipe.params.shape.flip_green)


def shadows_off(recipe, frame):
    """The reading alone: the render without its cast shadows (§6 off)."""
    return variant(recipe, frame, "shadows", "enabled", False)


def half_offset(recipe, frame):
    """The cos-θ term's softness (§6: rays start d below the surface, so relief finer than d
    is smoothed): the recipe's render with half its offset d."""
    return variant(recipe, frame, "shadows", "offset", recipe.params.shadows.offset / 2)


# Sets made from fetched ones, as artists also hand them over: (name, what it is, the set it
# comes from, its colour image, its map, the map's name in the variant, the map's true green)
VARIANTS = (
    ("walk_frame_jpeg_map", "SpriteIlluminator's first frame, its map saved as JPEG (85)",
     "spriteilluminator_walk", "01.png", "01_n.png", "01_n.jpg", "up"),
    ("unity_nori_green_down", "Unity's Nori, its map's green turned down (DirectX style)",
     "unity_nori", "Nori.png", "Nori_n.png", "Nori_n.png", "down"),
)


def variants(entries, work):
    """The VARIANTS whose source set is listed → [(name, tool, folder, true green, frames)]."""
    out = []
    by_name = {e["name"]: e for e in entries}
    for name, tool, source, colour, normal, saved_as, green in VARIANTS:
        if source not in by_name:
            continue
        folder = os.path.join(work, f"src_{name}")
        os.makedirs(folder)
        src = fetch(by_name[source])
        shutil.copy(os.path.join(src, colour), folder)
        n = read_image(os.path.join(src, normal)).pixels.copy()
        if green == "down":
            n[..., 1] = 1 - n[..., 1]
        if saved_as.endswith(".jpg"):
            write_jpeg(os.path.join(folder, saved_as), ImageData(n).rgb().astype(np.float32), 85)
        else:
            write_png(os.path.join(folder, saved_as), n)
        out.append((name, tool, folder, green, 1))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", help="Markdown report")
    ap.add_argument("--only", nargs="*", help="set names to try (default: all)")
    args = ap.parse_args(argv)
    with open(FETCH_LIST, "rb") as fh:
        entries = tomllib.load(fh)["set"]
    rows = []
    with tempfile.TemporaryDirectory() as work:
        tries = [(e["name"], e["tool"], fetch(e), e["green"], e.get("frames", 1))
                 for e in entries]
        tries += variants(entries, work)
        made = os.path.join(work, "generated")
        tries += [(f"made_{os.path.basename(s.folder)}", f"generated: {s.tool}", s.folder,
                   s.green, s.frames) for s in sprite_sets.write_all(made)]
        for name, tool, folder, green, frames in tries:
            if args.only and name not in args.only:
                continue
            rows.append(try_set(name, tool, folder, green, frames, work))
            r = rows[-1]
            print(f"{name}: r {_r(r['verdict'].pearson)}, IoU {r['verdict'].iou:.3f}, "
                  f"shadowed {r['verdict'].shadowed:.3f}, {r['seconds']:.1f} s", flush=True)
    lines = ["# Artists' files, lit at the first try (issue 59)", "",
             f"`{command_line(__file__, argv)}` — every set through `dynpaint new FOLDER` and "
             f"`dynpaint render FOLDER` with no hand edit (numpy engine, the recipe's Key sun "
             f"from the upper left). Goals per set: {GOALS}. Baseline in the same run: the "
             f"map read the other way (r), and before issue 59 every set rendered its colour "
             f"image unlit (r = 0). A figure whose true N·L hardly varies (spread under "
             f"{sprite_sets.FLAT_SPREAD}: a flat card) has no light to follow: its r is not "
             f"judged.", "",
             "| set | tool | size | frames | green read (true) | r | IoU | shadowed | r, read the other way | r, shadows off | r, offset ½d | new + render | goals |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        v = r["verdict"]
        lines.append(f"| {r['name']} | {r['tool']} | {r['size']} | {r['frames']} | "
                     f"{r['read']} ({r['true']}) | {_r(v.pearson)} | {v.iou:.3f} | "
                     f"{v.shadowed:.3f} | {_r(r['wrong_r'])} | {_r(r['unshadowed_r'])} | "
                     f"{_r(r['finer_r'])} | {r['seconds']:.1f} s | "
                     f"{met(v.passes() and r['read'] == r['true'])} |")
    passed = sum(r["verdict"].passes() and r["read"] == r["true"] for r in rows)
    lines += ["", f"{passed} of {len(rows)} sets meet every goal."]
    short = [r for r in rows if not r["verdict"].passes() and r["verdict"].iou >= 0.98 and
             r["verdict"].shadowed <= 0.15 and (r["unshadowed_r"] or 0) >= 0.5]
    if short:
        lines += ["", f"Short of r alone, with every other goal met and r ≥ 0.5 with shadows "
                  f"off: {', '.join(r['name'] for r in short)}. The map is read right there "
                  f"(r with shadows off: "
                  f"{', '.join(_r(r['unshadowed_r']) for r in short)}). On a figure whose N·L "
                  f"varies only at fine relief (a flat card with raised lettering: the light "
                  f"changes only the letters' rims, 1–3 px wide) r measures that relief alone, "
                  f"and the cos-θ term smooths relief finer than its offset d (§6: each ray "
                  f"starts d below the surface; d = "
                  f"{', '.join(_px(r) for r in short)} px here), "
                  f"which is the paper's subsurface look; the letters' cast shadows (under "
                  f"{max(r['verdict'].shadowed for r in short):.1%} of the pixels facing the "
                  f"light) lower it further. With half the offset, r is "
                  f"{', '.join(_r(r['finer_r']) for r in short)} (the column beside it: on "
                  f"{sum((r['finer_r'] or 0) >= (r['verdict'].pearson or 0) for r in rows)} of "
                  f"{len(rows)} sets r is as high or higher with it, but d is the artist's "
                  f"softness and every shadow number of the project is measured at the default)."]
        if args.out:
            lines += ["", "Where their N·L varies most (3× enlarged): the true N·L, the light "
                      "the render received, and the light with half the offset (red: a colour "
                      "too dark to tell) — the letters' lit and shaded rims blurred at d, "
                      "sharper at ½d.", "",
                      "| set | N·L, received at d, at ½d |", "|---|---|"]
            for r in short:
                picture = f"img/artists-files/{r['name']}.png"
                write_picture(os.path.join(os.path.dirname(args.out), picture), r["picture"])
                lines.append(f"| {r['name']} | ![]({picture}) |")
    publish(lines, args.out)
    return 0 if passed == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())
