"""The whole pipeline (§2–§11): hand-computed pixels, §12 neutral defaults, §14 input extremes."""
import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.colour import srgb_to_linear
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.input_rules import ImageData, input_notes, relief_of
from dynpaint_addon.core.pipeline import render, shadow_term, shape_normals


def srgb_decode(v):
    return v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4


def const(h, w, value, bits=8):
    value = np.atleast_1d(np.asarray(value, np.float32))
    return ImageData(np.broadcast_to(value, (h, w, value.size)).copy(), bits)


def hand_painting():
    """1×3 normal map: N = (0, 0, 1), (0.6, 0, 0.8), (−0.6, 0, 0.8); dark 64/255, bright 200/255."""
    shape = np.array([[[0.5, 0.5, 1.0], [0.8, 0.5, 0.9], [0.2, 0.5, 0.9]]], np.float32)
    return {"shape": ImageData(shape, 16), "dark": const(1, 3, 64 / 255), "bright": const(1, 3, 200 / 255)}


def test_end_to_end_against_values_computed_by_hand():
    p = params.defaults()
    p.specular.enabled = True
    p.specular.s0, p.specular.s1, p.specular.curve = 0.0, 1.0, "linear"
    colour = (1.0, 0.5, 0.25)
    out = render(hand_painting(), [Light("sun", (0.6, 0, 0.8), colour)], p).rgba
    c0, c1 = 64 / 255, 200 / 255                    # mixed as painted (§5), then decoded
    ndl = [0.8, 1.0, 0.28]                          # N·L by hand
    rz = [2 * 0.8 * 1.0 - 0.8, 2 * 1.0 * 0.8 - 0.8, 2 * 0.28 * 0.8 - 0.8]   # R_L.z = 0.8, 0.8, −0.352
    for i in range(3):
        for ch in range(3):
            w = min(ndl[i] * colour[ch], 1)
            cd = srgb_decode(c0 * (1 - w) + c1 * w)
            s = min(max(rz[i], 0) * colour[ch], 1)
            expected = cd * (1 - s) + 1.0 * s
            assert out[0, i, ch] == pytest.approx(expected, abs=2e-6), (i, ch)
        assert out[0, i, 3] == 1


def test_float64_path_matches_float32():
    p = params.defaults()
    lights = [Light("sun", (0.6, 0, 0.8))]
    a = render(hand_painting(), lights, p, np.float32).rgba
    b = render(hand_painting(), lights, p, np.float64).rgba
    assert b.dtype == np.float64 and np.abs(a - b).max() < 1e-6


def dome_painting(size=24, with_alpha=False):
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    z = np.sqrt(np.clip(0.3 - x * x - y * y, 0.01, None))
    n = np.stack([x, y, z], -1) / np.sqrt(x * x + y * y + z * z)[..., None]
    rgb = (n + 1) / 2
    if with_alpha:
        rgb = np.concatenate([rgb, (x * x + y * y < 0.16)[..., None]], -1)
    rng = np.random.default_rng(0)
    return {"shape": ImageData(rgb.astype(np.float32), 16),
            "dark": ImageData(rng.uniform(0, 0.5, (size, size, 3)).astype(np.float32)),
            "bright": ImageData(rng.uniform(0.5, 1, (size, size, 3)).astype(np.float32))}


def glass_params(**fresnel):
    p = params.defaults()
    p.transparency.amount = 0.7
    p.specular.enabled = True
    p.specular.s0 = 0.5
    for k, v in fresnel.items():
        setattr(p.fresnel, k, v)
    return p


LIGHTS = [Light("sun", (0.5, 0.3, 0.8), (1, 0.9, 0.8)), Light("point", (-0.3, 0.2, 0.4), (0.3, 0.4, 1), 0.7)]


