"""The command line, run as users run it: `python -m dynpaint_addon …` in a fresh process."""
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO, run_cli, unit
from dynpaint_addon.cli import main as cli_main
from dynpaint_addon.core.layers import bake_scene, render_scene
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.pipeline import render
from dynpaint_addon.core.shadow import cos_theta_shadow
from dynpaint_addon.core.shape import height_field_px, normals_from_height_px
from dynpaint_addon.inputs.imageio import read_image, write_png
from dynpaint_addon.inputs.recipe import load_images, load_layers, load_recipe
from dynpaint_addon.inputs.testpainting import write_test_painting, write_test_scene


@pytest.fixture(scope="module")
def painting(tmp_path_factory):
    return write_test_painting(str(tmp_path_factory.mktemp("cli")), size=48)


def test_help_documents_every_command_with_units():
    top = run_cli("--help")
    assert top.returncode == 0
    for cmd in ("render", "bake-shadow", "demo", "make-test-painting", "params"):
        assert cmd in top.stdout
    bake = run_cli("bake-shadow", "--help").stdout
    for word in ("image widths", "pixels", "--steps", "--quality", "--point-light", "ms"):
        assert word in bake
    assert "pixels" in run_cli("render", "--help").stdout
    params = run_cli("params").stdout
    assert "offset = 0.01 (image widths)" in params and "preblur" in params


def test_render_png_and_exr_match_the_core(painting, tmp_path):
    exr = tmp_path / "out.exr"
    res = run_cli("render", painting, "--out", exr, "--engine", "numpy")
    assert res.returncode == 0, res.stderr
    recipe = load_recipe(painting)
    expected = render(load_images(recipe), recipe.lights, recipe.params).rgba
    np.testing.assert_array_equal(read_image(str(exr)).pixels, expected)
    png = tmp_path / "out.png"
    assert run_cli("render", painting, "--out", png, "--width", 20).returncode == 0
    assert read_image(str(png)).pixels.shape == (20, 20, 4)


def test_bake_shadow_height_map(tmp_path):
    size = 40
    hgt = np.zeros((size, size), np.float32)
    hgt[14:26, 16:24] = 1.0
    write_png(str(tmp_path / "h.png"), hgt, bits=16)
    out = tmp_path / "t.exr"
    res = run_cli("bake-shadow", tmp_path / "h.png", "--kind", "height", "--height-scale", 0.2,
                  "--light", 1, 0, 0.6, "--offset", 0.005, "--steps", 96, "--out", out, "-v")
    assert res.returncode == 0, res.stderr
    assert "ms for 40×40" in res.stdout and "steps=96" in res.stdout and "offset=0.005" in res.stdout
    t = read_image(str(out))
    assert t.pixels.shape == (40, 40, 1) and t.bits == 32
    z = height_field_px(hgt, 0.2)
    # a custom K marches to the image's bounds, as the in-shader marches do (core/bake.py)
    ref = cos_theta_shadow(normals_from_height_px(z), Light("sun", (1, 0, 0.6)), 0.005, 96,
                           heights_px=z, bounds="image")
    np.testing.assert_array_equal(t.pixels[..., 0], ref)
    assert t.pixels[20, 8, 0] < 0.05 and t.pixels[20, 32, 0] == pytest.approx(unit((1, 0, 0.6))[2], abs=1e-3)
    # a quality level says what it ran: a sun at preview bakes by crossings, at ¼ resolution
    # but never below 192 px (a 40 px painting: all of it)
    res = run_cli("bake-shadow", tmp_path / "h.png", "--kind", "height", "--height-scale", 0.2,
                  "--light", 1, 0, 0.6, "--quality", "preview", "--out", out, "-v")
    assert "quality=preview method=exact crossings" in res.stdout, res.stdout
    assert "resolution=40×40" in res.stdout, res.stdout


def test_bake_shadow_normal_map_and_point_light(tmp_path):
    flat = np.tile(np.array([0.5, 0.5, 1.0]), (16, 24, 1))
    write_png(str(tmp_path / "n.png"), flat, bits=16)   # 16-bit: 0.5 is within 1e-5 of flat
    for light_args, check in ((("--light", 0, 0.6, 0.8), 0.8), (("--point-light", 0, 0, 0.5), None)):
        out = tmp_path / "n.exr"
        res = run_cli("bake-shadow", tmp_path / "n.png", "--kind", "normal", *light_args,
                      "--quality", "draft", "--out", out)
        assert res.returncode == 0, res.stderr
        t = read_image(str(out)).pixels[..., 0]
        assert t.shape == (16, 24)
        if check:
            np.testing.assert_allclose(t, check, atol=1e-4)
        else:
            assert t[8, 12] > t[0, 0] > 0      # brightest under the point light


