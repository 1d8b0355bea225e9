"""Height effects on a made relief (issue 41, point 3; core/effects.py): a bevel from the
figure's edge, smoothing inside it, a tileable structure — each measured on a disc, and in
the order make-shape applies them."""
import numpy as np
import pytest

from dynpaint_addon.core.effects import bevel, edge_distance, smooth, structure
from dynpaint_addon.shapes.relief import with_effects

N = 200
Y, X = (np.mgrid[0:N, 0:N] + 0.5) / N - 0.5
R = 0.4
DISC = X * X + Y * Y < R * R


def test_the_edge_distance_is_euclids_within_its_limit():
    """Against brute force: each pixel's distance to the nearest pixel outside the disc (or
    beyond a small image's border), centre to centre."""
    mask = np.zeros((40, 50), bool)
    mask[3:37, 2:48] = DISC[::5, ::4][:34, :46]
    d = edge_distance(mask, 12)
    ys, xs = np.nonzero(np.pad(~mask, 1, constant_values=True))
    gy, gx = np.mgrid[0:40, 0:50] + 1
    brute = np.sqrt(((gy[..., None] - ys) ** 2 + (gx[..., None] - xs) ** 2).min(axis=-1))
    np.testing.assert_allclose(d, np.where(mask, np.minimum(brute, 12), 0.0), atol=1e-12)


@pytest.mark.parametrize("profile", ["linear", "round"])
def test_a_bevel_rises_from_the_edge_to_its_height_over_its_width(profile):
    z = bevel(DISC, width=0.1, height=0.03, profile=profile)
    r = np.hypot(X, Y)
    assert float(z[r < R - 0.12].min()) == pytest.approx(0.03)        # the plateau
    rim = DISC & (r > R - 0.09)
    outer = float(z[DISC & (r > R - 0.01)].max())        # 2 px in: a ramp's 0.2, a circle's 0.6
    assert float(z[rim].max()) < 0.03 and outer < (0.008 if profile == "linear" else 0.02)
    row = z[N // 2, : N // 2]                                           # edge → centre
    assert np.all(np.diff(row) >= -1e-12)
    assert (z[~DISC] == 0).all()
    if profile == "round":        # a quarter circle stands above the ramp everywhere
        assert np.all(z >= bevel(DISC, 0.1, 0.03, "linear") - 1e-12)


def test_smoothing_keeps_the_edge_up_and_rounds_a_step():
    z = np.where(DISC, np.where(X > 0, 0.05, 0.0), 0.0)                # a step inside
    s = smooth(z, DISC, 0.02)
    assert float(np.abs(np.diff(s[N // 2, 40:160])).max()) < 0.01     # the step spread
    # the edge is not pulled toward the outside's 0: the step's high side stays near 0.05
    edge = DISC & (X > 0.3) & (np.abs(Y) < 0.05)
    assert float(s[edge].min()) > 0.045
    assert (s[~DISC] == 0).all()


def test_a_structure_repeats_every_scale_and_adds_no_mean():
    tile = np.random.default_rng(3).random((16, 16))
    z = structure(tile, np.ones((N, N), bool), scale=0.1, strength=0.01)
    period = int(0.1 * N)
    np.testing.assert_allclose(z[:, period:], z[:, :-period], atol=1e-12)
    np.testing.assert_allclose(z[period:], z[:-period], atol=1e-12)
    assert abs(float(z.mean())) < 1e-4 and float(np.abs(z).max()) <= 0.01


def test_make_shapes_order_keeps_the_structure_sharp():
    """A bevel, then smoothing, then the structure: the pattern is not blurred away."""
    tile = np.tile([[0.0, 1.0]], (2, 1)).repeat(4, axis=1)          # stripes 4 tile px wide
    flat = np.zeros((N, N))
    z = with_effects(flat, DISC, 0.05, 0.02, "round", 0.02, tile, 0.04, 0.01)
    centre = z[N // 2, N // 2 - 20: N // 2 + 20]
    assert float(centre.max() - centre.min()) > 0.008     # the stripes' full swing
