"""The web page's viewer (issue 17), driven in headless Chromium with real input events:
drag (mouse and touch), wheel, keys, light switches, turntable and keyframed animation,
reset, embedding, device pixel ratio, and the message where WebGL2 is missing. After each
move the page's pixels are compared with the core lit the same way."""
import math
import time

import numpy as np
import pytest

from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.pipeline import render as core_render
from dynpaint_addon.inputs.recipe import load_images
from dynpaint_addon.inputs.testpainting import builtin_images, builtin_recipe
from testkit.chromium import Chromium
from dynpaint_addon.web.page import page_data, write_page

from conftest import open_page, page_pixels, shown
from parity_recipes import make_recipe, write_images

BORDER = 1


@pytest.fixture(scope="module")
def painting(tmp_path_factory):
    """Two lights (a sun key, a point fill) over the parity normal map → (recipe, images, path,
    data)."""
    folder = tmp_path_factory.mktemp("viewer")
    recipe = make_recipe("two_lights_coloured", write_images(str(folder)))
    images = load_images(recipe)
    data, _ = page_data(images, recipe.lights, recipe.params, title="Two lights",
                        credits="Test painting, 2026", turntable_seconds=4.0)
    path = folder / "two_lights.html"
    write_page(path, data)
    return recipe, images, path, data


def places(page):
    return page.evaluate("window.dynamicPainting.lights.map(l => l.place)")


def canvas_box(page):
    return page.box("painting")


def at(page, fx, fy):
    """CSS pixel of the point (fx, fy) of the canvas, from its top-left corner in 0..1."""
    left, top, w, h = canvas_box(page)
    return left + fx * w, top + fy * h


def expected_place(data, fx, fy, height):
    return [fx - 0.5, (0.5 - fy) * data["height"] / data["width"], height]


def lit_like_page(recipe, page_places, on=(True, True)):
    """The recipe's lights moved where the page put them (a sun toward its place)."""
    out = []
    for light, place, is_on in zip(recipe.lights, page_places, on):
        if not is_on:
            continue
        vector = place if light.kind == "point" else tuple(np.asarray(place) / np.linalg.norm(place))
        out.append(Light(light.kind, vector, light.colour, light.strength, light.name))
    return out


def assert_matches_core(page, recipe, images, data, on=(True, True)):
    got = page_pixels(page, data["width"], data["height"])
    want = core_render(images, lit_like_page(recipe, places(page), on), recipe.params).rgba
    b = BORDER
    assert np.abs(got - want)[b:-b, b:-b].max() <= 2e-3
    return got


def test_drag_moves_the_key_light_and_the_picture_follows(painting, browser):
    recipe, images, path, data = painting
    page = open_page(browser, path)
    before = page_pixels(page, data["width"], data["height"])
    h0 = places(page)[0][2]
    page.mouse("pressed", *at(page, 0.1, 0.5))
    page.mouse("moved", *at(page, 0.5, 0.4))
    page.mouse("moved", *at(page, 0.9, 0.2))
    page.mouse("released", *at(page, 0.9, 0.2))
    np.testing.assert_allclose(places(page)[0], expected_place(data, 0.9, 0.2, h0), atol=2e-3)
    assert places(page)[1] == list(recipe.lights[1].vector)          # the fill stayed
    after = assert_matches_core(page, recipe, images, data)
    assert np.abs(after - before).max() > 0.05


def test_touch_drag_moves_the_light(painting, browser):
    recipe, images, path, data = painting
    page = open_page(browser, path)
    h0 = places(page)[0][2]
    page.touch("start", *at(page, 0.3, 0.7))
    page.touch("move", *at(page, 0.2, 0.8))
    page.touch("end", *at(page, 0.2, 0.8))
    np.testing.assert_allclose(places(page)[0], expected_place(data, 0.2, 0.8, h0), atol=2e-3)
    assert_matches_core(page, recipe, images, data)


def test_wheel_slider_and_keys(painting, browser):
    recipe, images, path, data = painting
    page = open_page(browser, path)
    x0, y0, h0 = places(page)[0]
    page.wheel(*at(page, 0.5, 0.5), 200)                    # scroll down: lower
    assert places(page)[0][2] == pytest.approx(h0 * math.exp(-0.2), rel=1e-6)
    page.evaluate("(() => { const s = document.getElementById('height'); s.value = '1.5'; "
                  "s.dispatchEvent(new Event('input')); })()")
    assert places(page)[0][2] == pytest.approx(1.5)
    page.evaluate("document.getElementById('painting').focus()")
    page.key("ArrowLeft")
    page.key("ArrowUp")
    page.key("PageDown")
    np.testing.assert_allclose(places(page)[0], [x0 - 0.02, y0 + 0.02, 1.5 / 1.1], atol=1e-9)
    assert "widths" in page.evaluate("document.getElementById('height-value').textContent")
    assert_matches_core(page, recipe, images, data)
    page.key("r")                                            # reset
    np.testing.assert_allclose(places(page)[0], [x0, y0, h0], atol=1e-12)


