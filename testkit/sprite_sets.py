"""Sets of sprite files in the conventions of the 2D-lighting tools and engines (issue 59), made
by numpy (and Blender's JPEG writer) from figures whose true normals are known, so that a
reading of them can be judged (`judge`): what `dynpaint new` + `render` are tried on in
tests/blender/test_sprite_sets.py and benchmarks/artists_files.py.

Each writer makes one folder as that tool leaves it and returns a `SpriteSet`: its folder,
the tool, and per frame the true unit normals (y-up, OpenGL convention) and the figure's
coverage. Their conventions (docs/your-painting.md has the table):

- `sprite_illuminator`: `knight.png` (RGBA) + `knight_n.png`, green up, the sprite's alpha;
- `sprite_lamp`: `knight_Diffuse.png` (its diffuse lighting profile's name) +
  `knight_Normal.png` (opaque, flat outside) + `knight_Depth.png` +
  `knight_AmbientOcclusion.png`, the maps Sprite Lamp saves;
- `sprite_lamp_wall`: `wall_Diffuse.png` + `wall_NormalDepth.png`, the depth in the map's alpha;
- `laigter`: `knight.png` + `knight_n.png` beside its `_s`, `_o` and `_p` maps;
- `godot_demo`: `logo.png` + `logo_normal.png`, **green down** (as Godot's 2D lights demo's
  map is), no alpha in the map;
- `unity`: `Knight_Albedo.png` + `Knight_Normal.png`, two-channel (blue 0);
- `blender_bake`: `head.png` + `head_normal.png` baked onto a transparent image: (0,0,0,0)
  outside and the rim blended with black;
- `jpeg_wall`: `wall.jpg` + `wall_normal.jpg`, a full-frame texture, both JPEG;
- `rgba_wall`: `tiles.png` + `tiles_n.png`, a full-frame map saved as RGBA, alpha 255;
- `numbered_walk`: `01.png` + `01_n.png` … `08_n.png`, a figure that moves;
- `scene_layer`: `foreground_01.png` + `foreground_01_n.png`, a scene's front layer.
"""
import os
from dataclasses import dataclass, field

import numpy as np

from dynpaint_addon.core.colour import srgb_to_linear
from dynpaint_addon.inputs.imageio import write_png
from testkit.artist_folders import write_jpeg

SUPERSAMPLE = 4


@dataclass
class SpriteSet:
    folder: str
    tool: str
    normals: list = field(default_factory=list)     # per frame (H, W, 3), y-up, unit
    coverage: list = field(default_factory=list)    # per frame (H, W) 0..1, None: full frame
    green: str = "up"                               # the map's convention: "up" or "down"

    @property
    def frames(self):
        return len(self.normals)


def figure(size, parts, shift=(0.0, 0.0)):
    """A figure of rounded parts (cx, cy, rx, ry, height: ellipsoids, image widths) → (unit
    normals (H, W, 3), coverage (H, W)), y-up; antialiased coverage by supersampling."""
    fine = size * SUPERSAMPLE
    y, x = (np.mgrid[0:fine, 0:fine] + 0.5) / fine
    z = np.zeros((fine, fine))
    for cx, cy, rx, ry, h in parts:
        r2 = ((x - cx - shift[0]) / rx) ** 2 + ((y - cy - shift[1]) / ry) ** 2
        z = np.maximum(z, h * np.sqrt(np.clip(1 - r2, 0, None)))
    inside = z > 0
    coverage = inside.reshape(size, SUPERSAMPLE, size, SUPERSAMPLE).mean((1, 3))
    zc = z.reshape(size, SUPERSAMPLE, size, SUPERSAMPLE).mean((1, 3))
    gy, gx = np.gradient(zc * size, axis=(0, 1))          # heights in pixels: slopes
    n = np.dstack([-gx, -gy, np.ones_like(zc)])
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    n[coverage < 1e-6] = (0.0, 0.0, 1.0)
    return n, coverage


KNIGHT = [(0.5, 0.68, 0.13, 0.13, 0.10), (0.5, 0.38, 0.2, 0.24, 0.14),
          (0.3, 0.4, 0.06, 0.16, 0.05), (0.7, 0.4, 0.06, 0.16, 0.05)]
HEAD = [(0.5, 0.5, 0.32, 0.38, 0.3), (0.5, 0.44, 0.06, 0.1, 0.36)]


