"""The add-on's material against the numpy core, pixel by pixel (issue 3).

Each recipe of parity_recipes.py is built exactly as the `render` command builds it
(blender/headless.py), rendered by Cycles (1 sample, no denoising, EXR) and by EEVEE, and
compared with core.pipeline.render on every pixel away from the plane's border:
Cycles within 1e-3 per channel, EEVEE within 3e-3 (half-float output, GPU lookups).
"""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.nodes.build import count_nodes  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images  # noqa: E402

from conftest import EEVEE_OPAQUE_SNAP  # noqa: E402
from parity_recipes import RECIPES, make_recipe, write_images  # noqa: E402

# The issue asks for 1e-3 (Cycles) and 3e-3 (EEVEE); Cycles measures ≤ 5e-6 here, so a
# regression shows long before it breaks the promise.
TOLERANCE = {"cycles": 1e-4, "eevee": 3e-3}
BORDER = 1   # the height gradient is one-sided there in numpy, extended in nodes


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("parity")))


def render_both(recipe, engine, out):
    headless.render_recipe(recipe, engine, str(out))
    got = read_image(str(out)).pixels
    want = core_render(load_images(recipe), recipe.lights, recipe.params).rgba
    return got, want


def max_error(got, want, border=BORDER):
    b = border
    return float(np.abs(got[b:-b, b:-b] - want[b:-b, b:-b]).max())


def test_at_least_twenty_recipes():
    assert len(RECIPES) >= 20


@pytest.mark.parametrize("engine", ["cycles", "eevee"])
@pytest.mark.parametrize("name", list(RECIPES))
def test_material_matches_core(name, engine, paths, tmp_path):
    recipe = make_recipe(name, paths)
    got, want = render_both(recipe, engine, tmp_path / f"{name}.exr")
    assert got.shape == want.shape
    if engine == "eevee":
        snapped = want[..., 3] >= EEVEE_OPAQUE_SNAP
        assert np.all(got[..., 3][snapped] >= want[..., 3][snapped] - TOLERANCE[engine])
        got[..., 3] = np.where(snapped, want[..., 3], got[..., 3])
    err = max_error(got, want)
    assert err <= TOLERANCE[engine], f"{name} {engine}: max |Δ| {err:.2e}"


def test_pruned_tree_renders_like_full_tree_fed_defaults(paths, tmp_path):
    """§12: same pixels (Cycles), far fewer nodes."""
    counts, pixels = {}, {}
    for name in ("pruned", "full_with_defaults"):
        recipe = make_recipe(name, paths)
        _, mat = headless.build_recipe_scene(recipe)
        counts[name] = count_nodes(mat.node_tree)
        got, want = render_both(recipe, "cycles", tmp_path / f"{name}.exr")
        assert max_error(got, want) <= TOLERANCE["cycles"]
        pixels[name] = got
    assert np.abs(pixels["pruned"] - pixels["full_with_defaults"]).max() <= 1e-5
    assert counts["pruned"] < 0.7 * counts["full_with_defaults"], counts
