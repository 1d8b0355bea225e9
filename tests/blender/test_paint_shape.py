"""Paint Shape (issue 41): the painting's shape painted in Blender in layers — a figure mask
inflated by parts and a height layer — lit as one paints. Strokes are pixels written into a
layer (Texture Paint itself needs a window); the headless contract then holds: after
`image.update_tag()` and a depsgraph evaluation the made shape and the shadows are what the
layers make, and a stroke on the height layer bakes incrementally."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from dynpaint_addon.blender.bake import shadow_images  # noqa: E402
from dynpaint_addon.blender.material import sync  # noqa: E402
from dynpaint_addon.blender.material.sync import update  # noqa: E402
from dynpaint_addon.blender.operators import paint_shape  # noqa: E402
from dynpaint_addon.blender.state import painted as painted_state, status  # noqa: E402
from dynpaint_addon.blender.state.edits import note_edited  # noqa: E402
from dynpaint_addon.blender.state.lights import linked_lights, painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import channel_images, settings_to_params  # noqa: E402
from dynpaint_addon.blender import headless  # noqa: E402
from dynpaint_addon.core.pipeline import render as core_render  # noqa: E402
from dynpaint_addon.core.pipeline import shape_normals  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender, read_image  # noqa: E402
from dynpaint_addon.shapes.maker import linear_luminance  # noqa: E402
from dynpaint_addon.inputs.recipe import load_images, load_recipe  # noqa: E402
from dynpaint_addon.shapes.painted import figure_relief, painted_height  # noqa: E402

from conftest import run_cli  # noqa: E402
from parity_recipes import make_recipe, write_images  # noqa: E402
from testkit.sun_painting import image_pixels, sun_painting  # noqa: E402


def painting(folder, size):
    mat = sun_painting(folder, size)
    status.LAST_ERRORS.clear()
    return mat


def pixels(img):
    return image_data_from_blender(img).pixels


def shadow(mat):
    return pixels(mat.dynamic_painting.lights[0].shadow)[..., 0]


def paint(img, fn):
    """A stroke: the layer's pixels changed by fn(rgba), then the Image update a script sends."""
    px = image_pixels(img)
    fn(px)
    img.pixels.foreach_set(px.ravel())
    img.update_tag()
    bpy.context.view_layer.update()


def disc(cx, cy, r, value):
    def fn(px):
        h, w = px.shape[:2]
        y, x = np.ogrid[0:h, 0:w]
        px[np.hypot(x - cx, y - cy) < r, :3] = value
    return fn


def whole_bake(mat):
    shadow_images.forget_cached_shape(mat)
    update(mat, bpy.context.scene, rebake=True, force=True)
    return shadow(mat)


def test_paint_shape_sets_up_layers_keeps_the_look_and_enters_texture_paint(tmp_path):
    """One click: the layers (packed, the painting's size), the made shape as the shape image
    (its old one kept as the base, never written), Texture Paint on the height layer with a
    soft brush — and the painting looks as before (the made shape is the base's relief)."""
    mat = painting(tmp_path, 256)
    s = mat.dynamic_painting
    base, before = s.image_shape, shadow(mat)
    base_pixels = pixels(base).copy()
    assert bpy.ops.dynpaint.paint_shape() == {"FINISHED"}
    pt = s.painted
    assert s.image_shape == pt.made and pt.base == base
    assert all(img.packed_file is not None and tuple(img.size) == (256, 256)
               for img in (pt.made, pt.mask, pt.height_layer))
    assert s.plane.mode == "TEXTURE_PAINT"
    paint_settings = bpy.context.scene.tool_settings.image_paint
    assert paint_settings.canvas == pt.height_layer and paint_settings.brush.name == "Paint Soft"
    assert status.LAST_ERRORS == []
    # the made shape is the base's relief, to float32's rounding of it (1.01e-5 measured once
    # the Sun was aimed in Euler XYZ: its direction rounds differently)
    assert np.abs(shadow(mat) - before).max() <= 2e-5
    assert np.array_equal(pixels(base), base_pixels)
    pt.layer = "mask"                                   # Paint On › Figure Mask
    assert paint_settings.canvas == pt.mask
    assert bpy.ops.dynpaint.paint_shape_done() == {"FINISHED"}
    assert s.plane.mode == "OBJECT"
    assert bpy.ops.dynpaint.paint_shape() == {"FINISHED"}     # again: the same layers
    assert s.painted.mask == pt.mask and s.plane.mode == "TEXTURE_PAINT"


