"""Generate docs/shape-from-painting.md: every make-shape method shown on the samples, before
and after, rendered by the numpy core (issue 16). Numbers on the page are measured here; the
3D ground truth is in docs/shape-numbers.md (benchmarks/shape_from_painting.py).

    .venv/bin/python docs/make_shape_pictures.py        # ≈ 20 s
"""
import copy
import os
import sys

import numpy as np

DOCS = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(DOCS))
sys.path.insert(0, DOCS)

from make_docs import sample_images, side_by_side              # noqa: E402

from dynpaint_addon import params                               # noqa: E402
from dynpaint_addon.core.colour import linear_to_srgb           # noqa: E402
from dynpaint_addon.core.inflate import inflate                 # noqa: E402
from dynpaint_addon.core.input_rules import ImageData  # noqa: E402
from dynpaint_addon.core.integrate import integrate             # noqa: E402
from dynpaint_addon.core.lights import Light                    # noqa: E402
from dynpaint_addon.core.occlusion import ambient_occlusion     # noqa: E402
from dynpaint_addon.core.photometric import (normals_from_profiles,  # noqa: E402
                                             normals_from_rg_photo, profile_directions)
from dynpaint_addon.core.pipeline import render, shape_normals  # noqa: E402
from dynpaint_addon.core.snap import snap_to_edges              # noqa: E402
from dynpaint_addon.inputs.imageio import write_png                    # noqa: E402
from dynpaint_addon.shapes.maker import (encode_normals, linear_luminance,  # noqa: E402
                                          normals_of_height)
from dynpaint_addon.shapes.painted import NEUTRAL, figure_relief, painted_height  # noqa: E402
from dynpaint_addon.shapes.relief import with_effects  # noqa: E402

PX = 192
SNAP_PX = 4          # the --snap picture's reach, pixels (about 0.02 image widths at PX)
LOW_SUN = Light("sun", (-0.8, 0.35, 0.42), (1.0, 0.95, 0.85), 1.0, "Low sun")


def _grey(values, top=None):
    """A grey picture (RGBA, opaque) of values scaled to their top."""
    top = float(np.max(values)) if top is None else top
    g = np.clip(np.asarray(values, np.float64) / max(top, 1e-12), 0, 1)
    return np.dstack([g, g, g, np.ones_like(g)])


def _colour(rgb):
    """A normal map or other data image as it is stored (no colour management)."""
    return np.dstack([np.clip(rgb, 0, 1), np.ones(rgb.shape[:2])])


def _lit(rgba):
    """A core render (linear, premultiplied) → display values, so _save shows it as seen."""
    return np.dstack([linear_to_srgb(np.clip(rgba[..., :3], 0, 1)), rgba[..., 3:4]])


def _save(out, name, tiles):
    write_png(os.path.join(out, "img", "shape", name), side_by_side(tiles))
    return f"![{name}](img/shape/{name})"


def _black_and_white(shape, size):
    """A painting whose render is its light weight W: black dark image, white bright one."""
    h, w = size
    return {"shape": shape, "dark": ImageData(np.zeros((h, w, 3), np.float32), 32),
            "bright": ImageData(np.ones((h, w, 3), np.float32), 32)}


def _angle(a, b):
    return np.degrees(np.arccos(np.clip(np.sum(a * b, -1), -1, 1)))


def portrait_relief():
    """The portrait's true heights (image widths) and their §2 normals."""
    recipe, images = sample_images("portrait", PX)
    n, z_px, _ = shape_normals(images["shape"], recipe.params, np.float64)
    return recipe, images, n, z_px / PX


def inflated_glass():
    """Inflate: the glass bottle rendered with its artist's normal map, then with a height map
    made from its silhouette alone."""
    recipe, images = sample_images("glass", PX)
    mask = images["shape"].alpha() >= 0.5
    height = inflate(mask).height
    made = {**images, "shape": ImageData(np.dstack([height, images["shape"].alpha()])
                                         .astype(np.float32), 32)}
    p = copy.deepcopy(recipe.params)
    p.shape.kind, p.shape.height_scale = "height", 1.0
    tiles = [_lit(render(images, recipe.lights, recipe.params).rgba), _grey(height),
             _lit(render(made, recipe.lights, p).rgba)]
    return tiles, float(height.max())