def test_pruned_graph_equals_full_graph_fed_the_neutral_defaults():
    """§12: each missing channel has a neutral default; leaving it out changes no pixel."""
    base = dome_painting()
    size = 24
    env = ImageData(np.random.default_rng(1).uniform(0, 1, (16, 20, 3)).astype(np.float32))
    bg = ImageData(np.random.default_rng(2).uniform(0, 1, (30, 12, 3)).astype(np.float32))
    p = glass_params()

    def same(a, b):
        np.testing.assert_array_equal(render(a, LIGHTS, p).rgba, render(b, LIGHTS, p).rgba)

    same(base, {**base, "specular_color": const(size, size, 1.0)})          # white highlights
    same(base, {**base, "gloss": const(size, size, 1.0)})                   # gloss 1
    same(base, {**base, "transparency": const(size, size, 1.0)})            # k = slider
    # one colour image A is an albedo (§1): C0 = a·A and C1 = A mixed in linear light …
    only = {k: v for k, v in base.items() if k != "dark"}
    a_lin = srgb_to_linear(base["bright"].pixels)
    pair = {**base, "dark": ImageData(p.diffuse.ambient * a_lin, 32),
            "bright": ImageData(a_lin, 32)}
    p_linear = glass_params()
    p_linear.diffuse.mix_space = "linear"
    np.testing.assert_allclose(render(only, LIGHTS, p).rgba, render(pair, LIGHTS, p_linear).rgba,
                               atol=2e-6)
    # … and with ambient 1 it serves as both (flat: the light changes nothing)
    p.diffuse.ambient = 1.0
    np.testing.assert_allclose(
        render({k: v for k, v in base.items() if k != "bright"}, LIGHTS, p).rgba,
        render({**base, "bright": base["dark"]}, LIGHTS, p).rgba, atol=1e-6)
    p.diffuse.ambient = 0.2
    # no silhouette = alpha 1 everywhere
    opaque = ImageData(np.concatenate([base["shape"].pixels, np.ones((size, size, 1), np.float32)], -1), 16)
    same({**base, "background": bg}, {**base, "background": bg, "shape": opaque})
    # no E and no B: G is transparent black; the same as E and B fully transparent
    clear = ImageData(np.zeros((5, 5, 4), np.float32))
    p.silhouette.source = "none"
    same(base, {**base, "environment": clear, "background": clear})
    # E missing: G = C_T, i.e. F = 0 (art Fresnel with κ = −1); B missing: G = C_M (κ = +1)
    full = {**base, "environment": env, "background": bg}
    for drop, kappa in (("environment", -1.0), ("background", 1.0)):
        p_full = glass_params(mode="art", kappa=kappa)
        p_full.silhouette.source = "none"
        pruned = {k: v for k, v in full.items() if k != drop}
        np.testing.assert_array_equal(render(pruned, LIGHTS, p_full).rgba, render(full, LIGHTS, p_full).rgba)


def test_transparency_composite_weights_sum_to_one():
    """§11: C = (1 − k)·C_s + k·C2′; at k = 1, s = 0 the result is G = F·E + (1 − F)·B exactly."""
    size = 6
    flat = ImageData(np.tile(np.array([0.5, 0.5, 1.0], np.float32), (size, size, 1)), 16)
    e_val, b_val = 0.8, 0.2
    imgs = {"shape": flat, "dark": const(size, size, 0.1), "bright": const(size, size, 0.9),
            "environment": const(3, 3, e_val, 32), "background": const(3, 3, b_val, 32)}
    p = params.defaults()
    p.transparency.amount = 1.0
    out = render(imgs, [Light("sun", (0, 0, 1))], p).rgba
    f = ((1.5 - 1) / 2.5) ** 2
    np.testing.assert_allclose(out[..., :3], f * e_val + (1 - f) * b_val, atol=1e-6)
    np.testing.assert_allclose(out[..., 3], 1)