def test_painting_the_figure_mask_inflates_it_and_the_settings_reshape_it(tmp_path):
    """A disc painted into the mask: the made shape is the base plus the disc inflated (what
    shapes.painted makes), the shadows are a fresh bake of it; a bevel set in the panel
    reshapes it at once."""
    mat = painting(tmp_path, 128)
    s = mat.dynamic_painting
    bpy.ops.dynpaint.paint_shape()
    pt = s.painted
    before = pixels(pt.made)[..., 0].copy()
    paint(pt.mask, disc(90, 40, 20, 1.0))
    made = pixels(pt.made)[..., 0]
    mask = pixels(pt.mask)[..., 0] >= 0.5
    want = painted_height(before, figure_relief(mask), None, 0)
    assert np.abs(made - want).max() <= 1e-6
    assert made.max() > before.max() + 0.05 or (made - before).max() > 0.1
    got = shadow(mat)
    assert np.abs(got - whole_bake(mat)).max() <= 1e-6
    pt.bevel_width, pt.bevel_height = 0.05, 0.03                 # the panel's Bevel
    bevelled = pixels(pt.made)[..., 0]
    want = painted_height(before, figure_relief(mask, bevel_width=0.05, bevel_height=0.03),
                          None, 0)
    assert np.abs(bevelled - want).max() <= 1e-6 and np.abs(bevelled - made).max() > 0.01
    pt.snap = 0.02                                  # the mask snapped onto the painting's edges
    lum = linear_luminance(image_data_from_blender(s.image_bright))
    want = painted_height(before, figure_relief(mask, lum, bevel_width=0.05, bevel_height=0.03,
                                                snap=0.02), None, 0)
    assert np.abs(pixels(pt.made)[..., 0] - want).max() <= 1e-6
    assert np.abs(pixels(pt.made)[..., 0] - bevelled).max() > 1e-3     # (it moved the edge)
    assert status.LAST_ERRORS == []


def test_strokes_on_the_figure_mask_with_snap_are_what_the_whole_mask_makes(tmp_path):
    """Snap to the Painting on: each stroke on the figure mask is snapped again around its box
    alone (core/snap.resnapped), and the made shape is what the whole mask makes, bit for bit;
    the painting edited, the mask is snapped onto its new edges (with no detail embossed)."""
    mat = painting(tmp_path, 128)
    s = mat.dynamic_painting
    paint(s.image_bright, disc(64, 64, 32, 0.1))            # a dark figure, 2 px past the mask
    bpy.ops.dynpaint.paint_shape()
    pt = s.painted
    before = pixels(pt.made)[..., 0].copy()
    pt.snap = 0.03

    def made_as_whole():
        lum = linear_luminance(image_data_from_blender(s.image_bright))
        mask = pixels(pt.mask)[..., 0]
        want = painted_height(before, figure_relief(mask, lum, snap=0.03), None, 0)
        assert np.abs(pixels(pt.made)[..., 0] - want).max() <= 1e-6
        return mask

    paint(pt.mask, disc(64, 64, 30, 1.0))
    mask = made_as_whole()
    unsnapped = painted_height(before, figure_relief(mask), None, 0)
    assert np.abs(pixels(pt.made)[..., 0] - unsnapped).max() > 1e-3      # (it moved the edge)
    for cx, cy, r, v in ((92, 64, 5, 1.0), (40, 50, 4, 0.0), (64, 20, 7, 1.0), (20, 100, 3, 1.0)):
        paint(pt.mask, disc(cx, cy, r, v))
        made_as_whole()
    shown = pixels(pt.made)[..., 0].copy()
    paint(s.image_bright, disc(64, 64, 34, 0.1))            # the painted figure grown
    made_as_whole()
    assert np.abs(pixels(pt.made)[..., 0] - shown).max() > 1e-3
    assert np.abs(shadow(mat) - whole_bake(mat)).max() <= 1e-6
    assert status.LAST_ERRORS == []


def test_beside_the_ui_a_mask_strokes_relief_is_made_in_a_worker(tmp_path, monkeypatch):
    """Live (a UI is up): a stroke on the figure mask leaves the made shape as it was and its
    relief is made in a worker (a large figure's part takes ~0.5 s to solve at 1024²);
    strokes while it runs wait, the newest replacing older ones; the timer then brings the
    painting up to date — what the layers make, the relief not made again."""
    mat = painting(tmp_path, 128)
    s = mat.dynamic_painting
    bpy.ops.dynpaint.paint_shape()
    pt = s.painted
    before = pixels(pt.made)[..., 0].copy()
    pt.snap = 0.02

    def stroke(fn):                        # as Texture Paint's dab, seen live
        px = image_pixels(pt.mask)
        fn(px)
        pt.mask.pixels.foreach_set(px.ravel())
        note_edited([pt.mask.name])
        return painted_state.update_painted_shape(mat, live=True)

    for cx in (60, 64, 68, 72):
        assert not stroke(disc(cx, 64, 30, 1.0))
        assert np.array_equal(pixels(pt.made)[..., 0], before)
    painted_state.LIVE_RELIEFS.wait()
    monkeypatch.setattr(painted_state, "relief_from", lambda job: 1 / 0)   # made already
    assert sync._reliefs_made() is None                      # (the timer's last look)
    mask = pixels(pt.mask)[..., 0]
    lum = linear_luminance(image_data_from_blender(s.image_bright))
    want = painted_height(before, figure_relief(mask, lum, snap=0.02), None, 0)
    assert np.abs(pixels(pt.made)[..., 0] - want).max() <= 1e-6
    assert np.abs(shadow(mat) - whole_bake(mat)).max() <= 1e-6
    assert status.LAST_ERRORS == []


