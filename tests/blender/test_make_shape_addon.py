"""Make Shape in the add-on (issue 16): a painting with no shape image gets its silhouette
inflated; Make Shape integrates a normal map into heights; Cycles renders what the core
renders with the new shape; undo brings the old shape back."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import channel_images, settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.inputs.imageio import (image_data_from_blender, read_image, write_exr,  # noqa: E402
                                    write_png)

from test_addon import render_cycles  # noqa: E402

SIZE = 64


def disc(size=SIZE, radius=0.35):
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    return x, y, x * x + y * y < radius ** 2


def core_of(mat, scene):
    """The core's render from the images as Blender holds them (packed ones included)."""
    s = mat.dynamic_painting
    images = {c: read_image(bpy.path.abspath(img.filepath)) if img.filepath and not
              img.packed_file else image_data_from_blender(img)
              for c, img in channel_images(s).items()}
    lights = [painting_frame_light(o, s.plane.matrix_world) for o in linked_lights(mat, scene)]
    return core_render(images, lights, settings_to_params(s)).rgba


def test_a_painting_with_no_shape_image_gets_its_silhouette_inflated(empty_scene, tmp_path):
    x, y, inside = disc()
    rgba = np.dstack([0.2 + 0.6 * (x + 0.5), np.full_like(x, 0.4), 0.8 - 0.5 * (y + 0.5),
                      inside.astype(float)])
    write_png(tmp_path / "portrait.png", rgba)
    assert bpy.ops.dynpaint.add(directory=str(tmp_path),
                                files=[{"name": "portrait.png"}]) == {"FINISHED"}
    plane = bpy.context.object
    mat = plane.active_material
    s = mat.dynamic_painting
    assert s.shape.kind == "height" and s.image_shape.packed_file is not None
    height = image_data_from_blender(s.image_shape).pixels
    assert height[..., 0].max() == pytest.approx(0.35, rel=0.03)          # a hemisphere
    assert np.array_equal(height[..., 3] > 0.5, inside)                 # the silhouette kept
    got = render_cycles(empty_scene, plane, str(tmp_path / "inflated.exr"))
    want = core_of(mat, empty_scene)
    assert np.abs(got - want)[1:-1, 1:-1].max() < 2e-3


def test_make_shape_integrates_the_normal_map_and_undo_brings_it_back(empty_scene, tmp_path):
    x, y, inside = disc()
    ball = 0.6
    z = np.sqrt(np.clip(ball ** 2 - x * x - y * y, 0, None))
    n = np.where(inside[..., None], np.dstack([x, y, z]) / ball, [0.0, 0.0, 1.0])
    write_png(tmp_path / "cap_normal.png", (n + 1) / 2, bits=16)
    write_png(tmp_path / "cap_dark.png", np.full((SIZE, SIZE, 3), 0.1))
    write_png(tmp_path / "cap_bright.png", np.full((SIZE, SIZE, 3), 0.9))
    assert bpy.ops.dynpaint.add(directory=str(tmp_path), files=[
        {"name": f"cap_{c}.png"} for c in ("normal", "dark", "bright")]) == {"FINISHED"}
    plane = bpy.context.object
    mat = plane.active_material
    name, old = mat.name, mat.dynamic_painting.image_shape.name
    bpy.ops.ed.undo_push(message="painting")
    assert bpy.ops.dynpaint.make_shape(method="integrate") == {"FINISHED"}
    bpy.ops.ed.undo_push(message="make shape")
    s = mat.dynamic_painting
    assert s.shape.kind == "height" and s.shape.height_scale == pytest.approx(1.0)
    h = image_data_from_blender(s.image_shape).pixels[..., 0]
    cap = np.where(inside, z - np.sqrt(ball ** 2 - 0.35 ** 2), 0)
    assert np.abs((h - h[0, 0]) - cap).max() < 0.03 * cap.max()
    got = render_cycles(empty_scene, plane, str(tmp_path / "integrated.exr"))
    assert np.abs(got - core_of(mat, empty_scene))[1:-1, 1:-1].max() < 2e-3
    made = s.image_shape.name
    bpy.ops.ed.undo()
    s = bpy.data.materials[name].dynamic_painting
    assert s.shape.kind == "normal" and s.image_shape.name == old
    assert made not in bpy.data.images


