"""The add-on from an artist's side, headless: Add › Dynamic Painting, live and structural
settings, lights coming and going, looks, bake, recipe export/import (issue 3)."""
import os
from types import SimpleNamespace

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon import blender, params  # noqa: E402
from dynpaint_addon.blender import handlers  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import FACE_CAMERA  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import channel_images, settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.blender.material.sync import update  # noqa: E402
from dynpaint_addon.blender.nodes.shader_backend import IMAGE_SIZE_NODES  # noqa: E402
from dynpaint_addon.inputs.imageio import read_image, write_png  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe  # noqa: E402
from dynpaint_addon.inputs.testpainting import write_test_painting  # noqa: E402

from parity_recipes import write_images  # noqa: E402
from testkit.scene_picture import render_cycles  # noqa: E402


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("addon"))
    write_images(folder)
    return folder


def add(folder, *names, **kw):
    return bpy.ops.dynpaint.add(directory=folder, files=[{"name": n} for n in names], **kw)


def core_of(mat, scene):
    """The numpy core's render of the painting as the scene has it now."""
    s = mat.dynamic_painting
    images = {c: read_image(bpy.path.abspath(img.filepath))
              for c, img in channel_images(s).items()}
    lights = [painting_frame_light(o, s.plane.matrix_world) for o in linked_lights(mat, scene)]
    return core_render(images, lights, settings_to_params(s)).rgba


def test_add_from_images_makes_a_lit_plane_with_the_image_aspect(empty_scene, folder):
    assert add(folder, "normal.png", "dark.png", "bright.png", size=2.0) == {"FINISHED"}
    plane = bpy.context.object
    mat = plane.active_material
    s = mat.dynamic_painting
    assert s.is_painting and s.shape.kind == "normal"
    xs = [v.co.x for v in plane.data.vertices]
    ys = [v.co.y for v in plane.data.vertices]
    assert (max(ys) - min(ys)) / (max(xs) - min(xs)) == pytest.approx(30 / 40)
    assert tuple(plane.scale) == pytest.approx((2.0, 2.0, 2.0))
    # no light in the scene: a Sun was added and shades the painting
    assert [i.object.data.type for i in s.lights] == ["SUN"]
    assert any(n.bl_idname == "ShaderNodeVectorTransform" for n in mat.node_tree.nodes)


def test_height_map_detected_and_camera_faced(empty_scene, folder):
    cam = bpy.data.objects.new("Cam", bpy.data.cameras.new("Cam"))
    empty_scene.collection.objects.link(cam)
    empty_scene.camera = cam
    assert add(folder, "height16.png", "dark.png", "bright.png") == {"FINISHED"}
    plane = bpy.context.object
    assert plane.active_material.dynamic_painting.shape.kind == "height"
    con = plane.constraints[FACE_CAMERA]
    assert con.type == "COPY_ROTATION" and con.target == cam


def test_bad_input_is_refused_and_the_scene_is_unchanged(empty_scene, folder):
    with open(os.path.join(folder, "notes.txt"), "w") as fh:
        fh.write("hello")
    before = (len(bpy.data.objects), len(bpy.data.materials), len(bpy.data.meshes))
    for files in (["notes.txt", "dark.png"], ["dark.png"], ["missing_normal.png", "dark.png"]):
        with pytest.raises(RuntimeError) as err:
            add(folder, *files)
        assert "Error" in str(err.value)
        assert (len(bpy.data.objects), len(bpy.data.materials), len(bpy.data.meshes)) == before


def test_live_value_changes_rebuild_nothing_and_render_right(empty_scene, folder, tmp_path):
    add(folder, "normal.png", "dark.png", "bright.png")
    plane = bpy.context.object
    mat = plane.active_material
    s = mat.dynamic_painting
    tree_nodes = [n.name for n in mat.node_tree.nodes]
    s.diffuse.t0, s.diffuse.t1, s.diffuse.curve = 0.2, 0.7, "smoothstep"   # curve: structural
    assert [n.name for n in mat.node_tree.nodes] == tree_nodes     # groups differ, not the tree
    signature = s.signature
    s.diffuse.t0 = 0.35
    assert s.signature == signature
    got = render_cycles(empty_scene, plane, str(tmp_path / "a.exr"))
    want = core_of(mat, empty_scene)
    assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-3
    s.specular.enabled = True
    assert s.signature != signature and len(mat.node_tree.nodes) > len(tree_nodes)