def test_a_relief_that_fails_in_the_worker_is_reported_and_the_shape_kept(tmp_path,
                                                                          monkeypatch):
    """A worker's error reaches the painting's status from the timer (never into Blender's
    timers), and the made shape stays as it was."""
    mat = painting(tmp_path, 64)
    bpy.ops.dynpaint.paint_shape()
    pt = mat.dynamic_painting.painted
    before = pixels(pt.made).copy()
    monkeypatch.setattr(painted_state, "relief_from", lambda job: np.zeros((2, 2)) / None)
    px = image_pixels(pt.mask)
    disc(32, 32, 12, 1.0)(px)
    pt.mask.pixels.foreach_set(px.ravel())
    note_edited([pt.mask.name])
    assert not painted_state.update_painted_shape(mat, live=True)
    painted_state.LIVE_RELIEFS.wait()
    assert sync._reliefs_made() is None
    assert len(status.LAST_ERRORS) == 1 and "unsupported operand" in status.LAST_ERRORS[0][1]
    assert np.array_equal(pixels(pt.made), before)


def test_a_stroke_on_the_height_layer_changes_the_shape_in_its_box_and_bakes_incrementally(
        tmp_path, monkeypatch):
    """512²: a dab on the height layer raises the made shape by strength × (value − ½) in the
    dab alone; the shadows are re-traced, not baked whole, and equal a whole bake."""
    mat = painting(tmp_path, 512)
    s = mat.dynamic_painting
    bpy.ops.dynpaint.paint_shape()
    pt = s.painted
    pt.strength = 0.1
    before = pixels(pt.made)[..., 0].copy()
    whole = shadow_images.shadow_term
    monkeypatch.setattr(shadow_images, "shadow_term", lambda *a, **k: 1 / 0)
    paint(pt.height_layer, disc(300, 200, 12, 0.9))
    monkeypatch.setattr(shadow_images, "shadow_term", whole)
    assert status.LAST_ERRORS == []
    made = pixels(pt.made)[..., 0]
    changed = np.argwhere(made != before)
    assert changed.size and changed[:, 0].min() >= 188 and changed[:, 0].max() <= 212
    assert abs(float((made - before).max()) - 0.1 * 0.4) < 1e-6
    assert np.abs(shadow(mat) - whole_bake(mat)).max() <= 1e-6


def test_a_stroke_no_update_announces_is_seen_by_the_watcher(tmp_path):
    """Where a stroke sends no Image update (pixels written, no update_tag), the watcher that
    runs while Texture Paint is on sees the layer's pixels change and updates the painting."""
    mat = painting(tmp_path, 128)
    s = mat.dynamic_painting
    bpy.ops.dynpaint.paint_shape()
    pt = s.painted
    assert paint_shape._watch() == paint_shape.WATCH_S          # first look: remembered
    before = pixels(pt.made)[..., 0].copy()
    img = pt.height_layer
    px = np.empty(128 * 128 * 4, np.float32)
    img.pixels.foreach_get(px)
    px.reshape(128, 128, 4)[60:70, 60:70, :3] = 1.0
    img.pixels.foreach_set(px)
    assert np.array_equal(pixels(pt.made)[..., 0], before)      # nothing announced it
    assert paint_shape._watch() == paint_shape.WATCH_S
    assert np.abs(pixels(pt.made)[..., 0] - before).max() > 0.01
    bpy.ops.dynpaint.paint_shape_done()
    assert paint_shape._watch() is None                          # Texture Paint left: it stops


def test_undo_of_paint_shape_gives_the_shape_back(tmp_path):
    """Ctrl Z after Paint Shape: the painting's own shape image again, and its shadows."""
    mat = painting(tmp_path, 128)
    s = mat.dynamic_painting
    before, base = shadow(mat), s.image_shape.name
    bpy.ops.ed.undo_push(message="before")
    bpy.ops.dynpaint.paint_shape()
    bpy.ops.object.mode_set(mode="OBJECT")
    bpy.ops.ed.undo_push(message="painted")
    paint(s.painted.mask, disc(64, 64, 30, 1.0))
    assert np.abs(shadow(mat) - before).max() > 0.01
    name = mat.name
    bpy.ops.ed.undo()
    mat = bpy.data.materials[name]
    assert mat.dynamic_painting.image_shape.name == base
    assert np.abs(shadow(mat) - before).max() <= 1e-6


