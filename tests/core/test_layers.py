"""§15 Layers, the core's reference: what the layers in front of a pixel let through along its
§6 ray (issue 30, first step: layers on one canvas, lights without size)."""
import numpy as np
import pytest

from dynpaint_addon.core.layers import Occluder, transmittance
from dynpaint_addon.core.lights import Light
from dynpaint_addon.core.sampling import pixel_centres

N = 64


def plane_origins(z=0.0):
    """P0 of a flat layer at depth z (pixels): its pixel centres."""
    x, y = pixel_centres(N, N, np.float64)
    return np.dstack([x, y, np.full((N, N), z)])


def card(lo, hi, z, thickness=2.0, opacity=1.0):
    """A flat square card covering pixels lo … hi − 1 in x and y."""
    alpha = np.zeros((N, N))
    alpha[lo:hi, lo:hi] = 1.0
    return Occluder(alpha, np.zeros((N, N)), z, thickness, np.full((N, N), opacity))


def card_shadow(lo, hi, z, thickness, direction):
    """Where a flat card's solid (its square, z − thickness … z) shades a plane at z = 0 under
    a sun along `direction`: the union of the square shifted back along the light over the
    card's depths → (certainly in shadow, certainly lit), each with a 2-pixel margin."""
    x, y, _ = np.moveaxis(plane_origins(), -1, 0)
    lx, ly, lz = np.asarray(direction) / np.linalg.norm(direction)
    depths = np.linspace(z - thickness, z, 41)
    dist = np.full((N, N), np.inf)               # distance from the square at any depth
    for d in depths:
        cx, cy = x + lx / lz * d, y + ly / lz * d
        dx = np.maximum(np.maximum(lo - cx, cx - hi), 0)
        dy = np.maximum(np.maximum(lo - cy, cy - hi), 0)
        inside = np.minimum(np.minimum(cx - lo, hi - cx), np.minimum(cy - lo, hi - cy))
        dist = np.minimum(dist, np.where((dx > 0) | (dy > 0), np.hypot(dx, dy), -inside))
    return dist < -2, dist > 2


def test_nothing_in_front_lets_everything_through():
    assert np.array_equal(transmittance(plane_origins(), Light("sun", (0.3, 0.2, 0.9)), []),
                          np.ones((N, N)))


@pytest.mark.parametrize("direction", [(0.0, 0.0, 1.0), (0.3, 0.2, 0.9), (-0.5, 0.4, 0.7)])
def test_an_opaque_card_casts_its_projected_shadow(direction):
    """§15: an opaque card in front of a plane: T = 0 in its shadow (the card's solid
    projected along the light), 1 outside it."""
    t = transmittance(plane_origins(), Light("sun", direction), [card(24, 40, 16.0)])
    shadow, lit = card_shadow(24, 40, 16.0, 2.0, direction)
    assert shadow.sum() > 100 and lit.sum() > 1000
    assert t[shadow].max() == 0.0 and t[lit].min() == 1.0


def test_a_glass_card_lets_its_transparency_through():
    """k = 0.6 (opacity 0.4): 0.6 of the light in its shadow (§15's example)."""
    direction = (0.3, 0.2, 0.9)
    t = transmittance(plane_origins(), Light("sun", direction), [card(24, 40, 16.0, opacity=0.4)])
    shadow, lit = card_shadow(24, 40, 16.0, 2.0, direction)
    assert np.allclose(t[shadow], 0.6) and t[lit].min() == 1.0


def test_two_cards_multiply():
    t = transmittance(plane_origins(), Light("sun", (0, 0, 1)),
                      [card(24, 40, 16.0, opacity=0.5), card(30, 50, 30.0, opacity=0.5)])
    assert t[32, 32] == pytest.approx(0.25) and t[26, 26] == pytest.approx(0.5)
    assert t[45, 45] == pytest.approx(0.5) and t[5, 5] == 1.0


def test_a_point_light_casts_a_central_projection_and_layers_behind_never_shade():
    """Aimed at a point light above the canvas's centre, the pixel under the card is in its
    shadow, a far corner sees the light past it; a card behind the receiver casts nothing;
    a ray that ends at a light below the card is not shaded by it."""
    light = Light("point", (0.0, 0.0, 1.0))         # one image width above the centre
    t = transmittance(plane_origins(), light, [card(28, 36, 16.0)])
    assert t[32, 32] == 0.0 and t[0, 0] == 1.0 and t[63, 63] == 1.0
    behind = transmittance(plane_origins(20.0), light, [card(28, 36, 16.0)])
    assert behind.min() == 1.0
    low = Light("point", (0.0, 0.0, 10.0 / N))       # 10 px up: below the card at 14–16 px
    assert transmittance(plane_origins(), low, [card(28, 36, 16.0)]).min() == 1.0