def test_silhouette_shows_the_background_outside():
    imgs = dome_painting(with_alpha=True)
    imgs["background"] = const(4, 4, (0.25, 0.5, 0.75), 32)
    out = render(imgs, LIGHTS, params.defaults()).rgba
    np.testing.assert_allclose(out[0, 0], [0.25, 0.5, 0.75, 1], atol=1e-6)     # outside
    no_bg = render({k: v for k, v in imgs.items() if k != "background"}, LIGHTS, params.defaults()).rgba
    np.testing.assert_allclose(no_bg[0, 0], 0)                                 # transparent
    assert no_bg[12, 12, 3] == 1


def test_mismatched_sizes_are_resampled_to_the_shape_image():
    imgs = dome_painting(24)
    imgs["dark"] = const(7, 11, 0.3)
    result = render(imgs, LIGHTS, params.defaults())
    assert result.rgba.shape == (24, 24, 4)
    assert any("resampled" in w and "dark" in w for w in result.warnings)


def test_nan_shape_and_tiny_images():
    """§14: a whole image of NaN → a clear error; 1×1 images render; partial NaN is reported."""
    with pytest.raises(ValueError, match="no finite pixel"):
        render({"shape": const(4, 4, np.nan, 32), "dark": const(4, 4, 0.5)}, LIGHTS, params.defaults())
    for kind in ("normal", "height"):
        p = params.defaults()
        p.shape.kind = kind
        p.shadows.enabled = True
        for hw in ((1, 1), (2, 2), (1, 5)):
            shape = const(*hw, 0.7) if kind == "height" else \
                ImageData(np.full(hw + (3,), (0.6, 0.5, 0.9), np.float32), 8)
            out = render({"shape": shape, "dark": const(*hw, 0.2)}, LIGHTS, p).rgba
            assert out.shape == hw + (4,) and np.all(np.isfinite(out))
    shape = dome_painting()["shape"].pixels.copy()
    shape[3, 4] = np.nan
    res = render({"shape": ImageData(shape, 32), "dark": const(24, 24, 0.5)}, LIGHTS, params.defaults())
    assert np.all(np.isfinite(res.rgba)) and any("NaN" in w for w in res.warnings)


def test_random_parameter_sweep_stays_finite_and_in_range():
    """§14 across the whole pipeline: 500 random parameter sets (each number at its min, its
    max or between: each extreme of each number drawn ~170 times, each pair of two numbers'
    extremes ~55 times) and random lights on a small painting with every channel present: no
    NaN/Inf, every value in [0, 1]. (tests/blender/test_sweeps.py renders such sets in
    Blender.)"""
    from parity_recipes import random_lights, random_params
    rng = np.random.default_rng(42)
    size = 12
    imgs = dome_painting(size, with_alpha=True)
    imgs.update(environment=ImageData(rng.uniform(0, 4, (9, 7, 3)).astype(np.float32), 32),
                background=ImageData(rng.uniform(0, 1, (5, 13, 4)).astype(np.float32)),
                transparency=ImageData(rng.uniform(0, 1, (size, size, 1)).astype(np.float32)),
                gloss=ImageData(rng.uniform(0, 1, (size, size, 1)).astype(np.float32)),
                specular_color=ImageData(rng.uniform(0, 1, (size, size, 3)).astype(np.float32)))
    as_height = params.defaults()
    as_height.shape.kind, as_height.shape.height_scale = "height", 0.1
    normal = ImageData(np.concatenate([shape_normals(imgs["shape"], as_height)[0] * 0.5 + 0.5,
                                       imgs["shape"].pixels[..., -1:]], -1), 32)
    for i in range(500):
        p = random_params(rng)
        lights = random_lights(rng)
        images = dict(imgs, shape=normal) if p.shape.kind == "normal" else imgs
        out = render(images, lights, p).rgba
        assert np.all(np.isfinite(out)), (i, vars(p))
        assert out.min() >= 0 and out.max() <= 1 + 1e-6, (i, vars(p))