def test_a_saved_file_keeps_the_painted_layers(tmp_path):
    """Strokes on packed layers survive save and reopen (packed again before the save), and
    the reopened painting makes the same shape from them."""
    mat = painting(tmp_path, 128)
    bpy.ops.dynpaint.paint_shape()
    pt = mat.dynamic_painting.painted
    paint(pt.mask, disc(40, 70, 25, 1.0))
    paint(pt.height_layer, disc(80, 50, 10, 0.8))
    made, mask = pixels(pt.made).copy(), pixels(pt.mask).copy()
    path, name = str(tmp_path / "painted.blend"), mat.name
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    pt = bpy.data.materials[name].dynamic_painting.painted
    assert np.array_equal(pixels(pt.mask), mask)
    assert np.abs(pixels(pt.made) - made).max() <= 1e-6


def test_a_normal_map_painting_is_painted_over_its_normals(tmp_path):
    """A normal-map painting (a two-channel map, read by its own §2 settings: encoding auto)
    gets the same layers, its normal map the base: the made shape is a normal map whose
    normals are the base's until something is painted (the look kept), then tilted by the
    painted relief's slopes."""
    paths = write_images(str(tmp_path))
    _, mat = headless.build_recipe_scene(make_recipe("shadows_normal_point", paths))
    bpy.context.view_layer.objects.active = mat.dynamic_painting.plane
    status.LAST_ERRORS.clear()
    s = mat.dynamic_painting
    base, before = s.image_shape, shadow(mat)
    n_before = shape_normals(image_data_from_blender(base), settings_to_params(s))[0]
    assert bpy.ops.dynpaint.paint_shape() == {"FINISHED"}
    assert s.painted.base == base and s.shape.kind == "normal" and s.shape.encoding == "rgb"
    n_made = shape_normals(image_data_from_blender(s.image_shape), settings_to_params(s))[0]
    assert np.abs(n_made - n_before).max() <= 1e-5
    assert np.abs(shadow(mat) - before).max() <= 1e-4
    h, w = n_made.shape[:2]
    paint(s.painted.mask, disc(w // 2, h // 2, min(w, h) // 4, 1.0))
    n_painted = shape_normals(image_data_from_blender(s.image_shape), settings_to_params(s))[0]
    assert np.abs(n_painted - n_made).max() > 0.1
    assert status.LAST_ERRORS == []


def test_export_writes_the_made_shape_and_its_layers_and_the_command_line_takes_them(tmp_path):
    """Export: the made shape is the recipe's shape image (the core renders the exported
    recipe as the add-on's core does the painting), the layers are written beside it, and
    make-shape export-maps takes the recipe."""
    mat = painting(tmp_path, 96)
    bpy.ops.dynpaint.paint_shape()
    pt = mat.dynamic_painting.painted
    paint(pt.mask, disc(30, 60, 18, 1.0))
    bpy.ops.object.mode_set(mode="OBJECT")
    out = tmp_path / "out" / "painting.toml"
    assert bpy.ops.dynpaint.export_recipe(filepath=str(out)) == {"FINISHED"}
    recipe = load_recipe(str(out))
    assert recipe.params.shape.height_scale == 1.0
    shape = read_image(recipe.images["shape"])
    assert np.abs(shape.pixels[..., 0] - pixels(pt.made)[..., 0]).max() <= 1e-6
    for role in ("mask", "height_layer"):
        written = read_image(str(tmp_path / "out" / f"{mat.name.replace(' ', '_')}"
                                                    f"_painted_{role}.exr"))
        assert np.abs(written.pixels[..., 0] - pixels(getattr(pt, role))[..., 0]).max() <= 1e-6
    s = mat.dynamic_painting
    lights = [painting_frame_light(o, s.plane.matrix_world)
              for o in linked_lights(mat, bpy.context.scene)]
    here = core_render({c: image_data_from_blender(img) for c, img in channel_images(s).items()},
                       lights, settings_to_params(s)).rgba
    exported = core_render(load_images(recipe), recipe.lights, recipe.params).rgba
    assert np.abs(exported - here).max() <= 1e-5
    maps = tmp_path / "maps"
    done = run_cli("make-shape", "export-maps", str(out), "--out", str(maps))
    assert done.returncode == 0, done.stderr
    height = read_image(str(next(maps.glob("*height*"))))
    assert height.pixels[..., 0].max() > 0.1
