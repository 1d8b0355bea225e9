"""A painting that moves, in Blender (§16, issue 31): a sequence of height maps and a sprite
sheet of dark frames become a painting whose material and shadows follow the frame — as the
core draws each frame — in renders one by one and in Render Animation (a frame alone = the
frame in sequence, bit for bit), through undo, a saved and reopened file (relative paths, a
packed sheet), a missing frame (the last good one stays) and the animated sample."""
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender.bake import shadow_images  # noqa: E402
from dynpaint_addon.blender.bake import live_bake  # noqa: E402
from dynpaint_addon.blender.bake.live_bake import LIVE  # noqa: E402
from dynpaint_addon.blender.headless import build_recipe_scene  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.blender.state import status  # noqa: E402
from dynpaint_addon.blender.state.frames import frame_data, painting_frames, slot_frame  # noqa: E402
from dynpaint_addon.blender.state.settings import settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import render  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender, read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe  # noqa: E402
from dynpaint_addon.shapes.methods import make_shape  # noqa: E402
from testkit.animated import moving_dome, write_sequence, write_sheet  # noqa: E402

SIZE = 48


def write_painting(folder, frames='mode = "ping-pong"'):
    """Four height frames (16-bit PNG), a 2 × 2 sheet of dark frames, a still bright image."""
    write_sequence(os.path.join(folder, "height_####.png"), moving_dome(SIZE, 4), bits=16)
    darks = [np.dstack([np.full((SIZE, SIZE), 0.15 + 0.15 * i)] * 3) for i in range(4)]
    write_sheet(os.path.join(folder, "dark_sheet.png"), darks, 2, 2, bits=8)
    write_png(os.path.join(folder, "bright.png"), np.full((SIZE, SIZE, 3), 0.85), bits=8)
    path = os.path.join(folder, "painting.toml")
    with open(path, "w") as fh:
        fh.write(f'[images]\nshape = "height_####.png"\ndark = "dark_sheet.png"\n'
                 f'bright = "bright.png"\n[shape]\nkind = "height"\nheight_scale = 0.1\n'
                 f'[shadows]\nenabled = true\n[frames]\n{frames}\n[frames.dark]\ncolumns = 2\n'
                 f'rows = 2\n[[lights]]\ndirection = [0.6, 0.2, 0.5]\n')
    return path


@pytest.fixture
def recipe(tmp_path):
    return write_painting(str(tmp_path))


def render_frame(scene, f, path):
    scene.frame_set(f)
    LIVE.wait()
    output_settings(scene, path)
    bpy.ops.render.render(write_still=True)
    return read_image(path).pixels


@pytest.mark.parametrize("engine", ["cycles", "eevee", "osl"])
def test_every_frame_renders_as_the_core_draws_it(empty_scene, recipe, tmp_path, engine):
    """Cycles within 1e-4 of the core on every frame; EEVEE (half floats) within 1e-3 mean;
    Cycles with the OSL shader, whose in-shader march stands for the bake, within 5e-3 mean
    (test_osl's measure) — each drawing's images written to files of their own."""
    r = load_recipe(recipe)
    if engine == "osl":
        r.params.shadows.source = "osl"
    plane, mat = build_recipe_scene(r)
    scene = bpy.context.scene
    exact_render_settings(scene, "eevee" if engine == "eevee" else "cycles")
    shown = []
    for f in (1, 2, 3, 4, 5, 6, 9) if engine == "cycles" else (2, 5):  # ping-pong: 1 2 3 4 3 2
        got = render_frame(scene, f, str(tmp_path / f"f{f}.exr"))
        want = render(load_images(r, f), r.lights, r.params).rgba
        diff = np.abs(got - want)[1:-1, 1:-1]
        if engine == "cycles":
            assert diff.max() <= 1e-4, (f, diff.max())
        else:
            assert diff.mean() <= (1e-3 if engine == "eevee" else 5e-3), (f, diff.mean())
        shown.append(slot_frame(mat, "shape", f))
    assert shown == ([1, 2, 3, 4, 3, 2, 3] if engine == "cycles" else [2, 3])