@pytest.mark.parametrize("args,message", [
    (("render", "missing.toml", "--out", "x.png"), "missing.toml: recipe file not found"),
    (("bake-shadow", "missing.png", "--kind", "height", "--light", 0, 0, 1, "--out", "t.exr"),
     "missing.png: file not found"),
    (("bake-shadow", "notimage.png", "--kind", "height", "--light", 0, 0, 1, "--out", "t.exr"),
     "notimage.png: not an image Blender can read"),
    (("bake-shadow", "notimage.png", "--kind", "height", "--light", 0, 0, 1, "--out", "t.png"),
     "the shadow term is written as a float EXR"),
    (("bake-shadow", "notimage.png", "--kind", "height", "--light", 0, 0, 0, "--out", "t.exr"),
     "sun direction must not be (0, 0, 0)"),
    (("bake-shadow", "notimage.png", "--kind", "height", "--light", 0, 0, 1, "--steps", -3,
      "--out", "t.exr"), "--steps: -3 is out of range [0, "),
    (("render", "bad.toml", "--out", "x.png"), "bad.toml: shadows.stpes: unknown key (did you mean 'steps'?)"),
    (("render", "good.toml", "--out", "x.jpg"), "unsupported output format '.jpg'"),
    (("render", "good.toml", "--out", "x.png", "--frame", 3), "--frame needs --engine eevee or cycles"),
    # what cost a newcomer minutes (issue 27)
    (("render", "portriat", "--out", "x.png"),
     "portriat: no recipe file and no sample of that name (did you mean 'portrait'?) (samples: "),
    (("turntable", "portriat", "--out", "x.mp4"), "(did you mean 'portrait'?)"),
    (("render", "height.png", "--out", "x.png"),
     "height.png is an image: a recipe (painting.toml) was expected"),
])
def test_user_mistakes_give_one_clear_line(tmp_path, painting, args, message):
    (tmp_path / "notimage.png").write_text("hello")
    (tmp_path / "height.png").write_bytes(b"\x89PNG\r\n")
    (tmp_path / "bad.toml").write_text('[images]\nshape = "notimage.png"\ndark = "notimage.png"\n[shadows]\nstpes = 3\n')
    args = [painting if a == "good.toml" else a for a in args]
    res = run_cli(*args, cwd=tmp_path)
    assert res.returncode == 1
    assert "Traceback" not in res.stderr
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert len(lines) == 1 and message in lines[0], res.stderr


def test_malformed_command_lines_exit_2():
    res = run_cli("bake-shadow", "x.png", "--kind", "sphere", "--light", 0, 0, 1, "--out", "t.exr")
    assert res.returncode == 2 and "invalid choice" in res.stderr and "Traceback" not in res.stderr
    res = run_cli("rendr", "portrait", "--out", "x.png")
    assert res.returncode == 2 and "'rendr' is no command (did you mean 'render'?)" in res.stderr


def test_a_sample_name_renders_and_a_closed_pipe_ends_quietly(tmp_path):
    res = run_cli("render", "portrait", "--width", 32, "--out", tmp_path / "p.png")
    assert res.returncode == 0 and "rendered 32×32" in res.stdout, res.stderr
    head = subprocess.run(f"{sys.executable} -m dynpaint_addon params | head -3", shell=True,
                          cwd=REPO, capture_output=True, text=True)
    assert len(head.stdout.splitlines()) == 3 and "Error" not in head.stderr, head.stderr


def test_demo_writes_an_image(tmp_path):
    res = run_cli("demo", "--out", tmp_path / "demo.png", "--size", 32)
    assert res.returncode == 0, res.stderr
    img = read_image(str(tmp_path / "demo.png")).pixels
    assert img.shape == (32, 32, 4) and img[..., :3].std() > 0.02


def test_render_with_cycles_matches_numpy(tmp_path):
    """`render --engine cycles` builds the add-on's scene in background Blender."""
    folder = tmp_path / "painting"
    assert run_cli("make-test-painting", folder, "--size", 48).returncode == 0
    recipe = folder / "painting.toml"
    res = run_cli("render", recipe, "--engine", "cycles", "--frame", 1, "--out", tmp_path / "c.exr")
    assert res.returncode == 0, res.stderr
    assert "rendered with cycles" in res.stdout
    assert run_cli("render", recipe, "--out", tmp_path / "n.exr").returncode == 0
    got = read_image(str(tmp_path / "c.exr")).pixels
    want = read_image(str(tmp_path / "n.exr")).pixels
    assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-3


