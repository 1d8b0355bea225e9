"""Generate docs/your-painting.md: the first hour on the command line (issues 27, 38, 59) — a
sprite and its normal map, then a folder of a painting's images, to a render, a turntable and
a web page with `dynpaint new` and the README alone. The commands run here as a user types them (`.venv/bin/dynpaint` from the
painting's own folder, no PYTHONPATH), and the pictures show what each one wrote.

    .venv/bin/python docs/make_walkthrough.py        # ≈ 20 s (needs Chromium for the page)
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(DOCS)
sys.path.insert(0, REPO)

from dynpaint_addon.inputs.imageio import read_image, write_png        # noqa: E402
from dynpaint_addon.core.lights import Light          # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render        # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe        # noqa: E402
from dynpaint_addon.params import defaults          # noqa: E402
from testkit.chromium import find_chromium           # noqa: E402
from testkit.sprite_sets import sprite_illuminator   # noqa: E402

PX = 256
OFFSET = defaults().shadows.offset
DYNPAINT = os.path.join(os.path.dirname(sys.executable), "dynpaint")


def pear(size=PX):
    """A painted pear with its figure in the alpha (y-up, straight alpha): the bright image and
    its shaded copy (the dark image)."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    body = np.hypot(x / 0.26, (y + 0.12) / 0.27)
    top = np.hypot(x / 0.15, (y - 0.13) / 0.18)
    stem = (np.abs(x - 0.01 - 0.15 * (y - 0.3)) < 0.012) & (y > 0.25) & (y < 0.4)
    inside = np.minimum(body, top)
    alpha = np.clip((1 - inside) * size * 0.1, 0, 1)
    alpha = np.maximum(alpha, stem.astype(float))
    rng = np.random.default_rng(7)
    strokes = np.cumsum(rng.normal(0, 0.02, (size, size)), axis=1)
    strokes = 0.06 * (strokes - strokes.mean(axis=1, keepdims=True))
    bright = np.stack([0.82 + 0.1 * y + strokes, 0.72 - 0.25 * y + strokes, 0.2 + 0.05 * x], -1)
    bright[stem] = (0.35, 0.22, 0.1)
    dark = bright * np.array([0.32, 0.3, 0.5])
    return (np.dstack([np.clip(bright, 0, 1), alpha]), np.dstack([np.clip(dark, 0, 1), alpha]))


def still_life(size=PX):
    """The pear painted on a background, the whole frame (no alpha), and the mask an artist
    paints for it (white = the figure, a little off its outline)."""
    bright, _ = pear(size)
    a = bright[..., 3:4]
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    wall = np.stack([0.35 + 0.2 * y, 0.42 + 0.1 * y, 0.55 + 0.0 * x], -1)
    painting = bright[..., :3] * a + wall * (1 - a)
    mask = np.roll(a[..., 0], 1, axis=1) >= 0.5                  # a hand's mask, 1 px off
    return painting, mask.astype(np.float64)


