"""Fills and lines drawn by numpy (core/raster.py, issue 61): each pixel's covered area
against a fine grid of samples, on polygons of every kind — convex, concave, crossing
themselves (the non-zero rule), partly off the image — and round-capped lines; the 16-bit
sRGB table against the exact encoding."""
import numpy as np
import pytest

from dynpaint_addon.core.colour import linear_to_srgb, linear_to_srgb16
from dynpaint_addon.core.raster import over, polygon_coverage, stroke_coverage, whole

SAMPLES = 32         # per pixel side: the reference's grid (area to 1/1024 of a pixel)


def _winding(points, x, y):
    """The winding number of the closed polygon `points` about each point (x, y)."""
    w = np.zeros(np.broadcast(x, y).shape, np.int32)
    for (ax, ay), (bx, by) in zip(points, np.roll(points, -1, axis=0)):
        cross = (bx - ax) * (y - ay) - (x - ax) * (by - ay)
        w += ((ay <= y) & (by > y) & (cross > 0)).astype(np.int32)
        w -= ((by <= y) & (ay > y) & (cross < 0)).astype(np.int32)
    return w


def _reference(points, h, w):
    """Each pixel's share of a SAMPLES² grid inside `points` by the non-zero rule."""
    s = (np.arange(SAMPLES) + 0.5) / SAMPLES
    ys = (np.arange(h)[:, None] + s).ravel()
    xs = (np.arange(w)[:, None] + s).ravel()
    inside = _winding(points, xs[None, :], ys[:, None]) != 0
    return inside.reshape(h, SAMPLES, w, SAMPLES).mean(axis=(1, 3))


def _star(cx, cy, r, k=5, step=2):
    a = np.pi / 2 + 2 * np.pi * step * np.arange(k) / k
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def _rotate(points, centre, angle):
    c, s = np.cos(angle), np.sin(angle)
    d = points - centre
    return np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]]) + centre


SHAPES = {
    "square half off the image": np.array([[-3.3, 2.2], [9.7, 2.2], [9.7, 30.1], [-3.3, 30.1]]),
    "thin sliver": np.array([[2.1, 3.0], [27.9, 4.2], [27.5, 4.9]]),
    "concave": np.array([[2, 2], [28, 3], [15, 12.5], [27, 26], [3.5, 27]], float),
    "pentagram (crosses itself)": _star(15.3, 14.6, 13.0),
    "clockwise disc off the top": np.column_stack(
        [16 + 11 * np.cos(-np.linspace(0, 2 * np.pi, 40, endpoint=False)),
         25 + 11 * np.sin(-np.linspace(0, 2 * np.pi, 40, endpoint=False))]),
}


@pytest.mark.parametrize("name", SHAPES)
def test_a_fills_coverage_is_each_pixels_area_inside_it(name):
    points = SHAPES[name]
    got = whole(polygon_coverage(points, 30, 31), 30, 31)
    ref = _reference(points, 30, 31)
    err = np.abs(got - ref)
    if "crosses" in name:
        # a pixel holding a twice-covered part and an uncovered one is over-covered (its
        # mean winding is clipped, not its winding: the signed-area method's limit) — at
        # the five points where the star's sides cross, nowhere else
        crossing = _star(15.3, 14.6, 13.0 * np.cos(0.4 * np.pi) / np.cos(0.2 * np.pi),
                         step=1)
        y, x = np.mgrid[0:30, 0:31] + 0.5
        near = np.min([np.hypot(x - cx, y - cy) for cx, cy in
                       _rotate(crossing, (15.3, 14.6), np.pi / 5)], axis=0) < 1.5
        assert err[near].max() <= 0.5 and np.count_nonzero(near) <= 5 * 9
        err = err[~near]
    # the grid's own error: a straight side crosses ≤ SAMPLES + 1 of a pixel's samples
    assert err.max() <= 1.5 / SAMPLES
    assert got.min() >= 0 and got.max() <= 1


