"""Editing a painting as an artist does (issue 14): whatever order settings, lights and images
change in — dragged through the properties, moved, swapped, undone — the material is what a
fresh build for the same settings gives (node tree, drivers, derived and shadow images), and
it renders (Cycles) like the numpy core."""
import hashlib
import os
import sys

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon import params  # noqa: E402
from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.blender.bake import shadow_images  # noqa: E402
from dynpaint_addon.blender.material.sync import update  # noqa: E402
from dynpaint_addon.blender.scenes.painting_scene import exact_render_settings, output_settings  # noqa: E402
from dynpaint_addon.blender.state import images, status  # noqa: E402
from dynpaint_addon.blender.state.images import grey_image, load_image  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import channel_images, settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender, read_image  # noqa: E402
from dynpaint_addon.nodegraph import derived_inputs  # noqa: E402
from dynpaint_addon.nodegraph.derived_inputs import grey_rgba  # noqa: E402
from dynpaint_addon.inputs.recipe import Recipe  # noqa: E402
from testkit.sun_painting import image_pixels, sun_painting  # noqa: E402

from conftest import REPO  # noqa: E402
from parity_recipes import SUN, write_images  # noqa: E402

sys.path.insert(0, os.path.join(REPO, "benchmarks"))
import paint_latency  # noqa: E402

NODE_ATTRS = ("operation", "data_type", "interpolation_type", "clamp", "use_clamp", "factor_mode",
              "clamp_factor", "blend_type", "vector_type", "convert_from", "convert_to", "target",
              "interpolation", "extension", "label", "mode")


@pytest.fixture(scope="module")
def paths(tmp_path_factory):
    return write_images(str(tmp_path_factory.mktemp("edits")))


def _pixels_hash(img):
    px = np.empty(len(img.pixels), np.float32)
    img.pixels.foreach_get(px)
    return hashlib.sha1(px.tobytes()).hexdigest()


def _value(v):
    if hasattr(v, "__len__") and not isinstance(v, str):
        return tuple(round(float(x), 6) for x in v)
    return round(v, 6) if isinstance(v, float) else v


def state(mat):
    """Everything a build makes: nodes (kind, settings, unlinked inputs, images and their
    pixels), links, drivers, the shadow images and the render method."""
    tree = mat.node_tree
    driven = {d.data_path for d in (tree.animation_data.drivers if tree.animation_data else ())}
    nodes = []
    for n in sorted(tree.nodes, key=lambda n: n.name):
        attrs = tuple((a, _value(getattr(n, a))) for a in NODE_ATTRS if hasattr(n, a))
        image = getattr(n, "image", None)
        group = getattr(n, "node_tree", None)
        inputs = tuple((s.identifier, _value(s.default_value)) for s in n.inputs
                       if not s.is_linked and hasattr(s, "default_value")
                       and s.path_from_id("default_value") not in driven)   # drivers: below
        nodes.append((n.name, n.bl_idname, attrs, inputs, group.name if group else None,
                      (image.name, _pixels_hash(image)) if image else None))
    links = sorted((ln.from_node.name, ln.from_socket.identifier, ln.to_node.name,
                    ln.to_socket.identifier) for ln in tree.links)
    drivers = sorted(
        (d.data_path, d.array_index, d.driver.type, d.driver.expression,
         tuple((v.name, v.type, tuple((t.id.name if t.id else None, t.data_path, t.transform_type)
                                      for t in v.targets)) for v in d.driver.variables))
        for d in (tree.animation_data.drivers if tree.animation_data else ()))
    s = mat.dynamic_painting
    shadows = [(i.object.name, i.bake_key, _pixels_hash(i.shadow) if i.shadow else None)
               for i in s.lights]
    return nodes, links, drivers, shadows, mat.surface_render_method