def run(folder, *args):
    """`dynpaint ARGS` in `folder` as a user runs it (the command the README's set-up
    installs, no PYTHONPATH) → what it printed, each line's timing left out (it differs from
    run to run)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    res = subprocess.run([DYNPAINT, *args], cwd=folder, capture_output=True, text=True, env=env)
    if res.returncode:
        raise RuntimeError(res.stderr)
    return re.sub(r" in \d+(\.\d+)? ?m?s\b", "", (res.stderr + res.stdout).strip())


def _grey(values):
    g = np.clip(values / max(float(values.max()), 1e-9), 0, 1)
    return np.dstack([g, g, g, np.ones_like(g)])


def over_white(rgba_straight):
    a = rgba_straight[..., 3:4]
    return np.dstack([rgba_straight[..., :3] * a + (1 - a), np.ones_like(a)])


def screenshot(page, path):
    """The page as `chromium --headless --screenshot` shoots it at its load event."""
    subprocess.run([find_chromium(), "--headless", "--no-sandbox", f"--screenshot={path}",
                    f"--window-size={PX},{PX}", f"file://{page}?embed"], capture_output=True,
                   timeout=120, cwd=os.path.dirname(page))
    return read_image(path).pixels


# Where the light comes from in the sprite's pictures (toward the light, §0)
SPRITE_LIGHTS = {"left": (-0.8, 0.1, 0.6), "above": (0.0, 0.75, 0.66), "right": (0.8, -0.1, 0.6)}


def sprite_section(work):
    """A SpriteIlluminator sprite and its map (testkit.sprite_sets) through `new` and `render`,
    and the recipe lit from three sides → (what the commands said, {picture: pixels})."""
    made = sprite_illuminator(work, 192)
    folder = os.path.basename(made.folder)
    said = run(work, "new", folder) + "\n" + run(work, "render", folder, "--out", "knight.png")
    colour = read_image(os.path.join(made.folder, "knight.png")).pixels
    normal = read_image(os.path.join(made.folder, "knight_n.png")).pixels
    tiles = {"sprite.png": over_white(colour), "sprite_n.png": over_white(normal),
             "sprite_render.png": over_white(read_image(os.path.join(work, "knight.png"))
                                             .pixels)}
    recipe = load_recipe(os.path.join(made.folder, "painting.toml"))
    images = load_images(recipe)
    for side, vector in SPRITE_LIGHTS.items():
        rgba = core_render(images, [Light("sun", vector)], recipe.params).rgba
        straight = rgba[..., :3] / np.maximum(rgba[..., 3:], 1e-6)
        lit = np.dstack([np.clip(straight, 0, 1) ** (1 / 2.2), rgba[..., 3]])
        tiles[f"sprite_{side}.png"] = over_white(lit)
    return folder, said, tiles


def main(out=DOCS):
    pictures = os.path.join(out, "img", "walkthrough")
    os.makedirs(pictures, exist_ok=True)
    with tempfile.TemporaryDirectory() as work:
        sprite_folder, said_sprite, sprite_tiles = sprite_section(work)
        folder = os.path.join(work, "pear")       # the artist's folder, as it arrives
        os.makedirs(folder)
        bright, dark = pear()
        write_png(os.path.join(folder, "pear.png"), bright)
        write_png(os.path.join(folder, "pear_dark.png"), dark)
        said_new = run(work, "new", "pear")
        recipe = open(os.path.join(folder, "painting.toml"), encoding="utf-8").read()
        said_render = run(work, "render", "pear", "--out", "render.png")
        said_page = run(work, "export-web", "pear", "--out", "pear.html")
        height = read_image(os.path.join(folder, "pear_height.exr")).pixels[..., 0]
        render = read_image(os.path.join(work, "render.png")).pixels
        shot = screenshot(os.path.join(work, "pear.html"), os.path.join(work, "shot.png"))
        # a painting with no shape image and no alpha: a painted mask, then make-shape
        still = os.path.join(work, "still")
        os.makedirs(still)
        full, mask = still_life()
        write_png(os.path.join(still, "still_bright.png"), full)
        write_png(os.path.join(still, "still_dark.png"), full * np.array([0.32, 0.3, 0.5]))
        write_png(os.path.join(work, "figure.png"), mask)        # beside the folder, not in it
        said_shape = run(work, "make-shape", "inflate", "figure.png", "--detail", "0.01",
                         "--detail-image", "still/still_bright.png", "--bevel-width", "0.01",
                         "--bevel-height", "0.01", "--smoothing", "0.002",
                         "--out", "still/still_height.exr")
        said_still = run(work, "new", "still") + "\n" + \
            run(work, "render", "still", "--out", "still_render.png")
        still_height = read_image(os.path.join(still, "still_height.exr")).pixels[..., 0]
        still_render = read_image(os.path.join(work, "still_render.png")).pixels
    tiles = {"painting.png": over_white(bright), "dark.png": over_white(dark),
             "height.png": _grey(height),
             "render.png": over_white(render), "page.png": shot,
             "still.png": np.dstack([full, np.ones(mask.shape)]),
             "figure.png": np.dstack([mask, mask, mask, np.ones(mask.shape)]),
             "still_height.png": _grey(still_height), "still_render.png": over_white(still_render),
             **sprite_tiles}
    for name, px in tiles.items():
        write_png(os.path.join(pictures, name), np.clip(px, 0, 1), bits=8)
    page = f"""# You have a sprite and its normal map

Every 2D-lighting tool and engine keeps a sprite as **one colour image and its normal map**.
Put the two in a folder as your tool wrote them and start a recipe from it: the colour image
is lit as an albedo — colour × (ambient + light) — its alpha is the figure, the map's green
is read the way its slopes fit, and shadows are on.

| the sprite (`{sprite_folder}/knight.png`) | its normal map (`knight_n.png`) | `dynpaint render` | lit from the left | from above | from the right |
|---|---|---|---|---|---|
| ![](img/walkthrough/sprite.png) | ![](img/walkthrough/sprite_n.png) | ![](img/walkthrough/sprite_render.png) | ![](img/walkthrough/sprite_left.png) | ![](img/walkthrough/sprite_above.png) | ![](img/walkthrough/sprite_right.png) |

