"""§3 Clamp&Step, §4 diffuse, §5 mixing, §7 specular."""
import numpy as np
import pytest

from dynpaint_addon.core.colour import linear_to_srgb
from dynpaint_addon.core.shading import (barycentric_mix, clamp_step, light_weight,
                                         opaque_highlight, specular_term)


def test_classic_and_gooch_terms():
    t = np.linspace(-1, 1, 201).astype(np.float32)
    np.testing.assert_allclose(clamp_step(t, 0, 1), np.maximum(t, 0), atol=1e-7)   # classic
    np.testing.assert_allclose(clamp_step(t, -1, 1), (t + 1) / 2, atol=1e-7)       # Gooch


@pytest.mark.parametrize("curve", ["linear", "smoothstep", "smootherstep"])
def test_t0_equals_t1_is_a_heaviside_step(curve):
    """§14: t0 = t1 → Heaviside step, only 0 or 1, never NaN."""
    t = np.array([-1, 0.29, 0.3, 0.30001, 1, np.float32(0.3)], np.float32)
    out = clamp_step(t, 0.3, 0.3, curve)
    assert set(np.unique(out)) <= {0.0, 1.0}
    np.testing.assert_array_equal(out, [0, 0, 0, 1, 1, 0])


def test_curves_and_inversion():
    u = np.linspace(0, 1, 11)
    np.testing.assert_allclose(clamp_step(u, 0, 1, "smoothstep"), 3 * u**2 - 2 * u**3, atol=1e-12)
    np.testing.assert_allclose(clamp_step(u, 0, 1, "smootherstep"),
                               6 * u**5 - 15 * u**4 + 10 * u**3, atol=1e-12)
    np.testing.assert_allclose(clamp_step(u, 1, 0), 1 - u, atol=1e-12)   # t0 > t1 inverts
    np.testing.assert_allclose(clamp_step(np.array([-5.0, 5.0]), 0.2, 0.6), [0, 1])


def test_coloured_lights_tint_the_mix():
    """§5: W = clip(Σ k_i c_i t_i, 0, 1) per channel; C_d = C0(1 − W) + C1·W."""
    t1 = np.full((1, 1), 0.5, np.float32)
    t2 = np.full((1, 1), 0.8, np.float32)
    w = light_weight([t1, t2], [(1, 0, 0), (0, 0.5, 1)], [1.0, 2.0])
    np.testing.assert_allclose(w[0, 0], [0.5, 0.8, 1.0])     # blue clipped at 1
    c0 = np.array([0.1, 0.2, 0.3], np.float32)
    c1 = np.array([0.9, 0.8, 0.7], np.float32)
    np.testing.assert_allclose(barycentric_mix(c0, c1, w, "linear")[0, 0],
                               c0 * (1 - w[0, 0]) + c1 * w[0, 0])


def test_painted_mix_is_the_mix_of_the_colours_as_painted():
    """§5 painted: half-way between black and white painted is 50 % grey as painted (0.5 on
    screen), not 50 % linear light (0.735 on screen, 60 levels of 255 lighter); the ends are
    the images themselves."""
    black, white = np.zeros(3, np.float32), np.ones(3, np.float32)
    half = np.full(3, 0.5, np.float32)
    painted = barycentric_mix(black, white, half, "painted")
    linear = barycentric_mix(black, white, half, "linear")
    np.testing.assert_allclose(linear_to_srgb(painted), 0.5, atol=1e-6)
    np.testing.assert_allclose(linear_to_srgb(linear), 0.7354, atol=1e-4)
    c0 = np.array([0.02, 0.3, 0.7], np.float32)
    c1 = np.array([0.9, 0.05, 0.4], np.float32)
    for w in (0.0, 1.0):
        np.testing.assert_allclose(barycentric_mix(c0, c1, np.full(3, w, np.float32), "painted"),
                                   c1 if w else c0, rtol=1e-5, atol=1e-7)
    with pytest.raises(ValueError, match="unknown mix space"):
        barycentric_mix(c0, c1, half, "ok")


def test_specular_is_gated_on_the_unlit_side():
    """§7: R_L = 2(N·L)N − L, s = CS(R_L.z), 0 where N·L ≤ 0."""
    rng = np.random.default_rng(5)
    n = rng.normal(size=(4000, 3))
    n[:, 2] = np.abs(n[:, 2])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    l = rng.normal(size=(4000, 3))
    l /= np.linalg.norm(l, axis=1, keepdims=True)
    s = specular_term(n, l, 0.0, 1.0)
    ndl = np.sum(n * l, axis=1)
    r_z = 2 * ndl * n[:, 2] - l[:, 2]
    assert np.all(s[ndl <= 0] == 0)
    np.testing.assert_allclose(s[ndl > 0], np.clip(r_z[ndl > 0], 0, 1), atol=1e-12)
    # without the gate, some unlit pairs would have had a highlight
    assert np.mean((ndl <= 0) & (r_z > 0)) > 0.02
    # a mirror direction: light along the normal reflects straight to the eye
    assert specular_term(np.array([0, 0, 1.0]), np.array([0, 0, 1.0]), 0.9, 1.0) == 1


def test_opaque_highlight():
    c = opaque_highlight(np.array([0.2, 0.2, 0.2]), np.array([1.0, 0.5, 0.0]), np.array([0.5] * 3))
    np.testing.assert_allclose(c, [0.6, 0.35, 0.1])