def assert_fresh(mat, scene, what, built=None):
    """The painting as the edits left it equals a fresh build for its current settings.
    built: {settings: state} of the fresh builds made so far for the same images and lights
    (a fresh build is made from those alone: a drag's every step back to the default is
    compared with the default's one build, not built again)."""
    assert status.LAST_ERRORS == [], f"{what}: {status.LAST_ERRORS}"
    before = state(mat)
    key = _settings(mat) if built is not None else None
    if key in (built or {}):
        after = built[key]
    else:
        update(mat, scene, force=True)            # remake every image, bake and rebuild
        after = state(mat)
        if built is not None:
            built[key] = after
    for part, b, a in zip(("nodes", "links", "drivers", "shadows", "render method"),
                          before, after):
        assert b == a, f"after {what}: the {part} differ from a fresh build"


def _settings(mat):
    """Every setting's value, as the core reads them (a key for assert_fresh)."""
    p = settings_to_params(mat.dynamic_painting)
    return repr([(prm.path, getattr(getattr(p, prm.section), prm.key)) for prm in params.PARAMS])


def renders_like_the_core(mat, scene, tmp_path, what):
    s = mat.dynamic_painting
    out = str(tmp_path / "edit.exr")
    output_settings(scene, out)
    bpy.ops.render.render(write_still=True)
    got = read_image(out).pixels
    images = {c: read_image(bpy.path.abspath(img.filepath))
              for c, img in channel_images(s).items()}
    lights = [painting_frame_light(o, s.plane.matrix_world) for o in linked_lights(mat, scene)]
    want = core_render(images, lights, settings_to_params(s)).rgba
    err = float(np.abs(got - want)[1:-1, 1:-1].max())
    assert err <= 1e-3, f"after {what}: Cycles is {err:.2e} from the core"


def painting(paths, kind="normal", without=(), **settings):
    """A painting with every channel (but those `without`), shadows and highlights on, framed
    for exact renders."""
    p = params.defaults()
    p.shape.kind = kind
    p.shadows.enabled = p.specular.enabled = True
    p.transparency.amount = 0.5
    for path, value in settings.items():
        section, key = path.split("__")
        setattr(getattr(p, section), key, value)
    shape = "normal_alpha" if kind == "normal" else "height16"
    images = {"shape": shape, "dark": "dark", "bright": "bright", "specular_color": "spec",
              "gloss": "gloss", "transparency": "transparency", "environment": "env",
              "background": "bg"}
    recipe = Recipe(p, [SUN], {c: paths[i] for c, i in images.items() if c not in without},
                    "Edited")
    plane, mat = headless.build_recipe_scene(recipe)
    scene = bpy.context.scene
    exact_render_settings(scene, "cycles")
    status.LAST_ERRORS.clear()
    return mat, scene


def _set(s, param, value):
    group = getattr(s, param.section)
    if param.kind == "auto_float":
        if value == "auto":
            setattr(group, param.key + "_auto", True)
            return
        setattr(group, param.key + "_auto", False)
    setattr(group, param.key, value)


def test_transparency_amount_from_zero_rebuilds_the_tree(paths):
    """The bug: Transparency › Amount 0 → 0.5 must bring the reflection/refraction branch in
    (the hand list of structural settings missed it). Without a transparency map, an amount
    of 0 prunes the branch; any other amount needs it."""
    mat, scene = painting(paths, without=("transparency",), transparency__amount=0.0)
    groups = lambda: {n.node_tree.name for n in mat.node_tree.nodes  # noqa: E731
                      if n.bl_idname == "ShaderNodeGroup"}
    assert not any("Refraction" in g for g in groups())
    mat.dynamic_painting.transparency.amount = 0.5          # dragged in the panel
    assert any("Refraction" in g for g in groups()) and any("Reflection" in g for g in groups())
    assert_fresh(mat, scene, "Transparency › Amount 0 → 0.5")


def _drag_values(param):
    if param.kind is bool:
        return [not param.default, param.default]
    if param.kind == "enum":
        return [c for c in param.choices if c != param.default] + [param.default]
    if param.kind is int:
        return [0, 1, 8, param.default]
    values = [float(v) for v in np.linspace(param.min, param.max, 4)]
    if param.kind == "vec2":
        return [(x, y) for x, y in zip(values, values[::-1])] + [param.default]
    if param.kind == "auto_float":
        return values + ["auto"]
    return values + [param.default]