def effects_glass():
    """Inflate's effects: the bottle's silhouette inflated flat with a bevel and smoothing,
    then with a woven structure, each rendered (shapes.relief.with_effects)."""
    recipe, images = sample_images("glass", PX)
    alpha = images["shape"].alpha()
    mask = alpha >= 0.5
    base = inflate(mask, "flat", 0.5).height
    y, x = np.mgrid[0:32, 0:32] + 0.5
    weave = 0.5 + 0.25 * (np.sin(2 * np.pi * x / 16) + np.sin(2 * np.pi * y / 16))   # a tile
    p = copy.deepcopy(recipe.params)
    p.shape.kind, p.shape.height_scale = "height", 1.0
    tiles = []
    for extra in ({"bevel_width": 0.03, "bevel_height": 0.02, "smoothing": 0.003},
                  {"structure_tile": weave, "structure_scale": 0.05,
                   "structure_strength": 0.003}):
        height = with_effects(base, mask, **extra)
        made = {**images, "shape": ImageData(np.dstack([height, alpha]).astype(np.float32), 32)}
        tiles += [_grey(height), _lit(render(made, [LOW_SUN], p).rgba)]
    return tiles


SLIP = (3, -2)       # pixels a hand's mask is off the figure in the --snap picture: x, y


def _outlined(rgba, mask, colour):
    """The picture with the mask's edge pixels (inside, beside one outside) in `colour`."""
    inner = mask & np.roll(mask, 1, 0) & np.roll(mask, -1, 0) & np.roll(mask, 1, 1) & \
        np.roll(mask, -1, 1)
    out = rgba.copy()
    out[mask & ~inner] = (*colour, 1.0)
    return out


def _slipped(sample):
    """A sample's figure (its alpha) and the mask a hand paints of it, SLIP off."""
    recipe, images = sample_images(sample, PX)
    figure = next(images[c].alpha() for c in ("shape", "bright")
                  if images[c].alpha() is not None) >= 0.5
    return recipe, images, figure, np.roll(np.roll(figure, SLIP[0], 1), SLIP[1], 0)


def snapped_blink():
    """--snap: the blink sample's figure as a hand paints it, over the painting (red), the
    same snapped onto the painting's outline (green, core/snap.py), and the snapped mask
    inflated (tube); → (tiles, {sample: (pixels wrong before, after)}) of blink and the
    glass bottle (whose outline hardly shows in its painting)."""
    wrong = {}
    for sample in ("blink", "glass"):
        recipe, images, figure, hand = _slipped(sample)
        snapped = snap_to_edges(hand, linear_luminance(images["bright"]), SNAP_PX)
        wrong[sample] = (int((hand != figure).sum()), int((snapped != figure).sum()))
        if sample == "blink":
            shown = _lit(render(images, recipe.lights, recipe.params).rgba)
            tiles = [_outlined(shown, hand, (0.9, 0.1, 0.1)),
                     _outlined(shown, snapped, (0.1, 0.7, 0.2)),
                     _grey(inflate(snapped, "tube").height)]
    return tiles, wrong