def test_blur_cache_is_reused_and_never_stale():
    """Glossy/translucent copies are blurred once per image; a new image is never served stale."""
    imgs = dome_painting()
    p = glass_params()
    p.reflection.blur = p.refraction.blur = 0.05
    rng = np.random.default_rng(9)
    env = ImageData(rng.uniform(0, 1, (16, 16, 3)).astype(np.float32), 32)
    cache = {}
    first = render({**imgs, "environment": env}, LIGHTS, p, cache=cache).rgba
    assert len(cache) == 1
    again = render({**imgs, "environment": env}, [Light("sun", (0, 0, 1))], p, cache=cache).rgba
    assert len(cache) == 1 and not np.array_equal(first, again)
    for _ in range(3):   # fresh image objects (ids may be recycled) always give fresh results
        other = ImageData(rng.uniform(0, 1, (16, 16, 3)).astype(np.float32), 32)
        cached = render({**imgs, "environment": other}, LIGHTS, p, cache=cache).rgba
        np.testing.assert_array_equal(cached, render({**imgs, "environment": other}, LIGHTS, p).rgba)


# -- masks painted in one colour channel (issue 15) -------------------------------------------
from dynpaint_addon.core.inputs import mask_values  # noqa: E402


def test_masks_read_a_pure_channel_or_luminance():
    rng = np.random.default_rng(7)
    k = rng.uniform(0, 1, (6, 5))
    zero = np.zeros_like(k)
    red = np.stack([k, zero, zero], -1)
    values, channel = mask_values(red)
    assert channel == "red" and np.array_equal(values, k)
    # luminance when asked (what it was before: pure red reads at most 0.2126)
    assert mask_values(red, "luminance")[0].max() <= 0.2126 + 1e-12
    colour = rng.uniform(0, 1, (6, 5, 3))
    assert mask_values(colour)[1] == "luminance"
    assert np.array_equal(mask_values(colour, "blue")[0], colour[..., 2])
    grey_alpha = np.stack([k, 1 - k], -1)
    assert np.array_equal(mask_values(grey_alpha)[0], k)
    assert np.array_equal(mask_values(grey_alpha, "alpha")[0], 1 - k)
    assert np.all(mask_values(colour, "alpha")[0] == 1)          # no alpha: opaque


def test_a_red_transparency_mask_shows_the_glass_fully_and_says_so():
    imgs = builtin_images_for_masks()
    p = params.defaults()
    p.transparency.amount = 1.0
    lights = [Light("sun", (0.2, 0.3, 0.9))]
    result = render(imgs, lights, p, keep_passes=True)
    assert result.passes["k"].max() == pytest.approx(1.0)
    assert any("read from its red channel" in w for w in result.warnings)
    p.transparency.channel = "luminance"
    assert render(imgs, lights, p).passes["k"].max() == pytest.approx(0.2126, abs=1e-6)


def builtin_images_for_masks():
    h, w = 12, 16
    n = np.zeros((h, w, 3))
    n[..., 2] = 1
    red = np.zeros((h, w, 3))
    red[3:9, 4:12, 0] = 1.0
    return {"shape": ImageData((n + 1) / 2, 16), "dark": ImageData(np.full((h, w, 3), 0.2)),
            "bright": ImageData(np.full((h, w, 3), 0.8)), "transparency": ImageData(red),
            "background": ImageData(np.full((h, w, 3), 0.5))}