def test_a_frame_rendered_alone_is_the_frame_rendered_in_sequence(empty_scene, recipe,
                                                                   tmp_path):
    plane, mat = build_recipe_scene(load_recipe(recipe))
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    output_settings(scene, str(tmp_path / "seq_####.exr"))
    scene.frame_start, scene.frame_end = 1, 5
    scene.render.use_lock_interface = True
    bpy.ops.render.render(animation=True)
    in_sequence = read_image(str(tmp_path / "seq_0005.exr")).pixels
    build_recipe_scene(load_recipe(recipe))                       # a fresh scene
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    alone = render_frame(scene, 5, str(tmp_path / "alone.exr"))
    np.testing.assert_array_equal(alone, in_sequence)
    assert not np.array_equal(alone, read_image(str(tmp_path / "seq_0004.exr")).pixels)


def test_the_bake_follows_the_drawing_not_the_scene_frame(empty_scene, tmp_path):
    """On twos (rate 0.5) two scene frames show one drawing: one bake for both."""
    plane, mat = build_recipe_scene(load_recipe(write_painting(str(tmp_path), "rate = 0.5")))
    scene = bpy.context.scene
    item = mat.dynamic_painting.lights[0]
    keys, images = [], []
    for f in (1, 2, 3, 4):
        scene.frame_set(f)
        LIVE.wait()
        keys.append(item.bake_key)
        images.append(image_data_from_blender(item.shadow).pixels.copy())
    assert keys[0] == keys[1] != keys[2] == keys[3]
    np.testing.assert_array_equal(images[0], images[1])
    assert not np.array_equal(images[1], images[2])


def test_a_loop_that_comes_round_under_a_still_light_shows_its_bakes_again(
        empty_scene, recipe, monkeypatch):
    """A moving shape's bakes are kept by key: a drawing shown again under the same light
    takes its shadows without baking them (the same pixels); a moved light bakes, and a
    forced bake (the shape's pixels may have been edited) bakes anew."""
    plane, mat = build_recipe_scene(load_recipe(recipe))
    scene = bpy.context.scene
    item = mat.dynamic_painting.lights[0]
    first = {}
    for f in (1, 2, 3, 4):
        scene.frame_set(f)
        LIVE.wait()
        first[f] = image_data_from_blender(item.shadow).pixels.copy()
    baked = []
    bake_core = shadow_images.shadow_term
    monkeypatch.setattr(shadow_images, "shadow_term",
                        lambda *a, **k: baked.append(1) or bake_core(*a, **k))
    for f in (1, 2, 3, 4):
        scene.frame_set(f)
        LIVE.wait()
        np.testing.assert_array_equal(image_data_from_blender(item.shadow).pixels, first[f])
    assert baked == []
    item.object.rotation_mode = "XYZ"            # (the recipe's sun is turned by a quaternion)
    item.object.rotation_euler = (0.3, 0.2, 0.0)
    scene.frame_set(4)
    LIVE.wait()
    assert len(baked) == 1
    shadow_images.bake_shadows(mat, scene)
    assert len(baked) == 2