def painted_in_layers():
    """Paint Shape (shapes/painted.py): a figure mask painted as an artist would (a body and a
    head), a height layer with two strokes (one raising, one lowering), the shape they make
    (the mask inflated with a bevel, the layer added) and its render under a low sun."""
    y, x = (np.mgrid[0:PX, 0:PX] + 0.5) / PX
    mask = (((x - 0.5) / 0.3) ** 2 + ((y - 0.36) / 0.24) ** 2 < 1) | \
        (np.hypot(x - 0.5, y - 0.74) < 0.14)
    layer = np.full((PX, PX), NEUTRAL)
    layer += 0.35 * np.exp(-((y - 0.3 - 0.3 * (x - 0.5)) / 0.02) ** 2) * (np.abs(x - 0.5) < 0.2)
    layer -= 0.35 * np.exp(-(np.hypot(x - 0.56, y - 0.76) / 0.03) ** 2)
    height = painted_height(None, figure_relief(mask, height=0.6, bevel_width=0.02,
                                                bevel_height=0.01), layer, 0.03)
    p = params.defaults()
    p.shape.kind, p.shape.height_scale, p.shadows.enabled = "height", 1.0, True
    made = _black_and_white(ImageData(height.astype(np.float32), 32), (PX, PX))
    return [_grey(mask), _grey(layer, 1.0), _grey(height), _lit(render(made, [LOW_SUN], p).rgba)]


def integrated_portrait():
    """Integrate: the portrait's true height, the height integrated from its normal map, and
    the Penrose stairs' residual (the part of their normals no height field has)."""
    _, _, n, z = portrait_relief()
    got = integrate(n)
    diff = np.abs((got.height - got.height.min()) - (z - z.min())) / np.ptp(z)
    err = (float(diff.mean()), float(diff.max()))
    stairs_recipe, stairs = sample_images("impossible", PX)
    n_stairs, _, _ = shape_normals(stairs["shape"], stairs_recipe.params, np.float64,
                                   relief=False)
    curl = integrate(n_stairs)
    tiles = [_grey(z), _grey(got.height - got.height.min(), np.ptp(z)),
             _grey(curl.residual, np.percentile(curl.residual, 99.5))]
    return tiles, err, got.residual_share, curl.residual_share


def relief_shadows():
    """§6 Relief: the portrait as a normal map under a low sun, shadows from its true heights,
    from its integrated relief and along each ray (the paper's way)."""
    recipe, images, n, z = portrait_relief()
    normal_map = {**images, "shape": ImageData(((n + 1) / 2).astype(np.float32), 32)}
    tiles = [_lit(render(images, [LOW_SUN], recipe.params).rgba)]
    for relief in ("integrated", "along_ray"):
        p = copy.deepcopy(recipe.params)
        p.shape.kind, p.shadows.relief = "normal", relief
        tiles.append(_lit(render(normal_map, [LOW_SUN], p).rgba))
    truth = tiles[0][..., :3]
    errs = [float(np.abs(t[..., :3] - truth).mean()) for t in tiles[1:]]
    return tiles, errs


def portrait_profiles():
    """Profiles: the portrait lit from the left, right, top and bottom with its cast shadows
    (core renders: black dark image, white bright one, linear mix, so a pixel is its cos-θ
    term), the normal map they give back, and its true normal map."""
    recipe, images, n, _ = portrait_relief()
    p = copy.deepcopy(recipe.params)
    p.diffuse.mix_space, p.specular.enabled = "linear", False
    flat = _black_and_white(images["shape"], n.shape[:2])
    dirs = profile_directions(("left", "right", "top", "bottom"), 45.0)
    shots = {side: render(flat, [Light("sun", tuple(d))], p).rgba[..., 0]
             for side, d in dirs.items()}
    got = normals_from_profiles(shots, 45.0)
    tiles = [_grey(shots["left"], 1.0), _grey(shots["top"], 1.0), _colour(encode_normals(got)),
             _colour(encode_normals(n))]
    return tiles, float(_angle(got, n).mean())


def rg_photo():
    """The paper's red/green photograph, made by the core: a red sun from the right and a green
    one from the top, light terms over [−1, 1] (t0 = −1, t1 = 1), linear mix of black and
    white, so the picture stores (N.x + 1)/2 and (N.y + 1)/2; decoded, the normal map."""
    recipe, images, n, _ = portrait_relief()
    p = copy.deepcopy(recipe.params)
    p.diffuse.t0, p.diffuse.t1, p.diffuse.mix_space = -1.0, 1.0, "linear"
    p.shadows.enabled = p.specular.enabled = False
    flat = _black_and_white(images["shape"], n.shape[:2])
    photo = render(flat, [Light("sun", (1, 0, 0), (1, 0, 0)), Light("sun", (0, 1, 0), (0, 1, 0))],
                   p).rgba[..., :3]
    got = normals_from_rg_photo(photo)
    return [_colour(photo), _colour(encode_normals(got)), _colour(encode_normals(n))], \
        float(_angle(got, n).mean())


