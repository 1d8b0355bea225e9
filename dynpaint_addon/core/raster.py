"""Filled shapes and round-capped lines drawn into pixels (issue 61: a Grease Pencil drawing's
layers drawn by numpy, in a worker thread, instead of by Blender's renderer on its main one).

Coverage is each pixel's covered area, exactly for a fill (signed-area accumulation: every
edge, cut where it crosses a pixel's side, adds its signed height to the cells on its right,
and a running sum along each row gives the winding; |winding| clipped to 1 is the non-zero
rule, anti-aliased by area; a pixel that holds both a part a self-crossing fill covers
twice and an uncovered part is over-covered) and to a pixel's width for a line (its distance to the stroke's
centre line against the radius there, ramped over one pixel — exact along a straight side).
Pixels are unit squares, (x, y) in pixels from the image's lower-left corner (§0: row 0 at
the bottom).

    >>> import numpy as np
    >>> square = np.array([[1.5, 1.0], [3.5, 1.0], [3.5, 2.5], [1.5, 2.5]])
    >>> cover = whole(polygon_coverage(square, 4, 5), 4, 5)
    >>> float(cover.sum()), cover[1].round(2).tolist()
    (3.0, [0.0, 0.5, 1.0, 0.5, 0.0])
    >>> line = whole(stroke_coverage(np.array([[1.0, 2.5], [4.0, 2.5]]), np.array([0.5, 0.5]),
    ...                              4, 6), 4, 6)
    >>> line[2].round(2).tolist(), float(line.sum())     # its centre row: caps, then full
    ([0.5, 1.0, 1.0, 1.0, 0.5, 0.0], 4.0)
"""
import numpy as np


def _cut_at_pixel_sides(x0, y0, x1, y1):
    """Edges (arrays of their ends) cut where they cross an integer x or y → the pieces'
    ends (xa, ya, xb, yb), each piece inside one pixel, in order along its edge."""
    def crossings(a, b):
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        first = np.floor(lo) + 1
        count = np.maximum(0, np.ceil(hi) - first).astype(np.int64)    # integers in (lo, hi)
        edge = np.repeat(np.arange(a.size), count)
        k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (first[edge] + k - a[edge]) / (b - a)[edge]
        return edge, t
    ex, tx = crossings(x0, x1)
    ey, ty = crossings(y0, y1)
    n = x0.size
    edge = np.concatenate([np.arange(n), np.arange(n), ex, ey])
    t = np.concatenate([np.zeros(n), np.ones(n), tx, ty])
    order = np.lexsort((t, edge))
    edge, t = edge[order], t[order]
    same = edge[1:] == edge[:-1]
    e, ta, tb = edge[1:][same], t[:-1][same], t[1:][same]
    dx, dy = x1 - x0, y1 - y0
    return x0[e] + ta * dx[e], y0[e] + ta * dy[e], x0[e] + tb * dx[e], y0[e] + tb * dy[e]


def polygon_coverage(points, height, width):
    """The area of each pixel of a height × width image inside the closed polygon `points`
    ((N, 2) x, y in pixels; several loops: a list of such arrays) by the non-zero rule →
    (coverage (h, w) float32 in 0..1, (r0, c0)): the box of the image it can touch, at row
    r0, column c0 (whole() puts it in the image)."""
    loops = [np.asarray(points, np.float64)] if np.ndim(points) == 2 else \
        [np.asarray(p, np.float64) for p in points]
    ends = [(p, np.roll(p, -1, axis=0)) for p in loops if len(p) >= 3]
    if not ends:
        return np.zeros((0, 0), np.float32), (0, 0)
    a = np.concatenate([s for s, _ in ends])
    b = np.concatenate([e for _, e in ends])
    both = np.concatenate([a, b])
    r0, c0 = (max(0, int(np.floor(v))) for v in both.min(axis=0)[::-1])
    r1, c1 = min(height, int(np.ceil(both[:, 1].max()))), min(width, int(np.ceil(both[:, 0].max())))
    if r0 >= r1 or c0 >= c1:
        return np.zeros((0, 0), np.float32), (0, 0)
    h, w = r1 - r0, c1 - c0
    a, b = a - (c0, r0), b - (c0, r0)                        # the box's own pixels
    keep = (a[:, 1] != b[:, 1]) & (np.maximum(a[:, 1], b[:, 1]) > 0) & \
        (np.minimum(a[:, 1], b[:, 1]) < h) & (np.minimum(a[:, 0], b[:, 0]) < w)
    xa, ya, xb, yb = _cut_at_pixel_sides(a[keep, 0], a[keep, 1], b[keep, 0], b[keep, 1])
    row = np.floor((ya + yb) / 2).astype(np.int64)
    xa, xb = np.clip(xa, 0, w), np.clip(xb, 0, w)           # left of the box: its edge
    xm = (xa + xb) / 2
    col = np.minimum(np.floor(xm), w - 1).astype(np.int64)
    inside = (row >= 0) & (row < h) & (xm < w)
    dy, frac, at = (yb - ya)[inside], (xm - col)[inside], (row * (w + 1) + col)[inside]
    # a piece's height counts in full right of its cell, and in its cell the share of the
    # cell's width right of its middle (its trapezoid's area)
    size = h * (w + 1)
    acc = np.bincount(at, dy * (1 - frac), size) + np.bincount(at + 1, dy * frac, size)
    winding = np.cumsum(acc.reshape(h, w + 1)[:, :w], axis=1)
    return np.minimum(np.abs(winding), 1.0).astype(np.float32), (r0, c0)