def test_images_of_another_size_keep_the_tree_and_render_right(empty_scene, folder, tmp_path):
    """A painting's images made anew at another size (a lit drawing drawn past its bounds,
    issue 61) keep its node tree — the size is a value set in place (ShaderBackend.size), not
    a rebuild (20–30 ms of Blender's main thread at 512²) — and it renders as the core at the
    new size (a height map: its texel steps and slope scale are of the size)."""
    add(folder, "height16.png", "dark.png", "bright.png")
    plane = bpy.context.object
    mat = plane.active_material
    nodes = [n.as_pointer() for n in mat.node_tree.nodes]
    for img in channel_images(mat.dynamic_painting).values():
        data = read_image(bpy.path.abspath(img.filepath))
        path = str(tmp_path / os.path.basename(img.filepath))
        write_png(path, data.pixels[3:27, 4:36], data.bits)         # 40×30 → 32×24
        img.filepath = path
        img.reload()
    update(mat, empty_scene)                           # (as the lit drawing's reframe does)
    assert [n.as_pointer() for n in mat.node_tree.nodes] == nodes
    assert [mat.node_tree.nodes[name].outputs[0].default_value
            for name in IMAGE_SIZE_NODES] == [32.0, 24.0]
    got = render_cycles(empty_scene, plane, str(tmp_path / "a.exr"))
    want = core_of(mat, empty_scene)
    assert got.shape[:2] == (24, 32) and np.abs(got - want)[1:-1, 1:-1].max() <= 1e-3


def test_keyframed_parameter_animates(empty_scene, folder, tmp_path):
    add(folder, "normal.png", "dark.png", "bright.png")
    plane = bpy.context.object
    mat = plane.active_material
    s = mat.dynamic_painting
    for frame, t0 in ((1, -0.8), (11, 0.6)):
        s.diffuse.t0 = t0
        s.diffuse.keyframe_insert("t0", frame=frame)
    empty_scene.frame_set(6)
    assert s.diffuse.t0 == pytest.approx(-0.1, abs=0.05)
    got = render_cycles(empty_scene, plane, str(tmp_path / "k.exr"))
    want = core_of(mat, empty_scene)
    assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-3


def test_lights_added_deleted_and_collections(empty_scene, folder):
    add(folder, "normal.png", "dark.png", "bright.png")
    mat = bpy.context.object.active_material
    s = mat.dynamic_painting
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    empty_scene.collection.objects.link(lamp)
    bpy.context.view_layer.update()
    assert [i.object.name for i in s.lights] == ["Lamp", "Sun"]
    lamp.data.type = "SUN"          # a light changing kind rebuilds its branch
    bpy.context.view_layer.update()
    assert [i.kind for i in s.lights] == ["SUN", "SUN"]
    bpy.data.objects.remove(lamp)
    bpy.context.view_layer.update()
    assert [i.object.name for i in s.lights] == ["Sun"]
    # only the lights of a chosen collection
    coll = bpy.data.collections.new("Key lights")
    empty_scene.collection.children.link(coll)
    s.light_collection = coll
    assert list(s.lights) == []
    drivers = mat.node_tree.animation_data.drivers if mat.node_tree.animation_data else []
    assert all(d.driver.is_valid for d in drivers)


