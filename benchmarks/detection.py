"""Guessing the conventions of real files (issue 27): what each guess measures on every
convention as other tools write it, the threshold beside it, and fourteen example sets
rendered from their files as found against the painting as its artist meant it.

Conventions (testkit/example_paintings.py draws them): masks painted in one pure
channel (red, green, blue on black), a grey mask, a photograph read as a mask; normal maps in
RGB, two-channel (blue 0), painted for a decoder that halves each tilt (unit vectors) and the
same with vectors of other lengths (the decoder normalises them first), and a photograph read
as a normal map. Variants, as files: 8-bit PNG, 16-bit PNG, 8-bit with export noise (Gaussian,
σ = 1 level, rounded), and JPEG at quality 95, 75, 50 and 30 (Blender's writer, chroma
subsampled). Every file is written and read back through `imageio.read_image`.

The guesses and their statistics (core/inputs.py, core/shape.py):
- mask channel: the other channels' 99.9th percentile over the painted one's (MASK_LEAK);
- two-channel normal map: blue's 99th percentile (TWO_CHANNEL_BLUE);
- halving decoder: the share of tilted pixels whose vectors are unit length (UNIT_SHARE) and
  the share of vectors facing away (HALVING_AWAY).

    .venv/bin/python benchmarks/detection.py --out docs/detection-numbers.md     # ≈ 10 s
"""
import argparse
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from report import command_line, publish  # noqa: E402

from testkit import example_paintings as ex  # noqa: E402
from testkit.artist_folders import write_jpeg  # noqa: E402
from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.inputs import MASK_LEAK, mask_channel  # noqa: E402
from dynpaint_addon.core.inputs import AWAY_NOTE, normal_map_notes, noticeably_away  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.pipeline import render  # noqa: E402
from dynpaint_addon.core.shape import (ALL_AWAY, HALVING_AWAY, TWO_CHANNEL_BLUE,  # noqa: E402
                                       UNIT_SHARE, facing_away, normal_vectors,
                                       resolve_encoding, resolve_strength, unit_share)
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402

VARIANTS = ("png8", "png16", "png8+noise", "jpeg95", "jpeg75", "jpeg50", "jpeg30")
SUN = Light("sun", (-0.55, 0.45, 0.7), (1.0, 0.97, 0.9), 1.0, "Key")


def _disc_mask(size):
    """A mask with soft and hard edges: a soft disc and a box at 0.8."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    soft = np.clip(1 - np.hypot(x - 0.1, y) / 0.35, 0, 1) ** 0.5
    box = ((np.abs(x) < 0.3) & (np.abs(y + 0.1) < 0.2)) * 0.8
    return np.maximum(soft, box)


def _not_unit(normal_map, size):
    """The same map with vectors 0.55 … 1 long (longer toward the rim), as a painting program
    that does not normalise leaves them."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    length = 0.55 + 0.45 * np.clip(np.hypot(x, y) / 0.4, 0, 1)
    return ((2 * normal_map - 1) * length[..., None] + 1) / 2


def conventions(size):
    """{name: (RGB pixels 0..1, kind, as meant, what 'auto' should guess)}: kind 'mask' (the
    channel to read) or 'normal' ((encoding, strength)). A halving decoder's map of vectors
    of other lengths cannot tell: 'auto' reads it as it is and its note says the fix."""
    n, inside = ex.sphere(size, 0.4)
    mask = _disc_mask(size)
    red = ex.red_mask(mask)
    photo = ex.photograph(size, size, seed=3)
    out = {
        "mask painted in red": (red, "mask", "red"),
        "mask painted in green": (np.roll(red, 1, -1), "mask", "green"),
        "mask painted in blue": (np.roll(red, 2, -1), "mask", "blue"),
        "grey mask": (np.repeat(mask[..., None], 3, -1), "mask", "luminance"),
        "photograph as a mask": (photo, "mask", "luminance"),
        "RGB normal map": (ex.normal_map_rgb(n), "normal", ("rgb", 1.0)),
        "two-channel normal map": (ex.normal_map_rg(n), "normal", ("rg", 1.0)),
        "halving decoder, unit vectors": (ex.normal_map_halving(n), "normal", ("rgb", 0.5)),
        "halving decoder, other lengths": (_not_unit(ex.normal_map_halving(n), size), "normal",
                                           ("rgb", 0.5), ("rgb", 1.0)),
        "halving decoder, every pixel away": (ex.normal_map_all_away(n), "normal", ("rgb", 0.5)),
        "RGB normal map, antialiased cut-out": (
            ex.antialiased_cutout(ex.normal_map_rgb(n), inside, size), "normal", ("rgb", 1.0)),
        "photograph as a normal map": (photo, "normal", ("rgb", 1.0)),
    }
    return {name: c if len(c) == 4 else c + (c[2],) for name, c in out.items()}