def colours(size, coverage, seed=0):
    """A painted colour image (display values, y-up) over the figure: hues that change across
    it and soft strokes; RGBA with the coverage as alpha (straight)."""
    rng = np.random.default_rng(seed)
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    base = rng.uniform(0.45, 0.85, 3)
    strokes = 0.08 * np.sin(31 * x + 17 * y + rng.uniform(0, 6)) * np.cos(23 * y - 9 * x)
    rgb = np.clip(np.dstack([base[0] + 0.2 * (x - 0.5) + strokes, base[1] + 0.2 * (y - 0.5),
                             base[2] - 0.15 * x + strokes]), 0.05, 0.95)
    return np.dstack([rgb, coverage])


def encode(n, green_down=False, two_channel=False):
    """Unit normals → a map's RGB (0..1): (N + 1)/2, green negated for DirectX style, blue 0
    for a two-channel map."""
    c = (n * ([1, -1, 1] if green_down else [1, 1, 1]) + 1) / 2
    if two_channel:
        c[..., 2] = 0
    return c


def _folder(root, name):
    path = os.path.join(root, name)
    os.makedirs(path, exist_ok=True)
    return path


def _write(path, px):
    write_png(path, px, 8)


def sprite_illuminator(root, size=128):
    d = _folder(root, "sprite_illuminator")
    n, cov = figure(size, KNIGHT)
    _write(os.path.join(d, "knight.png"), colours(size, cov, 1))
    _write(os.path.join(d, "knight_n.png"), np.dstack([encode(n), cov]))
    return SpriteSet(d, "SpriteIlluminator", [n], [cov])


def sprite_lamp(root, size=160):
    d = _folder(root, "sprite_lamp")
    n, cov = figure(size, KNIGHT, (0.04, -0.02))
    _write(os.path.join(d, "knight_Diffuse.png"), colours(size, cov, 2))
    _write(os.path.join(d, "knight_Normal.png"), encode(n))          # opaque: flat outside
    _write(os.path.join(d, "knight_Depth.png"), np.clip(1 - n[..., 2], 0, 1))
    _write(os.path.join(d, "knight_AmbientOcclusion.png"), 0.6 + 0.4 * n[..., 2])
    return SpriteSet(d, "Sprite Lamp", [n], [cov])


def laigter(root, size=112):
    d = _folder(root, "laigter")
    n, cov = figure(size, HEAD)
    _write(os.path.join(d, "knight.png"), colours(size, cov, 3))
    _write(os.path.join(d, "knight_n.png"), np.dstack([encode(n), cov]))
    for suffix, value in (("s", 0.4), ("o", 0.8), ("p", 0.5)):      # specular, occlusion, parallax
        _write(os.path.join(d, f"knight_{suffix}.png"), np.dstack([np.full((size, size), value),
                                                                   cov]))
    return SpriteSet(d, "Laigter", [n], [cov])


def godot_demo(root, size=128):
    d = _folder(root, "godot_demo")
    n, cov = figure(size, [(0.5, 0.5, 0.38, 0.34, 0.2), (0.36, 0.58, 0.08, 0.08, 0.26),
                           (0.64, 0.58, 0.08, 0.08, 0.26)])
    _write(os.path.join(d, "logo.png"), colours(size, cov, 4))
    _write(os.path.join(d, "logo_normal.png"), encode(n, green_down=True))
    return SpriteSet(d, "Godot (green down)", [n], [cov], "down")


def unity(root, size=144):
    d = _folder(root, "unity")
    n, cov = figure(size, KNIGHT, (-0.03, 0.02))
    _write(os.path.join(d, "Knight_Albedo.png"), colours(size, cov, 5))
    _write(os.path.join(d, "Knight_Normal.png"), encode(n, two_channel=True))
    return SpriteSet(d, "Unity (two-channel)", [n], [cov])


def blender_bake(root, size=160):
    d = _folder(root, "blender_bake")
    n, cov = figure(size, HEAD)
    _write(os.path.join(d, "head.png"), colours(size, cov, 6))
    baked = encode(n) * cov[..., None]                     # blended with the black background
    _write(os.path.join(d, "head_normal.png"), np.dstack([baked, cov]))
    return SpriteSet(d, "Blender bake (premultiplied rim)", [n], [cov])


def jpeg_wall(root, size=192):
    """A full-frame texture: bricks of rounded relief, colour and map both JPEG."""
    d = _folder(root, "jpeg_wall")
    n, rgb, _ = _bricks(size, 6)
    write_jpeg(os.path.join(d, "wall.jpg"), rgb.astype(np.float32), 88)
    write_jpeg(os.path.join(d, "wall_normal.jpg"), encode(n).astype(np.float32), 88)
    return SpriteSet(d, "JPEG texture (full frame)", [n], [None])