def test_many_paintings_cost_each_add_alike(empty_scene, tmp_path, monkeypatch):
    """Paintings added from one recipe (issue 60): each is lit by its recipe's own lights (a
    collection of their own), and adding one more brings no other painting up to date — the
    n-th Add re-lit all n with every light before (benchmarks/many_paintings.py times it)."""
    recipe = write_test_painting(str(tmp_path / "small"), 32)
    for _ in range(3):
        assert bpy.ops.dynpaint.add(filepath=recipe) == {"FINISHED"}
    mats = [m for m in bpy.data.materials if m.dynamic_painting.is_painting]
    assert len(mats) == 3 and len(bpy.data.lights) == 6
    for mat in mats:
        own = mat.dynamic_painting.light_collection
        assert own is not None and {o.name for o in linked_lights(mat, empty_scene)} == \
            {o.name for o in own.objects} and len(own.objects) == 2
    updated = []
    real = handlers.update
    monkeypatch.setattr(handlers, "update", lambda mat, *a, **k: (updated.append(mat.name),
                                                                   real(mat, *a, **k))[1])
    assert bpy.ops.dynpaint.add(filepath=recipe) == {"FINISHED"}
    new = bpy.context.object.active_material.name
    assert set(updated) <= {new}, updated           # the three others: untouched
    updated.clear()
    mats[0].dynamic_painting.light_collection.objects[0].location.x += 0.5
    bpy.context.view_layer.update()                 # one painting's light moved: that one
    assert set(updated) == {mats[0].name}, updated
    # a light added to the scene lights a painting lit by every light, not the recipes'
    mats[1].dynamic_painting.light_collection = None
    updated.clear()
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    empty_scene.collection.objects.link(lamp)
    bpy.context.view_layer.update()
    assert set(updated) == {mats[1].name}, updated
    assert "Lamp" in [o.name for o in linked_lights(mats[1], empty_scene)]
    # a light taken out of a collection inside a painting's Lights: that painting
    inner = bpy.data.collections.new("Inner")
    mats[2].dynamic_painting.light_collection.children.link(inner)
    rim = bpy.data.objects.new("Rim", bpy.data.lights.new("Rim", "SUN"))
    inner.objects.link(rim)
    bpy.context.view_layer.update()
    assert "Rim" in [o.name for o in linked_lights(mats[2], empty_scene)]
    updated.clear()
    inner.objects.unlink(rim)
    bpy.context.view_layer.update()
    assert mats[2].name in updated, updated
    assert "Rim" not in [i.object.name for i in mats[2].dynamic_painting.lights if i.object]


def test_the_sun_add_makes_turns_as_scripts_turn_it(empty_scene, folder):
    """Issue 61: the Sun was turned by quaternion, so setting rotation_euler (what scripts,
    drivers and Blender's new objects use) changed nothing. It is aimed in Euler XYZ now."""
    add(folder, "normal.png", "dark.png", "bright.png")
    mat = bpy.context.object.active_material
    sun = linked_lights(mat, empty_scene)[0]
    assert sun.rotation_mode == "XYZ"
    before = painting_frame_light(sun, mat.dynamic_painting.plane.matrix_world).vector
    sun.rotation_euler = (0.0, 0.0, 0.0)            # straight down the painting's normal
    bpy.context.view_layer.update()
    after = painting_frame_light(sun, mat.dynamic_painting.plane.matrix_world).vector
    assert np.abs(np.subtract(after, before)).max() > 0.1
    assert abs(abs(after[2]) - 1) < 1e-6, after


def test_looks_and_bake(empty_scene, folder):
    add(folder, "height16.png", "dark.png", "bright.png")
    mat = bpy.context.object.active_material
    s = mat.dynamic_painting
    assert bpy.ops.dynpaint.apply_look(look="CARTOON") == {"FINISHED"}
    assert s.diffuse.t0 == s.diffuse.t1 and s.specular.enabled
    assert s.shadows.enabled           # a painting added with a shape casts shadows (issue 59)
    s.shadows.enabled = False
    assert bpy.ops.dynpaint.bake_shadows() == {"CANCELLED"}     # shadows are off
    s.shadows.enabled = True
    shadow = s.lights[0].shadow
    assert shadow is not None and tuple(shadow.size) == (40, 30)
    assert bpy.ops.dynpaint.bake_shadows() == {"FINISHED"}


