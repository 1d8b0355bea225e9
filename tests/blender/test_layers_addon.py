"""Add › Dynamic Painting › Layered… (issue 30): an .ora file and a layered recipe become one
plane per layer under a parent; the layers in front shadow those behind — the same t as the
core's bake of the same scene — and the shadows follow a dragged light, a moved layer, undo,
a saved and reopened file, and a render frame by frame."""

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender.bake import layers  # noqa: E402
from dynpaint_addon.blender.bake.layers import (LAYERED, bake_group_live,  # noqa: E402
                                                core_scene, forget_scenes, group_materials,
                                                layer_parent, settle)
from dynpaint_addon.blender.headless import build_recipe_scene  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.blender.state.lights import painting_frame_light  # noqa: E402
from dynpaint_addon.core.layers import bake_scene, render_scene  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender, read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_layers, load_recipe  # noqa: E402
from dynpaint_addon.inputs.testpainting import write_test_scene  # noqa: E402
from mathutils import Matrix  # noqa: E402
from test_addon import render_cycles  # noqa: E402
from dynpaint_addon.web.page import data_of_page  # noqa: E402
from testkit.layered_files import window_scene, write_ora  # noqa: E402

SIZE = 64


@pytest.fixture(scope="module")
def recipe(tmp_path_factory):
    return write_test_scene(str(tmp_path_factory.mktemp("scene")), size=SIZE)


def shadow_of(mat):
    """The painting's first light's cos-θ image (H, W)."""
    return image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels[..., 0]


def add_layered(path, **kw):
    assert bpy.ops.dynpaint.add_layered(filepath=str(path), **kw) == {"FINISHED"}
    parent = bpy.context.object
    assert parent.get(LAYERED)
    return parent


def test_a_layered_recipe_becomes_planes_whose_shadows_are_the_cores(empty_scene, recipe):
    parent = add_layered(recipe)
    mats = group_materials(parent)
    assert [m.name for m in mats] == ["scene back", "scene ring", "scene star"]
    assert all(layer_parent(m) == parent for m in mats)
    depths = [m.dynamic_painting.plane.location.z for m in mats]
    assert depths == pytest.approx([0.0, 0.12, 0.25])
    # the core's bake of the recipe's layers with the light where the scene has it
    back = mats[0].dynamic_painting.plane
    sun = painting_frame_light(mats[0].dynamic_painting.lights[0].object, back.matrix_world)
    want = bake_scene(load_layers(load_recipe(recipe)), sun)
    for mat, t in zip(mats, want):
        np.testing.assert_allclose(shadow_of(mat), t, atol=2e-3)
    assert shadow_of(mats[0]).min() < 0.05 < shadow_of(mats[2]).min()


def consistent(parent_name):
    """Every layer's shadow image equals a fresh core bake of the group as the scene has it
    now (its planes' places, its light) → the back layer's t."""
    parent = bpy.data.objects[parent_name]
    mats = group_materials(parent)
    back = mats[0].dynamic_painting.plane
    sun = painting_frame_light(mats[0].dynamic_painting.lights[0].object, back.matrix_world)
    forget_scenes()
    want = core_scene(parent, mats).bake(sun)
    for mat, t in zip(mats, want):
        np.testing.assert_allclose(shadow_of(mat), t, atol=1e-6, err_msg=mat.name)
    return shadow_of(mats[0]).copy()


def turn(obj, angle):
    obj.matrix_world = Matrix.Rotation(angle, 4, "X") @ obj.matrix_world


