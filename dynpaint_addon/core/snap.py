"""A figure mask painted by hand, snapped onto the painting's own outline (issue 41, "a
painting with no shape image"; docs/shape-from-painting.md).

A hand's mask is seldom on the figure's outline: a brush a little wide, a stroke a pixel or
two off — and a thin part's cast shadow moves with it (docs/no-shape-numbers.md: a torus's
shadows lose a fifth of their IoU to a slip of two pixels). The painting shows where the
outline is: its strongest edge near the mask's. Let s be the signed distance to the mask's
edge (pixels, + inside). Each pixel beside the edge (|s| ≤ 1) looks along the edge's normal,
t = −reach … reach pixels from the edge, for the largest gradient of the painting's
luminance (blurred by `blur` pixels; its offset t* the centroid of that peak's upper half,
within a pixel: sub-pixel, as the interpolated top is flat); the offsets t* found are
smoothed along the edge (a Gaussian of `smooth` pixels, normalised by the edge's own) into a
field δ, and the snapped mask is s > δ: the edge moved onto the painting's. Where the
painting has no edge within reach (no peak of its gradient inside the window, or one
gentler than FLOOR) the offset is 0: the mask's edge stays where it is. The image's border
is not an edge (a figure the frame cuts goes on beyond it).

    >>> import numpy as np
    >>> y, x = np.mgrid[0:64, 0:64] + 0.5
    >>> figure = (x - 32) ** 2 + (y - 32) ** 2 < 20 ** 2        # a dark disc painted on white
    >>> painting = np.where(figure, 0.2, 1.0)
    >>> mask = (x - 34) ** 2 + (y - 31) ** 2 < 20 ** 2          # the hand's: 2 px right, 1 up
    >>> int((mask != figure).sum()), int((snap_to_edges(mask, painting, 3) != figure).sum())
    (180, 20)

(what is left: pixels whose centre lies within a fraction of a pixel of the outline, where
the distance to a mask's pixel edge and to the round outline differ).

Every step reads a bounded neighbourhood (snap_margin_px) and none reads where in the image
it is, so a stroke on the mask is snapped again around its box alone (`resnapped`: Paint
Shape's figure mask), bit for bit what snapping the whole mask gives.
"""
import numpy as np

from .effects import edge_distance
from .sampling import gaussian_blur, gaussian_radius

STEP_PX = 0.25       # the offsets tried along the normal, this far apart
PEAK = 0.5           # the share of its top above which a peak's offsets count
FLOOR = 1e-3         # luminance per pixel: a gentler gradient is no edge


def signed_edge_distance(mask, limit_px):
    """(H, W) pixels from each pixel's centre to the mask's edge, + inside, − outside (the
    edge half a pixel beyond the last pixel's centre), up to limit_px either way; the
    image's border is no edge (the figure and its ground go on beyond it)."""
    pad = int(np.ceil(limit_px)) + 1
    wide = np.pad(np.asarray(mask, bool), pad, mode="edge")
    inside = edge_distance(wide, limit_px + 0.5)[pad:-pad, pad:-pad]
    outside = edge_distance(~wide, limit_px + 0.5)[pad:-pad, pad:-pad]
    return np.where(mask, inside, -outside) - np.where(mask, 0.5, -0.5)


def snapped(mask, luminance, reach, before=None):
    """The mask snapped onto the painting's edges within `reach` image widths (make-shape
    inflate's --snap); as it is where reach is 0 or there is no painting (luminance None).
    before: (an earlier mask, what this gave for it) with the same painting and reach — only
    around what changed is it snapped again (resnapped)."""
    if not reach or luminance is None:
        return np.asarray(mask, bool)
    reach_px = reach * np.shape(mask)[1]
    if before is not None and np.shape(before[0]) == np.shape(mask):
        return resnapped(*before, mask, luminance, reach_px)
    return snap_to_edges(mask, luminance, reach_px)


def snap_margin_px(reach_px, blur_px=0.7, smooth_px=2.0):
    """How far (pixels, along either axis) a change to the mask or the painting can change
    snap_to_edges' result: the offsets' smoothing around each edge pixel, whose own offset
    reads the signed distance (reach + 2 px of mask, +1 for its padding), its normal (a blur
    and a central difference of that) and the painting's gradient along the normal (reach +
    1 px, the bilinear's next pixel, the painting's blur and difference)."""
    distance = int(np.ceil(reach_px + 2.5)) + 1
    normal = distance + gaussian_radius(1.0) + 1
    search = int(np.ceil(reach_px + 1)) + 1 + gaussian_radius(blur_px) + 1
    return gaussian_radius(smooth_px) + max(normal, search)


