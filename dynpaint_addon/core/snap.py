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
"""
import numpy as np

from .effects import edge_distance
from .sampling import gaussian_blur, sample_bilinear

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


def snapped(mask, luminance, reach):
    """The mask snapped onto the painting's edges within `reach` image widths (make-shape
    inflate's --snap); as it is where reach is 0 or there is no painting (luminance None)."""
    if not reach or luminance is None:
        return np.asarray(mask, bool)
    return snap_to_edges(mask, luminance, reach * np.shape(mask)[1])


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
    # the gradient at signed distance t on each pixel's normal (pixel centres at +0.5)
    g = sample_bilinear(strength, xs[:, None] + 0.5 + ux[:, None] * (ts - at[:, None]),
                        ys[:, None] + 0.5 + uy[:, None] * (ts - at[:, None]))
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