def test_a_dragged_lights_final_bake_runs_beside_the_ui_and_never_writes_a_stale_group(
        empty_scene, recipe):
    """After a drag (bake_group_live: draft now) the final bake starts in a worker thread once
    the light is still (layers._final_bakes, the UI's timer, called here) and is written by
    the timer when done: each layer's shadows then equal a fresh core bake, and an update that
    moves nothing bakes nothing again. A bake the scene outran (its light or a layer moved meanwhile) is dropped, not written."""
    parent = add_layered(recipe)
    name, mats = parent.name, group_materials(parent)
    key = bpy.data.objects["Key"]

    def drag_then_start():
        turn(key, 0.2)
        assert bake_group_live(parent) > 0
        assert all("|draft|" in m.dynamic_painting.lights[0].bake_key for m in mats)
        layers._FINAL_DUE[name] -= layers.DEBOUNCE_S                 # still long enough
        assert layers._final_bakes() == layers.POLL_S                 # started, not done
        return layers._RUNNING[name]
    job = drag_then_start()
    job.thread.join()
    assert layers._final_bakes() is None                              # written
    assert all("|own|" in m.dynamic_painting.lights[0].bake_key for m in mats)
    consistent(name)
    # an update where nothing moved (a setting the bake does not read): its final stands —
    # no draft on the main thread, no final again
    assert bake_group_live(parent) == 0 and name not in layers._FINAL_DUE
    assert all("|own|" in m.dynamic_painting.lights[0].bake_key for m in mats)
    job = drag_then_start()
    turn(key, 0.1)                                   # the light moves on: its bake is dropped
    job.thread.join()
    assert not job.write()
    del layers._RUNNING[name]
    job = drag_then_start()
    bpy.data.objects["scene star"].location.x += 0.1                   # the group moves on
    bpy.context.view_layer.update()                        # (its own bake, synchronous here)
    job.thread.join()
    assert not job.write()                                             # dropped
    del layers._RUNNING[name]
    consistent(name)


def test_a_dragged_lights_draft_is_written_at_its_own_size(empty_scene, tmp_path):
    """A drag's draft (issue 62: ≤ 50 ms at 1024², docs/layers-speed.md) is written as the
    core bakes it at its own size — 96² images for 768² layers, which the material enlarges as
    it samples them — nothing upsampled on the way."""
    parent = add_layered(write_test_scene(str(tmp_path), size=768))
    mats = group_materials(parent)
    turn(bpy.data.objects["Key"], 0.2)
    assert bake_group_live(parent) > 0
    back = mats[0].dynamic_painting.plane
    sun = painting_frame_light(mats[0].dynamic_painting.lights[0].object, back.matrix_world)
    want = core_scene(parent, mats).bake(sun, "draft", own_size=True)
    for mat, t in zip(mats, want):
        assert t.shape == (96, 96)
        np.testing.assert_allclose(shadow_of(mat), t, atol=1e-6, err_msg=mat.name)


def test_a_moved_light_or_layer_rebakes_the_group_and_undo_brings_it_back(empty_scene, recipe):
    parent = add_layered(recipe)
    name = parent.name
    bpy.ops.ed.undo_push(message="layered")
    start = consistent(name)
    star = bpy.data.objects["scene star"]
    star.location.x += 0.1                       # move the front layer: its shadow moves
    bpy.context.view_layer.update()
    settle()
    bpy.ops.ed.undo_push(message="move layer")
    moved = consistent(name)
    assert np.abs(moved - start).mean() > 1e-3
    turn(bpy.data.objects["Key"], 0.2)           # drag the light: draft now, final once still
    bpy.context.view_layer.update()
    settle()
    bpy.ops.ed.undo_push(message="move light")
    lit = consistent(name)
    assert np.abs(lit - moved).mean() > 1e-3
    bpy.ops.ed.undo()                            # the light back
    np.testing.assert_allclose(consistent(name), moved, atol=1e-6)
    bpy.ops.ed.undo()                            # the layer back
    np.testing.assert_allclose(consistent(name), start, atol=1e-6)