def test_recipe_round_trip_through_the_addon(empty_scene, folder, tmp_path):
    add(folder, "normal.png", "dark.png", "bright.png")
    plane = bpy.context.object
    mat = plane.active_material
    s = mat.dynamic_painting
    s.diffuse.t0, s.refraction.ior, s.specular.enabled = -0.25, 1.7, True
    out = str(tmp_path / "exported" / "painting.toml")
    assert bpy.ops.dynpaint.export_recipe(filepath=out) == {"FINISHED"}
    recipe = load_recipe(out)
    assert recipe.params.diffuse.t0 == -0.25 and recipe.params.refraction.ior == 1.7
    assert recipe.params.specular.enabled is True
    assert [lt.kind for lt in recipe.lights] == ["sun"]
    # the exported recipe renders in numpy like the scene renders in Cycles
    got = render_cycles(empty_scene, plane, str(tmp_path / "scene.exr"))
    want = core_render(load_images(recipe), recipe.lights, recipe.params).rgba
    assert np.abs(got - want)[1:-1, 1:-1].max() <= 1e-3
    # and imports back as a new painting with the same settings
    assert bpy.ops.dynpaint.import_recipe(filepath=out) == {"FINISHED"}
    again = bpy.context.object.active_material.dynamic_painting
    assert again.diffuse.t0 == pytest.approx(-0.25) and again.specular.enabled


def test_register_unregister_leaves_nothing_behind():
    blender.register_once()
    for _ in range(3):
        blender.unregister()
        assert not hasattr(bpy.types.Material, "dynamic_painting")
        names = [h.__name__ for h in bpy.app.handlers.depsgraph_update_post
                 + bpy.app.handlers.frame_change_post]
        assert "on_frame_change" not in names and "on_depsgraph_update" not in names
        blender.register()
    assert hasattr(bpy.types, "DYNPAINT_PT_view3d_main")
    assert hasattr(bpy.types, "DYNPAINT_OT_add") or hasattr(bpy.ops.dynpaint, "add")


def test_every_driver_runs_without_python_auto_run(empty_scene, folder):
    """Drivers are native (SUM/AVERAGE) or simple expressions: files opened without
    auto-run still animate (blender-notes.md)."""
    assert add(folder, "normal.png", "dark.png", "bright.png") == {"FINISHED"}
    lamp = bpy.data.objects.new("Lamp", bpy.data.lights.new("Lamp", "POINT"))
    empty_scene.collection.objects.link(lamp)
    bpy.context.view_layer.update()
    mat = bpy.context.object.active_material
    drivers = list(mat.node_tree.animation_data.drivers)
    assert len(drivers) > 10
    for fc in drivers:
        d = fc.driver
        assert d.is_valid, fc.data_path
        assert d.type != "SCRIPTED" or d.is_simple_expression, (fc.data_path, d.expression)


def test_static_lights_bake_once_per_animation(empty_scene, folder):
    add(folder, "height16.png", "dark.png", "bright.png")
    s = bpy.context.object.active_material.dynamic_painting
    s.shadows.enabled = True
    before = s.lights[0].bake_key
    assert before
    empty_scene.frame_set(7)      # nothing moved: the frame handler skips the bake
    assert s.lights[0].bake_key == before
    sun = s.lights[0].object
    sun.rotation_mode = "XYZ"
    sun.rotation_euler = (0.3, 0.4, 0.5)
    sun.keyframe_insert("rotation_euler", frame=8)
    empty_scene.frame_set(8)
    assert s.lights[0].bake_key != before


class RecordingLayout:
    """Stands in for Blender's UI layout, which background mode does not have: records every
    property and operator a panel draws and checks that each one exists."""

    def __init__(self, log):
        self.log = log
        self.enabled = self.active = True
        self.use_property_split = self.use_property_decorate = False

    def _sub(self, *args, **kw):
        return RecordingLayout(self.log)
    row = column = box = split = _sub

    def label(self, **kw):
        self.log.append(("label", kw.get("text", "")))

    def prop(self, data, name, **kw):
        assert name in data.bl_rna.properties, f"{data} has no property {name}"
        self.log.append(("prop", name))

    def operator(self, idname, **kw):
        module, op = idname.split(".")
        assert hasattr(getattr(bpy.ops, module), op), idname
        self.log.append(("operator", idname))
        return type("OpProps", (), {})()

    def operator_menu_enum(self, idname, prop, **kw):
        self.operator(idname)

    def separator(self, **kw):
        pass


