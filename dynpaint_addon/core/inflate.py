"""Inflate a silhouette into a height map (docs/shape-from-painting.md).

Inside the figure (a mask, e.g. the painting's alpha) solve −Δh = 1 with h = 0 on its edge
(h in image widths², Δ in image widths). Each connected part of the figure is inflated alone
(its solve, profile and detail mean its own): the same drawing gives the same heights, bit
for bit, whatever else the image holds — frames of an animation keep what does not change
(pipeline.md §16). For a disc of radius R, h = (R² − r²)/4, so the
*round* profile z = 2√h is exactly the hemisphere √(R² − r²); on any other outline it follows
the figure smoothly (Lumo, Monster Mash), but its cross-sections are round only where the
outline is: a long strip of half-width a gets h = (a² − x²)/2, z = √2 · √(a² − x²), half as
tall again as round (a ring becomes a torus √2 too tall). Other profiles reshape the round
one, normalised u = z / max z:

* round:    z                          (a ball for a disc)
* soft:     max z · u²                 (the Poisson bump itself: gentle rims, a pointed middle)
* flat:     max z · (1 − (1 − min(2u, 1))²)   (rounded rims, a plateau above half height)

and one is made apart, with no Poisson solve:

* tube:     √(d · (2a − d))            (every cross-section a semicircle as wide as the figure)

d is a pixel's distance to the figure's edge, a the half-width of the figure where the pixel
lies: the distance to the edge at the ridge (the medial axis) that its steepest climb up d
first reaches (Teddy's rule: heights from the chordal axis). A disc gives the same hemisphere
as round, a strip a half-cylinder of its own width, a ring the true torus.

Optional detail embosses the painting's luminance: + strength · (blurred luminance − its
mean inside the figure), so painted folds and features stand out.

    >>> import numpy as np
    >>> y, x = (np.mgrid[0:200, 0:200] + 0.5) / 200 - 0.5
    >>> z = inflate(x * x + y * y < 0.4 ** 2).height
    >>> abs(float(z.max()) - 0.4) < 0.004     # a hemisphere of radius 0.4 image widths
    True
    >>> r = np.hypot(x, y)
    >>> ring = (0.2 < r) & (r < 0.4)             # a torus's tube of radius 0.1 image widths
    >>> [round(float(inflate(ring, p).height.max()), 2) for p in ("round", "tube")]
    [0.15, 0.1]
"""
from dataclasses import dataclass

import numpy as np

from .effects import edge_distance, smooth_px
from .laplace import Grid, components, parts, solve_parts
from .sampling import gaussian_blur, gaussian_radius

RESHAPED = ("round", "soft", "flat")      # the round profile reshaped (shape_profile)
PROFILES = RESHAPED + ("tube",)
RIDGE_SLOPE = 0.5   # a climb gaining less than this per pixel walked runs along a ridge
TUBE_SMOOTH = 0.015     # image widths the half-widths a are blurred by: neighbours that climbed
#                         to different ridges would meet in a crease


@dataclass
class Inflated:
    height: np.ndarray       # (H, W) image widths, 0 outside the figure
    iterations: int          # conjugate-gradient iterations of the Poisson solve
    residual: float          # its relative residual


def _dirichlet_grid(mask):
    """−Δ on the figure's pixels; neighbours outside it (or beyond the image) are held at 0."""
    m = mask.astype(np.float64)
    inside = np.pad(m, 1)
    neighbours_inside = inside[1:-1, 2:] + inside[1:-1, :-2] + inside[2:, 1:-1] + inside[:-2, 1:-1]
    return Grid(m[:, 1:] * m[:, :-1], m[1:, :] * m[:-1, :], m * (4 - neighbours_inside),
                np.float32)      # a round profile needs ~1e-4: float32 halves the time


def shape_profile(round_height, profile):
    """Reshape the round profile (see the module's docstring)."""
    top = float(round_height.max())
    if profile == "round" or top <= 0:
        return round_height
    u = round_height / top
    if profile == "soft":
        return top * u * u
    if profile == "flat":
        rim = np.minimum(2 * u, 1)
        return top * (1 - (1 - rim) ** 2)
    raise ValueError(f"unknown profile {profile!r} (expected one of {', '.join(PROFILES)})")


