"""Example artworks in the conventions other tools and artists use (issue 15), made by numpy.

Test data and the pictures of docs/real-paintings.md come from here, never from an outside image
set. Arrays are y-up like the core's (row 0 at the bottom, pipeline.md §0), values in [0, 1].

    >>> n, facet = penrose_triangle(96)
    >>> n.shape, n[0, 0].tolist()        # the canvas faces the viewer
    ((96, 96, 3), [0.0, 0.0, 1.0])
    >>> float(np.unique(n[facet > 0][:, 2]).round(3)[0])   # every facet tilted alike: 1/√3
    0.577
"""
import numpy as np

# An isometric view (pipeline.md §0 painting frame: x right, y up, z toward the viewer): the
# camera looks along −(1, 1, 1), so a cube shows its +x, +y and +z faces.
_RIGHT = np.array([1.0, -1.0, 0.0]) / np.sqrt(2)
_UP = np.array([-1.0, -1.0, 2.0]) / np.sqrt(6)
_VIEW = np.array([1.0, 1.0, 1.0]) / np.sqrt(3)
_FACES = {   # outward normal → (corner offset, the two edges spanning the face)
    (0, 0, 1): ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    (1, 0, 0): ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    (0, 1, 0): ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
}


def _screen(p):
    return np.array([np.dot(p, _RIGHT), np.dot(p, _UP)])


def penrose_triangle(size, bar=7):
    """A Penrose tribar drawn as flat facets, isometric: three bars of `bar` cubes along x,
    y and z whose ends meet in the picture but not in space (the first cube is drawn over the
    last, which no solid allows). → (unit normals (size, size, 3) with (0, 0, 1) on the
    background, facet index (size, size): 0 background, 1 + 3·cube + face)."""
    cubes = [(i, 0, 0) for i in range(bar)] + [(bar - 1, j, 0) for j in range(1, bar)] \
        + [(bar - 1, bar - 1, k) for k in range(1, bar)]
    order = sorted(range(1, len(cubes)), key=lambda c: sum(cubes[c])) + [0]   # far → near
    corners = np.array([_screen(np.add(c, o)) for c in cubes for o in np.ndindex(2, 2, 2)])
    lo, hi = corners.min(0), corners.max(0)
    span = (hi - lo).max() * 1.15
    centre = (lo + hi) / 2
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    px, py = centre[0] + x * span, centre[1] + y * span
    normals = np.zeros((size, size, 3))
    normals[..., 2] = 1.0
    facet = np.zeros((size, size), int)
    for c in order:
        for f, (normal, (corner, e1, e2)) in enumerate(_FACES.items()):
            o = _screen(np.add(cubes[c], corner))
            a, b = _screen(np.array(e1, float)), _screen(np.array(e2, float))
            det = a[0] * b[1] - a[1] * b[0]
            s = ((px - o[0]) * b[1] - (py - o[1]) * b[0]) / det
            t = (a[0] * (py - o[1]) - a[1] * (px - o[0])) / det
            on = (s >= 0) & (s <= 1) & (t >= 0) & (t <= 1)
            n = np.array(normal, float)
            normals[on] = [np.dot(n, _RIGHT), np.dot(n, _UP), np.dot(n, _VIEW)]
            facet[on] = 1 + 3 * c + f
    return normals, facet


def normal_map_rgb(normals):
    """The usual 8-bit-style encoding C = (N + 1)/2 of unit normals (red x, green y, blue z)."""
    return (np.asarray(normals) + 1) / 2


def normal_map_rg(normals):
    """Two-channel convention: x and y in red and green, blue 0 (z = √(1 − x² − y²))."""
    c = normal_map_rgb(normals)
    c[..., 2] = 0.0
    return c


def normal_map_halving(normals):
    """A map painted for a decoder that halves every tilt (N = normalize((0, 0, 1) + M)):
    stores M, the normal whose tilt from +z is twice the drawn one (azimuth kept)."""
    n = np.asarray(normals, float)
    tilt = np.arccos(np.clip(n[..., 2], -1, 1))
    rxy = np.hypot(n[..., 0], n[..., 1])
    scale = np.where(rxy > 0, np.sin(2 * tilt) / np.where(rxy > 0, rxy, 1), 0)
    m = np.stack([n[..., 0] * scale, n[..., 1] * scale, np.cos(2 * tilt)], -1)
    return normal_map_rgb(m)