def as_file(rgb, variant, folder, name):
    """The pixels written as `variant` and read back → ImageData (as a command reads it)."""
    stem = os.path.join(folder, name.replace(" ", "_").replace(",", ""))
    if variant.startswith("jpeg"):
        path = f"{stem}_{variant}.jpg"
        write_jpeg(path, rgb, int(variant[4:]))     # testkit: Blender's writer
    else:
        px = rgb
        if variant == "png8+noise":
            noise = np.random.default_rng(len(name)).normal(0, 1 / 255, rgb.shape)
            px = np.clip(rgb + noise, 0, 1)
        path = f"{stem}_{variant.replace('+', '_')}.png"
        write_png(path, px, bits=16 if variant == "png16" else 8)
    return read_image(path)


def statistics(px, kind):
    """The numbers the guesses read (module docstring)."""
    rgb = px[..., :3].reshape(-1, 3).astype(np.float32)
    if kind == "mask":
        top = np.percentile(rgb, 99.9, axis=0)
        lit = int(np.argmax(top))
        return {"leak": float(np.max(np.delete(top, lit)) / max(top[lit], 1e-6))}
    alpha = px[..., 3] if px.shape[-1] == 4 else None
    encoding = resolve_encoding(px)
    as_read = normal_vectors(px[..., :3], encoding, resolve_strength(px, "auto", encoding, alpha))
    return {"blue p99": float(np.percentile(rgb[:, 2], 99)), "unit share": unit_share(rgb),
            "away": facing_away(2 * px[..., :3] - 1, alpha),
            "away as read": noticeably_away(as_read, alpha)}


def face_away_note(px, kind):
    """Whether the note on pixels facing away fires on the file read with 'auto'."""
    return kind == "normal" and any("face away from the viewer" in n
                                    for n in normal_map_notes(px, "map"))


def guess(px, kind):
    """What 'auto' makes of the pixels: the mask channel, or (encoding, strength)."""
    if kind == "mask":
        return mask_channel(px, "auto")
    encoding = resolve_encoding(px, "auto")
    alpha = px[..., 3] if px.shape[-1] == 4 else None
    return encoding, resolve_strength(px, "auto", encoding, alpha)


def measure(size, folder):
    """[(convention, variant, statistics, guess, expected)] for every convention × variant."""
    rows = []
    for name, (rgb, kind, _, expected) in conventions(size).items():
        for variant in VARIANTS:
            if rgb.shape[-1] == 4 and variant.startswith("jpeg"):
                continue                       # a JPEG holds no alpha: no cut-out
            px = as_file(rgb, variant, folder, name).pixels
            rows.append((name, variant, statistics(px, kind), guess(px, kind), expected,
                         face_away_note(px, kind)))
    return rows


# -- the fourteen example sets ----------------------------------------------------------------
PAINT = (0.16, 0.12, 0.22), (0.95, 0.82, 0.55)


def _images(size, shape, **more):
    dark, bright = (ImageData(np.broadcast_to(np.float32(c), (size, size, 3)).copy(), 8)
                    for c in PAINT)
    return {"shape": shape, "dark": dark, "bright": bright, **more}


def _params(*settings):
    """The defaults with normal maps, no shadows, and each {params path: value} given."""
    p = params.defaults()
    p.shape.kind, p.shadows.enabled = "normal", False
    for path, value in (kv for group in settings for kv in group.items()):
        section, key = path.split(".")
        setattr(getattr(p, section), key, value)
    return p