@pytest.mark.parametrize("level", live_bake.LIVE_LEVELS)
def test_the_live_worker_shows_a_drawings_finest_kept_bake_without_baking(empty_scene, recipe,
                                                                           level):
    """During playback with a UI the live worker bakes at its live level; a drawing it comes
    back to under the same light is shown from its finest kept bake at once (no bake, no
    thread), whichever level the worker has come to (a loaded machine moves it to draft)."""
    plane, mat = build_recipe_scene(load_recipe(recipe))
    scene = bpy.context.scene
    live = live_bake.LiveBake()
    item = mat.dynamic_painting.lights[0]
    scene.frame_set(2)                 # (background Blender bakes its final quality here)
    final = image_data_from_blender(item.shadow).pixels.copy(), item.bake_key
    live.request(mat, scene, quality=level)       # kept: the final is shown, nothing baked
    assert live.threads == [] and live.wait() == 0
    scene.frame_set(3)
    live.levels[mat.name] = level
    live.request(mat, scene, quality="final")     # baked already: shown from the cache too
    assert live.threads == []
    scene.frame_set(2)
    live.request(mat, scene)
    assert live.threads == [] and live.wait() == 0
    np.testing.assert_array_equal(image_data_from_blender(item.shadow).pixels, final[0])
    assert item.bake_key == final[1]


def _shape_copy(mat):
    """What the material samples of the moving height map now (its derived height copy)."""
    item = next(d for d in mat.dynamic_painting.derived if d.channel == "height")
    return image_data_from_blender(item.image).pixels[..., 0].copy()


