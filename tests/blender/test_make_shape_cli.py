"""`make-shape` on the command line (issue 16): each method on files in other tools'
conventions (16-bit PNGs, Sprite Lamp names, alpha silhouettes, EXR heights in image widths),
the bake reading an integrated height at its true scale, and bad input as one line."""
import os
import shutil

import numpy as np
import pytest

from dynpaint_addon.inputs.imageio import read_image, write_exr, write_png
from dynpaint_addon.inputs.samples import recipe_path

from conftest import run_cli

SIZE = 96


def sphere(size=SIZE, radius=0.35, ball=0.6):
    """A cap of a ball (radius `ball`) cut at `radius`: heights in image widths, unit
    normals, the disc it covers."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    r2 = x * x + y * y
    disc = r2 < radius ** 2
    z = np.where(disc, np.sqrt(ball ** 2 - np.minimum(r2, ball ** 2))
                 - np.sqrt(ball ** 2 - radius ** 2), 0)
    n = np.dstack([x, y, np.sqrt(np.clip(ball ** 2 - r2, 0, None))]) / ball
    return z, np.where(disc[..., None], n, [0.0, 0.0, 1.0]), disc


def ok(res):
    assert res.returncode == 0, res.stderr
    assert "Traceback" not in res.stderr
    return res.stdout


def test_integrate_writes_heights_in_image_widths_that_bake_at_their_true_scale(tmp_path):
    z, n, inside = sphere()
    write_png(tmp_path / "normal.png", (n + 1) / 2, bits=16)
    out = ok(run_cli("make-shape", "integrate", tmp_path / "normal.png", "--out",
                     tmp_path / "height.exr", "--residual", tmp_path / "res.exr", "-v"))
    assert "integrate:" in out and "residual" in out and " s" in out
    height = read_image(tmp_path / "height.exr").pixels[..., 0]
    assert np.abs((height - height[0, 0]) - z).max() < 0.02 * z.max()     # a kink at its rim
    ok(run_cli("bake-shadow", tmp_path / "height.exr", "--kind", "height", "--height-scale", "1",
               "--light", "1", "0", "0.5", "--out", tmp_path / "t.exr"))
    t = read_image(tmp_path / "t.exr").pixels[..., 0]
    assert t[SIZE // 2, SIZE // 2 + 40] < 0.5 < t[SIZE // 2, SIZE // 2 + 20]  # shadow beside it


def test_integrate_with_the_alpha_as_mask_lifts_the_figure_by_its_depth(tmp_path):
    n = np.zeros((40, 50, 3))
    n[..., 2] = 1
    rgba = np.concatenate([(n + 1) / 2, np.zeros((40, 50, 1))], axis=2)
    rgba[10:30, 10:40, 3] = 1
    write_png(tmp_path / "box.png", rgba, bits=16)
    ok(run_cli("make-shape", "integrate", tmp_path / "box.png", "--mask", "alpha", "--depth",
               "0.08", "--out", tmp_path / "box.exr"))
    h = read_image(tmp_path / "box.exr").pixels[..., 0]
    assert h[20, 20] == pytest.approx(0.08, abs=1e-4) and h[0, 0] == pytest.approx(0, abs=1e-4)


def test_normals_profiles_and_rg_photo_make_normal_maps(tmp_path):
    z, n, inside = sphere()
    write_exr(tmp_path / "h.exr", z)
    ok(run_cli("make-shape", "normals", tmp_path / "h.exr", "--height-scale", "1",
               "--out", tmp_path / "n.png"))
    got = read_image(tmp_path / "n.png").pixels[..., :3] * 2 - 1
    inner = (np.linalg.norm(n[..., :2], axis=2) < 0.25) & inside
    assert np.degrees(np.arccos(np.clip(np.sum(got * n, 2), -1, 1)))[inner].mean() < 1.0
    # Sprite Lamp's names: portrait_left.png … lit at 45°, the command's default
    e = np.radians(45)
    for side, l in {"left": (-np.cos(e), 0, np.sin(e)), "right": (np.cos(e), 0, np.sin(e)),
                    "top": (0, np.cos(e), np.sin(e)), "bottom": (0, -np.cos(e), np.sin(e))}.items():
        shot = np.clip(n @ np.array(l), 0, 1)
        write_exr(tmp_path / f"portrait_{side}.exr", shot)
    res = run_cli("make-shape", "profiles", *[tmp_path / f"portrait_{s}.exr" for s in
                                              ("left", "right", "top", "bottom")],
                  "--out", tmp_path / "p.exr", "-v")
    ok(res)
    assert "portrait_left.exr: the left profile (by its name; --left sets it)" in res.stderr
    got = read_image(tmp_path / "p.exr").pixels[..., :3] * 2 - 1
    assert np.degrees(np.arccos(np.clip(np.sum(got * n, 2), -1, 1)))[inside].mean() < 0.5
    write_png(tmp_path / "photo.png", (n + 1) / 2, bits=16)
    ok(run_cli("make-shape", "rg-photo", tmp_path / "photo.png", "--green", "directx",
               "--out", tmp_path / "rg.png"))
    rg = read_image(tmp_path / "rg.png").pixels[..., :3] * 2 - 1
    assert np.abs(rg[..., 1] + n[..., 1]).max() < 1e-3              # DirectX: green down


def test_inflate_makes_a_hemisphere_of_a_silhouette(tmp_path):
    _, _, disc = sphere(128, 0.4, 0.4)
    rgba = np.ones((128, 128, 4))
    rgba[..., 3] = disc
    write_png(tmp_path / "painting.png", rgba)
    out = ok(run_cli("make-shape", "inflate", tmp_path / "painting.png", "--out",
                     tmp_path / "h.png", "-v"))
    assert "height_scale" in out
    scale = float(out.split("height_scale ")[1].split(")")[0])
    h = read_image(tmp_path / "h.png").pixels[..., 0] * scale
    assert h.max() == pytest.approx(0.4, rel=0.02) and h[0, 0] == 0


def test_inflate_takes_a_painted_mask_with_a_bevel_smoothing_and_a_structure(tmp_path):
    """Issue 41, point 3, on the command line: a mask painted white on black, inflated with
    the effects: the result is the inflated mask plus the bevel's plateau, smoothed, with the
    structure's stripes repeating every --structure-scale."""
    _, _, disc = sphere(128, 0.4, 0.4)
    write_png(tmp_path / "mask.png", disc.astype(np.float64))
    stripes = np.tile(np.repeat([0.0, 1.0], 8), (16, 1))                # a 16-px tile
    write_png(tmp_path / "tile.png", stripes)
    ok(run_cli("make-shape", "inflate", tmp_path / "mask.png", "--out", tmp_path / "plain.exr"))
    ok(run_cli("make-shape", "inflate", tmp_path / "mask.png", "--bevel-width", "0.05",
               "--bevel-height", "0.03", "--smoothing", "0.004", "--structure",
               tmp_path / "tile.png", "--structure-scale", "0.125", "--structure-strength",
               "0.004", "--out", tmp_path / "fx.exr"))
    plain = read_image(tmp_path / "plain.exr").pixels[..., 0]
    fx = read_image(tmp_path / "fx.exr").pixels[..., 0]
    added = (fx - plain)[40:88, 40:88]                    # the middle: the bevel's plateau
    assert float(np.median(added)) == pytest.approx(0.03, abs=0.003)
    row = added[24]
    np.testing.assert_allclose(row[16:], row[:-16], atol=2e-4)      # a tile every 16 px
    assert float(row.max() - row.min()) == pytest.approx(0.004, abs=3e-4)   # the swing
    assert fx[0, 0] == 0


