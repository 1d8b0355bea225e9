"""The files artists already have, lit at the first try (issue 59): a folder of each 2D-lighting
tool's and engine's convention (testkit/sprite_sets.py) goes through `dynpaint new` and
`dynpaint render` with no hand edit, and the render follows the true normals (Pearson r ≥ 0.5),
keeps the sprite's alpha (IoU ≥ 0.98) and leaves at most 15 % of the pixels facing the light
in shadow; numbered frames and texture atlases animate; Add makes the same painting lit."""
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import settings_to_params  # noqa: E402
from dynpaint_addon.cli import main, new as new_cmd  # noqa: E402
from dynpaint_addon.core.frames import expand_pattern  # noqa: E402
from dynpaint_addon.core.lights import DEFAULT_SUN_DIRECTION  # noqa: E402
from dynpaint_addon.inputs import painting_folder  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image  # noqa: E402
from dynpaint_addon.inputs.recipe import load_recipe  # noqa: E402
from testkit import sprite_sets  # noqa: E402
from testkit.scene_picture import render_cycles  # noqa: E402
from testkit.sun_painting import image_pixels  # noqa: E402

LIGHT = np.asarray(DEFAULT_SUN_DIRECTION) / np.linalg.norm(DEFAULT_SUN_DIRECTION)


@pytest.fixture(scope="module")
def sets(tmp_path_factory):
    return {s.tool: s for s in sprite_sets.write_all(str(tmp_path_factory.mktemp("sprites")))}


def rendered(folder, out, frame=None):
    args = ["render", folder, "--out", out] + ([] if frame is None else ["--frame", str(frame)])
    assert main(args) == 0
    return read_image(out).pixels


def colour_of(folder, frame=1):
    recipe = load_recipe(os.path.join(folder, "painting.toml"))
    px = read_image(expand_pattern(recipe.images["bright"], frame)).pixels
    return px if px.shape[2] == 4 else np.dstack([px, np.ones(px.shape[:2])])


@pytest.mark.parametrize("tool", [w.__name__ for w in sprite_sets.WRITERS])
def test_each_tools_files_are_lit_at_the_first_try(sets, tool, tmp_path):
    found = next(s for s in sets.values() if os.path.basename(s.folder) == tool)
    assert main(["new", found.folder, "--force"]) == 0
    relief = load_recipe(os.path.join(found.folder, "painting.toml")).params.shadows.relief
    assert relief == ("along_ray" if tool == "rgba_wall" else "auto")   # an opaque alpha
    if tool == "sprite_lamp_wall":      # its map's alpha is the depth: the map is its RGB
        shape = load_recipe(os.path.join(found.folder, "painting.toml")).images["shape"]
        assert shape.endswith("made/wall_NormalDepth_rgb.png") and \
            read_image(shape).pixels.shape[2] == 3
    for frame in ([1, 5] if found.frames > 1 else [None]):
        index = (frame or 1) - 1
        got = rendered(found.folder, str(tmp_path / f"{tool}_{frame}.exr"), frame)
        verdict = sprite_sets.judge(got, colour_of(found.folder, frame or 1),
                                    found.normals[index], found.coverage[index], LIGHT)
        assert verdict.passes(), (tool, frame, verdict)


def test_numbered_frames_animate(sets, tmp_path):
    walk = sets["numbered frames"]
    assert main(["new", walk.folder, "--force"]) == 0
    first, third = (rendered(walk.folder, str(tmp_path / f"{f}.exr"), f) for f in (1, 3))
    assert np.abs(first[..., 3] - third[..., 3]).max() > 0.5      # the figure moved


@pytest.mark.parametrize("form", ["hash", "array", "multiatlas"])
def test_a_texture_atlas_is_the_frames_it_lists(sets, form, tmp_path):
    folder = sprite_sets.pack_atlas(sets["numbered frames"], str(tmp_path), form)
    assert main(["new", folder]) == 0
    recipe = load_recipe(os.path.join(folder, "painting.toml"))
    walk = sets["numbered frames"].folder
    for frame in (1, 2, 8):              # frame 2 was packed turned, every frame trimmed
        for channel, suffix in (("bright", ""), ("shape", "_n")):
            made = read_image(expand_pattern(recipe.images[channel], frame)).pixels
            want = read_image(os.path.join(walk, f"{frame:02d}{suffix}.png")).pixels
            figure = want[..., 3] > 0
            assert made.shape == want.shape
            np.testing.assert_array_equal(made[figure], want[figure])
    got = rendered(folder, str(tmp_path / "atlas.exr"), 2)
    verdict = sprite_sets.judge(got, colour_of(folder, 2), sets["numbered frames"].normals[1],
                                sets["numbered frames"].coverage[1], LIGHT)
    assert verdict.passes(), verdict


@pytest.mark.every_blender
def test_add_lights_a_sprite_and_its_map_at_once(sets, empty_scene, tmp_path):
    """Add › Dynamic Painting with a sprite and its (green-down, alpha-less) map picked: the
    painting is lit as an albedo, cut out by the sprite's alpha, its map read green down and
    its shadows on — in Cycles as the numpy core draws it."""
    godot = sets["Godot (green down)"]
    assert bpy.ops.dynpaint.add(directory=godot.folder, files=[
        {"name": "logo.png"}, {"name": "logo_normal.png"}]) == {"FINISHED"}
    plane = bpy.context.object
    s = plane.active_material.dynamic_painting
    assert s.shadows.enabled and s.shape.flip_green
    got = render_cycles(empty_scene, plane, str(tmp_path / "add.exr"))
    sun = linked_lights(plane.active_material, empty_scene)[0]
    light = painting_frame_light(sun, s.plane.matrix_world).vector
    colour = read_image(os.path.join(godot.folder, "logo.png")).pixels
    verdict = sprite_sets.judge(got, colour, godot.normals[0], godot.coverage[0], light)
    assert verdict.passes(), verdict