def test_undo_a_saved_and_reopened_file_and_a_packed_sheet(empty_scene, recipe, tmp_path):
    folder = os.path.dirname(recipe)
    assert bpy.ops.dynpaint.add(filepath=recipe, directory=folder,
                                files=[{"name": "painting.toml"}]) == {"FINISHED"}
    mat = bpy.context.object.active_material
    name = mat.name                 # undo replaces the data: Python references go stale
    s = mat.dynamic_painting
    scene = bpy.context.scene
    scene.frame_set(3)
    third = _shape_copy(mat)
    bpy.ops.ed.undo_push(message="added")
    s.frames.mode = "hold"                        # a setting of the painting's mapping
    scene.frame_set(7)                            # hold: the last drawing, 4
    assert slot_frame(mat, "shape") == 4
    bpy.ops.ed.undo_push(message="hold")
    bpy.ops.ed.undo()
    mat = bpy.data.materials[name]
    scene = bpy.context.scene
    assert mat.dynamic_painting.frames.mode == "ping-pong"
    scene.frame_set(3)
    np.testing.assert_array_equal(_shape_copy(mat), third)
    # saved beside its images: the sequence by a relative path, the sheet packed
    mat.dynamic_painting.image_dark.pack()
    blend = os.path.join(folder, "painting.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, relative_remap=True)
    assert mat.dynamic_painting.image_shape.filepath.startswith("//")
    os.remove(os.path.join(folder, "dark_sheet.png"))               # the packed copy serves
    bpy.ops.wm.open_mainfile(filepath=blend)
    mat = bpy.data.materials[name]
    bpy.context.scene.frame_set(3)
    np.testing.assert_array_equal(_shape_copy(mat), third)
    dark = next(d for d in mat.dynamic_painting.derived if d.channel == "dark")
    assert image_data_from_blender(dark.image).pixels[0, 0, 0] > 0    # the packed sheet's cell


def test_a_missing_frame_is_said_and_the_last_good_frame_stays(empty_scene, recipe):
    plane, mat = build_recipe_scene(load_recipe(recipe))
    scene = bpy.context.scene
    scene.frame_set(2)
    second = _shape_copy(mat)
    os.remove(os.path.join(os.path.dirname(recipe), "height_0003.png"))
    painting_frames(mat).forget()                 # as a file deleted behind Blender's back
    scene.frame_set(3)
    assert any("height_0003.png (frame 3 of height_####.png, scene frame 3) is missing"
               in str(e) for e in status.LAST_ERRORS), status.LAST_ERRORS
    status.LAST_ERRORS.clear()
    np.testing.assert_array_equal(_shape_copy(mat), second)


def test_the_animated_sample_moves_as_its_light_turns(empty_scene):
    assert bpy.ops.dynpaint.add_sample(sample="blink") == {"FINISHED"}
    scene = bpy.context.scene
    mat = bpy.context.object.active_material
    assert (scene.frame_start, scene.frame_end) == (1, 48)
    s = mat.dynamic_painting
    copies, keys = [], []
    for f in (1, 2, 25):
        scene.frame_set(f)
        LIVE.wait()
        copies.append(image_data_from_blender(next(d.image for d in s.derived
                                                    if d.channel == "shape")).pixels.copy())
        keys.append(s.lights[0].bake_key)
    assert not np.array_equal(copies[0], copies[1])
    np.testing.assert_array_equal(copies[0], copies[2])          # 24 frames: 25 shows 1 again
    assert len(set(keys)) == 3                                    # the light turned meanwhile


def test_the_web_page_of_a_painting_that_moves_holds_its_drawings(empty_scene, recipe,
                                                                   tmp_path):
    """File › Export › Dynamic Painting (.html): every drawing of one loop (ping-pong: 4
    drawings over 6 frames), at the scene's rate."""
    plane, mat = build_recipe_scene(load_recipe(recipe))
    bpy.context.scene.render.fps = 12
    bpy.context.view_layer.objects.active = plane
    out = str(tmp_path / "page.html")
    assert bpy.ops.dynpaint.export_web(filepath=out) == {"FINISHED"}
    from dynpaint_addon.blender.scenes.web_page import painting_page
    data, _ = painting_page(mat, bpy.context.scene, "t", animation=False)
    assert data["frames"]["sequence"] == [0, 1, 2, 3, 2, 1] and data["frames"]["fps"] == 12
    assert len(data["frames"]["textures"]["dark"]) == 4


def test_make_shape_on_a_painting_that_moves_gives_each_drawing_its_shape(empty_scene, recipe):
    """Make Shape › Normal Map from Height on the moving height maps: a packed sheet of one
    cell per frame of the loop (ping-pong over 4 drawings: 6), which the shape slot's own
    mapping shows on its frame — each cell the normal map of that frame's heights."""
    plane, mat = build_recipe_scene(load_recipe(recipe))
    bpy.context.view_layer.objects.active = plane
    s = mat.dynamic_painting
    p = settings_to_params(s)
    want = {f: make_shape("normals", {"shape": frame_data(mat, "shape", f)}, p)[1]
            for f in (2, 3, 5, 8)}
    assert bpy.ops.dynpaint.make_shape(method="normals") == {"FINISHED"}
    assert s.frames_shape_own and (s.frames_shape.count, s.frames_shape.mode) == (6, "cyclic")
    assert s.image_shape.packed_file is not None and s.shape.kind == "normal"
    for f, rgba in want.items():
        np.testing.assert_allclose(frame_data(mat, "shape", f).pixels, rgba, atol=1e-6)
    np.testing.assert_array_equal(want[2], want[8])             # 8 shows frame 2 again
    assert not np.array_equal(want[2], want[3])
    bpy.context.scene.frame_set(5)                           # and the painting shows them
    copy = next(d.image for d in s.derived if d.channel == "shape")
    np.testing.assert_allclose(image_data_from_blender(copy).pixels, want[5], atol=1e-6)


def test_the_compositor_group_of_a_painting_that_moves_shows_the_frame(empty_scene, recipe,
                                                                        tmp_path):
    """Add Compositor Group on a moving painting wires the frame's copies: as the frame
    changes, the group relights that frame's drawing, as the core does."""
    r = load_recipe(recipe)
    plane, mat = build_recipe_scene(r)
    scene = bpy.context.scene
    bpy.context.view_layer.objects.active = plane
    assert bpy.ops.dynpaint.add_compositor_group() == {"FINISHED"}
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.view_settings.view_transform = "Standard"
    for f in (2, 5):
        scene.frame_set(f)
        output_settings(scene, str(tmp_path / f"c{f}.exr"))
        bpy.ops.render.render(write_still=True)
        got = read_image(str(tmp_path / f"c{f}.exr")).pixels
        want = render(load_images(r, f), r.lights, r.params).rgba
        assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-4, f