def test_a_fill_wholly_inside_covers_its_area_exactly():
    rng = np.random.default_rng(7)
    for _ in range(20):
        a = np.sort(rng.uniform(0, 2 * np.pi, 50))
        r = rng.uniform(5, 30, 50)
        points = np.column_stack([40 + r * np.cos(a), 40 + r * np.sin(a)])   # star-shaped
        area = 0.5 * abs(np.sum(points[:, 0] * np.roll(points[:, 1], -1)
                                - np.roll(points[:, 0], -1) * points[:, 1]))
        cover, (r0, c0) = polygon_coverage(points, 80, 80)
        assert cover.sum() == pytest.approx(area, rel=1e-5)
        assert r0 == int(np.floor(points[:, 1].min())) and c0 == int(np.floor(points[:, 0].min()))


def test_a_fill_off_the_image_covers_nothing():
    cover, _ = polygon_coverage(np.array([[-9, -9], [-2, -9], [-2, -2]], float), 10, 10)
    assert cover.size == 0
    assert not whole(polygon_coverage(SHAPES["concave"] + 100, 30, 31), 30, 31).any()


def test_a_lines_coverage_is_its_round_capped_band():
    """A straight line of radius r, length L: area 2rL + πr² (to the ramp's error on the
    caps), 1 on its centre line, 0 a pixel beyond its side, ½ at its side."""
    p = np.array([[5.3, 10.2], [25.8, 17.9]])
    r = 3.2
    cover = whole(stroke_coverage(p, [r, r], 30, 32), 30, 32)
    length = np.hypot(*(p[1] - p[0]))
    assert cover.sum() == pytest.approx(2 * r * length + np.pi * r * r, rel=0.01)
    y, x = np.mgrid[0:30, 0:32] + 0.5
    t = np.clip(((x - p[0, 0]) * (p[1, 0] - p[0, 0]) + (y - p[0, 1]) * (p[1, 1] - p[0, 1]))
                / length ** 2, 0, 1)
    d = np.hypot(x - p[0, 0] - t * (p[1, 0] - p[0, 0]), y - p[0, 1] - t * (p[1, 1] - p[0, 1]))
    assert np.all(cover[d <= r - 0.5] == 1) and np.all(cover[d >= r + 0.5] == 0)


def test_a_line_crossing_itself_covers_once_and_carries_its_points_values():
    loop = np.array([[4, 4], [26, 26], [26, 4], [4, 26]], float)       # an X, closed
    values = np.array([[0.0], [1.0], [0.0], [1.0]])
    cover, field, at = stroke_coverage(loop, np.full(4, 2.0), 30, 30, values=values)
    assert cover.max() == 1                                 # where it crosses: once
    middle = field[15 - at[0], 15 - at[1], 0]
    assert middle == pytest.approx(0.5, abs=0.05)           # halfway along both diagonals
    near_start = field[int(5 - at[0]), int(5 - at[1]), 0]
    assert near_start < 0.1


def test_over_composites_premultiplied_in_its_box():
    rgba = np.zeros((6, 6, 4), np.float32)
    over(rgba, (1.0, 0.0, 0.0), (np.ones((2, 3), np.float32), (1, 2)), 0.5)
    over(rgba, (0.0, 0.0, 1.0), (np.ones((2, 2), np.float32), (2, 3)), 1.0)
    assert rgba[1, 2].tolist() == [0.5, 0, 0, 0.5]
    assert rgba[2, 3].tolist() == [0, 0, 1, 1]
    assert rgba[0].sum() == 0 and rgba[:, 5].sum() == 0


def test_the_16_bit_srgb_table_is_within_a_code_of_the_exact_encoding():
    x = np.concatenate([np.linspace(0, 1, 200001), np.random.default_rng(3).random(100000),
                        [-0.5, 0.0031308, 1.5]]).astype(np.float32)
    exact = np.round(linear_to_srgb(np.clip(x.astype(np.float64), 0, 1)) * 65535)
    codes = linear_to_srgb16(x) * 65535
    assert np.abs(codes - exact).max() <= 1.0001
    assert np.mean(np.abs(codes - exact) > 0.5) < 0.05     # (1.6 % measured)