def glass_set(size, folder, convention, variant):
    """A glass sphere (its shape image's alpha the figure) whose transparency mask is
    `convention`, over a photograph: (images as found, the clean images, the setting that
    reads the mask as meant, the other one)."""
    n, inside = ex.sphere(size, 0.4)
    rgb, _, channel, _ = conventions(size)[convention]
    found = as_file(rgb, variant, folder, f"set {convention}")
    photo = ImageData(ex.photograph(size, size, seed=7).astype(np.float32), 8)
    shape = ImageData(np.concatenate([ex.normal_map_rgb(n), inside[..., None]], -1)
                      .astype(np.float32), 16)
    clean = ImageData(rgb.astype(np.float32), 32)
    other = "red" if channel == "luminance" else "luminance"
    return (_images(size, shape, transparency=found, environment=photo, background=photo),
            _images(size, shape, transparency=clean, environment=photo, background=photo),
            {"transparency.channel": channel}, {"transparency.channel": other})


def normal_set(size, folder, convention, variant):
    """A painting whose normal map is `convention`: as glass_set."""
    rgb, _, (encoding, strength), _ = conventions(size)[convention]
    found = as_file(rgb, variant, folder, f"set {convention}")
    clean = ImageData(rgb.astype(np.float32), 32)
    meant = {"shape.encoding": encoding, "shape.strength": strength}
    other = {**meant, "shape.encoding": "rgb"} if encoding == "rg" else \
        {**meant, "shape.strength": 1.0 if strength != 1 else 0.5}
    return _images(size, found), _images(size, clean), meant, other


# (maker, convention, variant, the keys its recipe names: only a halving decoder's strength
# where the map cannot tell)
SETS = (
    (glass_set, "mask painted in red", "png8+noise", {}),
    (glass_set, "mask painted in red", "jpeg75", {}),
    (glass_set, "mask painted in green", "jpeg50", {}),
    (glass_set, "mask painted in blue", "png16", {}),
    (glass_set, "photograph as a mask", "jpeg75", {}),
    (normal_set, "two-channel normal map", "png8", {}),
    (normal_set, "two-channel normal map", "jpeg75", {}),
    (normal_set, "two-channel normal map", "jpeg30", {}),
    (normal_set, "RGB normal map", "jpeg50", {}),
    (normal_set, "halving decoder, unit vectors", "png8", {}),
    (normal_set, "halving decoder, unit vectors", "jpeg75", {}),
    (normal_set, "halving decoder, other lengths", "png8", {"shape.strength": 0.5}),
    (normal_set, "halving decoder, other lengths", "jpeg50", {"shape.strength": 0.5}),
    (normal_set, "halving decoder, every pixel away", "png8", {}),
    (normal_set, "halving decoder, every pixel away", "jpeg75", {}),
    (normal_set, "RGB normal map, antialiased cut-out", "png8", {}),
    (normal_set, "photograph as a normal map", "jpeg75", {}),
)