def test_saved_and_reopened_and_rendered_frame_by_frame(empty_scene, recipe, tmp_path):
    parent = add_layered(recipe)
    name = parent.name
    scene = bpy.context.scene
    sun = bpy.data.objects["Key"]
    for frame, angle in ((1, 0.0), (3, 0.4)):
        sun.rotation_mode = "XYZ"
        sun.rotation_euler = (angle, 0.2, 0.5)
        sun.keyframe_insert("rotation_euler", frame=frame)
    blend = str(tmp_path / "layers.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    consistent(name)                              # the pixels remade as the file opened
    scene = bpy.context.scene
    scene.frame_set(2)                            # frame 2 alone …
    alone = consistent(name)
    scene.frame_set(1)
    scene.frame_set(3)
    scene.frame_set(2)                            # … and after others: bit for bit
    np.testing.assert_array_equal(consistent(name), alone)
    back = bpy.data.materials["scene back"].dynamic_painting.plane
    render_cycles(scene, back, str(tmp_path / "frame2.exr"))   # renders, never raises


def test_an_ora_file_adds_with_parallax_for_a_perspective_camera(empty_scene, tmp_path):
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    bpy.context.scene.collection.objects.link(cam)
    cam.location = (0.0, 0.0, 4.0)
    bpy.context.scene.camera = cam
    path = write_ora(str(tmp_path / "window.ora"), SIZE, window_scene(SIZE))
    parent = add_layered(path, spacing=0.1)
    mats = group_materials(parent)
    assert [m.dynamic_painting.plane.name for m in mats] == [
        "window sky", "window hill", "window figure"]
    for mat in mats:     # each layer scaled by (D − z)/D: the camera sees the composition
        plane = mat.dynamic_painting.plane
        assert plane.scale.x == pytest.approx((4.0 - plane.location.z) / 4.0, rel=1e-3)
    figure = mats[2].dynamic_painting
    assert figure.shape.kind == "normal" and figure.image_shape.packed_file is not None


@pytest.mark.parametrize("engine", ["cycles", "eevee"])
def test_every_layer_renders_as_the_core_draws_it(recipe, tmp_path, engine):
    """The material of each layer (its shadow image holding t_own·T) in Cycles and EEVEE
    against the core's render of that layer in the scene (§15), ≤ 1e-3; and the composite of
    the whole scene (an orthographic camera: the core's back-to-front over) as well."""
    plane, _ = build_recipe_scene(load_recipe(recipe))
    scene = bpy.context.scene
    exact_render_settings(scene, engine)
    want = render_scene(load_layers(load_recipe(recipe)), load_recipe(recipe).lights)
    parent = plane.parent
    mats = group_materials(parent)
    for i, mat in enumerate(mats):
        for j, other in enumerate(mats):
            other.dynamic_painting.plane.visible_camera = i == j   # still shadowing
        output_settings(scene, str(tmp_path / f"{engine}_{i}.exr"))
        bpy.ops.render.render(write_still=True)
        got = read_image(str(tmp_path / f"{engine}_{i}.exr")).pixels
        err = np.abs(got - want.layers[i].rgba)[1:-1, 1:-1]
        assert err.mean() <= 1e-3, (engine, mat.name, err.mean())
    for other in mats:
        other.dynamic_painting.plane.visible_camera = True
    output_settings(scene, str(tmp_path / f"{engine}_all.exr"))
    bpy.ops.render.render(write_still=True)
    got = read_image(str(tmp_path / f"{engine}_all.exr")).pixels
    assert np.abs(got - want.rgba)[1:-1, 1:-1].mean() <= 1e-3


def test_file_export_html_of_a_layer_exports_its_whole_scene(empty_scene, recipe, tmp_path):
    parent = add_layered(recipe)
    bpy.context.view_layer.objects.active = group_materials(parent)[1].dynamic_painting.plane
    out = str(tmp_path / "scene.html")
    assert bpy.ops.dynpaint.export_web(filepath=out) == {"FINISHED"}
    data = data_of_page(open(out, encoding="utf-8").read())
    assert [layer["name"] for layer in data["layers"]] == ["scene back", "scene ring",
                                                            "scene star"]
    assert data["layers"][0]["front"] == [1, 2] and "through" in data["layers"][0]


def test_a_layers_edited_pixels_rebake_the_layers_behind(empty_scene, recipe):
    """Issue 41's headless contract in a layered group: the ring layer's alpha cut away in
    Blender (its dark and bright images), `update_tag()` and a depsgraph evaluation: every
    layer's shadows are at once a fresh core bake of the group as its images are now — the
    back layer is lit where the ring's shadow fell."""
    parent = add_layered(recipe)
    mats = group_materials(parent)
    bpy.context.view_layer.update()
    before = consistent(parent.name)
    s = mats[1].dynamic_painting
    for img in {s.image_dark, s.image_bright}:
        px = np.empty(len(img.pixels), np.float32)
        img.pixels.foreach_get(px)
        px = px.reshape(-1, img.channels)
        px[:, 3] = 0.0                       # the ring gone
        img.pixels.foreach_set(px.ravel())
        img.update_tag()
    bpy.context.view_layer.update()
    after = consistent(parent.name)
    assert (after > before + 0.1).sum() > 20         # the ring's shadow lifted off the back