```sh
dynpaint new {sprite_folder}
dynpaint render {sprite_folder} --out knight.png
```
```
{said_sprite}
```

What each tool writes, and what is read of it (the files of each were tried: `testkit/sprite_sets.py`
makes them, `benchmarks/artists_files.py` measures public ones):

| tool | its files | green | what Dynamic Painting reads |
|---|---|---|---|
| SpriteIlluminator | `knight.png` + `knight_n.png`; its sheets with TexturePacker | up | the pair by their names; the sprite's alpha is the figure |
| Sprite Lamp | `knight_Diffuse.png` (or `knight.png`) + `knight_Normal.png` (opaque), or `_NormalDepth` (the depth in its alpha); `_Depth`, `_AmbientOcclusion`, `_SpecGloss` | up | the normal map beside the colour image of its stem (a depth map only without one); a NormalDepth's colour alone is the map (`new` writes it to `made/`: its alpha is no figure); the other maps are said not used, each with why |
| Laigter | `knight.png` + `knight_n.png`, `_s`, `_o`, `_p` | up | the `_n` map; `_s` (specular), `_o` (occlusion), `_p` (parallax) said not used |
| Godot | `logo.png` + `logo_normal.png` (or `_n`) | its 2D lights demo's map: **down** | read down: its slopes fit a height field that way (circulation 0.41 per image width, 10.28 the other way) |
| Unity | `Knight_Albedo.png` + `Knight_Normal.png`, or a sprite's secondary texture `_n` | up | the names' words; a two-channel map (blue 0) as x, y |
| Phaser | `brick.jpg` + `brick_n.png`, `skull-n.png`; Phaser 3 multiatlases | up | the pair; JPEG colour; the atlas's frames |
| TexturePacker | `sheet.json` + `sheet.png` + `sheet_n.png` (hash, array, Phaser 3 multiatlas) | — | each frame it lists at its source size (trimmed borders put back, rotated frames turned back), written to `made/` as numbered frames: a painting that moves |
| any, full frame | `wall.png` + `wall_n.png` saved as RGBA, the alpha 255 everywhere | — | an alpha that covers every pixel cuts nothing out: its shadows fall along each ray (`shadows.relief = "along_ray"`, said) |
| Blender bake | `head.png` + `head_normal.png`: (0, 0, 0, 0) outside, the rim blended with black | up | uncovered pixels flat, the rim divided by its alpha: no wall of shadow round the figure |
| any, animated | `01.png` + `01_n.png` … `08_n.png` | — | a painting that moves (`##.png`, `##_n.png`) |