@pytest.mark.parametrize("kind", ["normal", "height"])
def test_every_parameter_dragged_through_its_range_keeps_a_fresh_material(paths, kind):
    """Each parameter, through the property an artist drags, from its minimum to its maximum
    (each choice of a menu): after every step the material equals a fresh build."""
    mat, scene = painting(paths, kind)
    s, built = mat.dynamic_painting, {}
    for param in params.PARAMS:
        if param.path == "shape.kind":
            continue          # the other test's painting (a height image is no normal map)
        for value in _drag_values(param):
            _set(s, param, value)
            assert_fresh(mat, scene, f"{param.path} = {value!r}", built)
    assert len(built) < 200        # the default's fresh build made once (215 steps)


IMAGE_CHOICES = {
    "dark": ["dark", "dark_alpha"], "bright": ["bright", "white"],
    "specular_color": ["spec", None], "gloss": ["gloss", None],
    "transparency": ["transparency", None], "environment": ["env", None],
    "background": ["bg", "bg.exr", None],
}
SHAPES = {"normal": ["normal", "normal_alpha", "normal_opaque_alpha"],
          "height": ["height16", "height8", "height.exr"]}
EDITABLE = [p for p in params.PARAMS if p.path not in ("shape.kind", "shadows.source")]


def _random_value(rng, param):
    if param.kind is bool:
        return bool(rng.integers(2))
    if param.kind == "enum":
        return param.choices[rng.integers(len(param.choices))]
    if param.kind is int:
        return int(rng.choice([0, 1, 8, 64]))
    if param.kind == "vec2":
        return tuple(float(rng.uniform(param.min, param.max)) for _ in range(2))
    value = float(rng.choice([param.min, param.max, rng.uniform(param.min, param.max)]))
    return "auto" if param.kind == "auto_float" and rng.random() < 0.3 else value


def test_a_random_edit_sequence_keeps_the_material_fresh_and_like_the_core(paths, tmp_path):
    """A few hundred edits in random order, as a state machine: a setting changed, a light
    moved, a point light added or deleted, an image swapped, removed or added back, the shape
    swapped for one of the other kind, undo and redo. After every step the material equals a
    fresh build and Cycles renders what the core renders."""
    rng = np.random.default_rng(14)
    mat, scene = painting(paths)
    name = mat.name
    bpy.ops.ed.undo_push(message="start")
    done, undone = 0, 0          # edits that undo can take back, and redo bring again
    history = []
    for step in range(200):
        mat, scene = bpy.data.materials[name], bpy.context.scene
        s = mat.dynamic_painting
        action = rng.choice(["setting"] * 10 + ["move"] * 4 + ["point"] + ["image"] * 3
                            + ["shape"] + ["undo"] * 2 + ["redo"])
        if action == "setting":
            param = EDITABLE[rng.integers(len(EDITABLE))]
            value = _random_value(rng, param)
            _set(s, param, value)
            what = f"{param.path} = {value!r}"
        elif action == "move":
            light = linked_lights(mat, scene)[rng.integers(len(linked_lights(mat, scene)))]
            if light.data.type == "SUN":
                light.rotation_mode = "XYZ"
                light.rotation_euler = tuple(rng.uniform(-1.4, 1.4, 3))
            else:
                light.location = tuple(rng.uniform(-1, 1, 3) * [1, 1, 0.5] + [0, 0, 0.05])
            # Without a UI a moved light bakes when the frame is set (a render, or a script's
            # frame_set); in the UI the live bake does it (test_live_bake.py).
            scene.frame_set(scene.frame_current)
            what = f"{light.name} moved"
        elif action == "point":
            points = [o for o in linked_lights(mat, scene) if o.data.type == "POINT"]
            if points:
                bpy.data.objects.remove(points[0])
                what = "point light deleted"
            else:
                data = bpy.data.lights.new("Point", "POINT")
                obj = bpy.data.objects.new("Point", data)
                scene.collection.objects.link(obj)
                obj.location = tuple(rng.uniform(-1, 1, 3) * [1, 1, 0.5] + [0, 0, 0.1])
                what = "point light added"
            bpy.context.view_layer.update()
        elif action == "image":
            channel = list(IMAGE_CHOICES)[rng.integers(len(IMAGE_CHOICES))]
            choice = IMAGE_CHOICES[channel][rng.integers(len(IMAGE_CHOICES[channel]))]
            setattr(s, f"image_{channel}",
                    load_image(paths[choice], channel) if choice else None)
            what = f"{channel} image → {choice}"
        elif action == "shape":
            kind = ["normal", "height"][rng.integers(2)]
            choice = SHAPES[kind][rng.integers(3)]
            s.shape.kind = kind          # for a moment a normal map read as height, or back
            s.image_shape = load_image(paths[choice], "shape")
            what = f"shape → {kind} {choice}"
        elif action == "undo" and done:
            bpy.ops.ed.undo()
            done, undone = done - 1, undone + 1
            what = "undo"
        elif action == "redo" and undone:
            bpy.ops.ed.redo()
            done, undone = done + 1, undone - 1
            what = "redo"
        else:
            continue
        if action not in ("undo", "redo"):
            bpy.ops.ed.undo_push(message=what)
            done, undone = done + 1, 0
        mat, scene = bpy.data.materials[name], bpy.context.scene
        history.append(what)
        what = f"step {step} ({what}; before: {'; '.join(history[-6:-1])})"
        assert_fresh(mat, scene, what)
        renders_like_the_core(mat, scene, tmp_path, what)