def test_export_maps_of_a_sample(tmp_path):
    out = ok(run_cli("make-shape", "export-maps", "portrait", "--out", tmp_path / "maps"))
    for name in ("normal.png", "height.exr", "height.png", "ambient_occlusion.png"):
        assert (tmp_path / "maps" / name).exists(), out
    ao = read_image(tmp_path / "maps" / "ambient_occlusion.png").pixels[..., 0]
    assert 0 < ao.min() < 0.95 and ao.max() == 1.0


def test_export_maps_height_of_a_normal_map_does_not_follow_the_shadows_relief(tmp_path):
    """A normal map's exported height is its figure integrated apart at the alpha, whether the
    recipe's shadows fall from that relief or are rebuilt along the ray."""
    shutil.copytree(os.path.dirname(recipe_path("glass")), tmp_path / "glass")
    text = (tmp_path / "glass" / "painting.toml").read_text(encoding="utf-8")
    heights = []
    for relief in ("integrated", "along_ray"):
        recipe = tmp_path / "glass" / f"{relief}.toml"
        recipe.write_text(text + f'\n[shadows]\nrelief = "{relief}"\n', encoding="utf-8")
        ok(run_cli("make-shape", "export-maps", recipe, "--out", tmp_path / relief))
        heights.append(read_image(tmp_path / relief / "height.exr").pixels[..., 0])
    assert np.ptp(heights[0]) > 0.01 and np.array_equal(heights[0], heights[1])