def rgba_wall(root, size=160):
    """A full-frame texture whose map is saved as RGBA with its alpha 255 everywhere, as paint
    programs export a layer: the alpha cuts nothing out."""
    d = _folder(root, "rgba_wall")
    n, rgb, _ = _bricks(size, 4)
    _write(os.path.join(d, "tiles.png"), rgb)
    _write(os.path.join(d, "tiles_n.png"), np.dstack([encode(n), np.ones((size, size))]))
    return SpriteSet(d, "paint program (full-frame map saved as RGBA)", [n], [None])


def sprite_lamp_wall(root, size=160):
    """A full-frame texture as Sprite Lamp saves it for its shaders: `wall_Diffuse.png` and
    `wall_NormalDepth.png`, the normal map whose alpha is the depth (low between the bricks:
    read as a figure's alpha, it would cut the mortar out)."""
    d = _folder(root, "sprite_lamp_wall")
    n, rgb, z = _bricks(size, 5)
    _write(os.path.join(d, "wall_Diffuse.png"), rgb)
    _write(os.path.join(d, "wall_NormalDepth.png"), np.dstack([encode(n), z / z.max()]))
    return SpriteSet(d, "Sprite Lamp (NormalDepth: the depth in the map's alpha)", [n], [None])


def _bricks(size, rows):
    """Rows of bricks of rounded relief → (true normals, colour RGB, heights)."""
    fine = size * SUPERSAMPLE
    y, x = (np.mgrid[0:fine, 0:fine] + 0.5) / fine
    row = np.floor(y * rows)
    u = (x * 3 + 0.5 * (row % 2)) % 1
    v = (y * rows) % 1
    z = 0.02 * np.sqrt(np.clip(1 - ((u - 0.5) / 0.46) ** 8 - ((v - 0.5) / 0.4) ** 8, 0, None))
    zc = z.reshape(size, SUPERSAMPLE, size, SUPERSAMPLE).mean((1, 3))
    gy, gx = np.gradient(zc * size, axis=(0, 1))
    n = np.dstack([-gx, -gy, np.ones_like(zc)])
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n, colours(size, np.ones((size, size)), 7)[..., :3], zc


def numbered_walk(root, size=96, frames=8):
    d = _folder(root, "numbered_walk")
    found = SpriteSet(d, "numbered frames")
    for f in range(frames):
        step = 0.04 * np.sin(2 * np.pi * f / frames)
        n, cov = figure(size, [(0.5 + step, 0.68, 0.13, 0.13, 0.1),
                               (0.5, 0.4, 0.18, 0.24, 0.14),
                               (0.42 - step, 0.14, 0.06, 0.12, 0.05),
                               (0.58 + step, 0.14, 0.06, 0.12, 0.05)])
        _write(os.path.join(d, f"{f + 1:02d}.png"), colours(size, cov, 8))
        _write(os.path.join(d, f"{f + 1:02d}_n.png"), np.dstack([encode(n), cov]))
        found.normals.append(n)
        found.coverage.append(cov)
    return found


def scene_layer(root, size=128):
    d = _folder(root, "scene_layer")
    n, cov = figure(size, [(0.3, 0.3, 0.25, 0.2, 0.1), (0.7, 0.35, 0.2, 0.25, 0.12)])
    _write(os.path.join(d, "foreground_01.png"), colours(size, cov, 9))
    _write(os.path.join(d, "foreground_01_n.png"), np.dstack([encode(n), cov]))
    return SpriteSet(d, "a scene's layer (name says 'foreground')", [n], [cov])


WRITERS = (sprite_illuminator, sprite_lamp, sprite_lamp_wall, laigter, godot_demo, unity,
           blender_bake, jpeg_wall, rgba_wall, numbered_walk, scene_layer)


def write_all(root):
    """Every set under `root` → [SpriteSet]."""
    return [writer(root) for writer in WRITERS]


# Below this spread of the true N·L over the figure (a flat card: a background with embossed
# lettering) there is no light to follow, and r measures the colour's noise: not judged.
FLAT_SPREAD = 0.03


@dataclass
class Verdict:
    pearson: float          # render ÷ colour against the true N·L, over the lit figure (None:
    #                         a flat figure, nothing to follow)
    iou: float              # the render's alpha against the colour's (the figure kept)
    shadowed: float         # share of the pixels facing the light (N·L ≥ 0.6) in shadow

    def passes(self):
        return (self.pearson is None or self.pearson >= 0.5) and self.iou >= 0.98 and \
            self.shadowed <= 0.15