def normal_map_all_away(normals, length=1.4):
    """A map like the original research system's (issue 38: Picasso's self-portrait): painted
    for the halving decoder with every drawn tilt between 55° and 90° (the stored, doubled ones
    110°–180°: every pixel faces away, blue 0 … 0.17) and vectors `length` long, not unit (each
    channel clipped to 0..1, as a file holds it)."""
    n = np.asarray(normals, float)
    tilt = np.radians(55) + np.arccos(np.clip(n[..., 2], -1, 1)) * (35 / 90)
    azimuth = np.arctan2(n[..., 1], n[..., 0])
    stored = length * np.stack([np.sin(2 * tilt) * np.cos(azimuth),
                                np.sin(2 * tilt) * np.sin(azimuth), np.cos(2 * tilt)], -1)
    return np.clip(normal_map_rgb(stored), 0, 1)


def antialiased_cutout(normal_map, inside, size, samples=4):
    """A cut-out normal map as painting programs export one: RGBA whose alpha is the figure's
    coverage (`samples`² per pixel, so its edge is antialiased) and whose colour is
    premultiplied by it (a black fringe: the edge's vectors face away)."""
    y, x = (np.mgrid[0:size * samples, 0:size * samples] + 0.5) / (size * samples) - 0.5
    fine = (np.hypot(x, y) < 0.4).astype(float)
    cover = fine.reshape(size, samples, size, samples).mean(axis=(1, 3))
    rgb = np.where(inside[..., None] | (cover[..., None] > 0), normal_map, normal_map_rgb(
        np.array([0.0, 0.0, 1.0])))
    return np.concatenate([rgb * cover[..., None], cover[..., None]], -1)


def red_mask(mask):
    """A mask painted in pure red on black (one colour channel), as RGB."""
    m = np.asarray(mask, float)
    return np.stack([m, np.zeros_like(m), np.zeros_like(m)], -1)


def photograph(h, w, seed=0):
    """A photograph-like environment: a sky gradient over a darker ground with soft
    'trees' (its left and right edges differ, as a photograph's do: wrapping shows a seam)."""
    rng = np.random.default_rng(seed)
    y, x = (np.mgrid[0:h, 0:w] + 0.5) / np.array([h, w])[:, None, None]
    sky = np.stack([0.35 + 0.4 * y, 0.55 + 0.35 * y, 0.85 + 0.1 * y], -1)
    ground = np.stack([0.25 + 0.3 * x, 0.3 + 0.15 * x, 0.12 + 0.05 * x], -1)
    horizon = 0.35 + 0.08 * np.sin(6 * x) + 0.05 * x
    img = np.where((y < horizon)[..., None], ground, sky)
    for _ in range(6):
        cx, cy, r = rng.uniform(0.05, 0.95), rng.uniform(0.35, 0.6), rng.uniform(0.04, 0.1)
        blob = np.exp(-((x - cx) ** 2 + ((y - cy) * 0.7) ** 2) / (2 * r * r))
        img = img * (1 - 0.6 * blob[..., None]) + 0.6 * blob[..., None] * np.array([0.1, 0.3, 0.1])
    return np.clip(img, 0, 1)


def sphere(size, radius=0.4):
    """A hemisphere of the given radius (image widths) in the middle: unit normals and its
    disc mask."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size - 0.5
    r2 = (x * x + y * y) / (radius * radius)
    inside = r2 < 1
    z = np.sqrt(np.clip(1 - r2, 0, 1))
    n = np.where(inside[..., None], np.stack([x / radius, y / radius, z], -1), [0.0, 0.0, 1.0])
    return n / np.linalg.norm(n, axis=-1, keepdims=True), inside


def _far_from_edges(facet, radius):
    """Pixels with no other facet within `radius` pixels (square window)."""
    edge = np.zeros(facet.shape, bool)
    edge[:, 1:] |= facet[:, 1:] != facet[:, :-1]
    edge[:, :-1] |= facet[:, 1:] != facet[:, :-1]
    edge[1:] |= facet[1:] != facet[:-1]
    edge[:-1] |= facet[1:] != facet[:-1]
    near = edge.copy()
    for axis in (0, 1):
        grown = near.copy()
        for s in range(1, radius + 1):
            grown |= np.roll(near, s, axis) | np.roll(near, -s, axis)
        near = grown
    return ~near


def streak_share(t, n, light, facet, radius):
    """The measure of point 5 of issue 15: on a figure drawn as flat facets, each facet is a
    plane, lit t = max(N·L, 0) (§6); a streak is a pixel farther than `radius` from any other
    facet whose t is off that by more than 0.1. → share of such pixels among those far ones."""
    far = _far_from_edges(facet, radius)
    v = np.asarray(light.vector, np.float64)
    want = np.clip(n @ (v / np.linalg.norm(v)), 0, 1)
    return float((np.abs(t - want) > 0.1)[far].mean())
