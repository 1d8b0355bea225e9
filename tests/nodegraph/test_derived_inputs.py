"""The derived inputs every backend samples, planned and made without Blender (issue 14)."""
import numpy as np

from dynpaint_addon import params
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.pipeline import lookup_copy
from dynpaint_addon.core.shape import preblurred_height
from dynpaint_addon.nodegraph.derived_inputs import (GreyMade, Source, derived_inputs,
                                                     make_derived)
from dynpaint_addon.nodegraph.features import Features


def plan(f, p, bits=None):
    bits = bits or {}
    return {d.channel: d for d in derived_inputs(
        f, p, {c: Source(c, bits.get(c, 8)) for c in f.channels})}


def test_only_what_the_graph_samples_is_planned():
    p = params.defaults()
    # a normal map is checked for its convention (two-channel, scaled tilts); nothing else
    assert list(plan(Features(size=(8, 8)), p)) == ["shape"]
    f = Features(size=(8, 8), shape_kind="height", transparency="param", silhouette="dark",
                 channels=frozenset({"shape", "dark", "environment", "background"}),
                 lookup_sizes=(("background", (8, 8)), ("environment", (8, 8))))
    assert set(plan(f, p)) == {"height", "silhouette", "environment", "background",
                               "background_sharp"}
    assert plan(f, p)["silhouette"].source == "dark"
    # the sharp background is the background itself while it is not blurred
    assert plan(f, p)["background_sharp"].same_as == "background"
    p.refraction.blur = 0.1
    assert plan(f, p)["background_sharp"].same_as == ""


def test_made_images_are_the_cores_own():
    rng = np.random.default_rng(0)
    shape = ImageData(rng.uniform(0, 1, (6, 9, 1)).astype(np.float32), 8)
    env = ImageData(rng.uniform(0, 1, (5, 7, 4)).astype(np.float32), 8)
    p = params.defaults()
    p.shape.kind, p.reflection.blur = "height", 0.2
    f = Features.from_params(p, {"shape", "dark", "environment"}, ["sun"], (9, 6), (),
                             {"environment": (7, 5)})
    f = type(f)(**{**vars(f), "transparency": "param"})
    items = derived_inputs(f, p, {"shape": Source("h", 8), "environment": Source("e", 8)})
    made, warnings = make_derived(items, {"shape": shape, "environment": env}.__getitem__,
                                  lambda c: "colour" if c != "shape" else "height")
    assert warnings == []
    np.testing.assert_array_equal(made["height"][..., 0], preblurred_height(shape.grey(), 1.5))
    np.testing.assert_array_equal(made["environment"], lookup_copy(env, 0.2, p.reflection.extension))


def test_a_float_input_gets_a_finite_copy_only_where_it_needs_one():
    p = params.defaults()
    f = Features(size=(4, 3))
    good = ImageData(np.full((3, 4, 3), 0.5, np.float32), 32)
    bad = ImageData(good.pixels.copy(), 32)
    bad.pixels[1, 2, 0] = np.nan
    items = [d for d in derived_inputs(f, p, {"dark": Source("d", 32)}) if d.channel == "dark"]
    assert items and items[0].finite_copy
    made, warnings = make_derived(items, lambda c: good, lambda c: "colour")
    assert made["dark"] is None and warnings == []          # the image itself will do
    made, warnings = make_derived(items, lambda c: bad, lambda c: "colour")
    assert np.all(np.isfinite(made["dark"])) and made["dark"].shape == (3, 4, 4)
    assert len(warnings) == 1 and "NaN" in warnings[0]


def test_a_local_grey_image_remade_in_an_edits_box_equals_the_whole_made_again():
    """Issue 41: the pre-blurred height (σ 1.5 px: reach 5) and the silhouette (reach 0), made
    with made_from (the source pixels their images were made from by the same recipe) after
    30 random box edits — some at the image's edges, some changing nothing — are remade in the
    box grown by their reach alone, and pasted into what was made before they equal making the
    whole again, bit for bit. Another recipe (σ changed) is made whole."""
    rng = np.random.default_rng(4)
    p = params.defaults()
    p.shape.kind, p.shape.preblur = "height", 1.5
    f = Features(size=(57, 41), shape_kind="height", silhouette="shape",
                 channels=frozenset({"shape", "dark"}))
    px = rng.random((41, 57, 4)).astype(np.float32)

    def plan_of(version, preblur=1.5):
        p.shape.preblur = preblur
        return [d for d in derived_inputs(f, p, {"shape": Source("h", 16, (57, 41), True,
                                                                  version=version)})
                if d.channel in ("height", "silhouette")]
    items = plan_of(0)
    assert {d.channel: d.reach for d in items} == {"height": 5, "silhouette": 0}

    def made(items, pixels, made_from=None):
        return make_derived(items, lambda c: ImageData(pixels, 16), lambda c: "height",
                            grey=True, made_from=made_from)[0]
    images = {c: (m.grey.copy(), m.alpha.copy()) for c, m in made(items, px).items()}
    sources = {c: px for c in images}
    for k in range(30):
        after = px.copy()
        r, c = rng.integers(-4, 41), rng.integers(-4, 57)
        if k % 7 != 3:
            after[max(r, 0):r + 6, max(c, 0):c + 9] = rng.random(
                after[max(r, 0):r + 6, max(c, 0):c + 9].shape)
        items = plan_of(k + 1)
        edited = made(items, after, lambda item: sources[item.channel])
        whole = made(items, after)
        for item in items:
            m = edited[item.channel]
            assert isinstance(m, GreyMade) and m.box is not None and m.source is after
            r0, r1, c0, c1 = m.box
            grey, alpha = images[item.channel]
            grey[r0:r1, c0:c1] = m.grey
            if m.alpha is not None:
                alpha[r0:r1, c0:c1] = m.alpha
            assert np.array_equal(grey, whole[item.channel].grey), (k, item.channel)
            assert np.array_equal(alpha, whole[item.channel].alpha), (k, item.channel)
            sources[item.channel] = after
        px = after
    other = plan_of(31, preblur=2.0)
    assert other[0].recipe != items[0].recipe    # the writer's made_from answers None then
    assert made(other, px)["height"].box is None


def test_a_grey_height_map_not_pre_blurred_is_sampled_itself():
    """A one-channel 8/16-bit shape image at σ 0 (16-bit's default) is its own height image
    (the graph reads red: no derived image written per stroke); colour, float, pre-blurred
    or moving ones get the derived pre-blurred heights."""
    p = params.defaults()
    p.shape.kind = "height"
    f = Features(size=(8, 8), shape_kind="height")

    def height(src, preblur="auto"):
        p.shape.preblur = preblur
        item = next(d for d in derived_inputs(f, p, {"shape": src}) if d.channel == "height")
        made, _ = make_derived([item], lambda c: ImageData(np.zeros((8, 8, 1), np.float32), 16),
                               lambda c: "height", grey=True)
        return made["height"]
    assert height(Source("h", 16, grey=True)) is None
    assert height(Source("h", 8, grey=True), 0.0) is None
    assert isinstance(height(Source("h", 8, grey=True)), GreyMade)          # σ 1.5 by default
    assert isinstance(height(Source("h", 16)), GreyMade)                    # RGB: luminance
    assert isinstance(height(Source("h", 32, grey=True)), GreyMade)         # may hold NaN
    assert isinstance(height(Source("h", 16, grey=True, frame=3)), GreyMade)  # a frame's copy