def light_received(render_rgba, colour_rgba, ambient=0.2):
    """The light each pixel of a render (premultiplied linear RGBA, y-up) of a colour image
    (display values) got: W = (render/colour − a)/(1 − a) (§1) → (H, W), NaN where the
    colour is too dark to tell (under 0.03 linear)."""
    alpha = render_rgba[..., 3]
    colour = srgb_to_linear(np.asarray(colour_rgba[..., :3], np.float64))
    straight = render_rgba[..., :3] / np.maximum(alpha, 1e-6)[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = (straight / colour).mean(-1)
    return np.where(colour.min(-1) > 0.03, (ratio - ambient) / (1 - ambient), np.nan)


def judge(render_rgba, colour_rgba, normals, coverage, light, ambient=0.2):
    """How a render (premultiplied linear RGBA, y-up) of a colour image (display values,
    straight alpha) follows the true normals under a sun `light` (unit vector toward it): the
    light each pixel got (light_received) against the true N·L, its shadow where it falls
    under half the true N·L."""
    alpha = render_rgba[..., 3]
    figure = np.ones(alpha.shape, bool) if coverage is None else coverage > 0.99
    received = light_received(render_rgba, colour_rgba, ambient)
    ok = figure & np.isfinite(received)
    w = received[ok]
    ndl = np.asarray(normals)[ok] @ np.asarray(light, np.float64)
    pearson = None if ndl.std() < FLAT_SPREAD else \
        float(np.corrcoef(w, ndl)[0, 1]) if w.std() > 0 else 0.0
    if coverage is None:
        iou = 1.0 if np.all(alpha > 0.5) else float(np.mean(alpha > 0.5))
    else:
        want, got = colour_rgba[..., 3] > 0.5, alpha > 0.5
        iou = float(np.sum(want & got) / max(np.sum(want | got), 1))
    facing = ndl >= 0.6
    shadowed = float(np.mean(w[facing] < 0.5 * ndl[facing])) if facing.any() else 0.0
    return Verdict(pearson, iou, shadowed)


def pack_atlas(walk, root, form="hash"):
    """The frames of a `numbered_walk` set packed as TexturePacker packs them: each trimmed to
    its figure's box, every other one turned 90° clockwise, in one row of a sheet and its
    normal-map sheet (`walk.png`, `walk_n.png`), listed in `walk.json` in `form` ('hash',
    'array' or Phaser 3's 'multiatlas') → (folder, [(colour RGBA, map RGBA)] per frame as cut
    back to its source size, top row first)."""
    import json
    from dynpaint_addon.inputs.imageio import read_image
    d = _folder(root, f"atlas_{form}")
    cells, entries, x = [], [], 0
    for f in range(walk.frames):
        name = f"{f + 1:02d}"
        colour = read_image(os.path.join(walk.folder, f"{name}.png")).pixels[::-1]
        normal = read_image(os.path.join(walk.folder, f"{name}_n.png")).pixels[::-1]
        ys, xs = np.nonzero(colour[..., 3] > 0)
        y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
        rotated = f % 2 == 1
        cut = [img[y0:y1, x0:x1] for img in (colour, normal)]
        packed = [np.rot90(c, -1) if rotated else c for c in cut]
        cells.append((x, packed))
        h, w = y1 - y0, x1 - x0
        entries.append((f"walk_{name}.png", {
            "frame": {"x": x, "y": 0, "w": int(w), "h": int(h)}, "rotated": rotated,
            "trimmed": True, "spriteSourceSize": {"x": int(x0), "y": int(y0), "w": int(w),
                                                  "h": int(h)},
            "sourceSize": {"w": colour.shape[1], "h": colour.shape[0]}}))
        x += packed[0].shape[1] + 2
    height = max(p[0].shape[0] for _, p in cells)
    sheets = [np.zeros((height, x, 4)) for _ in range(2)]
    for x0, packed in cells:
        for sheet, img in zip(sheets, packed):
            sheet[:img.shape[0], x0:x0 + img.shape[1]] = img
    _write(os.path.join(d, "walk.png"), sheets[0][::-1])
    _write(os.path.join(d, "walk_n.png"), sheets[1][::-1])
    meta = {"app": "https://www.codeandweb.com/texturepacker", "image": "walk.png",
            "size": {"w": x, "h": height}, "scale": "1"}
    if form == "hash":
        data = {"frames": dict(entries), "meta": meta}
    elif form == "array":
        data = {"frames": [{"filename": n, **e} for n, e in entries], "meta": meta}
    else:
        data = {"textures": [{"image": "walk.png", "normalMap": "walk_n.png",
                              "size": meta["size"], "scale": 1,
                              "frames": [{"filename": n, **e} for n, e in entries]}],
                "meta": {"app": meta["app"]}}
    with open(os.path.join(d, "walk.json"), "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1)
    return d