def exported_maps():
    """export-maps of the portrait: its normal map (DirectX green), height, occlusion."""
    _, _, n, z = portrait_relief()
    return [_colour(encode_normals(normals_of_height(z), "directx")), _grey(z),
            _grey(ambient_occlusion(z), 1.0)]


def main(out=DOCS):
    os.makedirs(os.path.join(out, "img", "shape"), exist_ok=True)
    tiles, top = inflated_glass()
    inflated = _save(out, "inflate.png", tiles)
    effects = _save(out, "effects.png", effects_glass())
    tiles, wrong = snapped_blink()
    snap = _save(out, "snap.png", tiles)
    painted = _save(out, "painted.png", painted_in_layers())
    tiles, portrait_err, portrait_share, stairs_share = integrated_portrait()
    integrated = _save(out, "integrate.png", tiles)
    tiles, (err_integrated, err_along) = relief_shadows()
    relief = _save(out, "relief_shadows.png", tiles)
    tiles, profile_err = portrait_profiles()
    profiles = _save(out, "profiles.png", tiles)
    tiles, rg_err = rg_photo()
    photo = _save(out, "rg_photo.png", tiles)
    maps = _save(out, "export_maps.png", exported_maps())
    page = f"""# Making the shape from the painting (`make-shape`, *Make Shape*)

No normal or height map? Make one from what you have. Every method is numpy only (no new
dependency), works on any image size, and writes files the add-on and the other commands read
directly. Heights are in **image widths**: an EXR written here bakes at its true scale with
`--height-scale 1` (`bake-shadow`) or *Height* 1 in the add-on. In Blender: the painting's
*Images* panel › **Make Shape** (inflate the silhouette, a height map from the normal map, a
normal map from the height map, from lighting profiles — pick one, the others named like it
are found — or from a red/green photo; change the options in the *Adjust Last Operation* panel
to see the painting made again, one undo step; the new image is packed in the .blend), and *Add › Dynamic Painting › From Images* with no
shape image inflates the painting's silhouette.

| you have | method | command |
|---|---|---|
| only the painting, with its figure in the alpha (or a mask) | **inflate** the silhouette: round, soft or flat-topped, plus the painting's luminance embossed as detail | `dynpaint make-shape inflate painting.png --profile round --detail 0.01 --out height.exr` |
| 2–5 pictures of the subject lit from the left, right, top, bottom (and front), painted or photographed: Sprite Lamp's *lighting profiles* | **profiles** → normal map (photometric stereo) | `dynpaint make-shape profiles portrait_left.png portrait_right.png portrait_top.png portrait_bottom.png --out normal.png` |
| one photograph lit by a red light from one side and a green light from the top (the paper's trick) | **rg-photo** → normal map | `dynpaint make-shape rg-photo photo.png --red-from right --out normal.png` |
| a normal map, and you want its height (cast shadows, export) | **integrate** → height map (least squares; `--mask` cuts a figure from its background) | `dynpaint make-shape integrate normal.png --mask alpha --out height.exr -v` |
| a height map, and you want its normal map | **normals** (§2) | `dynpaint make-shape normals height.exr --height-scale 1 --out normal.png` |
| a finished painting, for a game engine | **export-maps**: normal (OpenGL or DirectX green), height (EXR and 16-bit PNG), ambient occlusion, specular | `dynpaint make-shape export-maps painting.toml --green directx --out maps/` |

Every command prints what it wrote; `-v` adds the time and, for *integrate*, the part of the
normal map no height map can hold (its curl, as an RMS slope and a share of the field; write
it as an image with `--residual residual.exr`). Bad input ends with one line `error: …`.
Measured against Cycles renders of 3D objects: [shape-numbers.md](shape-numbers.md). Pictures
made by `docs/make_shape_pictures.py` at {PX}² from the samples, rendered by the numpy core.

## Inflate a silhouette

{inflated}

The glass bottle with its artist's normal map (left); the height map made from its alpha alone
(`inflate`, round: highest point {top:.3f} image widths); the bottle rendered with it (right).
A disc becomes its hemisphere within 0.3 % of the radius (RMS) in under a second at 1024².
*soft* is gentler at the rim and pointed in the middle; *flat* has rounded rims and a plateau
(a coin, a cushion). *tube* makes every cross-section a semicircle as wide as the figure there:
round, which rounds the outline as a whole, makes a long part (an arm, a ring) about √2 too
tall; tube gives a ring its torus and is no better for a head, which flat suits best (its
face a plateau with steep walls: 0.68 of a true map's IoU, round 0.51). `--detail` lifts light areas
of the painting and sinks dark ones (image widths per unit of luminance: 0.005–0.02), blurred
by `--detail-blur` first. `--snap 0.01` moves a mask painted by hand onto the painting's own
outline (its strongest edge within 0.01 image widths: a brush a little wide, a stroke a pixel
or two off; `--detail-image` names the painting when the mask is a file of its own). Against
3D ([no-shape-numbers.md](no-shape-numbers.md)), a torus's cast shadows from a hand's mask
went from 0.59 of a true map's IoU (round) to 0.78 (tube) and 0.91 (tube, snapped). When to
use: a portrait or an object with nothing but its painting and a transparent background, or
a mask painted for it.

{snap}

`--snap`: the blink sample's figure as a hand might paint it, {abs(SLIP[0])} pixels across
and {abs(SLIP[1])} along off its outline (red, over the painting: {wrong['blink'][0]} pixels
wrong at {PX}²), snapped within {SNAP_PX} pixels onto the painting's outline (green: {wrong['blink'][1]}
wrong), and the snapped mask inflated with the tube profile. Snapping finds the painting's
strongest edge: a figure drawn with a dark outline has one on each side of the line (the
nearer wins); where the outline hardly shows in the painting — the glass bottle, see-through
— it finds none better and moves little ({wrong['glass'][0]} pixels wrong before,
{wrong['glass'][1]} after).

{effects}

Effects on the inflated figure (the bottle's silhouette inflated *flat*, under a low sun):
a **bevel** 0.03 image widths wide and 0.02 high with a **smoothing** of 0.003 (left: the
heights, then the render), and a woven **structure** tile repeated every 0.05 image widths at
0.003 (right). `--bevel-width`, `--bevel-height`, `--bevel-profile` (round: a quarter circle;
linear: a ramp), `--smoothing`, `--structure TILE.png --structure-scale --structure-strength`;
the bevel comes first, then the smoothing, then the structure (which smoothing would blur
away). The figure can be any painted mask (`--mask-channel`: white on black, or one colour
channel) and the detail any painting (`--detail-image`). In the add-on's Make Shape: the
bevel and the smoothing; its Paint Shape panel (below) takes them all, a structure image too.

## Paint it in Blender (*Paint Shape*)

{painted}

In the add-on, the painting's **Paint Shape** panel › *Paint Shape* gives the painting two
layers, packed in the .blend, and enters Texture Paint on its plane: a **figure mask** (paint
white where the figure is: it is inflated part by part, with the panel's profile, height,
bevel, smoothing, detail and structure) and a **height layer** (grey is the canvas: lighter
raises, darker lowers, by *Height Layer Strength* image widths at white). The shape the
painting reads is made from them — plus its old shape image, kept as the base — and the
painting stays lit while you paint: each stroke bakes a draft, then final once the strokes
stop, re-baking only the rays the stroke changed. Above, left to right: a mask painted as a
body and a head, a height layer with one raised stroke and one lowered dab, the shape they
make (a 0.02-wide bevel) and its render under a low sun. *Done Painting* leaves Texture Paint;
*Export* writes the made shape as the recipe's shape image and the layers beside it.

## Integrate a normal map into heights

{integrated}

The portrait's true height map (left) and the height integrated from its normal map (middle):
mean error {100 * portrait_err[0]:.2f} % of the relief, largest {100 * portrait_err[1]:.1f} % at
the walls where Suzanne's relief drops by more than a normal map's steepest slope (§2 keeps
N.z ≥ z_min); {100 * portrait_share:.1f} % of its slopes are such that no height field holds them.
Right: the same residual for the Penrose stairs, whose normals no height field has —
{100 * stairs_share:.0f} % of their slopes circulate around the ring. When to use: cast shadows
of real shapes drawn as normal maps (the add-on does it for you: below), a height map for
export. Not for impossible figures: the residual says how much of the drawing would be lost.

## Shadows of a normal map (`shadows.relief`)

{relief}

The portrait under a low sun, from its height map (left, the truth), then as a normal map with
its shadows from the integrated relief (middle: what `relief = "auto"`, the default, bakes
live for a map with the figure in its alpha) and rebuilt along each ray (right, the paper's way,
which `auto` bakes live for a full-frame map); a final bake casts the shadow of either, the
darker of the two ([relief-choice.md](relief-choice.md)). Mean colour difference from the truth: {err_integrated:.4f} integrated,
{err_along:.4f} along the ray. Against 3D renders (shape-numbers.md) the integrated relief's
cast shadows overlap the truth 0.84–0.89× as well as a true height map's, along the ray 0.33×.
What keeps it under 0.9× is walls the figure hides: Suzanne's muzzle stands up to 0.16 image
widths above the ground beside it, and the normals on either side of such a wall are smooth, so
no normal map says where it is or how tall. Cut at the walls that only the 3D scene knows, the
same integration reaches 0.99× (the "bound" rows of shape-numbers.md). An artist who knows a
figure stands off the canvas integrates it with its mask and the rim's height (`make-shape
integrate --mask … --depth`, or Make Shape's Depth) and uses that height map as the shape.
Set `relief = "along_ray"` for impossible figures (the Penrose sample does).

## Lighting profiles

{profiles}

Two of the four profiles (lit from the left and from the top, 45° above the painting, cast
shadows and all), the normal map the four give back, and the portrait's true normal map: mean
angular error {profile_err:.2f}°, most of it on the canvas where two profiles' soft shadows
overlap (a shadow darker than the other profiles predict is left out, but only one per pixel
among four). Against Cycles renders with hard cast shadows: about 2° with four or five
profiles, 5° with three; two (left and right) cannot tell whether a surface tilts up or down
(~26°). Side lights lower than ~45° leave steep faces seen by only two profiles: say their
height with `--elevation`. Profiles are read as linear light (8/16-bit files are sRGB-decoded).

## The red/green photograph

{photo}

The paper's shortcut: lit by a red light from the right and a green light from the top (each
spread over the whole sphere of directions, so red = (N.x + 1)/2), a photograph *is* a normal
map's x and y; `rg-photo` adds z = √(1 − x² − y²). Made here by the core (left), decoded
(middle) against the true normal map (right): {rg_err:.3f}° mean (exact: this is the
decoder's own convention). `--red-from left`,
`--green-from bottom` for other set-ups.

## Maps for game engines

{maps}

`export-maps` of the portrait: the normal map with DirectX green (down), the height map (EXR in
image widths and a 16-bit PNG with its scale printed), and ambient occlusion from the height
(horizon-based, 8 directions), plus the gloss map as a specular map when the painting has one.
"""
    with open(os.path.join(out, "shape-from-painting.md"), "w", encoding="utf-8") as fh:
        fh.write(page)
    print(f"wrote {os.path.join(out, 'shape-from-painting.md')} and {out}/img/shape/*.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else DOCS)