def test_make_shape_reports_what_it_cannot_do(empty_scene, tmp_path):
    write_png(tmp_path / "flat_height.png", np.full((16, 16), 0.5), bits=16)
    write_png(tmp_path / "flat_dark.png", np.full((16, 16, 3), 0.2))
    assert bpy.ops.dynpaint.add(directory=str(tmp_path), files=[
        {"name": f"flat_{c}.png"} for c in ("height", "dark")]) == {"FINISHED"}
    s = bpy.context.object.active_material.dynamic_painting
    with pytest.raises(RuntimeError, match="no silhouette to inflate"):
        bpy.ops.dynpaint.make_shape(method="inflate")
    with pytest.raises(RuntimeError, match="needs a normal map"):
        bpy.ops.dynpaint.make_shape(method="integrate")
    assert s.shape.kind == "height"
    assert bpy.ops.dynpaint.make_shape(method="normals") == {"FINISHED"}
    assert s.shape.kind == "normal"


def test_make_shape_from_lighting_profiles_and_a_red_green_photo(empty_scene, tmp_path):
    """Sprite Lamp's names: the left profile is given, the others beside it are found; the
    red/green photograph decodes to the same normals."""
    x, y, inside = disc()
    z = np.sqrt(np.clip(0.6 ** 2 - x * x - y * y, 0, None))
    n = np.dstack([x, y, z]) / 0.6
    write_png(tmp_path / "ball_dark.png", np.full((SIZE, SIZE, 3), 0.1))
    write_png(tmp_path / "ball_bright.png", np.full((SIZE, SIZE, 3), 0.9))
    write_png(tmp_path / "ball_height.png", np.full((SIZE, SIZE), 0.5), bits=16)
    e = np.radians(45)
    for side, light in {"left": (-np.cos(e), 0, np.sin(e)), "right": (np.cos(e), 0, np.sin(e)),
                        "top": (0, np.cos(e), np.sin(e)),
                        "bottom": (0, -np.cos(e), np.sin(e))}.items():
        write_exr(tmp_path / f"lit_{side}.exr", np.clip(n @ np.array(light), 0, None))
    write_png(tmp_path / "photo.png", (n + 1) / 2, bits=16)
    assert bpy.ops.dynpaint.add(directory=str(tmp_path), files=[
        {"name": f"ball_{c}.png"} for c in ("height", "dark", "bright")]) == {"FINISHED"}
    s = bpy.context.object.active_material.dynamic_painting
    for method, kw in (("profiles", {"profile_left": str(tmp_path / "lit_left.exr")}),
                       ("rg_photo", {"photo": str(tmp_path / "photo.png")})):
        assert bpy.ops.dynpaint.make_shape(method=method, **kw) == {"FINISHED"}
        assert s.shape.kind == "normal"
        got = image_data_from_blender(s.image_shape).pixels[..., :3] * 2 - 1
        angle = np.degrees(np.arccos(np.clip(np.sum(got * n, -1), -1, 1)))
        assert angle.mean() < 0.5, (method, angle.mean())


def test_a_lone_opaque_painting_is_refused_with_what_to_do_and_nothing_is_made(empty_scene,
                                                                              tmp_path):
    write_png(tmp_path / "opaque.png", np.full((SIZE, SIZE, 3), 0.5))
    objects, images = set(bpy.data.objects), set(bpy.data.images)
    with pytest.raises(RuntimeError, match="no silhouette to inflate"):
        bpy.ops.dynpaint.add(directory=str(tmp_path), files=[{"name": "opaque.png"}])
    assert set(bpy.data.objects) == objects and set(bpy.data.images) == images


def test_the_operator_is_generated_from_the_one_table():
    """Make Shape's properties are shapes.methods.OPTIONS' add-on rows (issue 28), with the
    table's defaults and ranges; its menu holds the methods that make a shape."""
    from dynpaint_addon import blender
    from dynpaint_addon.shapes.methods import METHODS, OPTIONS
    blender.register_once()
    props = bpy.ops.dynpaint.make_shape.get_rna_type().properties
    addon = [o for o in OPTIONS if o.where != "cli"]
    assert {p.identifier for p in props} - {"rna_type"} == {"method"} | {o.name for o in addon}
    for o in addon:
        prop = props[o.name]
        if o.kind is float:
            assert (prop.default, prop.hard_min, prop.hard_max) == pytest.approx(
                (o.default, o.min, o.max)), o.name
    assert [i.identifier for i in props["method"].enum_items] == [
        k for k, m in METHODS.items() if m.make]
