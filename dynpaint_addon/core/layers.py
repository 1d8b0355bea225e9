"""Layers that shadow each other (pipeline.md §15): what the layers in front of a pixel let
through along its §6 ray — the reference march, first step of issue 30.

A layer k seen from the layers behind it is the solid
S_k = {(x, y, z): α_k(x, y) ≥ ½, z_k − τ_k ≤ z ≤ z_k + relief_k(x, y)} of opacity
ρ_k = 1 − k_k. A pixel of layer i keeps its own cos-θ term (§6) and is multiplied by
T = Π_{k in front} (1 − ρ_k·v_k), where v_k says whether §6's ray from its P0 (a sun's L, or
aimed at a point light and ending there) passes through S_k. Here the layers share one canvas
(a layered file: offset 0, scale 1) and lights have no size; everything is in pixels of that
canvas, z toward the viewer from layer 0's plane.

    >>> import numpy as np
    >>> from dynpaint_addon.core.lights import Light
    >>> card = Occluder(alpha=np.ones((8, 8)), relief_px=np.zeros((8, 8)), z_px=4.0,
    ...                 thickness_px=1.0, opacity=np.ones((8, 8)))
    >>> origins = np.zeros((8, 8, 3)); origins[..., 0] = 4.5; origins[..., 1] = 4.5
    >>> float(transmittance(origins, Light("sun", (0, 0, 1)), [card]).max())
    0.0
"""
from dataclasses import dataclass

import numpy as np

from .sampling import sample_bilinear
from .shadow import inside_box


@dataclass
class Occluder:
    """A layer in front, as the rays of the layers behind it meet it (§15 "Occluders")."""
    alpha: np.ndarray         # (H, W): its silhouette's alpha; the solid is where α ≥ ½
    relief_px: np.ndarray     # (H, W): its relief above its plane, pixels (0 for a flat card)
    z_px: float               # its plane's depth, pixels toward the viewer
    thickness_px: float       # τ: how far the solid reaches behind its plane, pixels
    opacity: np.ndarray       # (H, W): ρ = 1 − k (§11's transparency): 1 opaque, 0 clear


def transmittance(origins, light, occluders, steps=64):
    """T (H, W) of §15: what `occluders` (the layers in front) let through along each
    pixel's §6 ray, by a march of `steps` samples through each occluder's slab.

    Parameters
    ----------
    origins : ndarray (H, W, 3)
        Each pixel's P0 (§6: its surface point moved back by d along its normal), pixels of
        the shared canvas, z toward the viewer.
    light : core.lights.Light
        A sun (direction toward the light) or a point light (position, image widths from the
        canvas's centre, §0); no size.
    occluders : list of Occluder
        The layers in front of the receiving one (those behind never occlude: rays rise).
    steps : int
        Samples per occluder along the part of the ray inside its slab
        [z_k − τ_k, z_k + max relief].

    Returns
    -------
    ndarray (H, W)
        T in [0, 1]: 1 where nothing in front is met, Π (1 − ρ_k) over the layers met.
    """
    h, w = origins.shape[:2]
    o = np.asarray(origins, np.float64)
    if light.kind == "sun":
        d = np.asarray(light.vector, np.float64)
        d = np.broadcast_to(d / np.linalg.norm(d), o.shape)
        length = np.full((h, w), np.inf)          # a sun's ray never ends
    else:
        to = light.position_px(h, w)[None, None, :] - o
        length = np.linalg.norm(to, axis=-1)
        d = to / np.maximum(length, 1e-12)[..., None]
    t = np.ones((h, w))
    for k in occluders:
        top = k.z_px + float(np.max(k.relief_px, initial=0.0))
        bottom = k.z_px - k.thickness_px
        with np.errstate(divide="ignore", invalid="ignore"):
            s0 = np.where(d[..., 2] > 0, (bottom - o[..., 2]) / d[..., 2], np.inf)
            s1 = np.where(d[..., 2] > 0, (top - o[..., 2]) / d[..., 2], -np.inf)
        s0, s1 = np.maximum(s0, 0.0), np.minimum(s1, length)
        hit = np.zeros((h, w), bool)
        rho = np.zeros((h, w))
        for j in range(steps):                    # midpoints of the slab's part of the ray
            s = s0 + (s1 - s0) * ((j + 0.5) / steps)
            live = (s1 > s0) & ~hit
            if not live.any():
                break
            p = o + np.where(live, s, 0.0)[..., None] * d
            x, y, z = p[..., 0], p[..., 1], p[..., 2]
            on = live & inside_box(x, y, h, w)
            inside = on & (sample_bilinear(k.alpha, x, y) >= 0.5) & \
                (z <= k.z_px + sample_bilinear(k.relief_px, x, y))
            rho = np.where(inside, sample_bilinear(k.opacity, x, y), rho)
            hit |= inside
        t *= 1.0 - np.clip(rho, 0.0, 1.0) * hit
    return t
