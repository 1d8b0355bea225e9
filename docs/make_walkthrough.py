"""Generate docs/your-painting.md: your own painting from files to a web page on the command
line, step by step (issue 27) — the commands are run here as a user types them, and the
pictures show what each one wrote.

    .venv/bin/python docs/make_walkthrough.py        # ≈ 15 s (needs Chromium for the page)
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

from dynpaint_addon.imageio import read_image, write_png        # noqa: E402
from testkit.chromium import find_chromium           # noqa: E402

PX = 256
RECIPE = """name = "Pear"
[images]
shape = "pear_height.exr"     # made by make-shape: heights in image widths
bright = "pear.png"           # the painting (its alpha is the figure)
dark = "pear_dark.png"        # optional: a shaded copy (without it, bright serves both)
[shape]
kind = "height"
height_scale = 1.0            # make-shape's heights are already in image widths
[shadows]
enabled = true
[[lights]]
type = "sun"
direction = [-0.6, 0.45, 0.5]
color = [1.0, 0.95, 0.85]
name = "Key"
"""


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


def run(folder, *args):
    """`python -m dynpaint_addon ARGS` in `folder` as a user runs it → what it printed, with
    each line's timing left out (it differs from run to run)."""
    res = subprocess.run([sys.executable, "-m", "dynpaint_addon", *args], cwd=folder,
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": REPO})
    if res.returncode:
        raise RuntimeError(res.stderr)
    return re.sub(r" in \d+(\.\d+)? ?m?s\b", "", (res.stderr + res.stdout).strip())


def over_white(rgba_straight):
    a = rgba_straight[..., 3:4]
    return np.dstack([rgba_straight[..., :3] * a + (1 - a), np.ones_like(a)])


def screenshot(page, path):
    """The page as `chromium --headless --screenshot` shoots it at its load event."""
    subprocess.run([find_chromium(), "--headless", "--no-sandbox", f"--screenshot={path}",
                    f"--window-size={PX},{PX}", f"file://{page}?embed"], capture_output=True,
                   timeout=120, cwd=os.path.dirname(page))
    return read_image(path).pixels


def main(out=DOCS):
    pictures = os.path.join(out, "img", "walkthrough")
    os.makedirs(pictures, exist_ok=True)
    with tempfile.TemporaryDirectory() as folder:
        bright, dark = pear()
        write_png(os.path.join(folder, "pear.png"), bright)
        write_png(os.path.join(folder, "pear_dark.png"), dark)
        said_shape = run(folder, "make-shape", "inflate", "pear.png", "--out", "pear_height.exr")
        with open(os.path.join(folder, "painting.toml"), "w", encoding="utf-8") as fh:
            fh.write(RECIPE)
        said_render = run(folder, "render", "painting.toml", "--out", "render.png")
        said_page = run(folder, "export-web", "painting.toml", "--out", "pear.html")
        height = read_image(os.path.join(folder, "pear_height.exr")).pixels[..., 0]
        render = read_image(os.path.join(folder, "render.png")).pixels
        shot = screenshot(os.path.join(folder, "pear.html"), os.path.join(folder, "shot.png"))
    grey = np.clip(height / max(float(height.max()), 1e-9), 0, 1)
    tiles = {"painting.png": over_white(bright), "dark.png": over_white(dark),
             "height.png": np.dstack([grey, grey, grey, np.ones_like(grey)]),
             "render.png": over_white(render), "page.png": shot}
    for name, px in tiles.items():
        write_png(os.path.join(pictures, name), np.clip(px, 0, 1), bits=8)
    page = f"""# Your own painting, from files to a web page (command line)

Made by `docs/make_walkthrough.py`, which runs these commands as you would type them (the
output shown is theirs, timings left out). In Blender the same takes two clicks: *Add ›
Dynamic Painting › From Images or Recipe…* ([addon.md](addon.md)).

| 1. your painting (`pear.png`, the figure in its alpha) | its shaded copy (`pear_dark.png`, optional) | 2. the shape made from it | 3. rendered | 4. the web page |
|---|---|---|---|---|
| ![](img/walkthrough/painting.png) | ![](img/walkthrough/dark.png) | ![](img/walkthrough/height.png) | ![](img/walkthrough/render.png) | ![](img/walkthrough/page.png) |

**1. The painting.** One PNG with the figure in its alpha is enough; a second, shaded copy
(the *dark* image) gives the shadow side its own colours — without it the bright image serves
both. Any size; colour images are sRGB.

**2. The shape.** No normal or height map? Inflate the silhouette
([shape-from-painting.md](shape-from-painting.md) has the other ways: from lighting profiles,
a red/green photo, a normal map):

```sh
python -m dynpaint_addon make-shape inflate pear.png --out pear_height.exr
```
```
{said_shape}
```

**3. The recipe.** A small text file, `painting.toml`, names the images and says how to read
them (every key: `python -m dynpaint_addon params`; [parameters.md](parameters.md)):

```toml
{RECIPE.strip()}
```

Render it (the numpy core; `--engine cycles` or `eevee` renders the add-on's material in
background Blender, the same pixels):

```sh
python -m dynpaint_addon render painting.toml --out render.png
```
```
{said_render}
```

Each command says what it guessed about your files in a `note:` line (a mask painted in one
colour channel, a two-channel normal map, a shape image without the alpha a glass painting
needs …): read them, they name the setting that changes the guess.

**4. Share it.** One self-contained page, images inside; drag the light, the wheel lifts it
([web.md](web.md)):

```sh
python -m dynpaint_addon export-web painting.toml --out pear.html
```
```
{said_page}
```

A picture of the page for a README or a post — the page draws its first frame before its load
event, so a headless screenshot shows the painting (picture 4 was taken so):

```sh
chromium --headless --screenshot=pear_page.png --window-size={PX},{PX} "file://$PWD/pear.html?embed"
```

A video of the light going round: `python -m dynpaint_addon turntable painting.toml --out
pear.mp4` (48 frames; [main-job.md](main-job.md) times it on the portrait).
"""
    with open(os.path.join(out, "your-painting.md"), "w", encoding="utf-8") as fh:
        fh.write(page)
    print(f"wrote {os.path.join(out, 'your-painting.md')} and {pictures}/*.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else DOCS)
