"""Keyframed lights animate the material in one animation render (issue 3), with and without
the per-frame cos-θ bake (handlers.on_frame_change)."""
import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.material.sync import batch  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.blender.state import status  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images  # noqa: E402

from parity_recipes import make_recipe, write_images  # noqa: E402

FRAMES = (1, 10, 20)


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("anim")))


def keyframe_lights(lights):
    """Suns turn (one of them in Euler XYZ, to exercise the drivers' quaternion conversion);
    point lights move and change colour."""
    for i, obj in enumerate(lights):
        for frame, angle in zip(FRAMES, (0.0, 1.2, 2.6)):
            if obj.data.type == "SUN":
                obj.rotation_mode = "XYZ"
                obj.rotation_euler = (0.5 + 0.2 * angle, -0.3, angle)
                obj.keyframe_insert("rotation_euler", frame=frame)
            else:
                obj.location = (0.3 * math.cos(angle), 0.3 * math.sin(angle), 0.15 + 0.1 * angle)
                obj.keyframe_insert("location", frame=frame)
                obj.data.color = (1.0, 0.5 + 0.2 * angle, 0.3)
                obj.data.keyframe_insert("color", frame=frame)


@pytest.mark.parametrize("name", ["two_lights_coloured", "shadows_height"])
def test_keyframed_lights_in_one_animation_render(name, paths, tmp_path):
    recipe = make_recipe(name, paths)
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    lights = linked_lights(mat, scene)
    keyframe_lights(lights)
    exact_render_settings(scene, "cycles")
    output_settings(scene, str(tmp_path / "f.exr"))
    scene.render.filepath = str(tmp_path / "f_####")
    scene.frame_start, scene.frame_end = 1, 20
    scene.frame_set(5)          # the render must not depend on where the timeline was
    bpy.ops.render.render(animation=True)
    images = load_images(recipe)
    for frame in FRAMES:
        scene.frame_set(frame)
        core_lights = [painting_frame_light(o, plane.matrix_world) for o in lights]
        want = core_render(images, core_lights, recipe.params).rgba
        got = read_image(str(tmp_path / f"f_{frame:04d}.exr")).pixels
        err = float(np.abs(got - want)[1:-1, 1:-1].max())
        assert err <= 1e-3, f"{name} frame {frame}: max |Δ| {err:.2e}"
    # and the frames differ: the lights did move
    first = read_image(str(tmp_path / "f_0001.exr")).pixels
    last = read_image(str(tmp_path / "f_0020.exr")).pixels
    assert np.abs(first - last).max() > 0.05


def test_per_frame_bake_depends_only_on_the_frame(paths, tmp_path):
    """A farm renders frame chunks in fresh processes: the bake of frame k must not depend on
    what was rendered before. Frame 17 after playing 1…16 equals frame 17 alone."""
    from dynpaint_addon.inputs.imageio import image_data_from_blender

    def scene_at(frames):
        recipe = make_recipe("shadows_height", paths)
        plane, mat = headless.build_recipe_scene(recipe)
        keyframe_lights(linked_lights(mat, bpy.context.scene))
        for f in frames:
            bpy.context.scene.frame_set(f)
        return image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels.copy()
    played = scene_at(range(1, 18))
    alone = scene_at([17])
    assert np.array_equal(played, alone)
    assert not np.array_equal(played, scene_at([1]))


def test_animation_frame_equals_a_single_frame_render(paths, tmp_path):
    """Frame 3 of an animation render is bit-identical to rendering frame 3 alone (Cycles),
    shadows baked per frame in both."""
    def build():
        recipe = make_recipe("shadows_normal_point", paths)
        plane, mat = headless.build_recipe_scene(recipe)
        keyframe_lights(linked_lights(mat, bpy.context.scene))
        scene = bpy.context.scene
        exact_render_settings(scene, "cycles")
        output_settings(scene, str(tmp_path / "x.exr"))
        return scene
    scene = build()
    scene.render.filepath = str(tmp_path / "anim_####")
    scene.frame_start, scene.frame_end = 1, 3
    bpy.ops.render.render(animation=True)
    scene = build()
    scene.frame_set(3)
    scene.render.filepath = str(tmp_path / "still.exr")
    bpy.ops.render.render(write_still=True)
    anim = read_image(str(tmp_path / "anim_0003.exr")).pixels
    still = read_image(str(tmp_path / "still.exr")).pixels
    assert np.array_equal(anim, still)


def test_a_failing_frame_bake_keeps_the_image_and_never_raises(paths):
    from dynpaint_addon.inputs.imageio import image_data_from_blender
    recipe = make_recipe("shadows_height", paths)
    plane, mat = headless.build_recipe_scene(recipe)
    lights = linked_lights(mat, bpy.context.scene)
    keyframe_lights(lights)
    before = image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels.copy()
    status.LAST_ERRORS.clear()
    with batch():                              # no refresh: the next bake meets it
        mat.dynamic_painting.image_shape = None   # the shape image is gone
    bpy.context.scene.frame_set(10)               # must not raise
    after = image_data_from_blender(mat.dynamic_painting.lights[0].shadow).pixels
    assert np.array_equal(before, after)
    assert [name for name, _ in status.LAST_ERRORS] == [mat.name]
    assert "no shape image" in status.LAST_ERRORS[0][1]
    status.LAST_ERRORS.clear()
