"""Height effects on a made relief (issue 41, "effects from the painting";
docs/shape-from-painting.md): the generators artists know from SpriteIlluminator and Laigter,
each a few numbers, added to an inflated figure's heights (image widths throughout).

* bevel: a rim that rises from the figure's edge over `width` to `height`, its cross-section
  a quarter circle (round: √(1 − (1 − t)²)) or a ramp (linear: t), t = distance / width ≤ 1;
  the distance to the edge is the Euclidean one (`edge_distance`), the image's border counting
  as edge, as inflate's does.
* smooth: a Gaussian blur of the heights inside the figure, normalised by the blurred mask so
  the edge does not pull them down.
* structure: a tileable image's values, less their mean, repeated every `scale` image widths
  and added × `strength` inside the figure (a fabric, a canvas, brush strokes).

    >>> import numpy as np
    >>> y, x = (np.mgrid[0:100, 0:100] + 0.5) / 100 - 0.5
    >>> disc = x * x + y * y < 0.4 ** 2
    >>> z = bevel(disc, width=0.1, height=0.02, profile="linear")
    >>> round(float(z.max()), 3), round(float(z[50, 15]), 3)   # the plateau; 5.5 px in
    (0.02, 0.011)
"""
import numpy as np

from .sampling import gaussian_blur, sample_bilinear

BEVEL_PROFILES = ("round", "linear")


def edge_distance(mask, limit_px=None):
    """Euclidean distance (pixels, centre to centre) from each pixel of `mask` (H, W) bool to
    the nearest pixel outside it or beyond the image, up to `limit_px` (farther pixels read
    limit_px; None: no limit); 0 outside. Exact within the limit: each column's distance to
    the nearest outside pixel first, then the nearest over the columns within the limit on
    either side (the separable distance transform, its second pass by brute force over
    2·limit + 1 shifts)."""
    mask = np.asarray(mask, bool)
    h, w = mask.shape
    rows = np.arange(h)[:, None]
    above = np.maximum.accumulate(np.where(mask, -1, rows), axis=0)     # -1: beyond the top
    below = np.minimum.accumulate(np.where(mask, h, rows)[::-1], axis=0)[::-1]
    g = np.minimum(rows - above, below - rows)                          # 0 outside
    if limit_px is None:          # no pixel is farther from the edge than from its column's
        limit_px = float(g.max()) if g.size else 0.0
    reach = int(np.ceil(limit_px))
    # squared distances in whole pixels: exact in int32 (below 2³¹ up to 16384² images)
    g2 = np.pad(np.minimum(g, reach + 1).astype(np.int32) ** 2,
                ((0, 0), (reach + 1, reach + 1)))                        # beyond: 0
    best = np.full((h, w), 2 * (reach + 1) ** 2, np.int32)
    shifted = np.empty_like(best)
    for s in range(-reach - 1, reach + 2):
        np.add(g2[:, reach + 1 + s: reach + 1 + s + w], s * s, out=shifted)
        np.minimum(best, shifted, out=best)
    return np.where(mask, np.minimum(np.sqrt(best), limit_px), 0.0)


def bevel(mask, width, height, profile="round"):
    """The bevel's heights (H, W): `height` image widths reached `width` image widths in from
    the figure's edge (see the module's docstring), 0 outside the figure."""
    if profile not in BEVEL_PROFILES:
        raise ValueError(f"unknown bevel profile {profile!r} (expected one of "
                         f"{', '.join(BEVEL_PROFILES)})")
    mask = np.asarray(mask, bool)
    w = mask.shape[1]
    width_px = max(float(width) * w, 1e-9)
    # a pixel's centre lies half a pixel in from the edge its step counts
    t = np.clip((edge_distance(mask, np.ceil(width_px) + 1) - 0.5) / width_px, 0.0, 1.0)
    rise = t if profile == "linear" else np.sqrt(1.0 - (1.0 - t) ** 2)
    return np.where(mask, height * rise, 0.0)


def smooth(heights, mask, sigma):
    """The heights blurred by `sigma` image widths inside the figure (mask-normalised)."""
    mask = np.asarray(mask, bool)
    return smooth_px(heights, mask, float(sigma) * mask.shape[1])


def smooth_px(values, mask, sigma_px):
    """values (H, W) blurred by sigma_px pixels inside `mask` (H, W) bool, normalised by the
    blurred mask (the edge does not pull them toward 0); 0 outside."""
    if sigma_px <= 0:
        return np.where(mask, values, 0.0)
    blurred = gaussian_blur(np.where(mask, values, 0.0), sigma_px)
    weight = gaussian_blur(mask.astype(np.float64), sigma_px)
    return np.where(mask, blurred / np.maximum(weight, 1e-12), 0.0)


def structure(tile, mask, scale, strength):
    """A tileable pattern's heights: `tile` (h, w) values less their mean, one tile every
    `scale` image widths across the figure (H, W), × `strength`; 0 outside the figure."""
    mask = np.asarray(mask, bool)
    tile = np.asarray(tile, np.float64)
    th, tw = tile.shape
    h, w = mask.shape
    per_px = tw / max(float(scale) * w, 1e-9)          # tile pixels per painting pixel
    y, x = np.mgrid[0:h, 0:w] + 0.5
    values = sample_bilinear(tile - tile.mean(), x * per_px, y * per_px, extension="wrap")
    return np.where(mask, strength * values, 0.0)