def inflate(mask, profile="round", height=1.0, detail=0.0, luminance=None, detail_blur=0.002,
            tol=1e-4, by_parts=True):
    """Height map (image widths) of a figure's mask (H, W) bool, y up → Inflated.

    height: scales the profile (1 = a disc's hemisphere as tall as its radius); detail: image
    widths of relief per unit of luminance (H, W, 0..1) embossed inside the figure, blurred by
    detail_blur image widths first. by_parts: each connected part of the figure alone (see
    above); False solves and reshapes the whole figure at once, as before pipeline.md §16
    (benchmarks/frames_stability.py measures what that costs an animation).
    """
    mask = np.asarray(mask, bool)
    h, w = mask.shape
    z = np.zeros((h, w))
    iterations, residual = 0, 0.0
    if mask.any():
        grid = _dirichlet_grid(mask)
        labels, count = components(grid.wx > 0, grid.wy > 0) if by_parts else \
            (np.zeros((h, w), np.int64), 1)
        if profile == "tube":
            z = tube_heights(mask, labels) / w * height
        else:
            poisson, iterations, residual = solve_parts(grid, mask / float(w * w), labels,
                                                        count, tol=tol)
            z = 2 * np.sqrt(np.maximum(poisson, 0)) * height
            z = _per_part(shape_profile, z, labels, count, mask, profile)
        if detail and luminance is not None:
            lum = gaussian_blur(np.asarray(luminance, np.float64), detail_blur * w)
            z = z + detail * _per_part(_less_mean, lum, labels, count, mask)
    return Inflated(np.where(mask, z, 0.0), iterations, residual)


def tube_heights(mask, labels):
    """The tube profile's heights (pixels) of a figure (H, W) bool whose parts are `labels`:
    √(d · (2a − d)) (see the module's docstring). d: the exact Euclidean distance to the
    nearest pixel outside, less the half pixel from that pixel's centre to the edge. a: each
    pixel climbs to its 8-neighbour (of its own part) of largest d while that gains at least
    RIDGE_SLOPE per pixel walked (off a ridge d rises one per pixel; along one, by the ridge's
    own slope), by pointer jumping; a is d where the climb stops, blurred by TUBE_SMOOTH
    inside each part (neighbours that climbed to different ridges would meet in a crease)."""
    h, w = mask.shape
    d = np.where(mask, edge_distance(mask) - 0.5, -1.0)
    index = np.arange(h * w).reshape(h, w)
    padded_d = np.pad(d, 1, constant_values=-1.0)
    padded_label = np.pad(np.where(mask, labels, -1), 1, constant_values=-1)
    rate, parent = np.full((h, w), RIDGE_SLOPE), index.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dy == dx == 0:
                continue
            seen = np.s_[1 + dy: 1 + dy + h, 1 + dx: 1 + dx + w]
            gain = (padded_d[seen] - d) / np.hypot(dy, dx)
            steeper = (gain >= rate) & (padded_label[seen] == labels) & mask
            rate = np.where(steeper, gain, rate)
            parent = np.where(steeper, index + dy * w + dx, parent)
    top = parent.ravel()
    for _ in range(max(int(np.ceil(np.log2(max(h * w, 2)))), 1)):
        top = top[top]       # each round doubles the steps climbed; every climb ends on a ridge
    a = _smoothed_in_parts(d.ravel()[top].reshape(h, w), mask, labels, TUBE_SMOOTH * w)
    a = np.maximum(a, d)      # (a pixel lies no farther in than its part's half-width)
    return np.where(mask, np.sqrt(np.clip(d * (2 * a - d), 0.0, None)), 0.0)


def _smoothed_in_parts(values, mask, labels, sigma_px):
    """values (H, W) blurred by sigma_px inside each part of the figure alone (smooth_px in
    the part's box: a part's values never read another's)."""
    out = values.copy()
    if sigma_px <= 0:
        return out
    h, w = mask.shape
    reach = gaussian_radius(sigma_px)
    for k, (r0, r1, c0, c1) in parts(labels, int(labels.max()) + 1, mask):
        r0, r1, c0, c1 = max(r0 - reach, 0), min(r1 + reach, h), max(c0 - reach, 0), \
            min(c1 + reach, w)
        own = (labels[r0:r1, c0:c1] == k) & mask[r0:r1, c0:c1]
        out[r0:r1, c0:c1][own] = smooth_px(values[r0:r1, c0:c1], own, sigma_px)[own]
    return out


def _less_mean(values):
    return values - values.mean()


def _per_part(fn, values, labels, count, mask, *args):
    """fn(values of one figure part, *args) for each part alone (its tallest point, its mean):
    one figure's relief never depends on another's (§16: frames keep what does not change)."""
    out = np.zeros_like(values)
    for k, (r0, r1, c0, c1) in parts(labels, count, mask):
        own = (labels[r0:r1, c0:c1] == k) & mask[r0:r1, c0:c1]
        out[r0:r1, c0:c1][own] = fn(values[r0:r1, c0:c1][own], *args)
    return out
