"""A cut-out normal map's pixels where its alpha says the surface is missing or partial (§2,
§14), read before decoding so that no rim becomes a cliff.

A normal map baked in Blender onto a transparent image, or exported premultiplied, stores
(0, 0, 0, 0) where there is no surface and, along its anti-aliased rim, the normal's colour
blended with that black: C·α. Decoded as it is, black is N = (−1, −1, −1) and a rim pixel at
α = ½ tilts 60°–90° toward the lower left, so every relief built from the slopes (§6) rises
or falls by a cliff all round the figure: a wall of shadow. So:

- a pixel with no coverage (α ≤ 1/255) holds no normal: it is flat, (0, 0, 1);
- the rim (0 < α < 1) is divided by α where the map's rim says it was blended with black:
  its vectors 2C/α − 1 are nearer unit length than 2C − 1 (a map written with straight alpha,
  as sprite tools write theirs, keeps its rim as it is).

    >>> import numpy as np
    >>> c = np.array([0.7, 0.5, 0.9])                  # a unit normal's colour, (0.4, 0, 0.8)…
    >>> rim = np.array([c * a for a in (0.25, 0.5, 0.75)] + [c] * 6)[None]   # … blended with black
    >>> alpha = np.array([[0.25, 0.5, 0.75] + [1.0] * 6])
    >>> fixed, empty = cut_out_pixels(rim, alpha)
    >>> bool(np.allclose(fixed[0, :3], c)), empty.any()
    (True, False)
"""
import numpy as np

NO_COVERAGE = 1 / 255       # alpha at or below: no surface (8-bit 0 after any rounding)
MIN_RIM = 3                 # rim pixels needed to judge how the rim was written


def premultiplied_rim(rgb, alpha):
    """Whether a map's partly covered pixels were blended with black (C·α), judged by which
    reading leaves their vectors nearer unit length (median |length − 1|)."""
    rim = (alpha > NO_COVERAGE) & (alpha < 1 - NO_COVERAGE)
    if np.count_nonzero(rim) < MIN_RIM:
        return False
    a = alpha[rim][:, None]
    straight = np.linalg.norm(2 * rgb[rim] - 1, axis=-1)
    divided = np.linalg.norm(2 * rgb[rim] / a - 1, axis=-1)
    return bool(np.median(np.abs(divided - 1)) < np.median(np.abs(straight - 1)))


def cut_out_pixels(rgb, alpha, rim=True):
    """A normal map's RGB (H, W, 3, 0..1) with its blended rim divided by alpha (where it was
    blended; `rim` False for a two-channel map, whose lengths say nothing) → (rgb, empty):
    `empty` marks the pixels with no coverage (the caller makes them flat), None without an
    alpha. `rgb` itself comes back when no rim was divided."""
    if alpha is None:
        return rgb, None
    alpha = np.nan_to_num(np.asarray(alpha, np.float32))
    empty = alpha <= NO_COVERAGE
    if rim and premultiplied_rim(rgb[..., :3], alpha):
        partial = ~empty & (alpha < 1)
        rgb = np.array(rgb[..., :3], copy=True)
        rgb[partial] = np.clip(rgb[partial] / alpha[partial][:, None], 0, 1)
    return rgb, empty


def needs_cleaning(rgb, alpha, rim=True):
    """Whether cut_out_pixels changes anything the graph would read of an RGB map as stored:
    a blended rim, or an uncovered pixel that is not stored flat."""
    fixed, empty = cut_out_pixels(rgb, alpha, rim)
    if empty is None:
        return False
    if fixed is not rgb:                # its rim was divided
        return True
    stored = np.asarray(rgb)[..., :3][empty]
    return not bool(np.all(np.abs(stored - (0.5, 0.5, 1.0)) < 1 / 255))
