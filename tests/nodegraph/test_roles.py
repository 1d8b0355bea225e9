"""Each parameter's role in params.py is what the code does with it (issue 14), checked by
perturbing every parameter: the declared roles drive the add-on (what rebuilds, what is
remade, what re-bakes), so a wrong role would be a stale material, and this finds it first."""
import dataclasses

import numpy as np
import pytest

from dynpaint_addon import params
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.input_rules import ImageData, pixel_role
from dynpaint_addon.core.pipeline import shadow_term, shape_normals
from dynpaint_addon.nodegraph.derived_inputs import Source, derived_inputs, make_derived
from dynpaint_addon.nodegraph.features import Features
from dynpaint_addon.nodegraph.pipeline_graph import describe

H, W = 20, 24
LIGHTS = ["sun", "point"]


def alternatives(prm, base):
    """Other values of a parameter than the one `base` has."""
    if prm.kind is bool:
        return [not base]
    if prm.kind == "enum":
        return [c for c in prm.choices if c != base]
    if prm.kind is int:
        return [v for v in (0, 3, 200) if v != base]
    values = [prm.min, (prm.min + prm.max) / 3, prm.max]
    if prm.kind == "auto_float":
        values += ["auto"]
    return [v for v in values if v != base]


def with_value(p, prm, value):
    p = params.defaults() if p is None else p
    q = type(p)(**{s: type(v)(**vars(v)) for s, v in vars(p).items()})
    setattr(getattr(q, prm.section), prm.key, value)
    return q


def base_params(kind="height"):
    p = params.defaults()
    p.shape.kind = kind
    p.shadows.enabled = p.specular.enabled = True
    p.reflection.blur = p.refraction.blur = 0.05        # blurred lookups: extension matters
    p.transparency.amount = 0.5
    p.shadows.quality, p.shadows.steps, p.shadows.resolution = "custom", 16, 1.0
    return p


def features(p):
    channels = set(params.CHANNELS)
    return Features.from_params(p, channels, LIGHTS, (W, H), {"shape"},
                                {c: (W, H) for c in channels})


@pytest.mark.parametrize("kind", ["normal", "height"])
def test_structural_parameters_are_exactly_those_that_change_the_features(kind):
    base = base_params(kind)
    for prm in params.PARAMS:
        value = getattr(getattr(base, prm.section), prm.key)
        changed = [v for v in alternatives(prm, value)
                   if features(with_value(base, prm, v)) != features(base)]
        if not prm.structural:
            assert not changed, f"{prm.path} changes the graph's features: declare it structural"
        elif prm.path != "transparency.amount":       # 0.5 and 1 are both 'param' (live)
            assert changed, f"{prm.path} is declared structural but changes no feature"


def test_every_parameter_has_a_consumer():
    """Every parameter is read by something: the graph's structure or its live values (a
    driver or a group input), a derived image or the bake."""
    used = set()
    for kind in ("normal", "height"):
        for refraction, fresnel, falloff in (("physical", "physical", "none"),
                                             ("linear", "art", "inverse_square")):
            f = dataclasses.replace(features(base_params(kind)), refraction_mode=refraction,
                                    fresnel_mode=fresnel, falloff_mode=falloff,
                                    lights=("sun", "point"))
            used |= describe(f).params()
            used |= describe(dataclasses.replace(f, channels=f.channels - {"dark"})).params()
    idle = [prm.path for prm in params.PARAMS if not (prm.structural or prm.derives or prm.bake
                                                       or prm.path in used)]
    assert idle == []


def images(kind):
    rng = np.random.default_rng(3)
    y, x = np.mgrid[0:H, 0:W] / max(H, W)
    hgt = (np.exp(-((x - 0.5) ** 2 + (y - 0.4) ** 2) / 0.05)).astype(np.float32)
    n = np.stack([0.5 + 0.3 * np.sin(6 * x), 0.5 + 0.3 * np.cos(5 * y), np.ones_like(x)], -1)
    # slopes that fit no height field (a whirl): shadows.reach applies to such a map only (§6)
    whirl = np.stack([0.5 - 0.25 * (y - 0.4) * 8, 0.5 + 0.25 * (x - 0.5) * 8, np.ones_like(x)],
                     -1)
    shape = hgt[..., None] if kind == "height" else whirl if kind == "whirl" else n
    alpha = np.clip(2 - 4 * np.hypot(x - 0.5, y - 0.4), 0, 1)[..., None]
    colour = lambda: rng.uniform(0, 1, (H, W, 3)).astype(np.float32)  # noqa: E731
    return {"shape": ImageData(np.concatenate([shape, alpha], -1).astype(np.float32), 16),
            "dark": ImageData(colour()), "bright": ImageData(colour()),
            "specular_color": ImageData(colour()), "gloss": ImageData(colour()[..., :1]),
            "transparency": ImageData(colour()[..., :1]), "environment": ImageData(colour()),
            "background": ImageData(colour())}