def test_banded_renders_read_a_mask_from_the_channel_the_whole_image_says(monkeypatch):
    """'auto' decides on the whole mask: a band whose pixels happen to be pure red reads the
    same channel (luminance) as the rest of a colour mask, so bands equal one pass."""
    from dynpaint_addon.core import pipeline
    imgs = builtin_images_for_masks()
    colour = np.zeros((12, 16, 3))
    colour[:6, :, 0] = np.linspace(0, 1, 16)            # top half: red only …
    colour[6:] = [0.2, 0.7, 0.4]                        # … bottom half: a colour
    imgs["transparency"] = ImageData(colour)
    p = params.defaults()
    p.transparency.amount = 1.0
    lights = [Light("sun", (0.2, 0.3, 0.9))]
    whole = render(imgs, lights, p, keep_passes=False).rgba
    monkeypatch.setattr(pipeline, "RENDER_BAND_PIXELS", 16 * 3)
    banded = render(imgs, lights, p, keep_passes=False).rgba
    np.testing.assert_array_equal(banded, whole)


def _dot_image(size, at):
    """A float image, black with one white texel at pixel (row, column) `at`."""
    px = np.zeros((size, size, 3), np.float32)
    px[at] = 1.0
    return ImageData(px, 32)


def _brightest(grey):
    return np.unravel_index(np.argmax(grey), grey.shape)


@pytest.mark.parametrize("section, channel", [("reflection", "environment"),
                                              ("refraction", "background")])
def test_environment_and_background_are_placed_by_offset_and_scale(section, channel):
    """§8, §9 placement: a flat glass painting (no warp) shows E or B where the offset puts its
    centre and as large as the scale says (a dot's light, summed, grows with scale²). Before,
    neither could be placed."""
    size = 32
    flat = ImageData(np.tile(np.array([0.5, 0.5, 1.0], np.float32), (size, size, 1)), 16)
    imgs = {"shape": flat, "dark": const(size, size, 0.0), "transparency": const(size, size, 1.0),
            channel: _dot_image(size, (20, 20))}
    p = params.defaults()
    p.refraction.ior = 1.0
    p.reflection.extension = p.refraction.extension = "extend"    # one dot, no mirrored copies

    def shown(offset=(0.0, 0.0), scale=1.0):
        getattr(p, section).offset, getattr(p, section).scale = offset, scale
        return render(imgs, [Light("sun", (0, 0, 1))], p).rgba[..., 0]

    assert _brightest(shown()) == (20, 20)
    assert _brightest(shown((0.25, -0.125))) == (20 - 4, 20 + 8)   # right, down
    for scale in (2.0, 0.5):
        assert shown(scale=scale).sum() == pytest.approx(scale ** 2, rel=1e-5)
    assert _brightest(shown(scale=0.5)) == (18, 18)    # nearer the centre


def test_the_background_around_the_silhouette_is_placed_like_the_refraction():
    """What shows outside the figure is the background the glass refracts: both move together."""
    imgs = dome_painting(with_alpha=True)
    h, w = imgs["shape"].pixels.shape[:2]
    imgs["background"] = _dot_image(w, (1, 1))
    p = params.defaults()
    assert _brightest(render(imgs, LIGHTS, p).rgba[..., 0]) == (1, 1)
    p.refraction.offset = (3 / w, 2 / w)
    assert _brightest(render(imgs, LIGHTS, p).rgba[..., 0]) == (3, 4)


