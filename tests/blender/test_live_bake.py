"""The live cos-θ bake (issue 4): preview while a light moves, final once it is still, a newer
request supersedes a bake in flight, and images only ever show a finished bake."""
import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
pytestmark = pytest.mark.every_blender

from dynpaint_addon import blender  # noqa: E402
from dynpaint_addon.blender.bake import live_bake, shadow_images  # noqa: E402
from dynpaint_addon.blender.bake.shadow_images import light_bakes, light_key, stale_lights  # noqa: E402
from dynpaint_addon.blender.material.sync import update  # noqa: E402
from dynpaint_addon.blender.state.edits import note_edited  # noqa: E402
from dynpaint_addon.blender.state.lights import painting_frame_light  # noqa: E402
from dynpaint_addon.blender.state.settings import settings_to_params  # noqa: E402
from dynpaint_addon.core.pipeline import shadow_term, shape_normals  # noqa: E402
from dynpaint_addon.inputs.imageio import image_data_from_blender  # noqa: E402
from dynpaint_addon.inputs.painting_frames import BoundedCache  # noqa: E402
from testkit.sun_painting import image_pixels, sun_painting  # noqa: E402

from parity_recipes import write_images  # noqa: E402


@pytest.fixture
def painting(tmp_path):
    write_images(str(tmp_path))
    bpy.ops.wm.read_homefile(use_empty=True)
    blender.register_once()
    bpy.ops.dynpaint.add(directory=str(tmp_path), files=[{"name": n} for n in (
        "height16.png", "dark.png", "bright.png")])
    mat = bpy.context.object.active_material
    mat.dynamic_painting.shape.height_scale = 0.15
    mat.dynamic_painting.shadows.enabled = True
    return mat


def shadow_pixels(item):
    return image_data_from_blender(item.shadow).pixels[..., 0]


def expected(mat, quality):
    s = mat.dynamic_painting
    p = settings_to_params(s)
    if quality != "final":
        p.shadows.quality = quality
    shape = shape_normals(image_data_from_blender(s.image_shape), p)
    light = painting_frame_light(s.lights[0].object, s.plane.matrix_world)
    return shadow_term(*shape, light, p)


def test_preview_then_final_once_still(painting):
    live = live_bake.LiveBake()
    sun = painting.dynamic_painting.lights[0].object
    sun.rotation_mode = "XYZ"
    sun.rotation_euler = (0.9, 0.3, 2.0)
    bpy.context.view_layer.update()
    assert stale_lights(painting)
    live.request(painting, bpy.context.scene)
    assert live.wait() == 1
    item = painting.dynamic_painting.lights[0]
    assert np.abs(shadow_pixels(item) - expected(painting, "preview")).max() < 1e-6
    # the preview is of the light's new place (its final bake is still due)
    assert all(light_key(light) in item.bake_key for item, light, _ in light_bakes(painting))
    # nothing happens before the light has been still for the debounce time …
    live.tick(now=live.still_since[painting.name] + live_bake.DEBOUNCE_S / 2)
    assert live.wait() == 0
    # … then the painting's own quality replaces the preview
    live.tick(now=live.still_since[painting.name] + live_bake.DEBOUNCE_S + 1e-3)
    assert live.wait() == 1
    assert np.abs(shadow_pixels(item) - expected(painting, "final")).max() < 1e-6
    assert [q for q, _ in live.latencies] == ["preview", "final"]
    assert all(ms > 0 for _, ms in live.latencies)


def test_a_newer_request_supersedes_the_one_in_flight(painting):
    live = live_bake.LiveBake()
    sun = painting.dynamic_painting.lights[0].object
    sun.rotation_mode = "XYZ"
    for angle in (0.5, 1.0, 1.5, 2.0):           # a light dragged through four positions
        sun.rotation_euler = (0.8, 0.2, angle)
        bpy.context.view_layer.update()
        live.request(painting, bpy.context.scene, quality="final")
    live.wait()
    # whatever finished early was superseded or dropped: the image is the last position's
    item = painting.dynamic_painting.lights[0]
    assert np.abs(shadow_pixels(item) - expected(painting, "final")).max() < 1e-6
    assert live.latencies and len(live.latencies) == 1