A map read the other way from what your tool meant: set `shape.flip_green` in the recipe (a
`note:` says when the map fits the other way better). A flat look (the light changing
nothing): `diffuse.ambient = 1`. Fine relief that looks soft (lettering, bevels a pixel or two wide):
with shadows on, the light is the cos-θ term, which smooths relief finer than its offset
(`shadows.offset`, {OFFSET:g} image widths: {OFFSET * 640:.1f} px on a 640-px card; the paper's subsurface look):
lower it for crisper relief ([artists-files.md](artists-files.md) measures half of it on every set).
Two hand-painted images, dark and lit (the paper's way), are
mixed by the light instead ([the next section](#your-own-painting-from-a-folder-of-files-to-a-web-page-command-line)).

# Your own painting, from a folder of files to a web page (command line)

Made by `docs/make_walkthrough.py`, which runs these commands as you would type them, from
the folder that holds your painting's folder (the output shown is theirs, timings left out).
Set-up: the README's (`scripts/bootstrap.sh`), then `source /path/to/the/repo/.venv/bin/activate`
once per shell so that `dynpaint` works from any folder. In Blender the same takes two clicks:
*Add › Dynamic Painting › From Images or Recipe…* ([addon.md](addon.md)).

| 1. your painting (`pear/pear.png`, the figure in its alpha) | its shaded copy (`pear/pear_dark.png`, optional) | 2. the shape `new` made | 3. rendered | 4. the web page |
|---|---|---|---|---|
| ![](img/walkthrough/painting.png) | ![](img/walkthrough/dark.png) | ![](img/walkthrough/height.png) | ![](img/walkthrough/render.png) | ![](img/walkthrough/page.png) |

**1. The folder.** Put the painting's images in a folder: one PNG with the figure in its
alpha is enough; a shaded copy (a name with `dark` in it) gives the shadow side its own
colours, and a normal or height map (`…normal…`, `…height…`) its shape. Files are matched to
their channels by the words in their names, as *Add › From Images* matches them (`…lit…`,
`…env…`, `…background…`, `…mask…`, … — [addon.md](addon.md)).

**2. The recipe.** `dynpaint new` reads the folder as every command will read it and writes
a commented starter recipe, `painting.toml`, saying what it guessed and why. Without a shape
image it inflates one from the painting's silhouette
([shape-from-painting.md](shape-from-painting.md) has the other ways: lighting profiles, a
red/green photo, a normal map):

```sh
dynpaint new pear
```
```
{said_new}
```

It wrote `pear/painting.toml` (every key: `dynpaint params`; [parameters.md](parameters.md)):

```toml
{recipe.strip()}
```

**3. Render it.** Every command takes the folder (its `painting.toml`) or the recipe; the
numpy core renders by default, `--engine cycles` or `eevee` the add-on's material in
background Blender, the same pixels:

```sh
dynpaint render pear --out render.png
```
```
{said_render}
```

Each command says what it guessed about your files in a `note:` line (a mask painted in one
colour channel, a two-channel normal map, glass over a black background, a setting that does
nothing as the recipe stands, a file cut short …): read them, they name the setting that
changes the guess.

**4. Share it.** One self-contained page, images inside; drag the light, the wheel lifts it
([web.md](web.md)):

```sh
dynpaint export-web pear --out pear.html
```
```
{said_page}
```

A picture of the page for a README or a post — the page draws its first frame before its load
event, so a headless screenshot shows the painting (picture 4 was taken so; as root, Chromium
also needs `--no-sandbox`):

```sh
chromium --headless --screenshot=pear_page.png --window-size={PX},{PX} "file://$PWD/pear.html?embed"
```

**5. A video** of the light going round: `dynpaint turntable pear --out pear.mp4` (48 frames;
[main-job.md](main-job.md) times it on the portrait).

## A painting with no shape image (and no alpha)

A painting that fills its frame has no silhouette to inflate: `new` would take every light
patch of paint for the figure. Paint the figure's mask instead (white on black, any editor;
or in one colour channel: `--mask-channel`), then make the shape from the mask, with the
painting's own light and dark embossed as detail, a bevel at its rim and a little smoothing:

| the painting (`still/still_bright.png`, and a shaded copy `still_dark.png`) | the mask you paint (`figure.png`) | the shape made | rendered |
|---|---|---|---|
| ![](img/walkthrough/still.png) | ![](img/walkthrough/figure.png) | ![](img/walkthrough/still_height.png) | ![](img/walkthrough/still_render.png) |

Keep the mask outside the painting's folder (in it, a file named `…mask…` would be read as
the painting's transparency mask):

```sh
dynpaint make-shape inflate figure.png --detail 0.01 --detail-image still/still_bright.png \\
    --bevel-width 0.01 --bevel-height 0.01 --smoothing 0.002 --out still/still_height.exr
dynpaint new still
dynpaint render still --out still_render.png
```
```
{said_shape}
{said_still}
```

The folder now holds the painting and its height map (`…height…`), which every command reads
([shape-from-painting.md](shape-from-painting.md): the effects, each with a picture). Measured
against 3D ([no-shape-numbers.md](no-shape-numbers.md)): a mask a hand paints, inflated, gives
a sphere's cast shadows at about 0.9 of a true height map's IoU, a torus's and a head's about
half; the mask is what matters: snapped onto the painting's outline (`--snap 0.01`) and with
round cross-sections as wide as the figure (`--profile tube`), a sphere's shadows reach 0.99
of the true map's and a torus's 0.91; a head's stay about half (0.68 with `--profile flat`,
and no profile, height or bevel takes them past 0.71: a face's depth is in its features, so
paint its height). The embossed detail is a finish (it moves the IoU by
0.02 or less). A figure standing on the ground needs its rim lifted: a bevel one pixel wide as
tall as the rim (`--bevel-width 0.004 --bevel-height 0.15 --bevel-profile linear` at 256²) took a
resting sphere from 0.4 to 0.9 of the true map's IoU.
"""
    with open(os.path.join(out, "your-painting.md"), "w", encoding="utf-8") as fh:
        fh.write(page)
    print(f"wrote {os.path.join(out, 'your-painting.md')} and {pictures}/*.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else DOCS)
