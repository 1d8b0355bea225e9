"""Undo, redo and handlers (issue 7): after undoing or redoing a light move or a parameter
change the painting is consistent (its generated images are those of the restored settings and
lights); a bake that fails inside an animation render is reported, keeps the last good image
and never reaches Blender's render loop.

Blender's undo works headless once steps are pushed (`ed.undo_push`), so this is real undo.
"""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender import handlers, headless  # noqa: E402
from dynpaint_addon.blender.bake.shadow_images import bake_shape  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.blender.state import status  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import shadow_term  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender  # noqa: E402

from parity_recipes import make_recipe, write_images  # noqa: E402
from test_addon import core_of, render_cycles  # noqa: E402


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("undo")))


def consistent(mat, scene, tmp_path, tag):
    """The shadow images equal a fresh bake for the lights and settings as they are now, and
    Cycles renders what the core renders → (offset, sun direction) for the caller."""
    s = mat.dynamic_painting
    p = settings_to_params(s)
    plane = s.plane
    n, z, slopes = bake_shape(mat, p, fresh=True)
    for item in s.lights:
        light = painting_frame_light(item.object, plane.matrix_world)
        fresh = shadow_term(n, z, slopes, light, p)
        got = image_data_from_blender(item.shadow).pixels[..., 0]
        assert np.array_equal(got, fresh), f"{tag}: {item.object.name}'s shadow image is stale"
    got = render_cycles(scene, plane, tmp_path / f"{tag}.exr")
    want = core_of(mat, scene)
    err = float(np.abs(got - want)[1:-1, 1:-1].max())
    assert err <= 1e-4, f"{tag}: Cycles is {err:.2e} from the core"
    return p.shadows.offset, painting_frame_light(s.lights[0].object, plane.matrix_world).vector


def test_undo_and_redo_of_a_light_move_and_a_parameter_change(paths, tmp_path):
    recipe = make_recipe("shadows_height", paths)
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    sun = linked_lights(mat, scene)[0]
    bpy.context.view_layer.objects.active = plane
    status.LAST_ERRORS.clear()
    bpy.ops.ed.undo_push(message="painting")
    start = consistent(mat, scene, tmp_path, "start")

    sun.rotation_mode = "XYZ"
    sun.rotation_euler = (0.9, 0.3, 2.0)             # move the light …
    bpy.ops.dynpaint.bake_shadows()                   # … and bake it (as the UI's live bake)
    bpy.ops.ed.undo_push(message="move light")
    moved = consistent(mat, scene, tmp_path, "moved")
    assert not np.allclose(moved[1], start[1])

    mat.dynamic_painting.shadows.offset = 0.05       # a shadow input: re-bakes
    bpy.ops.ed.undo_push(message="offset")
    changed = consistent(mat, scene, tmp_path, "changed")
    assert changed[0] == pytest.approx(0.05)

    name = mat.name               # undo replaces the data: Python references go stale

    def current():
        return bpy.data.materials[name], bpy.context.scene
    bpy.ops.ed.undo()                                 # offset back
    assert consistent(*current(), tmp_path, "undo1")[0] == pytest.approx(moved[0])
    bpy.ops.ed.undo()                                 # light back
    back = consistent(*current(), tmp_path, "undo2")
    assert np.allclose(back[1], start[1], atol=1e-6)
    bpy.ops.ed.redo()                                 # light moved again
    again = consistent(*current(), tmp_path, "redo")
    assert np.allclose(again[1], moved[1], atol=1e-6)
    assert status.LAST_ERRORS == []


def test_a_bake_failing_inside_an_animation_render_never_reaches_the_render_loop(
        paths, tmp_path, monkeypatch):
    recipe = make_recipe("shadows_height", paths)
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    sun = linked_lights(mat, scene)[0]
    sun.rotation_mode = "XYZ"
    for frame, z in ((1, 0.0), (3, 1.5)):
        sun.rotation_euler = (0.6, 0.2, z)
        sun.keyframe_insert("rotation_euler", frame=frame)
    scene.frame_set(1)
    good = image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels.copy()

    def broken(*args, **kwargs):
        raise RuntimeError("the bake broke (test)")
    monkeypatch.setattr(handlers, "bake_painting", broken)  # what the handler calls
    status.LAST_ERRORS.clear()
    exact_render_settings(scene, "cycles")
    output_settings(scene, str(tmp_path / "x.exr"))
    scene.render.filepath = str(tmp_path / "f_####")
    scene.frame_start, scene.frame_end = 1, 3
    bpy.ops.render.render(animation=True)             # must finish: three frames written
    for frame in (1, 2, 3):
        assert (tmp_path / f"f_{frame:04d}.exr").exists()
    after = image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels
    assert np.array_equal(good, after)                # the last good image is kept
    assert status.LAST_ERRORS and all("the bake broke" in m for _, m in status.LAST_ERRORS)
    status.LAST_ERRORS.clear()