def test_bake_shadow_chooses_the_relief_and_its_reach(tmp_path):
    """--relief and --reach reach the bake (issues 27, 39, 62): auto is the shadow of either
    relief at final quality (core/either_relief.py), at a live level along the ray for a
    full-frame normal map and integrated for one with an alpha (core.input_rules.relief_of);
    the reach stops an impossible figure's relief only (core.shape.reach_of)."""
    from testkit.example_paintings import penrose_triangle
    size = 48
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    z = np.sqrt(np.clip(0.3 ** 2 - x * x - y * y, 0, None))
    n = normals_from_height_px((z * size).astype(np.float32))
    write_png(tmp_path / "n.png", (n + 1) / 2, bits=16)
    write_png(tmp_path / "na.png", np.concatenate([(n + 1) / 2, (z > 0)[..., None]], -1), bits=16)

    def bake(image, *extra):       # (in this process: sixteen Blender starts were half its time)
        out = tmp_path / f"t{len(list(tmp_path.iterdir()))}.exr"
        assert cli_main(["bake-shadow", str(tmp_path / image), "--kind", "normal", "--light",
                         "1", "0", "0.6", *map(str, extra), "--out", str(out)]) == 0
        return read_image(str(out)).pixels[..., 0]
    along, integrated = bake("n.png", "--relief", "along_ray"), bake("n.png", "--relief",
                                                                      "integrated")
    assert np.abs(along - integrated).max() > 0.1
    np.testing.assert_array_equal(bake("n.png"), np.minimum(along, integrated))
    np.testing.assert_array_equal(bake("na.png"), np.minimum(
        bake("na.png", "--relief", "integrated"), bake("na.png", "--relief", "along_ray")))
    np.testing.assert_array_equal(bake("n.png", "--quality", "draft"),
                                  bake("n.png", "--quality", "draft", "--relief", "along_ray"))
    np.testing.assert_array_equal(bake("na.png", "--quality", "draft"),
                                  bake("na.png", "--quality", "draft", "--relief", "integrated"))
    # the dome's normals fit a height field: its relief is felt along the whole ray, whatever
    # --reach says (§6 Reach); an impossible figure's stops at --reach
    np.testing.assert_array_equal(bake("n.png", "--relief", "along_ray", "--reach", 0.01), along)
    tribar, _ = penrose_triangle(size)
    write_png(tmp_path / "tribar.png", (tribar + 1) / 2, bits=16)
    assert np.abs(bake("tribar.png", "--relief", "along_ray", "--reach", 0.01)
                  - bake("tribar.png", "--relief", "along_ray", "--reach", 10)).max() > 0.05
    # an impossible figure casts one relief's shadow, even at final (it fits no height field)
    np.testing.assert_array_equal(bake("tribar.png"), bake("tribar.png", "--relief", "along_ray"))


# -- layered recipes (§15) -----------------------------------------------------------------

@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    return write_test_scene(str(tmp_path_factory.mktemp("scene")), size=48)


def test_bake_shadow_layers_writes_each_layers_term_as_the_core_bakes_it(scene, tmp_path):
    out = tmp_path / "t"
    res = run_cli("bake-shadow", "--layers", scene, "--light", 0.55, 0.35, 0.76,
                  "--light-angle", 4, "--out", out, "-v")
    assert res.returncode == 0, res.stderr
    assert "for 3 layers (48×48, 48×48, 48×48), sun light" in res.stdout
    want = bake_scene(load_layers(load_recipe(scene)),
                      Light("sun", (0.55, 0.35, 0.76), size=np.radians(4)))
    for i, t in enumerate(want):
        got = read_image(str(out / f"layer_{i}.exr")).pixels[..., 0]
        np.testing.assert_allclose(got, t, atol=1e-6)
    assert want[0].min() < 0.05 < want[2].min()       # the back is shadowed, the front is not


def test_render_of_a_layered_recipe_is_the_core_composite(scene, tmp_path):
    out = tmp_path / "scene.exr"
    res = run_cli("render", scene, "--out", out)
    assert res.returncode == 0, res.stderr
    assert "rendered 3 layers on 48×48" in res.stdout
    recipe = load_recipe(scene)
    want = render_scene(load_layers(recipe), recipe.lights).rgba
    np.testing.assert_array_equal(read_image(str(out)).pixels, want)


@pytest.mark.parametrize("args,message", [
    (("--light", 0, 0, 1, "--out", "t.exr"), "with --layers, a folder"),
    (("--point-light", 0, 0, 1, "--light-angle", 3, "--out", "t"),
     "--light-angle is a sun's size: give it with --light"),
    (("--light", 0, 0, 1, "--light-radius", 0.1, "--out", "t"),
     "--light-radius is a point light's size: give it with --point-light"),
    (("--light", 0, 0, 1, "--light-angle", 270, "--out", "t"), "--light-angle: degrees in 0 … 180"),
    (("--light", 0, 0, 1, "--kind", "height", "--out", "t"), "give no SHAPE or --kind"),
])
def test_layered_mistakes_give_one_clear_line(scene, tmp_path, args, message):
    res = run_cli("bake-shadow", "--layers", scene, *args, cwd=tmp_path)
    lines = [ln for ln in res.stderr.splitlines() if ln.startswith("error:")]
    assert res.returncode == 1 and len(lines) == 1 and message in lines[0], res.stderr
    res = run_cli("render", scene, "--out", tmp_path / "x.png", "--width", 20)
    assert res.returncode == 1 and "renders a layered painting at its canvas's size" in res.stderr