def test_switching_lights_off_and_choosing_the_dragged_one(painting, browser):
    recipe, images, path, data = painting
    page = open_page(browser, path)
    boxes = "document.querySelectorAll('#lights input[type=checkbox]')"
    page.evaluate(f"{boxes}[0].click()")
    assert_matches_core(page, recipe, images, data, on=(False, True))
    page.evaluate(f"{boxes}[1].click()")            # no light: the dark image (§5, W = 0)
    got = assert_matches_core(page, recipe, images, data, on=(False, False))
    want = core_render(images, [], recipe.params).rgba
    assert np.abs(got - want).max() <= 2e-3
    page.evaluate("document.querySelectorAll('#lights input[type=radio]')[1].click()")
    z_fill = places(page)[1][2]
    page.mouse("pressed", *at(page, 0.25, 0.25))
    page.mouse("released", *at(page, 0.25, 0.25))
    np.testing.assert_allclose(places(page)[1], expected_place(data, 0.25, 0.25, z_fill),
                               atol=2e-3)
    assert places(page)[0] == pytest.approx(list(np.asarray(recipe.lights[0].vector)
                                                 / np.linalg.norm(recipe.lights[0].vector)))


def test_turntable_plays_and_pauses(painting, browser):
    recipe, images, path, data = painting
    page = open_page(browser, path)
    x0, y0, h0 = places(page)[0]
    page.evaluate("document.getElementById('painting').focus()")
    page.key(" ")
    assert page.evaluate("document.getElementById('play').getAttribute('aria-pressed')") == "true"
    frames0 = page.evaluate("window.dynamicPainting.frames")
    time.sleep(0.8)
    page.key(" ")                                            # pause
    x1, y1, h1 = places(page)[0]
    turned = math.atan2(y1, x1) - math.atan2(y0, x0)
    assert 0.05 < turned % (2 * math.pi) < math.pi           # counter-clockwise, < half a turn
    assert math.hypot(x1, y1) == pytest.approx(math.hypot(x0, y0)) and h1 == h0
    assert page.evaluate("window.dynamicPainting.frames") > frames0 + 2
    time.sleep(0.3)
    assert places(page)[0] == [x1, y1, h1]                    # paused: stays
    assert_matches_core(page, recipe, images, data)


def test_keyframed_animation_plays_its_frames(painting, browser, tmp_path):
    recipe, images, _, _ = painting
    frames = [[[math.cos(a), math.sin(a), 0.6], list(recipe.lights[1].vector)]
              for a in np.linspace(0, 2 * math.pi, 12, endpoint=False)]
    data, _ = page_data(images, recipe.lights, recipe.params,
                        animation={"fps": 12, "frames": frames})
    write_page(tmp_path / "animated.html", data)
    page = open_page(browser, tmp_path / "animated.html")
    page.evaluate("document.getElementById('play').click()")
    time.sleep(0.5)
    page.evaluate("document.getElementById('play').click()")
    frame = page.evaluate("Math.floor(window.dynamicPainting.state.frame)")
    assert 2 <= frame <= 11
    want = np.asarray(frames[frame][0]) / np.linalg.norm(frames[frame][0])
    np.testing.assert_allclose(places(page)[0], want, atol=1e-6)


def test_title_credits_and_controls_are_shown(painting, browser):
    _, _, path, _ = painting
    page = open_page(browser, path)
    assert page.evaluate("document.getElementById('title').textContent") == "Two lights"
    assert page.evaluate("document.getElementById('credits').textContent") == "Test painting, 2026"
    assert page.evaluate("document.querySelectorAll('#lights .light').length") == 2
    # fits the window: the whole canvas is inside the viewport, aspect kept
    left, top, w, h = canvas_box(page)
    assert left >= 0 and top >= 0 and left + w <= 900 + 0.5 and top + h <= 700 + 0.5
    assert w / h == pytest.approx(40 / 30, rel=1e-3)


