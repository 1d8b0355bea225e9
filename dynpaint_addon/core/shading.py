"""Local shading terms: Clamp&Step (§3), diffuse (§4), barycentric mixing (§5), specular (§7).

Lights are given per pixel as unit vectors toward the light (§0), shape (H, W, 3).
"""
import numpy as np

from .colour import linear_to_srgb, srgb_to_linear

CURVES = ("linear", "smoothstep", "smootherstep")
MIX_SPACES = ("painted", "linear")


def clamp_step(t, t0, t1, curve="linear"):
    """§3 CS(t; t0, t1, kind) = f(clip((t − t0)/(t1 − t0), 0, 1)).

    t0 = t1 is the cartoon limit, a Heaviside step u = [t > t0] (only 0 or 1, never NaN).
    t0 > t1 inverts. f is identity, smoothstep 3u²−2u³ or smootherstep 6u⁵−15u⁴+10u³.
    """
    t = np.asarray(t)
    dtype = t.dtype if t.dtype.kind == "f" else np.dtype(np.float32)
    if t0 == t1:
        return (t > t0).astype(dtype)
    u = np.clip((t - dtype.type(t0)) / dtype.type(t1 - t0), 0, 1).astype(dtype, copy=False)
    if curve == "linear":
        return u
    if curve == "smoothstep":
        return u * u * (3 - 2 * u)
    if curve == "smootherstep":
        return u * u * u * (u * (u * 6 - 15) + 10)
    raise ValueError(f"unknown curve {curve!r} (expected one of {', '.join(CURVES)})")


def n_dot_l(n, l):
    """Per-pixel N·L for unit normals n (H, W, 3) and light directions l (H, W, 3) or (3,)."""
    return np.sum(n * l, axis=-1)


def specular_term(n, l, s0, s1, curve="linear"):
    """§7: R_L = 2(N·L)N − L, s = CS(R_L·I) with I = (0, 0, 1), gated to 0 where N·L ≤ 0."""
    ndl = n_dot_l(n, l)
    r_z = 2 * ndl * n[..., 2] - (l[..., 2] if np.ndim(l) == n.ndim else l[2])
    s = clamp_step(r_z, s0, s1, curve)
    return np.where(ndl > 0, s, 0).astype(s.dtype, copy=False)


def light_weight(terms, colours, strengths):
    """§5: W = clip(Σ_i k_i c_i t_i, 0, 1) per channel, for per-light scalar terms t_i (H, W)
    and strengths k_i: a number, or one per pixel (H, W) where a point light falls off."""
    acc = None
    for t, c, k in zip(terms, colours, strengths):
        contrib = (t * np.asarray(k, dtype=t.dtype))[..., None] * np.asarray(c, dtype=t.dtype)
        acc = contrib if acc is None else acc + contrib
    return np.clip(acc, 0, 1)


def barycentric_mix(c0, c1, w, space):
    """§5: C_d = C0·(1 − W) + C1·W (W per channel, so coloured lights tint the mix).

    c0, c1 are linear RGB. space 'painted' mixes their display (sRGB) values, the colours the
    artist painted and saw, and returns the mix linear; 'linear' mixes linear light."""
    if space == "linear":
        return c0 * (1 - w) + c1 * w
    if space == "painted":
        return srgb_to_linear(linear_to_srgb(c0) * (1 - w) + linear_to_srgb(c1) * w)
    raise ValueError(f"unknown mix space {space!r} (expected one of {', '.join(MIX_SPACES)})")


def albedo_lit(a, w, ambient):
    """§1, §5: one colour image A (linear RGB) lit as an albedo, C_d = A·(a + (1 − a)·W) —
    §5's mix of C0 = a·A and C1 = A in linear light, as every 2D-lighting tool lights a sprite.
    ambient a = 1 is the flat look (the light changes nothing).

    >>> albedo_lit(0.5, w=0.5, ambient=0.25)       # half lit: 0.5 × (0.25 + 0.75 × 0.5)
    0.3125
    """
    return a * (ambient + (1 - ambient) * w)


def opaque_highlight(c_d, c_spec, gs):
    """§7 (paper eq. SpecShade): C_s = C_d·(1 − g·s) + C_spec·g·s, gs = g·s per channel."""
    return c_d * (1 - gs) + c_spec * gs