def made(p, imgs):
    plan = derived_inputs(features(p), p, {c: Source(c, im.bits) for c, im in imgs.items()})
    arrays, _ = make_derived(plan, imgs.__getitem__,
                             lambda c: pixel_role(c, p))
    return {d.channel: (d.key, arrays[d.channel]) for d in plan}


@pytest.mark.parametrize("kind, source", [("normal", "baked"), ("height", "baked"),
                                          ("normal", "osl")])     # osl: the relief image
def test_derived_images_depend_on_exactly_their_declared_parameters(kind, source):
    """A parameter not naming a derived image in `derives` never changes it (else the image
    would go stale: its key would not see the change); one naming it changes its key."""
    imgs = images(kind)
    base = base_params(kind)
    base.shadows.source = source
    before = made(base, imgs)
    for prm in params.PARAMS:
        value = getattr(getattr(base, prm.section), prm.key)
        for v in alternatives(prm, value):
            after = made(with_value(base, prm, v), imgs)
            for channel in before.keys() & after.keys():
                (key0, a0), (key1, a1) = before[channel], after[channel]
                same = (a0 is None and a1 is None) or (
                    a0 is not None and a1 is not None and np.array_equal(a0, a1))
                if channel not in prm.derives:
                    assert same and key0 == key1, \
                        f"{prm.path} = {v!r} changes the derived {channel} image"
                elif not same:
                    assert key0 != key1, f"{prm.path} = {v!r}: {channel} changed, key did not"


def bake(p, imgs):
    n, z, slopes = shape_normals(imgs["shape"], p, np.float32)
    return [shadow_term(n, z, slopes, light, p) for light in
            (Light("sun", (0.5, -0.3, 0.45)), Light("point", (-0.2, 0.1, 0.3)))]


def test_bake_parameters_are_exactly_those_that_change_the_bake():
    """The bake's key is made of the `bake` parameters: any other never changes its result,
    and each of them changes it (for some value, with one kind of shape image or the other)."""
    changes = {}
    for kind, relief in (("normal", "integrated"), ("normal", "along_ray"), ("whirl", "along_ray"),
                         ("height", "")):
        imgs = images(kind)
        base = base_params("normal" if kind == "whirl" else kind)
        base.shape.preblur = 1.0
        base.shadows.relief = relief or base.shadows.relief      # reach: along the ray only
        before = bake(base, imgs)
        for prm in params.PARAMS:
            if prm.path == "shape.kind":
                continue
            value = getattr(getattr(base, prm.section), prm.key)
            for v in alternatives(prm, value):
                after = bake(with_value(base, prm, v), imgs)
                differs = any(not np.array_equal(a, b) for a, b in zip(before, after))
                if not prm.bake:
                    assert not differs, f"{prm.path} = {v!r} changes the bake: declare bake=True"
                changes[prm.path] = changes.get(prm.path, False) or differs
    declared = {prm.path for prm in params.PARAMS if prm.bake} - {"shape.kind"}
    assert {path for path in declared if not changes[path]} == set()


def test_panels_show_every_parameter_once():
    shown = [s for _, sections in params.PANELS.values() for s in sections]
    assert sorted(shown) == sorted(params.SECTIONS)
    for prm in params.PARAMS:       # (prm.panel would raise, not fail, for a lost section)
        assert sum(prm.section in sections for _, sections in params.PANELS.values()) == 1, \
            prm.path
        if prm.header:
            assert prm.kind is bool
        if prm.shown_if:
            path, value = prm.shown_if
            assert value in params.BY_PATH[path].choices