def test_controls_a_still_painting_has_no_use_for_are_not_seen(painting, browser):
    """A still painting of one layer: no frame slider, no Pause, no 'Drag moves' (issue 38:
    `.row { display: flex }` once showed them in spite of their `hidden` attribute)."""
    _, _, path, _ = painting
    page = open_page(browser, path)
    assert not shown(page, "frames-row") and not shown(page, "frames-play")
    assert not shown(page, "view-row")
    assert shown(page, "height") and shown(page, "play") and shown(page, "hint")
    assert page.evaluate("[...document.querySelectorAll('[hidden]')]"
                         ".every(e => e.getClientRects().length === 0)")


def test_embed_shows_the_painting_alone_at_native_size(painting, browser):
    recipe, images, path, data = painting
    for scale in (1.0, 2.0):
        page = open_page(browser, path, 300, 200, scale, "?embed")
        assert page.evaluate("getComputedStyle(document.getElementById('controls')).display") == "none"
        assert page.evaluate("getComputedStyle(document.getElementById('heading')).display") == "none"
        left, top, w, h = canvas_box(page)
        assert (w, h) == (40, 30)                       # one image pixel per CSS pixel
        assert page.evaluate("document.getElementById('painting').width") == 40 * scale
        assert_matches_core(page, recipe, images, data)


def test_device_pixel_ratio_sharpens_the_canvas(painting, browser):
    _, _, path, _ = painting
    page = open_page(browser, path, 900, 700, 2.0)
    css_w = canvas_box(page)[2]
    assert page.evaluate("document.getElementById('painting').width") == round(css_w * 2)


def test_a_browser_without_webgl2_gets_a_clear_message(painting):
    _, _, path, _ = painting
    with Chromium(extra_flags=("--disable-webgl", "--disable-3d-apis")) as no_gl:
        page = no_gl.open("file://" + str(path), 800, 600)
        page.evaluate("window.dynamicPainting.ready")
        text = page.evaluate("document.getElementById('message').textContent")
        assert "WebGL2" in text and not page.evaluate("document.getElementById('message').hidden")
        assert page.evaluate("document.body.dataset.state") == "failed"


def test_slow_frames_draw_drafts_while_the_light_moves(tmp_path, browser):
    """Where a full frame is slower than 33 ms (here: software WebGL at device pixel ratio 2),
    the page draws at a fraction of the pixels while the light moves and the full frame once
    it stops, so the light keeps up with the hand."""
    recipe = builtin_recipe()
    data, _ = page_data(builtin_images(256), recipe.lights, recipe.params, steps=64)
    write_page(tmp_path / "slow.html", data)
    page = open_page(browser, tmp_path / "slow.html", 900, 800, scale=2)
    page.wait_for("window.dynamicPainting.state.fullFrameMs > 0")
    full_ms = page.evaluate("window.dynamicPainting.state.fullFrameMs")
    assert full_ms > 33, "this machine draws too fast for drafts: nothing to test"
    page.mouse("pressed", *at(page, 0.3, 0.3))
    for step in range(40):           # keep dragging (a late layout re-measures once)
        page.mouse("moved", *at(page, 0.3 + 0.005 * step, 0.3))
        time.sleep(0.05)
        if page.evaluate("window.dynamicPainting.state.drawScale < 1"):
            break
    full_ms = page.evaluate("window.dynamicPainting.state.fullFrameMs")
    scale = page.evaluate("window.dynamicPainting.state.drawScale")
    assert scale == pytest.approx(max(0.25, math.sqrt(33 / full_ms)))
    page.mouse("released", *at(page, 0.4, 0.3))
    page.wait_for("window.dynamicPainting.state.drawScale === 1", 20)


def test_shadows_are_drawn_when_a_light_moves_and_only_then(tmp_path, browser):
    """A still light's frames read its cos-θ texture (no pass drawn); a dragged light's
    shadows are drawn before each frame at the draft size, and at full size once it stops —
    and then the page is the core again (issue 29)."""
    recipe = builtin_recipe()
    images = builtin_images(128)
    data, _ = page_data(images, recipe.lights, recipe.params, steps=64)
    write_page(tmp_path / "shadows.html", data)
    page = open_page(browser, tmp_path / "shadows.html")
    page.wait_for("window.dynamicPainting.state.fullFrameMs > 0")
    assert page.evaluate("window.dynamicPainting.frameTime(3)")["passes"] == 0   # still
    drag = page.evaluate("window.dynamicPainting.frameTime(3, 'drag')")
    assert drag["passes"] == 3                       # the key light's pass, once per frame
    got = page_pixels(page, data["width"], data["height"])      # final shadows first
    assert page.evaluate("window.dynamicPainting.shadows.final")
    moved = lit_like_page(recipe, places(page))
    want = core_render(images, moved, recipe.params).rgba
    assert np.abs(got - want)[1:-1, 1:-1].mean() <= 2e-3
