"""§6 "Relief", auto: the shadow of either relief (issue 62).

A normal map records slopes, not heights, and the same map fits a figure sunk to its middle and
one resting on the ground (docs/relief-choice.md): its integrated relief casts the first's
shadows best, its slopes marched along the whole ray the second's. A pixel is in the shadow of
either relief when it is in the shadow of one of them:

    t = min(t_integrated, t_along the ray)

which no fixed setting beats on both the mean |t − 3D| and the cast-shadow IoU, on any kind of
figure or size measured (docs/relief-choice.md). It bakes twice, so `shadows.relief = auto`
casts it where a picture is final (quality final and reference); the live levels (draft,
preview) and custom keep one relief — integrated where the shape image has an alpha, else along
the ray (input_rules.relief_of) — as do the in-shader marches (OSL, the web page). A map whose
normals fit no height field (an impossible figure) has no integrated relief to speak of: one
relief there too (shape.reach_of).

>>> import numpy as np
>>> from dynpaint_addon import params
>>> p = params.defaults()
>>> flat = np.dstack([np.zeros((8, 8)), np.zeros((8, 8)), np.ones((8, 8))]).astype(np.float32)
>>> z, slopes = both_reliefs(flat, None, np.zeros((8, 8, 2), np.float32), p)
>>> z.shape, float(abs(z).max())
((8, 8), 0.0)
>>> p.shadows.quality = "draft"
>>> both_reliefs(flat, None, np.zeros((8, 8, 2), np.float32), p) is None
True
"""
import copy
import weakref

import numpy as np

from .input_rules import normal_map_normals, relief_of
from .integrate import relief_px
from .shape import fits_height_field, slopes_from_normals

# the levels where a picture is final: the shadow of either relief is cast there
EITHER_QUALITIES = ("final", "reference")

_OTHER = {}     # id(normals) → (weak ref, the relief it was not decoded with): bakes repeat


def asks_either(p):
    """Whether these parameters ask for the shadow of either relief at the final levels (a
    normal map, relief auto), where its normals fit a height field."""
    return p.shape.kind == "normal" and p.shadows.relief == "auto"


def casts_either(p):
    """Whether these parameters cast the shadow of either relief now (asks_either, at a final
    quality level) where the normals fit a height field."""
    return asks_either(p) and p.shadows.quality in EITHER_QUALITIES


def image_casts_either(shape, p):
    """Whether a normal-map shape image (ImageData) read with parameters p casts the shadow of
    either relief at its final levels: asks_either, and normals that fit a height field."""
    return asks_either(p) and fits_height_field(
        slopes_from_normals(normal_map_normals(shape, p)))


def one_relief(p, shape_has_alpha):
    """Parameters p as the live levels and the in-shader marches (OSL, the web page) shade
    them: relief auto pinned to the one relief input_rules.relief_of names for a shape image
    with or without an alpha (what their pictures are checked against); p itself otherwise."""
    if not asks_either(p):
        return p
    pinned = copy.deepcopy(p)
    pinned.shadows.relief = relief_of(p.shadows.relief, shape_has_alpha)
    return pinned


def both_reliefs(n, z_px, slopes, p):
    """A normal map's two reliefs (heights in pixels, slopes) where it casts the shadow of
    either (casts_either, and its normals fit a height field); None where it casts one.
    n, z_px, slopes: as pipeline.shape_normals decodes it (one of the reliefs None): the other
    is made once per normals array while it lives — the slopes of the normals, or the
    least-squares heights of a map without an alpha (a map with one was decoded integrated,
    its figure cut at the alpha)."""
    if not casts_either(p) or (z_px is None) == (slopes is None) or \
            (slopes is not None and not fits_height_field(slopes)):   # (no integration then)
        return None
    hit = _OTHER.get(id(n))
    if hit is None or hit[0]() is not n:
        for gone in [k for k, (ref, _) in _OTHER.items() if ref() is None]:
            del _OTHER[gone]
        other = slopes_from_normals(n) if slopes is None else relief_px(n)
        hit = (weakref.ref(n), other)
        _OTHER[id(n)] = hit
    z_px, slopes = (z_px, hit[1]) if slopes is None else (hit[1], slopes)
    return (z_px, slopes) if fits_height_field(slopes) else None


def either_shadow(bake_one, z_px, slopes, progress=None):
    """min(t of the heights, t of the slopes along the whole ray): bake_one(heights_px=…,
    slopes=…, reach=…, progress=…) bakes one relief; progress: callable(fraction) over both."""
    def half(start):
        return None if progress is None else (lambda f: progress(start + f / 2))
    t = bake_one(heights_px=z_px, slopes=None, reach=np.inf, progress=half(0.0))
    return np.minimum(t, bake_one(heights_px=None, slopes=slopes, reach=np.inf,
                                  progress=half(0.5)))