def example_sets(size, folder):
    """[(set, the guess's cost, the file's own noise, read the other way, notes)]: each set's
    files rendered with only the keys SETS names, against the same files read with the keys
    that say what was meant (mean |Δ| over RGBA; 0 where the guesses are right); the file's
    own noise is the clean images read as meant against that, for scale."""
    out = []
    for maker, convention, variant, keys in SETS:
        found, clean, meant, other = maker(size, folder, convention, variant)
        as_meant = render(found, [SUN], _params(meant)).rgba
        as_found = render(found, [SUN], _params(keys))
        noise = render(clean, [SUN], _params(meant)).rgba
        misread = render(found, [SUN], _params(other)).rgba
        out.append((f"{convention}, {variant}" + "".join(f"; {k} = {v}" for k, v in keys.items()),
                    float(np.abs(as_found.rgba - as_meant).mean()),
                    float(np.abs(noise - as_meant).mean()),
                    float(np.abs(misread - as_meant).mean()), as_found.warnings))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256],
                    help="image sizes of the files measured, in pixels (default 64 128 256; "
                    "the example sets use the middle one)")
    ap.add_argument("--out", help="write the Markdown report here")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        rows = [row for size in args.sizes for row in measure(size, folder)]
        sets = example_sets(sorted(args.sizes)[len(args.sizes) // 2], folder)
    right = sum(r[3] == r[4] for r in rows)
    # a good map: a normal map that 'auto' can read as meant (a halving decoder's map of other
    # lengths cannot tell), and reads so; a photograph is none
    readable = {name for name, (_, kind, meant, auto) in conventions(8).items()
                if kind == "normal" and meant == auto and not name.startswith("photograph")}
    good_fired = sum(r[5] for r in rows if r[0] in readable and r[3] == r[4])
    lines = [
        "# Guessing the conventions of real files",
        "",
        f"Made by `{command_line(__file__, argv)}`: every convention written as {len(VARIANTS)} "
        f"kinds of file ({', '.join(VARIANTS)}) at {', '.join(f'{s}²' for s in args.sizes)}, "
        "read back as the commands read them; the module docstring says how each is made. "
        "Small files are the hard case: JPEG's 8 × 8 blocks cover more of the figure.",
        "",
        "## What each guess measures",
        "",
        "| convention | guess | statistic: lowest … highest over the files | threshold |",
        "|---|---|---|---|",
    ]
    thresholds = {"leak": f"one channel if ≤ {MASK_LEAK}",
                  "blue p99": f"two-channel if ≤ {TWO_CHANNEL_BLUE}",
                  "unit share": f"unit if ≥ {UNIT_SHARE}",
                  "away": f"halving if ≥ {HALVING_AWAY} (and unit), or ≥ {ALL_AWAY}",
                  "away as read": f"the note if > {AWAY_NOTE}"}
    for name in conventions(8):
        mine = [r for r in rows if r[0] == name]
        kind_guess = mine[0][4]
        for stat in mine[0][2]:
            values = [r[2][stat] for r in mine]
            lines.append(f"| {name} | {kind_guess} | {stat}: {min(values):.3f} … "
                         f"{max(values):.3f} | {thresholds[stat]} |")
    lines += [
        "",
        f"Guessed as meant: **{right} of {len(rows)}** files"
        + ("." if right == len(rows) else ": " + "; ".join(
            f"{n} {v} → {g}" for n, v, _, g, e, _ in rows if g != e)),
        "",
        "## The note on pixels facing away",
        "",
        "It should fire only where tilting those pixels back up changes the picture: on a "
        "map read the wrong way (a halving decoder's map of other lengths, which cannot tell; "
        "a photograph read as a normal map), never on a map read as meant — '*away as read*' "
        "above counts the figure's inside only (alpha ≥ 0.99 with every neighbour so) and "
        "only beyond the minimum N.z.",
        "",
        "| convention | fires on | files |",
        "|---|---|---|",
        *[f"| {name} | {sum(r[5] for r in rows if r[0] == name)} | "
          f"{sum(1 for r in rows if r[0] == name)} |"
          for name, (_, kind, *_) in conventions(8).items() if kind == "normal"],
        "",
        f"Good maps (read as meant by 'auto') it fires on: **{good_fired}** (goal 0).",
        "",
        "## Example sets, as found",
        "",
        "Each rendered by the numpy core from its files with no key that names a convention "
        "(except the strength of a halving decoder's map whose vectors are not unit length, "
        "where the map cannot tell), against the same files read with the keys that say what "
        "was meant (mean |Δ| over RGBA, linear: 0 where every guess is right). For scale: the "
        "file's own noise (its clean images against it) and the files read the other way.",
        "",
        "| set | as found | the file's noise | read the other way | notes |",
        "|---|---|---|---|---|",
        *[f"| {name} | {err:.2g} | {noise:.4f} | {wrong:.4f} | {'<br>'.join(notes) or '—'} |"
          for name, err, noise, wrong, notes in sets],
    ]
    publish(lines, args.out)
    return 0 if right == len(rows) and good_fired == 0 and all(e == 0 for _, e, *_ in sets) \
        else 1


if __name__ == "__main__":
    sys.exit(main())