def stroke_coverage(points, radii, height, width, cyclic=False, values=None):
    """The coverage of a round-capped line through `points` ((N, 2) x, y in pixels) of
    `radii` (N, pixels; linear between points) in a height × width image: 1 within the
    radius of the centre line, ramped to 0 over the pixel beyond (a pixel's centre half a
    pixel inside the side: ½) — one stroke covers a pixel once where it crosses itself →
    (coverage, (r0, c0)) as polygon_coverage's; with `values` (N, K: the points' colours,
    opacities), (coverage, their values at the nearest point of the line (h, w, K),
    (r0, c0))."""
    p = np.asarray(points, np.float64)
    r = np.asarray(radii, np.float64)
    v = None if values is None else np.asarray(values, np.float32).reshape(len(p), -1)
    if cyclic and len(p) > 2:
        p, r = np.vstack([p, p[:1]]), np.concatenate([r, r[:1]])
        v = None if v is None else np.vstack([v, v[:1]])
    if len(p) == 1:
        p, r = np.vstack([p, p]), np.concatenate([r, r])
        v = None if v is None else np.vstack([v, v])
    reach = r.max() + 1.0
    r0, c0 = max(0, int(np.floor(p[:, 1].min() - reach))), \
        max(0, int(np.floor(p[:, 0].min() - reach)))
    r1, c1 = min(height, int(np.ceil(p[:, 1].max() + reach))), \
        min(width, int(np.ceil(p[:, 0].max() + reach)))
    r0, c0, r1, c1 = (0, 0, 0, 0) if r0 >= r1 or c0 >= c1 else (r0, c0, r1, c1)
    out = np.zeros((r1 - r0, c1 - c0), np.float32)
    field = None if v is None else np.zeros((*out.shape, v.shape[1]), np.float32)
    p = p - (c0, r0)
    for i in range(len(p) - 1 if out.size else 0):
        (ax, ay), (bx, by), ra, rb = p[i], p[i + 1], r[i], r[i + 1]
        reach = max(ra, rb) + 1.0
        x0, x1 = max(0, int(np.floor(min(ax, bx) - reach))), \
            min(out.shape[1], int(np.ceil(max(ax, bx) + reach)))
        y0, y1 = max(0, int(np.floor(min(ay, by) - reach))), \
            min(out.shape[0], int(np.ceil(max(ay, by) + reach)))
        if x0 >= x1 or y0 >= y1:
            continue
        x = np.arange(x0, x1) + 0.5 - ax
        y = (np.arange(y0, y1) + 0.5 - ay)[:, None]
        dx, dy = bx - ax, by - ay
        length2 = dx * dx + dy * dy
        t = np.clip((x * dx + y * dy) / length2, 0, 1) if length2 > 0 else \
            np.zeros((y1 - y0, x1 - x0))
        d = np.hypot(x - t * dx, y - t * dy)
        cover = np.clip(ra + t * (rb - ra) - d + 0.5, 0, 1).astype(np.float32)
        box = out[y0:y1, x0:x1]
        if field is not None:          # the values of the segment that covers most
            nearer = cover > box
            t = t.astype(np.float32)[..., None]
            field[y0:y1, x0:x1][nearer] = ((1 - t) * v[i] + t * v[i + 1])[nearer]
        np.maximum(box, cover, out=box)
    return (out, (r0, c0)) if field is None else (out, field, (r0, c0))


def whole(coverage, height, width):
    """A coverage and its box's corner (polygon_coverage's) as the whole height × width
    image."""
    cover, (r0, c0) = coverage
    out = np.zeros((height, width), np.float32)
    out[r0:r0 + cover.shape[0], c0:c0 + cover.shape[1]] = cover
    return out


def over(under, colour, coverage, opacity=1.0):
    """Premultiplied RGBA `under` (H, W, 4, updated in place) with `colour` (linear RGB, or
    one per pixel of the coverage's box) drawn over it at a coverage (polygon_coverage's:
    the array and its box's corner) × `opacity` (a number, or one per pixel) → under."""
    cover, (r0, c0) = coverage
    if not cover.size or np.all(np.asarray(opacity) <= 0):
        return under
    box = under[r0:r0 + cover.shape[0], c0:c0 + cover.shape[1]]
    a = (cover * np.asarray(opacity, np.float32))[..., None]
    box *= 1 - a
    box[..., :3] += a * np.asarray(colour, np.float32)
    box[..., 3:] += a
    return under