def test_one_update_reads_the_settings_once(paths):
    """A setting change, a light move and a rebake each read the painting's settings once
    (painting_state.read_state), and every part of the update (derived images, bakes, tree)
    works from that one reading (issue 28: it converted them four to eight times)."""
    from dynpaint_addon.blender.state import settings
    mat, scene = painting(paths)
    s = mat.dynamic_painting
    calls = []

    def count(frame, event, _):
        if (event == "call" and frame.f_code.co_filename == settings.__file__
                and not frame.f_code.co_name.startswith(("<", "_"))):  # not comprehensions,
            # not the helpers a reading calls for each property
            calls.append(frame.f_code.co_name)
    sun = linked_lights(mat, scene)[0]
    edits = {"a setting": lambda: setattr(s.diffuse, "t0", 0.25),
             "a light move": lambda: (sun.rotation_euler.__setitem__(0, 0.4),
                                      update(mat, scene, bake="now")),
             "a rebake": lambda: update(mat, scene, rebake=True)}
    for what, edit in edits.items():
        calls.clear()
        sys.setprofile(count)
        try:
            edit()
        finally:
            sys.setprofile(None)
        assert sorted(calls) == ["channel_images", "settings_to_params"], (what, calls)
    assert_fresh(mat, scene, "the counted edits")


@pytest.mark.parametrize("kind, channel", [("normal", "shape"), ("height", "shape"),
                                           ("normal", "environment"), ("normal", "background"),
                                           ("normal", "bright")])