def test_a_failing_bake_keeps_the_last_good_image(painting, monkeypatch):
    live = live_bake.LiveBake()
    item = painting.dynamic_painting.lights[0]
    before = shadow_pixels(item).copy()
    key = shadow_images.shape_key(painting.dynamic_painting,
                                  settings_to_params(painting.dynamic_painting))
    broken = BoundedCache(0)                 # the decoded shape the bake reads: broken
    broken.put(key, (np.full((2, 2, 3), np.nan), None, None), 0)
    monkeypatch.setitem(shadow_images._SHAPES, painting.name, broken)
    from dynpaint_addon.blender.state.status import LAST_ERRORS
    LAST_ERRORS.clear()
    live.request(painting, bpy.context.scene)
    assert live.wait() == 0
    assert np.array_equal(shadow_pixels(item), before)
    assert LAST_ERRORS and "last good shadows are kept" in LAST_ERRORS[-1][1]
    LAST_ERRORS.clear()


def test_live_level_keeps_within_the_budget(painting, monkeypatch):
    """A live bake slower than its budget (issue 18: light change → image ≤ 33 ms for suns)
    makes the next one draft; a draft well inside it brings preview back."""
    live = live_bake.LiveBake()
    sun = painting.dynamic_painting.lights[0].object
    sun.rotation_mode = "XYZ"
    item = painting.dynamic_painting.lights[0]

    def move(angle):
        sun.rotation_euler = (0.8, 0.2, angle)
        bpy.context.view_layer.update()
        live.request(painting, bpy.context.scene)
        live.wait()
    monkeypatch.setitem(live_bake.LIVE_BUDGET_MS, "sun", 1e-6)       # nothing can keep up
    move(0.5)
    move(0.9)
    assert [q for q, _ in live.latencies] == ["preview", "draft"]
    assert np.abs(shadow_pixels(item) - expected(painting, "draft")).max() < 1e-6
    move(1.3)                                      # draft is the coarsest: it stays
    assert live.latencies[-1][0] == "draft"
    monkeypatch.setitem(live_bake.LIVE_BUDGET_MS, "sun", 1e9)        # anything keeps up
    move(1.7)
    move(2.1)
    assert [q for q, _ in live.latencies[-2:]] == ["draft", "preview"]
    assert np.abs(shadow_pixels(item) - expected(painting, "preview")).max() < 1e-6


def test_a_live_stroke_bakes_drafts_then_a_final_re_traced_from_the_final_before_it(
        tmp_path, monkeypatch):
    """Issue 41, live: dabs on a 512² height map while the UI is up (each an edit seen by the
    handler: the image's version bumped, a draft bake requested), then the final once they
    stop. The final starts from the final before the stroke and re-traces the boxes of all
    the dabs together (no whole bake); it equals a whole bake of the edited image."""
    mat = sun_painting(tmp_path, 512)
    img = mat.dynamic_painting.image_shape
    px = image_pixels(img)
    live = live_bake.LiveBake()
    y, x = np.ogrid[0:512, 0:512]
    for cx in (150, 190, 230):                  # a stroke: three dabs along a line
        px[..., :3] += 0.1 * np.clip(1 - np.hypot(x - cx, y - 260) / 20, 0, 1)[..., None]
        img.pixels.foreach_set(px.ravel())
        note_edited([img.name])
        live.request(mat, bpy.context.scene, quality="draft")
        assert live.wait() == 1
    whole_bake = shadow_images.shadow_term
    monkeypatch.setattr(shadow_images, "shadow_term", lambda *a, **k: 1 / 0)
    live.request(mat, bpy.context.scene, quality="final")
    assert live.wait() == 1
    monkeypatch.setattr(shadow_images, "shadow_term", whole_bake)
    item = mat.dynamic_painting.lights[0]
    incremental = shadow_pixels(item)
    shadow_images.forget_cached_shape(mat)
    update(mat, bpy.context.scene, rebake=True, force=True)
    assert np.abs(incremental - shadow_pixels(item)).max() <= 1e-6