def test_every_panel_draws_existing_properties_and_operators(empty_scene, folder):
    add(folder, "height16.png", "dark.png", "bright.png")
    s = bpy.context.object.active_material.dynamic_painting
    for p in params.PARAMS:      # open what other settings hide (the falloff's radius, …)
        if p.shown_if and p.shown_if[0] != "shape.kind":
            section, key = p.shown_if[0].split(".")
            setattr(getattr(s, section), key, p.shown_if[1])
    panels = [c for c in blender.panels.CLASSES]
    log = []
    for cls in panels:
        assert cls.poll(bpy.context)
        panel = SimpleNamespace(layout=RecordingLayout(log))
        for method in ("draw_header", "draw"):
            if hasattr(cls, method):
                getattr(cls, method)(panel, bpy.context)
    drawn = {name for kind, name in log if kind == "prop"}
    height_params = {p.key for p in params.PARAMS                 # a height map: no normal-only
                     if p.shown_if != ("shape.kind", "normal")}
    assert height_params <= drawn, height_params - drawn
    assert {"dynpaint.bake_shadows", "dynpaint.image_open", "dynpaint.apply_look",
            "dynpaint.add_light_turntable", "dynpaint.add", "dynpaint.add_sample"} <= \
        {name for kind, name in log if kind == "operator"}


def test_add_from_images_named_as_other_tools_name_them(empty_scene, folder, tmp_path):
    """Issue 15, point 3: 'diffuse', 'alpha', 'nrm' … land in their channels; a file named
    after none of them is reported, never taken as the dark image; the painting takes the
    images' common name."""
    import shutil
    picked = {"Eye_nrm.png": "normal.png", "Eye_diffuse.png": "bright.png",
              "Eye_alpha.png": "transparency.png", "Eye_trees.png": "bg.png"}
    for name, source in picked.items():
        shutil.copy(os.path.join(folder, source), tmp_path / name)
    assert add(str(tmp_path), *picked) == {"FINISHED"}
    s = bpy.context.object.active_material.dynamic_painting
    assert s.image_shape.name == "Eye_nrm.png" and s.image_bright.name == "Eye_diffuse.png"
    assert s.image_transparency.name == "Eye_alpha.png"
    assert s.image_dark is None and s.image_background is None     # trees: not guessed
    assert bpy.context.object.name == "Eye"


def test_the_proposed_channels_can_be_changed_before_the_painting_is_made(empty_scene, folder,
                                                                          tmp_path):
    """The confirm dialog's operator (with a UI it opens after the file browser): each file
    with the channel proposed for it, changed by the artist; one image per channel."""
    import shutil
    for name, source in {"a_nrm.png": "normal.png", "a_diffuse.png": "bright.png",
                         "a_trees.png": "bg.png"}.items():
        shutil.copy(os.path.join(folder, source), tmp_path / name)
    choose = [{"name": "a_nrm.png", "channel": "shape"},
              {"name": "a_diffuse.png", "channel": "bright"},
              {"name": "a_trees.png", "channel": "bright"}]
    with pytest.raises(RuntimeError, match="bright is chosen twice"):
        bpy.ops.dynpaint.add_images(directory=str(tmp_path), choices=choose)
    assert not bpy.data.materials
    choose[2]["channel"] = "background"                   # trees: the artist knows better
    assert bpy.ops.dynpaint.add_images(directory=str(tmp_path), choices=choose) == {"FINISHED"}
    s = bpy.context.object.active_material.dynamic_painting
    assert s.image_background.name == "a_trees.png" and s.image_bright.name == "a_diffuse.png"
    assert bpy.context.object.name == "a"