@pytest.mark.parametrize("args,message", [
    (["integrate", "missing.png", "--out", "h.exr"], "file not found"),
    (["integrate", "{d}/n.png", "--out", "h.tif"], ".exr (float) or .png"),
    (["integrate", "{d}/n.png", "--mask", "alpha", "--out", "h.exr"], "no alpha channel"),
    (["integrate", "{d}/n.png", "--mask", "{d}/small.png", "--out", "h.exr"], "must match"),
    (["inflate", "{d}/black.png", "--out", "h.exr"], "no figure to inflate"),
    (["profiles", "{d}/n.png", "--out", "made_n.png"], "does not say a side"),
    (["profiles", "--left", "{d}/n.png", "--out", "made_n.png"], "at least two"),
    (["profiles", "--left", "{d}/n.png", "--right", "{d}/small.png", "--out", "made_n.png"],
     "same size"),
])
def test_bad_input_is_one_line(tmp_path, args, message):
    write_png(tmp_path / "n.png", np.broadcast_to([0.5, 0.5, 1.0], (20, 30, 3)))   # flat normals
    write_png(tmp_path / "small.png", np.full((10, 10, 3), 0.5))
    write_png(tmp_path / "black.png", np.zeros((10, 10, 3)))
    res = run_cli("make-shape", *[a.format(d=tmp_path) for a in args], cwd=tmp_path)
    assert res.returncode == 1 and "Traceback" not in res.stderr
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and message in lines[0], lines


@pytest.mark.parametrize("bits", [8, 16])
def test_every_method_on_non_square_8_and_16_bit_files_writes_finite_maps(tmp_path, bits):
    """Each command on a 37×23 picture stored at 8 or 16 bits: finite output, right size."""
    h, w = 23, 37
    y, x = (np.mgrid[0:h, 0:w] + 0.5) / w - [[[0.3]], [[0.5]]]
    n = np.dstack([x, y, np.full_like(x, 0.6)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    rgba = np.dstack([(n + 1) / 2, (x * x + y * y < 0.09).astype(float)])
    write_png(tmp_path / "n.png", rgba, bits=bits)
    write_png(tmp_path / "h.png", np.clip(0.5 - x * x - y * y, 0, 1), bits=bits)
    for side, light in {"left": (-1, 0, 1), "right": (1, 0, 1), "top": (0, 1, 1)}.items():
        write_png(tmp_path / f"p_{side}.png", np.clip(n @ (np.array(light) / np.sqrt(2)), 0, 1),
                  bits=bits)
    runs = {"integrate.exr": ["integrate", tmp_path / "n.png", "--mask", "alpha"],
            "normals.png": ["normals", tmp_path / "h.png", "--height-scale", "0.1"],
            "profiles.png": ["profiles", *[tmp_path / f"p_{s}.png" for s in ("left", "right",
                                                                             "top")]],
            "rg.png": ["rg-photo", tmp_path / "n.png"],
            "inflate.exr": ["inflate", tmp_path / "n.png", "--detail", "0.01"]}
    for out, args in runs.items():
        ok(run_cli("make-shape", *args, "--out", tmp_path / out))
        px = read_image(tmp_path / out).pixels
        assert px.shape[:2] == (h, w) and np.all(np.isfinite(px)), out


def test_inflate_snaps_a_hand_painted_mask_onto_the_paintings_outline(tmp_path):
    """make-shape inflate MASK --detail-image PAINTING --snap: the figure inflated is where the
    painting's outline is, not where the hand slipped (core/snap.py); without --snap, where
    the mask is."""
    size = 128
    y, x = np.mgrid[0:size, 0:size] + 0.5
    figure = (x - 64) ** 2 + (y - 64) ** 2 < 40 ** 2
    slipped = (x - 67) ** 2 + (y - 62) ** 2 < 40 ** 2            # 3 px right, 2 down
    write_png(tmp_path / "mask.png", slipped.astype(float), bits=8)
    write_png(tmp_path / "painting.png", np.dstack([np.where(figure, 0.25, 0.9)] * 3), bits=8)
    for snap, out in (("0", "plain.exr"), ("0.04", "snapped.exr")):
        ok(run_cli("make-shape", "inflate", tmp_path / "mask.png", "--detail-image",
                   tmp_path / "painting.png", "--snap", snap, "--out", tmp_path / out))
    plain, snapped = (read_image(tmp_path / f).pixels[..., 0] > 0 for f in ("plain.exr",
                                                                             "snapped.exr"))
    assert (plain != slipped).sum() == 0
    assert (snapped != figure).sum() < 0.15 * (slipped != figure).sum()
