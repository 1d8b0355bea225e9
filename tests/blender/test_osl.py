"""The OSL shader (issue 5): the pipeline generated from the graph description as one Cycles
Script node, with the cos-θ march inside the shader."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.core.lights import Light  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render, shape_normals  # noqa: E402
from dynpaint_addon.core.shadow import cos_theta_shadow  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images  # noqa: E402
from dynpaint_addon.nodegraph import osl_codegen  # noqa: E402
from dynpaint_addon.nodegraph.pipeline_graph import Features, describe  # noqa: E402

from parity_recipes import RECIPES, make_recipe, write_images  # noqa: E402

NO_SHADOWS = [n for n, (_, over, _) in RECIPES.items() if not over.get("shadows.enabled")]


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("osl")))


def render_osl(recipe, out):
    recipe.params.shadows.source = "osl"
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    output_settings(scene, str(out))
    bpy.ops.render.render(write_still=True)
    return mat, read_image(str(out)).pixels


@pytest.mark.parametrize("name", NO_SHADOWS)
def test_osl_renders_match_core(name, paths, tmp_path):
    recipe = make_recipe(name, paths)
    mat, got = render_osl(recipe, tmp_path / "o.exr")
    assert any(n.bl_idname == "ShaderNodeScript" for n in mat.node_tree.nodes)
    assert bpy.context.scene.cycles.shading_system
    want = core_render(load_images(recipe), recipe.lights, recipe.params).rgba
    err = float(np.abs(got - want)[1:-1, 1:-1].max())
    assert err <= 1e-3, f"{name}: max |Δ| {err:.2e}"


@pytest.mark.parametrize("shape, light, relief", [
    ("height.exr", Light("sun", (0.8, 0.3, 0.5)), "integrated"),
    ("normal", Light("point", (-0.3, -0.2, 0.25)), "along_ray"),
    ("normal_alpha", Light("sun", (0.5, -0.4, 0.4)), "integrated"),    # §6 Relief, masked
    ("height16", Light("sun", (-0.4, -0.7, 0.35)), "integrated")])
def test_in_shader_march_matches_reference_bake(shape, light, relief, paths, tmp_path):
    """The OSL cos-θ term against numpy's reference quality (K = 1024, float64): ≤ 5e-3 mean."""
    recipe = make_recipe("shadows_height", paths)
    recipe.images["shape"] = paths[shape]
    recipe.params.shape.kind = "normal" if shape.startswith("normal") else "height"
    recipe.params.shadows.relief = relief
    recipe.params.shadows.steps = 64
    recipe.lights = [light]
    recipe.params.shadows.source = "osl"
    plane, mat = headless.build_recipe_scene(recipe)
    tree = mat.node_tree
    script = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeScript")
    to_colour = script.outputs["Color"].links[0].to_socket     # (via the straight-alpha divide)
    tree.links.new(script.outputs["Pass_W"], to_colour)             # W = t with this recipe
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    output_settings(scene, str(tmp_path / "t.exr"))
    bpy.ops.render.render(write_still=True)
    got = read_image(str(tmp_path / "t.exr")).pixels[..., 0]
    n, z, slopes = shape_normals(load_images(recipe)["shape"], recipe.params, np.float64)
    ref = cos_theta_shadow(n, light, recipe.params.shadows.offset, 1024, heights_px=z, slopes=slopes,
                           reach=recipe.params.shadows.reach)
    assert np.abs(got - ref).mean() <= 5e-3
    # measured ≈3e-4; 1.3e-3 on the figure's integrated relief (6e-4 from numpy's K = 64)
    assert np.abs(got - ref).mean() <= (2e-3 if shape == "normal_alpha" else 1e-3)


def test_generated_source_is_plain_text_and_complete():
    """No bpy needed to generate; every sub-graph becomes one OSL function."""
    f = Features(size=(64, 48), lights=("sun", "point"), shadows=True, specular=True)
    src = osl_codegen.generate(describe(f), f, march=True)
    assert "shader dynamic_painting(" in src and "dp_cos_theta(" in src
    assert src.count("void DP_Light_") == 2 and "#define DP_NORMAL_DECODE" in src
    assert "light2_world" in src and "p_diffuse_t0" in src


def test_shipped_shaders_are_current():
    """The example .osl files are what the generator writes today."""
    import importlib.util
    import os
    from conftest import REPO as repo
    spec = importlib.util.spec_from_file_location("make_shaders", os.path.join(
        repo, "shaders_osl", "make_shaders.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    for name, src in mod.sources().items():
        with open(os.path.join(repo, "shaders_osl", name), encoding="utf-8") as fh:
            assert fh.read() == src, f"{name} is stale: run shaders_osl/make_shaders.py"


def test_shipped_shader_compiles_with_cycles(tmp_path):
    import os
    from dynpaint_addon.blender.material import osl
    from conftest import REPO as repo
    bpy.ops.wm.read_homefile(use_empty=True)
    tree = bpy.data.materials.new("t").node_tree
    node = tree.nodes.new("ShaderNodeScript")
    node.mode = "EXTERNAL"
    import shutil     # compile a copy: Blender writes the .oso next to the source
    for name in os.listdir(os.path.join(repo, "shaders_osl")):
        if name.endswith(".osl"):
            shutil.copy(os.path.join(repo, "shaders_osl", name), tmp_path / name)
    node.filepath = str(tmp_path / "dynamic_painting_height_shadows.osl")
    osl._cycles_osl().update_script_node(node, lambda kind, msg: None)
    assert "Color" in node.outputs and "p_shadows_steps" in node.inputs