def test_paint_shapes_strokes_show_on_a_colour_painting(sets, empty_scene, tmp_path):
    """A colour painting alone (its shape inflated from its alpha), then Paint Shape: a stroke
    on the height layer changes the picture where it was painted (before issue 59 the
    picture stayed the colour image, bit for bit)."""
    knight = sets["SpriteIlluminator"]
    assert bpy.ops.dynpaint.add(directory=knight.folder, files=[{"name": "knight.png"}]) \
        == {"FINISHED"}
    plane = bpy.context.object
    s = plane.active_material.dynamic_painting
    before = render_cycles(empty_scene, plane, str(tmp_path / "before.exr"))
    colour = read_image(os.path.join(knight.folder, "knight.png")).pixels
    assert np.abs(before[..., 3] - colour[..., 3]).max() < 0.02        # cut out by its alpha
    assert bpy.ops.dynpaint.paint_shape() == {"FINISHED"}
    layer = s.painted.height_layer
    px = image_pixels(layer)
    h, w = px.shape[:2]
    y, x = np.ogrid[0:h, 0:w]
    stroke = np.hypot(x - 0.5 * w, y - 0.4 * h) < 0.1 * w
    px[stroke, :3] = 1.0
    layer.pixels.foreach_set(px.ravel())
    layer.update_tag()
    bpy.context.view_layer.update()
    bpy.ops.object.mode_set(mode="OBJECT")
    after = render_cycles(empty_scene, plane, str(tmp_path / "after.exr"))
    change = np.abs(after[..., :3] - before[..., :3]).max(-1)
    assert change[stroke].max() > 0.05 and change[~stroke].mean() < change[stroke].mean()


@pytest.mark.parametrize("size", [(1, 1), (7, 3), (75, 75)])
def test_a_sprite_of_any_size_renders_turns_and_exports(size, tmp_path):
    """A sprite of 1×1, 7×3 or 75² px (odd: H.264 wants even sizes) through new, render,
    turntable and export-web: each ends with its file, no traceback."""
    w, h = size
    folder = tmp_path / "tiny"
    folder.mkdir()
    rng = np.random.default_rng(w)
    sprite_sets.write_png(str(folder / "dot.png"), rng.uniform(0.2, 1, (h, w, 4)))
    sprite_sets.write_png(str(folder / "dot_n.png"), np.dstack([
        np.full((h, w, 2), 0.5), np.ones((h, w, 2))]))
    assert main(["new", str(folder)]) == 0
    for command, out in (("render", "a.png"), ("turntable", "a.mp4"), ("export-web", "a.html")):
        extra = ["--frames", "2"] if command == "turntable" else []
        assert main([command, str(folder), "--out", str(tmp_path / out), *extra]) == 0
        assert (tmp_path / out).stat().st_size > 0


def test_add_reads_an_alpha_opaque_everywhere_as_a_full_frame_map(sets, empty_scene):
    """Add with a full-frame map saved as RGBA (alpha 255): its shadows fall along each ray,
    as `new` writes it, and the report says why."""
    wall = sets["paint program (full-frame map saved as RGBA)"]
    assert bpy.ops.dynpaint.add(directory=wall.folder, files=[
        {"name": "tiles.png"}, {"name": "tiles_n.png"}]) == {"FINISHED"}
    s = bpy.context.object.active_material.dynamic_painting
    assert settings_to_params(s).shadows.relief == "along_ray"


def test_sprite_lamps_normal_depth_is_read_as_its_colour_everywhere(sets, empty_scene,
                                                                   tmp_path, monkeypatch):
    """Sprite Lamp's NormalDepth holds the depth in its alpha: `render FOLDER` asks for `new`
    (which writes the map's colour to made/, reading the file once), and Add packs the
    colour as the normal map, so the mortar (depth 0) is not cut out."""
    wall = sets["Sprite Lamp (NormalDepth: the depth in the map's alpha)"]
    folder = tmp_path / "wall"
    folder.mkdir()
    for name in ("wall_Diffuse.png", "wall_NormalDepth.png"):
        (folder / name).write_bytes(open(os.path.join(wall.folder, name), "rb").read())
    assert main(["render", str(folder), "--out", str(tmp_path / "x.png")]) == 1
    assert bpy.ops.dynpaint.add(directory=str(folder), files=[
        {"name": "wall_Diffuse.png"}, {"name": "wall_NormalDepth.png"}]) == {"FINISHED"}
    plane = bpy.context.object
    s = plane.active_material.dynamic_painting
    assert s.image_shape.name.endswith("normal map") and s.image_shape.packed_file is not None
    assert "wall_NormalDepth.png" not in bpy.data.images        # the file's copy left behind
    got = render_cycles(empty_scene, plane, str(tmp_path / "add.exr"))
    assert got[..., 3].min() > 0.99                      # nothing cut out
    sun = linked_lights(plane.active_material, empty_scene)[0]
    light = painting_frame_light(sun, s.plane.matrix_world).vector
    colour = read_image(str(folder / "wall_Diffuse.png")).pixels
    verdict = sprite_sets.judge(got, np.dstack([colour[..., :3], np.ones(colour.shape[:2])]),
                                wall.normals[0], None, light)
    assert verdict.passes(), verdict
    reads = []
    for module in (painting_folder, new_cmd):
        monkeypatch.setattr(module, "read_image", lambda path, *a, real=module.read_image, **k:
                            reads.append(os.path.basename(path)) or real(path, *a, **k))
    assert main(["new", str(folder)]) == 0
    assert reads.count("wall_NormalDepth.png") == 1