def test_point_light_falloff_halves_the_weight_at_its_radius_and_spares_suns():
    """§5: inverse-square falloff k / (1 + (dist/r)²) on a flat painting lit from straight above:
    N·L = 1 under the light, so W is the falloff itself there; a sun does not fade."""
    size = 65
    flat = {"shape": const(size, size, (0.5, 0.5, 1.0), 16),
            "dark": const(size, size, 0.0), "bright": const(size, size, 1.0)}
    p = params.defaults()
    p.falloff.mode, p.falloff.radius = "inverse_square", 0.25
    p.diffuse.mix_space = "linear"
    height = 0.25                                    # the light's height = its radius
    w = render(flat, [Light("point", (0.0, 0.0, height))], p).passes["W"][..., 0]
    assert w[size // 2, size // 2] == pytest.approx(0.5, abs=1e-6)      # dist = r → ½
    x = (size // 2 + 16.5) / size - 0.5               # a pixel about r to the side
    dist2 = x * x + height * height
    expected = height / np.sqrt(dist2) / (1 + dist2 / 0.25 ** 2)        # N·L × falloff
    assert w[size // 2, size // 2 + 16] == pytest.approx(expected, abs=1e-5)
    p.falloff.mode = "none"
    w_none = render(flat, [Light("point", (0.0, 0.0, height))], p).passes["W"][..., 0]
    assert w_none[size // 2, size // 2] == pytest.approx(1.0, abs=1e-6)
    p.falloff.mode = "inverse_square"
    w_sun = render(flat, [Light("sun", (0.0, 0.0, 1.0))], p).passes["W"][..., 0]
    assert np.allclose(w_sun, 1.0)


def test_auto_relief_integrates_cut_out_figures_and_marches_full_frame_maps_and_says_so():
    """shadows.relief 'auto' (docs/relief-choice.md): integrated where the shape image has an
    alpha, along the ray where it has none, with a note naming both ways out."""
    assert relief_of("auto", True) == "integrated" and relief_of("auto", False) == "along_ray"
    assert relief_of("integrated", False) == "integrated"
    rgb = np.full((16, 16, 3), (0.5, 0.5, 1.0), np.float32)
    p = params.defaults()
    p.shape.kind, p.shadows.enabled = "normal", True
    full = ImageData(rgb, 8, "n.png")
    alpha = np.zeros((16, 16), np.float32)
    alpha[2:-2, 2:-2] = 1                                # a figure cut out
    cut = ImageData(np.dstack([rgb, alpha]), 8, "n.png")
    assert shape_normals(full, p)[1] is None and shape_normals(cut, p)[1] is not None
    notes = input_notes({"shape": full}, p)
    assert len(notes) == 2 and "along each ray" in notes[0] and "integrated" in notes[0]
    assert "fit a height field" in notes[1] and "the whole way" in notes[1]   # §6 Reach
    assert input_notes({"shape": cut}, p) == []
    p.shadows.relief = "along_ray"                       # chosen: only how far it is felt
    assert input_notes({"shape": full}, p) == notes[1:]


def _dome_map(size=48, cut=True):
    """A dome's normal map (a figure of radius 0.3), with its figure as the alpha or full-frame."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    z = np.sqrt(np.clip(0.3 ** 2 - x * x - y * y, 0, None))
    gy, gx = np.gradient(z * size)
    n = np.dstack([-gx, -gy, np.ones_like(z)])
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    rgb = ((n + 1) / 2).astype(np.float32)
    return ImageData(np.dstack([rgb, (z > 0).astype(np.float32)]) if cut else rgb, 32, "n.exr")


@pytest.mark.parametrize("cut", [True, False], ids=["cut out", "full-frame"])
def test_auto_relief_casts_the_shadow_of_either_relief_at_final_and_one_live(cut):
    """§6 "Relief" auto (issue 62, core/either_relief.py): at final and reference quality a
    map whose normals fit a height field is shadowed where either relief shadows it — t is the
    min of the integrated relief's and the whole ray's, each baked as its own setting bakes it;
    draft and preview keep the one relief relief_of names."""
    shape = _dome_map(cut=cut)
    light = Light("sun", (0.8, 0.1, 0.45))

    def t(relief, quality):
        p = params.defaults()
        p.shape.kind, p.shadows.relief, p.shadows.quality = "normal", relief, quality
        return shadow_term(*shape_normals(shape, p), light, p)
    for quality in ("final", "reference"):
        integrated, along = t("integrated", quality), t("along_ray", quality)
        assert np.abs(integrated - along).max() > 0.1            # they differ: a choice
        np.testing.assert_array_equal(t("auto", quality), np.minimum(integrated, along))
    for quality in ("draft", "preview"):
        np.testing.assert_array_equal(t("auto", quality),
                                      t(relief_of("auto", cut), quality))