def _along(img, ys, xs, dx, dy):
    """img bilinearly at (ys + dy, xs + dx) in pixel-centre coordinates, indices clamped to the
    image (its edge extended): the integer part and the fraction split from the offsets alone,
    so the samples do not depend on where in the image (or a crop of it) the pixel lies."""
    h, w = img.shape
    jx, iy = np.floor(dx), np.floor(dy)
    fx, fy = dx - jx, dy - iy
    j0, i0 = xs[:, None] + jx.astype(np.int64), ys[:, None] + iy.astype(np.int64)
    j1, i1 = np.clip(j0 + 1, 0, w - 1), np.clip(i0 + 1, 0, h - 1)
    j0, i0 = np.clip(j0, 0, w - 1), np.clip(i0, 0, h - 1)
    bottom = img[i0, j0] * (1 - fx) + img[i0, j1] * fx
    top = img[i1, j0] * (1 - fx) + img[i1, j1] * fx
    return bottom * (1 - fy) + top * fy


def snap_to_edges(mask, luminance, reach_px, blur_px=0.7, smooth_px=2.0):
    """The mask (H, W) bool with its edge moved onto the painting's strongest edge within
    reach_px pixels (see the module's docstring); luminance: the painting's (H, W)."""
    mask = np.asarray(mask, bool)
    if reach_px <= 0 or not mask.any() or mask.all():
        return mask.copy()
    s = signed_edge_distance(mask, reach_px + 2)
    gy, gx = np.gradient(gaussian_blur(np.asarray(luminance, np.float64), blur_px))
    strength = np.hypot(gx, gy)
    ny, nx = np.gradient(gaussian_blur(s, 1.0))          # inward: toward larger s
    norm = np.maximum(np.hypot(nx, ny), 1e-12)
    ys, xs = np.nonzero(np.abs(s) <= 1.0)
    ux, uy, at = nx[ys, xs] / norm[ys, xs], ny[ys, xs] / norm[ys, xs], s[ys, xs]
    ts = np.arange(-reach_px, reach_px + STEP_PX / 2, STEP_PX)
    # the gradient at signed distance t on each pixel's normal
    g = _along(strength, ys, xs, ux[:, None] * (ts - at[:, None]), uy[:, None] * (ts - at[:, None]))
    top = np.argmax(g - 1e-9 * np.abs(ts), axis=1)          # the nearest of equal peaks
    peak = g[np.arange(len(ys)), top]
    # a step's gradient peaks between two pixel centres, and interpolated its top is flat
    # from one to the other: the offset is the centroid of the peak's upper half
    above = np.maximum(g - PEAK * peak[:, None], 0.0) * (np.abs(ts - ts[top][:, None]) <= 1.0)
    mass = above.sum(axis=1)
    # an edge within reach is a peak inside the window, not a slope rising out of it
    edge = (mass > 0) & (peak > FLOOR) & (top > 0) & (top < len(ts) - 1)
    found = np.where(edge, (above * ts).sum(axis=1) / np.maximum(mass, 1e-300), 0.0)
    offset, weight = np.zeros(mask.shape), np.zeros(mask.shape)
    offset[ys, xs], weight[ys, xs] = found, 1.0
    spread = gaussian_blur(weight, smooth_px)
    delta = np.where(spread > 1e-9, gaussian_blur(offset, smooth_px) / np.maximum(spread, 1e-9),
                     0.0)
    return s > delta


def resnapped(before, snapped_before, mask, luminance, reach_px, blur_px=0.7, smooth_px=2.0):
    """snap_to_edges(mask, …), given what it gave for the mask `before` (the same painting and
    settings): only the box around the pixels that changed (and snap_margin_px beyond it) is
    snapped again, from a crop reaching the margin beyond that — bit for bit the whole
    mask's snap (Paint Shape's stroke on the figure mask)."""
    mask = np.asarray(mask, bool)
    changed = np.asarray(before, bool) != mask
    if not changed.any():
        return np.array(snapped_before, bool)
    h, w = mask.shape
    m = snap_margin_px(reach_px, blur_px, smooth_px)
    rows, cols = np.flatnonzero(changed.any(1)), np.flatnonzero(changed.any(0))
    out = (max(rows[0] - m, 0), min(rows[-1] + 1 + m, h), max(cols[0] - m, 0),
           min(cols[-1] + 1 + m, w))
    crop = (max(out[0] - m, 0), min(out[1] + m, h), max(out[2] - m, 0), min(out[3] + m, w))
    if crop == (0, h, 0, w):
        return snap_to_edges(mask, luminance, reach_px, blur_px, smooth_px)
    part = snap_to_edges(mask[crop[0]:crop[1], crop[2]:crop[3]],
                         np.asarray(luminance)[crop[0]:crop[1], crop[2]:crop[3]],
                         reach_px, blur_px, smooth_px)
    result = np.array(snapped_before, bool)
    result[out[0]:out[1], out[2]:out[3]] = part[out[0] - crop[0]:out[1] - crop[0],
                                                out[2] - crop[2]:out[3] - crop[2]]
    return result
