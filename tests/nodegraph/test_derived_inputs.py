"""The derived inputs every backend samples, planned and made without Blender (issue 14)."""
import numpy as np

from dynpaint_addon import params
from dynpaint_addon.core.input_rules import ImageData
from dynpaint_addon.core.pipeline import lookup_copy
from dynpaint_addon.core.shape import preblurred_height
from dynpaint_addon.nodegraph.derived_inputs import Source, derived_inputs, make_derived
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
