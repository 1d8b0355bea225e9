"""The web page (issue 17) in a real browser: headless Chromium with its software WebGL2
renders the exported page, a float framebuffer is read back and compared with the numpy core,
and the viewer's controls are driven with real input events.

Images are read through Blender (tests/parity_recipes.py writes PNGs), hence tests/blender.
"""
import subprocess

import numpy as np
import pytest

from dynpaint_addon.core.pipeline import render as core_render
from dynpaint_addon.inputs.imageio import read_image
from testkit.chromium import find_chromium
from dynpaint_addon.inputs.recipe import load_images
from dynpaint_addon.looks import with_look
from dynpaint_addon.web.page import page_data, write_page

from conftest import open_page, page_pixels, run_cli
from parity_recipes import RECIPES, make_recipe, write_images

SHADOWS = [n for n, (_, over, _) in RECIPES.items() if over.get("shadows.enabled")]
NO_SHADOWS = [n for n in RECIPES if n not in SHADOWS] + ["pruned", "full_with_defaults"]  # §12
BORDER = 1    # the height gradient is one-sided there in numpy, extended in every node backend


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("web")))


def export(recipe, folder, **options):
    images = load_images(recipe)
    data, _ = page_data(images, recipe.lights, recipe.params, title=recipe.name, **options)
    path = folder / f"{recipe.name}.html"
    write_page(path, data)
    return path, data, images


def interior(a):
    return a[BORDER:-BORDER, BORDER:-BORDER]


@pytest.mark.parametrize("name", NO_SHADOWS)
def test_page_matches_core(name, paths, browser, tmp_path):
    """≤ 2e-3 per channel (the issue); measured ≤ 2.4e-4, from E and B stored as halves."""
    recipe = make_recipe(name, paths)
    path, data, images = export(recipe, tmp_path)
    got = page_pixels(open_page(browser, path), data["width"], data["height"])
    want = core_render(images, recipe.lights, recipe.params).rgba
    err = float(np.abs(interior(got) - interior(want)).max())
    assert err <= 2e-3, f"{name}: max |Δ| {err:.2e}"
    assert err <= 5e-4, f"{name}: max |Δ| {err:.2e} (measured ≤ 2.4e-4)"


def test_images_are_stored_in_their_own_precision(paths):
    """8-bit and 16-bit files as their integer codes, float files as floats (halves when
    they are halves); decoded texel for texel they are the values the core reads."""
    recipe = make_recipe("refraction_eta_two", paths)      # 16-bit normals, 8-bit colours, EXR
    data, _ = page_data(load_images(recipe), recipe.lights, recipe.params)
    tex = data["textures"]
    assert (tex["shape"]["format"], tex["dark"]["format"], tex["bright"]["format"]) == \
        ("u16", "u8", "u8")
    assert tex["dark"]["srgb"] == 1 and tex["shape"]["srgb"] == 0
    assert tex["background"]["format"] == "f16" and tex["background"]["srgb"] == 0


@pytest.mark.parametrize("steps", [16, 64])
@pytest.mark.parametrize("name", SHADOWS)
def test_in_page_march_matches_core_march_at_same_k(name, steps, paths, browser, tmp_path):
    """The fragment shader's cos-θ march against the core's march at the same K (custom
    quality: the core marches at full resolution): mean |Δ| ≤ 2e-3 (the issue; measured
    ≤ 1e-4). A march is discontinuous where a ray grazes a ridge, so single pixels may flip
    a step by float rounding: at most 1 % of them are off by more than 2e-3."""
    recipe = make_recipe(name, paths)
    recipe.params.shadows.quality = "custom"
    recipe.params.shadows.steps = steps
    path, data, images = export(recipe, tmp_path)
    assert data["steps"] == steps
    got = page_pixels(open_page(browser, path), data["width"], data["height"])
    want = core_render(images, recipe.lights, recipe.params).rgba
    diff = np.abs(interior(got) - interior(want))
    assert diff.mean() <= 2e-3, f"{name}: mean |Δ| {diff.mean():.2e}"
    assert diff.mean() <= 5e-4, f"{name}: mean |Δ| {diff.mean():.2e} (measured ≤ 1e-4)"
    assert (diff > 2e-3).mean() <= 0.01


def test_steps_option_sets_the_march(paths, browser, tmp_path):
    """--steps K reaches the shader: K = 0 marches nothing (t = N·L at d → the plane's)."""
    recipe = make_recipe("shadows_height", paths)
    recipe.params.shadows.quality = "custom"
    path, data, images = export(recipe, tmp_path, steps=2)
    assert data["steps"] == 2 and data["looks"][0]["uniforms"]["p_shadows_steps"] == 2
    recipe.params.shadows.steps = 2
    got = page_pixels(open_page(browser, path), data["width"], data["height"])
    want = core_render(images, recipe.lights, recipe.params).rgba
    assert np.abs(interior(got) - interior(want)).mean() <= 5e-4


def test_looks_are_offered_and_render_like_the_core_with_that_look(paths, browser, tmp_path):
    recipe = make_recipe("glass_physical_fresnel", paths)
    path, data, images = export(recipe, tmp_path)
    names = [look["name"] for look in data["looks"]]
    assert names[0] == "As exported" and {"Gooch", "Cartoon"} <= set(names)
    page = open_page(browser, path)
    for key, label in (("GOOCH", "Gooch"), ("CARTOON", "Cartoon")):
        page.evaluate(f"(() => {{ const s = document.getElementById('look'); "
                      f"s.value = '{names.index(label)}'; s.dispatchEvent(new Event('change')); }})()")
        got = page_pixels(page, data["width"], data["height"])
        want = core_render(images, recipe.lights, with_look(recipe.params, key)).rgba
        assert np.abs(interior(got) - interior(want)).max() <= 2e-3, label


def test_a_screenshot_taken_at_load_shows_the_painting(browser, tmp_path):
    """`chromium --headless --screenshot` (what a user runs) shoots at the load event: the
    images are inflated and the first frame drawn before it, every time (issue 27: 3 blank
    shots in 5 when the images were inflated asynchronously)."""
    page = tmp_path / "portrait.html"
    res = run_cli("export-web", "portrait", "--out", page)
    assert res.returncode == 0, res.stderr
    for i in range(3):
        shot = tmp_path / f"shot{i}.png"
        subprocess.run([find_chromium(), "--headless", "--no-sandbox", f"--screenshot={shot}",
                        "--window-size=700,700", f"file://{page}?embed"], capture_output=True,
                       timeout=120, cwd=tmp_path)
        px = read_image(str(shot)).pixels[..., :3]
        # the page's backdrop is one flat grey; the painting has light and shade
        assert px.std() > 0.05 and np.mean(np.abs(px - px[0, 0]).sum(-1) > 0.05) > 0.3, i
