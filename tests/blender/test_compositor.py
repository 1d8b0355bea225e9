"""The compositor node group: the same description as the material, relighting images with no
3D scene; checked against the numpy core on the parity suite's recipes (issue 5)."""
import warnings

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon import blender  # noqa: E402
from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.scenes import compositor  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import output_settings  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images  # noqa: E402

from testkit.sun_painting import sun_painting  # noqa: E402

from parity_recipes import RECIPES, make_recipe, write_images  # noqa: E402
from test_addon import core_of  # noqa: E402


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


def test_operator_adds_a_wired_group_for_the_active_painting(tmp_path):
    write_images(str(tmp_path))
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    folder = str(tmp_path)
    assert bpy.ops.dynpaint.add(directory=folder, files=[{"name": n} for n in (
        "normal.png", "dark.png", "bright.png")]) == {"FINISHED"}
    scene = bpy.context.scene
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert bpy.ops.dynpaint.add_compositor_group() == {"FINISHED"}
    # nothing Blender says it will remove (5.3: Scene.compositing_node_group, removal in 6.0)
    assert [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)] == []
    tree = compositor.compositor_tree(scene)
    node = next(n for n in tree.nodes if n.bl_idname == "CompositorNodeGroup")
    assert node.inputs["Shape"].is_linked and node.inputs["Dark"].is_linked
    assert node.outputs["Image"].is_linked
    sun = node.inputs["Light 1 Direction"].default_value
    assert abs(np.linalg.norm(sun) - 1) < 1e-5
    # and it composites what the material renders
    scene.render.engine = "BLENDER_WORKBENCH"
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.resolution_x, scene.render.resolution_y = 40, 30
    scene.view_settings.view_transform = "Standard"
    output_settings(scene, str(tmp_path / "op.exr"))
    bpy.ops.render.render(write_still=True)
    got = read_image(str(tmp_path / "op.exr")).pixels
    mat = bpy.context.object.active_material
    want = core_of(mat, scene)
    assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-4
    # without a painting: a group chosen by its options
    assert bpy.ops.dynpaint.add_compositor_group(match_painting=False, suns=2, points=1,
                                                 shadows=True, environment=True) == {"FINISHED"}
    group = tree.nodes.active.node_tree
    names = [s.name for s in group.interface.items_tree if s.in_out == "INPUT"]
    assert {"Light 3 Position", "Light 1 Shadow", "Environment"} <= set(names)


def test_a_drafts_small_cos_theta_image_composites_like_the_core(tmp_path):
    """A draft's cos-θ image is the size its bake ran at (shadow_images.write_shadow: 96² for
    a 768² painting); the group's Map UV lookup enlarges it as the core upsamples (≤ 1e-4)."""
    blender.register_once()
    mat = sun_painting(tmp_path, 768)
    mat.dynamic_painting.shadows.quality = "draft"
    bpy.context.view_layer.update()
    assert tuple(mat.dynamic_painting.lights[0].shadow.size) == (96, 96)
    assert bpy.ops.dynpaint.add_compositor_group() == {"FINISHED"}
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x = scene.render.resolution_y = 768
    scene.view_settings.view_transform = "Standard"
    output_settings(scene, str(tmp_path / "draft.exr"))
    bpy.ops.render.render(write_still=True)
    got = read_image(str(tmp_path / "draft.exr")).pixels
    assert np.abs(got - core_of(mat, scene))[1:-1, 1:-1].max() <= 1e-4


def test_shipped_node_groups_regenerate_and_append(tmp_path):
    import subprocess
    import sys
    import os
    from conftest import REPO as repo
    out = str(tmp_path / "groups.blend")
    res = subprocess.run([sys.executable, os.path.join(repo, "node_groups", "make_node_groups.py"),
                          "--out", out], capture_output=True, text=True)
    assert res.returncode == 0 and "wrote 5 groups" in res.stdout, res.stderr
    bpy.ops.wm.read_homefile(use_empty=True)
    shapes = []
    for path in (out, os.path.join(repo, "node_groups", "dynamic_painting.blend")):
        bpy.ops.wm.read_homefile(use_empty=True)
        with bpy.data.libraries.load(path) as (src, dst):
            dst.node_groups = [n for n in src.node_groups if n.startswith("Dynamic Painting:")]
        group = next(g for g in dst.node_groups if g.name.endswith("Everything"))
        names = {s.name for s in group.interface.items_tree if s.in_out == "INPUT"}
        assert {"Shape", "Environment", "Light 2 Position", "Light 1 Shadow",
                "Diffuse t0"} <= names
        assert group.asset_data is not None
        shapes.append({g.name: tree_shape(g) for g in dst.node_groups})
    # the committed file is what the generator writes today (issue 28, point 7)
    assert shapes[0] == shapes[1], "node_groups/dynamic_painting.blend is stale: run " \
        "node_groups/make_node_groups.py"


def tree_shape(tree):
    """What a node group is made of: its interface, its nodes (type, label) and links, and
    its sub-groups' shapes."""
    return (sorted((s.in_out, s.name) for s in tree.interface.items_tree
                   if s.item_type == "SOCKET"),
            sorted((n.bl_idname, n.label) for n in tree.nodes),
            sorted((link.from_node.label or link.from_node.bl_idname, link.from_socket.identifier,
                    link.to_node.label or link.to_node.bl_idname, link.to_socket.identifier)
                   for link in tree.links),
            sorted(tree_shape(n.node_tree) for n in tree.nodes
                   if getattr(n, "node_tree", None) is not None))


def test_passes_per_light_match_core(paths, tmp_path):
    """The group's 'Light i t' outputs are the §4 terms t_i = CS(N·L or cos-θ) of the core."""
    recipe = make_recipe("two_lights_coloured", paths)
    compositor.composite_recipe(recipe, str(tmp_path / "c.exr"))
    scene = bpy.context.scene
    tree = compositor.compositor_tree(scene)
    node = next(n for n in tree.nodes if n.bl_idname == "CompositorNodeGroup")
    out = next(n for n in tree.nodes if n.bl_idname == "NodeGroupOutput")
    from dynpaint_addon.core.pipeline import light_terms, shape_normals
    from dynpaint_addon.core.shading import clamp_step
    imgs = load_images(recipe)
    n, z, sl = shape_normals(imgs["shape"], recipe.params)
    raw, _, _ = light_terms(n, z, sl, recipe.lights, recipe.params)
    for i, t in enumerate(raw):
        tree.links.new(node.outputs[f"Light {i + 1} t"], out.inputs[0])
        bpy.ops.render.render(write_still=True)
        got = read_image(str(tmp_path / "c.exr")).pixels[..., 0]
        want = clamp_step(t, recipe.params.diffuse.t0, recipe.params.diffuse.t1,
                          recipe.params.diffuse.curve)
        assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-4
