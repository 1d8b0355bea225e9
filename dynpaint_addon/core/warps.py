"""UV-offset warps: mirror reflection of the environment (§8), refraction of the background (§9).

Offsets are returned in image widths, shape (H, W, 2), for unit normals n (H, W, 3) with
N.z ≥ z_min (§2). The lookup itself is `sampling.sample_bilinear` with the chosen extension.
"""
import numpy as np

REFLECTION_MODES = ("stereographic", "clamped")
REFRACTION_MODES = ("physical", "linear")
ETA_MIN, ETA_MAX = 0.5, 2.0


def clamp_eta(eta):
    """§9: η = η₂/η₁ clamped to [½, 2]; NaN → 1 (no refraction) so the result stays finite."""
    eta = float(eta)
    if not np.isfinite(eta):
        return 1.0 if np.isnan(eta) else (ETA_MAX if eta > 0 else ETA_MIN)
    return float(np.clip(eta, ETA_MIN, ETA_MAX))


def _radial(n, magnitude):
    """Vector of length `magnitude` along N.xy (zero where N.xy = 0)."""
    rxy = np.hypot(n[..., 0], n[..., 1])
    scale = np.where(rxy > 0, magnitude / np.where(rxy > 0, rxy, 1), 0)
    return n[..., :2] * scale[..., None]


def reflection_offset(n, distance, mode="stereographic", max_offset=0.5):
    """§8 bounded, continuous, monotone reflection offset Δ (image widths).

    The paper's Δ = d_E·R.xy/R.z with R = 2N.z·N − I blows up at a 45° tilt (R.z = 0) and flips
    sign beyond it. 'clamped' keeps the paper's curve but clamps |Δ| radially (along N.xy) to
    `max_offset`, including everywhere past 45°; 'stereographic' uses 2·d_E·N.xy/N.z, also
    clamped to `max_offset`. Both are odd in N.xy and monotone in the tilt.
    """
    dtype = n.dtype
    d = dtype.type(distance)
    dmax = dtype.type(max(0.0, max_offset))
    nz = n[..., 2]
    rxy = np.hypot(n[..., 0], n[..., 1])
    if mode == "stereographic":
        mag = 2 * d * rxy / nz
    elif mode == "clamped":
        r_xy = 2 * nz * rxy            # |R.xy|
        r_z = 2 * nz * nz - 1          # R.z
        # |Δ| = d·|R.xy|/R.z below 45°, "infinite" (→ max_offset) at and beyond it.
        inside = r_z * dmax > abs(d) * r_xy
        mag = np.where(inside, abs(d) * r_xy / np.where(inside, r_z, 1), dmax) * np.sign(d)
    else:
        raise ValueError(f"unknown reflection mode {mode!r}")
    mag = np.clip(mag, -dmax, dmax).astype(dtype, copy=False)
    return _radial(n, mag)


def refraction_offset_physical(n, distance, eta):
    """§9 physical: Δ = d_B(1 − η²)·N.xy / (η²N.z + √max(η² − |N.xy|², 0)).

    Zero at η = 1; a convex bump with η > 1 samples toward its centre (magnifies). Finite under
    total internal reflection (the root is clamped at 0 and N.z ≥ z_min).
    """
    dtype = n.dtype
    eta = dtype.type(clamp_eta(eta))
    e2 = eta * eta
    rxy2 = n[..., 0] ** 2 + n[..., 1] ** 2
    denom = e2 * n[..., 2] + np.sqrt(np.maximum(e2 - rxy2, 0))
    scale = dtype.type(distance) * (1 - e2) / denom
    return n[..., :2] * scale[..., None]


def refraction_offset_linear(n, distance, mu):
    """§9 art-directed: Δ = −d_B·μ·N.xy / ((1 − |μ|) + |μ|·N.z), μ = log₂η ∈ [−1, 1].

    Linear and odd in μ, zero at μ = 0, never singular for N.z ≥ z_min.
    """
    dtype = n.dtype
    mu = float(mu)
    mu = 0.0 if not np.isfinite(mu) else float(np.clip(mu, -1.0, 1.0))
    denom = dtype.type(1 - abs(mu)) + dtype.type(abs(mu)) * n[..., 2]
    scale = -dtype.type(distance * mu) / denom
    return n[..., :2] * scale[..., None]


def placed_uv(u, v, offset, scale, aspect):
    """§8, §9 placement: a painting UV (u, v) → the UV of an environment or background placed
    over it, centred on the painting's centre moved by `offset` (x, y in image widths) and
    `scale` × the painting's size. aspect = painting W/H (v per image width along y).
    (0, 0) and 1 map the image onto the painting's UV square, as before placement existed."""
    return ((u - 0.5 - offset[0]) / scale + 0.5,
            (v - 0.5 - offset[1] * aspect) / scale + 0.5)
