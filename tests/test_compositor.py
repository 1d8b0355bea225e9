"""The compositor node group: the same description as the material, relighting images with no
3D scene; checked against the numpy core on the parity suite's recipes (issue 5)."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender import compositor, headless  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.imageio import read_image  # noqa: E402
from dynpaint_addon.recipe import load_images  # noqa: E402

from parity_recipes import RECIPES, make_recipe, write_images  # noqa: E402


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("comp")))


@pytest.mark.parametrize("name", list(RECIPES))
def test_compositor_group_matches_core(name, paths, tmp_path):
    recipe = make_recipe(name, paths)
    out = compositor.composite_recipe(recipe, str(tmp_path / "c.exr"))
    got = read_image(out).pixels
    want = core_render(load_images(recipe), recipe.lights, recipe.params).rgba
    assert got.shape == want.shape
    err = float(np.abs(got - want)[1:-1, 1:-1].max())
    assert err <= 1e-4, f"{name}: max |Δ| {err:.2e}"


def group_names(tree, seen=None):
    seen = set() if seen is None else seen
    for node in tree.nodes:
        sub = getattr(node, "node_tree", None)
        if sub is not None and sub.name not in seen:
            seen.add(sub.name)
            group_names(sub, seen)
    return seen


def test_one_description_two_trees(paths, tmp_path):
    """The material and the compositor group are built from the same sub-graphs."""
    recipe = make_recipe("glass_physical_fresnel", paths)
    _, mat = headless.build_recipe_scene(recipe)
    shader_groups = {n for n in group_names(mat.node_tree) if n.startswith("DP ")}
    compositor.composite_recipe(recipe, str(tmp_path / "g.exr"))
    comp = bpy.data.node_groups[compositor.GROUP_NAME]
    comp_groups = {n.removeprefix("Compositor ") for n in group_names(comp)}
    assert shader_groups and shader_groups == comp_groups