def test_an_input_image_edited_in_place_is_followed(paths, kind, channel):
    """Issue 41, the headless contract: an input image's pixels edited in Blender (a box of
    them, as a stroke changes them), then `image.update_tag()` and a depsgraph evaluation:
    the painting is at once what Rebuild Material makes from the edited pixels — a shape's
    edit re-derives (a normal map's silhouette, a height map's pre-blurred heights) and
    re-bakes, an environment's or a background's re-blurs, a bright image's is shown as it
    is (before: only the last passed)."""
    mat, scene = painting(paths, kind)
    bpy.context.view_layer.update()
    before = state(mat)
    img = getattr(mat.dynamic_painting, f"image_{channel}")
    w, h = img.size
    px = np.empty(w * h * img.channels, np.float32)
    img.pixels.foreach_get(px)
    px = px.reshape(h, w, img.channels)
    y0, x0 = h // 3, w // 3
    box = px[y0:y0 + h // 4, x0:x0 + w // 4]
    if channel == "shape" and kind == "normal":       # the box's normals tipped right
        box[..., 0], box[..., 1], box[..., 2] = 0.85, 0.5, 0.85
        box[..., 3] = 0.0                                  # and cut out of the silhouette
    elif channel == "shape":                               # a bump of the heights
        box[...] = box + 0.3
    else:
        box[..., :3] = 1.0 - box[..., :3]
    img.pixels.foreach_set(px.ravel())
    img.update_tag()
    bpy.context.view_layer.update()
    edited = state(mat)
    assert edited != before, f"the {channel} edit changed nothing"
    if channel == "shape":
        assert edited[3] != before[3], "the shadows were not baked again"
    assert_fresh(mat, scene, f"a {channel} edit")
    bpy.context.view_layer.update()          # nothing more to do: no edit is seen twice
    assert state(mat) == edited


@pytest.mark.parametrize("preblur", [None, 2.0])
def test_strokes_on_a_large_height_map_bake_incrementally_and_equal_a_whole_bake(
        tmp_path, monkeypatch, preblur):
    """Issue 41, incremental: on a 512² height map under a sun (final quality bakes by
    crossings at that size), each of 12 dabs decodes and re-traces only what it changed
    (shadow_images keeps the decode before the edit, with its bakes; the derived heights
    pre-blurred σ 2 px again in the dab's box alone; at the 16-bit default, none, the graph
    samples the grey shape image itself), and the painting's cos-θ image and derived images
    after them equal a bake of the whole edited image (≤ 1e-6; the derived images exactly).
    Two of them change no pixel (the same pixels written again, as a dab clipped to what was
    there leaves them): they keep the bake they had, never bake the whole."""
    mat = sun_painting(tmp_path, 512)
    s = mat.dynamic_painting
    if preblur is not None:
        s.shape.preblur_auto = False
        s.shape.preblur = preblur
        bpy.context.view_layer.update()
    height = next(d.image for d in s.derived if d.channel == "height")
    assert (height == s.image_shape) == (preblur is None)
    img = mat.dynamic_painting.image_shape
    px = image_pixels(img)
    rng = np.random.default_rng(3)
    y, x = np.ogrid[0:512, 0:512]
    whole_bake, whole_bakes = shadow_images.shadow_term, []

    def counted_whole_bake(*args, **kwargs):     # (an exception would be reported, not seen)
        whole_bakes.append(len(whole_bakes))
        return whole_bake(*args, **kwargs)
    monkeypatch.setattr(shadow_images, "shadow_term", counted_whole_bake)
    boxed, grey_edited = [], derived_inputs.grey_edited

    def counted_grey_edited(item, data, box):
        boxed.append(item.channel)
        return grey_edited(item, data, box)
    monkeypatch.setattr(derived_inputs, "grey_edited", counted_grey_edited)
    for step in range(12):
        cy, cx = rng.integers(0, 512, 2)
        cone = np.clip(1 - np.hypot(x - cx, y - cy) / rng.integers(4, 40), 0, 1)[..., None]
        if step not in (4, 9):
            px[..., :3] = np.clip(px[..., :3] + rng.uniform(-0.2, 0.2) * cone, 0, 1)
        img.pixels.foreach_set(px.ravel())
        img.update_tag()
        bpy.context.view_layer.update()
    assert status.LAST_ERRORS == [] and whole_bakes == [], "a dab baked the whole image"
    assert boxed == (["height"] * 12 if preblur else []), "a dab pre-blurred the whole image"
    monkeypatch.setattr(shadow_images, "shadow_term", whole_bake)

    def pixels(image):
        out = np.empty(len(image.pixels), np.float32)
        image.pixels.foreach_get(out)
        return out
    shadow, derived = pixels(mat.dynamic_painting.lights[0].shadow), \
        [pixels(d.image) for d in mat.dynamic_painting.derived]
    shadow_images.forget_cached_shape(mat)
    update(mat, bpy.context.scene, rebake=True, force=True)
    assert np.abs(shadow - pixels(mat.dynamic_painting.lights[0].shadow)).max() <= 1e-6
    assert all(np.array_equal(a, pixels(d.image))
               for a, d in zip(derived, mat.dynamic_painting.derived))


def _shadow_images(mat):
    """{light's type: its cos-θ image's pixels (h, w), at the size it was written at}."""
    return {item.object.data.type: image_data_from_blender(item.shadow).pixels[..., 0]
            for item in mat.dynamic_painting.lights}


# 4096²'s final is the stroke benchmark's (docs/paint-latency.md: its whole bake with the
# point light alone takes ~23 s here); the levels a dab at 4096² goes stale in are tested
@pytest.mark.parametrize("size", [256, 512, 1024, 4096])
def test_a_dab_changes_every_lights_shadow_where_it_is_at_every_level(tmp_path, size):
    """Issue 61 (drafts that never followed the brush: 0 pixels changed at 512² draft, a
    point light's never at 1024²): under a sun and a point light, at each level a dab on the
    height map changes each light's cos-θ image where the dab is, and (below 4096²) the image
    after it is the level's bake of the whole edited image (≤ 1e-6)."""
    mat = sun_painting(tmp_path, size, ("sun", "point"), quality="draft")
    s = mat.dynamic_painting
    img = s.image_shape
    px = image_pixels(img)
    y, x = np.ogrid[0:size, 0:size]
    levels = ("draft", "preview", "final") if size < 4096 else ("draft", "preview")
    for k, level in enumerate(levels):
        s.shadows.quality = level
        bpy.context.view_layer.update()
        before = _shadow_images(mat)
        cx, cy, r = size * (0.3 + 0.2 * k), size * 0.4, size * 0.06
        px[..., :3] += 0.3 * np.clip(1 - np.hypot(x - cx, y - cy) / r, 0, 1)[..., None]
        img.pixels.foreach_set(px.ravel())
        img.update_tag()
        bpy.context.view_layer.update()
        after = _shadow_images(mat)
        for kind, t in after.items():
            h, w = t.shape          # (a draft's or preview's image: the size it baked at)
            yy, xx = np.ogrid[0:h, 0:w]
            at_dab = np.hypot((xx + 0.5) * size / w - cx, (yy + 0.5) * size / h - cy) < r
            assert np.abs(t - before[kind])[at_dab].max() > 0.01, (level, kind)
        if size < 4096:         # (4096²'s whole bakes: 8 s; the core's tests cover them)
            shadow_images.forget_cached_shape(mat)
            update(mat, bpy.context.scene, rebake=True, force=True)
            whole = _shadow_images(mat)
            assert all(np.abs(after[kind] - whole[kind]).max() <= 1e-6 for kind in after), level


def test_a_draft_is_written_at_the_size_it_baked_at_and_renders_like_the_core(tmp_path):
    """A draft's cos-θ image is the size its bake ran at (768² bakes by crossings at 96²: 64×
    fewer pixels through Blender's image API), resized in place — the nodes keep the same
    image — and Cycles' bilinear lookup of it renders what the core renders from the upsampled
    bake (≤ 1e-3); at final quality it is the painting's size again."""
    mat = sun_painting(tmp_path, 768)
    s, scene = mat.dynamic_painting, bpy.context.scene
    image = s.lights[0].shadow
    assert tuple(image.size) == (768, 768)
    exact_render_settings(scene, "cycles")
    s.shadows.quality = "draft"
    bpy.context.view_layer.update()
    assert s.lights[0].shadow == image and tuple(image.size) == (96, 96)
    renders_like_the_core(mat, scene, tmp_path, "a draft")
    s.shadows.quality = "final"
    bpy.context.view_layer.update()
    assert s.lights[0].shadow == image and tuple(image.size) == (768, 768)
    renders_like_the_core(mat, scene, tmp_path, "the final bake after a draft")


def test_the_paint_latency_benchmark_runs_and_checks_incremental_equals_whole():
    """benchmarks/paint_latency.py at a tiny size (numbers, not speed): both levels timed,
    incremental and whole (the figure mask's too), and the painting after the dabs equals a
    whole bake, lit by the sun alone and by the sun and the point light."""
    m = paint_latency.measure(128, 1)
    assert all(m[level][0] > 0 and m[level][1] > 0 for level in ("draft", "final", "mask"))
    assert m["error"] <= 1e-6
    both = paint_latency.measure(128, 1, mask=False, kinds=("sun", "point"))
    assert "mask" not in both and both["error"] <= 1e-6
    assert "sun's alone" in paint_latency.goal("final", 1024, 150.0, 60.0)


def test_a_grey_image_rewritten_where_it_changed_holds_the_whole_write(monkeypatch):
    """grey_image keeps the RGBA it wrote and fills only the box that changed (a stroke's
    cos-θ and derived images): after greys edited in boxes — with NaN, with an alpha and
    without, the image written over by something else meanwhile, its size changed and back
    (a live draft's cos-θ image and the final's: the same image resized, and the RGBA of the
    size it left kept to compare with, not made again) — the image holds grey_rgba of the
    newest, exactly."""
    made = []
    monkeypatch.setattr(images, "grey_rgba", lambda *a: made.append(1) or grey_rgba(*a))
    rng = np.random.default_rng(7)
    grey = rng.random((40, 56)).astype(np.float32)
    alpha = rng.random(grey.shape).astype(np.float32)
    name = "DP test grey written where it changed"
    first = other = None
    for step in range(12):
        grey, alpha = grey.copy(), alpha.copy()
        if step == 8:
            grey, other = rng.random((24, 32)).astype(np.float32), grey
        if step in (10, 11):                                 # the other size again
            grey, other = other, grey
        r, c = rng.integers(0, grey.shape[0]), rng.integers(0, grey.shape[1])
        if step != 5:
            grey[r:r + 9, c:c + 13] = rng.random(grey[r:r + 9, c:c + 13].shape)
        if step in (4, 5):                                   # (5: the alpha alone)
            alpha[c // 2:c // 2 + 7, r:r + 5] = rng.random(alpha[c // 2:c // 2 + 7, r:r + 5].shape)
        if step == 2:
            grey[5, 5] = np.nan
        if step == 6:
            bpy.data.images[name].pixels.foreach_set(np.zeros(40 * 56 * 4, np.float32))
        made.clear()
        img = grey_image(name, grey, alpha if 3 <= step <= 7 else None)
        first = first or img
        assert img == first and tuple(img.size) == grey.shape[::-1], step
        # made whole: new, an alpha added, a new size (and the alpha gone), back to a size
        # last written with an alpha; not when a size comes back as it was left (11)
        assert len(made) == (step in (0, 3, 8, 10)), step
        px = np.empty(len(img.pixels), np.float32)
        img.pixels.foreach_get(px)
        want = grey_rgba(grey, alpha if 3 <= step <= 7 else None)
        assert np.array_equal(px.reshape(grey.shape + (4,)), want, equal_nan=True), step
    bpy.data.images.remove(img)


def test_a_decode_a_live_bake_reads_is_copied_by_the_next_edit_and_patched_when_none_does(
        tmp_path):
    """Issue 41, copy on write: a stroke decodes into the arrays of the decode before (copying
    4096²'s took 45 ms a dab, at times 0.2–0.9 s) unless a live bake's worker holds it
    (shadow_images.held, released by the worker): then the worker's arrays stay as they were."""
    mat = sun_painting(tmp_path, 128)
    img = mat.dynamic_painting.image_shape
    px = image_pixels(img)

    def dab(depth):
        px[40:50, 60:70, :3] = np.clip(px[40:50, 60:70, :3] + depth, 0, 1)
        img.pixels.foreach_set(px.ravel())
        img.update_tag()
        bpy.context.view_layer.update()
        return shadow_images.bake_shape(mat, settings_to_params(mat.dynamic_painting))
    shape = dab(0.1)
    held = shadow_images.held(shape)
    before = [a.copy() for a in held[:2]]
    try:
        edited = dab(0.1)
        assert edited[0] is not held[0] and edited[1] is not held[1]
        assert all(np.array_equal(a, b) for a, b in zip(before, held[:2])), \
            "an edit wrote into a decode a worker reads"
    finally:
        shadow_images.released(held)
    assert not shadow_images._READING
    again = dab(-0.2)
    assert again[0] is edited[0] and again[1] is edited[1], "nothing reads it: patched"
    assert status.LAST_ERRORS == []
